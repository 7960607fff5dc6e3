//! Start gaits: where the local methods (the LPCC active-set method on P_m and the local search
//! over slip-mode sequences) and the P_m MILP begin when the user gives no start.
//!
//! A start need not be certified, only good and quick:
//! - [`phase_start`]: the phase optimum (theory §7) with `K` grown only to the first `K` without a
//!   gain (patience 1), within half the time limit. It is the default start of the local
//!   methods: they end where their start leads, and the phase optimum is the best
//!   continuous-time gait there is to lead them.
//! - [`pm_start`]: the default start of P_m under a time limit, one policy for a crawler's
//!   P_m and (P)'s, each kind bringing its own start gait and local method
//!   ([`StartKernels`]): the local method's gait on the same grid, so that a MILP cut short
//!   returns at least a local optimum of P_m; [`discrete_start`] is the crawler's. Without a
//!   time limit there is none, because a start does not shorten the proof (three blocks on 16
//!   steps: 12.0 s from its own optimum, 10.3 s without).
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

/// The default start of the P_m MILP on `2^m` steps, under `growth.time_limit`: [`pm_start`]
/// with the crawler's kernels, within the first half of the limit. The gait that starts the
/// local method is the phase start ([`phase_start`], within a quarter of the limit); the local
/// method on the same grid improves it from `shifts` time shifts of it (within what is left of
/// the first half). The phase gait itself is the start with a quadratic cost (the local method
/// has none), beyond the local method's grids (`m > MAX_LOCAL_M`), when the first half is
/// spent, or when the local method fails; a [`StartEvent::Note`] says which.
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
    let mut kernels = CrawlerStart {
        crawler,
        problem,
        m,
        shifts,
        growth,
        progress,
    };
    let start = crate::progress::within(growth.time_limit, || pm_start(&mut kernels, m))?;
    Ok(start.map(|s| StartGait {
        origin: s.name,
        result: s.gait,
    }))
}

/// A start of P_m of some kind ([`StartKernels::Gait`]), with its name as results record it
/// (`discrete_start.start`: `"phase (K = 5)"`, `"local on P_6, from phase (K = 5) shifted by
/// 1.25"`, `"input"`, `"local on P_3, from input"`).
#[derive(Debug, Clone, PartialEq)]
pub struct Named<G> {
    /// The start.
    pub gait: G,
    /// Its name.
    pub name: String,
}

/// What a kind of problem supplies to the one default-start policy of P_m ([`pm_start`]): its
/// own start gait and local method (a crawler's are the chain's phase growth and its LPCC method
/// on the crawler's grid; (P)'s are its `[input]` or its phase gait where `A = 0`, and its
/// active-set method), behind one interface, as each cone of a conic solver brings its own
/// operations to one solver loop.
pub trait StartKernels {
    /// A start of P_m: a crawler's gait, (P)'s controls on the grid.
    type Gait;
    /// The gait that starts the local method. `Ok(None)` where the kind has none and its local
    /// method starts from its own fallbacks ((P) with `A != 0`: square waves); an error where
    /// it could not be had (a note says so and P_m goes without a start).
    fn gait(&mut self) -> Result<Option<Named<Self::Gait>>>;
    /// Why the local method cannot run on this grid (a cost f2, a grid beyond its range);
    /// `None` where it can.
    fn local_refused(&self) -> Option<String>;
    /// The local method's answer on the grid from `gait` (and its time shifts) or, without
    /// one, from the kind's fallback starts (`Ok(None)` where it has none).
    fn local(&mut self, gait: Option<&Named<Self::Gait>>) -> Result<Option<Named<Self::Gait>>>;
    /// What a start gait of [`Self::gait`] is, in a note's words (`"phase gait"`, `"file's
    /// [input]"`).
    fn what(gait: &Self::Gait) -> &'static str;
    /// Tells the user how the start went.
    fn note(&mut self, text: &str);
}

