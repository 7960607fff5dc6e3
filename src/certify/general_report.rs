//! The one report of a certificate (a P_m process or a phase gait of (P), or of an instance of
//! it such as a crawler, named in its words): every condition with its residual, the
//! continuous group of Theorem 2.2, the margin and the verdict (module docs of
//! [`crate::certify`] and [`crate::certify::general`]).

use super::general_conditions::{
    is_box, residuals, strictly_convex, GeneralFaceMultiplier, GeneralMultipliers,
    GeneralNecessaryConditions, GENERAL_CERTIFICATE_FORMAT,
};
use super::general_kkt::{psi_of, GeneralRaw, GeneralStructure};
use super::general_process::GeneralProcess;
use super::records::ConditionCheck;
use super::stages::{scaled_sup, sup};
use super::verdict::{
    check, discrete_group, law_target, misplaced_mass, norm2, normalisation,
    significant_multipliers, step_distance, verdict,
};
use super::{CertifyOptions, CERTIFICATE_VERSION};
use crate::model::general::{ControlSet, GeneralCost, GeneralProblem};

/// How a certificate names (P)'s objects: (P)'s own words, or an instance's read back in its
/// own names (a crawler's links, blocks and `p + omega`). The numbers are (P)'s either way; the
/// units of the instance live on [`GeneralStructure`] (`state_scale`, `face_scale`,
/// `switching_unit`, `margin_cap`).
pub(super) struct Words {
    /// The switching function as the reason writes it (`B^T p + omega`, `p + omega`).
    pub switching: &'static str,
    /// One control component (`component`, `link`).
    pub component: &'static str,
    /// The instance's name and statement of a condition of (P) (its name and group, "6.2" or
    /// "2.2"), where it has its own.
    pub condition: fn(&str, &str) -> Option<(&'static str, &'static str)>,
    /// The maximised Hamiltonian of a phase, as the duration condition states it.
    pub hamiltonian: &'static str,
}

/// (P)'s own words.
pub(super) const GENERAL_WORDS: Words = Words {
    switching: "B^T p + omega",
    component: "component",
    condition: |_, _| None,
    hamiltonian: "H_i = sum_r rho_{i,r} h_r - <p_i, b> + lambda (Df2(u_i).u_i - f2(u_i))",
};

