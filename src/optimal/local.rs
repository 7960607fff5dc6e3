//! The local method for P_m (theory §6) of a crawler, for grids far beyond the reach of the
//! global MILP (`2^m ~ 10^3` steps and more, several blocks): (P)'s active-set method on the
//! LPCC of P_m ([`crate::optimal::general::local`]) on the crawler's instance
//! ([`crate::model::crawler_as_general`]: `x~ = K^(-1/2) x`, a pair of faces per block), with
//! what a crawler adds: a start given as a continuous-time gait (its knots), sampled on the
//! grid ([`sample_increments`]) and tried at several time shifts ([`shift_knots`],
//! [`solve_discrete_local_shifted`]), and the answer in the crawler's terms.
//!
//! In the crawler's words, every complementarity condition of P_m is a three-way choice per
//! step `i` and block `b` (its *mode*): stick (`D^i_b = 0`, `F_b(x^{i+1})` anywhere in its
//! range), slip+ (`F_b(x^{i+1}) = mu_b^+`, `D^i_b >= 0`) or slip- (`F_b(x^{i+1}) = -mu_b^-`,
//! `D^i_b <= 0`). On the instance a block's modes are the branches of its pair of faces:
//! stick is both faces off, slip+ its forward face on, slip- its backward face on (both on at
//! once is impossible, `mu_b^+ + mu_b^- > 0`). (P)'s branch LP gives such a pair one signed
//! multiplier column (the block's displacement, up to its scale) and one value column (the
//! block's force), so it is the LP the crawler had of its own, with the modes as column bounds:
//! 10 columns and 5 rows a step for three blocks. It is re-solved from its previous basis after
//! each switch; the switches that pay by their reduced costs are made at once, and where none
//! pays each degenerate mode's neighbouring LP that can gain is solved and the first that
//! gains is taken ([`Finish`]: (P)'s test, going to the neighbours also after an LP without a
//! gain): `stationary` means, for a crawler as for (P), that no single switch gains. The
//! answer is a `local` certificate, never a global one.
//!
//! Many starts (the time shifts of [`solve_discrete_local_shifted`]) are screened by the
//! reduced costs alone ([`ReducedCosts`]: no LP beyond the pivots), and only the best is
//! finished under the neighbours' test ([`Finish`], which goes to the neighbours
//! after an LP without a gain, so that it never ends `stalled`), on its own LP from the basis
//! its screen ended on (`optimal::general::branch_lp`). Until
//! the finish, a crawler's `stationary` was the first-order test alone, and some answers ended
//! `stalled`. The finish has changed no `J` of the examples (three and four blocks at `m = 2`
//! to `10`, one link, five blocks), turned `stalled` into `stationary` on three blocks at
//! `m = 7` and `10` and on five at `m = 4`, and costs 1.03 (three blocks, `m = 8`) to 1.13
//! (three blocks, `m = 10`, where it ended `stalled` before) of the time of the screen alone
//! (1.05 on five blocks and 1.07 on four of varied friction at `m = 10`; medians of 5 paired
//! runs of `optimize FILE --method local --m M`). The finish then began on a model built
//! afresh from the best's controls, its first LP cold; going on from the screen's basis, it
//! takes 0.023 s in place of 0.42 s on five blocks at `m = 10` (6 LPs in all where there
//! were 8), and about as long on three (0.29 to 0.40 s, 67 LPs in all where there were 50,
//! the path through the neighbours another one), with the same `J` and status on three and
//! five blocks at `m = 4` to `10` and on four of varied friction at `m = 8`.
//!
//! The start's modes are read off its process as they always were: a block whose force is on
//! a friction bound slips, even at rest (its face held with a zero multiplier), so that the
//! first LP may already move it (the default for (P) too; holding only the faces with a
//! positive reaction, (P)'s default until it took these rules, from one link's small rise and
//! fall at `m = 2` the reduced costs of that first basis see no
//! paying switch, and the method would stop at its start's `J = 0.5`, not at 3).
//!
//! Until this method ran on (P)'s, the crawler had that LPCC as a copy of its own. Run on
//! (P)'s, `optimize --method local` (8 time shifts of the phase optimum) reaches the same `J`
//! at `m = 8` (2.5859375) and `m = 10` (2.595703125) on three blocks and at `m = 10` on four
//! blocks of varied friction (6.5751605), and more at `m = 6`: 2.5625, where the copy stopped
//! at 2.46875. It takes 1.04 of the copy's time at `m = 10`, 1.01 at `m = 8` and 0.96 on the
//! four blocks (medians of 7 paired runs; nearly all of it HiGHS's).
//!
//! Every answer is re-verified by the crawler's own simulator: the returned increments are
//! played by catching-up from the returned initial state until the periodic regime, and the
//! verified displacement is the one reported.
//!
//! [`Finish`]: crate::optimal::general::Pivoting::Finish
//! [`ReducedCosts`]: crate::optimal::general::Pivoting::ReducedCosts

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::general::geometry::analyze_polyhedron;
use crate::optimal::general::{solve_general_local_best, MultiStart};
use crate::optimal::milp::{check_verified, replay_grid};
use crate::optimal::units::{scale_all, scale_rows, Units};
use crate::optimal::{Cost, GaitProblem};
use serde::Serialize;

