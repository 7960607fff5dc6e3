//! P_m of a general problem globally as a job ([`optimize_general`]): its settings, the
//! convergence table, a given start or, under a time limit, the default start (the local
//! method's answer on the same grid, as a crawler's P_m starts), the necessary conditions and
//! the chain's upper bound when asked.

use super::general::{add_bound_and_conditions, check_additions, general_problem};
use super::general_local::pm_default_start;
use super::general_start::given_start;
use crate::certify::bound::BoundSettings;
use crate::error::{Error, Result};
use crate::io::{GeneralAnswer, GeneralFile};
use crate::model::general::GeneralProblem;
use crate::optimal::general::{GeneralPm, Geometry};
use crate::optimal::StartRecord;

/// Settings of [`optimize_general`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralPmSettings {
    /// `m`: P_m on `2^m` steps (default [`crate::api::DEFAULT_M_DISCRETE`]).
    pub m: u32,
    /// Seconds for the job (`None`: no limit). Under a limit, without `start` or
    /// `convergence`, the first half of it goes to a default start: the local method's answer
    /// on the same grid, as a crawler's P_m starts (with a quadratic cost, which the local
    /// method does not take, where the first half is spent before it runs, or where it fails:
    /// the file's `[input]`, else where `A = 0` the phase gait, unsolved).
    pub time_limit: Option<f64>,
    /// Also check the necessary conditions on the optimum ([`crate::certify::general`];
    /// default false).
    pub certify: bool,
    /// Solve P_1, ..., P_m in turn and keep the table of `J_m`
    /// ([`crate::optimal::general::general_convergence`]; default false): the answer is the
    /// finest P_m solved, all within `time_limit`.
    pub convergence: bool,
    /// Also prove the crawler's upper bound over all periodic gaits (`chain_upper_bound`;
    /// default none): only for a problem that is a crawler's gait problem.
    pub bound: Option<BoundSettings>,
    /// Polish the answer of a quadratic cost on its fixed face pattern, a QP solved to the
    /// solvers' resolution ([`crate::optimal::polish`]; default
    /// [`crate::optimal::polish::POLISH_DEFAULT`], on): without it a control off the bounds
    /// of U is only as accurate as the MILP's outer approximation (about 1e-3), and the
    /// necessary conditions fail at that size.
    pub polish: bool,
    /// A start (default `None`: none, or under `time_limit` the local method's answer), as a
    /// crawler's P_m takes one: a general result of the
    /// same numbers of states and controls and the same period, its control averaged on the
    /// grid (as [`crate::api::GeneralLocalSettings::start`] reads it), whose process on the
    /// grid is the MILP's first incumbent ([`crate::optimal::general::solve_general_pm_from`]):
    /// the answer is never below it, and a time limit returns at least it. Recorded as the
    /// answer's `discrete_start`. Not with `convergence` (each `m` is solved afresh).
    pub start: Option<super::Start>,
    /// Rotations of each of the default start's own starts (default
    /// [`crate::api::DEFAULT_SHIFTS`]), as `shifts` of a crawler's P_m sets its default start's
    /// time shifts; read only where the default start runs (under `time_limit`, without
    /// `start` or `convergence`).
    pub shifts: usize,
    /// The largest `K` of the phase gait the default start grows (default `None`: the phase
    /// method's default, [`crate::api::GeneralPhaseSettings::max_phases_for`]), as
    /// `max_phases` bounds a crawler's P_m start; refused, naming it, where no phase gait
    /// starts (no default start; `A != 0`; the file's `[input]` starts instead).
    pub max_phases: Option<usize>,
}

impl Default for GeneralPmSettings {
    fn default() -> Self {
        GeneralPmSettings {
            m: crate::api::DEFAULT_M_DISCRETE,
            time_limit: None,
            certify: false,
            convergence: false,
            bound: None,
            polish: crate::optimal::polish::POLISH_DEFAULT,
            start: None,
            shifts: crate::api::DEFAULT_SHIFTS,
            max_phases: None,
        }
    }
}

/// The global optimum of P_m for a problem file ([`crate::optimal::general::discrete`]),
/// re-verified by the general simulator, with its necessary conditions when asked; with
/// `convergence`, the table of P_1..P_m too. Cancellable through `hooks` (within a HiGHS
/// callback); reports its stage, the MILP's incumbent and bound, and a `DiscreteSolved` event
/// per row of a convergence table.
pub fn optimize_general(
    file: &GeneralFile,
    s: &GeneralPmSettings,
    hooks: super::Hooks<'_>,
) -> Result<GeneralAnswer> {
    super::events::run_with(hooks, |em| pm_job(file, s, em))
}