/// The certificate of `pr` with the multipliers `raw` (scaled as `scaled_by` says), its
/// conditions named in `words`: one report for (P) and for every instance of it.
#[allow(clippy::too_many_arguments)]
pub(crate) fn report(
    p: &GeneralProblem,
    pr: &GeneralProcess,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    scaled_by: String,
    opts: &CertifyOptions,
    drift_term: bool,
    words: &Words,
) -> GeneralNecessaryConditions {
    let m = st.m;
    let discrete = !st.phase;
    let tol = opts.tol;
    let sup_p = scaled_sup(&raw.p, &st.state_scale);
    let ptol = tol * sup_p.max(1.0);
    let disc = residuals(p, st, raw, drift_term, false);
    let (adj, sign) = (disc[0].2, disc[5].2);
    let mut conditions = discrete_group(&disc, ptol, raw.lambda);

    let (psi, switching) = psi_and_switching(p, st, raw);
    // Support: dxi at knot k lies on step k-1 once p is extended piecewise linearly (§9; P_m
    // only: a phase gait's p jumps at its knots); each mass in its face's unit.
    let xi_units: Vec<Vec<f64>> = st
        .active
        .iter()
        .zip(&raw.xi)
        .map(|(faces, xs)| {
            faces
                .iter()
                .zip(xs)
                .map(|(&f, x)| x / st.face_scale[f])
                .collect()
        })
        .collect();
    let misplaced = misplaced_mass(&st.active, &xi_units, discrete);
    // The multipliers solve LPs to the conditions' tolerance: below it, a margin is zero at the
    // solver's resolution (a 1e-12 slack of the margin LP is no measured value).
    // (In units of the switching function: `ptol` times its unit per unit of `p`.)
    let resolution = ptol * st.units.psi;
    let margin = nondegeneracy_margin(p, st, raw, &switching);
    let margin = if margin <= resolution { 0.0 } else { margin };
    let nd_tol = 1e-6 * sup(&switching).max(st.switching_unit).max(1e-300);
    // With lambda > 0 a strictly convex f2 makes the Hamiltonian's maximiser unique whatever
    // sigma; with lambda = 0 the cost has left the Hamiltonian and only the margin could.
    let margin_required = !(strictly_convex(&p.cost, m) && raw.lambda > 0.0);
    let nondeg = !margin_required || margin > nd_tol;
    let law = control_law_residual(p, &pr.u, raw.lambda, &switching, nd_tol);
    // An integral over time: in the user's time (`ResidualUnits::time`), as its tolerance.
    let l1 = l1_maximality(p, st, raw, &psi).map(|v| v / st.units.psi * st.units.time);
    let continuous = ContinuousGroup {
        adj,
        sign,
        misplaced,
        l1,
        period: p.period * st.units.time,
        nontrivial: raw.lambda + sup_p,
        nondegenerate: margin > nd_tol,
        law,
    };
    conditions.extend(continuous.checks(p, ptol, tol));
    for c in &mut conditions {
        if let Some((name, statement)) = (words.condition)(&c.name, &c.theorem) {
            c.name = name.into();
            c.statement = statement.into();
        }
    }

    // The verdict reads the discrete group; a phase gait, an exact process of (P), must also
    // meet Theorem 2.2 itself (sign, support, L^1 maximality, ...; not the non-degeneracy,
    // which makes a verdict degenerate, nor the control law, which is reported only).
    // Times as the user states them (a crawler is certified in periods).
    let times: Vec<f64> = pr.times().iter().map(|t| t * st.units.time).collect();
    let holds = holds_reason(margin_required, is_box(&p.control), words);
    let (verdict, reason) = verdict(&conditions, discrete, raw.lambda, nondeg, &holds, || {
        degenerate_reason(p, words, &switching, margin, resolution, &times)
    });
    let paper = paper_norm(p, st, raw, &psi);
    GeneralNecessaryConditions {
        format: GENERAL_CERTIFICATE_FORMAT.into(),
        version: CERTIFICATE_VERSION,
        method: if discrete { "discrete" } else { "phase" }.into(),
        m: pr.m(),
        verdict,
        reason,
        lambda: raw.lambda,
        objective: pr.objective(p),
        nondegeneracy_margin: margin,
        nondegeneracy_resolution: resolution,
        margin_required,
        normalisation: normalisation(scaled_by, raw.lambda, sup_p, paper),
        conditions,
        multipliers: multipliers_record(pr, st, raw, times, switching, psi),
        one_link: super::one_link::general(p, pr, opts.structure_tol),
        branch_lp: None,
    }
}

/// The multipliers as the certificate records them: per piece `p`, the switching function,
/// `psi`, `u`; `omega`; the weights of U's active rows (numbered from 1); the masses of `dxi`.
fn multipliers_record(
    pr: &GeneralProcess,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    times: Vec<f64>,
    switching: Vec<Vec<f64>>,
    psi: Vec<Vec<f64>>,
) -> GeneralMultipliers {
    GeneralMultipliers {
        xi: face_multipliers(st, raw, &times),
        times,
        p: raw.p.clone(),
        switching,
        psi,
        u: pr.u.clone(),
        omega: raw.omega.clone(),
        normal_cone: st
            .urows_active
            .iter()
            .zip(&raw.rho)
            .map(|(rows, w)| rows.iter().zip(w).map(|(&r, &v)| (r + 1, v)).collect())
            .collect(),
    }
}

