//! The records and residuals of a general P_m certificate ([`crate::certify::general`]): the
//! multipliers and the necessary conditions as written, the discrete residuals recomputed in
//! floating point, and the properties of `f2` and U that the verdict reads. Below the driver
//! ([`crate::certify::general`]) and the report (`general_report`), which both use them.

use super::general_kkt::{psi_of, GeneralRaw, GeneralStructure};
use super::general_process::GeneralProcess;
use super::{CertifyOptions, NecessaryConditions};
use crate::error::{Error, Result};
use crate::model::general::{dot, ControlSet, GeneralCost, GeneralProblem};
use serde::Serialize;

/// Value of the `format` of a [`GeneralNecessaryConditions`].
pub const GENERAL_CERTIFICATE_FORMAT: &str = "crawlopt-general-necessary-conditions";

/// The mass of `dxi` at one knot on one face.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralFaceMultiplier {
    /// Knot `k` (`0..M`).
    pub knot: usize,
    /// `t_k`.
    pub time: f64,
    /// Face, 1-based.
    pub face: usize,
    /// `xi_{k,f}` (Theorem 2.2 sign: `>= 0`).
    pub value: f64,
}

/// The multipliers per piece (a step of P_m or a phase).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralMultipliers {
    /// Knot times `t_0 = 0, ..., t_P = T` (`t_k = k h` on P_m).
    pub times: Vec<f64>,
    /// `p_i` (the adjoint on step `i`).
    pub p: Vec<Vec<f64>>,
    /// The switching function `sigma_i = B^T p_i + omega`.
    pub switching: Vec<Vec<f64>>,
    /// `psi_i = -B^T p_i - omega - lambda R u^i`.
    pub psi: Vec<Vec<f64>>,
    /// `u^i`.
    pub u: Vec<Vec<f64>>,
    /// `omega` (per unit time).
    pub omega: Vec<f64>,
    /// `psi_i`'s weights on the active rows of U, as (row 1-based, weight); a box's rows are
    /// `u_l <= upper_l` (row `2l - 1`) and `-u_l <= -lower_l` (row `2l`).
    pub normal_cone: Vec<Vec<(usize, f64)>>,
    /// The non-zero masses of `dxi` (above `1e-14` times the largest).
    pub xi: Vec<GeneralFaceMultiplier>,
}

/// The certificate of a general P_m process or phase gait (module docs): the one record of
/// [`NecessaryConditions`] with (P)'s multipliers.
pub type GeneralNecessaryConditions = NecessaryConditions<GeneralMultipliers>;

/// The discrete residuals as (name, statement, residual), recomputed in floating point; with
/// `durations_free` (phase gaits) also the stationarity in the durations.
pub(crate) fn residuals(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    drift_term: bool,
    durations_free: bool,
) -> Vec<(&'static str, &'static str, f64)> {
    let (adj, comp, lp_sign) = adjoint_terms(p, st, raw, drift_term);
    let react = reaction_term(p, st, raw);
    let (maxim, ham_lo, ham_hi) = maximality_terms(p, st, raw);
    let mut out = vec![
        (
            "adjoint",
            "adjoint equation and transversality: p_k - p_(k-1) = -tau_k A^T p_k + sum_f \
             xi_{k,f} x*_f, p(T) = p(0) (Thm 6.2 (px), (p2mx))",
            adj,
        ),
        (
            "complementarity",
            "xi_{k,f} (c_f - <x*_f, x^k>) = 0: dxi only where its face is active, the slack in \
             units of C's scale (Thm 6.1 (necd1))",
            comp / st.units.slack,
        ),
        (
            "reaction_stationarity",
            "lambda w_f + <p_i, x*_f> = 0 for a reaction on face f in piece i, <= 0 at a \
             biactive face (branch LP in mu; Thm 6.2 (pr), eta in df1)",
            react.max(0.0),
        ),
        (
            "branch_face_sign",
            "xi_{k,f} <= 0 on an active face no reaction holds (a true inequality of the branch \
             LP)",
            lp_sign.max(0.0),
        ),
        (
            "weak_maximality",
            "psi_i = -B^T p_i - omega - lambda Df2(u_i) in N_U(u_i): |psi_i - sum_r rho_{i,r} G_r| \
             with rho >= 0 on the active rows of U, in units of max |B_ij| (Thm 6.2 (pw))",
            maxim / st.units.psi,
        ),
        ("sign", "xi_{k,f} >= 0", super::stages::sign_residual(st, raw)),
    ];
    if durations_free && st.phase {
        out.push((
            "duration_stationarity",
            "H_i = sum_r rho_{i,r} h_r - <p_i, b> + lambda (Df2(u_i).u_i - f2(u_i)) is the same \
             on every phase (phase LP stationary in the durations: the maximised Hamiltonian is \
             constant); residual (max H - min H)/2 in units of the fastest rate of a state",
            0.5 * (ham_hi - ham_lo) / st.units.speed,
        ));
    }
    out
}

