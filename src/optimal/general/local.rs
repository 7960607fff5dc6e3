//! The paper's P_m (§6, theory §11) for the general problem (P), locally: the active-set method on
//! its LPCC (`crate::optimal::active_set`), for grids beyond the reach of the global MILP
//! ([`super::discrete`]). A crawler's local method is this one on the crawler's instance.
//!
//! P_m's complementarity is, per step `i` and face `j`, `0 <= mu^i_j ⊥ s^i_j >= 0` with the
//! slack `s^i_j = c_j - <x*_j, x^(i+1)>` of the catching-up step's KKT system (the module docs
//! of [`super::discrete`]). A *branch* picks one side: on face (`s = 0`, `mu >= 0`) or off it
//! (`mu = 0`, `s >= 0`). With every branch fixed P_m is the LP of [`super::discrete::Form::
//! Branches`], where the branches are column bounds, and, the multipliers being unique
//! (independent active normals, checked), every feasible point of it is a catching-up process.
//!
//! The LPs are solved on the problem in units of order one (`optimal::general::units`), as
//! P_m's MILP is, and their answer converted back and replayed on the problem itself. The
//! branches are the same in any units, so exact twins (the same problem in other units) solve
//! the same LPs: the three-block instance with its controls a million times larger
//! (`B = 1e-6 I`), its opposite faces paired (below) and solved in its own units, ended with
//! HiGHS's status `unknown` at `m = 10`; in units of order one it gives the `J` of scale 1.
//!
//! The LP has a multiplier and a slack column for each face, except that two opposite faces (a
//! slab, such as a crawler block's two friction bounds) share one signed multiplier column
//! `nu = mu_j - mu_k`, its cost switched with the branch, and one value column `<x*_j, x>`
//! between their offsets (`Form::Branches` in `optimal::general::discrete_rows`): for the
//! three-block crawler's instance 10 columns and 5 rows a step instead of 16 and 8, the LP the
//! crawler's own local method had. With the units above, `optimize general_three_blocks.toml
//! --method local --m 10` takes 0.82 of the time it took with a multiplier and a slack column
//! per face, and the signed column 0.92 of that again (medians of 5 paired runs; 0.96 at
//! `m = 8`), with the same `J`.
//!
//! Pivoting (maximising `J`): at the LP optimum a pair is degenerate when `mu = s = 0`; its
//! other branch keeps the point feasible. An on-face pair with `mu = 0` whose slack has a
//! positive reduced cost (its column's, signed: leaving the face pays) goes off; an off-face
//! pair with `s = 0` whose multiplier has a positive reduced cost (pushing on the face pays;
//! a pair's signed column's reduced cost, signed, plus the face's weight, its cost while both
//! faces are off being 0) goes on. All such switches are made at once, as for crawlers. Where
//! none pays, the reduced costs of a
//! degenerate LP being those of one of its optimal bases, each degenerate pair's neighbouring
//! LP (that pair switched) is solved from the current basis and the first that gains is
//! taken; when none gains the point is stationary for every single switch (status
//! `stationary`; [`Pivoting::ReducedCosts`] stops before the neighbours, a screen of many
//! starts whose best is then finished: [`MultiStart::for_starts`], the one search of several
//! starts for (P)'s rotated starts and a crawler's shifted ones alike). That is a
//! local solution, not a global one: on the one-link problem with 16 steps, the square wave of
//! amplitude 0.5 ends at J = 1.75 < J* = 3 (tests/general_local.rs), on a plateau of J that
//! only two switches at once leave.
//!
//! Only the neighbours that can gain are solved. A switch loosens one column of its pair
//! (the multiplier going on, the slack or value column going off) and fixes the other, and
//! for two opposite faces it changes the cost of their signed multiplier column. Its
//! neighbouring LP holds the current point, and the current basis stays optimal for it
//! unless the loosened column is nonbasic with a rate that pays (the test above) or the
//! column whose cost changes is basic (the duals move). A basic column's reduced cost is 0,
//! so a neighbour is solved only where the switch's rate pays or its pair's signed column has
//! a reduced cost within the tolerance; the others cannot gain. A neighbour that does not
//! gain may still leave HiGHS at another optimal basis, so a path can go on differently
//! without them, but on `general_three_blocks.toml` every output is the same but the LP
//! counts (`--method local`, `m = 5, 6, 8, 10`): at `m = 10` the best start's LPs fall from
//! 118 to 6 and the command takes 0.65 of the time (medians of 5 paired runs). With every
//! degenerate pair solved, the unit tests find no skipped switch that gains, on random
//! polygons and crawlers' instances.
//!
//! The start is a control on the grid (one row per step), simulated by catching-up to its
//! periodic regime (or over the horizon of a Cauchy problem); the branches are read off that
//! process: on face where the projection's multiplier is positive (with
//! [`StartFaces::Touched`] also where the process touches the face at rest).
//! [`default_starts`] gives square waves along each control axis, at several time shifts
//! ([`rotated`]); the job (`crawlopt::api::optimize_general_local`) starts from the phase
//! optimum instead where `A = 0`. Every answer is re-verified by replaying its controls
//! through the general simulator ([`super::discrete`]'s replay).

