//! One `K`: the phase MILP (or, with fixed modes, its LP) solved, replayed and certified.

use super::decode::RawGait;
use super::layout::{build, ExtraRows};
use super::polish::polish_phases;
use super::{check_phase_args, start_unproven, PhaseOptions, PhaseSolution, MAX_OA_ROUNDS};
use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::milp::{certify, check_verified, replay, solve_max, TangentRates, OA_TOL};
use crate::optimal::units::Units;
use crate::optimal::{Certificate, Cost, GaitProblem, MilpStatus};

/// Solves (P) globally over gaits of at most `phases` slip phases (module docs).
pub fn solve_phase_global(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
) -> Result<PhaseSolution> {
    solve_phase_from(crawler, problem, phases, None)
}

/// [`solve_phase_global`] with a known gait of at most `phases` slip phases as the first
/// incumbent.
pub fn solve_phase_from(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    start: Option<&PhaseSolution>,
) -> Result<PhaseSolution> {
    if let Some(s) = start {
        let slips = RawGait::of(s).slip_phases();
        if slips > phases {
            return Err(Error::invalid(
                "start",
                slips,
                format!("has more than {phases} slip phases"),
            ));
        }
    }
    let opts = PhaseOptions {
        start: start.cloned(),
        ..PhaseOptions::default()
    };
    solve_phase_with(crawler, problem, phases, &opts)
}

/// [`solve_phase_global`] with the options of [`PhaseOptions`]: a known gait as the first
/// incumbent (or, when it has more than `phases` slip phases, its `J` as a cutoff), a cutoff,
/// optional valid rows.
pub fn solve_phase_with(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    opts: &PhaseOptions,
) -> Result<PhaseSolution> {
    check_phase_args(crawler, problem, phases)?;
    let start = opts.start.as_ref();
    if let Some(c) = opts.cutoff {
        if !c.is_finite() {
            return Err(Error::invalid("cutoff", c, "must be finite"));
        }
    }
    let fits = start.filter(|s| RawGait::of(s).slip_phases() <= phases);
    let cutoff = opts.cutoff.or_else(|| {
        start
            .filter(|_| fits.is_none())
            .map(PhaseSolution::objective)
    });
    let rows = ExtraRows {
        formulation: opts.formulation,
        // A hair below, so that the start's own J (and round-off) stays feasible.
        cutoff: cutoff.map(|c| c - 1e-9 * problem.length_scale(crawler)),
    };
    let solved = solve_steps(crawler, problem, phases, fits, None, &rows);
    let resolution = crate::optimal::growth::MOVE_RESOLUTION * problem.length_scale(crawler);
    let mut answer = match solved {
        // No gait of at most `phases` slip phases reaches the cutoff: the start, if any, is
        // at least as good as all of them.
        Err(Error::Infeasible(_)) if cutoff.is_some() => match start {
            Some(s) if cutoff.is_some_and(|c| s.objective() >= c) => {
                let j = s.objective();
                let mut s = s.clone();
                s.phases = phases;
                s.certificate = Certificate {
                    status: MilpStatus::OptimalAmongKPhases,
                    milp_objective: s.verified_displacement,
                    bound: j,
                    gap: 0.0,
                };
                Ok(s)
            }
            _ => Err(Error::Infeasible(format!(
                "no gait of at most {phases} slip phases reaches J >= {} (the cutoff)",
                cutoff.unwrap_or_default()
            ))),
        },
        // The limit came before the MILP found a gait beating the start (or before it took a
        // start it dropped): the start, with what is known without the MILP.
        Err(Error::TimeLimit(_)) if start.is_some() => Ok(start_unproven(
            crawler,
            problem,
            start.expect("a start"),
            phases,
        )),
        // A MILP answer below the start (cut short, or HiGHS dropped a start it found
        // infeasible at its tolerances, or the start has more slip phases than `phases` and
        // the cutoff row on the outer approximation let a gait through whose true J is lower):
        // the start. The MILP's bound covers every gait of at most `phases` slip phases; a
        // bound below the start's J says that none of them reaches it, so the claim is the
        // cutoff's: bound J of the start (a bound below a verified J would be false).
        // A MILP answer as good as the start up to the replay's resolution is kept: it is of at
        // most `phases` slip phases, so its claim is the stronger (optimal among them).
        Ok(s) => match start {
            Some(st) if st.objective() > s.objective() + resolution => {
                let mut st = st.clone();
                let bound = s.certificate.bound.max(st.objective());
                st.phases = phases;
                st.certificate = Certificate {
                    bound,
                    gap: Certificate::gap_of(bound, st.objective(), problem.j_floor(crawler)),
                    milp_objective: st.verified_displacement,
                    ..s.certificate
                };
                Ok(st)
            }
            _ => Ok(s),
        },
        r => r,
    }?;
    answer.settle_claim();
    Ok(answer)
}

