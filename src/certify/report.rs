//! The report of a crawler's certificate: (P)'s report on the crawler's instance read back in
//! the crawler's names; `J` of a process and the one-link structure (theory §9).

use super::crawler_general::AsGeneral;
use super::kkt::{FaceId, Raw, Structure};
use super::process::{Process, ProcessKind};
use super::records::*;
use super::verdict::significant_multipliers;

/// The certificate of the crawler process `pr` with the multipliers `raw` (in the crawler's
/// units): (P)'s report on its instance ([`AsGeneral::report`]: the same conditions, residuals,
/// margin, normalisations and verdict, in the crawler's units and words), read back in the
/// crawler's names (`p`, `p + omega` per link, `dxi` per block and side), with the one-link
/// structure of theory §9.
pub(super) fn report(
    pr: &Process,
    st: &Structure,
    general: &AsGeneral,
    raw: Raw,
    scaled_by: String,
    opts: &CertifyOptions,
) -> NecessaryConditions {
    let g = general.report(&raw, scaled_by, opts);
    let discrete = matches!(pr.kind, ProcessKind::Discrete { .. });
    let times = g.multipliers.times;
    NecessaryConditions {
        format: CERTIFICATE_FORMAT.into(),
        version: CERTIFICATE_VERSION,
        method: g.method,
        m: g.m,
        verdict: g.verdict,
        reason: g.reason,
        lambda: g.lambda,
        objective: process_objective(pr),
        nondegeneracy_margin: g.nondegeneracy_margin,
        nondegeneracy_resolution: g.nondegeneracy_resolution,
        margin_required: g.margin_required,
        normalisation: g.normalisation,
        conditions: g.conditions,
        multipliers: MultiplierData {
            extension: if discrete {
                "piecewise_linear"
            } else {
                "piecewise_constant"
            }
            .into(),
            xi: face_multipliers(st, &raw, &times),
            times,
            psi: g.multipliers.psi,
            p: raw.p,
            p_plus_omega: g.multipliers.switching,
            u: g.multipliers.u,
            omega: raw.omega,
        },
        one_link: one_link_structure(pr, opts.structure_tol),
        branch_lp: None,
    }
}

/// The face multipliers `dxi` per knot, block and side ([`significant_multipliers`]).
fn face_multipliers(st: &Structure, raw: &Raw, times: &[f64]) -> Vec<FaceMultiplier> {
    significant_multipliers(&st.active, &raw.xi, |j, FaceId { b, s }, value| {
        FaceMultiplier {
            knot: j,
            time: times[j],
            block: b + 1,
            side: if s > 0 { "+" } else { "-" }.into(),
            value,
        }
    })
}

/// `J` of a process: displacement per period minus `int f2(u) dt`.
pub fn process_objective(pr: &Process) -> f64 {
    let nb = pr.crawler.blocks() as f64;
    let displacement: f64 = pr.block_displacements.iter().flatten().sum::<f64>() / nb;
    let cost: f64 = pr
        .controls
        .iter()
        .zip(&pr.durations)
        .map(|(u, d)| d * pr.problem.cost.eval(u))
        .sum();
    displacement - cost
}

/// §4's structure of a one-link process: switches of the control, where they happen, interior
/// arcs (`x` linear between knots). `None` for more than one link.
pub fn one_link_structure(pr: &Process, tol: f64) -> Option<OneLinkStructure> {
    if pr.crawler.links() != 1 {
        return None;
    }
    let r = pr.crawler.link_force_ranges()[0];
    let (alpha, beta) = (r[0], r[1]);
    let a = pr.problem.rate_bound[0];
    let etol = tol * (beta - alpha);
    let times = pr.times();
    let np = pr.durations.len();
    let x: Vec<f64> = pr.states.iter().map(|s| s[0]).collect();
    let at_end = |v: f64| v <= alpha + etol || v >= beta - etol;
    let sgn = |u: f64| {
        if u > tol * a {
            1
        } else if u < -tol * a {
            -1
        } else {
            0
        }
    };
    let mut switch_times = Vec::new();
    let mut switch_at_end = Vec::new();
    for j in 0..np {
        let prev = (j + np - 1) % np;
        let (s0, s1) = (sgn(pr.controls[prev][0]), sgn(pr.controls[j][0]));
        if s0 != s1 {
            switch_times.push(times[j]);
            switch_at_end.push(at_end(x[j]));
        }
    }
    // Interior arcs, x linear between knots, walking from a knot at an end of C.
    let mut arcs: Vec<f64> = Vec::new();
    match (0..np).find(|&j| at_end(x[j])) {
        None => arcs.push(pr.problem.period),
        Some(s0) => {
            let mut cur = 0.0;
            for step in 0..np {
                let j = (s0 + step) % np;
                let (x0, x1, tau) = (x[j], x[j + 1], pr.durations[j]);
                match (at_end(x0), at_end(x1)) {
                    (true, true) if (x1 - x0).abs() <= etol => {}
                    (true, true) => arcs.push(tau),
                    (_, false) => cur += tau,
                    (false, true) => {
                        arcs.push(cur + tau);
                        cur = 0.0;
                    }
                }
            }
        }
    }
    Some(OneLinkStructure {
        alpha,
        beta,
        switch_times,
        switch_at_end,
        interior_arcs: arcs,
        expected_arc: (beta - alpha) / a,
        bang_bang: pr
            .controls
            .iter()
            .all(|u| (u[0].abs() - a).abs() <= tol * a),
    })
}
