//! Start gaits: where the local methods (the LPCC active-set method on P_m and the local search
//! over slip-mode sequences) and the P_m MILP begin when the user gives no start.
//!
//! A start need not be certified, only good and quick:
//! - [`phase_start`]: the phase optimum (theory §7) with `K` grown only to the first `K` without a
//!   gain (patience 1), within half the time limit. It is the default start of the local
//!   methods: they end where their start leads, and the phase optimum is the best
//!   continuous-time gait there is to lead them.
//! - [`discrete_start`]: under a time limit, the local method's gait on the same grid, so that
//!   a MILP cut short returns at least a local optimum of P_m. Without a time limit there is
//!   none, because a start does not shorten the proof (three blocks on 16 steps: 12.0 s from
//!   its own optimum, 10.3 s without).
//! - [`StartGait::from_result`]: a stored result, checked to be of this crawler and period.
//!
//! The policies report what they do through [`StartEvent`]s, so that a front end can show
//! progress and tell the user when a start could not be had (a start is only a hint: a failure
//! to compute one is a note, not an error, where the solve can go on without it).

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::{
    check_shifts, check_size, grow_phases, phase_gait_of, solve_discrete_local_shifted, Cost,
    CrawlerParams, GaitProblem, GaitResult, GrowOptions, PhaseSolution, PhaseStep, MAX_LOCAL_M,
    MAX_M,
};

