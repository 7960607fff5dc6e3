//! The text of the general problem's analysis and simulation (`crawlopt analyze` and
//! `simulate` on a `[sweeping_process]` file). Inputs (faces, offsets) are shown as given after
//! scaling; computed states at C's scale (the largest `|c_j|`).

use super::{list, max_abs, num, wln};
use crate::io::{CheckStatus, GeneralAnalysis, GeneralAnswer, GeneralSimulated, GeneralSolution};
use crate::model::general::{Boundary, ControlSet, GeneralCost, GeneralProblem, Reward};
use crate::optimal::general::{GeneralLocal, GeneralPhaseGait, GeneralPm};
use crate::optimal::{Certificate, LocalStop};

/// The human form of [`crate::api::analyze_general`].
pub fn general_analysis(a: &GeneralAnalysis) -> String {
    let mut out = String::new();
    let p = &a.problem;
    let g = &a.geometry;
    let s = p.c.scale();
    problem_lines(&mut out, p);
    wln!(
        out,
        "polyhedron C: {} faces in dimension {} (rank of the normals {}; rows scaled to unit \
         normals):",
        g.faces,
        g.dim,
        g.rank
    );
    for j in 0..p.c.faces() {
        let redundant = g.redundant_faces.contains(&(j + 1));
        wln!(
            out,
            "  face {:>3}: <{}, x> <= {}{}",
            j + 1,
            list(&p.c.normals[j], 0.0),
            num(p.c.offsets[j], 0.0),
            if redundant { "   (redundant)" } else { "" }
        );
    }
    wln!(
        out,
        "  Chebyshev centre {} radius {}{}",
        list(&g.chebyshev_centre, s),
        num(g.chebyshev_radius, s),
        if g.radius_capped {
            " (the LP's cap: C is unbounded)"
        } else {
            ""
        }
    );
    wln!(out, "  bounded: {}", if g.bounded { "yes" } else { "no" });
    match &g.vertices {
        None => wln!(
            out,
            "  vertices: not enumerated (more than {} candidate subsets)",
            crate::optimal::general::MAX_VERTEX_SUBSETS
        ),
        Some(vs) => {
            let what = if g.rank == g.dim {
                "vertices"
            } else {
                "minimal faces (C has no vertex; a point of each)"
            };
            wln!(out, "  {} {what}:", vs.len());
            for v in vs {
                wln!(
                    out,
                    "    {}   active faces {:?}",
                    list(&v.point, s),
                    v.active
                );
            }
        }
    }
    wln!(out, "checks:");
    for c in &a.checks {
        let mark = match c.status {
            CheckStatus::Pass => "ok  ",
            CheckStatus::Fail => "FAIL",
            CheckStatus::Info => "    ",
        };
        wln!(out, "  {mark} {}: {}", c.name, c.detail);
    }
    out
}

fn problem_lines(out: &mut String, p: &GeneralProblem) {
    wln!(
        out,
        "general problem (P): n = {} states, m = {} controls, period T = {}, {}",
        p.states(),
        p.controls(),
        num(p.period, 0.0),
        match &p.boundary {
            Boundary::Periodic => "periodic x(0) = x(T)".to_string(),
            Boundary::Initial(x0) => format!("Cauchy problem from x(0) = {}", list(x0, 0.0)),
        }
    );
    wln!(out, "  g(x, u) = A x + B u + b");
    for i in 0..p.states() {
        wln!(
            out,
            "    A[{}] = {}   B[{}] = {}   b[{}] = {}",
            i + 1,
            list(&p.dynamics.a[i], 0.0),
            i + 1,
            list(&p.dynamics.b[i], 0.0),
            i + 1,
            num(p.dynamics.drift[i], 0.0)
        );
    }
    match &p.control {
        ControlSet::Box { lower, upper } => wln!(
            out,
            "  U: box {} <= u <= {}{}",
            list(lower, 0.0),
            list(upper, 0.0),
            if p.zero_mean { ", zero mean" } else { "" }
        ),
        ControlSet::Polytope(u) => wln!(
            out,
            "  U: polytope of {} faces{}",
            u.faces(),
            if p.zero_mean { ", zero mean" } else { "" }
        ),
    }
    match &p.reward {
        Reward::FaceWeights(w) => wln!(out, "  f1: face weights {}", list(w, 0.0)),
        Reward::ReactionWeights(q) => wln!(out, "  f1: <q, eta>, q = {}", list(q, 0.0)),
    }
    match &p.cost {
        GeneralCost::None => wln!(out, "  f2: none"),
        GeneralCost::Quadratic { weight } => {
            wln!(out, "  f2: (c/2)|u|^2, c = {}", num(*weight, 0.0))
        }
        GeneralCost::Matrix { matrix } => wln!(out, "  f2: (1/2) u^T R u, R = {matrix:?}"),
    }
}