/// The residuals at the knots (Theorem 6.2 (px), (p2mx); Theorem 6.1 (necd1)): the adjoint
/// equation's `p_k - p_(k-1) + tau_k A^T p_k - sum_f xi_{k,f} x*_f` (without the `A^T` term when
/// `drift_term` is false), the complementarity `|xi| slack` and the largest `xi` on a face no
/// reaction holds, each the largest over the knots.
fn adjoint_terms(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    drift_term: bool,
) -> (f64, f64, f64) {
    let (n, steps) = (st.n, st.steps);
    let (mut adj, mut comp, mut lp_sign) = (0.0_f64, 0.0_f64, 0.0_f64);
    for k in 0..steps {
        let prev = (k + steps - 1) % steps;
        for l in 0..n {
            let mut v = raw.p[k][l] - raw.p[prev][l];
            if drift_term {
                v += st.tau[k]
                    * (0..n)
                        .map(|q| p.dynamics.a[q][l] * raw.p[k][q])
                        .sum::<f64>();
            }
            for (fi, &f) in st.active[k].iter().enumerate() {
                v -= raw.xi[k][fi] * p.c.normals[f][l];
            }
            adj = adj.max(v.abs() * st.state_scale[l]);
        }
        for (fi, &x) in raw.xi[k].iter().enumerate() {
            comp = comp.max(x.abs() * st.slack[k][fi]);
            if !st.held[k][fi] {
                lp_sign = lp_sign.max(x / st.face_scale[st.active[k][fi]]);
            }
        }
    }
    (adj, comp, lp_sign)
}

/// Reaction stationarity (Theorem 6.2 (pr)): the largest `|lambda w_f + <p_i, x*_f>|` on a face
/// reacting on piece `i`, and the largest signed value at a biactive face (not yet clipped at 0).
fn reaction_term(p: &GeneralProblem, st: &GeneralStructure, raw: &GeneralRaw) -> f64 {
    let steps = st.steps;
    let mut react = 0.0_f64;
    for i in 0..steps {
        for &(f, reacts) in &st.reacting[i] {
            let g = (raw.lambda * st.w[f] + dot(&raw.p[i], &p.c.normals[f])) * st.face_scale[f];
            react = react.max(if reacts { g.abs() } else { g });
        }
    }
    react
}

