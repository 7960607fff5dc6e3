//! Exact continuous-time gaits of the general problem (P) where `A = 0` (theory §7 generalised,
//! theory §11): a mixed-integer linear program over gaits of at most `K` *phases*, each a
//! stretch of constant control `u_j` and of held faces, solved globally in HiGHS and
//! re-verified by the exact event-driven simulator
//! ([`simulate_general_exact`](crate::integrate::simulate_general_exact)).
//!
//! With `g = B u + b`, phase `j` lasts `tau_j >= 0` (`sum_j tau_j = T`) and carries
//! `U_j = tau_j u_j` and the integrated reactions `L_{j,f} = tau_j lambda_{j,f} >= 0`:
//!
//! ```text
//! maximise   sum_{j,f} w_f L_{j,f}
//! subject to x_{j+1} = x_j + B U_j + b tau_j - sum_f L_{j,f} x*_f,   x_j in C,   x_K = x_0
//!            U_j in tau_j U  (box: lower tau_j <= U_j <= upper tau_j; polytope: G U_j <= h tau_j)
//!            sum_j U_j = 0   (zero mean)
//!            L_{j,f} <= M tau_j,   L_{j,f} <= M T s_{j,f}
//!            s_{j,f} = 1  =>  <x*_f, x_j> = c_f = <x*_f, x_{j+1}>   (big-M S_f)
//! ```
//!
//! `w_f` are the face weights (for `f1 = <q, eta>`, `w_f = <q, x*_f>`, as P_m does). `x_0` is
//! fixed for a Cauchy problem and `x_K` is then free.
//!
//! **Every feasible point is the exact solution.** On phase `j` (`tau_j > 0`) put
//! `x(t) = x_j + (t - t_j) v_j` with `v_j = (x_{j+1} - x_j) / tau_j`: a segment between two
//! points of C, so in C (convexity). A face with `L_{j,f} > 0` has `s_{j,f} = 1`, so both ends
//! lie on it; `<x*_f, x(t)>` is affine in `t`, so the face is active along the whole phase, and
//! `eta_j = g(u_j) - v_j = sum_f (L_{j,f} / tau_j) x*_f` (a non-negative combination of active
//! normals) lies in `N_C(x(t))` throughout. So `x` solves `x' in -N_C(x) + g` on every phase,
//! and solutions of the sweeping process are unique: it is *the* solution of its controls.
//! So the MILP need not decide which faces must push: reactions sit only on held faces, a face
//! not held gets none, and no other reaction is possible, since another would make another
//! solution (a face not held that "ought" to push would contradict uniqueness). A held face
//! with `L = 0` is harmless (the face is merely touched). The reward is well defined: with the
//! active normals independent at every vertex of C (checked by `check_sets`, and so at every
//! point of a bounded C, whose active sets are subsets of a vertex's), `eta` has one
//! representation and
//! `f1(eta_j) = sum_f w_f L_{j,f} / tau_j`, which integrates to the objective. A phase of
//! `tau_j = 0` has `U_j = 0`, `L_j = 0`, `x_{j+1} = x_j`: nothing. So there is no
//! discretisation error, and the optimum is global among gaits whose motion is a chain of at
//! most `K` such phases. The paper's §4 one-link optimum needs 4 (free rise, slide on `b`, free
//! fall, slide on `a`); a crawler step of the crawler's phase method (a transition and a slip
//! phase) is 2 phases here, and a phase here is a transition or a slip phase, so on a crawler
//! instance the crawler's optimum over `K` steps is at most this one over `2K` phases, which is
//! at most the crawler's over `2K` steps. Not equal in general: for a crawler of 4 blocks with
//! `T = 8` (measured; its parameters in `tests/general_phase.rs`), 3 crawler steps give
//! 3.0667, 6 phases give 3.0818 (two slip phases in a row, twice), which the crawler reaches
//! with 4 steps.
//!
//! The constants: `S_f = c_f - min_{x in C} <x*_f, x>` (C bounded), and `M = G / sigma_*` of
//! [P_m](super::discrete) with `h = 1`. It bounds the true reaction rates: on a solution
//! `eta = g - Proj_{T_C(x)}(g) = Proj_{N_C(x)}(g)`, so `|eta| <= |g| <= G` and
//! `|lambda| <= |eta| / sigma_*`; since every feasible point is a solution, the bound cuts none.
//!
//! The MILP's columns are measured in units of order one (C's scale, U's largest bound, the
//! time to cross C at the largest speed or the period where that is shorter), since HiGHS
//! holds rows to an absolute tolerance: in the problem's own units a small C or a short period
//! turned that tolerance into a control's mean and a periodicity a reader refuses.
//!
//! Symmetry is broken where it costs `K` binaries: a binary `y_j` per phase with
//! `tau_j <= T y_j`, `s_{j,f} <= y_j` and `y_{j+1} <= y_j`, so unused phases come last (empty
//! phases can always be moved to the end: they do not move `x`).
//!
//! **Free transitions** ([`solve_general_transitions`]): `K` *slots*, each a phase that holds no
//! face (its `L` and `s` fixed at 0: no binaries) followed by a phase as above, `2K` phases with
//! the binaries of `K`; the in-use flag `y` is per slot. A gait of at most `K` phases is a gait
//! of `K` slots (empty transitions), so the optimum over slots is at least the one over `K`
//! phases and at most the one over `2K`; it is what the chain's formulation does for a crawler
//! (a transition before each slip phase), and on crawlers written as (P) it reaches the
//! crawler's `J_K` (measured: `tests/general_phase.rs`, docs/guide/general.md).
//!
//! A quadratic cost `f2(u) = (1/2) u^T R u` (`R = c I` for `quadratic`) costs `tau_j f2(u_j)`
//! per phase, the perspective `tau_j f2(U_j / tau_j)`: convex in `(U_j, tau_j)`, not linear. It
//! enters by its outer approximation, as the crawler's phase method does: an epigraph variable
//! `e_j >= 0` with, for cut points `u0`, `e_j >= (R u0) . U_j - f2(u0) tau_j` (the perspective's
//! tangent plane: `f2(U / tau) >= f2(u0) + Df2(u0) (U / tau - u0)` times `tau`, with
//! `Df2(u0) u0 = 2 f2(u0)`), and `-sum_j e_j` in the objective. Fewer cuts under-estimate the
//! cost, so the MILP's bound stays a bound; the rates `u_j` of each solution become cut points
//! until the true (replayed) `J` of the incumbent meets the bound within 1e-6 (`OA_TOL`; status
//! `approximation_limit` after 40 rounds, as for P_m). The answer is then polished on its held
//! faces (`super::phase_polish`, exact to rounding) and kept when its replay agrees and `J` is
//! no worse.