/// The human form of [`crate::api::simulate_general`].
pub fn general_simulation(r: &GeneralSimulated) -> String {
    let mut out = String::new();
    let sim = &r.simulation;
    wln!(
        out,
        "method: {}{}, started at {} ({})",
        r.method,
        match (r.method, sim.projection) {
            ("exact", _) => String::new(),
            (_, "chain") => format!(
                ", {} steps per period (projections by the chain's O(N) method: the problem is \
                 a crawler's chain)",
                r.steps_per_period
            ),
            _ => format!(", {} steps per period", r.steps_per_period),
        },
        list(&r.start, 0.0),
        r.start_from
    );
    let scale = sim
        .x
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    if !sim.converged {
        wln!(
            out,
            "periodic regime NOT reached after {} periods; last state {}",
            sim.periods,
            list(sim.x.last().map_or(&[][..], |x| x), scale)
        );
        return out;
    }
    wln!(
        out,
        "periods integrated: {}{}",
        sim.periods,
        if r.regime_search == "chain" {
            " (the periodic regime searched by the crawler's simulator on the problem's chain)"
        } else {
            ""
        }
    );
    let j_scale = sim.reward.abs().max(sim.cost.abs()).max(1e-300);
    wln!(
        out,
        "J = {}   (int f1(eta) = {}, int f2(u) = {})",
        num(sim.objective.unwrap_or(f64::NAN), j_scale),
        num(sim.reward, j_scale),
        num(sim.cost, j_scale)
    );
    wln!(
        out,
        "mean control over a period: {}",
        list(&sim.mean_control, 0.0)
    );
    wln!(
        out,
        "x(0) on the recorded period: {}",
        list(&sim.x[0], scale)
    );
    wln!(
        out,
        "largest KKT residual of a projection: {:.3e}",
        sim.max_kkt_residual
    );
    out
}

/// The problem's floor of `J` ([`GeneralProblem::j_floor`], the scale its MILPs state gaps
/// over, at most 1; 0 where the stored problem does not read back): a `J` below `1e-9` of it
/// prints as 0, as a crawler's displacement below its length unit's does (P_1 of the
/// three-block crawler's general form is 0 up to 2.6e-17). Not `J`'s scale itself, the
/// largest weight times C's scale: with a face at 1e13 that hid every `J` below 5000.
fn j_floor(r: &GeneralAnswer) -> f64 {
    r.problem.problem().map_or(0.0, |p| p.j_floor())
}

/// The scale the numbers of `J` in the text of `r` snap against: the largest of `values` and
/// the problem's floor of `J` ([`j_floor`]).
pub(super) fn text_scale(r: &GeneralAnswer, values: &[f64]) -> f64 {
    values
        .iter()
        .fold(j_floor(r), |m, v| m.max(v.abs()))
        .max(1e-300)
}