/// Largest `m` of the local method (`2^m` steps).
pub const MAX_LOCAL_M: u32 = 14;

pub use super::active_set::LocalStop;

/// A local solution of P_m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LocalSolution {
    /// `m`.
    pub m: u32,
    /// `h = T / 2^m`.
    pub step: f64,
    /// `J` of the start gait on this grid (catching-up).
    pub start_objective: f64,
    /// The last LP's objective `J`.
    pub lp_objective: f64,
    /// Displacement per period, re-verified by simulation.
    pub verified_displacement: f64,
    /// `h sum f2(u)` (zero: the local method handles `f2 = 0`).
    pub actuation_cost: f64,
    /// LP solves.
    pub lp_solves: usize,
    /// Modes switched in all.
    pub switches: usize,
    /// Why it stopped.
    pub stop: LocalStop,
    /// Initial state on the orbit.
    pub initial_state: Vec<f64>,
    /// States `x^i`, `i = 0..=2^m`.
    pub states: Vec<Vec<f64>>,
    /// Controls `u^i`.
    pub controls: Vec<Vec<f64>>,
    /// Block displacements per step.
    pub block_displacements: Vec<Vec<f64>>,
}

impl LocalSolution {
    /// `J` = verified displacement minus actuation cost.
    pub fn objective(&self) -> f64 {
        self.verified_displacement - self.actuation_cost
    }
}

/// Grid increments `U^i = K (L(t_{i+1}) - L(t_i))` of a piecewise-linear periodic actuation
/// given by knots `times` (from 0, the last = `period`) and `lengths` (last row = first),
/// sampled on `steps` uniform steps; clamped to the rate bounds (rounding only) and centred.
pub fn sample_increments(
    times: &[f64],
    lengths: &[Vec<f64>],
    stiffness: &[f64],
    rate_bound: &[f64],
    period: f64,
    steps: usize,
) -> Vec<Vec<f64>> {
    let h = period / steps as f64;
    let n = stiffness.len();
    let grid: Vec<Vec<f64>> = (0..=steps)
        .map(|i| length_at(times, lengths, i as f64 * h))
        .collect();
    let mut incs: Vec<Vec<f64>> = grid
        .windows(2)
        .map(|w| {
            (0..n)
                .map(|l| {
                    (stiffness[l] * (w[1][l] - w[0][l]))
                        .clamp(-rate_bound[l] * h, rate_bound[l] * h)
                })
                .collect()
        })
        .collect();
    for l in 0..n {
        let mean = incs.iter().map(|u| u[l]).sum::<f64>() / steps as f64;
        for u in &mut incs {
            u[l] = (u[l] - mean).clamp(-rate_bound[l] * h, rate_bound[l] * h);
        }
    }
    incs
}

