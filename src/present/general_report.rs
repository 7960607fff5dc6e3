//! The report of the general problem (P) (theory §11): one self-contained HTML file, built on
//! the crawler's page ([`super::report`]: the same head, style sheet, figures and footer), with
//! the key numbers (the objective, the method, the status and the certificate, the chain's
//! upper bound where one is recorded, the problem's size), the necessary conditions when they
//! were computed, the problem's data (C's faces, the dynamics, U, f1, f2, the period), the
//! pieces of the process when there are few, and the figures of [`super::general`]. A general
//! problem has no animation.

use super::general::{answer_figures_with, general_path_figures, GeneralPath};
use super::report::{
    conditions_rows, esc, figures_section, footer, num, nums, open_page, upper_bound_kpi,
};
use crate::error::Result;
use crate::io::{GeneralAnswer, GeneralSimulated, GeneralSolution};
use crate::model::general::{Boundary, ControlSet, GeneralCost, GeneralProblem, Reward};
use crate::optimal::general::{
    analyze_polyhedron, GeneralLocal, GeneralPhaseGait, GeneralPm, Geometry,
};
use crate::optimal::LocalStop;

/// What a report of the general problem shows: a simulation or an optimum.
#[derive(Debug, Clone, Copy)]
pub enum GeneralReportInput<'a> {
    /// The file's `[input]` simulated (`crawlopt simulate`).
    Simulation(&'a GeneralSimulated),
    /// An optimum (`crawlopt optimize`, `crawlopt report`).
    Answer(&'a GeneralAnswer),
}

/// Most pieces listed in the report's table of the process (a longer process is in the
/// figures and in `--json`).
pub const MAX_LISTED_PIECES: usize = 64;

/// The report of a simulation or an optimum of `p` as one HTML document. `source` names the
/// input (a file name, shown in the page), `command` the command that made it (footer).
pub fn build_general_report(
    p: &GeneralProblem,
    input: GeneralReportInput<'_>,
    source: &str,
    command: &str,
) -> Result<String> {
    let g = analyze_polyhedron(&p.c)?;
    let path = match input {
        GeneralReportInput::Simulation(r) => GeneralPath::of_simulation(r)?,
        GeneralReportInput::Answer(a) => GeneralPath::of_answer(a)?,
    };
    let figs = match input {
        GeneralReportInput::Answer(a) => answer_figures_with(p, &g, &path, a)?,
        GeneralReportInput::Simulation(_) => general_path_figures(p, &g, &path)?,
    };
    let mut h = open_page(&format!("crawlopt report: {source}"));
    let (what, method, status, certificate) = describe(input);
    h.push_str(&format!(
        "<h1>{what} of a general problem (P)</h1>\n<p class=\"sub\">{} · crawlopt {} · \
         the sweeping process x′ ∈ −N_C(x) + A x + B u + b of the paper's §2</p>\n",
        esc(source),
        env!("CARGO_PKG_VERSION")
    ));
    h.push_str("<div class=\"kpi\">\n");
    h.push_str(&format!(
        "<div><span>objective J</span><b id=\"objective\" data-value=\"{}\">{}</b>\
         <span>∫ f₁(η) − f₂(u) dt over the period, verified by simulation</span></div>\n",
        path.objective,
        num(path.objective)
    ));
    h.push_str(&format!(
        "<div><span>method</span><b id=\"method\">{}</b><span>{}</span></div>\n",
        esc(method),
        esc(&status)
    ));
    h.push_str(&format!(
        "<div><span>certificate</span><b>{}</b><span>{}</span></div>\n",
        esc(&certificate.0),
        esc(&certificate.1)
    ));
    if let GeneralReportInput::Answer(a) = input {
        if let Some(ub) = &a.head.certificate.upper_bound {
            upper_bound_kpi(&mut h, ub, (path.objective, p.j_floor()), source);
        }
    }
    h.push_str(&format!(
        "<div><span>problem size</span><b id=\"size\">n = {}, m = {}, σ = {}</b>\
         <span>states, controls, faces of C; period T = {}{}</span></div>\n",
        p.states(),
        p.controls(),
        p.c.faces(),
        num(p.period),
        match p.boundary {
            Boundary::Periodic => ", periodic",
            Boundary::Initial(_) => ", Cauchy problem",
        }
    ));
    let nc = match input {
        GeneralReportInput::Answer(a) => a.necessary_conditions.as_ref(),
        _ => None,
    };
    if let Some(nc) = nc {
        let verdict = serde_json::to_string(&nc.verdict).unwrap_or_default();
        h.push_str(&format!(
            "<div><span>necessary conditions</span><b id=\"verdict\">{}</b><span>Theorem 2.2 \
             (discrete form): <a href=\"#certificate\">the conditions and their residuals</a>\
             </span></div>\n",
            esc(verdict.trim_matches('"'))
        ));
    }
    h.push_str("</div>\n");
    if let Some(nc) = nc {
        let verdict = serde_json::to_string(&nc.verdict).unwrap_or_default();
        h.push_str(&format!(
            "<h2 id=\"certificate\">Necessary conditions (Theorem 2.2, discrete form)</h2>\n\
             <p>Verdict: <b>{}</b>: {}.</p>\n<p>Multiplier λ = {}; J = {}; non-degeneracy \
             margin {}.</p>\n\
             <div class=\"scroll\">\n<table id=\"conditions\">\n<tr><th class=\"l\">theorem</th>\
             <th class=\"l\">condition</th><th>residual</th><th>tolerance</th>\
             <th class=\"l\">holds</th><th class=\"l\">statement</th></tr>\n",
            esc(verdict.trim_matches('"')),
            esc(&nc.reason),
            num(nc.lambda),
            num(nc.objective),
            esc(&super::text::margin_text(
                nc.nondegeneracy_margin,
                nc.nondegeneracy_resolution,
                nc.margin_required
            ))
        ));
        conditions_rows(&mut h, &nc.conditions);
        h.push_str("</table>\n</div>\n");
    }
    problem_section(&mut h, p, &g);
    process_section(&mut h, p, &path);
    figures_section(&mut h, &figs);
    footer(&mut h, command, "<code>--plot DIR</code>");
    h.push_str("</main>\n</body>\n</html>\n");
    Ok(h)
}

/// The head of a report of a record: what it is, its method, its status, its certificate.
type Description<'a> = (&'static str, &'a str, String, (String, String));

/// What the record is, its method, its status, and its certificate (headline, detail).
fn describe(input: GeneralReportInput<'_>) -> Description<'_> {
    match input {
        GeneralReportInput::Simulation(r) => describe_simulation(r),
        GeneralReportInput::Answer(r) => match &r.solution {
            GeneralSolution::Pm(s) => describe_discrete(r, s),
            GeneralSolution::Local(s) => describe_local(r, s),
            GeneralSolution::Phase(s) => describe_phase(r, s),
        },
    }
}

/// [`describe`] of a simulation: a given control played, no certificate.
fn describe_simulation(r: &GeneralSimulated) -> Description<'_> {
    (
        "Simulation",
        r.method,
        format!(
            "the file's [input] played to the periodic regime ({} periods{})",
            r.simulation.periods,
            if r.method == "exact" {
                String::new()
            } else {
                format!(", {} steps per period", r.steps_per_period)
            }
        ),
        (
            "none".into(),
            "a given control simulated, not optimised".into(),
        ),
    )
}

/// [`describe`] of a global P_m optimum: the MILP's status, gap and bound, and the start it
/// took, if any.
fn describe_discrete<'a>(r: &'a GeneralAnswer, s: &GeneralPm) -> Description<'a> {
    let c = &s.certificate;
    (
        "Optimum",
        "discrete",
        format!(
            "P_{} on {} steps, global MILP: {}",
            s.m,
            s.path.u.len(),
            c.status.as_str()
        ),
        (
            format!("gap {:.1e}", c.gap),
            format!(
                "MILP bound {} on J over P_{} (MILP objective {}){}",
                num(c.bound),
                s.m,
                num(c.milp_objective),
                r.discrete_start
                    .as_ref()
                    .map_or_else(String::new, |st| format!(
                        "; {}",
                        super::text::start_words(st, &num)
                    ))
            ),
        ),
    )
}

