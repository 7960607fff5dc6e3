//! The paper's discrete problem P_m (§6, theory §11) for the general problem (P), globally: a
//! mixed-integer linear program on `M = 2^m` steps of `h = T / M`, re-verified by the general
//! simulator ([`crate::integrate::general`]).
//!
//! Variables: states `x^i` (`i = 0..M`, `x^M = x^0` when periodic, `x^0` fixed for a Cauchy
//! problem), controls `u^i in U`, the projection's multipliers `mu^i_j >= 0` (`mu = h lambda`)
//! and a binary `z^i_j` per step and face. The catching-up step is its KKT system:
//! `x^(i+1) = x^i + h (A x^i + B u^i + b) - sum_j mu^i_j x*_j`, `<x*_j, x^(i+1)> <= c_j`, and
//! complementarity by big-M: `mu^i_j <= M_mu z^i_j`, `c_j - <x*_j, x^(i+1)> <= S_j (1 - z^i_j)`.
//! Since the projection is unique and, with the active normals independent at every vertex
//! (checked), so are its multipliers, every feasible point is the catching-up process of its
//! controls. Objective: `sum_i [f1(mu^i) - h f2(u^i)]` with `f1` linear in `mu` (face weights
//! `w_j`, or `<q, x*_j>` for `f1 = <q, eta>`); `sum_i u^i = 0` under the zero-mean constraint.
//! A chain's multipliers and binaries are made in the order of its faces' classes
//! (`discrete_rows::face_classes`: a crawler's P_m is this MILP on its instance, and HiGHS
//! searches that order about as fast as the crawler's former MILP of its own).
//!
//! The constants, from linear programs over C and U:
//! - `S_j = c_j - min_{x in C} <x*_j, x>`: the largest slack of face `j` in C (C bounded);
//! - `M_mu = h G / sigma_*`: `|v - x^(i+1)| <= |v - x^i| = h |g(x^i, u^i)| <= h G` (`x^i` is in C
//!   and the projection is the nearest point), `G^2 = sum_k max(|max g_k|, |min g_k|)^2` with
//!   `max g_k = max_{x in C} (A x)_k + max_{u in U} (B u)_k + b_k`, and
//!   `|mu| <= |v - x^(i+1)| / sigma_min(N_W)` for the active normals `N_W`, whose smallest
//!   singular value is at least `sigma_*`, the least over the vertices of C of that of their
//!   active normals (removing rows of a matrix of full row rank does not lower it: the
//!   eigenvalues of a principal submatrix of `N N^T` interlace).
//!
//! A quadratic `f2(u) = (1/2) u^T R u` (`R = c I` for `quadratic`) enters by its outer
//! approximation: an epigraph variable `e^i >= f2(u0) + Df2(u0) (u^i - u0)` for cut points `u0`
//! (tangent planes, below `f2` by convexity), `-h e^i` in the objective. With fewer cuts the MILP
//! under-estimates the cost, so its bound stays a bound on P_m; the controls of each solution
//! become cut points until the true objective of the incumbent meets the bound within
//! `OA_TOL` (relative above the problem's floor of `J`, C's scale capped at 1, in units of it
//! below), as for the crawler's P_m. A separable `f2`
//! (`R` diagonal) has the crawler's stronger form: an epigraph `e^i_k >= (r_k/2) (u^i_k)^2` per
//! component, cut by the tangents of the parabola at the cut points' components, the first 17
//! evenly spread over U (the sum of the components' tangents is a tangent plane, so this is
//! never weaker, and it combines one component's tangent with another's). C and U bounded.

use super::discrete_rows as rows;
pub(super) use super::discrete_rows::{
    branch_bounds, cost_epigraphs, cost_matrix, holds_a_pair, opposite_faces, pair_bounds,
    pair_multiplier, BigM, Form,
};
use super::geometry::{into_u, Geometry};
use crate::error::{Error, Result};
use crate::integrate::{simulate_general, ControlInput, GeneralSimOptions, InputKind};
use crate::model::general::{
    Boundary, ControlSet, GeneralCost, GeneralProblem, Reward, EXPLICIT_STEP_LIMIT,
};
use crate::optimal::milp::Certificate;
use crate::optimal::solver::{Highs, SolveStatus};
use highs::{Col, RowProblem, Sense};
use serde::{Deserialize, Serialize};

