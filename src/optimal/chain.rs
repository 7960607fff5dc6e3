//! The local method for long chains (method `chain`): a pattern search over per-link ramp gaits,
//! started from the best structured gait ([`super::structured`]), every trial evaluated exactly
//! by the periodic simulator. It scales with the chain because a trial is one periodic search
//! (milliseconds at N = 100) and a sweep is `O(N)` trials, with no model whose size grows with
//! blocks x steps; it never returns less than its start (a move is kept only when it improves the
//! exactly simulated `J`).
//!
//! Each link `l` follows a *ramp* profile of five parameters: its lag `phi_l` (fraction of the
//! period), the durations of its rise `r_l` and fall `f_l` (fractions, `r + f <= 1`), the share
//! `s_l` of the remaining dwell `1 - r - f` spent at the top, and its amplitude fraction
//! `alpha_l in (0, 1]`: the length rises linearly from `-A` to `A` over `r T`, holds, falls over
//! `f T`, holds, with `A_l = alpha_l (a_l / k_l) T min(r_l, f_l) / 2`, so that the faster ramp
//! runs at most at the rate bound. The triangle wave is `r = f = 1/2`, `alpha = 1`; the
//! bang-bang wave with dwell of duty `d` is `r = f = d`, `s = 1/2`.
//!
//! A sweep tries, link by link and parameter by parameter, the moves `+-delta` (the two in
//! parallel) and keeps the better one when it improves `J`; a sweep without a gain halves
//! `delta` (from [`FIRST_STEP`] down to [`LAST_STEP`]), after which the search stops
//! (`stalled`: no move of the smallest step pays; no stationarity is claimed). Time limit and
//! cancellation are checked between trials.

use super::structured::{knots_result, Profile, StructuredGait};
use crate::error::{Error, Result};
use crate::integrate::{simulate, Actuation, Method, SimOptions};
use crate::model::Crawler;
use crate::optimal::{GaitProblem, GaitResult, LocalStop};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The first step of the pattern search (fractions of the period; amplitude fractions).
pub const FIRST_STEP: f64 = 1.0 / 16.0;
/// The smallest step: the search stops when a sweep at this step gains nothing (`2^-10` of the
/// period, the step of P_10).
pub const LAST_STEP: f64 = 1.0 / 1024.0;
/// The shortest ramp (fraction of the period).
const MIN_RAMP: f64 = 1.0 / 512.0;
/// The smallest amplitude fraction.
const MIN_ALPHA: f64 = 1.0 / 64.0;
/// Parameters per link.
const PARAMS: usize = 5;

/// One link's ramp (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ramp {
    /// Lag `phi` (fraction of the period).
    pub lag: f64,
    /// Rise duration `r` (fraction).
    pub rise: f64,
    /// Fall duration `f` (fraction).
    pub fall: f64,
    /// Share `s` of the dwell at the top.
    pub top: f64,
    /// Amplitude fraction `alpha`.
    pub alpha: f64,
}

impl Ramp {
    /// The ramp of a structured profile (a sine is approximated by the triangle).
    pub fn of_profile(p: Profile, lag: f64) -> Self {
        let (rise, fall) = match p {
            Profile::BangBang { duty } => (duty, duty),
            Profile::Triangle | Profile::Sine => (0.5, 0.5),
        };
        Ramp {
            lag,
            rise,
            fall,
            top: 0.5,
            alpha: 1.0,
        }
    }

    /// Parameter `i` moved by `delta`, clamped to the admissible set; `None` when the clamp
    /// leaves it where it was.
    fn moved(self, i: usize, delta: f64) -> Option<Self> {
        let mut r = self;
        match i {
            0 => r.lag = (r.lag + delta).rem_euclid(1.0),
            1 => r.rise = (r.rise + delta).clamp(MIN_RAMP, 1.0 - r.fall),
            2 => r.fall = (r.fall + delta).clamp(MIN_RAMP, 1.0 - r.rise),
            3 => r.top = (r.top + 2.0 * delta).clamp(0.0, 1.0),
            _ => r.alpha = (r.alpha + 2.0 * delta).clamp(MIN_ALPHA, 1.0),
        }
        (r != self).then_some(r)
    }

