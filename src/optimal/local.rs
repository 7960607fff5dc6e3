//! The local method for P_m (theory §6): an active-set method on the LPCC, for grids far beyond
//! the reach of the global MILP (`2^m ~ 10^3` steps and more, several blocks).
//!
//! Every complementarity condition of P_m is a three-way choice per step `i` and block `b`
//! (its *mode*): stick (`D^i_b = 0`, `F_b(x^{i+1})` anywhere in its range), slip+
//! (`F_b(x^{i+1}) = mu_b^+`, `D^i_b >= 0`) or slip- (`F_b(x^{i+1}) = -mu_b^-`, `D^i_b <= 0`).
//! With the modes fixed, P_m is a linear program, and every feasible point of it is a
//! catching-up trajectory (the modes make the KKT system of the projection hold). With the
//! face values as columns `f^i_b` (`f^i_b = F_b(x^{i+1})`), a mode is nothing but column bounds:
//!
//! ```text
//! stick: D in [0, 0],      f in [-mu^-, mu^+]
//! slip+: D in [0, Md],     f in [mu^+, mu^+]
//! slip-: D in [-Md, 0],    f in [-mu^-, -mu^-]
//! ```
//!
//! so one HiGHS model is re-solved from its previous basis after each change of modes.
//!
//! Pivoting (minimising `-J`): at the LP optimum a pair is *degenerate* when both sides of its
//! complementarity are zero (a sticking block whose face is reached, or a slipping block that
//! does not move); switching its mode keeps the current point feasible, so the next LP is at
//! least as good. The reduced costs say which switches pay: a sticking block on its `+` face
//! with `d(D) < 0` (moving it forward lowers `-J`) becomes slip+; on its `-` face with
//! `d(D) > 0` slip-; a slip+ block at rest with `d(f) > 0` (lowering its force pays) and a
//! slip- block at rest with `d(f) < 0` stick. All profitable switches are made at once. When
//! none remains the point is B-stationary as far as these first-order tests see (each single
//! switch is tested by its reduced cost, not by solving the neighbouring LP), and the result is
//! reported as a `local` certificate, never as a global one.
//!
//! The start is any gait on the same period (typically the phase optimum): its actuation is
//! sampled on the grid, simulated by catching-up to the periodic orbit, and the modes are read
//! off that orbit. Every answer is re-verified by replaying it through the simulator.
//!
//! Why the crawler keeps this LPCC beside (P)'s ([`crate::optimal::general::local`]) on its
//! instance ([`crate::model::crawler_as_general`]): run there, with (P)'s pivoting limited to
//! the reduced-cost switches made here, (P)'s method reaches the same `J` from the phase
//! optimum (three blocks, `m` = 6, 8, 10; four blocks of varied friction, `m = 10`), but the
//! whole `optimize --method local --m 10` (8 time shifts) took 1.55 times as long on three
//! blocks (median of 5 paired runs) while (P)'s LP had a multiplier and a slack column and a
//! row per face (16 columns and 8 rows a step for three blocks, against 10 and 5 here). Since
//! (P)'s branch LP gives two opposite faces one value column and one row (13 columns and 5
//! rows) and is solved in units of order one, the same fold took 1.14 times as long at
//! `m = 10` and 1.00 at `m = 8`; with its pair's multipliers as one signed column (10 columns
//! and 5 rows, this LP's size) 1.10 at `m = 10` (5 paired runs, from 0.93 to 1.26). It also
//! pivots otherwise: from the small rise and fall of one link at `m = 2` it stopped at its
//! start's `J = 0.5` where this method reaches 3 (`tests/local.rs`), so the fold waits for
//! the reason.

use super::active_set;
use super::solver::Highs;
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::milp::{
    block_speed_bound, check_verified, force, replay_grid, GridColumns, GridReplay,
};
use crate::optimal::units::{scale_all, scale_rows, Units};
use crate::optimal::{Cost, GaitProblem};
use highs::{Col, RowProblem, Sense};
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

#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    Stick,
    Plus,
    Minus,
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

/// Solves P_m locally from a start gait given by its knots (module docs).
pub fn solve_discrete_local(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start_times: &[f64],
    start_lengths: &[Vec<f64>],
) -> Result<LocalSolution> {
    crawler.require_unique()?;
    problem.check_scales(crawler)?;
    check_local(problem, m)?;
    crate::optimal::check_size(crawler, 1 << m, "m", m)?;
    // Solved in the optimisers' internal units ([`Units`]), answered in the user's.
    let units = Units::of(crawler, problem);
    let (c, p) = (units.crawler(crawler)?, units.problem(problem));
    let (times, lengths) = units.knots_in(start_times, start_lengths);
    let s = crate::progress::with_objective_scale(units.objective_scale(), || {
        solve_local_in(&c, &p, m, &times, &lengths)
    })?;
    Ok(units.local(&s))
}