/// Largest `m` (`2^m` steps) of the general P_m.
pub const MAX_GENERAL_M: u32 = 10;

/// A process of P_m on its grid of `M = 2^m` steps, as every P_m answer carries it (the global
/// method's [`GeneralPm`] and the local method's
/// [`GeneralLocal`](super::GeneralLocal)), flattened into the answer's solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PmPath {
    /// States `x^0..x^M` (`states`, as every result's solution names them; `x` in version 2).
    #[serde(rename = "states", alias = "x")]
    pub x: Vec<Vec<f64>>,
    /// Controls `u^0..u^(M-1)` (`controls`; `u` in version 2).
    #[serde(rename = "controls", alias = "u")]
    pub u: Vec<Vec<f64>>,
    /// Reaction rates `lambda^i = mu^i / h` per step and face (`reactions`, as a phase gait's;
    /// `lambda` in version 2).
    #[serde(rename = "reactions", alias = "lambda")]
    pub lambda: Vec<Vec<f64>>,
}

/// The global optimum of P_m for a general problem, re-verified.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralPm {
    /// `m`.
    pub m: u32,
    /// `J` of the controls, as the simulator replays them (written once, as the result's
    /// `objective`; filled from it on reading).
    #[serde(skip_serializing)]
    pub objective: f64,
    /// The MILP's status, objective, bound and gap (written once, as the result's `status`,
    /// `solver_objective` and `certificate`; filled from them on reading).
    #[serde(skip_serializing)]
    pub certificate: Certificate,
    /// The process on the grid ([`PmPath`]).
    #[serde(flatten)]
    pub path: PmPath,
    /// What polishing on the fixed face pattern did ([`crate::optimal::polish`]); `None`
    /// without a quadratic cost (the MILP's answer is then exact) or with polishing off.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polish: Option<crate::optimal::polish::PolishRecord>,
}

/// `max_{x in C} <d, x>` (C bounded), solved in units of order one: the support function is
/// positively homogeneous in `d` and in the offsets, so the LP takes `d / |d|_inf` and the offsets
/// over their largest, and its optimum is scaled back. HiGHS holds reduced costs to an absolute
/// `1e-7`: with `d` of size `1e-8` as given (a row of `B` of a problem in slow time), every vertex
/// passed as optimal, the support came out 0, and P_m's multipliers were bounded by 0, which made
/// the MILP claim `J = 0` optimal where the problem reaches `3.9`.
fn support(rows: &[Vec<f64>], offsets: &[f64], d: &[f64], what: &str) -> Result<f64> {
    let largest = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let dn = largest(d);
    if dn == 0.0 {
        return Ok(0.0);
    }
    let cn = match largest(offsets) {
        c if c > 0.0 => c,
        _ => 1.0,
    };
    let mut pb = RowProblem::default();
    let x: Vec<Col> = d
        .iter()
        .map(|&di| pb.add_column(di / dn, f64::NEG_INFINITY..f64::INFINITY))
        .collect();
    for (r, &c) in rows.iter().zip(offsets) {
        pb.add_row(
            ..=c / cn,
            x.iter().zip(r).map(|(&x, &a)| (x, a)).collect::<Vec<_>>(),
        );
    }
    let a = Highs::new(pb, Sense::Maximise, what)?.solve()?;
    match a.status {
        SolveStatus::Optimal => Ok(a.objective * dn * cn),
        _ => Err(Error::Numerical(format!("{what}: no optimum"))),
    }
}

/// `max_{u in U} <d, u>`.
pub(super) fn support_u(u: &ControlSet, d: &[f64]) -> Result<f64> {
    match u {
        ControlSet::Box { lower, upper } => Ok(d
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(di, (lo, hi))| if *di >= 0.0 { di * hi } else { di * lo })
            .sum()),
        ControlSet::Polytope(p) => support(&p.normals, &p.offsets, d, "support function of U"),
    }
}

