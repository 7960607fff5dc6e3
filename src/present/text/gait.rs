//! The text of an optimal-gait result and of its necessary conditions.

use super::{list, num, status_word, wln, GaitScales};
use crate::certify::NecessaryConditions;
use crate::optimal::{GaitResult, GrowthStop, MilpStatus, PhaseStep, StructuredRecord};
use crate::present::text;

/// An optimal-gait result's key numbers in one line (as `crawlopt report` says it wrote the
/// page): J and the displacement per period, in the gait's units.
pub fn gait_summary(r: &GaitResult) -> String {
    let length = GaitScales::of(r).length;
    format!(
        "objective J = {}, displacement per period {}",
        num(r.head.objective, length),
        num(r.displacement_per_period, length)
    )
}

/// The human form of an optimal-gait result: the same content as the JSON.
pub fn gait_result(r: &GaitResult) -> String {
    let mut out = String::new();
    let sc = GaitScales::of(r);
    let len = |v: f64| num(v, sc.length);
    head(&mut out, r, &sc);
    certificate_line(&mut out, r, &len);
    if let Some(st) = &r.records.structured {
        structured_lines(&mut out, st, "");
    }
    if let Some(ub) = &r.head.certificate.upper_bound {
        upper_bound_line(&mut out, ub, (r.head.objective, sc.length), &len);
    }
    wln!(
        out,
        "verified by simulation: {} (solver: {})",
        len(r.displacement_per_period),
        len(r.solver_objective)
    );
    if let Some(p) = &r.polish {
        wln!(out, "{}", super::polish_line(p, "slip pattern", len));
    }
    if let Some(pg) = &r.records.phase_growth {
        growth_table(&mut out, pg, &len);
    }
    if let Some(st) = &r.discrete_start {
        start_line(&mut out, st, &len);
    }
    search_line(&mut out, r, &len);
    if let Some(table) = &r.records.convergence {
        convergence_table(&mut out, table, &len);
    }
    let g = &r.gait;
    for (j, u) in g.controls.iter().enumerate() {
        wln!(
            out,
            "  {j:>4}: t = [{}, {}]  u = {}  slip = {:?}",
            num(g.times[j], sc.time),
            num(g.times[j + 1], sc.time),
            text::list_each(u, &r.problem.rate_bound),
            g.slip[j]
        );
    }
    out
}

/// The first lines of [`gait_result`]: the method and its status, the objective, and that
/// the crawler stays idle when the proven optimum is 0.
fn head(out: &mut String, r: &GaitResult, sc: &GaitScales) {
    let c = &r.head.certificate;
    let len = |v: f64| num(v, sc.length);
    match (r.head.status, c.phases) {
        (
            MilpStatus::OptimalAmongKPhases | MilpStatus::DominatesKPhases | MilpStatus::TimeLimit,
            Some(k),
        ) => {
            wln!(
                out,
                "method {}: {} (K = {k})",
                r.head.method,
                status_word(r.head.status)
            )
        }
        _ => wln!(
            out,
            "method {}: {}",
            r.head.method,
            status_word(r.head.status)
        ),
    }
    wln!(
        out,
        "objective J = {} (displacement per period {}, actuation cost {})",
        len(r.head.objective),
        len(r.displacement_per_period),
        len(r.actuation_cost)
    );
    let proven = r.head.status.is_optimal() && c.gap.is_some_and(|g| g <= 1e-6);
    // Zero as the text shows it (below the snap of the length scale).
    let zero = |v: f64| v.abs() < text::SNAP * sc.length;
    if proven && zero(r.head.objective) && zero(r.displacement_per_period) {
        wln!(
            out,
            "no gait of this class moves the crawler forward: the optimum is 0 (stay idle)"
        );
    }
}

/// The certificate's line: global (over which class of gaits), local or not proven, with the
/// gap and the bound when there are, the values written by `len`.
fn certificate_line(out: &mut String, r: &GaitResult, len: &dyn Fn(f64) -> String) {
    let c = &r.head.certificate;
    let scope = match (c.kind.as_str(), c.phases, r.m) {
        ("global_k_phases", Some(k), _) => format!("gaits of at most {k} slip phases"),
        ("global", _, Some(m)) => format!("P_{m} ({} steps)", 1u64 << m),
        (kind, _, _) => kind.to_string(),
    };
    let what = match (r.head.status, c.kind.as_str()) {
        (_, "local") => format!("local ({})", status_word(r.head.status)),
        (MilpStatus::DominatesKPhases, _) => format!(
            "proven at least as good as all {scope} (this gait has {})",
            r.gait.slip_phases()
        ),
        (status, _) if status.is_optimal() => format!("global among {scope}"),
        (status, _) => format!(
            "not proven ({}); the bound is over {scope}",
            status_word(status)
        ),
    };
    match (c.gap, c.bound) {
        (Some(gap), Some(bound)) => {
            wln!(
                out,
                "certificate: {what}, gap {gap:.3e} (bound {})",
                len(bound)
            )
        }
        _ => wln!(out, "certificate: {what}"),
    }
}

