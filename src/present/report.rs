//! The report: one self-contained HTML file for a crawler and its optimal gait.
//!
//! Everything is inline (CSS, the figures as SVG, the animation's JavaScript and its data as
//! JSON), nothing is fetched, so the file opens from disk, can be mailed, and still works in
//! years. It shows the crawler's parameters and analysis, the optimal gait with its certificate,
//! the figures of [`super::figures`], and an animation of the crawler playing the gait over
//! [`SHOWN_PERIODS`] periods (`animation.js`).

use super::figures::{self, Figure};
use super::{replay_gait, SHOWN_PERIODS};
use crate::certify::NecessaryConditions;
use crate::error::{Error, Result};
use crate::integrate::{Method, Trajectory};
use crate::io::AtomicFile;
use crate::model::Analysis;
use crate::model::{Crawler, FaceSign};
use crate::optimal::bound_record::UpperBound;
use crate::optimal::{Cost, GaitResult, MilpStatus};
use serde::Serialize;
use std::io::Write;
use std::path::Path;

const CSS: &str = include_str!("report.css");
const ANIMATION_JS: &str = include_str!("animation.js");

/// What the animation plays (serialised into the page).
#[derive(Serialize)]
struct AnimationData<'a> {
    period: f64,
    periods: usize,
    displacement: f64,
    spacing: f64,
    y0: f64,
    k: &'a [f64],
    mu_forward: &'a [f64],
    mu_backward: &'a [f64],
    t: &'a [f64],
    #[serde(rename = "X")]
    positions: &'a [Vec<f64>],
    #[serde(rename = "L")]
    lengths: Vec<Vec<f64>>,
    x: &'a [Vec<f64>],
    slip: &'a [Vec<i8>],
}

/// HTML-escapes text.
pub(super) fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&#39;"),
            _ => o.push(c),
        }
    }
    o
}

/// A number for people: up to 6 significant digits, no trailing zeros.
pub(super) fn num(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-4..1e6).contains(&a) {
        let digits = (5 - a.log10().floor() as i32).clamp(0, 12) as usize;
        let s = format!("{v:.digits$}");
        let s = if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        };
        if s == "-0" {
            "0".into()
        } else {
            s
        }
    } else {
        format!("{v:.5e}")
    }
}

pub(super) fn nums(v: &[f64]) -> String {
    v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")
}

/// An inline SVG that scales with the page: a `viewBox` is added to the root element.
pub(super) fn inline_svg(fig: &Figure) -> String {
    let svg = fig.svg.trim();
    let start = svg.find("<svg").unwrap_or(0);
    let svg = &svg[start..];
    let attr = |name: &str| -> Option<String> {
        let head = &svg[..svg.find('>').unwrap_or(svg.len())];
        let i = head.find(&format!(" {name}=\""))? + name.len() + 3;
        let j = head[i..].find('"')? + i;
        Some(head[i..j].to_string())
    };
    match (attr("width"), attr("height")) {
        (Some(w), Some(h)) => svg.replacen(
            "<svg",
            &format!(
                "<svg viewBox=\"0 0 {w} {h}\" role=\"img\" aria-label=\"{}\"",
                esc(&fig.caption)
            ),
            1,
        ),
        _ => svg.to_string(),
    }
}

/// What a report says beside the gait: where it came from and, when it was computed, the
/// certificate of the necessary conditions.
#[derive(Debug, Clone)]
pub struct ReportContext<'a> {
    /// The input's name (a file name, shown in the page; no directories).
    pub source: &'a str,
    /// The command that made the report, named in the footer (`crawlopt report gait.json`,
    /// `crawlopt optimize model.toml --certify --report ...`).
    pub command: String,
    /// The necessary conditions of the gait (Theorem 2.2), shown with their verdict, their
    /// residuals and the adjoint figure; `None` when they were not computed.
    pub certificate: Option<&'a NecessaryConditions>,
}