pub(super) fn big_m(p: &GeneralProblem, g: &Geometry, h: f64) -> Result<BigM> {
    let c = &p.c;
    let mut slack = Vec::with_capacity(c.faces());
    for j in 0..c.faces() {
        let neg: Vec<f64> = c.normals[j].iter().map(|v| -v).collect();
        let min = -support(&c.normals, &c.offsets, &neg, "big-M of P_m (slack)")?;
        slack.push((c.offsets[j] - min).max(0.0) * (1.0 + 1e-9) + 1e-12 * c.scale());
    }
    let mut g2 = 0.0;
    for k in 0..p.states() {
        let mut ext = [0.0_f64; 2];
        for (e, sign) in ext.iter_mut().zip([1.0, -1.0]) {
            let ax: Vec<f64> = p.dynamics.a[k].iter().map(|v| sign * v).collect();
            let bu: Vec<f64> = p.dynamics.b[k].iter().map(|v| sign * v).collect();
            let x = if ax.iter().all(|v| *v == 0.0) {
                0.0
            } else {
                support(&c.normals, &c.offsets, &ax, "big-M of P_m (drift)")?
            };
            *e = x + support_u(&p.control, &bu)? + sign * p.dynamics.drift[k];
        }
        let m = ext[0].abs().max(ext[1].abs());
        g2 += m * m;
    }
    let sigma_min = match (&g.vertices, p.as_chain()) {
        (Some(vertices), _) => vertices
            .iter()
            .map(|v| {
                let rows: Vec<usize> = v.active.iter().map(|&j| j - 1).collect();
                c.least_singular_value(&rows)
            })
            .fold(f64::INFINITY, f64::min),
        // A chain too long to enumerate: its structure bounds every active set.
        (None, Some(view)) => {
            view.check_face_weights()?;
            view.least_active_singular_value(c)
        }
        (None, None) => {
            return Err(Error::invalid(
                "sweeping_process",
                format!("{} faces in dimension {}", c.faces(), c.dim()),
                "P_m needs the vertices of C, which are too many to enumerate",
            ))
        }
    };
    Ok(BigM {
        slack,
        multiplier: h * g2.sqrt() / sigma_min * (1.0 + 1e-6) + 1e-12,
    })
}

/// A bound on the objective of every point of a MILP whose reaction columns of face `j` add up
/// to at most `total` over the period (P_m: `2^m` steps of `mu^i_j <= M_mu`; the phase MILP:
/// `lambda_(k,j) <= M_mu tau_k` with `sum tau_k = T`): `f1`'s integral is at most
/// `total * sum_j max(w_j, 0)`, and the cost `f2 >= 0` only lowers it. The bound of a MILP that
/// the time limit cut short before HiGHS had a dual bound: weak, but a bound, where the
/// incumbent's own value would claim a proof that was never made.
pub(super) fn column_bound(p: &GeneralProblem, total: f64) -> f64 {
    total * p.face_weights().iter().map(|w| w.max(0.0)).sum::<f64>()
}

/// The range of magnitudes P_m's linear programs are handed (C's scale, the controls' bounds,
/// `h` times the dynamics, the weights, the big-M constants): HiGHS takes values from 1e20 on
/// as infinite and solves to absolute tolerances near 1e-9, so data beyond this range are
/// refused up front, naming the field, rather than failing inside HiGHS ("unbounded", "refused
/// the model") or giving an answer within its tolerance of anything.
pub const PM_DATA_RANGE: (f64, f64) = (1e-6, 1e12);