/// The human form of a global P_m optimum `s`, the solution of `r`
/// ([`crate::api::optimize_general`]).
fn general_optimum(r: &GeneralAnswer, s: &GeneralPm) -> String {
    let mut out = String::new();
    let c = &s.certificate;
    let scale = text_scale(r, &[s.objective, c.bound]);
    wln!(
        out,
        "P_{} ({} steps of h = {}), global MILP: {}",
        s.m,
        s.path.u.len(),
        num(r.period / s.path.u.len() as f64, 0.0),
        super::status_word(c.status)
    );
    milp_line(&mut out, s.objective, c, "simulation", scale);
    if let Some(st) = &r.discrete_start {
        super::gait::start_line(&mut out, st, &|v| num(v, scale));
    }
    if let Some(p) = &s.polish {
        wln!(
            out,
            "{}",
            super::polish_line(p, "face pattern", |v| num(v, scale))
        );
    }
    upper_bound(&mut out, r, s.objective, scale);
    if let Some(table) = &r.records.convergence {
        super::gait::convergence_table(&mut out, table, &|v| num(v, scale));
    }
    steps(&mut out, &s.path.x, &s.path.u);
    out
}

/// The line of a MILP's answer: `J` as `verified_by` measured it, the MILP's own value, its
/// bound and gap.
fn milp_line(out: &mut String, j: f64, c: &Certificate, verified_by: &str, scale: f64) {
    wln!(
        out,
        "J = {}   (verified by {verified_by}; MILP {}, bound {}, gap {:.3e})",
        num(j, scale),
        num(c.milp_objective, scale),
        num(c.bound, scale),
        c.gap
    );
}

/// The exact gait of at most `K` phases ([`crate::api::optimize_general_phase`]): the
/// certificate, the table of the `K` solved when `K` was grown, then per phase its duration, start state, control and held faces.
fn general_phase(r: &GeneralAnswer, s: &GeneralPhaseGait) -> String {
    let mut out = String::new();
    let c = &s.certificate;
    let local = r.head.method != "phase";
    let bound = if local { 0.0 } else { c.bound };
    let scale = text_scale(r, &[s.objective, bound]);
    phase_head(&mut out, r, s, local);
    if let Some(st) = &r.records.structured {
        super::gait::structured_lines(&mut out, st, " (the crawler's J)");
    }
    if local {
        wln!(
            out,
            "J = {}   (verified by the exact simulation; the crawler's J times the objective's \
             scale)",
            num(s.objective, scale)
        );
    } else {
        milp_line(&mut out, s.objective, c, "the exact simulation", scale);
    }
    if s.actuation_cost != 0.0 {
        wln!(
            out,
            "int f2(u) dt = {}   ({} MILP rounds of the outer approximation)",
            num(s.actuation_cost, scale),
            s.rounds
        );
    }
    let xs = s
        .states
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    let us = s
        .controls
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    upper_bound(&mut out, r, s.objective, scale);
    if let Some(pg) = &r.records.phase_growth {
        super::gait::growth_table(&mut out, pg, &|v| num(v, scale));
    }
    for (j, u) in s.controls.iter().enumerate() {
        wln!(
            out,
            "  phase {:>3}: tau = {}  x = {}  u = {}  held faces {:?}",
            j + 1,
            num(s.durations[j], r.period),
            list(&s.states[j], xs),
            list(u, us),
            s.held[j]
        );
    }
    out
}

/// The first line of a phase answer: the gait, the class its claim is over (by the
/// formulation that ran, `formulation`) and the status.
fn phase_head(out: &mut String, r: &GeneralAnswer, s: &GeneralPhaseGait, local: bool) {
    let c = &s.certificate;
    match r.formulation.as_deref() {
        _ if local => wln!(
            *out,
            "exact gait of {} phases by the crawler's {} method on the problem's chain (the \
             problem is a crawler's) (T = {}), no global claim: {}",
            s.durations.len(),
            r.head.method,
            num(r.period, 0.0),
            super::status_word(c.status),
        ),
        Some("chain") if c.status == crate::optimal::MilpStatus::DominatesKPhases => wln!(
            *out,
            "exact gait of {} phases, proven at least as good as every gait of at most {k} \
             phases by the chain's formulation ({k} slip phases, transitions free; the problem \
             is a crawler's) (T = {}), global MILP: {}",
            s.durations.len(),
            num(r.period, 0.0),
            super::status_word(c.status),
            k = s.max_phases,
        ),
        Some("transitions") => wln!(
            *out,
            "exact gait of {} phases, global among those of at most {k} phases by {k} slots of \
             a free transition and a phase (T = {}), global MILP: {}",
            s.durations.len(),
            num(r.period, 0.0),
            super::status_word(c.status),
            k = s.max_phases,
        ),
        Some("chain") => wln!(
            *out,
            "exact gait, global among those of at most {k} phases by the chain's formulation \
             ({k} slip phases, transitions free; the problem is a crawler's) (T = {}), global \
             MILP: {}",
            num(r.period, 0.0),
            super::status_word(c.status),
            k = s.max_phases,
        ),
        _ => wln!(
            *out,
            "exact gait of at most {} phases (T = {}), global MILP: {}",
            s.max_phases,
            num(r.period, 0.0),
            super::status_word(c.status)
        ),
    }
}