/// [`solve_steps_in`] in the optimisers' internal units ([`Units`]): the problem and the start
/// converted in, the answer converted back; within the current deadline.
pub(super) fn solve_steps(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    start: Option<&PhaseSolution>,
    fixed: Option<&[Vec<i8>]>,
    rows: &ExtraRows,
) -> Result<PhaseSolution> {
    let units = Units::of(crawler, problem);
    let (c, p) = (units.crawler(crawler)?, units.problem(problem));
    let start = start.map(|s| units.phase(s, false));
    let rows = ExtraRows {
        cutoff: rows.cutoff.map(|j| j / units.objective_scale()),
        ..*rows
    };
    let s = crate::progress::with_objective_scale(units.objective_scale(), || {
        solve_steps_in(&c, &p, phases, start.as_ref(), fixed, &rows)
    })?;
    Ok(units.phase(&s, true))
}

/// The outer-approximation loop of [`solve_steps_in`]: the phase MILP (or LP) built and solved
/// round after round, each answer's rates added as tangents of a quadratic cost, until the
/// bound meets the answer's true `J`, the time runs out or no tangent is new. Returns the last
/// answer, its bound, its status and the rounds.
fn oa_rounds(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    start: Option<&PhaseSolution>,
    fixed: Option<&[Vec<i8>]>,
    rows: &ExtraRows,
) -> Result<(RawGait, f64, MilpStatus, usize)> {
    let t = problem.period;
    let a = &problem.rate_bound;
    let what = format!("gait of at most {phases} slip phases");
    let mut rates = match problem.cost {
        Cost::Quadratic { .. } => Some(TangentRates::new(a)),
        Cost::None => None,
    };
    let mut incumbent = start.map(RawGait::of);
    let mut rounds = 0;
    let mut last_bound = f64::INFINITY;
    let (raw, bound, status) = loop {
        rounds += 1;
        let (pb, lay) = build(crawler, problem, phases, rates.as_ref(), fixed, rows);
        let ncols = pb.num_cols();
        let start_cols = incumbent.as_ref().and_then(|g| g.columns(&lay, ncols));
        if crate::progress::out_of_time()? {
            break match incumbent {
                Some(g) if rounds > 1 => (g, last_bound, MilpStatus::TimeLimit),
                _ => {
                    return Err(Error::TimeLimit(format!(
                        "{what}: the time limit was reached before any feasible gait was found"
                    )))
                }
            };
        }
        let gap = problem.length_scale(crawler) * 1e-9;
        let (cols, objective, bound, status) = solve_max(pb, &what, start_cols.as_deref(), gap)?;
        // Cut short before HiGHS had a bound: the work bound, valid for every gait.
        let bound = bound.unwrap_or_else(|| super::work_limit(crawler, problem).max(objective));
        let raw = RawGait::read(&lay, &cols, t, a);
        last_bound = bound;
        let Some(r) = rates.as_mut() else {
            break (raw, bound, status);
        };
        let true_objective = raw.displacement() - raw.cost(problem);
        let converged =
            bound - true_objective <= OA_TOL * true_objective.abs().max(problem.j_floor(crawler));
        if converged || status == MilpStatus::TimeLimit || rounds >= MAX_OA_ROUNDS {
            let status = match status {
                MilpStatus::Optimal if !converged => MilpStatus::ApproximationLimit,
                s => s,
            };
            break (raw, bound, status);
        }
        if !add_tangents(r, &raw, a) {
            break (raw, bound, MilpStatus::ApproximationLimit);
        }
        incumbent = Some(raw);
    };
    Ok((raw, bound, status, rounds))
}