/// What a start policy is doing, for a progress display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartEvent<'a> {
    /// A stage begins (e.g. "local LPCC method on P_6").
    Stage(&'a str),
    /// One `K` of the phase growth was solved.
    Phase(&'a PhaseStep),
    /// A start could not be had, and the solve goes on with another or without one; the text
    /// says which and why.
    Note(&'a str),
}

/// A start gait and where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct StartGait {
    /// Its origin in words, as recorded in results: e.g. `phase (K = 5)`, or
    /// `local on P_6, from phase (K = 5) shifted by 1.25`, or `phase (start.json)`.
    pub origin: String,
    /// The gait, with the result of the method that computed it.
    pub result: GaitResult,
}

impl StartGait {
    /// The gait of a stored result `r` (read from `what`, e.g. a path) as a start for
    /// `crawler` and `problem`: refused when it was computed for another crawler or period, or
    /// when a link's rate exceeds this problem's bound `a_l` (beyond the readers' relative
    /// [`INPUT_TOL`](crate::optimal::consistency::INPUT_TOL)): a gait of a problem with faster
    /// actuators is no gait of this one, and the local method's first LP had no feasible point
    /// ("an LP of fixed branches has no feasible point").
    pub fn from_result(
        crawler: &Crawler,
        problem: &GaitProblem,
        r: GaitResult,
        what: &str,
    ) -> Result<Self> {
        if r.crawler != CrawlerParams::of(crawler) || r.problem.period != problem.period {
            return Err(Error::invalid(
                "start",
                what,
                "was computed for another crawler or period",
            ));
        }
        let tol = crate::optimal::consistency::INPUT_TOL;
        for (j, u) in r.gait.controls.iter().enumerate() {
            for ((l, v), a) in u.iter().enumerate().zip(&problem.rate_bound) {
                if v.abs() > a * (1.0 + tol) {
                    return Err(Error::invalid(
                        "start",
                        what,
                        format!(
                            "its rate solution.controls[{j}][{l}] = {v} exceeds this problem's \
                             rate bound a_{} = {a}",
                            l + 1
                        ),
                    ));
                }
            }
        }
        Ok(StartGait {
            origin: format!("{} ({what})", r.head.method),
            result: r,
        })
    }

    /// The knot times of its actuation.
    pub fn times(&self) -> &[f64] {
        &self.result.gait.times
    }

    /// The actuator lengths at [`times`](Self::times), one row per knot.
    pub fn lengths(&self) -> &[Vec<f64>] {
        &self.result.gait.lengths
    }

    /// The gait in phase form ([`phase_gait_of`]): its pieces with the spring-force increments
    /// `U_j = k (L_(j+1) - L_j)` per link, played by the exact simulator into phases, so that
    /// the phase MILP can take it as its first incumbent or its cutoff
    /// ([`GrowOptions::start`](crate::optimal::GrowOptions::start)).
    pub fn phase_form(&self, crawler: &Crawler, problem: &GaitProblem) -> Result<PhaseSolution> {
        let g = &self.result.gait;
        let k = crawler.stiffness();
        let increments: Vec<Vec<f64>> = g
            .lengths
            .windows(2)
            .map(|w| (0..k.len()).map(|l| k[l] * (w[1][l] - w[0][l])).collect())
            .collect();
        phase_gait_of(crawler, problem, &g.durations, &increments)
    }
}

/// The default start of the local methods: the phase optimum with `K` grown as in `growth` but
/// with patience 1 (a start need not be certified) and within half of the time left (of
/// `growth.time_limit` from now, within the job's deadline: [`crate::progress::share`]; when
/// that is spent, the best gait found so far; a time-limit error when there is none).
pub fn phase_start(
    crawler: &Crawler,
    problem: &GaitProblem,
    growth: &GrowOptions,
    progress: &mut dyn FnMut(StartEvent),
) -> Result<StartGait> {
    growth.check()?;
    check_size(crawler, growth.max_phases, "max_phases", growth.max_phases)?;
    let opts = GrowOptions {
        time_limit: None,
        patience: 1,
        ..growth.clone()
    };
    progress(StartEvent::Stage(&format!(
        "start: phase gait, K = {}",
        opts.min_phases
    )));
    let g = crate::progress::within(growth.time_limit, || {
        crate::progress::share(0.5, || {
            grow_phases(crawler, problem, &opts, &mut |st| {
                progress(StartEvent::Phase(st))
            })
        })
    })?;
    Ok(StartGait {
        origin: format!("phase (K = {})", g.best.phases),
        result: GaitResult::from_phase(crawler, problem, &g.best),
    })
}

/// The origin of a gait searched from `origin` shifted in time by `shift` (as
/// [`solve_discrete_local_shifted`] returns it): `origin` itself when the shift is 0.
pub fn shifted_origin(origin: &str, shift: f64) -> String {
    if shift == 0.0 {
        origin.to_string()
    } else {
        format!("{origin} shifted by {shift}")
    }
}

/// The default start of the P_m MILP on `2^m` steps, under `growth.time_limit`: the phase
/// start ([`phase_start`], within a quarter of the limit) improved by the local method on the
/// same grid from `shifts` time shifts of it (within what is left of the first half). The phase
/// gait itself is the start with a quadratic cost (the local method has none), beyond the local
/// method's grids (`m > MAX_LOCAL_M`), when the first half is spent, or when the local method
/// fails.
///
/// `None` without a time limit (a start does not shorten the proof), with a total-variation
/// bound (phase gaits cannot express it), or when no phase start could be had in time (a
/// [`StartEvent::Note`] says why). Bad options (`growth` refused by [`GrowOptions::check`],
/// `shifts` refused by [`check_shifts`], a model beyond [`check_size`]) are errors, not notes.
pub fn discrete_start(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    shifts: usize,
    growth: &GrowOptions,
    progress: &mut dyn FnMut(StartEvent),
) -> Result<Option<StartGait>> {
    growth.check()?;
    check_shifts(shifts)?;
    if m <= MAX_M {
        // (An m beyond the grids is refused by the MILP's own range check.)
        check_size(crawler, 1 << m, "m", m)?;
    }
    check_size(crawler, growth.max_phases, "max_phases", growth.max_phases)?;
    if growth.time_limit.is_none() || problem.max_total_variation.is_some() {
        return Ok(None);
    }
    // The first half of the limit; phase_start grows K within half of it: a quarter.
    crate::progress::within(growth.time_limit, || {
        crate::progress::share(0.5, || {
            start_in_half(crawler, problem, m, shifts, growth, progress)
        })
    })
}

/// [`discrete_start`], options checked, within its half of the limit.
fn start_in_half(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    shifts: usize,
    growth: &GrowOptions,
    progress: &mut dyn FnMut(StartEvent),
) -> Result<Option<StartGait>> {
    let phase = match phase_start(crawler, problem, growth, progress) {
        Ok(s) => s,
        // A cancelled job ends; it does not go on without a start.
        Err(Error::Cancelled) => return Err(Error::Cancelled),
        Err(e) => {
            progress(StartEvent::Note(&format!(
                "no start gait ({e}); solving P_{m} without one"
            )));
            return Ok(None);
        }
    };
    if problem.cost != Cost::None || m > MAX_LOCAL_M || crate::progress::out_of_time()? {
        return Ok(Some(phase));
    }
    progress(StartEvent::Stage(&format!(
        "start: local LPCC method on P_{m}"
    )));
    match solve_discrete_local_shifted(crawler, problem, m, phase.times(), phase.lengths(), shifts)
    {
        Ok((s, shift)) => {
            let origin = shifted_origin(&phase.origin, shift);
            Ok(Some(StartGait {
                origin: format!("local on P_{m}, from {origin}"),
                result: GaitResult::from_local(crawler, problem, &s, &origin),
            }))
        }
        Err(Error::Cancelled) => Err(Error::Cancelled),
        Err(e) => {
            progress(StartEvent::Note(&format!(
                "the local method failed ({e}); the MILP starts from the phase gait"
            )));
            Ok(Some(phase))
        }
    }
}
