//! The optimisation job: settings in, one verified (and optionally certified) result out.

use super::events::{run_with, Emitter, Event, Hooks};
use super::settings::{GaitMethod, OptimizeSettings, Plan, Start};
use crate::certify::{certify_result, NecessaryConditions};
use crate::error::{Error, Result};
use crate::io::{GaitAnswer, ResultFile};
use crate::model::Crawler;
use crate::optimal::chain::{chain_starts, search_chain_multi, ChainOptions, DEFAULT_STARTS};
use crate::optimal::structured::{
    best_structured, structured_gaits, StructuredOptions, StructuredSearch,
};
use crate::optimal::{
    discrete_convergence, discrete_start, grow_phases, phase_start, search_sequences,
    shifted_origin, slip_sequence, solve_discrete_global_with, solve_discrete_local_shifted,
    solve_phase_with, GaitProblem, GaitResult, MilpStatus, PhaseOptions, PhaseSolution, StartGait,
    StartRecord, StructuredRecord, MAX_PHASES,
};

/// The answer of [`optimize`]: the gait result (verified by simulation, with its certificate
/// and status), the necessary conditions when asked for, and the notes the job sent. A file
/// writes it as [`crate::io::GaitAnswer`] ([`Optimized::answer`]); the notes are the job's,
/// not the result's.
#[derive(Clone, Debug, PartialEq)]
pub struct Optimized {
    /// The result.
    pub result: GaitResult,
    /// The necessary conditions of Theorem 2.2 on the gait ([`OptimizeSettings::certify`]).
    pub necessary_conditions: Option<NecessaryConditions>,
    /// Notes on how the job went (e.g. a start that could not be had).
    pub notes: Vec<String>,
}

impl Optimized {
    /// The result and its conditions as a result file holds them, and the notes.
    pub fn answer(self) -> (GaitAnswer, Vec<String>) {
        let answer = GaitAnswer {
            result: self.result,
            necessary_conditions: self.necessary_conditions,
        };
        (answer, self.notes)
    }
}

/// An optimal gait of `problem` for `crawler` under `settings` (every method of the paper's
/// problem (P), §§5–7: phase MILPs, P_m global and local, sequence search). Every answer is
/// re-verified by simulation before it is returned; `settings.certify` adds the necessary
/// conditions (Theorem 2.2). Progress and cancellation go through `hooks`.
pub fn optimize(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    hooks: Hooks<'_>,
) -> Result<Optimized> {
    run_with(hooks, |em| optimize_in(crawler, problem, settings, em))
}

/// [`optimize`] within a job that is running already (its emitter `em`): the general problem's
/// chain methods run the crawler's job inside their own. The answer's notes are the
/// emitter's, so they include any the outer job sent before. Errors name the settings as
/// `settings.naming` spells them.
pub(super) fn optimize_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    em: &Emitter<'_>,
) -> Result<Optimized> {
    optimize_named(crawler, problem, settings, em).map_err(|e| settings.naming.name_settings(e))
}

/// [`optimize_in`], its errors naming the fields as the library does.
fn optimize_named(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    em: &Emitter<'_>,
) -> Result<Optimized> {
    crawler.require_unique()?;
    // The scales every optimiser honours (and every reader of a result checks), whatever the
    // method: the chain method builds no model but its answer must read back.
    problem.check_scales(crawler)?;
    let plan = settings.plan(crawler, problem)?;
    crate::progress::check()?;
    // The job's deadline: `time_limit` from here, over the method and its start (the
    // bound has its own, `bound.time_limit`, after it).
    let mut result = crate::progress::within(settings.time_limit, || {
        solve(crawler, problem, settings, &plan, em)
    })?;
    if plan.method != GaitMethod::Discrete {
        result = at_least_idle(crawler, problem, &plan, result, em)?;
    }
    if let Some(b) = &settings.bound {
        em.stage("proving an upper bound over all periodic gaits");
        let ub = crate::certify::bound::upper_bound(crawler, problem, b)?;
        ub.check_bounds(result.head.objective, problem.j_floor(crawler))?;
        result.head.certificate.upper_bound = Some(ub);
    }
    let necessary_conditions = if settings.certify {
        em.stage("checking the necessary conditions");
        Some(certify_result(&result, "optimize")?)
    } else {
        None
    };
    Ok(Optimized {
        result,
        necessary_conditions,
        notes: em.notes(),
    })
}