    /// Breakpoints (fractions from the lag) and values in units of the amplitude.
    fn breakpoints(self) -> [(f64, f64); 4] {
        let dwell = (1.0 - self.rise - self.fall).max(0.0);
        let top_end = self.rise + self.top * dwell;
        [
            (0.0, -1.0),
            (self.rise, 1.0),
            (top_end, 1.0),
            (top_end + self.fall, -1.0),
        ]
    }

    /// The profile's value at `theta` (period 1), in units of the amplitude.
    fn at(self, theta: f64) -> f64 {
        let t = (theta - self.lag).rem_euclid(1.0);
        let bp = self.breakpoints();
        for w in 0..4 {
            let (t0, v0) = bp[w];
            let (t1, v1) = if w + 1 < 4 { bp[w + 1] } else { (1.0, -1.0) };
            if t <= t1 || w == 3 {
                return if t1 - t0 > 0.0 {
                    v0 + (t - t0).max(0.0) / (t1 - t0) * (v1 - v0)
                } else {
                    v1
                };
            }
        }
        -1.0
    }
}

/// The knots of a chain of ramps: the union of every link's breakpoints.
pub fn ramp_knots(
    crawler: &Crawler,
    problem: &GaitProblem,
    ramps: &[Ramp],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let t = problem.period;
    let amp: Vec<f64> = ramps
        .iter()
        .zip(&problem.rate_bound)
        .zip(crawler.stiffness())
        .map(|((r, a), k)| r.alpha * a / k * t * r.rise.min(r.fall) / 2.0)
        .collect();
    let mut times: Vec<f64> = ramps
        .iter()
        .flat_map(|r| {
            r.breakpoints()
                .into_iter()
                .map(move |(s, _)| (s + r.lag).rem_euclid(1.0))
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    if times.len() > 1 && 1.0 - times[times.len() - 1] < 1e-12 {
        times.pop();
    }
    let lengths = times
        .iter()
        .map(|&s| ramps.iter().zip(&amp).map(|(r, a)| a * r.at(s)).collect())
        .collect();
    (times.iter().map(|s| s * t).collect(), lengths)
}

/// Options of [`search_chain`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ChainOptions {
    /// Wall-clock limit, seconds (none: until the smallest step gains nothing).
    pub time_limit: Option<f64>,
}

/// One sweep of the search, for a progress display.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainStep {
    /// Sweeps so far.
    pub sweep: usize,
    /// The step of this sweep.
    pub step: f64,
    /// The best `J` after it.
    pub objective: f64,
    /// Trials (periodic searches) so far.
    pub evaluations: usize,
    /// Seconds so far.
    pub seconds: f64,
}

/// What [`search_chain`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSearch {
    /// The best gait (a structured-gait record whose origin says where it started).
    pub result: GaitResult,
    /// The ramps of the best gait.
    pub ramps: Vec<Ramp>,
    /// `J` of the start.
    pub start_objective: f64,
    /// Sweeps made.
    pub sweeps: usize,
    /// Moves kept.
    pub moves: usize,
    /// Trials (periodic searches).
    pub evaluations: usize,
    /// Why it stopped.
    pub stop: LocalStop,
}

/// `J` and the orbit state of a chain of ramps by the exact simulator from `x0`; `None` when
/// no periodic orbit was found.
fn evaluate(
    crawler: &Crawler,
    problem: &GaitProblem,
    ramps: &[Ramp],
    x0: &[f64],
) -> Option<(f64, Vec<f64>)> {
    let (times, lengths) = ramp_knots(crawler, problem, ramps);
    let act = Actuation::of_gait(problem.period, times.clone(), lengths.clone()).ok()?;
    let opts = SimOptions {
        method: Method::Exact,
        record_periods: 0,
        initial_state: Some(x0.to_vec()),
        ..SimOptions::default()
    };
    let sim = simulate(crawler, &act, &opts).ok()?;
    let d = sim.displacement_per_period?;
    Some((
        d - super::structured::knot_cost(crawler, problem, &times, &lengths),
        sim.orbit_state,
    ))
}