/// [`describe`] of a local P_m optimum: why the active-set method stopped, and its starts.
fn describe_local<'a>(r: &'a GeneralAnswer, s: &GeneralLocal) -> Description<'a> {
    let stop = match s.stop {
        LocalStop::Stationary => "stationary",
        LocalStop::Stalled => "stalled",
        LocalStop::RoundLimit => "round limit",
        LocalStop::TimeLimit => "time limit",
    };
    (
        "Local optimum",
        "local",
        format!(
            "P_{} on {} steps, active-set method on its LPCC: {stop} after {} LPs",
            s.m,
            s.path.u.len(),
            s.lp_solves
        ),
        (
            "local".into(),
            format!(
                "no global claim; {}from J = {}",
                r.starts.map_or_else(String::new, |st| format!(
                    "best of {} starts ({}), ",
                    st.starts_tried,
                    st.start_from.replace('_', " ")
                )),
                num(s.start_objective)
            ),
        ),
    )
}

/// [`describe`] of a gait of phases: the phase MILP's optimum (status, gap, bound), or the
/// gait of a crawler's method on the problem's chain (no global claim).
fn describe_phase<'a>(r: &'a GeneralAnswer, s: &GeneralPhaseGait) -> Description<'a> {
    if r.head.method != "phase" {
        return (
            "Gait",
            &r.head.method,
            format!(
                "the crawler's {} method on the problem's chain: {}",
                r.head.method,
                r.head.status.as_str()
            ),
            (
                "local".to_string(),
                format!(
                    "no global claim; an exact gait of {} phases",
                    s.durations.len()
                ),
            ),
        );
    }
    let c = &s.certificate;
    (
        "Optimum",
        "phase",
        format!(
            "exact gaits of at most {} phases, global MILP: {}",
            s.max_phases,
            c.status.as_str()
        ),
        (
            format!("gap {:.1e}", c.gap),
            format!(
                "MILP bound {} on J over gaits of at most {} phases",
                num(c.bound),
                s.max_phases
            ),
        ),
    )
}