use super::discrete::{
    big_m, check_sets, column_bound, cost_epigraphs, initial_cuts, state_columns, BigM,
    MAX_OA_ROUNDS,
};
use super::geometry::Geometry;
use super::phase_polish::{polish_general_phases, MilpPhases};
use super::phase_replay::verified_gait;
pub use super::phase_replay::GeneralPhaseGait;
use super::units::Units;
use crate::error::{Error, Result};
use crate::model::general::{ControlSet, GeneralCost, GeneralProblem};
use crate::optimal::milp::{solve_max, MilpStatus, OA_TOL};
use highs::{Col, RowProblem};

/// Largest `K` of the general phase method.
pub const MAX_GENERAL_PHASES: usize = 24;

/// Phases shorter than this times `T` are dropped from the answer (the MILP's zero durations).
pub(super) const EMPTY_PHASE: f64 = 1e-12;

/// Checks that the phase method applies to `p` with `k` phases.
pub fn check_general_phase(p: &GeneralProblem, g: &Geometry, k: usize) -> Result<()> {
    if !p.dynamics.is_state_independent() {
        return Err(Error::invalid(
            "dynamics.A",
            "non-zero",
            "the phase method needs A = 0 (piecewise-linear motion); use P_m (--method discrete)",
        ));
    }
    if !(1..=MAX_GENERAL_PHASES).contains(&k) {
        return Err(Error::invalid(
            "max_phases",
            k,
            format!("must be in 1..={MAX_GENERAL_PHASES}"),
        ));
    }
    check_sets(p, g, "the phase method")
}