/// The ramps of a structured gait.
pub fn ramps_of(g: &StructuredGait) -> Vec<Ramp> {
    g.lags
        .iter()
        .map(|&lag| Ramp::of_profile(g.profile, lag))
        .collect()
}

/// The pattern search (module docs) from `start` (one ramp per link), `origin` naming it;
/// `progress` sees every sweep.
pub fn search_chain(
    crawler: &Crawler,
    problem: &GaitProblem,
    start: &[Ramp],
    origin: &str,
    opts: &ChainOptions,
    progress: &mut dyn FnMut(&ChainStep),
) -> Result<ChainSearch> {
    crawler.require_unique()?;
    problem.validate(crawler)?;
    crate::optimal::check_time_limit(opts.time_limit)?;
    if start.len() != crawler.links() {
        return Err(Error::invalid(
            "start",
            format!("{} ramps", start.len()),
            format!("needs one per link ({})", crawler.links()),
        ));
    }
    crate::progress::within(opts.time_limit, || {
        search(crawler, problem, start, origin, progress)
    })
}

/// [`search_chain`], arguments checked, within the current deadline.
fn search(
    crawler: &Crawler,
    problem: &GaitProblem,
    start: &[Ramp],
    origin: &str,
    progress: &mut dyn FnMut(&ChainStep),
) -> Result<ChainSearch> {
    let began = Instant::now();
    let zero = vec![0.0; crawler.links()];
    let (mut best, mut x0) = evaluate(crawler, problem, start, &zero).ok_or_else(|| {
        Error::Numerical(format!(
            "{origin}: the exact simulator found no periodic orbit"
        ))
    })?;
    let start_objective = best;
    let mut ramps = start.to_vec();
    let (mut evaluations, mut sweeps, mut moves) = (1usize, 0usize, 0usize);
    let mut step = FIRST_STEP;
    let stop = 'search: loop {
        sweeps += 1;
        let mut gained = false;
        for l in 0..ramps.len() {
            for i in 0..PARAMS {
                if crate::progress::out_of_time()? {
                    break 'search LocalStop::TimeLimit;
                }
                let trials: Vec<Vec<Ramp>> = [step, -step]
                    .iter()
                    .filter_map(|&d| {
                        ramps[l].moved(i, d).map(|r| {
                            let mut v = ramps.clone();
                            v[l] = r;
                            v
                        })
                    })
                    .collect();
                let values: Vec<Option<(f64, Vec<f64>)>> = {
                    use rayon::prelude::*;
                    trials
                        .par_iter()
                        .map(|v| evaluate(crawler, problem, v, &x0))
                        .collect()
                };
                evaluations += trials.len();
                let mut pick: Option<usize> = None;
                let mut pick_j = best + 1e-12 * best.abs().max(problem.length_scale(crawler));
                for (t, v) in values.iter().enumerate() {
                    if let Some((j, _)) = v {
                        if *j > pick_j {
                            pick_j = *j;
                            pick = Some(t);
                        }
                    }
                }
                if let Some(t) = pick {
                    let (j, x) = values[t].clone().unwrap_or((best, x0.clone()));
                    best = j;
                    x0 = x;
                    ramps = trials[t].clone();
                    moves += 1;
                    gained = true;
                }
            }
        }
        progress(&ChainStep {
            sweep: sweeps,
            step,
            objective: best,
            evaluations,
            seconds: began.elapsed().as_secs_f64(),
        });
        if !gained {
            if step <= LAST_STEP {
                break LocalStop::Stalled;
            }
            step *= 0.5;
        }
    };
    let (times, lengths) = ramp_knots(crawler, problem, &ramps);
    let what = if moves == 0 {
        origin.to_string()
    } else {
        format!("chain pattern search ({moves} moves), from {origin}")
    };
    let mut result = knots_result(crawler, problem, times, lengths, &what)?;
    if stop == LocalStop::TimeLimit {
        result.head.status = crate::optimal::MilpStatus::TimeLimit;
    }
    Ok(ChainSearch {
        result,
        ramps,
        start_objective,
        sweeps,
        moves,
        evaluations,
        stop,
    })
}