/// The line of a local search, if the gait came from one: the local method on P_m's grid, or
/// the search over sequences of slip modes, the values written by `len`.
fn search_line(out: &mut String, r: &GaitResult, len: &dyn Fn(f64) -> String) {
    match (&r.local, r.m) {
        (Some(l), Some(_)) => wln!(
        out,
            "local method: from {} (J = {} on this grid), {} LP solves, {} mode switches, stopped: {:?}",
            l.start,
            len(l.start_objective),
            l.lp_solves,
            l.switches,
            l.stop
        ),
        (Some(l), None) => wln!(
        out,
            "sequence search: from {} (J = {} for its sequence of slip modes), {} LP solves, {} improving moves, stopped: {:?}",
            l.start,
            len(l.start_objective),
            l.lp_solves,
            l.switches,
            l.stop
        ),
        (None, _) => {}
    }
}

/// The non-degeneracy margin as measured (a margin within the solver's resolution is 0 at that
/// resolution) and whether the verdict asks it (not with `f2` strictly convex).
pub(crate) fn margin_text(margin: f64, resolution: f64, required: bool) -> String {
    let value = if margin == 0.0 {
        format!("0 (at the solver's resolution {resolution:.1e})")
    } else {
        format!("{margin:.3e}")
    };
    if required {
        value
    } else {
        format!("{value}, not required: f2 strictly convex")
    }
}

/// The human form of a certificate of the gait of `r`: the same content as its JSON,
/// multipliers abridged.
pub fn certificate(c: &NecessaryConditions, r: &GaitResult) -> String {
    let mut out = String::new();
    let sc = GaitScales::of(r);
    let m = &c.multipliers;
    // The adjoint's own scale (lambda + ||p||_inf is normalised, but omega shifts it).
    let adjoint = text::max_abs(m.p_plus_omega.iter().flatten().chain(&m.omega));
    conditions_head(&mut out, c.verdict, &c.reason, c.lambda, &c.normalisation);
    let margin = margin_text(
        c.nondegeneracy_margin,
        c.nondegeneracy_resolution,
        c.margin_required,
    );
    wln!(
        out,
        "  J = {}; min |p + omega| = {margin}; omega = {}",
        num(c.objective, sc.length),
        list(&m.omega, adjoint)
    );
    if let Some(b) = &c.branch_lp {
        wln!(
            out,
            "  {}: optimum {}, improvement over the gait {:.3e}",
            b.describe("active faces and slips"),
            num(b.optimum, sc.length),
            b.improvement
        );
    }
    super::condition_lines(&mut out, &c.conditions, 18);
    let rows = m.p.len();
    let show = rows.min(64);
    wln!(
        out,
        "  multipliers per piece ({}{}):",
        m.extension,
        if show < rows {
            format!(", first {show} of {rows}")
        } else {
            String::new()
        }
    );
    for j in 0..show {
        wln!(
            out,
            "    t = {}  u = {}  p + omega = {}",
            num(m.times[j], sc.time),
            text::list_each(&m.u[j], &r.problem.rate_bound),
            list(&m.p_plus_omega[j], adjoint)
        );
    }
    let mass = text::max_abs(m.xi.iter().map(|x| &x.value));
    for x in m.xi.iter().take(64) {
        wln!(
            out,
            "    dxi at t = {} (knot {}): face {}{} mass {}",
            num(x.time, sc.time),
            x.knot,
            x.block,
            x.side,
            num(x.value, mass)
        );
    }
    if let Some(o) = &c.one_link {
        super::one_link_lines(&mut out, o, sc.force, sc.time, "(beta - alpha)/a");
    }
    out
}