/// Checks a growth of the phase method over `range`: what [`check_general_phase`] asks at the
/// largest `K`, and the range itself.
pub(crate) fn check_phase_growth(
    p: &GeneralProblem,
    g: &Geometry,
    range: crate::optimal::growth::GrowthRange,
) -> Result<()> {
    check_general_phase(p, g, range.max_phases)?;
    range.check(MAX_GENERAL_PHASES)
}

/// The columns of the phase MILP, measured in [`Units`] of order one (each row divided by its
/// own unit: the dynamics and the faces by `s_x`, a cost cut by `t_0`; the objective stays in
/// the problem's units). Where HiGHS fails on that model (a period `3e9` crossing times long,
/// in a test), the problem's own units are tried ([`Units::own`]).
struct Layout {
    units: Units,
    x: Vec<Vec<Col>>,
    tau: Vec<Col>,
    u: Vec<Vec<Col>>,
    lam: Vec<Vec<Col>>,
    s: Vec<Vec<Col>>,
}

/// The column families of the phase MILP as [`build`] adds them: the states (`x_K` is `x_0`
/// when periodic), the durations `tau_j`, the slot-in-use flags `y_i`, the integrated controls
/// `U_j`, the integrated reactions `L_{j,f}` (carrying the reward `w_f`) and the held-face flags
/// `s_{j,f}`. A slot is one phase, or with free transitions ([`Slots`]) a transition and a
/// phase.
struct Columns {
    units: Units,
    xs: Vec<Vec<Col>>,
    tau: Vec<Col>,
    y: Vec<Col>,
    us: Vec<Vec<Col>>,
    lam: Vec<Vec<Col>>,
    s: Vec<Vec<Col>>,
    slots: Slots,
}

impl Columns {
    /// The states at the start of phase `i` (`i = K` wraps to `x_0` when periodic).
    fn x_at(&self, i: usize) -> Vec<Col> {
        self.xs[i % self.xs.len()].clone()
    }
}

/// How the `K` of a phase MILP is spent: `K` phases, or `K` slots of a *free transition* (a
/// phase that holds no face: no binaries) followed by a phase, `2K` phases in all, as the
/// chain's formulation has a transition before each slip phase. Every gait of at most `K`
/// phases is a gait of `K` slots (its phases in the slots' second halves, the transitions
/// empty), so the slots' optimum is at least the phases' at the same `K` with as many
/// binaries, and at most theirs at `2K`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Slots {
    /// `K`.
    pub k: usize,
    /// Whether each slot starts with a free transition.
    pub transitions: bool,
}

impl Slots {
    /// `k` slots, with transitions or not.
    fn of(k: usize, transitions: bool) -> Self {
        Slots { k, transitions }
    }

    /// The MILP's phases: `K`, or `2K` with transitions.
    fn phases(self) -> usize {
        if self.transitions {
            2 * self.k
        } else {
            self.k
        }
    }

    /// The slot of phase `j`.
    fn slot(self, j: usize) -> usize {
        if self.transitions {
            j / 2
        } else {
            j
        }
    }

    /// Whether phase `j` is a free transition (holds no face).
    fn free(self, j: usize) -> bool {
        self.transitions && j % 2 == 0
    }

    /// Whether phase `j` ends its slot.
    fn last_of_slot(self, j: usize) -> bool {
        !self.free(j)
    }
}

