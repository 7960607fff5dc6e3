//! The discrete residuals of a crawler's necessary conditions (Theorems 6.1–6.2): (P)'s
//! residuals recomputed on the crawler's instance, in the crawler's units
//! ([`AsGeneral::residuals`]), and stated in the crawler's own words (blocks that slip, links'
//! rates).

use super::crawler_general::AsGeneral;
use super::kkt::Raw;
use super::process::{Process, ProcessKind};

/// The crawler's name and statement of each of (P)'s discrete conditions.
fn crawler_words(general: &str) -> (&'static str, &'static str) {
    match general {
        "adjoint" => (
            "adjoint",
            "adjoint equation and transversality: p_j - p_{j-1} = sum_f xi_{j,f} x*_f, p(T) = \
             p(0) (Thm 6.2 (px), (p2mx))",
        ),
        "complementarity" => (
            "complementarity",
            "xi_{j,f} (c_f - <x*_f, x_j>) = 0: dxi only where its face is active (Thm 6.1 (necd1))",
        ),
        "reaction_stationarity" => (
            "slip_stationarity",
            "<p_j, K nu_b> + lambda/N = 0 while block b slips; relaxed sign at biactive faces \
             (branch LP in D; Thm 6.2 (pr), eta in df1)",
        ),
        "branch_face_sign" => (
            "branch_face_sign",
            "xi_{j,f} <= 0 on an active face no slip holds (a true inequality of the branch LP)",
        ),
        "weak_maximality" => (
            "weak_maximality",
            "psi_j = -p_j - omega - lambda Df2(u_j) in N_U(u_j) (Thm 6.2 (pw))",
        ),
        "sign" => ("sign", "xi_{j,f} >= 0"),
        _ => (
            "duration_stationarity",
            "H_j = sum_l a_l |psi_{j,l}| over the rates at their bound (psi_j's weight on the \
             box's active rows) + lambda (Df2(u_j).u_j - f2(u_j)) is the same on every phase \
             (phase LP stationary in the durations: the maximised Hamiltonian is constant); \
             residual (max H - min H)/2",
        ),
    }
}

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
            let (name, statement) = crawler_words(name);
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