/// The problem's data: C's faces (with redundancy), its geometry, g, U, f1, f2, T.
fn problem_section(h: &mut String, p: &GeneralProblem, g: &Geometry) {
    let faces = match &p.reward {
        Reward::FaceWeights(w) => Some(w),
        Reward::ReactionWeights(_) => None,
    };
    h.push_str(
        "<h2 id=\"problem\">The problem</h2>\n<div class=\"scroll\">\n<table id=\"faces\">\n\
         <tr><th>face j</th><th class=\"l\">unit normal x*ⱼ</th><th>offset cⱼ</th>",
    );
    if faces.is_some() {
        h.push_str("<th>weight in f₁</th>");
    }
    h.push_str("<th class=\"l\">facet</th></tr>\n");
    for j in 0..p.c.faces() {
        h.push_str(&format!(
            "<tr><td>{}</td><td class=\"l\">({})</td><td>{}</td>",
            j + 1,
            nums(&p.c.normals[j]),
            num(p.c.offsets[j])
        ));
        if let Some(w) = faces {
            h.push_str(&format!("<td>{}</td>", num(w[j])));
        }
        h.push_str(&format!(
            "<td class=\"l\">{}</td></tr>\n",
            if g.redundant_faces.contains(&(j + 1)) {
                "no (redundant)"
            } else {
                "yes"
            }
        ));
    }
    h.push_str("</table>\n</div>\n<ul>\n");
    h.push_str(&format!(
        "<li>C = {{x : ⟨x*ⱼ, x⟩ ≤ cⱼ}}: {}, Chebyshev centre ({}) of radius {}{}.</li>\n",
        if g.bounded { "bounded" } else { "unbounded" },
        nums(&g.chebyshev_centre),
        num(g.chebyshev_radius),
        match &g.vertices {
            Some(v) if g.rank == g.dim => format!(", {} vertices", v.len()),
            Some(v) => format!(", {} minimal faces", v.len()),
            None => ", vertices not enumerated".into(),
        }
    ));
    let rows = |m: &[Vec<f64>]| {
        m.iter()
            .map(|r| format!("({})", nums(r)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    h.push_str(&format!(
        "<li>Dynamics g(x, u) = A x + B u + b with A = [{}], B = [{}], b = ({}).</li>\n",
        rows(&p.dynamics.a),
        rows(&p.dynamics.b),
        nums(&p.dynamics.drift)
    ));
    h.push_str(&format!(
        "<li>Controls U: {}{}.</li>\n",
        match &p.control {
            ControlSet::Box { lower, upper } =>
                format!("the box ({}) ≤ u ≤ ({})", nums(lower), nums(upper)),
            ControlSet::Polytope(u) => format!(
                "the polytope {{u : G u ≤ h}} of {} faces, G = [{}], h = ({})",
                u.faces(),
                rows(&u.normals),
                nums(&u.offsets)
            ),
        },
        if p.zero_mean {
            ", with zero mean over a period"
        } else {
            ""
        }
    ));
    h.push_str(&format!(
        "<li>Reward f₁(η): {}; cost f₂(u): {}.</li>\n",
        match &p.reward {
            Reward::FaceWeights(_) =>
                "the face weights above times the faces' reaction rates".to_string(),
            Reward::ReactionWeights(q) => format!("⟨q, η⟩ with q = ({})", nums(q)),
        },
        match &p.cost {
            GeneralCost::None => "none".to_string(),
            GeneralCost::Quadratic { weight } => format!("(c/2)|u|² with c = {}", num(*weight)),
            GeneralCost::Matrix { matrix } => format!("(1/2) uᵀ R u with R = [{}]", rows(matrix)),
        }
    ));
    h.push_str(&format!(
        "<li>Period T = {}; {}.</li>\n</ul>\n",
        num(p.period),
        match &p.boundary {
            Boundary::Periodic => "periodic, x(0) = x(T)".to_string(),
            Boundary::Initial(x0) => format!("a Cauchy problem from x(0) = ({})", nums(x0)),
        }
    ));
}

/// The pieces of the process (time, control, faces holding the state), when at most
/// [`MAX_LISTED_PIECES`].
fn process_section(h: &mut String, p: &GeneralProblem, path: &GeneralPath) {
    let k = path.u.len();
    // Solver noise (1e-12 of the quantity's scale) is shown as the 0 it stands for.
    let snap = |v: f64, scale: f64| if v.abs() <= 1e-12 * scale { 0.0 } else { v };
    let cs = p.c.scale();
    let x0: Vec<f64> = path.x[0].iter().map(|v| snap(*v, cs)).collect();
    h.push_str(&format!(
        "<h2 id=\"process\">The process</h2>\n<p>{k} pieces; x(0) = ({}).</p>\n",
        nums(&x0)
    ));
    if k > MAX_LISTED_PIECES {
        h.push_str(&format!(
            "<p>More than {MAX_LISTED_PIECES} pieces: see the figures (and <code>--json</code> \
             for every number).</p>\n"
        ));
        return;
    }
    h.push_str("<div class=\"scroll\">\n<table id=\"pieces\">\n<tr><th>piece</th><th>from t</th><th>to t</th>");
    for l in 1..=p.controls() {
        h.push_str(&format!("<th>u{}</th>", super::figures::sub(l)));
    }
    h.push_str("<th class=\"l\">faces holding x (λⱼ &gt; 0)</th></tr>\n");
    let biggest = path.lambda.iter().flatten().fold(0.0_f64, |a, v| a.max(*v));
    let us = path.u.iter().flatten().fold(0.0_f64, |a, v| a.max(v.abs()));
    for (i, u) in path.u.iter().enumerate() {
        h.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td>",
            i + 1,
            num(path.t[i]),
            num(path.t[i + 1])
        ));
        for v in u {
            h.push_str(&format!("<td>{}</td>", num(snap(*v, us))));
        }
        let held: Vec<String> = path.lambda[i]
            .iter()
            .enumerate()
            .filter(|(_, l)| **l > 1e-12 * biggest && **l > 0.0)
            .map(|(j, _)| (j + 1).to_string())
            .collect();
        h.push_str(&format!(
            "<td class=\"l\">{}</td></tr>\n",
            if held.is_empty() {
                "none".to_string()
            } else {
                held.join(", ")
            }
        ));
    }
    h.push_str("</table>\n</div>\n");
}