/// Adds the columns of the phase MILP in `units` ([`Units`]), family by family in this order
/// (the solver's results depend on it): states, `tau_j in [0, T]`, `y_i` per slot, free `U_j`,
/// `L_{j,f} in [0, M T]` with the objective weight `w_f`, `s_{j,f}` (both fixed at 0 on a free
/// transition); in the columns' units `tau'_j in [0, T / t_0]`, `L'_{j,f} in [0, M T / s_x]`
/// with the weight `w_f s_x`.
fn add_columns(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    slots: Slots,
    multiplier: f64,
    units: Units,
) -> Columns {
    let (sigma, m) = (p.c.faces(), p.controls());
    let (t, k) = (p.period, slots.phases());
    let w = p.face_weights();
    let free = || f64::NEG_INFINITY..f64::INFINITY;
    let xs = state_columns(pb, p, k, units.state);
    let period = units.period;
    let tau: Vec<Col> = (0..k).map(|_| pb.add_column(0.0, 0.0..=period)).collect();
    let y: Vec<Col> = (0..slots.k)
        .map(|_| pb.add_integer_column(0.0, 0..=1))
        .collect();
    let us: Vec<Vec<Col>> = (0..k)
        .map(|_| (0..m).map(|_| pb.add_column(0.0, free())).collect())
        .collect();
    let held = |j: usize| if slots.free(j) { 0.0 } else { 1.0 };
    let lam: Vec<Vec<Col>> = (0..k)
        .map(|j| {
            (0..sigma)
                .map(|f| {
                    let top = held(j) * multiplier * t / units.state;
                    pb.add_column(w[f] * units.state, 0.0..=top)
                })
                .collect()
        })
        .collect();
    let s: Vec<Vec<Col>> = (0..k)
        .map(|j| {
            (0..sigma)
                .map(|_| pb.add_integer_column(0.0, 0..=i32::from(!slots.free(j))))
                .collect()
        })
        .collect();
    Columns {
        units,
        xs,
        tau,
        y,
        us,
        lam,
        s,
        slots,
    }
}

/// `U_j in tau_j U` for phase `j`: the box `lower tau_j <= U_j <= upper tau_j` or the polytope
/// `G U_j <= h tau_j`.
fn add_control_rows(pb: &mut RowProblem, p: &GeneralProblem, cols: &Columns, j: usize) {
    let (us, tau, su) = (&cols.us, &cols.tau, cols.units.control);
    match &p.control {
        ControlSet::Box { lower, upper } => {
            for c in 0..p.controls() {
                pb.add_row(..=0.0, [(us[j][c], 1.0), (tau[j], -upper[c] / su)]);
                pb.add_row(0.0.., [(us[j][c], 1.0), (tau[j], -lower[c] / su)]);
            }
        }
        ControlSet::Polytope(u) => {
            for f in 0..u.faces() {
                let mut row: Vec<_> = us[j]
                    .iter()
                    .zip(&u.normals[f])
                    .map(|(&c, &a)| (c, a))
                    .collect();
                row.push((tau[j], -u.offsets[f] / su));
                pb.add_row(..=0.0, row);
            }
        }
    }
}

/// The state update of phase `j`, one row per state component:
/// `x_{j+1} - x_j - B U_j - b tau_j + sum_f L_{j,f} x*_f = 0`.
fn add_dynamics_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    cols: &Columns,
    j: usize,
    (xj, xn): (&[Col], &[Col]),
) {
    let (n, sigma, m) = (p.states(), p.c.faces(), p.controls());
    let Units {
        time,
        state,
        control,
        ..
    } = cols.units;
    for r in 0..n {
        let mut row = vec![(xn[r], 1.0), (xj[r], -1.0)];
        for c in 0..m {
            let b = p.dynamics.b[r][c];
            if b != 0.0 {
                row.push((cols.us[j][c], -b * time * control / state));
            }
        }
        if p.dynamics.drift[r] != 0.0 {
            row.push((cols.tau[j], -p.dynamics.drift[r] * time / state));
        }
        for f in 0..sigma {
            let a = p.c.normals[f][r];
            if a != 0.0 {
                row.push((cols.lam[j][f], a));
            }
        }
        pb.add_row(0.0..=0.0, merged(row));
    }
}