/// Refuses data of `p` outside [`PM_DATA_RANGE`] for P_m on steps `h` (module docs of the
/// constant); `bm`: the big-M constants of the MILP, where they are used.
pub(super) fn check_solver_range(p: &GeneralProblem, h: f64, bm: Option<&BigM>) -> Result<()> {
    let (lo, hi) = PM_DATA_RANGE;
    let top = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0_f64, |t, x| t.max(x.abs()));
    let scale = p.c.scale();
    let advice = "scale the problem (lengths, time, rates, weights) so that its data lie within";
    if !(lo..=hi).contains(&scale) {
        return Err(Error::invalid(
            "sweeping_process.offsets",
            format!("C's scale max |c_j| = {scale:e}"),
            format!("P_m's solver needs it within [{lo:e}, {hi:e}]; {advice} that range"),
        ));
    }
    let (u_field, u_top) = match &p.control {
        ControlSet::Box { lower, upper } => (
            "control.lower, control.upper",
            top(&mut lower.iter().chain(upper).copied()),
        ),
        ControlSet::Polytope(u) => ("control.h", top(&mut u.offsets.iter().copied())),
    };
    let w_field = match p.reward {
        Reward::FaceWeights(_) => "objective.face_weights",
        Reward::ReactionWeights(_) => "objective.reaction_weights",
    };
    let mut sizes = vec![
        (u_field, "its largest size", u_top),
        (
            "dynamics.A",
            "its largest entry times h",
            h * top(&mut p.dynamics.a.iter().flatten().copied()),
        ),
        (
            "dynamics.B",
            "its largest entry times h",
            h * top(&mut p.dynamics.b.iter().flatten().copied()),
        ),
        (
            "dynamics.b",
            "its largest entry times h",
            h * top(&mut p.dynamics.drift.iter().copied()),
        ),
        (
            w_field,
            "the largest weight (of the unit normals)",
            top(&mut p.face_weights().into_iter()),
        ),
    ];
    if let Some(bm) = bm {
        sizes.push((
            "dynamics",
            "the bound M_mu on the reactions it gives over C and U",
            bm.multiplier,
        ));
    }
    for (field, what, v) in sizes {
        if v.is_nan() || v > hi {
            return Err(Error::invalid(
                field,
                format!("{what} {v:e}"),
                format!(
                    "is beyond P_m's solver range (magnitudes up to {hi:e}; HiGHS takes 1e20 \
                     as infinite); {advice} [{lo:e}, {hi:e}]"
                ),
            ));
        }
    }
    Ok(())
}

/// Checks that P_m's global method applies to `p` at this `m` (its range first, naming `m`),
/// before any work on a grid of `2^m` steps.
pub fn check(p: &GeneralProblem, g: &Geometry, m: u32) -> Result<()> {
    if m == 0 {
        // One step with zero-mean controls is u = 0: no model, only a degenerate one.
        return Err(Error::invalid(
            "m",
            m,
            "must be at least 1 (a periodic process with zero-mean controls needs two steps)",
        ));
    }
    if m > MAX_GENERAL_M {
        return Err(Error::invalid(
            "m",
            m,
            format!("must be in 1..={MAX_GENERAL_M}"),
        ));
    }
    check_explicit_step(p, m)?;
    check_sets(p, g, "P_m's global method")
}

/// Refuses a grid too coarse for P_m's explicit step (paper §6:
/// `x^(i+1) = x^i + h g(x^i, u^i) - h eta^i`): `h = T / 2^m` times the rate of A's decaying and rotating part
/// ([`crate::model::general::DriftSplit::stiff_rate`]) must be at most
/// [`EXPLICIT_STEP_LIMIT`], else a stiff drift oscillates between faces of C and the optimum
/// of P_m is wrong by orders of magnitude (the simulator steps such a drift implicitly).
pub(super) fn check_explicit_step(p: &GeneralProblem, m: u32) -> Result<()> {
    let h = p.period / (1u64 << m.min(63)) as f64;
    let rate = p.dynamics.split().stiff_rate;
    if h * rate <= EXPLICIT_STEP_LIMIT {
        return Ok(());
    }
    let need = crate::model::general::min_steps(p.period, rate)
        .log2()
        .ceil();
    Err(Error::invalid(
        "m",
        m,
        format!(
            "P_m's explicit step h = T/2^m = {h:e} times the decaying and rotating rate \
             {rate:e} of dynamics.A (|S_- + K|_2) exceeds the stability limit \
             {EXPLICIT_STEP_LIMIT}: P_m needs m >= {need}{}; or scale A down (the simulator \
             steps a stiff damping implicitly)",
            if need > f64::from(MAX_GENERAL_M) {
                format!(", beyond the largest m ({MAX_GENERAL_M})")
            } else {
                String::new()
            }
        ),
    ))
}

