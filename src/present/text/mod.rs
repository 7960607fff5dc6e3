//! Numbers in human-readable (text) output.
//!
//! Text output shows values at a precision a reader can use: [`DIGITS`] significant digits by
//! default, solver noise (below [`SNAP`] times the scale of the quantity) shown as `0`, and
//! exponent notation for very large or small magnitudes, so that no value prints as hundreds of
//! digits (Rust's `{}` writes `1e300` as 301 digits). JSON output does not use this: it keeps
//! every number at full precision.
//!
//! The human forms of results (what the command line prints and Python's summaries show) are
//! here too, each a function returning the text: [`analysis`], [`simulation`],
//! [`gait_result`], [`certificate`].

mod analysis;
mod fit;
mod gait;
mod general;
mod general_certify;
mod simulation;

pub use analysis::{analysis, gait_problem};
pub use fit::fit;
pub use gait::{certificate, gait_result, gait_summary, phase_step};
pub(crate) use gait::{margin_text, start_words};
pub use general::{general_analysis, general_answer, general_simulation, general_summary};
pub use general_certify::general_certificate;
pub use simulation::simulation;

pub use crate::number::{num, number, DIGITS, SNAP};

use crate::model::Crawler;
use crate::optimal::{GaitProblem, GaitResult, MilpStatus};

/// `writeln!` into a `String` (which cannot fail).
macro_rules! wln {
    ($o:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        let _ = writeln!($o, $($arg)*);
    }};
}
pub(crate) use wln;

/// The scales of a gait problem's quantities: text output shows a value smaller than
/// [`crate::number::SNAP`] times its quantity's scale as 0 (solver noise).
pub struct GaitScales {
    /// Lengths, displacements and the objective: the largest stroke an actuator can make in a
    /// period, `T max_l a_l / k_l`.
    pub length: f64,
    /// Times: the period.
    pub time: f64,
    /// Computed forces (states, the ends of C): the smallest friction threshold, the smallest
    /// force the model tells apart ([`force_scale`]).
    pub force: f64,
}

impl GaitScales {
    pub fn new(
        stiffness: &[f64],
        mu: impl IntoIterator<Item = f64>,
        problem: &GaitProblem,
    ) -> Self {
        let sweep = problem.rate_bound.iter().zip(stiffness);
        GaitScales {
            length: problem.period * sweep.fold(0.0_f64, |m, (a, k)| m.max(a / k)),
            time: problem.period,
            force: mu.into_iter().fold(f64::INFINITY, f64::min),
        }
    }

    /// Of a problem posed for a crawler.
    pub fn of_problem(crawler: &Crawler, problem: &GaitProblem) -> Self {
        let mu = crawler.mu_forward().iter().chain(crawler.mu_backward());
        Self::new(crawler.stiffness(), mu.copied(), problem)
    }

    /// Of a result (its crawler and problem).
    pub fn of(r: &GaitResult) -> Self {
        let c = &r.crawler;
        let mu = c.mu_forward.iter().chain(&c.mu_backward);
        Self::new(&c.stiffness, mu.copied(), &r.problem)
    }
}

/// The scale of computed forces of a crawler (states, the ends of C, vertices): its smallest
/// friction threshold. The exact ones are sums of thresholds, so a force smaller than
/// [`crate::number::SNAP`] times the smallest threshold is rounding noise of a zero. (Not the
/// largest threshold: with mu+ = 1e300 and mu- = 3, C spans [-6, 3].)
pub fn force_scale(crawler: &Crawler) -> f64 {
    let mu = crawler.mu_forward().iter().chain(crawler.mu_backward());
    mu.fold(f64::INFINITY, |m, &v| m.min(v))
}

pub fn status_word(s: MilpStatus) -> &'static str {
    s.as_str()
}

/// The line of a P_m answer's polishing ([`crate::optimal::polish`]): `J` before and after and
/// how far the controls moved, or why the MILP's answer was kept; `pattern` names what was
/// fixed, `fmt` formats an objective.
pub fn polish_line(
    r: &crate::optimal::polish::PolishRecord,
    pattern: &str,
    fmt: impl Fn(f64) -> String,
) -> String {
    if r.applied {
        format!(
            "polished on its fixed {pattern} ({}): J {} -> {}, controls moved by {:.3e}",
            r.note,
            fmt(r.objective_before),
            fmt(r.objective_after),
            r.control_change
        )
    } else {
        format!("not polished: {}", r.note)
    }
}

/// A vector as `[a, b, c]`, each entry by [`num`] with the same scale.
pub fn list(v: &[f64], scale: f64) -> String {
    let parts: Vec<String> = v.iter().map(|&x| num(x, scale)).collect();
    format!("[{}]", parts.join(", "))
}

/// A vector as `[a, b, c]`, entry `i` by [`num`] with scale `scales[i]` (e.g. each link's
/// control at its own rate bound; entries without a scale are not snapped).
pub fn list_each(v: &[f64], scales: &[f64]) -> String {
    let parts: Vec<String> = v
        .iter()
        .enumerate()
        .map(|(i, &x)| num(x, scales.get(i).copied().unwrap_or(0.0)))
        .collect();
    format!("[{}]", parts.join(", "))
}

/// The largest magnitude among `v` (0 when empty; NaN entries ignored): a scale for [`num`]
/// when a quantity has no better one.
pub fn max_abs<'a>(v: impl IntoIterator<Item = &'a f64>) -> f64 {
    v.into_iter()
        .filter(|x| x.is_finite())
        .fold(0.0, |m, x| m.max(x.abs()))
}