use super::branch_lp::{BranchLp, Keepsake};
pub use super::branch_lp::{GeneralLocal, Pivoting};
use super::discrete::{check_sets, run_on_grid};
use super::geometry::Geometry;
use crate::error::{Error, Result};
use crate::integrate::{ControlInput, GeneralSimOptions, InputKind};
use crate::model::general::{Boundary, ControlSet, GeneralCost, GeneralProblem};
use crate::optimal::active_set::LocalStop;

/// Largest `m` (`2^m` steps) of the general local method.
pub const MAX_GENERAL_LOCAL_M: u32 = 14;

/// Refuses what the local method cannot solve (cheap, before any start is simulated): `m`
/// outside `1..=MAX_GENERAL_LOCAL_M`, a quadratic cost (the branch problems are LPs), and what
/// `check_sets` refuses.
pub fn check_general_local(p: &GeneralProblem, g: &Geometry, m: u32) -> Result<()> {
    if !(1..=MAX_GENERAL_LOCAL_M).contains(&m) {
        return Err(Error::invalid(
            "m",
            m,
            format!("must be in 1..={MAX_GENERAL_LOCAL_M} for the local method"),
        ));
    }
    if p.cost != GeneralCost::None {
        return Err(Error::invalid(
            "objective.cost",
            "a quadratic cost",
            "the local method handles f2 = none only; use the discrete (global) method",
        ));
    }
    super::discrete::check_explicit_step(p, m)?;
    super::discrete::check_solver_range(p, p.period / (1u64 << m) as f64, None)?;
    check_sets(p, g, "P_m's local method")
}

/// The largest `t >= 0` with `t d` in U (U contains 0).
fn reach(u: &ControlSet, d: &[f64]) -> f64 {
    let ratio = |a: f64, c: f64| if a > 0.0 { c / a } else { f64::INFINITY };
    match u {
        ControlSet::Box { lower, upper } => d
            .iter()
            .zip(lower.iter().zip(upper))
            .map(|(&d, (&lo, &hi))| ratio(d, hi).min(ratio(-d, -lo)))
            .fold(f64::INFINITY, f64::min),
        ControlSet::Polytope(q) => q
            .normals
            .iter()
            .zip(&q.offsets)
            .map(|(n, &c)| ratio(crate::model::general::dot(n, d), c))
            .fold(f64::INFINITY, f64::min),
    }
}

/// The default starts on `2^m` steps: for each control component `k`, the square wave `+a e_k`
/// on the first half period and `-a e_k` on the second (`a` the largest with both in U, so the
/// mean is zero), advanced by `j M / shifts` steps ([`rotated`]), `j = 0..shifts` (on a grid,
/// where a wave switches decides which process it makes). Components along which U holds no
/// segment through 0 are skipped.
pub fn default_starts(p: &GeneralProblem, m: u32, shifts: usize) -> Vec<Vec<Vec<f64>>> {
    let mm = 1usize << m;
    let nu = p.controls();
    let mut starts = Vec::new();
    for k in 0..nu {
        let mut e = vec![0.0; nu];
        e[k] = 1.0;
        let up = reach(&p.control, &e);
        e[k] = -1.0;
        let down = reach(&p.control, &e);
        let a = up.min(down);
        if !(a.is_finite() && a > 0.0) {
            continue;
        }
        let wave: Vec<Vec<f64>> = (0..mm)
            .map(|i| {
                let mut u = vec![0.0; nu];
                u[k] = if i < mm / 2 { a } else { -a };
                u
            })
            .collect();
        starts.extend(rotated(&wave, shifts));
    }
    starts
}