impl<'a> ReportContext<'a> {
    /// The context of `crawlopt report source`: no certificate.
    pub fn report_command(source: &'a str) -> Self {
        ReportContext {
            source,
            command: format!("crawlopt report {source}"),
            certificate: None,
        }
    }
}

/// The report of a gait result as one HTML document, as `crawlopt report` makes it. `source`
/// names the input (a file name, shown in the page; no directories).
pub fn build_report(result: &GaitResult, source: &str) -> Result<String> {
    build_report_with(result, &ReportContext::report_command(source))
}

/// The report of a gait result as one HTML document, with what `ctx` adds (the command that
/// made it, the certificate).
pub fn build_report_with(result: &GaitResult, ctx: &ReportContext<'_>) -> Result<String> {
    let (crawler, sim) = replay_gait(result, SHOWN_PERIODS)?;
    let traj = sim
        .trajectory
        .as_ref()
        .ok_or_else(|| Error::Numerical("no trajectory was recorded".into()))?;
    let mut figs = super::gait_figures_from(result, &crawler, traj)?;
    if let Some(c) = ctx.certificate {
        figs.push(super::adjoint_figure_of(&c.multipliers)?);
    }
    let data = animation_data(result, &crawler, traj)?;
    let json = serde_json::to_string(&data)
        .map_err(|e| Error::Numerical(format!("report data: {e}")))?
        .replace("</", "<\\/");
    Ok(page(result, &crawler, ctx, &figs, &json))
}

fn animation_data<'a>(
    result: &'a GaitResult,
    crawler: &'a Crawler,
    traj: &'a Trajectory,
) -> Result<AnimationData<'a>> {
    let act = super::gait_actuation(result)?;
    let lengths = traj
        .t
        .iter()
        .map(|&t| {
            let mut row = vec![0.0; crawler.links()];
            act.lengths_at(t, &mut row);
            row
        })
        .collect();
    Ok(AnimationData {
        period: result.problem.period,
        periods: SHOWN_PERIODS,
        displacement: result.displacement_per_period,
        spacing: figures::display_spacing(traj),
        y0: traj.barycentre[0],
        k: crawler.stiffness(),
        mu_forward: crawler.mu_forward(),
        mu_backward: crawler.mu_backward(),
        t: &traj.t,
        positions: &traj.positions,
        lengths,
        x: &traj.x,
        slip: &traj.slip,
    })
}

fn page(
    result: &GaitResult,
    crawler: &Crawler,
    ctx: &ReportContext<'_>,
    figs: &[Figure],
    json: &str,
) -> String {
    let source = ctx.source;
    let a = crawler.analyze();
    let nb = crawler.blocks();
    let mut h = open_page(&format!("crawlopt report: {}", source));
    h.push_str(&format!(
        "<h1>Optimal gait of a {nb}-block crawler</h1>\n<p class=\"sub\">{} · crawlopt {} · \
         units: any consistent set (lengths, forces, times as in the input)</p>\n",
        esc(source),
        env!("CARGO_PKG_VERSION")
    ));
    let (cert, status) = claims(result);
    key_numbers(&mut h, result, ctx, &cert);
    animation_section(&mut h, result);
    crawler_section(&mut h, result, crawler, &a);
    analysis_section(&mut h, &a);
    gait_section(&mut h, result, crawler.links(), &cert, &status);
    if let Some(c) = ctx.certificate {
        certificate_section(&mut h, c);
    }

    figures_section(&mut h, figs);
    footer(&mut h, &ctx.command, "<code>crawlopt plot</code>");
    h.push_str("</main>\n<script type=\"application/json\" id=\"crawler-data\">");
    h.push_str(json);
    h.push_str("</script>\n<script>\n");
    h.push_str(ANIMATION_JS);
    h.push_str("</script>\n</body>\n</html>\n");
    h
}