/// Checks what every method for P_m needs (`who` names the method): C and U bounded (the
/// big-M constants; a bounded LP of fixed branches) and independent active normals at every
/// vertex of C (unique multipliers, so that every feasible point is the catching-up process
/// of its controls).
pub(super) fn check_sets(p: &GeneralProblem, g: &Geometry, who: &str) -> Result<()> {
    if !g.bounded {
        return Err(Error::invalid(
            "sweeping_process",
            "an unbounded C",
            format!("{who} needs a bounded C"),
        ));
    }
    if let ControlSet::Polytope(u) = &p.control {
        let ug = super::geometry::analyze_polyhedron(u)?;
        if !ug.bounded {
            return Err(Error::invalid(
                "control",
                "an unbounded U",
                format!("{who} needs a bounded U"),
            ));
        }
    }
    if let Some(k) = g.degenerate_vertex {
        return Err(Error::invalid(
            "sweeping_process",
            format!("vertex {k}"),
            "P_m needs independent active normals at every vertex (unique multipliers)",
        ));
    }
    Ok(())
}

/// The columns of the MILP (or of a branch LP).
pub(super) struct Layout {
    /// States `x^0..x^M` (`x^M` the columns of `x^0` when periodic).
    pub x: Vec<Vec<Col>>,
    /// Controls `u^0..u^(M-1)`.
    pub u: Vec<Vec<Col>>,
    /// Multipliers `mu^i_j`, by their columns ([`Layout::multiplier`] reads them): a pair of
    /// opposite faces' two entries are its one signed column in a branch LP.
    pub mu: Vec<Vec<Col>>,
    /// Each face's opposite face where a branch LP pairs them ([`opposite_faces`]; empty for
    /// the MILP).
    pub partner: Vec<Option<usize>>,
    /// Slacks `s^i_j = c_j - <x*_j, x^(i+1)>`, each read from its column
    /// ([`rows::Slack`]; branch LPs only, empty for the MILP).
    pub s: Vec<Vec<rows::Slack>>,
    /// Binaries `z^i_j` (the MILP only; empty for a branch LP).
    pub z: Vec<Vec<Col>>,
    /// A quadratic cost's epigraph columns, per step and epigraph ([`rows::cost_epigraphs`]).
    pub e: Vec<Vec<Col>>,
}

impl Layout {
    /// The face opposite face `j` that a branch LP pairs it with, if any.
    pub fn partner_of(&self, j: usize) -> Option<usize> {
        self.partner.get(j).copied().flatten()
    }

    /// `mu^i_j` in the solution `cols`: its column, or for a pair's signed column
    /// `nu = mu_j - mu_k` its positive part for the first face and negative part for the second.
    pub fn multiplier(&self, i: usize, j: usize, cols: &[f64]) -> f64 {
        let v = cols[self.mu[i][j].index()];
        match self.partner_of(j) {
            Some(k) if j < k => v.max(0.0),
            Some(_) => (-v).max(0.0),
            None => v,
        }
    }
}

/// Builds P_m in `form` (the objective `J`, to be maximised): the states, controls and
/// multipliers, then step by step the control set, the catching-up step and the
/// complementarity ([`super::discrete_rows`]), then the cost's cuts and the zero mean.
pub(super) fn build(
    p: &GeneralProblem,
    m: u32,
    form: Form<'_>,
    cuts: &[Vec<f64>],
) -> (RowProblem, Layout) {
    let partner = match form {
        Form::Branches(_) => opposite_faces(p),
        Form::Milp(_) => Vec::new(),
    };
    build_paired(p, m, form, cuts, &partner)
}