/// The face rows of phase `j`, face by face: `L_{j,f} <= M tau_j`, `L_{j,f} <= M T s_{j,f}`,
/// `s_{j,f} <= y_j`, and the held face `s_{j,f} = 1 => <x*_f, x> = c_f` at both ends of the
/// phase (big-M `S_f`).
fn add_face_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    cols: &Columns,
    bm: &BigM,
    j: usize,
    (xj, xn): (&[Col], &[Col]),
) {
    if cols.slots.free(j) {
        // A free transition holds no face: its L and s are fixed at 0.
        return;
    }
    let (tau, y, lam, s) = (&cols.tau, &cols.y[cols.slots.slot(j)], &cols.lam, &cols.s);
    // The rate bound `M` in the columns' units: `L' <= (M t_0 / s_x) tau'`.
    let (sx, rate) = (
        cols.units.state,
        bm.multiplier * cols.units.time / cols.units.state,
    );
    let period = cols.units.period;
    for f in 0..p.c.faces() {
        let (c, slack) = (p.c.offsets[f] / sx, bm.slack[f] / sx);
        pb.add_row(..=0.0, [(lam[j][f], 1.0), (tau[j], -rate)]);
        pb.add_row(..=0.0, [(lam[j][f], 1.0), (s[j][f], -rate * period)]);
        pb.add_row(..=0.0, [(s[j][f], 1.0), (*y, -1.0)]);
        // <x*_f, x> - S_f s >= c_f - S_f at both ends.
        for end in [xj, xn] {
            let mut row: Vec<_> = end
                .iter()
                .zip(&p.c.normals[f])
                .map(|(&col, &a)| (col, a))
                .collect();
            row.push((s[j][f], -slack));
            pb.add_row(c - slack..=f64::INFINITY, row);
        }
    }
}

/// The rows of phase `j` in order: `tau_j <= T y_i` (`i` its slot), `y_{i+1} <= y_i` at a
/// slot's last phase, the control set, the state update, the faces.
fn add_phase_rows(pb: &mut RowProblem, p: &GeneralProblem, cols: &Columns, bm: &BigM, j: usize) {
    let (tau, y, i) = (&cols.tau, &cols.y, cols.slots.slot(j));
    // tau_j <= T y_i, y_{i+1} <= y_i.
    pb.add_row(..=0.0, [(tau[j], 1.0), (y[i], -cols.units.period)]);
    if cols.slots.last_of_slot(j) && i + 1 < y.len() {
        pb.add_row(..=0.0, [(y[i + 1], 1.0), (y[i], -1.0)]);
    }
    add_control_rows(pb, p, cols, j);
    let (xj, xn) = (cols.x_at(j), cols.x_at(j + 1));
    add_dynamics_rows(pb, p, cols, j, (&xj, &xn));
    add_face_rows(pb, p, cols, bm, j, (&xj, &xn));
}

/// Every state in C (`x_K` is `x_0` when periodic) and, with a zero-mean control,
/// `sum_j U_j = 0`.
fn add_state_and_mean_rows(pb: &mut RowProblem, p: &GeneralProblem, cols: &Columns) {
    for xj in &cols.xs {
        for f in 0..p.c.faces() {
            let row: Vec<_> = xj
                .iter()
                .zip(&p.c.normals[f])
                .map(|(&col, &a)| (col, a))
                .collect();
            pb.add_row(..=p.c.offsets[f] / cols.units.state, row);
        }
    }
    if p.zero_mean {
        for c in 0..p.controls() {
            let row: Vec<_> = cols.us.iter().map(|u| (u[c], 1.0)).collect();
            pb.add_row(0.0..=0.0, row);
        }
    }
}

/// The outer approximation of a quadratic cost on the phases ([`cost_epigraphs`], the same
/// cuts as P_m's): per phase and epigraph a column `e` (objective `-1`; in the columns' units
/// `e = t_0 e'`, objective `-t_0`) with the perspectives of its cuts, `e - a . U_j + c tau_j >= 0`.
fn add_cost_cuts(pb: &mut RowProblem, p: &GeneralProblem, cols: &Columns, cuts: &[Vec<f64>]) {
    let epigraphs = cost_epigraphs(p, cuts);
    // `e = t_0 e'`, and each cut divided by `t_0`.
    let Units { time, control, .. } = cols.units;
    for j in 0..cols.tau.len() {
        for cuts in &epigraphs {
            let e = pb.add_column(-time, 0.0..);
            for (a, c) in cuts {
                let mut row = vec![(e, 1.0), (cols.tau[j], *c)];
                row.extend(a.iter().map(|&(k, v)| (cols.us[j][k], -v * control)));
                pb.add_row(0.0..=f64::INFINITY, row);
            }
        }
    }
}