/// The method of `plan` run, after the structured gaits (every method but the discrete P_m,
/// whose answer is the optimum of its grid problem): the best structured gait is the start of
/// the chain method, a candidate start of the local methods, and the floor of the answer
/// (the method's answer when it is at least as good, else the structured gait, recording
/// what the method found in [`GaitResult::structured`]). A method that ends at the time limit
/// without a gait returns the structured gait. Runs within the job's deadline.
fn solve(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    plan: &Plan,
    em: &Emitter<'_>,
) -> Result<GaitResult> {
    if plan.method == GaitMethod::Discrete {
        return solve_method(crawler, problem, settings, plan, None, em);
    }
    em.stage("structured gaits (travelling, alternating and grouped waves)");
    let floor = best_structured(crawler, problem, &StructuredOptions::default())?;
    if let Some(f) = &floor {
        em.stage(format!(
            "best structured gait: J = {:.6} ({}; {} gaits simulated in {:.2} s)",
            f.objective,
            f.best.origin,
            f.rows.len(),
            f.seconds
        ));
    }
    // What is left of the time limit goes to the method.
    if crate::progress::out_of_time()? {
        if let Some(f) = floor {
            let mut r = floor_answer(f, plan);
            r.head.status = MilpStatus::TimeLimit;
            if let Some(s) = r.records.structured.as_mut() {
                s.replaced = Some("the time limit was spent on the structured gaits".into());
            }
            return Ok(r);
        }
        return Err(Error::TimeLimit(
            "the time limit was reached while evaluating the structured gaits".into(),
        ));
    }
    let answer = solve_method(crawler, problem, settings, plan, floor.as_ref(), em);
    let Some(f) = floor else {
        return answer;
    };
    let r = match answer {
        Ok(r) => r,
        Err(Error::TimeLimit(e)) => {
            let mut r = floor_answer(f, plan);
            r.head.status = MilpStatus::TimeLimit;
            if let Some(s) = r.records.structured.as_mut() {
                s.replaced = Some(format!("the method found no gait: {e}"));
            }
            return Ok(r);
        }
        Err(e) => return Err(e),
    };
    let tol = 1e-9 * problem.length_scale(crawler).max(f.objective.abs());
    if r.head.objective >= f.objective - tol {
        return Ok(r);
    }
    em.send(Event::Note(format!(
        "the {} method's gait (J = {:.6}) is below the best structured gait (J = {:.6}), \
         which is returned",
        plan.method.name(),
        r.head.objective,
        f.objective
    )));
    let mut out = floor_answer(f, plan);
    if r.head.status == MilpStatus::TimeLimit {
        // The method was cut by the time limit: so is the job, whichever gait it returns.
        out.head.status = MilpStatus::TimeLimit;
    }
    let what = match (
        r.head.certificate.kind.as_str(),
        r.head.certificate.phases,
        r.head.certificate.bound,
    ) {
        ("global_k_phases", Some(k), Some(b)) => format!(
            "{}: J = {} among gaits of at most {k} slip phases (status {}, bound {b} on that \
             class)",
            r.head.method,
            r.head.objective,
            r.head.status.as_str()
        ),
        (_, _, Some(b)) => format!(
            "{}: J = {} (status {}, bound {b} on its problem)",
            r.head.method,
            r.head.objective,
            r.head.status.as_str()
        ),
        _ => format!(
            "{}: J = {} (status {})",
            r.head.method,
            r.head.objective,
            r.head.status.as_str()
        ),
    };
    if let Some(s) = out.records.structured.as_mut() {
        s.replaced = Some(format!("{what}, below the structured gait"));
    }
    Ok(out)
}

