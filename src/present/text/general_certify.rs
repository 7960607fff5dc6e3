//! The text of a general P_m certificate ([`crate::certify::general`]): the crawler
//! certificate's layout ([`super::certificate`]), faces numbered from 1 as in the problem file.

use super::{list, max_abs, num, wln};
use crate::certify::GeneralNecessaryConditions;

/// The human form of [`crate::certify::certify_general`]: the same content as its JSON,
/// multipliers abridged (the first 64 steps and masses).
pub fn general_certificate(c: &GeneralNecessaryConditions) -> String {
    let mut out = String::new();
    let m = &c.multipliers;
    let adjoint = max_abs(m.switching.iter().flatten().chain(&m.omega)).max(1e-300);
    super::gait::conditions_head(&mut out, c.verdict, &c.reason, c.lambda, &c.normalisation);
    wln!(
        out,
        "  J = {}; non-degeneracy margin {}; omega = {}",
        num(c.objective, c.objective.abs().max(1e-300)),
        super::gait::margin_text(
            c.nondegeneracy_margin,
            c.nondegeneracy_resolution,
            c.margin_required
        ),
        list(&m.omega, adjoint)
    );
    if let Some(b) = &c.branch_lp {
        let scale = b.optimum.abs().max(b.process_objective.abs()).max(1e-300);
        wln!(
            out,
            "  {}: optimum {}, improvement over the process {:.3e}",
            b.describe("reactions"),
            num(b.optimum, scale),
            b.improvement
        );
    }
    super::condition_lines(&mut out, &c.conditions, 21);
    let rows = m.p.len();
    let show = rows.min(64);
    let us = max_abs(m.u.iter().flatten()).max(1e-300);
    let ps = max_abs(m.p.iter().flatten()).max(1e-300);
    wln!(
        out,
        "  multipliers per piece (a step of P_m or a phase){}:",
        if show < rows {
            format!(" (first {show} of {rows})")
        } else {
            String::new()
        }
    );
    for j in 0..show {
        wln!(
            out,
            "    t = {}  u = {}  p = {}  B^T p + omega = {}",
            num(m.times[j], m.times[rows]),
            list(&m.u[j], us),
            list(&m.p[j], ps),
            list(&m.switching[j], adjoint)
        );
    }
    let mass = max_abs(m.xi.iter().map(|x| &x.value));
    for x in m.xi.iter().take(64) {
        wln!(
            out,
            "    dxi at t = {} (knot {}): face {} mass {}",
            num(x.time, m.times[rows]),
            x.knot,
            x.face,
            num(x.value, mass)
        );
    }
    if let Some(o) = &c.one_link {
        let x_scale = o.alpha.abs().max(o.beta.abs());
        super::one_link_lines(
            &mut out,
            o,
            x_scale,
            m.times[rows],
            "(beta - alpha)/(|B| a)",
        );
    }
    out
}