/// The reason of a `holds` verdict: the control is unique because `f2` is strictly convex
/// (`margin_required` false), or because the switching function vanishes nowhere (a box U)
/// or leaves it unique (a polytope).
fn holds_reason(margin_required: bool, box_u: bool, words: &Words) -> String {
    match (margin_required, box_u) {
        (false, _) => "the necessary conditions hold with lambda = 1 (f2 strictly convex: the \
                       control is unique)"
            .to_string(),
        (true, true) => format!(
            "the necessary conditions hold with lambda = 1 and {} vanishes nowhere",
            words.switching
        ),
        (true, false) => "the necessary conditions hold with lambda = 1 and B^T p + omega \
                          leaves the control unique"
            .to_string(),
    }
}

/// Why the conditions hold only degenerately (§4 (nndg)): for a box U, where the switching
/// function is least (piece, time, component); for a polytope, the least weight of the
/// normal cone.
fn degenerate_reason(
    p: &GeneralProblem,
    words: &Words,
    switching: &[Vec<f64>],
    margin: f64,
    resolution: f64,
    times: &[f64],
) -> String {
    if !is_box(&p.control) {
        return format!(
            "the conditions hold with lambda = 1 but only degenerately: non-degeneracy margin \
             {margin:.3e} (§4 (nndg) fails)"
        );
    }
    // Where the switching function is 0 at the resolution, the first such place (in time, then
    // component): the least of values below the resolution would be round-off's choice.
    let (j, l) = if margin == 0.0 {
        first_within(switching, resolution)
    } else {
        argmin_abs(switching)
    };
    format!(
        "the conditions hold with lambda = 1 but only degenerately: {} = {} on piece {j} \
         (t = {:.6}), {} {} (§4 (nndg) fails)",
        words.switching,
        if margin == 0.0 {
            format!("0 at the solver's resolution {resolution:.1e}")
        } else {
            format!("{:.3e}", switching[j][l])
        },
        times[j],
        words.component,
        l + 1
    )
}

/// The first (row, column) whose `|value|` is at most `within` (the least `|value|` if none).
fn first_within(rows: &[Vec<f64>], within: f64) -> (usize, usize) {
    rows.iter()
        .enumerate()
        .find_map(|(j, r)| r.iter().position(|v| v.abs() <= within).map(|l| (j, l)))
        .unwrap_or_else(|| argmin_abs(rows))
}

/// The (row, column) of the least `|value|`.
fn argmin_abs(rows: &[Vec<f64>]) -> (usize, usize) {
    let mut best = (0, 0, f64::INFINITY);
    for (j, r) in rows.iter().enumerate() {
        for (l, v) in r.iter().enumerate() {
            if v.abs() < best.2 {
                best = (j, l, v.abs());
            }
        }
    }
    (best.0, best.1)
}

/// `psi_i = -B^T p - omega` per step and the switching function `sigma_i = -psi_i - lambda
/// Df2(u_i)`.
fn psi_and_switching(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let psi: Vec<Vec<f64>> = (0..st.steps).map(|i| psi_of(p, st, raw, i)).collect();
    let switching = psi
        .iter()
        .zip(&st.grad_f2)
        .map(|(psi, g)| {
            psi.iter()
                .zip(g)
                .map(|(s, g)| -s - raw.lambda * g)
                .collect()
        })
        .collect();
    (psi, switching)
}

/// The non-degeneracy margin (§4 (nndg)): for a box U the least `|sigma_l|` over the steps,
/// for a polytope U the least weight `rho` of the normal cone at a vertex of U (0 off a
/// vertex); a weight the LP left at -1e-12 is 0 at its resolution.
fn nondegeneracy_margin(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    switching: &[Vec<f64>],
) -> f64 {
    match &p.control {
        ControlSet::Box { .. } => switching
            .iter()
            .flatten()
            .fold(f64::INFINITY, |a, v| a.min(v.abs())),
        ControlSet::Polytope(_) => (0..st.steps)
            .map(|i| {
                if st.at_vertex[i] {
                    raw.rho[i].iter().fold(f64::INFINITY, |a, &v| a.min(v))
                } else {
                    0.0
                }
            })
            .fold(f64::INFINITY, f64::min),
    }
    .max(0.0)
}

