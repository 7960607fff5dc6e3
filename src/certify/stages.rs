//! The search for multipliers of the one certificate ([`crate::certify::general`], on (P) or on
//! an instance of it such as a crawler's): with `lambda = 1`, three LPs (least violation `r` of
//! the branch LP's KKT system, then least violation of `xi >= 0` keeping `r`, then the largest
//! non-degeneracy margin keeping both); if `r` stays above tolerance, a degenerate multiplier
//! with `lambda = 0` (a generic functional and its opposite maximised over the homogeneous
//! conditions in a box, the maximiser scaled to `max(|p|, |omega|) = 1`). Every size is taken
//! in the structure's units (`GeneralStructure::state_scale`, `face_scale`: a crawler's own
//! `p` and `xi`). Module docs of [`crate::certify`].

use super::general_kkt::{GeneralRaw, GeneralStructure, Norm, Stage};
use crate::error::{Error, Result};

/// The rows divided by `by` (a degenerate multiplier's scaling).
fn divided(rows: Vec<Vec<f64>>, by: f64) -> Vec<Vec<f64>> {
    rows.into_iter()
        .map(|r| r.into_iter().map(|v| v / by).collect())
        .collect()
}

/// `max |v|` over the rows.
pub(crate) fn sup(rows: &[Vec<f64>]) -> f64 {
    rows.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// `sup |p|` with each state's adjoint in its unit (`state_scale`: a crawler's own `p`).
pub(crate) fn scaled_sup(p: &[Vec<f64>], state_scale: &[f64]) -> f64 {
    p.iter()
        .flat_map(|p| p.iter().zip(state_scale).map(|(v, s)| (v * s).abs()))
        .fold(0.0, f64::max)
}

/// The largest violation of `xi >= 0` (Theorem 2.2 sign), each mass in its face's unit
/// (`xi / face_scale`: a crawler's `xi` per unnormalised `nu_b`).
pub(crate) fn sign_residual(st: &GeneralStructure, raw: &GeneralRaw) -> f64 {
    let mut s = 0.0_f64;
    for (k, row) in raw.xi.iter().enumerate() {
        for (fi, &x) in row.iter().enumerate() {
            s = s.max(-x / st.face_scale[st.active[k][fi]]);
        }
    }
    s
}

/// The same multipliers divided by `by`, marked degenerate (`lambda = 0`).
fn degenerate(raw: GeneralRaw, by: f64) -> GeneralRaw {
    GeneralRaw {
        lambda: 0.0,
        p: divided(raw.p, by),
        xi: divided(raw.xi, by),
        omega: raw.omega.into_iter().map(|v| v / by).collect(),
        rho: divided(raw.rho, by),
    }
}

/// The search: `solve(lambda, stage, norm)` is the multiplier LP, `residual` the KKT residual
/// recomputed in floating point, `st` the structure whose units measure `p`, `xi` and the
/// margin's bound (`GeneralStructure::margin_cap`), `sign_hard` whether `xi >= 0` is imposed
/// in the degenerate search. Returns the multipliers and how they are scaled.
pub(crate) fn search(
    solve: impl Fn(f64, Stage, Option<Norm>) -> Result<Option<GeneralRaw>>,
    residual: impl Fn(&GeneralRaw) -> f64,
    st: &GeneralStructure,
    tol: f64,
    sign_hard: bool,
) -> Result<(GeneralRaw, String)> {
    let eps = 1e-12;
    let cap = st.margin_cap;
    // Always feasible (p constant, xi = 0, r large); an infeasible report is a solver failure.
    let first = solve(1.0, Stage::Kkt, None)?.ok_or_else(|| {
        Error::Numerical("certify: HiGHS found the multiplier LP infeasible".into())
    })?;
    let r1 = residual(&first);
    if r1 <= tol * scaled_sup(&first.p, &st.state_scale).max(1.0) {
        let r_max = r1 * (1.0 + 1e-6) + eps;
        let Some(sg) = solve(1.0, Stage::Sign { r_max }, None)? else {
            return Ok((first, "lambda = 1".into()));
        };
        let s_max = sign_residual(st, &sg) * (1.0 + 1e-6) + eps;
        let margin = solve(1.0, Stage::Margin { r_max, s_max, cap }, None)?;
        return Ok((margin.unwrap_or(sg), "lambda = 1".into()));
    }
    for sign in [1.0, -1.0] {
        let Some(raw) = solve(0.0, Stage::Kkt, Some(Norm { sign, sign_hard }))? else {
            continue;
        };
        let size = scaled_sup(&raw.p, &st.state_scale)
            .max(raw.omega.iter().fold(0.0_f64, |m, v| m.max(v.abs())));
        if size < 1e-6 {
            continue;
        }
        let raw = degenerate(raw, size);
        if residual(&raw) <= tol {
            return Ok((raw, "lambda = 0, max(|p|, |omega|) = 1".into()));
        }
    }
    Ok((first, "lambda = 1".into()))
}