/// The idle gait (`u = 0`, `J = 0`, a gait of every class) in place of an answer below it: a
/// method cut short by the time limit (or a local one stopped in a costly gait, with every
/// structured gait costing more than it moves) may end below 0 (six blocks with a quadratic
/// cost, `--phases 4 --time-limit 10`: J = -0.084). The idle answer keeps the claim's status
/// where it was `time_limit` (the job was cut short) and records what the method found.
/// Not for the discrete method, whose P_m answer is the optimum of its own grid problem.
fn at_least_idle(
    crawler: &Crawler,
    problem: &GaitProblem,
    plan: &Plan,
    r: GaitResult,
    em: &Emitter<'_>,
) -> Result<GaitResult> {
    let tol = 1e-9 * problem.length_scale(crawler);
    if r.head.objective >= -tol {
        return Ok(r);
    }
    em.send(Event::Note(format!(
        "the {} method's gait has J = {:.6e} < 0: the idle gait (u = 0, J = 0) is returned",
        plan.method.name(),
        r.head.objective
    )));
    let n = crawler.links();
    let mut idle = crate::optimal::structured::knots_result(
        crawler,
        problem,
        vec![0.0, 0.5 * problem.period],
        vec![vec![0.0; n]; 2],
        "the idle gait (u = 0)",
    )?;
    if matches!(plan.method, GaitMethod::Sequence | GaitMethod::Chain) {
        idle.head.method = plan.method.name().into();
    }
    if r.head.status == MilpStatus::TimeLimit {
        idle.head.status = MilpStatus::TimeLimit;
    }
    if let Some(s) = idle.records.structured.as_mut() {
        s.replaced = Some(format!(
            "{}: J = {} (status {}), below the idle gait",
            r.head.method,
            r.head.objective,
            r.head.status.as_str()
        ));
    }
    Ok(idle)
}

/// The best structured gait `f` as the job's answer, when the method found none or a worse
/// one. Its envelope names the method that ran where that method answers with exact phase
/// gaits (sequence, chain; [`GaitResult::is_phase_gait`]); the local and discrete methods
/// answer with P_m processes, so a structured gait in their place is written as `phase`.
fn floor_answer(f: StructuredSearch, plan: &Plan) -> GaitResult {
    let mut r = f.best.result;
    if matches!(plan.method, GaitMethod::Sequence | GaitMethod::Chain) {
        r.head.method = plan.method.name().into();
    }
    r
}

/// The method of `plan` run, `floor` the best structured gait (none for the discrete method),
/// within the job's deadline (its steps are given no time limit of their own; a start gait's
/// share is [`phase_start`]'s and [`discrete_start`]'s).
fn solve_method(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    plan: &Plan,
    floor: Option<&StructuredSearch>,
    em: &Emitter<'_>,
) -> Result<GaitResult> {
    let m = plan.m;
    let start = settings.start.as_ref();
    match plan.method {
        GaitMethod::Chain => solve_chain(crawler, problem, floor, em),
        GaitMethod::Local => {
            let from = start_gait(start, crawler, problem, plan, floor, em)?;
            em.stage(format!("local LPCC method on P_{m} ({} steps)", 1u64 << m));
            let (s, shift) = solve_discrete_local_shifted(
                crawler,
                problem,
                m,
                from.times(),
                from.lengths(),
                plan.shifts,
            )?;
            let origin = shifted_origin(&from.origin, shift);
            Ok(GaitResult::from_local(crawler, problem, &s, &origin))
        }
        GaitMethod::Sequence => solve_sequence(crawler, problem, settings, plan, floor, em),
        GaitMethod::Phase | GaitMethod::Auto => {
            // The best structured gait in phase form: the MILPs' first incumbent where it fits
            // K, their cutoff where it has more slip phases (a K no gait of which beats it is
            // settled at once).
            let start = floor.and_then(|f| match f.best.phase_form(crawler, problem) {
                Ok(p) => Some(p),
                Err(e) => {
                    em.send(Event::Note(format!(
                        "the best structured gait is not a start of the phase MILP: {e}"
                    )));
                    None
                }
            });
            let mut r = solve_phase_method(crawler, problem, settings, plan, start.clone(), em)?;
            // The MILPs kept their start: the answer is the structured gait, said so.
            if let (Some(f), Some(p)) = (floor, &start) {
                if r.gait.durations == p.durations && r.gait.states == p.states {
                    r.records.structured = Some(StructuredRecord {
                        origin: f.best.origin.clone(),
                        replaced: None,
                    });
                }
            }
            Ok(r)
        }
        GaitMethod::Discrete if settings.convergence => {
            em.stage("m = 1");
            let (table, s) = discrete_convergence(crawler, problem, m, &mut |row| {
                em.send(Event::DiscreteSolved(row.clone()))
            })?;
            let mut r = GaitResult::from_discrete(crawler, problem, &s);
            r.records.convergence = Some(table);
            Ok(r)
        }
        GaitMethod::Discrete => {
            let from = match start {
                Some(s) => Some(start_of(s, crawler, problem)?),
                None => discrete_start(crawler, problem, m, plan.shifts, &plan.growth, &mut |e| {
                    em.start_event(e)
                })?,
            };
            started_in_time(&format!("P_{m}: "))?;
            em.stage(format!("solving P_{m} ({} steps)", 1u64 << m));
            let s = solve_discrete_global_with(
                crawler,
                problem,
                m,
                from.as_ref().map(|f| (f.times(), f.lengths())),
                settings
                    .polish
                    .unwrap_or(crate::optimal::polish::POLISH_DEFAULT),
            )?;
            let mut r = GaitResult::from_discrete(crawler, problem, &s);
            r.discrete_start = from.zip(s.start_objective).map(|(f, j)| StartRecord {
                start: f.origin,
                start_objective: j,
            });
            Ok(r)
        }
    }
}

