//! The report of a crawler's certificate: (P)'s report on the crawler's instance read back in
//! the crawler's names; `J` of a process.

#[cfg(doc)]
use super::crawler_general::AsGeneral;
use super::crawler_general::{FaceId, Raw};
use super::general_conditions::GeneralNecessaryConditions;
use super::process::{Process, ProcessKind};
use super::records::*;
use super::verdict::significant_multipliers;

/// The certificate of the crawler process `pr`: (P)'s report `g` on its instance
/// ([`AsGeneral::certify`]: the same conditions, residuals, margin, normalisations and
/// verdict, in the crawler's units and words) with the multipliers `raw` it states (in the
/// crawler's units), read back in the crawler's names (`p`, `p + omega` per link, `dxi` per
/// block and side), with the one-link structure of theory §9.
pub(super) fn report(pr: &Process, g: GeneralNecessaryConditions, raw: Raw) -> NecessaryConditions {
    let discrete = matches!(pr.kind, ProcessKind::Discrete { .. });
    let mut c = g.named(move |g| MultiplierData {
        extension: if discrete {
            "piecewise_linear"
        } else {
            "piecewise_constant"
        }
        .into(),
        xi: face_multipliers(&raw, &g.times),
        times: g.times,
        psi: g.psi,
        p: raw.p,
        p_plus_omega: g.switching,
        u: g.u,
        omega: raw.omega,
    });
    c.format = CERTIFICATE_FORMAT.into();
    c.objective = process_objective(pr);
    // §4's structure is the instance's, whose C is the crawler's in `x~ = x / sqrt(k)`
    // (switches, arcs and the expected arc are invariant under that scaling).
    let sqrt_k = pr.crawler.stiffness()[0].sqrt();
    c.one_link = c.one_link.map(|o| OneLinkStructure {
        alpha: o.alpha * sqrt_k,
        beta: o.beta * sqrt_k,
        ..o
    });
    c
}

/// The face multipliers `dxi` per knot, block and side ([`significant_multipliers`]).
fn face_multipliers(raw: &Raw, times: &[f64]) -> Vec<FaceMultiplier> {
    significant_multipliers(&raw.active, &raw.xi, |j, FaceId { b, s }, value| {
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
