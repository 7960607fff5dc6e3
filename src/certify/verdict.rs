//! What the report of a certificate does alike for a crawler's process and for a process of the
//! general problem (P): the groups of conditions of Theorem 6.2 (the discrete problem P_m) and
//! Theorem 2.2 (continuous time), the support of the face multipliers, the L^1 weak maximality
//! on one step, the verdict that reads the two groups, and the normalisations of the
//! multipliers. They serve the one report ([`super::general_report`]), which a crawler's
//! certificate reads back in its own names ([`super::report`]).

use super::records::{ConditionCheck, Normalisation, Verdict};

/// One condition with its residual held against its tolerance.
pub(super) fn check(
    name: &str,
    theorem: &str,
    statement: &str,
    residual: f64,
    tolerance: f64,
) -> ConditionCheck {
    ConditionCheck {
        name: name.into(),
        theorem: theorem.into(),
        statement: statement.into(),
        residual,
        tolerance,
        holds: residual <= tolerance,
    }
}

/// The group of Theorem 6.2 from the residuals of the discrete conditions (the sign condition
/// is left to the group of Theorem 2.2, which states it for the measure `dxi`), each held to
/// `tol`, and `lambda > 0`.
pub(super) fn discrete_group<S: AsRef<str>>(
    residuals: &[(&str, S, f64)],
    tol: f64,
    lambda: f64,
) -> Vec<ConditionCheck> {
    let mut group: Vec<ConditionCheck> = residuals
        .iter()
        .filter(|(name, _, _)| *name != "sign")
        .map(|(name, statement, r)| check(name, "6.2", statement.as_ref(), *r, tol))
        .collect();
    group.push(check(
        "lambda_positive",
        "6.2",
        "lambda > 0 (Thm 6.2 (lambda))",
        if lambda > 0.0 { 0.0 } else { 1.0 },
        0.0,
    ));
    group
}

/// The face multipliers `dxi` worth reporting, each made by `entry(knot, face, value)`: those
/// of the faces `active` at each knot, leaving out values below 1e-14 of the largest.
pub(super) fn significant_multipliers<F: Copy, T>(
    active: &[Vec<F>],
    xi: &[Vec<f64>],
    entry: impl Fn(usize, F, f64) -> T,
) -> Vec<T> {
    let xmax = xi.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut out = Vec::new();
    for (k, faces) in active.iter().enumerate() {
        for (&f, &v) in faces.iter().zip(&xi[k]) {
            if v.abs() > 1e-14 * xmax {
                out.push(entry(k, f, v));
            }
        }
    }
    out
}

/// The mass of `dxi` outside its support (Theorem 2.2: `supp dxi^j` in the times where face
/// `j` is active): with `p` extended piecewise linearly (a P_m process), the multiplier at knot
/// `k` acts on step `k - 1`, so a face held at knot `k` but not on the step before carries
/// misplaced mass. A phase gait's `p` jumps at its knots: nothing is misplaced.
pub(super) fn misplaced_mass<F: PartialEq>(
    active: &[Vec<F>],
    xi: &[Vec<f64>],
    discrete: bool,
) -> f64 {
    let steps = active.len();
    let mut misplaced = 0.0;
    for k in (0..steps).filter(|_| discrete) {
        let start = (k + steps - 1) % steps;
        for (fi, f) in active[k].iter().enumerate() {
            if !active[start].contains(f) {
                misplaced += xi[k][fi].abs();
            }
        }
    }
    misplaced
}

/// `int_0^tau dist(psi(t), N_[lo, hi](u))` of one control component on one step, `psi`
/// linear from `a` to `b`: at the upper bound (`up`) only `psi < 0` is off the normal cone,
/// at the lower bound (`down`) only `psi > 0`, inside both, at both (a degenerate interval)
/// neither.
pub(super) fn step_distance(a: f64, b: f64, tau: f64, up: bool, down: bool) -> f64 {
    match (up, down) {
        (true, true) => 0.0,
        (true, false) => int_pos(-a, -b, tau),
        (false, true) => int_pos(a, b, tau),
        (false, false) => int_pos(a, b, tau) + int_pos(-a, -b, tau),
    }
}