/// The chain method: a pattern search over the chain's ramp gaits from the best structured
/// gaits (`floor`; none is an error: the method has no start). Written as method `chain`; a
/// ramp gait below 0 gives way to the idle gait ([`at_least_idle`]).
fn solve_chain(
    crawler: &Crawler,
    problem: &GaitProblem,
    floor: Option<&StructuredSearch>,
    em: &Emitter<'_>,
) -> Result<GaitResult> {
    let Some(f) = floor else {
        return Err(Error::Numerical(
            "no structured gait reached a periodic orbit: the chain method has no start".into(),
        ));
    };
    let gaits = structured_gaits(crawler, f.lags);
    let values: Vec<Option<f64>> = f.rows.iter().map(|r| r.objective).collect();
    let starts = chain_starts(&gaits, &values, problem.j_floor(crawler), DEFAULT_STARTS);
    em.stage(format!(
        "chain pattern search over {} ramp parameters, from the {} best structured \
         gaits",
        5 * crawler.links(),
        starts.len()
    ));
    let s = search_chain_multi(
        crawler,
        problem,
        &starts,
        &ChainOptions::default(),
        &mut |st| em.send(Event::ChainSweep(st.clone())),
    )?;
    // A ramp gait below 0 (every ramp paying more than it moves the crawler) gives way to the
    // idle gait in `at_least_idle`.
    let mut r = s.result;
    r.head.method = GaitMethod::Chain.name().into();
    Ok(r)
}

/// The sequence method: a local search over cyclic sequences of `settings.phases` slip modes
/// (default: the start's slip phases plus two, at most [`MAX_PHASES`]) from the start gait
/// ([`start_gait`]), refused when the start has more slip phases than that, naming the setting
/// the user gave.
fn solve_sequence(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    plan: &Plan,
    floor: Option<&StructuredSearch>,
    em: &Emitter<'_>,
) -> Result<GaitResult> {
    let start = settings.start.as_ref();
    // With K given, a structured gait of more slip modes cannot start the search.
    let floor = floor.filter(|f| {
        settings
            .phases
            .is_none_or(|k| slip_sequence(&f.best.result.gait.slip).len() <= k)
    });
    let from = start_gait(start, crawler, problem, plan, floor, em)?;
    let (seq, origin) = (slip_sequence(&from.result.gait.slip), from.origin);
    let k = settings
        .phases
        .unwrap_or((seq.len().max(1) + 2).min(MAX_PHASES));
    if seq.len() > k {
        // The search moves within sequences of k slip modes: a longer start does not
        // fit, and the setting to change is the one the user gave.
        let n = settings.naming;
        let got = format!("{} slip phases", seq.len());
        return Err(match start {
            Some(_) => Error::invalid(
                n.setting("start"),
                got,
                format!("has more slip phases than {} = {k}", n.setting("phases")),
            ),
            None => Error::invalid(
                n.setting("phases"),
                k,
                format!(
                    "is below the {got} of the default start gait: give at least {} \
                     phases, or {} with at most {k} slip phases",
                    seq.len(),
                    n.setting("start")
                ),
            ),
        });
    }
    em.stage(format!(
        "local search over sequences of {k} slip modes, from {} of {origin}",
        seq.len()
    ));
    let s = search_sequences(crawler, problem, &seq, k)?;
    Ok(GaitResult::from_sequence(crawler, problem, &s, &origin))
}