/// What the certificate claims (its kind in words) and the solver's status in words.
fn claims(result: &GaitResult) -> (String, String) {
    let c = &result.head.certificate;
    let cert = match (c.kind.as_str(), c.phases, result.m) {
        ("global_k_phases", Some(k), _) if result.head.status == MilpStatus::DominatesKPhases => {
            format!("at least as good as every gait of at most {k} slip phases (it has more)")
        }
        ("global_k_phases", Some(k), _) if !result.head.status.is_optimal() => {
            format!("not proven: the bound is over gaits of at most {k} slip phases")
        }
        ("global_k_phases", Some(k), _) => {
            format!("globally optimal among gaits of at most {k} slip phases")
        }
        ("global", _, Some(m)) => format!("globally optimal for P_{m} ({} steps)", 1u64 << m),
        ("local", _, Some(m)) if result.head.status == MilpStatus::Stationary => {
            format!("locally optimal for P_{m} ({} steps)", 1u64 << m)
        }
        ("local", Some(k), None) if result.head.status == MilpStatus::Stationary => format!(
            "locally optimal: no change of one slip mode in its sequence of {k} improves it"
        ),
        ("local", _, _) if result.records.structured.is_some() => {
            "a structured gait, or the chain method's improvement of one (no optimality claim)"
                .into()
        }
        ("local", _, _) => "the best gait the local method found before it stopped (no \
                            optimality claim)"
            .into(),
        (k, _, _) => k.to_string(),
    };
    let among = match c.phases {
        Some(k) => format!("solved to optimality among gaits of at most {k} slip phases"),
        None => "solved to optimality among gaits of at most K slip phases".into(),
    };
    let dominates = format!(
        "proven: no gait of at most {} slip phases does better (this one has {})",
        c.phases.unwrap_or_default(),
        result.gait.slip_phases()
    );
    let status = match result.head.status {
        MilpStatus::Optimal => "solved to optimality",
        MilpStatus::OptimalAmongKPhases => among.as_str(),
        MilpStatus::DominatesKPhases => dominates.as_str(),
        MilpStatus::TimeLimit => "stopped at the time limit (see the gap)",
        MilpStatus::ApproximationLimit => {
            "outer approximation of the cost stopped before closing the gap (see the gap)"
        }
        MilpStatus::Stationary => "a stationary point of the local method (no global claim)",
        MilpStatus::Stalled => "the local method stopped improving (no global claim)",
    };
    (cert, status.to_string())
}

/// The key numbers: J, the verified displacement, the certificate and its bound, the upper
/// bound and the necessary conditions' verdict when there are.
fn key_numbers(h: &mut String, result: &GaitResult, ctx: &ReportContext<'_>, cert: &str) {
    let source = ctx.source;
    let c = &result.head.certificate;
    h.push_str("<div class=\"kpi\">\n");
    h.push_str(&format!(
        "<div><span>objective J</span><b id=\"objective\">{}</b><span>displacement − cost per period [length]</span></div>\n",
        num(result.head.objective)
    ));
    h.push_str(&format!(
        "<div><span>displacement per period</span><b id=\"displacement-per-period\" data-value=\"{}\">{}</b><span>verified by simulation [length]</span></div>\n",
        result.displacement_per_period,
        num(result.displacement_per_period)
    ));
    // A result read from a file was checked (GaitResult::check_consistent): its gait, values
    // and tables recomputed or replayed, its bound at least the verified J with the gap it
    // states. The bound itself is a claim of the optimiser that wrote the file: re-proving it
    // takes the solve again, so the page says so.
    let recorded = if c.bound.is_some() && source.ends_with(".json") {
        " (as recorded in the file: at least the verified J, not re-proven here)"
    } else {
        ""
    };
    h.push_str(&format!(
        "<div><span>certificate</span><b>{}</b><span>{}; bound {}{recorded}</span></div>\n",
        c.gap.map_or("local".into(), |g| format!("gap {g:.1e}")),
        esc(cert),
        c.bound.map_or("none".into(), num)
    ));
    if let Some(ub) = &c.upper_bound {
        let length = super::text::GaitScales::of(result).length;
        upper_bound_kpi(h, ub, (result.head.objective, length), source);
    }
    if let Some(nc) = ctx.certificate {
        let verdict = serde_json::to_string(&nc.verdict).unwrap_or_default();
        h.push_str(&format!(
            "<div><span>necessary conditions</span><b>{}</b><span>Theorem 2.2: \
             <a href=\"#certificate\">the conditions and their residuals</a></span></div>\n",
            esc(verdict.trim_matches('"'))
        ));
    }
    h.push_str("</div>\n");
}