/// Controls on a grid of `M` steps advanced by `j M / shifts` steps (the control `u(t + j h
/// M / shifts)`, rotated to the left), `j = 0..shifts` (equal rotations once), in the order of
/// a crawler's time shifts ([`crate::optimal::shift_knots`], `j T / shifts`): where a start
/// switches on the grid decides which process it makes, so a local search tries it at several
/// time shifts.
pub fn rotated(grid: &[Vec<f64>], shifts: usize) -> Vec<Vec<Vec<f64>>> {
    rotations(grid.len(), shifts)
        .into_iter()
        .map(|r| {
            let mut w = grid.to_vec();
            w.rotate_left(r);
            w
        })
        .collect()
}

/// The rotations of [`rotated`] on a grid of `steps` steps, in its order: `j steps / shifts`
/// steps to the left (the control advanced by as many steps), `j = 0..shifts`, equal ones once.
pub fn rotations(steps: usize, shifts: usize) -> Vec<usize> {
    let mut r: Vec<usize> = (0..shifts).map(|j| j * steps / shifts).collect();
    r.dedup();
    r
}

/// The time shift of the `index`-th rotation of [`rotated`] on a grid of `steps` steps over
/// `period`, in a crawler's convention ([`crate::optimal::shift_knots`]: the start advanced,
/// `u(t + shift)`): a rotation of `r` steps to the left advances the control by `r h`.
pub fn rotation_shift(steps: usize, shifts: usize, index: usize, period: f64) -> f64 {
    rotations(steps, shifts)[index] as f64 * period / steps as f64
}

/// A phase gait's controls (`controls[j]` for `durations[j]`) as a start on `2^m` steps: the
/// mean over each step, moved to an exact zero mean within U where the problem asks it
/// (`to_zero_mean`; the gait's mean is zero only to its solver's tolerance, which on a short
/// period is more than a start's `1e-9`). Refused (field `start`) where the controls are not a
/// piecewise-constant control in U.
pub fn phase_grid(
    p: &GeneralProblem,
    durations: &[f64],
    controls: &[Vec<f64>],
    m: u32,
) -> Result<Vec<Vec<f64>>> {
    // The pieces' start times, their durations scaled to sum to `T` exactly; a piece that
    // starts no later than the one before, or at `T`, lasts less than the rounding of the sum
    // and is left out (a phase gait of a random polytope with `T = 1e-3` had its last phase
    // start at `T + 3.4e-13`, and the start was refused).
    let total: f64 = durations.iter().sum();
    let (mut times, mut kept) = (Vec::new(), Vec::new());
    let mut at = 0.0;
    for (d, u) in durations.iter().zip(controls) {
        let t = at * (p.period / total);
        if times.last().is_none_or(|&last| t > last && t < p.period) {
            times.push(if times.is_empty() { 0.0 } else { t });
            kept.push(u.clone());
        }
        at += d;
    }
    let input = ControlInput::new(
        InputKind::PiecewiseConstant,
        p.period,
        times,
        kept,
        &p.control,
        "start",
    )?;
    let mut grid = grid_controls(&input, m);
    if p.zero_mean {
        to_zero_mean(&p.control, &mut grid);
    }
    Ok(grid)
}

