//! Raising `K` until the value stops improving ([`grow_phases`]).

use super::solve::{gain_tolerance, solve_phase_with};
use super::{start_unproven, Formulation, PhaseOptions, PhaseSolution, MAX_PHASES};
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::milp::check_time_limit;
use crate::optimal::{GaitProblem, MilpStatus};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The relative resolution (times the problem's length scale) above which a verified `J_K`
/// counts as moving the crawler in [`grow_phases`]: the replay reproduces `J` to about `1e-14`
/// of the length scale, so `1e-9` leaves room for round-off and nothing else. It only decides
/// whether the growth's patience has started counting; the best verified gait is kept whatever
/// its size.
pub const MOVE_RESOLUTION: f64 = 1e-9;

/// How [`grow_phases`] raises `K`.
/// The last `K` a growth tries unless told ([`GrowOptions::max_phases`]; the one definition
/// of this default: the CLI's `--max-phases`, Python's `max_phases=` and a sweep's
/// `max_phases` leave it to the library).
pub const DEFAULT_MAX_PHASES: usize = 8;

/// Consecutive `K` without a gain that end a growth unless told ([`GrowOptions::patience`]).
pub const DEFAULT_PATIENCE: usize = 2;

#[derive(Debug, Clone, PartialEq)]
pub struct GrowOptions {
    /// First `K`.
    pub min_phases: usize,
    /// Last `K` tried.
    pub max_phases: usize,
    /// Stop after this many consecutive `K` without a gain, counted once `J_K` moves the crawler
    /// (above [`MOVE_RESOLUTION`] times the length scale; before,
    /// `K` is too small for any gait to move the crawler, e.g. one link needs 2 slip phases).
    /// The default is 2: plateaus `J_K = J_{K+1} < J_{K+2}` occur (a 4-block crawler with
    /// per-block friction had `J_3 = J_4 = 6.575 < J_5 = 6.600`).
    pub patience: usize,
    /// Wall-clock limit for the whole growth, seconds (from its start, within the job's
    /// deadline: [`crate::progress::within`]).
    pub time_limit: Option<f64>,
    /// A known gait to start from (e.g. the best structured gait, through
    /// [`phase_gait_of`](super::phase_gait_of)): the best gait before the first `K`, so every
    /// MILP takes it as its incumbent where it fits and as a cutoff where it has more slip
    /// phases than `K` ([`PhaseOptions::start`]). A `K` whose MILP proves that nothing of at
    /// most `K` slip phases beats it does not count towards `patience`. Default: none.
    pub start: Option<PhaseSolution>,
    /// Optional valid rows of every MILP.
    pub formulation: Formulation,
}

impl Default for GrowOptions {
    fn default() -> Self {
        GrowOptions {
            min_phases: 1,
            max_phases: DEFAULT_MAX_PHASES,
            patience: DEFAULT_PATIENCE,
            time_limit: None,
            start: None,
            formulation: Formulation::default(),
        }
    }
}

impl GrowOptions {
    /// Refuses options no growth can run with: `1 <= min_phases <= max_phases <= MAX_PHASES`,
    /// `patience >= 1`, a positive finite time limit.
    pub fn check(&self) -> Result<()> {
        check_time_limit(self.time_limit)?;
        if self.min_phases < 1 {
            return Err(Error::invalid("min_phases", 0, "must be at least 1"));
        }
        if self.max_phases < self.min_phases || self.max_phases > MAX_PHASES {
            return Err(Error::invalid(
                "max_phases",
                self.max_phases,
                format!("must be in {}..={MAX_PHASES}", self.min_phases),
            ));
        }
        if self.patience == 0 {
            return Err(Error::invalid("patience", 0, "must be at least 1"));
        }
        Ok(())
    }
}

/// One `K` of a growth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PhaseStep {
    /// `K`.
    pub phases: usize,
    /// Its optimum `J_K` (verified).
    pub objective: f64,
    /// The MILP's bound on `J_K`.
    pub bound: f64,
    /// Its gap.
    pub gap: f64,
    /// `"optimal_among_k_phases"`, `"time_limit"` or `"approximation_limit"`.
    pub status: MilpStatus,
    /// Wall time of this `K`, seconds.
    pub seconds: f64,
}

/// Why a growth stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GrowthStop {
    /// `patience` consecutive `K` brought no gain.
    NoGain,
    /// `max_phases` was reached while the value still improved (or was still 0).
    MaxPhases,
    /// v_m <= 0 for every shape rate (model analysis), so no gait moves the crawler forward and
    /// staying idle is globally optimal, for every `K`.
    NoForwardMotion,
    /// The time limit ended it.
    TimeLimit,
}

/// The result of [`grow_phases`].
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseGrowth {
    /// The best gait, certified for the last `K` solved to optimality (`best.phases`).
    pub best: PhaseSolution,
    /// Every `K` solved.
    pub table: Vec<PhaseStep>,
    /// Why it stopped.
    pub stop: GrowthStop,
}