/// Weak maximality (Theorem 6.2 (pw)): the largest `|psi_i - sum_r rho_{i,r} G_r|` (weights
/// clipped at 0), and the smallest and largest maximised Hamiltonian `H_i = sum_r rho_{i,r} h_r
/// - <p_i, b> + lambda cost_h_i` over the pieces.
fn maximality_terms(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
) -> (f64, f64, f64) {
    let mut maxim = 0.0_f64;
    let (mut ham_lo, mut ham_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..st.steps {
        let psi = psi_of(p, st, raw, i);
        for l in 0..st.m {
            let cone: f64 = st.urows_active[i]
                .iter()
                .zip(&raw.rho[i])
                .map(|(&r, w)| w.max(0.0) * st.urows[r].0[l])
                .sum();
            maxim = maxim.max((psi[l] - cone).abs());
        }
        let ham = st.urows_active[i]
            .iter()
            .zip(&raw.rho[i])
            .map(|(&r, w)| w.max(0.0) * st.urows[r].1)
            .sum::<f64>()
            - dot(&raw.p[i], &p.dynamics.drift)
            + raw.lambda * st.cost_h[i];
        ham_lo = ham_lo.min(ham);
        ham_hi = ham_hi.max(ham);
    }
    (maxim, ham_lo, ham_hi)
}

/// Whether `f2` is strictly convex (`R` positive definite).
pub(crate) fn strictly_convex(cost: &GeneralCost, m: usize) -> bool {
    match cost {
        GeneralCost::None => false,
        GeneralCost::Quadratic { weight } => *weight > 0.0,
        GeneralCost::Matrix { matrix } => {
            let r = nalgebra::DMatrix::from_fn(m, m, |i, k| matrix[i][k]);
            // A decomposition that fails counts as not strictly convex.
            crate::linalg::symmetric_eigen(r).is_some_and(|e| {
                let scale = e.eigenvalues.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
                e.eigenvalues.iter().all(|&v| v > 1e-12 * scale)
            })
        }
    }
}

/// Whether U is a box.
pub(crate) fn is_box(u: &ControlSet) -> bool {
    matches!(u, ControlSet::Box { .. })
}

/// The discrete residuals (name, residual; the group "6.2" and the sign) of given multipliers
/// at `lambda`: `p`, `omega`, the `dxi` masses and the normal-cone weights of `mult` (the rest
/// of it is not read). For checking multipliers found elsewhere, e.g. a crawler certificate's
/// after the change of variables; a mass on a face inactive at its knot, or a weight on a row of
/// U inactive at its step, is an error naming it.
pub fn residuals_of(
    p: &GeneralProblem,
    pr: &GeneralProcess,
    lambda: f64,
    mult: &GeneralMultipliers,
    opts: &CertifyOptions,
) -> Result<Vec<(&'static str, f64)>> {
    pr.check(p, opts.structure_tol)?;
    let st = GeneralStructure::of(p, pr, opts.structure_tol);
    let shape_ok = mult.p.len() == st.steps
        && mult.p.iter().all(|r| r.len() == st.n)
        && mult.omega.len() == st.m
        && mult.normal_cone.len() == st.steps;
    if !shape_ok {
        return Err(Error::invalid(
            "multipliers",
            "their shapes",
            "need p per step (n values), omega (m values) and normal-cone weights per step",
        ));
    }
    let mut xi: Vec<Vec<f64>> = st.active.iter().map(|a| vec![0.0; a.len()]).collect();
    for x in &mult.xi {
        let slot = (x.knot < st.steps)
            .then(|| st.active[x.knot].iter().position(|&f| f + 1 == x.face))
            .flatten()
            .ok_or_else(|| {
                Error::invalid(
                    format!("multipliers.xi (knot {}, face {})", x.knot, x.face),
                    x.value,
                    "the face is not active at that knot",
                )
            })?;
        xi[x.knot][slot] += x.value;
    }
    let mut rho: Vec<Vec<f64>> = st.urows_active.iter().map(|a| vec![0.0; a.len()]).collect();
    for (i, rows) in mult.normal_cone.iter().enumerate() {
        for &(r, v) in rows {
            let slot = st.urows_active[i]
                .iter()
                .position(|&q| q + 1 == r)
                .ok_or_else(|| {
                    Error::invalid(
                        format!("multipliers.normal_cone[{i}] (row {r})"),
                        v,
                        "the row of U is not active at that step",
                    )
                })?;
            rho[i][slot] += v;
        }
    }
    let raw = GeneralRaw {
        lambda,
        p: mult.p.clone(),
        xi,
        omega: mult.omega.clone(),
        rho,
    };
    Ok(residuals(p, &st, &raw, true, false)
        .into_iter()
        .map(|(name, _, r)| (name, r))
        .collect())
}