/// The upper bound over all periodic gaits and how far `j` can be from it, crawler or general
/// (a chain's), the values written by `len`; `scale` is the problem's length scale.
pub(super) fn upper_bound_line(
    out: &mut String,
    ub: &crate::optimal::bound_record::UpperBound,
    (j, scale): (f64, f64),
    len: &dyn Fn(f64) -> String,
) {
    let within = format!("{:.1} %", 100.0 * ub.within(j, scale));
    wln!(
        out,
        "upper bound over all periodic gaits: {} ({}, grid {}{}): optimal within {within}",
        len(ub.value),
        ub.method,
        ub.resolution_text(),
        if ub.status == crate::certify::bound::BoundStatus::TimeLimit {
            ", LP cut short by the time limit"
        } else {
            ""
        }
    );
}

/// The lines of a structured gait kept as the answer ([`StructuredRecord`]): what it is and,
/// where the method found a gait below it, what was replaced; `units` follows that (e.g. ` (the
/// crawler's J)` where the answer is in other units than the record).
pub(super) fn structured_lines(out: &mut String, st: &StructuredRecord, units: &str) {
    wln!(out, "gait: {}", st.origin);
    if let Some(why) = &st.replaced {
        wln!(out, "kept instead of the method's answer: {why}{units}");
    }
}

/// The table of `J_m` over `m`, crawler or general, the values written by `len`.
pub(super) fn convergence_table(
    out: &mut String,
    table: &[crate::optimal::ConvergenceRow],
    len: &dyn Fn(f64) -> String,
) {
    wln!(out, "convergence of the discrete problems P_m:");
    wln!(out, "  | m | steps | J_m | gap | status | seconds |");
    for row in table {
        wln!(
            out,
            "  | {} | {} | {} | {:.1e} | {} | {:.2} |",
            row.m,
            row.steps,
            len(row.objective),
            row.gap,
            status_word(row.status),
            row.seconds
        );
    }
}

/// How `K` was grown, crawler or general: why it stopped and one row per `K` solved, the
/// values written by `len`.
pub(super) fn growth_table(
    out: &mut String,
    pg: &crate::optimal::PhaseGrowthRecord,
    len: &dyn Fn(f64) -> String,
) {
    wln!(
        out,
        "phases grown until {}:",
        match pg.stop {
            GrowthStop::NoGain => "the value stopped improving",
            GrowthStop::MaxPhases => "--max-phases (the value was still improving or still 0)",
            GrowthStop::NoForwardMotion =>
                "K = 1: v_m <= 0 for every shape rate, so no gait moves this crawler forward",
            GrowthStop::TimeLimit => "the time limit",
        }
    );
    wln!(out, "  | K | J_K | bound | status | seconds |");
    for st in &pg.table {
        wln!(
            out,
            "  | {} | {} | {} | {} | {:.2} |",
            st.phases,
            len(st.objective),
            len(st.bound),
            status_word(st.status),
            st.seconds
        );
    }
}

/// One solved K of a phase growth, for the progress line (J and the bound at the problem's
/// length scale `length`).
pub fn phase_step(st: &PhaseStep, length: f64) -> String {
    format!(
        "K = {}: J = {} (bound {}, {:.2} s); K = {} next",
        st.phases,
        num(st.objective, length),
        num(st.bound, length),
        st.seconds,
        st.phases + 1
    )
}

/// The first lines of a certificate, crawler or general: the verdict, its reason, and how the
/// multipliers are scaled.
pub(super) fn conditions_head(
    out: &mut String,
    verdict: crate::certify::Verdict,
    reason: &str,
    lambda: f64,
    n: &crate::certify::Normalisation,
) {
    wln!(
        out,
        "necessary conditions (Theorem 2.2; discrete form Theorems 6.1-6.2): {}",
        serde_json::to_string(&verdict)
            .expect("enum")
            .trim_matches('"')
    );
    wln!(out, "  {}", reason);
    wln!(
        out,
        "  lambda = {} (scaled: {}); lambda + ||p||_inf = {}; sum of the paper's (norm) = {}",
        num(lambda, 1.0),
        n.scaled_by,
        num(n.lambda_plus_sup_p, 0.0),
        num(n.paper_norm, 0.0)
    );
}

/// The line of the start a P_m MILP took as its first incumbent (a crawler's or (P)'s).
pub(super) fn start_line(
    out: &mut String,
    st: &crate::optimal::StartRecord,
    len: &dyn Fn(f64) -> String,
) {
    wln!(out, "{}", start_words(st, len));
}

/// The start a P_m MILP took as its first incumbent, in words, for the text and the HTML
/// reports of both kinds: where it came from and its `J` on the grid (`len` formats it).
pub(crate) fn start_words(st: &crate::optimal::StartRecord, len: &dyn Fn(f64) -> String) -> String {
    format!(
        "the MILP started from {} (J = {} on this grid)",
        st.start,
        len(st.start_objective)
    )
}