/// The key number of an upper bound over all periodic gaits recorded with a result of either
/// kind (`certificate.upper_bound`): its value, its grid and how far the verified `J` can be
/// from it, over `scale` (the length unit, or (P)'s floor of `J`). Like the certificate's
/// bound, a bound read from a result file (`source` a `.json`) was checked to be at least the
/// verified `J` but is not re-proven.
pub(super) fn upper_bound_kpi(
    h: &mut String,
    ub: &UpperBound,
    (j, scale): (f64, f64),
    source: &str,
) {
    let recorded = if source.ends_with(".json") {
        " (as recorded in the file, not re-proven here)"
    } else {
        ""
    };
    h.push_str(&format!(
        "<div><span>upper bound over all periodic gaits</span><b id=\"upper-bound\">{}</b>\
         <span>{} on a {} grid{}: optimal within {:.1} % among all periodic gaits{recorded}</span></div>\n",
        num(ub.value),
        esc(&ub.method),
        esc(&ub.resolution_text()),
        if ub.status == crate::optimal::bound_record::BoundStatus::TimeLimit {
            ", its LP cut short by the time limit"
        } else {
            ""
        },
        100.0 * ub.within(j, scale)
    ));
}

/// The animation's section (its data are the page's JSON).
fn animation_section(h: &mut String, result: &GaitResult) {
    let replayer = match result.verified_with() {
        Method::CatchingUp => "catching-up on the gait's grid (as it was verified)",
        Method::Exact => "the exact simulator",
    };
    h.push_str(&format!(
        "<h2 id=\"animation\">The crawler playing the gait</h2>\n\
         <p>{SHOWN_PERIODS} periods of the optimal gait on its periodic orbit, replayed by {replayer}. \
         Blocks are coloured while they slide (<span style=\"color:var(--fwd)\">forward</span>, \
         <span style=\"color:var(--bwd)\">backward</span>); the white arrow on a sliding block is the friction force, \
         which opposes the motion with threshold μ⁺ or μ⁻. Each link is an actuator (grey body and rod, length L) \
         in series with a spring (zig-zag, compressed when x &gt; 0). Spacing between blocks is for display only.</p>\n\
         <svg id=\"crawler-svg\" role=\"img\" aria-label=\"animation of the crawler\"></svg>\n\
         <div class=\"controls\">\n<button id=\"anim-play\" type=\"button\">Pause</button>\n\
         <label class=\"time\">time <input id=\"anim-time\" type=\"range\" min=\"0\" max=\"1\" step=\"0.001\" value=\"0\"></label>\n\
         <label>speed <input id=\"anim-speed\" type=\"range\" min=\"0.1\" max=\"4\" step=\"0.05\" value=\"1\"></label>\n\
         <output id=\"anim-speed-value\"></output>\n</div>\n\
         <div id=\"anim-state\" aria-live=\"off\"></div>\n\
         <p class=\"sub\">At speed 1× a period lasts 4 seconds.</p>\n"
    ));
}

