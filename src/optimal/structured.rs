//! Structured gaits (issue "never worse than the obvious"): families of gaits one writes by hand
//! for a chain, evaluated exactly by the periodic simulator, the best of which is the start of
//! the local methods and the floor of every answer of `optimize`.
//!
//! Every gait of the families moves each link `l` along one periodic *profile* `p` (values in
//! `[-1, 1]`) with its own time lag `phi_l` (a fraction of the period) and the largest amplitude
//! the rate bound allows, `A_l = (a_l / k_l) T / max|p'|`, so that `|u_l| <= a_l` holds
//! ([`GaitProblem::rate_bound`]). The profiles:
//! - *triangle*: up and down at the full rate (the control is bang-bang, `u = +-a`);
//! - *bang-bang with dwell* (trapezoid, duty `d`): up at the full rate for `d T`, hold, down for
//!   `d T`, hold (`u` in `{a, 0, -a}`; `d = 1/2` is the triangle);
//! - *sine*, sampled on [`SINE_KNOTS`] common knots (its chords are no steeper than the sine).
//!
//! and the lags:
//! - *travelling waves*: `phi_l = l lambda` for every lag `lambda = j / M` of a grid of `M`
//!   lags ([`StructuredOptions::lags`] for the triangle, [`COARSE_LAGS`] for the others), plus
//!   the lags of one and two wavelengths along the body, in both directions; `lambda = 0` moves
//!   all links together, `lambda = 1/2` is the *alternating* pattern (odd links against even
//!   links);
//! - *grouped*: the links in `g` contiguous groups (`g = 2..=MAX_GROUPS`), group `i` lagged by
//!   `i lambda` (triangle profile, [`COARSE_LAGS`] lags).
//!
//! Measured (uniform chains, k = a = 1, T = 10, mu+ = 1, mu- = 1.3, release build, 2-core
//! machine shared with other jobs): see `docs/guide/long-chains.md`.
//!
//! Each gait's value is its displacement per period on the periodic orbit found by the exact
//! event-driven simulator ([`crate::integrate::simulate`], Newton-Krylov search), less its
//! actuation cost; the gaits are simulated in parallel (rayon). The best one is returned as a
//! [`StartGait`] whose result is the gait on the simulator's own pieces (a `phase` record: one
//! constant control and one slip pattern per piece, replayed exactly), so that it is re-verified
//! like every other answer.

use crate::error::{Error, Result};
use crate::integrate::{simulate, Actuation, Method, SimOptions};
use crate::model::Crawler;
use crate::optimal::{GaitProblem, GaitResult, StartGait};

pub use super::structured_record::knots_result;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Knots per period of the sampled sine profile.
pub const SINE_KNOTS: usize = 48;

/// Most contiguous groups of the grouped patterns.
pub const MAX_GROUPS: usize = 5;

/// Duties of the bang-bang profiles with dwell, besides the triangle (`d = 1/2`).
const DUTIES: [f64; 3] = [0.375, 0.25, 0.125];

/// Lags of the sine and dwell profiles and of the grouped patterns (a coarser grid than the
/// triangle waves': they rarely win, and each lag is one simulation).
pub const COARSE_LAGS: usize = 16;

/// Default number of lags of the travelling triangle waves: `2 n` for `n` links, within
/// `16..=32`.
pub fn default_lags(links: usize) -> usize {
    (2 * links).clamp(16, 32)
}

/// Options of [`best_structured`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StructuredOptions {
    /// Lags `j / lags`, `j = 0..lags`, of the travelling triangle waves (default
    /// [`default_lags`]).
    pub lags: Option<usize>,
}

/// The shape of a structured gait's profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// Up and down at the full rate.
    Triangle,
    /// Up at the full rate for a fraction `duty` of the period, hold, down, hold.
    BangBang {
        /// In `(0, 1/2)`.
        duty: f64,
    },
    /// A sine sampled on [`SINE_KNOTS`] knots.
    Sine,
}

