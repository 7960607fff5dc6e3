//! The search for multipliers shared by the crawler's certificate ([`crate::certify`]) and the
//! general one ([`crate::certify::general`]), which differ only in their multiplier LPs and
//! residuals: with `lambda = 1`, three LPs (least violation `r` of the branch LP's KKT system,
//! then least violation of `xi >= 0` keeping `r`, then the largest non-degeneracy margin keeping
//! both); if `r` stays above tolerance, a degenerate multiplier with `lambda = 0` (a generic
//! functional and its opposite maximised over the homogeneous conditions in a box, the
//! maximiser scaled to `max(|p|, |omega|) = 1`). Module docs of [`crate::certify`].

use super::kkt::{Norm, Stage};
use crate::error::{Error, Result};

/// Multipliers the search handles.
pub(crate) trait Multipliers: Sized {
    /// `p_j` per piece.
    fn p(&self) -> &[Vec<f64>];
    /// `omega`.
    fn omega(&self) -> &[f64];
    /// `xi` per knot and active face.
    fn xi(&self) -> &[Vec<f64>];
    /// The same multipliers divided by `by`, marked degenerate (`lambda = 0`).
    fn degenerate(self, by: f64) -> Self;
}

/// The rows divided by `by` (a degenerate multiplier's scaling, [`Multipliers::degenerate`]).
pub(crate) fn divided(rows: Vec<Vec<f64>>, by: f64) -> Vec<Vec<f64>> {
    rows.into_iter()
        .map(|r| r.into_iter().map(|v| v / by).collect())
        .collect()
}

/// `max |v|` over the rows.
pub(crate) fn sup(rows: &[Vec<f64>]) -> f64 {
    rows.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// The largest violation of `xi >= 0`.
pub(crate) fn sign_residual<M: Multipliers>(m: &M) -> f64 {
    m.xi().iter().flatten().fold(0.0_f64, |a, &v| a.max(-v))
}

/// The search: `solve(lambda, stage, norm)` is the multiplier LP, `residual` the KKT residual
/// recomputed in floating point, `cap` the bound on the margin (in the units of `p`),
/// `sign_hard` whether `xi >= 0` is imposed in the degenerate search. Returns the multipliers
/// and how they are scaled.
pub(crate) fn search<M: Multipliers>(
    solve: impl Fn(f64, Stage, Option<Norm>) -> Result<Option<M>>,
    residual: impl Fn(&M) -> f64,
    tol: f64,
    cap: f64,
    sign_hard: bool,
) -> Result<(M, String)> {
    let eps = 1e-12;
    // Always feasible (p constant, xi = 0, r large); an infeasible report is a solver failure.
    let first = solve(1.0, Stage::Kkt, None)?.ok_or_else(|| {
        Error::Numerical("certify: HiGHS found the multiplier LP infeasible".into())
    })?;
    let r1 = residual(&first);
    if r1 <= tol * sup(first.p()).max(1.0) {
        let r_max = r1 * (1.0 + 1e-6) + eps;
        let Some(sg) = solve(1.0, Stage::Sign { r_max }, None)? else {
            return Ok((first, "lambda = 1".into()));
        };
        let s_max = sign_residual(&sg) * (1.0 + 1e-6) + eps;
        let margin = solve(1.0, Stage::Margin { r_max, s_max, cap }, None)?;
        return Ok((margin.unwrap_or(sg), "lambda = 1".into()));
    }
    for sign in [1.0, -1.0] {
        let Some(raw) = solve(0.0, Stage::Kkt, Some(Norm { sign, sign_hard }))? else {
            continue;
        };
        let size = sup(raw.p()).max(raw.omega().iter().fold(0.0_f64, |m, v| m.max(v.abs())));
        if size < 1e-6 {
            continue;
        }
        let raw = raw.degenerate(size);
        if residual(&raw) <= tol {
            return Ok((raw, "lambda = 0, max(|p|, |omega|) = 1".into()));
        }
    }
    Ok((first, "lambda = 1".into()))
}