/// [`build`] with a branch LP's opposite faces given (`partner`, [`opposite_faces`]; none
/// paired, each face's slack a column of its own, in the tests that compare the two).
fn build_paired(
    p: &GeneralProblem,
    m: u32,
    form: Form<'_>,
    cuts: &[Vec<f64>],
    partner: &[Option<usize>],
) -> (RowProblem, Layout) {
    let mm = 1usize << m;
    let h = p.period / mm as f64;
    let w = p.face_weights();
    let mut pb = RowProblem::default();
    let xs = state_columns(&mut pb, p, mm, 1.0);
    let nx = xs.len();
    let x_at = |i: usize| &xs[i % nx];
    let us = rows::add_control_columns(&mut pb, p, mm);
    // A chain's per-face columns in its classes' order (rows::face_classes), binaries too.
    let classes = match form {
        Form::Milp(_) => rows::face_classes(p),
        Form::Branches(_) => None,
    };
    let mus = rows::add_multiplier_columns(&mut pb, p, mm, (form, classes.as_deref()), partner, &w);
    let made = classes.map(|c| {
        rows::per_face_columns(&mut pb, (mm, p.c.faces()), &c, |pb, _, _| {
            pb.add_integer_column(0.0, 0..=1)
        })
    });
    let (mut s, mut z) = (Vec::new(), Vec::new());
    for i in 0..mm {
        rows::add_control_rows(&mut pb, p, &us[i]);
        rows::add_dynamics_rows(
            &mut pb,
            p,
            h,
            (x_at(i), x_at(i + 1)),
            (&us[i], &mus[i], partner),
        );
        match form {
            Form::Branches(b) => s.push(rows::add_branch_rows(
                &mut pb,
                p,
                (&b[i], partner),
                x_at(i + 1),
            )),
            Form::Milp(bm) => {
                let made_i = made.as_ref().map(|z| &z[i][..]);
                z.push(rows::add_face_rows(
                    &mut pb,
                    p,
                    bm,
                    (x_at(i + 1), &mus[i]),
                    made_i,
                ));
            }
        }
    }
    let e = rows::add_cost_cuts(&mut pb, p, h, &us, cuts);
    rows::add_zero_mean_rows(&mut pb, p, &us);
    let x = (0..=mm).map(|i| x_at(i).clone()).collect();
    (
        pb,
        Layout {
            x,
            u: us,
            mu: mus,
            partner: partner.to_vec(),
            s,
            z,
            e,
        },
    )
}

/// Most rounds of the outer approximation of a quadratic cost.
pub(super) const MAX_OA_ROUNDS: usize = 40;

/// The state columns at the knots of `pieces` pieces, in units of `unit`: `pieces` of them for
/// a periodic problem (the last knot is the first), `pieces + 1` for a Cauchy problem, whose
/// first is fixed to `x(0) / unit`.
pub(super) fn state_columns(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    pieces: usize,
    unit: f64,
) -> Vec<Vec<Col>> {
    let nx = match p.boundary {
        Boundary::Periodic => pieces,
        Boundary::Initial(_) => pieces + 1,
    };
    (0..nx)
        .map(|i| match &p.boundary {
            Boundary::Initial(x0) if i == 0 => x0
                .iter()
                .map(|&v| pb.add_column(0.0, v / unit..=v / unit))
                .collect(),
            _ => (0..p.states())
                .map(|_| pb.add_column(0.0, f64::NEG_INFINITY..f64::INFINITY))
                .collect(),
        })
        .collect()
}

/// A replayed answer of a periodic problem must end where it began (to `allowed`: `1e-6` of
/// C's scale, plus a phase gait's rounding): else the solver's process and the simulated one
/// differ, and the answer is refused.
pub(super) fn replay_periodic(
    p: &GeneralProblem,
    end: &[f64],
    start: &[f64],
    allowed: f64,
    what: &str,
    replayed: &str,
) -> Result<()> {
    if p.boundary != Boundary::Periodic {
        return Ok(());
    }
    let gap = crate::optimal::process::max_diff(end, start);
    if gap > allowed {
        return Err(Error::Numerical(format!(
            "{what}: the {replayed} is not periodic (x(T) - x(0) = {gap:e})"
        )));
    }
    Ok(())
}