impl Profile {
    /// The profile's breakpoints in `[0, 1)` and its values there (piecewise linear between,
    /// periodic), and the largest slope `max |p'|` per period.
    fn knots(self) -> (Vec<f64>, Vec<f64>, f64) {
        match self {
            Profile::Triangle => (vec![0.0, 0.5], vec![-1.0, 1.0], 4.0),
            Profile::BangBang { duty } => (
                vec![0.0, duty, 0.5, 0.5 + duty],
                vec![-1.0, 1.0, 1.0, -1.0],
                2.0 / duty,
            ),
            Profile::Sine => {
                let s = SINE_KNOTS;
                let th: Vec<f64> = (0..s).map(|j| j as f64 / s as f64).collect();
                let v = th
                    .iter()
                    .map(|t| (2.0 * std::f64::consts::PI * t).sin())
                    .collect();
                (th, v, 2.0 * std::f64::consts::PI)
            }
        }
    }

    /// Its value at `theta` (any real; period 1).
    fn at(self, theta: f64) -> f64 {
        let (th, v, _) = self.knots();
        let t = theta.rem_euclid(1.0);
        let j = th.iter().rposition(|&s| s <= t).unwrap_or(0);
        let (t0, v0) = (th[j], v[j]);
        let (t1, v1) = if j + 1 < th.len() {
            (th[j + 1], v[j + 1])
        } else {
            (1.0, v[0])
        };
        v0 + (t - t0) / (t1 - t0) * (v1 - v0)
    }

    /// Its name in an origin.
    fn name(self) -> String {
        match self {
            Profile::Triangle => "triangle wave".into(),
            Profile::BangBang { duty } => format!("bang-bang wave with dwell (duty {duty})"),
            Profile::Sine => "sine wave".into(),
        }
    }
}

/// One structured gait: a profile and the lag of every link.
#[derive(Debug, Clone, PartialEq)]
pub struct StructuredGait {
    /// The profile every link follows.
    pub profile: Profile,
    /// `phi_l`, fractions of the period.
    pub lags: Vec<f64>,
    /// What it is, in words (recorded as the origin of a result).
    pub description: String,
}

impl StructuredGait {
    /// Its knots over one period: times in `[0, T)` and the lengths of every link there.
    pub fn knots(&self, crawler: &Crawler, problem: &GaitProblem) -> (Vec<f64>, Vec<Vec<f64>>) {
        let t = problem.period;
        let (th, _, slope) = self.profile.knots();
        let amp: Vec<f64> = problem
            .rate_bound
            .iter()
            .zip(crawler.stiffness())
            .map(|(a, k)| a / k * t / slope)
            .collect();
        // The union of every link's breakpoints (a sine's knots are common to all links).
        let mut times: Vec<f64> = match self.profile {
            Profile::Sine => th.clone(),
            _ => self
                .lags
                .iter()
                .flat_map(|phi| th.iter().map(move |s| (s + phi).rem_euclid(1.0)))
                .collect(),
        };
        times.sort_by(f64::total_cmp);
        times.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        if times.len() > 1 && 1.0 - times[times.len() - 1] < 1e-12 {
            times.pop();
        }
        let lengths = times
            .iter()
            .map(|&s| {
                self.lags
                    .iter()
                    .zip(&amp)
                    .map(|(phi, a)| a * self.profile.at(s - phi))
                    .collect()
            })
            .collect();
        (times.iter().map(|s| s * t).collect(), lengths)
    }
}

/// The gait result of a structured gait: one period on its periodic orbit recorded by the exact
/// simulator, cut into pieces at every knot and event (one control and one slip pattern per
/// piece), so that it is a process of the problem on its own knots ([`knots_result`]).
pub fn structured_result(
    crawler: &Crawler,
    problem: &GaitProblem,
    g: &StructuredGait,
) -> Result<GaitResult> {
    let (times, lengths) = g.knots(crawler, problem);
    knots_result(crawler, problem, times, lengths, &g.description)
}

/// The lags `j / m`, `j = 0..m`, and those of one and two wavelengths along the `n` links in
/// both directions, each with its name.
fn lag_set(n: usize, m: usize) -> Vec<(f64, String)> {
    let m = m.max(1);
    let mut set: Vec<(f64, String)> = (0..m)
        .map(|j| (j as f64 / m as f64, format!("lag {j}/{m} of the period")))
        .collect();
    for waves in [1usize, 2] {
        for sign in [1.0, -1.0] {
            let lambda = (sign * waves as f64 / n as f64).rem_euclid(1.0);
            let dir = if sign > 0.0 { "" } else { ", reversed" };
            set.push((lambda, format!("{waves} wavelength(s) along the body{dir}")));
        }
    }
    set
}

