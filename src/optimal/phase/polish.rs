//! Polishing a phase gait of a quadratic cost on its own sequence of slip modes.
//!
//! The phase MILP carries `f2` by an outer approximation (tangent cuts of the perspective
//! `tau f2(U / tau) = (c/2) |U|^2 / tau`, refined until the incumbent's true objective meets the
//! bound to [`OA_TOL`](crate::optimal::milp::OA_TOL)), so a rate off the bounds is only as
//! accurate as the cuts (about 1e-4 on the one-link example with `c = 0.6`), and the necessary
//! conditions fail at that size although the gait is the MILP's optimum to its gap (the same
//! defect P_m's polish, [`crate::optimal::polish`], removes).
//!
//! With the slip mode of every piece fixed, the phase problem is convex in the durations, the
//! increments, the states and the block displacements, and every feasible point is an exact
//! gait. It is (P)'s phase polish on the crawler's instance
//! ([`crate::model::crawler_as_general`], `x~ = K^(-1/2) x`): the slip modes are the held faces
//! (block `b` slipping forward holds face `2b + 1`, backward `2b + 2`, 1-based), the block
//! displacements the integrated reactions over the row norms (`D_b = (L_(b+) - L_(b-)) / s_b`,
//! `s_b = sqrt(k_(b-1) + k_b)`), and the phase MILP's block speed bound `|D| <= V tau` the
//! reactions' rate bound `s_b V`. The MILP's answer is feasible for it, so the optimum is no
//! worse; pieces that shrink to nothing are dropped, and the caller replays the result with the
//! exact simulator and keeps it only when the replay agrees and `J` is no worse.

use super::decode::RawGait;
use crate::model::{crawler_row_norms, Crawler, CrawlerInstance};
use crate::optimal::general::{polish_phases_within, MilpPhases};
use crate::optimal::milp::block_speed_bound;
use crate::optimal::{Cost, GaitProblem};

/// Pieces at most this fraction of the period long are dropped from the polished gait.
const EMPTY_PIECE: f64 = 1e-12;

/// The gait of the best durations, increments and states on `raw`'s sequence of slip modes
/// (module docs); `None` without a quadratic cost or when Clarabel finds no solution.
pub(super) fn polish_phases(
    crawler: &Crawler,
    problem: &GaitProblem,
    raw: &RawGait,
) -> Option<RawGait> {
    if problem.cost == Cost::None {
        return None;
    }
    if raw.durations.is_empty() {
        return None;
    }
    let inst = problem.instance(crawler).ok()?;
    let s_b = crawler_row_norms(crawler.stiffness());
    let v = block_speed_bound(crawler, problem);
    let rate_bounds: Vec<f64> = s_b.iter().flat_map(|&s| [s * v, s * v]).collect();
    let held: Vec<Vec<usize>> = raw
        .modes
        .iter()
        .map(|modes| {
            modes
                .iter()
                .enumerate()
                .filter(|(_, &s)| s != 0)
                .map(|(b, &s)| 2 * b + if s > 0 { 1 } else { 2 })
                .collect()
        })
        .collect();
    let phases = polish_phases_within(
        &inst.problem,
        &rate_bounds,
        &raw.durations,
        &held,
        EMPTY_PIECE,
    )?;
    read_back(&phases, &inst, &s_b)
}

/// The polished phases of the instance as the crawler's gait: states `x = K^(1/2) x~` at the
/// piece starts (the first repeated at the end), the same increments, the block displacements
/// `D_b = (L_(b+) - L_(b-)) / s_b` and the modes of the faces held; `None` when no piece is
/// left.
fn read_back(phases: &MilpPhases, inst: &CrawlerInstance, s_b: &[f64]) -> Option<RawGait> {
    let mut out = RawGait::default();
    for (j, &d) in phases.durations.iter().enumerate() {
        out.durations.push(d);
        out.increments.push(phases.increments[j].clone());
        out.states.push(inst.to_crawler(&phases.states[j]));
        let l = &phases.integrated[j];
        out.block_displacements.push(
            s_b.iter()
                .enumerate()
                .map(|(b, s)| (l[2 * b] - l[2 * b + 1]) / s)
                .collect(),
        );
        let mut modes = vec![0i8; s_b.len()];
        for &f in &phases.held[j] {
            modes[(f - 1) / 2] = if (f - 1) % 2 == 0 { 1 } else { -1 };
        }
        out.modes.push(modes);
    }
    let x0 = out.states.first()?.clone();
    out.states.push(x0);
    Some(out)
}
