//! The text of an analysis (`crawlopt analyze`).

use super::{force_scale, list, num, wln, GaitScales};
use crate::model::{Analysis, Crawler, FaceSign, OneLink};
use crate::optimal::{Cost, GaitProblem, OneLinkOptimum};

/// The human form of an analysis. Parameters and the faces of C (sums of them) are shown
/// without snapping; computed forces (link ranges, vertices) at [`force_scale`].
pub fn analysis(c: &Crawler, a: &Analysis) -> String {
    let mut out = String::new();
    let force = force_scale(c);
    wln!(
        out,
        "crawler: N = {} blocks, n = {} links",
        a.blocks,
        a.links
    );
    wln!(out, "  stiffness k    = {}", list(c.stiffness(), 0.0));
    wln!(out, "  mu_forward     = {}", list(c.mu_forward(), 0.0));
    wln!(out, "  mu_backward    = {}", list(c.mu_backward(), 0.0));
    wln!(out, "uniqueness condition (eq. 3.6):");
    match (&a.violating_subset, &a.uniqueness_undecided) {
        (Some(j), _) => wln!(out, "  FAILS for J = {j:?}: the motion is not unique"),
        (None, Some(r)) => wln!(out, "  undecided: {r}"),
        (None, None) => wln!(
            out,
            "  holds; margin {} (closest subset J = {:?})",
            num(a.uniqueness_margin.unwrap_or(f64::NAN), 0.0),
            a.closest_subset.clone().unwrap_or_default()
        ),
    }
    polytope_lines(&mut out, a, force);
    if let Some(class) = a.vm_class {
        wln!(out, "displacement function v_m (exact):");
        wln!(
            out,
            "  class: {}",
            serde_json::to_string(&class)
                .expect("enum")
                .trim_matches('"')
        );
        wln!(
            out,
            "  moves forward: {}   moves backward: {}",
            a.moves_forward.unwrap_or(false),
            a.moves_backward.unwrap_or(false)
        );
    }
    if let Some(o) = &a.one_link {
        one_link_lines(&mut out, o, force);
    }
    out
}

/// The polytope C of an analysis: its faces (facets marked), the range of each link's force
/// and the vertices, the computed forces at the scale `force`.
fn polytope_lines(out: &mut String, a: &Analysis, force: f64) {
    wln!(out, "polytope C (F_b = x_(b-1) - x_b; facets marked *):");
    for f in &a.faces {
        let (rel, bound) = match f.sign {
            FaceSign::Forward => ("<=", num(f.offset, 0.0)),
            FaceSign::Backward => (">=", num(-f.offset, 0.0)),
        };
        wln!(
            out,
            "  {} block {:>3} {}: F_{} {rel} {bound}",
            if f.facet { "*" } else { " " },
            f.block,
            match f.sign {
                FaceSign::Forward => "+ (slides forward) ",
                FaceSign::Backward => "- (slides backward)",
            },
            f.block
        );
    }
    for (l, r) in a.link_force_ranges.iter().enumerate() {
        wln!(
            out,
            "  link {:>3}: x in [{}, {}]",
            l + 1,
            num(r[0], force),
            num(r[1], force)
        );
    }
    if let Some(v) = &a.vertices {
        wln!(out, "  {} vertices:", v.len());
        for x in v {
            wln!(out, "    {}", list(x, force));
        }
    }
}

/// The closed forms of a one-link crawler (theory §9): C, which strokes move it forward, and
/// the least stroke that does, the forces at the scale `force`.
fn one_link_lines(out: &mut String, o: &OneLink, force: f64) {
    wln!(
        out,
        "one link (theory §9): C = [{}, {}], width w = {}",
        num(o.alpha, force),
        num(o.beta, force),
        num(o.width, force)
    );
    wln!(
        out,
        "  extension moves forward: {}   contraction moves forward: {}",
        o.extension_moves_forward,
        o.contraction_moves_forward
    );
    match (o.min_at_forward, o.min_at_backward) {
        (Some(m), _) => wln!(
            out,
            "  forward locomotion needs a*T > {} (rate bound x period)",
            num(m, force)
        ),
        (None, Some(m)) => wln!(
            out,
            "  no periodic gait moves it forward; backward locomotion needs a*T > {}",
            num(m, force)
        ),
        _ => wln!(out, "  v_m is linear: no periodic gait moves it"),
    }
}

/// The line of a gait problem (and the one-link closed form) under an analysis.
pub fn gait_problem(
    crawler: &Crawler,
    g: &GaitProblem,
    optimum: Option<&OneLinkOptimum>,
) -> String {
    let mut out = String::new();
    wln!(
        out,
        "gait problem: period {}, rate bounds a = {}, cost {}{}",
        num(g.period, 0.0),
        list(&g.rate_bound, 0.0),
        match g.cost {
            Cost::None => "none".to_string(),
            Cost::Quadratic { weight } => format!("(c/2)|u|^2 with c = {}", num(weight, 0.0)),
        },
        g.max_total_variation.map_or(String::new(), |v| format!(
            ", total variation <= {}",
            num(v, 0.0)
        ))
    );
    if let Some(opt) = optimum {
        wln!(
            out,
            "  closed-form optimum (one link): J* = {} ({})",
            num(opt.value, GaitScales::of_problem(crawler, g).length),
            opt.reason
        );
    }
    out
}