/// Controls on equal steps moved to an exact zero mean while staying in U. A shift by the mean
/// (`milp::shift_to_zero_mean`) moved a control at its bound out of U: by `1.6e-9` on a
/// random 3-D polytope with `T = 1e-3`, and the local method refused that start. Here each
/// control becomes `(1 - theta) u_i + theta c`, with `c` the point at distance `rho` from 0
/// opposite the mean `m`, where the ball of radius `rho` about 0 lies in U, and `theta = |m|
/// / (rho + |m|)`: the new mean is `(1 - theta) m + theta c = 0`, and each control, a convex
/// combination of two points of U, stays in it. Where 0 is not inside U (no such ball), the
/// shift.
fn to_zero_mean(u: &ControlSet, grid: &mut [Vec<f64>]) {
    // The distance from 0 to U's nearest row (unit rows: a box's `upper_l` and `-lower_l`).
    let rho = crate::optimal::process::control_rows(u)
        .iter()
        .fold(f64::INFINITY, |r, (_, h)| r.min(*h));
    let steps = grid.len() as f64;
    let mut mean = vec![0.0; grid.first().map_or(0, Vec::len)];
    for row in grid.iter() {
        for (m, v) in mean.iter_mut().zip(row) {
            *m += v / steps;
        }
    }
    let norm = mean.iter().map(|v| v * v).sum::<f64>().sqrt();
    if norm == 0.0 {
        return;
    }
    if !(rho > 0.0 && rho.is_finite()) {
        crate::optimal::milp::shift_to_zero_mean(grid);
        return;
    }
    let theta = norm / (rho + norm);
    for row in grid.iter_mut() {
        for (v, m) in row.iter_mut().zip(&mean) {
            *v = (1.0 - theta) * *v - theta * rho * m / norm;
        }
    }
}

/// The controls of `input` on `2^m` steps: the mean over each step.
pub fn grid_controls(input: &ControlInput, m: u32) -> Vec<Vec<f64>> {
    input.step_means(1usize << m)
}

/// Which faces the start's branches hold (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StartFaces {
    /// The faces with a positive reaction in the start's process.
    Reacting,
    /// Also every face the start's process touches at rest (to `1e-9` of C's scale), with a
    /// zero multiplier, so that the first LP can already push on it: without that, one link's
    /// small rise and fall at `m = 2` stops at its start's `J = 0.5`, the reduced costs of the
    /// first basis seeing no paying switch (`tests/local.rs`; with it, 3, the optimum). The
    /// default, for (P) and a crawler alike.
    #[default]
    Touched,
}

/// How the local method runs: its pivoting test and its start's faces (each type's docs).
/// The default, for (P) and for a crawler (whose local method is (P)'s on its instance), is
/// [`Pivoting::Finish`] from [`StartFaces::Touched`]: the start holds the faces its process
/// touches, and `stationary` means that no single switch gains (never `stalled`). Until
/// both kinds took these rules, (P)'s default was [`Pivoting::Neighbours`] from
/// [`StartFaces::Reacting`], a crawler's these: on the three-block crawler and its general
/// form at `m = 6` the crawler found 2.5625 and (P) 2.46875 from the same start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LocalRules {
    /// The switches tested before the method stops.
    pub pivoting: Pivoting,
    /// The faces the start's branches hold.
    pub start: StartFaces,
}

impl LocalRules {
    /// A screen of many starts: reduced costs only from the faces the start touches (see
    /// [`MultiStart::for_starts`]).
    pub const SCREEN: LocalRules = LocalRules {
        pivoting: Pivoting::ReducedCosts,
        start: StartFaces::Touched,
    };
}

/// How a search from several starts runs: each start by `rules`, then, with `finish`, the
/// best continued under that pivoting from the basis it ended on (`super::branch_lp`): a
/// screen's best, finished ([`MultiStart::for_starts`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MultiStart {
    /// The rules of every start.
    pub rules: LocalRules,
    /// The pivoting of the best start's finish, if any.
    pub finish: Option<Pivoting>,
}

impl MultiStart {
    /// The search of `n` starts, for (P) and a crawler alike: one start by the default rules
    /// ([`LocalRules`]); several screened by the reduced costs alone ([`LocalRules::SCREEN`],
    /// no LP beyond the pivots) and the best finished under [`Pivoting::Finish`] from the
    /// basis its screen ended on, in its LP rebuilt at that basis (a crawler's time shifts,
    /// (P)'s rotated starts).
    pub fn for_starts(n: usize) -> MultiStart {
        if n <= 1 {
            MultiStart::default()
        } else {
            MultiStart {
                rules: LocalRules::SCREEN,
                finish: Some(Pivoting::Finish),
            }
        }
    }
}