/// The actuator lengths at time `t` of the piecewise-linear actuation with knots `times` and
/// `lengths` (the last row past the last knot).
fn length_at(times: &[f64], lengths: &[Vec<f64>], t: f64) -> Vec<f64> {
    let j = match times.iter().rposition(|&s| s <= t) {
        Some(j) if j + 1 < times.len() => j,
        Some(_) => return lengths[lengths.len() - 1].clone(),
        None => 0,
    };
    let span = times[j + 1] - times[j];
    let w = if span > 0.0 {
        (t - times[j]) / span
    } else {
        0.0
    };
    lengths[j]
        .iter()
        .zip(&lengths[j + 1])
        .map(|(a, b)| a + w * (b - a))
        .collect()
}

/// Refuses what the local method cannot solve: `m` outside `1..=MAX_LOCAL_M`, or a quadratic
/// cost (the method handles `f2 = 0` only). Cheap, so callers can check before computing a
/// start.
pub fn check_local(problem: &GaitProblem, m: u32) -> Result<()> {
    if !(1..=MAX_LOCAL_M).contains(&m) {
        return Err(Error::invalid(
            "m",
            m,
            format!("must be in 1..={MAX_LOCAL_M} for the local method"),
        ));
    }
    if problem.cost != Cost::None {
        return Err(Error::invalid(
            "gait.cost",
            "quadratic",
            "the local method handles f2 = 0 only; use --method discrete or phase",
        ));
    }
    Ok(())
}

/// A start gait given by its knots: times and actuator lengths.
type Knots = (Vec<f64>, Vec<Vec<f64>>);

/// Solves P_m locally from a start gait given by its knots (module docs).
pub fn solve_discrete_local(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start_times: &[f64],
    start_lengths: &[Vec<f64>],
) -> Result<LocalSolution> {
    let start = (start_times.to_vec(), start_lengths.to_vec());
    let (s, _) = solve_by(crawler, problem, m, &[start])?;
    Ok(s)
}

/// [`solve_discrete_local`] from each of `starts` (one by (P)'s rules, several screened and
/// the best finished: [`MultiStart::for_starts`]), keeping the best; also returns the index of
/// its start.
fn solve_by(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    starts: &[Knots],
) -> Result<(LocalSolution, usize)> {
    crawler.require_unique()?;
    problem.check_scales(crawler)?;
    check_local(problem, m)?;
    crate::optimal::check_size(crawler, 1 << m, "m", m)?;
    // Solved in the optimisers' internal units ([`Units`]), answered in the user's.
    let units = Units::of(crawler, problem);
    let (c, p) = (units.crawler(crawler)?, units.problem(problem));
    let starts: Vec<Knots> = starts
        .iter()
        .map(|(times, lengths)| units.knots_in(times, lengths))
        .collect();
    let (s, k) = crate::progress::with_objective_scale(units.objective_scale(), || {
        solve_local_in(&c, &p, m, &starts)
    })?;
    Ok((units.local(&s), k))
}

/// [`solve_by`] in internal units, arguments checked: (P)'s local method on the crawler's
/// instance from each start sampled on the grid, the best answer replayed by the crawler's
/// simulator (module docs).
fn solve_local_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    starts: &[Knots],
) -> Result<(LocalSolution, usize)> {
    let big_m = 1usize << m;
    let t = problem.period;
    let h = t / big_m as f64;
    let what = format!("P_{m} (local)");
    let inst = problem.instance(crawler)?;
    let geometry = analyze_polyhedron(&inst.problem.c)?;
    let grids: Vec<Vec<Vec<f64>>> = starts
        .iter()
        .map(|(times, lengths)| {
            sample_increments(
                times,
                lengths,
                crawler.stiffness(),
                &problem.rate_bound,
                t,
                big_m,
            )
            .iter()
            .map(|u| u.iter().map(|v| v / h).collect())
            .collect()
        })
        .collect();
    let plan = MultiStart::for_starts(grids.len());
    let best = solve_general_local_best(&inst.problem, &geometry, m, &grids, plan, &mut |_| {})?;
    let s = best.solution;
    let incs: Vec<Vec<f64>> = s
        .path
        .u
        .iter()
        .map(|u| u.iter().map(|v| v * h).collect())
        .collect();
    let x0 = inst.to_crawler(&s.path.x[0]);
    let g = replay_grid(crawler, t, &incs, &x0, &what)?;
    check_verified(
        &what,
        s.lp_objective,
        g.verified,
        problem.length_scale(crawler),
    )?;
    let solution = LocalSolution {
        m,
        step: h,
        start_objective: s.start_objective,
        lp_objective: s.lp_objective,
        verified_displacement: g.verified,
        actuation_cost: 0.0,
        lp_solves: s.lp_solves,
        switches: s.switches,
        stop: s.stop,
        initial_state: g.initial_state,
        block_displacements: g.block_displacements,
        states: g.states,
        controls: g.controls,
    };
    Ok((solution, best.best_start))
}