/// The structured gaits of `crawler` (module docs): triangle waves at `lags` lags, the other
/// profiles and the grouped patterns at [`COARSE_LAGS`] lags.
pub fn structured_gaits(crawler: &Crawler, lags: usize) -> Vec<StructuredGait> {
    let n = crawler.links();
    let fine = lag_set(n, lags);
    let coarse = lag_set(n, COARSE_LAGS.min(lags.max(1)));
    let mut profiles = vec![(Profile::Triangle, &fine), (Profile::Sine, &coarse)];
    profiles.extend(
        DUTIES
            .iter()
            .map(|&duty| (Profile::BangBang { duty }, &coarse)),
    );
    let mut out = Vec::new();
    for (profile, set) in profiles {
        for (lambda, what) in set.iter() {
            let name = profile.name();
            let description = if (lambda - 0.5).abs() < 1e-12 {
                format!("structured: alternating {name} (odd links against even links)")
            } else if *lambda == 0.0 {
                format!("structured: synchronous {name} (all links together)")
            } else {
                format!("structured: travelling {name}, {what}")
            };
            out.push(StructuredGait {
                profile,
                lags: (0..n)
                    .map(|l| (l as f64 * lambda).rem_euclid(1.0))
                    .collect(),
                description,
            });
        }
    }
    for groups in 2..=MAX_GROUPS.min(n) {
        for (lambda, what) in coarse.iter().skip(1) {
            out.push(StructuredGait {
                profile: Profile::Triangle,
                lags: (0..n)
                    .map(|l| ((l * groups / n) as f64 * lambda).rem_euclid(1.0))
                    .collect(),
                description: format!(
                    "structured: grouped triangle wave, {groups} contiguous groups, group {what}"
                ),
            });
        }
    }
    out
}

/// One evaluated structured gait.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StructuredRow {
    /// What it is.
    pub description: String,
    /// Its `J` (displacement per period on the orbit, less the actuation cost) as screened
    /// (periodic state to a relative 1e-9: `J` to about 1e-8; the best gait's is recorded to
    /// the default tolerance); `None` when the simulator found no periodic orbit.
    pub objective: Option<f64>,
}

/// What [`best_structured`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct StructuredSearch {
    /// The best gait, as a start (its result is the gait on the simulator's pieces).
    pub best: StartGait,
    /// Its `J`, re-verified (the result's objective).
    pub objective: f64,
    /// Every gait evaluated, in the order of [`structured_gaits`].
    pub rows: Vec<StructuredRow>,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// The lags of the triangle waves ([`structured_gaits`] of these lags are the rows').
    pub lags: usize,
}

/// The simulator options of the evaluation: exact, no recording, the periodic state to a
/// relative 1e-9 (the default 1e-12 took twice the time on the heterogeneous chain of 100
/// blocks, 7.3 s against 3.6 s for 192 gaits, for differences of J of 1e-8); the best gait is
/// then recorded with the default tolerance ([`structured_result`]).
fn eval_options() -> SimOptions {
    SimOptions {
        method: Method::Exact,
        record_periods: 0,
        tol: 1e-9,
        ..SimOptions::default()
    }
}

/// `int_0^T f2(u) dt` of a piecewise-linear gait's knots.
pub(crate) fn knot_cost(
    crawler: &Crawler,
    problem: &GaitProblem,
    times: &[f64],
    lengths: &[Vec<f64>],
) -> f64 {
    let k = crawler.stiffness();
    let p = times.len();
    (0..p)
        .map(|j| {
            let (t0, t1) = (
                times[j],
                if j + 1 < p {
                    times[j + 1]
                } else {
                    problem.period
                },
            );
            let next = &lengths[(j + 1) % p];
            let d = t1 - t0;
            let u: Vec<f64> = (0..k.len())
                .map(|l| k[l] * (next[l] - lengths[j][l]) / d)
                .collect();
            d * problem.cost.eval(&u)
        })
        .sum()
}