/// [`solve_discrete_local`] in internal units, arguments checked.
fn solve_local_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start_times: &[f64],
    start_lengths: &[Vec<f64>],
) -> Result<LocalSolution> {
    let (n, nb) = (crawler.links(), crawler.blocks());
    let (k, mp, mm) = (
        crawler.stiffness(),
        crawler.mu_forward(),
        crawler.mu_backward(),
    );
    let big_m = 1usize << m;
    let t = problem.period;
    let h = t / big_m as f64;
    let a = &problem.rate_bound;
    let what = format!("P_{m} (local)");
    let md = h * block_speed_bound(crawler, problem);

    // The start on this grid, on its periodic orbit.
    let incs = sample_increments(start_times, start_lengths, k, a, t, big_m);
    let start = replay_grid(crawler, t, &incs, &vec![0.0; n], &what)?;
    let start_objective = start.verified;
    let tol_f = 1e-9 * mp.iter().chain(mm).fold(0.0f64, |s, v| s.max(*v));
    let tol_d = 1e-12 * md.max(1e-300);
    let mut modes = start_modes(crawler, &start, big_m, tol_f, tol_d);

    // One LP for every choice of modes; modes are column bounds.
    let (pb, grid, ds, fs) = mode_lp(crawler, problem, big_m, md);
    let mut model = Highs::new(pb, Sense::Minimise, &what)?;
    model.option("primal_feasibility_tolerance", 1e-10)?;
    model.option("dual_feasibility_tolerance", 1e-10)?;
    let set_bounds = |model: &mut Highs, i: usize, b: usize, mode: Mode| match mode {
        Mode::Stick => {
            model.set_bounds(ds[i][b], 0.0, 0.0)?;
            model.set_bounds(fs[i][b], -mm[b], mp[b])
        }
        Mode::Plus => {
            model.set_bounds(ds[i][b], 0.0, md)?;
            model.set_bounds(fs[i][b], mp[b], mp[b])
        }
        Mode::Minus => {
            model.set_bounds(ds[i][b], -md, 0.0)?;
            model.set_bounds(fs[i][b], -mm[b], -mm[b])
        }
    };
    for i in 0..big_m {
        for b in 0..nb {
            set_bounds(&mut model, i, b, modes[i][b])?;
        }
    }

    // Profitable switches at degenerate pairs (module docs).
    let tol_red = 1e-9;
    let pivot = |model: &mut Highs, cols: &[f64], red: &[f64], _: f64| -> Result<usize> {
        let mut changed = 0;
        for i in 0..big_m {
            for b in 0..nb {
                let (d, f) = (cols[ds[i][b].index()], cols[fs[i][b].index()]);
                let (rd, rf) = (red[ds[i][b].index()], red[fs[i][b].index()]);
                let new = match modes[i][b] {
                    Mode::Stick if (f - mp[b]).abs() <= tol_f && rd < -tol_red => Mode::Plus,
                    Mode::Stick if (f + mm[b]).abs() <= tol_f && rd > tol_red => Mode::Minus,
                    Mode::Plus if d.abs() <= tol_d && rf > tol_red => Mode::Stick,
                    Mode::Minus if d.abs() <= tol_d && rf < -tol_red => Mode::Stick,
                    same => same,
                };
                if new != modes[i][b] {
                    modes[i][b] = new;
                    set_bounds(model, i, b, new)?;
                    changed += 1;
                }
            }
        }
        Ok(changed)
    };
    // In internal units, the floor of `J` is 1.
    let run = active_set::run(&mut model, -1.0, 20 * big_m * nb, 3, 1.0, &what, pivot)?;
    reverified(crawler, problem, m, &grid, run, start_objective, &what)
}

/// The modes of the start's steps: a block slipping forward (`Plus`) or backward (`Minus`)
/// where its force is on the friction bound, to `tol_f`, and it does not move against it, to
/// `tol_d`; else `Stick`. The active set the local method starts from.
fn start_modes(
    crawler: &Crawler,
    start: &GridReplay,
    big_m: usize,
    tol_f: f64,
    tol_d: f64,
) -> Vec<Vec<Mode>> {
    let nb = crawler.blocks();
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    (0..big_m)
        .map(|i| {
            let x = &start.states[i + 1];
            (0..nb)
                .map(|b| {
                    let f = force(x, b);
                    let d = start.block_displacements[i][b];
                    if (f - mp[b]).abs() <= tol_f && d >= -tol_d {
                        Mode::Plus
                    } else if (f + mm[b]).abs() <= tol_f && d <= tol_d {
                        Mode::Minus
                    } else {
                        Mode::Stick
                    }
                })
                .collect()
        })
        .collect()
}