/// Starts of the chain method unless told: the best structured gaits of distinct values.
pub const DEFAULT_STARTS: usize = 4;

/// [`search_chain`] from each of `starts` (ramps and origin, best first) in turn within
/// `opts.time_limit` in all, keeping the best answer (the first of equals); the first start is
/// always searched, the others while time is left.
pub fn search_chain_multi(
    crawler: &Crawler,
    problem: &GaitProblem,
    starts: &[(Vec<Ramp>, String)],
    opts: &ChainOptions,
    progress: &mut dyn FnMut(&ChainStep),
) -> Result<ChainSearch> {
    crate::optimal::check_time_limit(opts.time_limit)?;
    crate::progress::within(opts.time_limit, || {
        search_each(crawler, problem, starts, progress)
    })
}

/// [`search_chain_multi`] within the current deadline. The progress reports the best `J` over
/// the starts searched so far; when the limit cuts a start or leaves one unsearched, the answer
/// says `time_limit` (its own search may have stalled, but the method did not finish).
fn search_each(
    crawler: &Crawler,
    problem: &GaitProblem,
    starts: &[(Vec<Ramp>, String)],
    progress: &mut dyn FnMut(&ChainStep),
) -> Result<ChainSearch> {
    let mut best: Option<ChainSearch> = None;
    let mut cut = false;
    for (ramps, origin) in starts {
        if best.is_some() && crate::progress::out_of_time()? {
            cut = true;
            break;
        }
        let so_far = best
            .as_ref()
            .map_or(f64::NEG_INFINITY, |b| b.result.head.objective);
        let s = search_chain(
            crawler,
            problem,
            ramps,
            origin,
            &ChainOptions::default(),
            &mut |st: &ChainStep| {
                progress(&ChainStep {
                    objective: st.objective.max(so_far),
                    ..st.clone()
                })
            },
        )?;
        cut = s.stop == LocalStop::TimeLimit;
        if best
            .as_ref()
            .is_none_or(|b| s.result.head.objective > b.result.head.objective + 1e-12)
        {
            best = Some(s);
        }
        if cut {
            break;
        }
    }
    let mut best =
        best.ok_or_else(|| Error::invalid("starts", 0, "the chain method needs a start"))?;
    if cut {
        best.stop = LocalStop::TimeLimit;
        best.result.head.status = crate::optimal::MilpStatus::TimeLimit;
    }
    Ok(best)
}

/// The starts of the chain method from the structured gaits `gaits` and their values `values`
/// (as [`super::structured::best_structured`] evaluated them): the `count` best piecewise-linear
/// ones (a sine has no ramp) of distinct values (relative to the problem's floor of `J`,
/// [`super::GaitProblem::j_floor`]), best first.
pub fn chain_starts(
    gaits: &[StructuredGait],
    values: &[Option<f64>],
    floor: f64,
    count: usize,
) -> Vec<(Vec<Ramp>, String)> {
    let mut order: Vec<(f64, &StructuredGait)> = gaits
        .iter()
        .zip(values)
        .filter(|(g, _)| g.profile != Profile::Sine)
        .filter_map(|(g, v)| v.map(|j| (j, g)))
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut out: Vec<(Vec<Ramp>, String)> = Vec::new();
    let mut last = f64::NAN;
    for (j, g) in order {
        if (j - last).abs() <= 1e-9 * j.abs().max(floor) {
            continue;
        }
        last = j;
        out.push((ramps_of(g), g.description.clone()));
        if out.len() >= count {
            break;
        }
    }
    out
}