/// One line per condition of Theorem 2.2 (a crawler's certificate or (P)'s alike): its
/// theorem, name (padded to `width`), residual, tolerance, whether it holds and its statement.
pub fn condition_lines(
    out: &mut String,
    conditions: &[crate::certify::ConditionCheck],
    width: usize,
) {
    for k in conditions {
        wln!(
            out,
            "  [Thm {}] {:<width$} residual {:>10.3e}  tol {:.1e}  {}  {}",
            k.theorem,
            k.name,
            k.residual,
            k.tolerance,
            if k.holds { "holds" } else { "FAILS" },
            k.statement
        );
    }
}

/// The lines of §4's one-link structure of a certificate (a crawler's or (P)'s on a line): C,
/// bang-bang, the switches and the interior arcs against `arc` (how the arc length is written),
/// C's ends written to `x_scale`, times to `t_scale`.
pub fn one_link_lines(
    out: &mut String,
    o: &crate::certify::OneLinkStructure,
    x_scale: f64,
    t_scale: f64,
    arc: &str,
) {
    wln!(
        out,
        "  one link (§4): C = [{}, {}], bang-bang {}, switches at t = {} (at an end of C: {:?})",
        num(o.alpha, x_scale),
        num(o.beta, x_scale),
        o.bang_bang,
        list(&o.switch_times, t_scale),
        o.switch_at_end
    );
    wln!(
        out,
        "    interior arcs {} vs {arc} = {}",
        list(&o.interior_arcs, t_scale),
        num(o.expected_arc, t_scale)
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_snaps_and_never_prints_hundreds_of_digits() {
        assert_eq!(num(1.0000000000005613, 1.0), "1");
        assert_eq!(num(1.0000000000005613, 0.0), "1");
        assert_eq!(num(1.4431e-13, 1.0), "0");
        assert_eq!(num(0.0000000000001443115198287173, 3.0), "0");
        assert_eq!(num(1e-300, 0.0), "1e-300");
        assert_eq!(num(1e300, 0.0), "1e300");
        assert_eq!(num(-1e300, 1.0), "-1e300");
        assert_eq!(num(2.5625, 1.0), "2.5625");
        assert_eq!(num(-0.0, 0.0), "0");
        assert_eq!(num(0.0, 1.0), "0");
        assert_eq!(num(-0.9999999999999999, 1.0), "-1");
        assert_eq!(num(-0.00000000000000008326672684688674, 1.0), "0");
        assert_eq!(num(1.9142135623730947, 1.0), "1.914213562");
        assert_eq!(num(0.1 + 0.2, 0.0), "0.3");
        assert_eq!(num(-0.5000000000000004, 3.0), "-0.5");
        assert_eq!(num(9.99999999999, 0.0), "10");
        assert_eq!(num(123456.789, 0.0), "123456.789");
        assert_eq!(num(1e6, 0.0), "1000000");
        assert_eq!(num(1e10, 0.0), "1e10");
        assert_eq!(num(12345678901.0, 0.0), "1.23456789e10");
        assert_eq!(num(0.00015, 0.0), "0.00015");
        assert_eq!(num(-0.000015, 0.0), "-0.000015");
        assert_eq!(num(1.5e-6, 0.0), "1.5e-6");
        assert_eq!(num(f64::MIN_POSITIVE / 4.0, 0.0), "5.562684646e-309");
        assert_eq!(num(f64::NAN, 1.0), "NaN");
        assert_eq!(num(f64::INFINITY, 1.0), "inf");
        assert_eq!(num(f64::NEG_INFINITY, 1.0), "-inf");
    }

    #[test]
    fn snapping_is_relative_to_the_scale_and_strict() {
        assert_eq!(num(1e-10, 1.0), "0");
        assert_eq!(num(1e-10, 0.01), "1e-10");
        assert_eq!(num(1e-9, 1.0), "1e-9");
        assert_eq!(num(5e290, 1e300), "0");
        // A scale that is no scale never snaps.
        assert_eq!(num(1e-20, f64::NAN), "1e-20");
        assert_eq!(num(1e-20, f64::INFINITY), "1e-20");
        assert_eq!(num(1e-20, -1.0), "1e-20");
    }

    #[test]
    fn digits_are_honoured_and_clamped() {
        assert_eq!(number(std::f64::consts::PI, 0.0, 3), "3.14");
        assert_eq!(number(std::f64::consts::PI, 0.0, 0), "3");
        assert_eq!(number(std::f64::consts::PI, 0.0, 40), "3.1415926535897931");
        assert_eq!(number(0.1, 0.0, 17), "0.10000000000000001");
        assert_eq!(number(1234.5, 0.0, 3), "1.23e3");
    }

    #[test]
    fn lists_share_a_scale() {
        assert_eq!(list(&[1.0000000000005613, -1.0], 1.0), "[1, -1]");
        assert_eq!(list(&[], 1.0), "[]");
        assert_eq!(
            list_each(&[1e-12, 1e-12, 1e-12], &[1.0, 1e-6]),
            "[0, 1e-12, 1e-12]"
        );
        assert_eq!(max_abs(&[1.0, -3.0, f64::NAN]), 3.0);
    }

    #[test]
    fn every_finite_value_is_short_and_reads_back_close() {
        let mut x: f64 = 1.234567890123e-308;
        while x.is_finite() {
            for v in [x, -x, x * 1.0000000001, 1.0 / 3.0 * x] {
                let s = num(v, 0.0);
                assert!(s.len() <= 22, "{v:e}: {s}");
                let back: f64 = s.parse().unwrap();
                assert!(((back - v) / v).abs() < 6e-10, "{v:e}: {s}");
            }
            x *= 7.3;
        }
    }
}
