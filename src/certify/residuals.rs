//! The discrete residuals of a crawler's necessary conditions (Theorems 6.1–6.2): (P)'s
//! residuals recomputed on the crawler's instance, in the crawler's units
//! ([`AsGeneral::residuals`]), and stated in the crawler's own words (blocks that slip, links'
//! rates).

use super::crawler_general::AsGeneral;
use super::crawler_words::crawler_words;
use super::kkt::Raw;
use super::process::{Process, ProcessKind};

/// The discrete residuals, each as (name, statement, residual), in the crawler's words; the
/// duration stationarity only for a phase gait with `durations_free`.
pub(super) fn discrete_residuals(
    pr: &Process,
    general: &AsGeneral,
    raw: &Raw,
    durations_free: bool,
) -> Vec<(&'static str, String, f64)> {
    general
        .residuals(raw, durations_free && pr.kind == ProcessKind::Phase)
        .into_iter()
        .map(|(name, r)| {
            let (name, statement) = crawler_words(name, "6.2").unwrap_or((name, ""));
            (name, statement.to_string(), r.max(0.0))
        })
        .collect()
}

/// Largest residual of the branch-LP KKT system (all discrete conditions but the sign).
pub(super) fn kkt_residual(pr: &Process, general: &AsGeneral, raw: &Raw) -> f64 {
    kkt_residual_with(pr, general, raw, false)
}

/// The same, with the stationarity in the durations of a phase gait when `durations_free`.
pub(super) fn kkt_residual_with(
    pr: &Process,
    general: &AsGeneral,
    raw: &Raw,
    durations_free: bool,
) -> f64 {
    discrete_residuals(pr, general, raw, durations_free)
        .iter()
        .filter(|(name, _, _)| *name != "sign")
        .fold(0.0_f64, |m, (_, _, r)| m.max(*r))
}