/// Raises `K` from `min_phases` until `J_K` has not improved (by more than a relative `1e-7`,
/// or the outer-approximation tolerance `1e-6` with a quadratic cost, whose values are only
/// that accurate) for `patience` consecutive `K`, or `max_phases` or the time limit is reached
/// (module docs). The returned gait is the best found, and its certificate is that of the largest
/// `K` solved: `optimal_among_k_phases` when that `K` was solved to optimality (the gait has at
/// most that many slip phases, and no gait of that many does better than the bound), `time_limit`
/// with that `K`'s bound and gap when the limit cut its MILP short. `progress` sees each `K` as it
/// is solved.
pub fn grow_phases(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &GrowOptions,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<PhaseGrowth> {
    opts.check()?;
    crate::progress::within(opts.time_limit, || grow(crawler, problem, opts, progress))
}

/// [`grow_phases`], options checked, within the current deadline.
fn grow(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &GrowOptions,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<PhaseGrowth> {
    let mut best: Option<PhaseSolution> = opts.start.clone();
    let mut table = Vec::new();
    let mut without_gain = 0;
    let mut stop = GrowthStop::MaxPhases;
    // y' = v_m(z') (theory §3): when v_m <= 0 everywhere, J <= 0 for every gait.
    let idle = crawler.analyze().moves_forward == Some(false);
    // Whether a verified J_K moves the crawler: above the replay's resolution, relative to the
    // problem's own length scale (not to 1: lengths may be 1e-6 or 1e6).
    let resolution = MOVE_RESOLUTION * problem.length_scale(crawler);
    let moves = |j: f64| j > resolution;
    for k in opts.min_phases..=opts.max_phases {
        if crate::progress::out_of_time()? {
            stop = GrowthStop::TimeLimit;
            break;
        }
        let t0 = Instant::now();
        let phase_opts = PhaseOptions {
            start: best.clone(),
            cutoff: None,
            formulation: opts.formulation,
        };
        let s = match solve_phase_with(crawler, problem, k, None, &phase_opts) {
            Ok(s) => s,
            Err(Error::TimeLimit(_)) if best.is_some() => {
                stop = GrowthStop::TimeLimit;
                break;
            }
            Err(e) => return Err(e),
        };
        let step = PhaseStep {
            phases: k,
            objective: s.objective(),
            bound: s.certificate.bound,
            gap: s.certificate.gap,
            status: s.certificate.status,
            seconds: t0.elapsed().as_secs_f64(),
        };
        progress(&step);
        table.push(step);
        let timed_out = s.certificate.status == MilpStatus::TimeLimit;
        let gain = best.as_ref().map_or(f64::INFINITY, |b| {
            s.objective()
                - b.objective()
                - gain_tolerance(problem) * b.objective().abs().max(problem.length_scale(crawler))
        });
        if timed_out {
            match best.as_mut() {
                Some(b) if s.objective() <= b.objective() => {
                    // The best gait stays, but the claim is now this K's: a time limit with
                    // this K's bound (not "optimal" for the smaller K it was proven for, which
                    // read as if the growth had finished).
                    b.phases = s.phases;
                    b.certificate.bound = s.certificate.bound;
                    b.certificate.gap = ((s.certificate.bound - b.objective())
                        / b.objective().abs().max(1.0))
                    .max(0.0);
                    b.certificate.status = MilpStatus::TimeLimit;
                }
                _ => best = Some(s),
            }
            stop = GrowthStop::TimeLimit;
            break;
        }
        if idle {
            best = Some(s);
            stop = GrowthStop::NoForwardMotion;
            break;
        }
        if gain > 0.0 {
            without_gain = 0;
            best = Some(s);
        } else if best.as_ref().is_some_and(|b| !moves(b.objective())) {
            // Nothing moves yet (at the replay's resolution): K is still too small. A verified
            // gait better than the best so far is never overruled by the gain tolerance, which
            // is relative to the length scale and can exceed a small true optimum (one link
            // with T just above 2w/a: J* = 5e-8 against a tolerance of 3e-7).
            // The idle gait so far: kept, or replaced by a better one.
            keep_or_recertify(&mut best, s);
        } else {
            // The given start returned because nothing of at most K slip phases beats it:
            // the MILPs have not reached it yet, so this K is no plateau.
            let is_start = opts
                .start
                .as_ref()
                .is_some_and(|st| st.durations == s.durations && st.states == s.states);
            if !is_start {
                without_gain += 1;
            }
            // Better within the tolerance only, or the same gait.
            keep_or_recertify(&mut best, s);
            if without_gain >= opts.patience {
                stop = GrowthStop::NoGain;
                break;
            }
        }
    }
    let mut best = best.ok_or_else(|| {
        Error::TimeLimit(
            "phase growth: the time limit was reached before any feasible gait was found".into(),
        )
    })?;
    // The given start, never certified (the limit came before any K): say what is known.
    if best.certificate.bound.is_nan() {
        best = start_unproven(crawler, problem, &best, opts.min_phases);
    }
    Ok(PhaseGrowth { best, table, stop })
}

/// The best gait after solving a larger `K` with no gain beyond the tolerance: `s` when it is
/// better (with its own certificate), else the best so far, now certified for `s`'s `K` (its
/// bound, gap and status).
fn keep_or_recertify(best: &mut Option<PhaseSolution>, s: PhaseSolution) {
    match best.as_mut() {
        Some(b) if s.objective() <= b.objective() => {
            b.phases = s.phases;
            b.certificate.bound = s.certificate.bound;
            b.certificate.gap =
                ((s.certificate.bound - b.objective()) / b.objective().abs().max(1.0)).max(0.0);
            b.certificate.status = s.certificate.status;
        }
        Some(_) => *best = Some(s),
        None => {}
    }
}