/// The control law weak maximality implies (a box U, f2 = 0 or (c/2)|u|^2): the largest
/// `|u - law| / (upper - lower)` over the steps (controls `u`, switching function `sigma` at
/// `lambda`); `None` where no law is closed-form.
pub(crate) fn control_law_residual(
    p: &GeneralProblem,
    u: &[Vec<f64>],
    lambda: f64,
    switching: &[Vec<f64>],
    nd_tol: f64,
) -> Option<f64> {
    let (ControlSet::Box { lower, upper }, GeneralCost::None | GeneralCost::Quadratic { .. }) =
        (&p.control, &p.cost)
    else {
        return None;
    };
    let c = match p.cost {
        GeneralCost::Quadratic { weight } => weight,
        _ => 0.0,
    };
    let quadratic = (c > 0.0 && lambda > 0.0).then_some(lambda * c);
    let mut worst = 0.0_f64;
    for (s, u) in switching.iter().zip(u) {
        for l in 0..s.len() {
            if let Some(w) = law_target(s[l], quadratic, lower[l], upper[l], nd_tol) {
                worst = worst.max((u[l] - w).abs() / (upper[l] - lower[l]));
            }
        }
    }
    Some(worst)
}

/// Weak maximality in L^1(0, T) with p extended piecewise linearly (§9; a box U): on step i,
/// psi ramps from its value at p_i to that at p_(i+1), u^i fixed. On a phase p is constant
/// (A = 0). `None` for a polytope U.
pub(crate) fn l1_maximality(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    psi: &[Vec<f64>],
) -> Option<f64> {
    let ControlSet::Box { .. } = &p.control else {
        return None;
    };
    let (n, m, steps) = (st.n, st.m, st.steps);
    let discrete = !st.phase;
    let mut l1 = 0.0;
    for i in 0..steps {
        let h = st.tau[i];
        let next = &raw.p[if discrete { (i + 1) % steps } else { i }];
        let end: Vec<f64> = (0..m)
            .map(|l| {
                let btp: f64 = (0..n).map(|q| p.dynamics.b[q][l] * next[q]).sum();
                -btp - raw.omega[l] - raw.lambda * st.grad_f2[i][l]
            })
            .collect();
        for l in 0..m {
            let (a, b) = (psi[i][l], end[l]);
            let up = st.urows_active[i].contains(&(2 * l));
            let down = st.urows_active[i].contains(&(2 * l + 1));
            l1 += step_distance(a, b, h, up, down);
        }
    }
    Some(l1)
}

/// The residuals of Theorem 2.2's continuous group, before they are checked.
struct ContinuousGroup {
    adj: f64,
    sign: f64,
    misplaced: f64,
    /// Theorem 2.2's weak maximality, an integral over time, in the user's time.
    l1: Option<f64>,
    /// The period in the user's time: the weak maximality's tolerance is `ptol T`.
    period: f64,
    nontrivial: f64,
    nondegenerate: bool,
    law: Option<f64>,
}