/// A local optimum of the general P_m ([`crate::api::optimize_general_local`]).
fn general_local(r: &GeneralAnswer, s: &GeneralLocal) -> String {
    let mut out = String::new();
    let scale = text_scale(r, &[s.objective, s.start_objective]);
    wln!(
        out,
        "P_{} ({} steps of h = {}), local LPCC method: {} after {} LPs, {} branch switches",
        s.m,
        s.path.u.len(),
        num(r.period / s.path.u.len() as f64, 0.0),
        match s.stop {
            LocalStop::Stationary => "stationary",
            LocalStop::Stalled => "stalled",
            LocalStop::RoundLimit => "round limit",
            LocalStop::TimeLimit => "time limit",
        },
        s.lp_solves,
        s.switches
    );
    wln!(
        out,
        "J = {}   (verified by simulation; a local optimum, no global claim; from {}, whose J \
         = {})",
        num(s.objective, scale),
        r.starts.map_or_else(
            || "its start".to_string(),
            |st| format!(
                "start {} of {} ({})",
                st.best_start + 1,
                st.starts_tried,
                st.start_from.replace('_', " ")
            )
        ),
        num(s.start_objective, scale)
    );
    upper_bound(&mut out, r, s.objective, scale);
    steps(&mut out, &s.path.x, &s.path.u);
    out
}

/// The line of the chain's upper bound over all periodic gaits, where the answer records one
/// (`bound`, any method), against its `J` (`scale`: the text's scale of `J`).
fn upper_bound(out: &mut String, r: &GeneralAnswer, j: f64, scale: f64) {
    if let Some(ub) = &r.head.certificate.upper_bound {
        super::gait::upper_bound_line(out, ub, (j, scale), &|v| num(v, scale));
    }
}

/// A P_m process step by step: the state at the step's start and its control, each column
/// scaled by its largest entry.
fn steps(out: &mut String, x: &[Vec<f64>], u: &[Vec<f64>]) {
    let xs = max_abs(x.iter().flatten()).max(1e-300);
    let us = max_abs(u.iter().flatten()).max(1e-300);
    for (i, ui) in u.iter().enumerate() {
        wln!(
            out,
            "  step {:>4}: x = {}  u = {}",
            i + 1,
            list(&x[i], xs),
            list(ui, us)
        );
    }
}

/// The text of any of the general `optimize` answers ([`GeneralAnswer`]): the optimum, the
/// local answer, the phase gait (its necessary conditions are rendered beside it, by
/// [`crate::present::result_text`] for either kind).
pub fn general_answer(r: &GeneralAnswer) -> String {
    match &r.solution {
        GeneralSolution::Pm(s) => general_optimum(r, s),
        GeneralSolution::Local(s) => general_local(r, s),
        GeneralSolution::Phase(s) => general_phase(r, s),
    }
}

/// A general answer's key number in one line: its J (0 below `1e-9` of the problem's floor of
/// `J`, as a crawler's displacement is below its length unit's; `GeneralProblem::j_floor`).
pub fn general_summary(r: &GeneralAnswer) -> String {
    let j = r.head.objective;
    format!("objective J = {}", num(j, text_scale(r, &[j])))
}