/// The phase MILP of `slots` with the cost's cuts at `cuts` (module docs): its columns, then
/// `sum_j tau_j = T`, the rows of each phase, the states in C, the zero mean and the cost's
/// cuts, in this order.
fn build(
    p: &GeneralProblem,
    g: &Geometry,
    slots: Slots,
    cuts: &[Vec<f64>],
    units: Units,
) -> Result<(RowProblem, Layout)> {
    let bm = big_m(p, g, 1.0)?;
    let k = slots.phases();
    let mut pb = RowProblem::default();
    let cols = add_columns(&mut pb, p, slots, bm.multiplier, units);
    // sum_j tau_j = T.
    let period = cols.units.period;
    pb.add_row(
        period..=period,
        cols.tau.iter().map(|&c| (c, 1.0)).collect::<Vec<_>>(),
    );
    for j in 0..k {
        add_phase_rows(&mut pb, p, &cols, &bm, j);
    }
    add_state_and_mean_rows(&mut pb, p, &cols);
    add_cost_cuts(&mut pb, p, &cols, cuts);
    let x = (0..=k).map(|i| cols.x_at(i)).collect();
    Ok((
        pb,
        Layout {
            units: cols.units,
            x,
            tau: cols.tau,
            u: cols.us,
            lam: cols.lam,
            s: cols.s,
        },
    ))
}

/// `row` with the coefficients of a repeated column summed (with `K = 1` and a periodic
/// problem `x_1` is `x_0`), which HiGHS would refuse.
fn merged(row: Vec<(Col, f64)>) -> Vec<(Col, f64)> {
    let mut out: Vec<(Col, f64)> = Vec::with_capacity(row.len());
    for (c, a) in row {
        match out.iter_mut().find(|(d, _)| d.index() == c.index()) {
            Some(e) => e.1 += a,
            None => out.push((c, a)),
        }
    }
    out
}

/// The globally optimal gait among those of at most `k` phases (module docs), re-verified by
/// the exact simulator, within the job's deadline ([`crate::progress::within`]).
pub fn solve_general_phase(p: &GeneralProblem, g: &Geometry, k: usize) -> Result<GeneralPhaseGait> {
    solve_general_slots(p, g, Slots::of(k, false))
}

/// The globally optimal gait of `k` slots of a free transition and a phase (module docs),
/// re-verified by the exact simulator: at least [`solve_general_phase`]'s at the same `k`, with as
/// many binaries, within the job's deadline ([`crate::progress::within`]). Its gait has up to `2k`
/// phases.
pub fn solve_general_transitions(
    p: &GeneralProblem,
    g: &Geometry,
    k: usize,
) -> Result<GeneralPhaseGait> {
    solve_general_slots(p, g, Slots::of(k, true))
}

/// [`solve_general_phase`] or [`solve_general_transitions`] by `slots`.
fn solve_general_slots(p: &GeneralProblem, g: &Geometry, slots: Slots) -> Result<GeneralPhaseGait> {
    let k = slots.k;
    check_general_phase(p, g, k)?;
    let what = format!("the phase MILP of the general problem (K = {k})");
    let mut cuts = initial_cuts(p)?;
    let mut round = 0;
    loop {
        round += 1;
        let (phases, milp_objective, bound, status) = solve_milp(p, g, slots, &cuts, &what)?;
        let mut sol = verified_gait(p, &phases, milp_objective, bound, status, k, &what)?;
        sol.rounds = round;
        // Within `OA_TOL` of the bound relative to `|J|`, or to the floor below it, as P_m's.
        let j_scale = sol.objective.abs().max(p.j_floor());
        let done = p.cost == GeneralCost::None
            || sol.certificate.bound - sol.objective <= OA_TOL * j_scale
            || status != MilpStatus::Optimal; // the MILP's own status
        if done {
            return Ok(polished(p, g, sol, &what));
        }
        if round >= MAX_OA_ROUNDS {
            sol.certificate.status = MilpStatus::ApproximationLimit;
            return Ok(polished(p, g, sol, &what));
        }
        cuts.extend(sol.controls.iter().cloned());
    }
}