/// The knots of a periodic piecewise-linear actuation shifted in time by `shift`: the gait
/// `L(s + shift)`, with knots at the shifted old knots and at `0` and `period` (the last row
/// equal to the first). The same continuous-time gait, but sampled on a grid it gives another
/// discrete gait.
pub fn shift_knots(
    times: &[f64],
    lengths: &[Vec<f64>],
    shift: f64,
    period: f64,
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let mut knots: Vec<f64> = times
        .iter()
        .map(|&x| (x - shift).rem_euclid(period))
        .chain([0.0, period])
        .collect();
    knots.sort_by(f64::total_cmp);
    knots.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * period);
    let last = knots.len() - 1;
    knots[last] = period;
    let mut rows: Vec<Vec<f64>> = knots
        .iter()
        .map(|&s| length_at(times, lengths, (s + shift).rem_euclid(period)))
        .collect();
    rows[last] = rows[0].clone();
    (knots, rows)
}

/// [`solve_discrete_local`] from `shifts` time shifts of the start (`j T / shifts`, `j =
/// 0..shifts`, see [`shift_knots`]), keeping the best answer (the first of equals), within the
/// job's deadline ([`crate::progress::within`]) in all: the local search ends where its start
/// leads, and on a grid the phase at which a continuous-time start is sampled decides which
/// discrete gait it becomes (three blocks of `examples/three_blocks_gait.toml`, 64 steps, 2.5625
/// from the phase optimum as it is; before this method ran on (P)'s, 2.4688 from it and from the
/// best of 8 shifts, 2.5625 from the best of 32). Also returns the shift of the best. The
/// shifts are screened and the best finished (module docs); one shift is
/// [`solve_discrete_local`] itself.
pub fn solve_discrete_local_shifted(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start_times: &[f64],
    start_lengths: &[Vec<f64>],
    shifts: usize,
) -> Result<(LocalSolution, f64)> {
    crate::optimal::check_shifts(shifts)?;
    if shifts == 1 {
        let s = solve_discrete_local(crawler, problem, m, start_times, start_lengths)?;
        return Ok((s, 0.0));
    }
    let t = problem.period;
    let shift = |j: usize| t * j as f64 / shifts as f64;
    let starts: Vec<Knots> = (0..shifts)
        .map(|j| shift_knots(start_times, start_lengths, shift(j), t))
        .collect();
    let (s, k) = solve_by(crawler, problem, m, &starts)?;
    Ok((s, shift(k)))
}

/// A local P_m solution's conversion between unit systems ([`Units`]): here, beside the
/// solution, so that the unit system needs not know it.
impl Units {
    /// A local P_m solution from internal units to the user's.
    pub fn local(&self, s: &LocalSolution) -> LocalSolution {
        let (f, t, l) = (self.force, self.time, self.length);
        LocalSolution {
            m: s.m,
            step: s.step * t,
            start_objective: s.start_objective * l,
            lp_objective: s.lp_objective * l,
            verified_displacement: s.verified_displacement * l,
            actuation_cost: s.actuation_cost * l,
            lp_solves: s.lp_solves,
            switches: s.switches,
            stop: s.stop,
            initial_state: scale_all(&s.initial_state, f),
            states: scale_rows(&s.states, f),
            controls: scale_rows(&s.controls, f / t),
            block_displacements: scale_rows(&s.block_displacements, l),
        }
    }
}