/// The first cut points of a quadratic cost's outer approximation (P_m and phase gaits): 0 and
/// the extreme values of each control component in U; for a separable cost
/// ([`rows::separable`]), 17 points evenly spread over each component's range in U (the
/// crawler's first tangents), whose components are the tangent points.
pub(super) fn initial_cuts(p: &GeneralProblem) -> Result<Vec<Vec<f64>>> {
    let m = p.controls();
    let extreme = |k: usize, sign: f64| -> Result<f64> {
        let mut d = vec![0.0; m];
        d[k] = sign;
        Ok(sign * support_u(&p.control, &d)?)
    };
    if cost_matrix(&p.cost, m).is_some_and(|r| rows::separable(&r).is_some()) {
        let range = (0..m)
            .map(|k| Ok((extreme(k, -1.0)?, extreme(k, 1.0)?)))
            .collect::<Result<Vec<_>>>()?;
        return Ok((0..17)
            .map(|i| {
                let t = i as f64 / 16.0;
                range.iter().map(|&(lo, hi)| lo + t * (hi - lo)).collect()
            })
            .collect());
    }
    let mut cuts = vec![vec![0.0; m]];
    for k in 0..m {
        for sign in [1.0, -1.0] {
            let mut u0 = vec![0.0; m];
            u0[k] = extreme(k, sign)?;
            cuts.push(u0);
        }
    }
    Ok(cuts)
}

/// The optimum of P_m on fixed complementarity branches (an LP; `None` when infeasible):
/// `active[i][j]` holds face `j` at `x^(i+1)` and lets `mu^i_j` be positive. Refused (field
/// `active`) without `2^m` rows of one branch per face.
pub fn solve_general_branch(
    p: &GeneralProblem,
    m: u32,
    active: &[Vec<bool>],
) -> Result<Option<f64>> {
    if p.cost != GeneralCost::None {
        return Err(Error::invalid(
            "objective.cost",
            "a quadratic cost",
            "the branch LP of P_m is linear: f2 = none",
        ));
    }
    let sigma = p.c.faces();
    if 1usize.checked_shl(m) != Some(active.len()) || active.iter().any(|row| row.len() != sigma) {
        return Err(Error::invalid(
            "active",
            format!("{} rows", active.len()),
            format!("needs 2^m = 2^{m} rows of one branch per face ({sigma} each)"),
        ));
    }
    if holds_a_pair(&opposite_faces(p), active) {
        return Ok(None);
    }
    let (pb, _) = build(p, m, Form::Branches(active), &[]);
    let a = Highs::new(pb, Sense::Maximise, "a branch LP of P_m")?.solve()?;
    Ok(match a.status {
        SolveStatus::Optimal => Some(a.objective),
        _ => None,
    })
}

/// The controls of an LP or MILP solution, replayed by the general simulator from its `x^0`:
/// the process they make, checked against the solver's (the reward `int f1` and, for a
/// periodic problem, `x^M = x^0`); a disagreement is an error naming `what`.
pub(super) struct Replayed {
    /// `J` as simulated.
    pub objective: f64,
    /// The simulated process: states `x^0..x^M`, the controls (moved into U against the
    /// solver's feasibility tolerance, [`into_u`]) and the reactions `lambda^i`.
    pub path: PmPath,
}

/// See [`Replayed`].
pub(super) fn replay(
    p: &GeneralProblem,
    m: u32,
    lay: &Layout,
    cols: &[f64],
    what: &str,
) -> Result<Replayed> {
    replay_in(p, (1.0, 1.0), (m, lay, cols), what)
}