/// [`optimize_general`] reporting to `em`: its stage announced once every setting is checked.
fn pm_job(
    file: &GeneralFile,
    s: &GeneralPmSettings,
    em: &super::events::Emitter<'_>,
) -> Result<GeneralAnswer> {
    let (p, g) = general_problem(file)?;
    let chain = check_additions(&p, s.bound.as_ref(), s.certify)?;
    crate::optimal::check_time_limit(s.time_limit)?;
    crate::optimal::check_shifts(s.shifts)?;
    let default_start = s.time_limit.is_some() && s.start.is_none() && !s.convergence;
    if let (Some(k), false) = (s.max_phases, default_start) {
        return Err(Error::invalid(
            "max_phases",
            k,
            "applies only to the default start (under time_limit, without start or convergence)",
        ));
    }
    if s.convergence && s.start.is_some() {
        return Err(Error::invalid(
            "start",
            "given",
            "does not apply to convergence (each m is solved afresh)",
        ));
    }
    em.stage(if s.convergence {
        format!("P_1..P_{} of the general problem, global MILPs", s.m)
    } else {
        format!(
            "P_{} of the general problem ({} steps), global MILP",
            s.m,
            1u64 << s.m.min(63)
        )
    });
    let (solution, convergence, started) = if s.convergence {
        let mut progress = |row: &crate::optimal::ConvergenceRow| {
            em.send(super::Event::DiscreteSolved(row.clone()))
        };
        let (table, finest) = crate::progress::within(s.time_limit, || {
            crate::optimal::general::general_convergence(&p, &g, s.m, s.polish, &mut progress)
        })?;
        (finest, Some(table), None)
    } else {
        // `m` first: a start is averaged on a grid of `2^m` steps.
        crate::optimal::general::check_general_pm(&p, &g, s.m)?;
        let (sol, started) =
            crate::progress::within(s.time_limit, || solve_started(file, &p, &g, s, em))?;
        (sol, None, started)
    };
    let mut r = GeneralAnswer::discrete(file, p.period, solution);
    r.records.convergence = convergence;
    r.discrete_start = started;
    let bound = chain.as_ref().zip(s.bound.as_ref());
    add_bound_and_conditions(&p, &mut r, bound, s.certify, em)?;
    Ok(r)
}

/// P_m from the start given, else under a time limit from the default one (the local
/// method's answer on this grid from `shifts` rotations of its starts, within the first half
/// of the limit: [`pm_default_start`]), else without one; the answer and the start's record.
fn solve_started(
    file: &GeneralFile,
    p: &GeneralProblem,
    g: &Geometry,
    s: &GeneralPmSettings,
    em: &super::events::Emitter<'_>,
) -> Result<(GeneralPm, Option<StartRecord>)> {
    use crate::optimal::general::{solve_general_pm_from, solve_general_pm_with};
    let start = match (&s.start, s.time_limit) {
        (Some(st), _) => Some(given_start(st, p, s.m)?),
        (None, Some(_)) => {
            let local = super::GeneralLocalSettings {
                m: s.m,
                shifts: s.shifts,
                max_phases: s.max_phases,
                ..Default::default()
            };
            pm_default_start(file, p, g, &local, em)?
        }
        (None, None) => None,
    };
    let Some((grid, name)) = start else {
        return Ok((solve_general_pm_with(p, g, s.m, s.polish)?, None));
    };
    em.stage(format!("P_{} from the start {name}", s.m));
    match solve_general_pm_from(p, g, s.m, s.polish, &grid) {
        Ok((sol, j)) => {
            let record = StartRecord {
                start: name,
                start_objective: j,
            };
            Ok((sol, Some(record)))
        }
        // A default start that is no process of the grid (the phase gait or the file's input
        // averaged on it): a note, and P_m without a start.
        Err(Error::InvalidParameter { field, reason, .. })
            if s.start.is_none() && field.starts_with("start") =>
        {
            em.send(super::Event::Note(format!(
                "the start {name} is no start of P_{} ({field}: {reason}); solving it without \
                 one",
                s.m
            )));
            Ok((solve_general_pm_with(p, g, s.m, s.polish)?, None))
        }
        Err(e) => Err(e),
    }
}