/// The phase method: the `K`-phase MILP when `settings.phases` fixes `K`, else the growth of
/// `K` (theory §7), each from `start` when there is one.
fn solve_phase_method(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &OptimizeSettings,
    plan: &Plan,
    start: Option<PhaseSolution>,
    em: &Emitter<'_>,
) -> Result<GaitResult> {
    match settings.phases {
        Some(k) => {
            em.stage(format!("solving the {k}-phase MILP"));
            let opts = PhaseOptions {
                start,
                ..PhaseOptions::default()
            };
            let s = solve_phase_with(crawler, problem, k, &opts)?;
            Ok(GaitResult::from_phase(crawler, problem, &s))
        }
        None => {
            let mut growth = plan.growth.clone();
            growth.start = start;
            em.stage(format!("K = {}", growth.min_phases));
            let g = grow_phases(crawler, problem, &growth, &mut |st| {
                em.send(Event::PhaseSolved {
                    step: st.clone(),
                    start: false,
                })
            })?;
            Ok(GaitResult::from_growth(crawler, problem, &g))
        }
    }
}

/// An error (prefixed by `what`) when the job's deadline passed while its start gait was
/// computed: the method has no time left.
fn started_in_time(what: &str) -> Result<()> {
    if crate::progress::out_of_time()? {
        return Err(Error::TimeLimit(format!(
            "{what}the time limit was reached while computing the start gait"
        )));
    }
    Ok(())
}

/// The start of a local method: the given one (checked to be of this crawler and period), or
/// the better of [`phase_start`] and the best structured gait `floor` (the structured gait
/// alone when the phase start fails for want of time), with time left of the job's deadline.
fn start_gait(
    start: Option<&Start>,
    crawler: &Crawler,
    problem: &GaitProblem,
    plan: &Plan,
    floor: Option<&StructuredSearch>,
    em: &Emitter<'_>,
) -> Result<StartGait> {
    let start = match start {
        Some(s) => start_of(s, crawler, problem)?,
        None => {
            match (
                phase_start(crawler, problem, &plan.growth, &mut |e| em.start_event(e)),
                floor,
            ) {
                (Ok(p), Some(f)) if f.objective > p.result.head.objective => {
                    em.send(Event::Note(format!(
                        "the local method starts from the best structured gait (J = {:.6}), \
                         better than the phase start (J = {:.6})",
                        f.objective, p.result.head.objective
                    )));
                    f.best.clone()
                }
                (Ok(p), _) => p,
                (Err(Error::TimeLimit(e)), Some(f)) => {
                    em.send(Event::Note(format!(
                        "no phase start ({e}); the local method starts from the best \
                         structured gait"
                    )));
                    f.best.clone()
                }
                (Err(e), _) => return Err(e),
            }
        }
    };
    started_in_time("")?;
    Ok(start)
}

/// A given start gait, read (a file) and checked against the crawler and the period.
fn start_of(start: &Start, crawler: &Crawler, problem: &GaitProblem) -> Result<StartGait> {
    match start.read()? {
        (ResultFile::Crawler(g), name) => StartGait::from_result(crawler, problem, g.result, &name),
        (ResultFile::General(_), name) => Err(Error::invalid(
            "start",
            name,
            "is a general problem's result; a crawler's gait starts from a crawler's gait result",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimal::structured::knots_result;
    use crate::optimal::Cost;

    /// An answer below the idle gait (a stroke that costs more than it moves the crawler, as a
    /// MILP cut short by its time limit may return: six blocks at `--phases 4 --time-limit 10`
    /// gave J = -0.084) gives way to the idle gait, J = 0, keeping the `time_limit` status and
    /// saying what the method had found; the answer reads back.
    #[test]
    fn an_answer_below_zero_gives_way_to_the_idle_gait() {
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        let cost = Cost::Quadratic { weight: 100.0 };
        let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], cost, None).unwrap();
        let lengths = vec![vec![0.1, 0.0], vec![-0.1, 0.0]];
        let mut costly = knots_result(&c, &p, vec![0.0, 5.0], lengths, "a stroke").unwrap();
        assert!(
            costly.head.objective < -0.1,
            "J = {}",
            costly.head.objective
        );
        costly.head.status = MilpStatus::TimeLimit;
        let plan = OptimizeSettings::default().plan(&c, &p).unwrap();
        let r = at_least_idle(&c, &p, &plan, costly, &Emitter::new(None)).unwrap();
        assert_eq!(r.head.objective, 0.0);
        assert_eq!(r.head.status, MilpStatus::TimeLimit);
        let why = r
            .records
            .structured
            .as_ref()
            .and_then(|s| s.replaced.clone());
        assert!(why.is_some_and(|w| w.contains("below the idle gait")));
        GaitResult::from_json(&serde_json::to_string(&r).unwrap(), "idle").unwrap();
    }
}