/// [`replay`] of a solution of `p` in other units, states and multipliers (so `J`) measured in
/// `s_x` and controls in `s_u` (`units`, [`super::units::Units`]): `x = s_x x'`, `u = s_u u'`.
pub(super) fn replay_in(
    p: &GeneralProblem,
    (s_x, s_u): (f64, f64),
    (m, lay, cols): (u32, &Layout, &[f64]),
    what: &str,
) -> Result<Replayed> {
    let val = |c: &Col| cols[c.index()];
    let x0: Vec<f64> = lay.x[0].iter().map(|c| s_x * val(c)).collect();
    let u: Vec<Vec<f64>> = lay
        .u
        .iter()
        .map(|r| r.iter().map(|c| s_u * val(c)).collect())
        .collect();
    let w = p.face_weights();
    let lp_reward: f64 = s_x
        * (0..lay.mu.len())
            .map(|i| {
                (0..w.len())
                    .map(|j| w[j] * lay.multiplier(i, j, cols))
                    .sum::<f64>()
            })
            .sum::<f64>();
    replay_controls(p, m, &x0, u, lp_reward, what)
}

/// [`replay`] of controls `u` from `x0`, the solver's reward `int f1` being `lp_reward`.
pub(super) fn replay_controls(
    p: &GeneralProblem,
    m: u32,
    x0: &[f64],
    u: Vec<Vec<f64>>,
    lp_reward: f64,
    what: &str,
) -> Result<Replayed> {
    // The controls moved into U against the solver's feasibility tolerance (a box clipped, a
    // polytope by projection).
    let mut centre = None;
    let u: Vec<Vec<f64>> = u
        .into_iter()
        .map(|r| into_u(&p.control, &mut centre, r))
        .collect::<Result<_>>()?;
    let sim = simulate_grid(p, m, x0, &u, "P_m controls")?;
    let scale = p.c.scale();
    let reward = sim.reward;
    if (reward - lp_reward).abs() > 1e-6 * (scale + reward.abs()) {
        return Err(Error::Numerical(format!(
            "{what}: the controls give int f1 = {reward} when simulated, not {lp_reward}"
        )));
    }
    replay_periodic(
        p,
        sim.x.last().expect("steps"),
        x0,
        1e-6 * scale,
        what,
        "simulated process",
    )?;
    Ok(Replayed {
        objective: sim.objective.unwrap_or(f64::NAN),
        path: PmPath {
            x: sim.x,
            u,
            lambda: sim.lambda,
        },
    })
}

/// The catching-up process of P_m's controls `u` (`2^m` rows, one per step of `h = T / 2^m`)
/// from `x0` over one period, the drift stepped explicitly as in P_m's step: what a P_m answer
/// is verified by, here and when a result file is read back. `what` names the controls in
/// errors (a control outside U).
pub fn simulate_grid(
    p: &GeneralProblem,
    m: u32,
    x0: &[f64],
    u: &[Vec<f64>],
    what: &str,
) -> Result<crate::integrate::GeneralSimulation> {
    debug_assert_eq!(u.len(), 1usize << m);
    let mut cauchy = p.clone();
    cauchy.boundary = Boundary::Initial(x0.to_vec());
    run_on_grid(&cauchy, x0, u, what)
}

/// The sweeping process of `p` (its own boundary condition) driven by the piecewise-constant
/// controls `u`, one row per step of the uniform grid `h = T / u.len()`, started from `x0` and
/// stepped as P_m steps (`u.len()` steps per period, the drift explicit). The P_m replay
/// ([`simulate_grid`], a Cauchy problem) and the local method's periodic start run through it.
pub(crate) fn run_on_grid(
    p: &GeneralProblem,
    x0: &[f64],
    u: &[Vec<f64>],
    what: &str,
) -> Result<crate::integrate::GeneralSimulation> {
    let mm = u.len();
    let h = p.period / mm as f64;
    let times: Vec<f64> = (0..mm).map(|i| i as f64 * h).collect();
    let input = ControlInput::new(
        InputKind::PiecewiseConstant,
        p.period,
        times,
        u.to_vec(),
        &p.control,
        what,
    )?;
    let opts = GeneralSimOptions {
        steps_per_period: mm,
        drift: crate::integrate::DriftStep::Explicit,
        ..GeneralSimOptions::DEFAULT
    };
    simulate_general(p, &input, x0, &opts)
}

#[cfg(test)]
#[path = "discrete_tests.rs"]
mod tests;