/// The LP of P_m with the modes left to column bounds (module docs): the grid's columns, block
/// displacements `d^i_b` (objective `-1/N` each, `|d| <= md`) and forces `f^i_b` in
/// `[-mu-_b, mu+_b]`, the dynamics `x^{i+1} - x^i - U^i + k (d_{l+1} - d_l) = 0`, the forces
/// `f = F_b(x^{i+1})` and the rows on the control alone. Returns the problem, the grid
/// columns and the `d` and `f` columns per step and block.
fn mode_lp(
    crawler: &Crawler,
    problem: &GaitProblem,
    big_m: usize,
    md: f64,
) -> (RowProblem, GridColumns, Vec<Vec<Col>>, Vec<Vec<Col>>) {
    let (n, nb) = (crawler.links(), crawler.blocks());
    let (k, mp, mm) = (
        crawler.stiffness(),
        crawler.mu_forward(),
        crawler.mu_backward(),
    );
    let mut pb = RowProblem::default();
    let grid = GridColumns::new(&mut pb, crawler, problem, big_m);
    let (xs, us) = (&grid.xs, &grid.us);
    let inv_n = 1.0 / nb as f64;
    let ds: Vec<Vec<Col>> = (0..big_m)
        .map(|_| (0..nb).map(|_| pb.add_column(-inv_n, -md..=md)).collect())
        .collect();
    let fs: Vec<Vec<Col>> = (0..big_m)
        .map(|_| {
            (0..nb)
                .map(|b| pb.add_column(0.0, -mm[b]..=mp[b]))
                .collect()
        })
        .collect();
    for i in 0..big_m {
        let next = &xs[(i + 1) % big_m];
        for l in 0..n {
            pb.add_row(
                0.0..=0.0,
                [
                    (next[l], 1.0),
                    (xs[i][l], -1.0),
                    (us[i][l], -1.0),
                    (ds[i][l + 1], k[l]),
                    (ds[i][l], -k[l]),
                ],
            );
        }
        for b in 0..nb {
            // f = F_b(x^{i+1}) = x_{b-1} - x_b.
            let mut row = vec![(fs[i][b], -1.0)];
            if b > 0 {
                row.push((next[b - 1], 1.0));
            }
            if b < n {
                row.push((next[b], -1.0));
            }
            pb.add_row(0.0..=0.0, row);
        }
    }
    grid.add_control_rows(&mut pb, problem);
    (pb, grid, ds, fs)
}

/// Re-verification: the LP's increments played by catching-up from its x^0, checked against
/// the LP's objective; the verified displacement is the one reported (module docs).
fn reverified(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    grid: &GridColumns,
    run: active_set::Outcome,
    start_objective: f64,
    what: &str,
) -> Result<LocalSolution> {
    let t = problem.period;
    let h = t / (1usize << m) as f64;
    let (cols, lp_objective) = (run.cols, run.objective);
    let rows = grid.increments(&cols);
    let x0: Vec<f64> = grid.xs[0].iter().map(|c| cols[c.index()]).collect();
    let g = replay_grid(crawler, t, &rows, &x0, what)?;
    check_verified(
        what,
        lp_objective,
        g.verified,
        problem.length_scale(crawler),
    )?;
    Ok(LocalSolution {
        m,
        step: h,
        start_objective,
        lp_objective,
        verified_displacement: g.verified,
        actuation_cost: 0.0,
        lp_solves: run.lp_solves,
        switches: run.switches,
        stop: run.stop,
        initial_state: g.initial_state,
        block_displacements: g.block_displacements,
        states: g.states,
        controls: g.controls,
    })
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
/// discrete gait it becomes (three blocks, 64 steps: 2.4688 from the phase optimum as it is, 2.5625
/// from 6 of 32 shifts, among them 2 of the 8 shifts tried by default). Also returns the shift of
/// the best.
pub fn solve_discrete_local_shifted(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start_times: &[f64],
    start_lengths: &[Vec<f64>],
    shifts: usize,
) -> Result<(LocalSolution, f64)> {
    crate::optimal::check_shifts(shifts)?;
    let t = problem.period;
    let mut best: Option<(LocalSolution, f64)> = None;
    for j in 0..shifts {
        if best.is_some() && crate::progress::out_of_time()? {
            break;
        }
        let shift = t * j as f64 / shifts as f64;
        let (times, lengths) = shift_knots(start_times, start_lengths, shift, t);
        let s = match solve_discrete_local(crawler, problem, m, &times, &lengths) {
            Ok(s) => s,
            Err(Error::TimeLimit(_)) if best.is_some() => break,
            Err(e) => return Err(e),
        };
        let stop = s.stop == LocalStop::TimeLimit;
        if best
            .as_ref()
            .is_none_or(|(b, _)| s.objective() > b.objective() + 1e-9)
        {
            best = Some((s, shift));
        }
        if stop {
            break;
        }
    }
    // The loop runs at least once (shifts >= 1, checked) and either stores its first
    // answer or returns its error, so `best` is set here.
    Ok(best.expect("the first shift solved or an error returned"))
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