/// The answer of [`solve_general_local_best`]: the best verified answer, the index of its
/// start and how many starts were solved.
#[derive(Debug, Clone, PartialEq)]
pub struct BestLocal {
    /// The best answer (finished where the search asks it).
    pub solution: GeneralLocal,
    /// The index of its start.
    pub best_start: usize,
    /// The starts solved (the time limit may end the search before the last).
    pub tried: usize,
}

/// Solves P_m locally from `start` (one control per step of `2^m`; module docs) by `rules`,
/// within the job's deadline ([`crate::progress::within`]). The start
/// is refused (field `start`) when it does not have one row in U per step, or a non-zero mean
/// under the zero-mean constraint, or when its periodic regime is not reached.
pub fn solve_general_local(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    start: &[Vec<f64>],
    rules: LocalRules,
) -> Result<GeneralLocal> {
    let plan = MultiStart {
        rules,
        finish: None,
    };
    let best = solve_general_local_best(p, g, m, &[start.to_vec()], plan, &mut |_| {})?;
    Ok(best.solution)
}

/// Solves P_m locally from each of `starts` in turn by `plan`, within the job's deadline,
/// and keeps the best verified answer (the first of equals, to `1e-9` of its `J`), finished
/// where `plan` asks it; `on_start` is told each start's index before it is solved. No start
/// is refused naming `start`; a start's refusal before any answer is held is the error
/// returned (each start is checked as [`solve_general_local`] checks it); the time limit
/// after one ends the search, and a finish that runs out of time before its first LP, or
/// ends below it (a numerical oddity: its first LP is the best's last), leaves the best as it
/// was.
pub fn solve_general_local_best(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    starts: &[Vec<Vec<f64>>],
    plan: MultiStart,
    on_start: &mut dyn FnMut(usize),
) -> Result<BestLocal> {
    check_general_local(p, g, m)?;
    if starts.is_empty() {
        return Err(Error::invalid(
            "start",
            "no start",
            "the search needs a start",
        ));
    }
    let mut best: Option<(GeneralLocal, usize, Option<Keepsake>)> = None;
    let mut tried = 0;
    for (k, start) in starts.iter().enumerate() {
        if best.is_some() && crate::progress::out_of_time()? {
            break;
        }
        on_start(k);
        let (sol, lp) = match one_start(p, g, m, start, plan.rules) {
            Ok(solved) => solved,
            Err(Error::TimeLimit(_)) if best.is_some() => break,
            Err(e) => return Err(e),
        };
        tried += 1;
        let out_of_time = sol.stop == LocalStop::TimeLimit;
        if best
            .as_ref()
            .is_none_or(|(b, ..)| sol.objective > b.objective + 1e-9 * (1.0 + b.objective.abs()))
        {
            // Its branches and the basis it ended on are kept for its finish (not its model:
            // two solvers alive at once, the best's and the next start's, held P_1024 of five
            // blocks at 55 MB where one start takes 38 MB).
            best = Some((sol, k, plan.finish.map(|_| lp.keepsake())));
        }
        if out_of_time {
            break;
        }
    }
    // There is a start, and the first either stores its answer or returns its error.
    let (solution, best_start, lp) = best.expect("the first start solved or an error returned");
    let solution = match (plan.finish, lp) {
        (Some(pivoting), Some(kept)) => {
            finished(p, &mut BranchLp::resume(p, m, kept)?, solution, pivoting)?
        }
        _ => solution,
    };
    Ok(BestLocal {
        solution,
        best_start,
        tried,
    })
}

/// One start (checked) solved by `rules` on a branch LP of its own, which is returned with
/// the answer at the basis it ended on.
fn one_start(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    start: &[Vec<f64>],
    rules: LocalRules,
) -> Result<(GeneralLocal, BranchLp)> {
    check_start(p, 1usize << m, start)?;
    let (start_objective, active) = start_branches(p, g, start, rules.start)?;
    let mut lp = BranchLp::new(p, m, active)?;
    let run = lp.run(rules.pivoting)?;
    Ok((lp.answer(p, run, start_objective)?, lp))
}