/// Adds the rates `U_l / tau` of every phase of `raw` as tangent points of the quadratic cost
/// (rates bounded by `a`); whether any was new.
fn add_tangents(r: &mut TangentRates, raw: &RawGait, a: &[f64]) -> bool {
    let mut added = false;
    for (d, u) in raw.durations.iter().zip(&raw.increments) {
        for (l, &ul) in u.iter().enumerate() {
            added |= r.add(l, ul / d, a[l]);
        }
    }
    added
}

/// The displacement per period of `raw` as the exact simulator replays it from its first state
/// (0 for a gait of fewer than two phases).
fn verify_replay(crawler: &Crawler, t: f64, raw: &RawGait, what: &str) -> Result<f64> {
    if raw.durations.len() < 2 {
        return Ok(0.0);
    }
    replay(
        crawler,
        t,
        &raw.durations,
        &raw.increments,
        Some(&raw.states[0]),
        Method::Exact,
        what,
    )?
    .displacement_per_period
    .ok_or_else(|| Error::Numerical(format!("{what}: the replay did not converge")))
}

/// `raw` or, with a quadratic cost, its polish on its sequence of slip modes
/// (`super::polish`), kept when its replay agrees and J is no worse; with its replayed
/// displacement.
fn polished_or_replayed(
    crawler: &Crawler,
    problem: &GaitProblem,
    raw: RawGait,
    what: &str,
) -> Result<(RawGait, f64)> {
    let (t, scale) = (problem.period, problem.length_scale(crawler));
    let polished = polish_phases(crawler, problem, &raw).and_then(|p| {
        let v = verify_replay(crawler, t, &p, what).ok()?;
        check_verified(what, p.displacement(), v, scale).ok()?;
        let better = v - p.cost(problem) >= raw.displacement() - raw.cost(problem) - 1e-9 * scale;
        better.then_some((p, v))
    });
    Ok(match polished {
        Some(pv) => pv,
        None => {
            let v = verify_replay(crawler, t, &raw, what)?;
            (raw, v)
        }
    })
}

/// The phase MILP of `phases` steps (or, with `fixed` modes, its LP), solved with outer
/// approximation of a quadratic cost ([`oa_rounds`]), the answer replayed by the exact
/// simulator ([`polished_or_replayed`]) and certified. Arguments are checked by the callers.
fn solve_steps_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    start: Option<&PhaseSolution>,
    fixed: Option<&[Vec<i8>]>,
    rows: &ExtraRows,
) -> Result<PhaseSolution> {
    let what = format!("gait of at most {phases} slip phases");
    let (raw, bound, status, rounds) = oa_rounds(crawler, problem, phases, start, fixed, rows)?;
    let scale = problem.length_scale(crawler);
    let (raw, verified) = polished_or_replayed(crawler, problem, raw, &what)?;
    let cost = raw.cost(problem);
    // What the MILP proved is optimality among gaits of at most `phases` slip phases.
    let status = match status {
        MilpStatus::Optimal => MilpStatus::OptimalAmongKPhases,
        s => s,
    };
    let certificate = certify(
        &what,
        scale,
        status,
        raw.displacement(),
        bound,
        verified,
        cost,
    )?;
    Ok(raw.into_solution(phases, certificate, verified, cost, rounds))
}

/// The relative gain in `J` below which a larger `K` or a move of [`search_sequences`] counts
/// as no gain: `1e-7` for a linear objective (LP round-off), and the outer-approximation
/// tolerance [`OA_TOL`] with a quadratic cost, whose values are only that accurate (a gain
/// within it would be noise: on three blocks with c = 0.2, `J_4 - J_3 = 1.5e-7` kept the
/// growth going for another 54 s).
pub(super) fn gain_tolerance(problem: &GaitProblem) -> f64 {
    match problem.cost {
        Cost::None => 1e-7,
        Cost::Quadratic { .. } => OA_TOL,
    }
}