/// The crawler's parameters per block and per link, and the gait problem.
fn crawler_section(h: &mut String, result: &GaitResult, crawler: &Crawler, a: &Analysis) {
    let (nb, n) = (crawler.blocks(), crawler.links());
    h.push_str(
        "<h2 id=\"crawler\">The crawler</h2>\n<div class=\"scroll\">\n<table>\n<tr><th class=\"l\">block b</th>",
    );
    for b in 1..=nb {
        h.push_str(&format!("<th>{b}</th>"));
    }
    h.push_str("</tr>\n<tr><td class=\"l\">μ⁺ (against forward sliding) [force]</td>");
    for v in crawler.mu_forward() {
        h.push_str(&format!("<td>{}</td>", num(*v)));
    }
    h.push_str("</tr>\n<tr><td class=\"l\">μ⁻ (against backward sliding) [force]</td>");
    for v in crawler.mu_backward() {
        h.push_str(&format!("<td>{}</td>", num(*v)));
    }
    h.push_str(
        "</tr>\n</table>\n</div>\n<div class=\"scroll\">\n<table>\n<tr><th class=\"l\">link l (blocks l, l+1)</th>",
    );
    for l in 1..=n {
        h.push_str(&format!("<th>{l}</th>"));
    }
    h.push_str("</tr>\n<tr><td class=\"l\">stiffness k [force/length]</td>");
    for v in crawler.stiffness() {
        h.push_str(&format!("<td>{}</td>", num(*v)));
    }
    h.push_str("</tr>\n<tr><td class=\"l\">rate bound a = k·max|L′| [force/time]</td>");
    for v in &result.problem.rate_bound {
        h.push_str(&format!("<td>{}</td>", num(*v)));
    }
    h.push_str("</tr>\n<tr><td class=\"l\">range of x over C [force]</td>");
    for r in &a.link_force_ranges {
        h.push_str(&format!("<td>[{}, {}]</td>", num(r[0]), num(r[1])));
    }
    h.push_str("</tr>\n</table>\n</div>\n");
    h.push_str(&format!(
        "<p>Gait problem: period T = {}, cost {}{}.</p>\n",
        num(result.problem.period),
        match result.problem.cost {
            Cost::None => "none (f₂ = 0)".to_string(),
            Cost::Quadratic { weight } => format!("(c/2)|u|² with c = {}", num(weight)),
        },
        result
            .problem
            .max_total_variation
            .map_or(String::new(), |v| format!(
                ", total variation of u at most {}",
                num(v)
            ))
    ));
}

/// The analysis: the uniqueness condition, v_m, the one-link structure and the faces of C.
fn analysis_section(h: &mut String, a: &Analysis) {
    h.push_str("<h2 id=\"analysis\">Analysis</h2>\n<ul>\n");
    h.push_str(&match (&a.violating_subset, a.uniqueness_margin) {
        (Some(j), _) => {
            format!("<li>Uniqueness condition (eq. 3.6) <b>fails</b> for J = {j:?}.</li>\n")
        }
        (None, Some(m)) => format!(
            "<li>Uniqueness condition (eq. 3.6) holds, margin {} (closest subset J = {:?}).</li>\n",
            num(m),
            a.closest_subset.clone().unwrap_or_default()
        ),
        _ => "<li>Uniqueness condition: undecided.</li>\n".into(),
    });
    if let Some(class) = a.vm_class {
        let class = serde_json::to_string(&class).unwrap_or_default();
        h.push_str(&format!(
            "<li>Displacement function vₘ: <b>{}</b>; some shape rate moves the crawler forward: {}, backward: {}.</li>\n",
            esc(class.trim_matches('"')),
            yes(a.moves_forward),
            yes(a.moves_backward)
        ));
    }
    if let Some(o) = &a.one_link {
        h.push_str(&format!(
            "<li>One link (paper §4): C = [α, β] = [{}, {}], width w = {}; extension moves it forward: {}, contraction: {}.</li>\n",
            num(o.alpha),
            num(o.beta),
            num(o.width),
            yes(Some(o.extension_moves_forward)),
            yes(Some(o.contraction_moves_forward))
        ));
    }
    h.push_str("</ul>\n<table>\n<tr><th class=\"l\">face of C</th><th class=\"l\">constraint</th><th class=\"l\">facet</th><th class=\"l\">meaning</th></tr>\n");
    for f in &a.faces {
        let (label, cons, meaning) = match f.sign {
            FaceSign::Forward => (
                format!("{}+", f.block),
                format!("F{} ≤ {}", figures::sub(f.block), num(f.offset)),
                format!("block {} slides forward", f.block),
            ),
            FaceSign::Backward => (
                format!("{}−", f.block),
                format!("F{} ≥ {}", figures::sub(f.block), num(-f.offset)),
                format!("block {} slides backward", f.block),
            ),
        };
        h.push_str(&format!(
            "<tr><td class=\"l\">{label}</td><td class=\"l\">{cons}</td><td class=\"l\">{}</td><td class=\"l\">{meaning}</td></tr>\n",
            if f.facet { "yes" } else { "no (redundant)" }
        ));
    }
    h.push_str("</table>\n");
}