/// `J` of a gait by the exact simulator: `None` when it finds no periodic orbit.
fn evaluate(crawler: &Crawler, problem: &GaitProblem, g: &StructuredGait) -> Option<f64> {
    let (times, lengths) = g.knots(crawler, problem);
    let act = Actuation::of_gait(problem.period, times.clone(), lengths.clone()).ok()?;
    let sim = simulate(crawler, &act, &eval_options()).ok()?;
    let d = sim.displacement_per_period?;
    Some(d - knot_cost(crawler, problem, &times, &lengths))
}

/// The best of the structured gaits of `crawler` for `problem` (module docs), re-verified and
/// recorded as a gait result of origin `structured: ...`. Gaits are simulated in parallel, in
/// chunks of one per thread between which the job's cancellation is checked, and its deadline:
/// once it has passed, the gaits simulated so far (at least one chunk) are the search. `None`
/// with a bound on the total variation of `u` (the families do not honour one) or when no gait
/// reached a periodic orbit.
pub fn best_structured(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &StructuredOptions,
) -> Result<Option<StructuredSearch>> {
    crawler.require_unique()?;
    problem.validate(crawler)?;
    if problem.max_total_variation.is_some() {
        return Ok(None);
    }
    let began = Instant::now();
    let lags = opts.lags.unwrap_or_else(|| default_lags(crawler.links()));
    if lags == 0 || lags > 1024 {
        return Err(Error::invalid(
            "lags",
            lags,
            "must be in 1..=1024 (each lag is one simulation per profile)",
        ));
    }
    let gaits = structured_gaits(crawler, lags);
    let mut values = Vec::with_capacity(gaits.len());
    let chunk = rayon::current_num_threads().max(1);
    for part in gaits.chunks(chunk) {
        // The job's deadline ends the screening after the first chunk (the families come
        // simplest first): at 1000 blocks the 192 gaits take about 18 s, beyond a limit of 1 s.
        if crate::progress::out_of_time()? && !values.is_empty() {
            break;
        }
        values.par_extend(part.par_iter().map(|g| evaluate(crawler, problem, g)));
    }
    let rows: Vec<StructuredRow> = gaits
        .iter()
        .zip(&values)
        .map(|(g, v)| StructuredRow {
            description: g.description.clone(),
            objective: *v,
        })
        .collect();
    // The first of the best (ties go to the simplest family: triangle waves come first), a tie
    // relative to the problem's floor of `J` (an absolute floor of 1 made every gait of a
    // crawler of lengths `1e-12` a tie, and the first, a worse lag, the start).
    let floor = problem.j_floor(crawler);
    let mut best: Option<(usize, f64)> = None;
    for (i, v) in values.iter().enumerate() {
        if let Some(v) = *v {
            if best.is_none_or(|(_, b)| v > b + 1e-12 * b.abs().max(floor)) {
                best = Some((i, v));
            }
        }
    }
    let Some((i, _)) = best else {
        return Ok(None);
    };
    let result = structured_result(crawler, problem, &gaits[i])?;
    Ok(Some(StructuredSearch {
        objective: result.head.objective,
        best: StartGait {
            origin: gaits[i].description.clone(),
            result,
        },
        rows,
        seconds: began.elapsed().as_secs_f64(),
        lags,
    }))
}

/// The hook for a global method's incumbent: the best structured gait (its knots are
/// [`StartGait::times`] and [`StartGait::lengths`], from 0 to `T`; its pieces, controls, states
/// and slip modes are in the result's gait) and its `J`, re-verified by the exact simulator;
/// `None` as for [`best_structured`]. A phase MILP can take the pieces as its first incumbent
/// when it allows as many phases, or the value alone as a cutoff.
pub fn structured_incumbent(
    crawler: &Crawler,
    problem: &GaitProblem,
) -> Result<Option<(StartGait, f64)>> {
    Ok(
        best_structured(crawler, problem, &StructuredOptions::default())?
            .map(|s| (s.best, s.objective)),
    )
}