/// The control weak maximality implies for one component of a box `[lo, hi]`, from its switching
/// value `s` (`p + omega` for a crawler, `B^T p + omega` for (P)): with `f2 = (c/2)|u|^2` and
/// `lambda > 0` (`quadratic = Some(lambda c)`) the projection of `-s / (lambda c)`; else the
/// bang-bang control, `hi` where `s < 0` and `lo` where `s > 0`, once `|s|` is above the
/// non-degeneracy `threshold`; `None` where it decides nothing.
pub(super) fn law_target(
    s: f64,
    quadratic: Option<f64>,
    lo: f64,
    hi: f64,
    threshold: f64,
) -> Option<f64> {
    match quadratic {
        Some(lc) => Some((-s / lc).clamp(lo, hi)),
        None if s.abs() > threshold => Some(if s < 0.0 { hi } else { lo }),
        None => None,
    }
}

/// Whether a condition counts for the verdict of its group: all but `lambda > 0` (which
/// decides between the verdicts), the non-degeneracy (which makes a verdict degenerate, not
/// failed) and the control law (reported only: what the maximality implies where it decides).
fn counted(c: &ConditionCheck, theorem: &str) -> bool {
    c.theorem == theorem
        && !matches!(
            c.name.as_str(),
            "lambda_positive" | "nondegeneracy" | "control_law"
        )
}

/// The verdict of a certificate from its conditions: `holds` when both groups hold (the
/// group of Theorem 2.2 only for an exact process, not for P_m, `discrete`) with `lambda > 0`
/// and `nondegenerate`, with the reason `holds_reason`; `degenerate` when they hold with
/// `lambda > 0` but the non-degeneracy fails (the reason `degenerate_reason()`), or only with
/// `lambda = 0`; else `fails`, naming the failing conditions of the discrete group (or of the
/// continuous one when the discrete group holds).
pub(super) fn verdict(
    conditions: &[ConditionCheck],
    discrete: bool,
    lambda: f64,
    nondegenerate: bool,
    holds_reason: &str,
    degenerate_reason: impl FnOnce() -> String,
) -> (Verdict, String) {
    let group_ok = |th: &str| {
        conditions
            .iter()
            .filter(|c| counted(c, th))
            .all(|c| c.holds)
    };
    let disc_ok = group_ok("6.2");
    let cont_ok = discrete || group_ok("2.2");
    let lambda_ok = lambda > 0.0;
    if disc_ok && cont_ok && lambda_ok && nondegenerate {
        (Verdict::Holds, holds_reason.into())
    } else if disc_ok && cont_ok && lambda_ok {
        (Verdict::Degenerate, degenerate_reason())
    } else if disc_ok && cont_ok {
        (
            Verdict::Degenerate,
            "no multipliers with lambda > 0 exist; the conditions hold only with lambda = 0".into(),
        )
    } else {
        let failing = |th: &str| -> Vec<String> {
            conditions
                .iter()
                .filter(|c| !c.holds && counted(c, th))
                .map(|c| format!("{} (Thm {th}, residual {:.3e})", c.name, c.residual))
                .collect()
        };
        let mut names = failing("6.2");
        if names.is_empty() {
            names = failing("2.2");
        }
        (
            Verdict::Fails,
            format!(
                "no multipliers satisfy the necessary conditions, with lambda = 1 or 0; at the \
                 least violating ones with lambda = 1: {}",
                names.join(", ")
            ),
        )
    }
}

/// The Euclidean norm.
pub(super) fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The normalisations of the multipliers: `lambda + sup|p|` (Theorem 2.2's nontriviality) and
/// the paper's norm `paper` (`lambda + |p(0)| + |omega| + sum_k |sum_j xi^j_k x*_j| + sum_k
/// tau_k |psi_k|`), with `lambda` relative to each.
pub(super) fn normalisation(
    scaled_by: String,
    lambda: f64,
    sup_p: f64,
    paper: f64,
) -> Normalisation {
    let nontrivial = lambda + sup_p;
    Normalisation {
        scaled_by,
        lambda_plus_sup_p: nontrivial,
        lambda_theorem_2_2: lambda / nontrivial,
        paper_norm: paper,
        lambda_paper_norm: lambda / paper,
    }
}

/// `int_0^tau max(0, linear from a to b) ds`.
fn int_pos(a: f64, b: f64, tau: f64) -> f64 {
    if a >= 0.0 && b >= 0.0 {
        0.5 * tau * (a + b)
    } else if a <= 0.0 && b <= 0.0 {
        0.0
    } else {
        let hi = a.max(b);
        0.5 * tau * hi * hi / (b - a).abs()
    }
}