/// One phase MILP in [`Units`] of order one, or in the problem's own where HiGHS fails on
/// those: its phases, objective, bound (the column bound when the time limit left HiGHS without
/// one) and status.
fn solve_milp(
    p: &GeneralProblem,
    g: &Geometry,
    slots: Slots,
    cuts: &[Vec<f64>],
    what: &str,
) -> Result<(MilpPhases, f64, f64, MilpStatus)> {
    let gap = 1e-9 * p.c.scale().max(1e-300);
    let units = Units::of(p);
    let (pb, mut lay) = build(p, g, slots, cuts, units)?;
    let (cols, milp_objective, bound, status) = match solve_max(pb, what, None, gap) {
        Err(Error::Numerical(_)) if units != Units::own(p) => {
            let pb;
            (pb, lay) = build(p, g, slots, cuts, Units::own(p))?;
            solve_max(pb, what, None, gap)?
        }
        answer => answer?,
    };
    let bound = match bound {
        Some(b) => b,
        None => column_bound(p, big_m(p, g, 1.0)?.multiplier * p.period),
    };
    Ok((read_phases(&lay, &cols), milp_objective, bound, status))
}

/// `sol` polished on its held faces when it has a cost ([`super::phase_polish`]): the polished
/// gait, verified as the MILP's is, with the MILP's status, bound and rounds, when the replay
/// agrees and `J` is no worse; else `sol`.
fn polished(
    p: &GeneralProblem,
    g: &Geometry,
    sol: GeneralPhaseGait,
    what: &str,
) -> GeneralPhaseGait {
    let Some(phases) = polish_general_phases(p, g, &sol.durations, &sol.held, EMPTY_PHASE) else {
        return sol;
    };
    // The polish's own objective: int f1 less the exact cost of its phases.
    let w = p.face_weights();
    let objective: f64 = phases
        .integrated
        .iter()
        .zip(phases.increments.iter().zip(&phases.durations))
        .map(|(r, (u, tau))| {
            let rate: Vec<f64> = u.iter().map(|v| v / tau).collect();
            r.iter().zip(&w).map(|(l, w)| w * l).sum::<f64>() - tau * p.cost.eval(&rate)
        })
        .sum();
    let c = &sol.certificate;
    match verified_gait(
        p,
        &phases,
        objective,
        c.bound,
        c.status,
        sol.max_phases,
        what,
    ) {
        Ok(mut better)
            if better.objective >= sol.objective - 1e-9 * sol.objective.abs().max(p.j_floor()) =>
        {
            better.certificate.status = c.status;
            better.rounds = sol.rounds;
            better
        }
        _ => sol,
    }
}

/// The MILP's gait read off its columns: the phases longer than [`EMPTY_PHASE`] `T`. A face's
/// integrated reaction is kept on a held face only, and at least 0: the MILP's `L_{j,f} <= M T
/// s_{j,f}` and `L_{j,f} >= 0` hold to HiGHS's feasibility tolerance only, and on a phase of
/// `1e-12 T` that noise divided by the duration gave reactions of 0.8 and 1.6 on faces the
/// phase does not hold (a random quadrilateral, `K = 3`).
fn read_phases(lay: &Layout, cols: &[f64]) -> MilpPhases {
    let val = |c: &Col| cols[c.index()];
    let Units {
        time,
        state,
        control,
        period,
    } = lay.units;
    let at = |c: &Col| state * val(c);
    let mut phases = MilpPhases {
        states: vec![lay.x[0].iter().map(at).collect::<Vec<f64>>()],
        ..MilpPhases::default()
    };
    for j in 0..lay.tau.len() {
        let tau = val(&lay.tau[j]);
        if tau <= EMPTY_PHASE * period {
            continue;
        }
        phases.durations.push(time * tau);
        phases
            .increments
            .push(lay.u[j].iter().map(|c| time * control * val(c)).collect());
        let held: Vec<usize> = (0..lay.s[j].len())
            .filter(|&f| val(&lay.s[j][f]) > 0.5)
            .map(|f| f + 1)
            .collect();
        phases.integrated.push(
            lay.lam[j]
                .iter()
                .enumerate()
                .map(|(f, c)| {
                    if held.contains(&(f + 1)) {
                        at(c).max(0.0)
                    } else {
                        0.0
                    }
                })
                .collect(),
        );
        phases.held.push(held);
        phases.states.push(lay.x[j + 1].iter().map(at).collect());
    }
    phases
}