impl ContinuousGroup {
    /// The checks, in the report's order, at the tolerance `ptol` of p's scale (the control
    /// law at the conditions' `tol`).
    fn checks(&self, p: &GeneralProblem, ptol: f64, tol: f64) -> Vec<ConditionCheck> {
        let mut conditions = vec![
            check(
                "adjoint",
                "2.2",
                "dp = -A^T p dt + sum_j x*_j dxi^j, p(T) = p(0) (Thm 2.2 adjoint, transversality)",
                self.adj,
                ptol,
            ),
            check(
                "sign",
                "2.2",
                "dxi^j >= 0 (Thm 2.2; Thm 6.1 for the paper's P_m: the branch LP of the \
                 computational P_m leaves it free on held faces)",
                self.sign,
                ptol,
            ),
            check(
                "support",
                "2.2",
                "supp dxi^j in {t : face j active at x(t)}: dxi mass on steps where the face is \
                 not active throughout (Thm 2.2 support)",
                self.misplaced,
                ptol,
            ),
        ];
        if let Some(l1) = self.l1 {
            conditions.push(check(
                "weak_maximality",
                "2.2",
                "int_0^T dist(psi(t), N_U(u(t))) dt, psi = -B^T p - omega - lambda Df2(u), p \
                 piecewise linear, in units of max |B_ij| (Thm 2.2; O(h) on P_m grids)",
                l1,
                ptol * self.period,
            ));
        }
        conditions.push(check(
            "nontriviality",
            "2.2",
            "lambda + ||p||_inf > 0 (Thm 2.2)",
            if self.nontrivial > 0.0 { 0.0 } else { 1.0 },
            0.0,
        ));
        conditions.push(check(
            "nondegeneracy",
            "2.2",
            if is_box(&p.control) {
                "sigma = B^T p + omega != 0 componentwise (§4 (nndg)): min |sigma| above 1e-6 \
                 max(sup|sigma|, max|w| max|B_ij|) and the solver's resolution; residual 1 when it is not \
                 (the margin is reported beside J); required unless f2 is strictly convex and \
                 lambda > 0"
            } else {
                "psi in the interior of N_U(u) at a vertex of U on every step: min rho above 1e-6 \
                 max(sup|sigma|, max|w| max|B_ij|) and the solver's resolution; residual 1 when it is not; \
                 required unless f2 is strictly convex and lambda > 0"
            },
            if self.nondegenerate { 0.0 } else { 1.0 },
            0.0,
        ));
        if let Some(law) = self.law {
            conditions.push(check(
                "control_law",
                "2.2",
                "u_l = upper_l where sigma_l < 0, lower_l where sigma_l > 0 (f2 = 0), u = \
                 proj_U(-sigma/(lambda c)) (f2 = (c/2)|u|^2): max |u - law| / (upper - lower)",
                law,
                tol.max(1e-9) * 10.0,
            ));
        }
        conditions
    }
}

/// The paper's normalisation of the multipliers: `lambda + |p(0)| + |omega| + sum_k
/// (|sum_j xi_k^j x*_j| + tau_k |psi_k|)`, the state's vectors (`p` and its jumps) in the units
/// of `state_scale` (a crawler's own `p` and `sum_b xi_b nu_b`; `psi` and `omega` are the
/// controls', the same for an instance).
fn paper_norm(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    psi: &[Vec<f64>],
) -> f64 {
    let n = st.n;
    let in_units =
        |v: &[f64]| -> Vec<f64> { v.iter().zip(&st.state_scale).map(|(v, s)| v * s).collect() };
    let mut paper = raw.lambda + norm2(&in_units(&raw.p[0])) + norm2(&raw.omega);
    for k in 0..st.steps {
        let mut v = vec![0.0; n];
        for (fi, &f) in st.active[k].iter().enumerate() {
            for (l, vl) in v.iter_mut().enumerate() {
                *vl += raw.xi[k][fi] * p.c.normals[f][l];
            }
        }
        paper += norm2(&in_units(&v)) + st.tau[k] * st.units.time * norm2(&psi[k]);
    }
    paper
}

/// The face multipliers `dxi` per knot and face ([`significant_multipliers`]).
fn face_multipliers(
    st: &GeneralStructure,
    raw: &GeneralRaw,
    times: &[f64],
) -> Vec<GeneralFaceMultiplier> {
    significant_multipliers(&st.active, &raw.xi, |k, f, value| GeneralFaceMultiplier {
        knot: k,
        time: times[k],
        face: f + 1,
        value,
    })
}