/// The best answer of a search continued by `pivoting` on its own branch LP `lp` (rebuilt at
/// the basis it ended on, [`BranchLp::resume`]): its LPs and switches add to the best's, its start is the best's. A best
/// cut short by the time limit is returned as it is, and so is the best when the finish runs
/// out of time before its first LP or ends below it (a numerical oddity: its first LP is the
/// best's last).
fn finished(
    p: &GeneralProblem,
    lp: &mut BranchLp,
    best: GeneralLocal,
    pivoting: Pivoting,
) -> Result<GeneralLocal> {
    if best.stop == LocalStop::TimeLimit {
        return Ok(best);
    }
    let run = match lp.run(pivoting) {
        Ok(run) => run,
        Err(Error::TimeLimit(_)) => return Ok(best),
        Err(e) => return Err(e),
    };
    let f = lp.answer(p, run, best.start_objective)?;
    let tol = 1e-9 * best.objective.abs().max(p.j_floor());
    if f.objective < best.objective - tol {
        return Ok(best);
    }
    Ok(GeneralLocal {
        lp_solves: best.lp_solves + f.lp_solves,
        switches: best.switches + f.switches,
        ..f
    })
}

/// Refuses a start (field `start`) without one control per step of the grid, or, under the
/// zero-mean constraint, with a non-zero mean (relative to its largest entry).
fn check_start(p: &GeneralProblem, mm: usize, start: &[Vec<f64>]) -> Result<()> {
    if start.len() != mm {
        return Err(Error::invalid(
            "start",
            format!("{} steps", start.len()),
            format!("needs one control per step ({mm})"),
        ));
    }
    let umax = start.iter().flatten().fold(1.0_f64, |s, v| s.max(v.abs()));
    if p.zero_mean {
        for k in 0..p.controls() {
            let mean = start.iter().map(|u| u[k]).sum::<f64>() / mm as f64;
            if mean.abs() > 1e-9 * umax {
                return Err(Error::invalid(
                    format!("start[{}]", k + 1),
                    mean,
                    "the start control must have zero mean (zero_mean = true)",
                ));
            }
        }
    }
    Ok(())
}

/// The start's process on this grid (module docs): its `J` and the branches read off it, on
/// face where the projection's multiplier is positive and, with [`StartFaces::Touched`], also
/// where its state lies on the face (to `1e-9` of C's scale) with a zero multiplier. Refused
/// (field `start`) as [`start_process`] refuses it.
fn start_branches(
    p: &GeneralProblem,
    g: &Geometry,
    start: &[Vec<f64>],
    faces: StartFaces,
) -> Result<(f64, Vec<Vec<bool>>)> {
    let (start_objective, sim) = start_process(p, g, start)?;
    // With `Touched`, a face the process touches at rest is held too (module docs).
    let touched = faces == StartFaces::Touched;
    let tol = 1e-9 * p.c.scale();
    let active: Vec<Vec<bool>> = sim
        .lambda
        .iter()
        .zip(&sim.x[1..])
        .map(|(l, x)| {
            (0..l.len())
                .map(|j| l[j] > 0.0 || (touched && p.c.slack(j, x) >= -tol))
                .collect()
        })
        .collect();
    Ok((start_objective, active))
}

/// The P_m process of a start control on this grid: the control (one row per step, in U)
/// simulated by catching-up to its periodic regime from C's Chebyshev centre (or from 0 when 0
/// is in C), or over the horizon of a Cauchy problem; returns its `J` and the process. Refused
/// (field `start`) when the control is not in U or the periodic regime is not reached.
pub(crate) fn start_process(
    p: &GeneralProblem,
    g: &Geometry,
    start: &[Vec<f64>],
) -> Result<(f64, crate::integrate::GeneralSimulation)> {
    let x0 = match &p.boundary {
        Boundary::Initial(x0) => x0.clone(),
        Boundary::Periodic if p.c.violation(&vec![0.0; p.states()], 0.0).is_none() => {
            vec![0.0; p.states()]
        }
        Boundary::Periodic => g.chebyshev_centre.clone(),
    };
    let sim = run_on_grid(p, &x0, start, "start")?;
    let start_objective = sim.objective.ok_or_else(|| {
        Error::invalid(
            "start",
            "the start control",
            format!(
                "its periodic regime was not reached within {} periods",
                GeneralSimOptions::DEFAULT.max_periods
            ),
        )
    })?;
    Ok((start_objective, sim))
}

#[cfg(test)]
#[path = "local_tests.rs"]
mod tests;