/// The gait: method, claim and values, and its pieces with their controls and slips.
fn gait_section(h: &mut String, result: &GaitResult, n: usize, cert: &str, status: &str) {
    h.push_str(&format!(
        "<h2 id=\"gait\">The optimal gait</h2>\n<p>Method <code>{}</code>, {status}; {}. \
         Displacement per period {} (simulator) against {} (solver); actuation cost {}.</p>\n",
        esc(&result.head.method),
        esc(cert),
        num(result.displacement_per_period),
        num(result.solver_objective),
        num(result.actuation_cost)
    ));
    if let Some(st) = &result.records.structured {
        h.push_str(&format!(
            "<p id=\"structured\">The gait: {}.",
            esc(&st.origin)
        ));
        if let Some(why) = &st.replaced {
            h.push_str(&format!(
                " Kept instead of the method's answer: {}.",
                esc(why)
            ));
        }
        h.push_str("</p>\n");
    }
    if let Some(st) = &result.discrete_start {
        h.push_str(&format!(
            "<p id=\"start\">{}.</p>\n",
            esc(&sentence(super::text::start_words(st, &num)))
        ));
    }
    // Pieces are numbered from 0, as in the text of `crawlopt optimize` and its certificate
    // ("piece 1" is the second piece there too).
    h.push_str("<div class=\"scroll\">\n<table id=\"pieces\">\n<tr><th>piece</th><th>from t</th><th>to t</th>");
    for l in 1..=n {
        h.push_str(&format!("<th>u{} [force/time]</th>", figures::sub(l)));
    }
    h.push_str("<th class=\"l\">slip of blocks 1..N</th></tr>\n");
    let g = &result.gait;
    for (j, u) in g.controls.iter().enumerate() {
        h.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td>",
            j,
            num(g.times[j]),
            num(g.times[j + 1])
        ));
        for (v, a) in u.iter().zip(&result.problem.rate_bound) {
            // Solver noise (1e-14 of the rate bound) is shown as the 0 it stands for.
            let v = if v.abs() <= 1e-9 * a { 0.0 } else { *v };
            h.push_str(&format!("<td>{}</td>", num(v)));
        }
        let slip: Vec<&str> = g.slip[j]
            .iter()
            .map(|s| match s {
                1 => "+",
                -1 => "−",
                _ => "0",
            })
            .collect();
        h.push_str(&format!("<td class=\"l\">{}</td></tr>\n", slip.join(" ")));
    }
    h.push_str(&format!(
        "</table>\n</div>\n<p>Initial state on the orbit x(0) = ({}).</p>\n",
        nums(&g.initial_state)
    ));
}