/// The default start of P_m on `2^m` steps under a time limit, for every kind of problem
/// (written once; each kind's [`StartKernels`]), within the first half of the time left
/// ([`crate::progress::share`]), so that a MILP cut short returns at least a local optimum of
/// P_m: the local method's answer on the same grid from the kind's start gait. Where the local
/// method cannot run (`local_refused`), the first half is spent, or it fails, the start gait
/// itself, unsolved, as the MILP's first incumbent; none where there is no gait either. A
/// start is only a hint: every failure is a note and P_m goes on without it, except a cancelled
/// job, which ends.
pub fn pm_start<K: StartKernels>(k: &mut K, m: u32) -> Result<Option<Named<K::Gait>>> {
    crate::progress::share(0.5, || {
        let gait = match k.gait() {
            Ok(gait) => gait,
            Err(Error::Cancelled) => return Err(Error::Cancelled),
            Err(e) => {
                k.note(&format!("no start gait ({e}); solving P_{m} without one"));
                return Ok(None);
            }
        };
        let why = match k.local_refused() {
            Some(why) => why,
            None if crate::progress::out_of_time()? => {
                "the first half of the time limit is spent".to_string()
            }
            None => match k.local(gait.as_ref()) {
                Ok(Some(found)) => return Ok(Some(found)),
                Ok(None) => "the local method has no start".to_string(),
                Err(Error::Cancelled) => return Err(Error::Cancelled),
                Err(e) => format!("the local method failed: {e}"),
            },
        };
        Ok(unsolved(k, gait, m, &why))
    })
}

/// P_m's default start where the local method cannot make it (`why`): the gait that would
/// have started that method, itself, or none; a note says which.
fn unsolved<K: StartKernels>(
    k: &mut K,
    gait: Option<Named<K::Gait>>,
    m: u32,
    why: &str,
) -> Option<Named<K::Gait>> {
    match &gait {
        None => k.note(&format!(
            "no start for P_{m} ({why}; no gait to start from); solving it without one"
        )),
        Some(g) => k.note(&format!(
            "P_{m} starts from the {} itself ({why})",
            K::what(&g.gait)
        )),
    }
    gait
}

/// The crawler's [`StartKernels`]: the phase start and the LPCC method on the crawler's grid.
struct CrawlerStart<'a> {
    crawler: &'a Crawler,
    problem: &'a GaitProblem,
    m: u32,
    shifts: usize,
    growth: &'a GrowOptions,
    progress: &'a mut dyn FnMut(StartEvent),
}

impl StartKernels for CrawlerStart<'_> {
    type Gait = GaitResult;

    fn gait(&mut self) -> Result<Option<Named<GaitResult>>> {
        let phase = phase_start(self.crawler, self.problem, self.growth, &mut *self.progress)?;
        Ok(Some(Named {
            gait: phase.result,
            name: phase.origin,
        }))
    }

    fn local_refused(&self) -> Option<String> {
        if self.problem.cost != Cost::None {
            Some("the local method takes no cost f2".into())
        } else if self.m > MAX_LOCAL_M {
            Some(format!("the local method's grids end at m = {MAX_LOCAL_M}"))
        } else {
            None
        }
    }

    fn local(&mut self, gait: Option<&Named<GaitResult>>) -> Result<Option<Named<GaitResult>>> {
        let Some(gait) = gait else {
            return Ok(None);
        };
        let m = self.m;
        (self.progress)(StartEvent::Stage(&format!(
            "start: local LPCC method on P_{m}"
        )));
        let (crawler, problem) = (self.crawler, self.problem);
        let g = &gait.gait.gait;
        let (s, shift) =
            solve_discrete_local_shifted(crawler, problem, m, &g.times, &g.lengths, self.shifts)?;
        let origin = shifted_origin(&gait.name, shift);
        Ok(Some(Named {
            name: format!("local on P_{m}, from {origin}"),
            gait: GaitResult::from_local(crawler, problem, &s, &origin),
        }))
    }

    fn what(_: &GaitResult) -> &'static str {
        "phase gait"
    }

    fn note(&mut self, text: &str) {
        (self.progress)(StartEvent::Note(text))
    }
}