/// The certificate's section: the verdict and its reason, and every condition with its
/// residual and tolerance (the table `crawlopt optimize --certify` prints).
fn certificate_section(h: &mut String, c: &NecessaryConditions) {
    let verdict = serde_json::to_string(&c.verdict).unwrap_or_default();
    h.push_str(&format!(
        "<h2 id=\"certificate\">Necessary conditions (Theorem 2.2)</h2>\n\
         <p>Verdict: <b id=\"verdict\">{}</b>: {}.</p>\n\
         <p>Multiplier λ = {} (scaled: {}); J = {}; min |p + ω| = {}.</p>\n",
        esc(verdict.trim_matches('"')),
        esc(&c.reason),
        num(c.lambda),
        esc(&c.normalisation.scaled_by),
        num(c.objective),
        esc(&super::text::margin_text(
            c.nondegeneracy_margin,
            c.nondegeneracy_resolution,
            c.margin_required
        ))
    ));
    h.push_str(
        "<div class=\"scroll\">\n<table id=\"conditions\">\n<tr><th class=\"l\">theorem</th>\
         <th class=\"l\">condition</th><th>residual</th><th>tolerance</th><th class=\"l\">holds</th>\
         <th class=\"l\">statement</th></tr>\n",
    );
    conditions_rows(h, &c.conditions);
    h.push_str("</table>\n</div>\n<p>The adjoint p(t) with the controls is the figure <a href=\"#fig-adjoint\">adjoint</a> below.</p>\n");
}

/// The rows of a table of conditions, each with its residual and tolerance.
pub(super) fn conditions_rows(h: &mut String, conditions: &[crate::certify::ConditionCheck]) {
    for k in conditions {
        h.push_str(&format!(
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{:.3e}</td><td>{:.1e}</td>\
             <td class=\"l\">{}</td><td class=\"l\">{}</td></tr>\n",
            esc(&k.theorem),
            esc(&k.name),
            k.residual,
            k.tolerance,
            if k.holds { "holds" } else { "<b>FAILS</b>" },
            esc(&k.statement)
        ));
    }
}

/// The start of a report's page: the document's head with the style sheet, up to `<main>`.
pub(super) fn open_page(title: &str) -> String {
    let mut h = String::with_capacity(200_000);
    h.push_str(&format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"crawlopt {}\">\n<title>{}</title>\n<style>\n{}</style>\n</head>\n<body>\n<main>\n",
        env!("CARGO_PKG_VERSION"),
        esc(title),
        CSS
    ));
    h
}

/// A report's section of figures, each inline with its caption (anchor `fig-NAME`).
pub(super) fn figures_section(h: &mut String, figs: &[Figure]) {
    h.push_str("<h2 id=\"figures\">Figures</h2>\n");
    for f in figs {
        h.push_str(&format!(
            "<figure id=\"fig-{}\">\n{}\n<figcaption>{}</figcaption>\n</figure>\n",
            esc(&f.name),
            inline_svg(f),
            esc(&f.caption)
        ));
    }
}

/// A report's footer: the version, the command that made it (`command`), how the figures are
/// also written (`figures_by`, HTML) and the paper.
pub(super) fn footer(h: &mut String, command: &str, figures_by: &str) {
    h.push_str(&format!(
        "<footer>Made by crawlopt {} (<code>{}</code>). Figures are also written as SVG and PNG by \
         {figures_by}. Paper: “On the optimal control of rate-independent soft crawlers”.</footer>\n",
        env!("CARGO_PKG_VERSION"),
        esc(command)
    ));
}

/// `words` as a sentence: its first letter capitalised.
fn sentence(mut words: String) -> String {
    if let Some(first) = words.get(..1) {
        let upper = first.to_uppercase();
        words.replace_range(..1, &upper);
    }
    words
}

fn yes(v: Option<bool>) -> &'static str {
    match v {
        Some(true) => "yes",
        Some(false) => "no",
        None => "unknown",
    }
}

/// Writes the report by the rules of [`AtomicFile`]: a regular file (or the file a symbolic
/// link resolves to) atomically, a temporary file renamed into place, nothing left on
/// failure; a device or FIFO straight into it; a directory is refused before anything is
/// written.
pub fn write_report(path: &Path, html: &str) -> Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.writer()
        .write_all(html.as_bytes())
        .map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: format!("cannot write: {e}"),
        })?;
    f.commit()
}
