//! Is a general result what it says? The check [`super::ResultFile`] runs on a general
//! problem's result read back (the counterpart of the crawler's
//! [`crate::optimal::consistency`]): the stored problem (P) rebuilt and checked, the stored
//! process a process of it (one check of (P)'s conditions for both, [`ProcessRows::fault`]:
//! through [`GeneralProcess::check_as`] for P_m, on the record's own rows for a phase gait,
//! whose durations, shapes and held faces are checked first), the controls replayed by the
//! general simulator that verified them when they were found ([`simulate_grid`],
//! [`replay_phases`]) and every stored number compared with the replay, then the envelope's
//! `objective`, `status` and `certificate` against the solution. A file is data from
//! elsewhere: a number that disagrees is refused naming its field.

use super::general_claims::{
    bad, check_dominates, check_global, check_local_claim, check_local_phase, check_records,
    check_slots,
};
use super::{GeneralAnswer, GeneralFile, GeneralSolution};
use crate::certify::GeneralProcess;
use crate::error::Result;
use crate::model::general::GeneralProblem;
use crate::optimal::consistency::INPUT_TOL;
use crate::optimal::general::{
    replay_phases, simulate_grid, GeneralLocal, GeneralPhaseGait, GeneralPm, MAX_GENERAL_LOCAL_M,
    MAX_GENERAL_M, MAX_GENERAL_PHASES,
};
use crate::optimal::process::{max_diff, Fault, FieldNames, ProcessKind, ProcessRows};
use crate::optimal::{local_status, MilpStatus, ResultKind};

/// The problem of a stored file, its errors naming `{what}: problem.<field>`.
fn stored_problem(file: &GeneralFile, what: &str) -> Result<GeneralProblem> {
    file.problem()
        .map_err(|e| crate::optimal::envelope::in_problem(e, what))
}

/// Closeness of two values of `J`, relative to the size of its two parts.
struct Close(f64);

impl Close {
    fn of(reward: f64, cost: f64) -> Self {
        Close(INPUT_TOL * (reward.abs() + cost.abs()) + 1e-14)
    }
    /// [`Close::of`] at least relative to the problem's scale of `J` (the largest face weight
    /// times C's length scale): a gait that barely moves (`J` near 0) is stored to the
    /// solver's tolerance of that scale, not of its own tiny `J`.
    fn scaled(p: &GeneralProblem, reward: f64, cost: f64) -> Self {
        let sigma = p.c.faces();
        let wmax = (0..sigma)
            .map(|f| {
                let mut e = vec![0.0; sigma];
                e[f] = 1.0;
                p.reward.eval(&p.c.normals, &e).abs()
            })
            .fold(0.0_f64, f64::max);
        Close(INPUT_TOL * (reward.abs() + cost.abs() + wmax * p.c.scale()) + 1e-14)
    }
    fn check(&self, what: &str, field: &str, got: f64, want: f64, why: &str) -> Result<()> {
        if got.is_finite() && (got - want).abs() <= self.0 {
            Ok(())
        } else {
            Err(bad(what, field, got, format!("{why} ({want})")))
        }
    }
}

impl GeneralAnswer {
    /// Checks that a general result is what it says (module docs); `what` names the source.
    pub fn check_consistent(&self, what: &str) -> Result<()> {
        // The head as the variant has it (a record deserialised directly, not through
        // `ResultFile::from_json`, has not had its kind and method read yet).
        let head = &self.head;
        if head.kind != ResultKind::General {
            return Err(bad(
                what,
                "kind",
                head.kind.as_str(),
                "a general problem's answer is of kind \"general\"",
            ));
        }
        let methods = self.solution.kind().methods();
        if !methods.contains(&head.method.as_str()) {
            return Err(bad(
                what,
                "method",
                &head.method,
                format!("is not a method of this answer ({methods:?})"),
            ));
        }
        if self.starts.is_some() && !matches!(self.solution, GeneralSolution::Local(_)) {
            return Err(bad(
                what,
                "start_from",
                &head.method,
                "only the local method records its starts",
            ));
        }
        let p = stored_problem(&self.problem, what)?;
        if self.period != p.period {
            return Err(bad(
                what,
                "period",
                self.period,
                format!("differs from the problem's period {}", p.period),
            ));
        }
        match &self.solution {
            GeneralSolution::Pm(s) => check_discrete_answer(self, s, &p, what),
            GeneralSolution::Local(s) => check_local_answer(self, s, &p, what),
            GeneralSolution::Phase(s) => check_phase_answer(self, s, &p, what),
        }
    }

    /// The MILP's own objective, which every method but the local one records.
    fn recorded_solver_objective(&self, what: &str) -> Result<f64> {
        self.solver_objective.ok_or_else(|| {
            bad(
                what,
                "solver_objective",
                "nothing",
                format!(
                    "the {} method records its MILP's objective",
                    self.head.method
                ),
            )
        })
    }
}

/// A P_m answer of the global method: its process replayed, its objective, its convergence
/// table, its upper bound and its global certificate.
fn check_discrete_answer(
    r: &GeneralAnswer,
    s: &GeneralPm,
    p: &GeneralProblem,
    what: &str,
) -> Result<()> {
    let j = check_pm(p, MAX_GENERAL_M, &GeneralProcess::from_pm(p, s), what)?;
    objectives(what, j, s.objective, r.head.objective)?;
    solver_objective(
        what,
        r.recorded_solver_objective(what)?,
        s.certificate.milp_objective,
    )?;
    check_records(what, &r.records, None, Some(s.m as usize), j, p.j_floor())?;
    check_global(
        what,
        &r.head.method,
        r.head.status,
        &r.head.certificate,
        &s.certificate,
        None,
        (p, j),
    )
}

/// A P_m answer of the local method: its process replayed, its objective, its status against
/// its stop, its local certificate and its start record.
fn check_local_answer(
    r: &GeneralAnswer,
    s: &GeneralLocal,
    p: &GeneralProblem,
    what: &str,
) -> Result<()> {
    let j = check_pm(
        p,
        MAX_GENERAL_LOCAL_M,
        &GeneralProcess::from_local(p, s),
        what,
    )?;
    objectives(what, j, s.objective, r.head.objective)?;
    if r.head.status != local_status(s.stop) {
        return Err(bad(
            what,
            "status",
            r.head.status.as_str(),
            format!(
                "disagrees with solution.stop ({})",
                local_status(s.stop).as_str()
            ),
        ));
    }
    // A local answer proves no bound of its own; the chain's upper bound over all periodic
    // gaits may be recorded with it (`bound`), checked as with a global answer.
    check_local_claim(what, p, &r.head.certificate, j)?;
    for (field, v) in [
        ("solution.lp_objective", s.lp_objective),
        ("solution.start_objective", s.start_objective),
    ] {
        if !v.is_finite() {
            return Err(bad(what, field, v, "must be finite"));
        }
    }
    if let Some(j) = r.solver_objective {
        return Err(bad(
            what,
            "solver_objective",
            j,
            "the local method solves no MILP",
        ));
    }
    let Some(st) = r.starts else {
        return Err(bad(
            what,
            "start_from",
            "nothing",
            "a local answer records its starts (start_from, starts_tried, best_start)",
        ));
    };
    if st.starts_tried == 0 || st.best_start >= st.starts_tried {
        return Err(bad(
            what,
            "best_start",
            st.best_start,
            format!("must be below starts_tried ({})", st.starts_tried),
        ));
    }
    Ok(())
}

/// An answer of exact phase gaits (the general MILP, or the crawler's local methods on a
/// chain): its formulation, its gait replayed, its objective, then its growth table, upper
/// bound and global certificate, or its local record.
fn check_phase_answer(
    r: &GeneralAnswer,
    s: &GeneralPhaseGait,
    p: &GeneralProblem,
    what: &str,
) -> Result<()> {
    // The crawler's local methods on the chain (`sequence`, `chain`).
    let local = r.head.method != "phase";
    // A transition before each of the K phases: the chain's formulation and "transitions".
    let transitions = r.formulation.as_deref() == Some("transitions");
    let chain = match r.formulation.as_deref() {
        None | Some("transitions") => false,
        Some("chain") if p.as_chain().is_some() => true,
        Some("chain") => {
            return Err(bad(
                what,
                "formulation",
                "chain",
                "the problem is not a crawler's gait problem (a chain), so the \
                     chain's formulation cannot have run",
            ))
        }
        Some(other) => {
            return Err(bad(
                what,
                "formulation",
                other,
                "the formulations recorded are \"chain\" and \"transitions\" (absent: \
                     the general one)",
            ))
        }
    };
    if local && !chain {
        return Err(bad(
            what,
            "formulation",
            format!("{:?}", r.formulation),
            format!(
                "the {} method runs on the chain: must be \"chain\"",
                r.head.method
            ),
        ));
    }
    let j = check_phase(p, s, chain || transitions, local, what)?;
    objectives(what, j, s.objective, r.head.objective)?;
    solver_objective(
        what,
        r.recorded_solver_objective(what)?,
        s.certificate.milp_objective,
    )?;
    if transitions {
        check_slots(s, what)?;
    }
    if r.head.status == MilpStatus::DominatesKPhases {
        check_dominates(r, chain, what)?;
    }
    if local {
        return check_local_phase(what, r, s, p, j);
    }
    check_records(what, &r.records, Some(s.max_phases), None, j, p.j_floor())?;
    let holding = s.held.iter().filter(|h| !h.is_empty()).count();
    let k = Some((s.max_phases, holding));
    check_global(
        what,
        &r.head.method,
        r.head.status,
        &r.head.certificate,
        &s.certificate,
        k,
        (p, j),
    )
}

/// The most phases a gait of the crawler's local methods on a chain may have in a result file.
const MAX_LOCAL_PHASES: usize = 1 << 20;

/// The envelope's `objective` against `J` of the replay, then the solution's (a copy of the
/// envelope's since version 3; version 2 wrote it, and a disagreeing one is refused).
fn objectives(what: &str, j: f64, solution: f64, top: f64) -> Result<()> {
    let close = Close(INPUT_TOL * j.abs().max(1e-300) + 1e-14);
    let why = "disagrees with the solution replayed by simulation";
    close.check(what, "objective", top, j, why)?;
    close.check(what, "solution.objective", solution, j, why)
}

/// The envelope's `solver_objective` against the MILP certificate's copy, which the claim's
/// checks read: equal when the reader filled the copy from it (version 3), and a version 2
/// file's own copy may not be contradicted by an added top-level value.
fn solver_objective(what: &str, top: f64, milp: f64) -> Result<()> {
    if top == milp {
        Ok(())
    } else {
        Err(bad(
            what,
            "solver_objective",
            top,
            format!("disagrees with solution.certificate.milp_objective ({milp})"),
        ))
    }
}

/// Checks a P_m process (`m` at most `max_m`) against the problem and its replay; returns `J`
/// of the replay.
fn check_pm(p: &GeneralProblem, max_m: u32, pr: &GeneralProcess, what: &str) -> Result<f64> {
    let (m, x, u, lambda) = (pr.m().unwrap_or(0), &pr.x, &pr.u, &pr.lambda);
    if !(1..=max_m).contains(&m) {
        return Err(bad(
            what,
            "solution.m",
            m,
            format!("must be in 1..={max_m}"),
        ));
    }
    let at = format!("{what}: solution");
    pr.check_as(p, INPUT_TOL, &FieldNames::record(&at))?;
    let sim = simulate_grid(p, m, &x[0], u, "solution.controls")?;
    let scale = p.c.scale();
    for (k, (got, want)) in x.iter().zip(&sim.x).enumerate() {
        if max_diff(got, want) > INPUT_TOL * scale {
            return Err(bad(
                what,
                &format!("solution.states[{k}]"),
                format!("{got:?}"),
                format!("disagrees with the process the controls give when simulated ({want:?})"),
            ));
        }
    }
    let h = p.period / (1u64 << m) as f64;
    for (i, (got, want)) in lambda.iter().zip(&sim.lambda).enumerate() {
        if max_diff(got, want) * h > INPUT_TOL * scale {
            return Err(bad(
                what,
                &format!("solution.reactions[{i}]"),
                format!("{got:?}"),
                format!("disagrees with the reactions of the simulated process ({want:?})"),
            ));
        }
    }
    let j = sim.reward - sim.cost;
    let close = Close::of(sim.reward, sim.cost);
    close.check(
        what,
        "solution.reactions",
        pr.objective(p),
        j,
        "J of the stored reactions and controls disagrees with the replay's",
    )?;
    Ok(j)
}

/// The shapes of a phase gait's records against the problem and its method (`transitions`: a
/// transition before each phase, the chain's formulation or free transitions; `local`: as many
/// phases as it says), and `A = 0`.
fn check_phase_shape(
    p: &GeneralProblem,
    s: &crate::optimal::general::GeneralPhaseGait,
    transitions: bool,
    local: bool,
    what: &str,
) -> Result<()> {
    let cap = if local {
        MAX_LOCAL_PHASES
    } else {
        MAX_GENERAL_PHASES
    };
    if !(1..=cap).contains(&s.max_phases) {
        return Err(bad(
            what,
            "solution.max_phases",
            s.max_phases,
            format!("must be in 1..={cap}"),
        ));
    }
    if local && s.durations.len() != s.max_phases {
        return Err(bad(
            what,
            "solution.max_phases",
            s.max_phases,
            format!(
                "a local method's gait has as many phases as it says ({})",
                s.durations.len()
            ),
        ));
    }
    if !p.dynamics.is_state_independent() {
        return Err(bad(
            what,
            "problem.dynamics.A",
            "non-zero",
            "a phase gait needs A = 0",
        ));
    }
    let (n, mc, sigma) = (p.states(), p.controls(), p.c.faces());
    // A transition may precede each of the K phases (the chain's slip phases, or free
    // transitions). A gait that dominates the class (the chain's structured start, kept) is not
    // of it: any length.
    let most = if s.certificate.status == crate::optimal::MilpStatus::DominatesKPhases {
        MAX_LOCAL_PHASES
    } else if transitions {
        2 * s.max_phases
    } else {
        s.max_phases
    };
    let np = s.durations.len();
    if np == 0 || np > most {
        return Err(bad(
            what,
            "solution.durations",
            format!("{np} phases"),
            format!("needs 1 to {most} phases (max_phases = {})", s.max_phases),
        ));
    }
    for (field, rows, len, width) in [
        ("solution.controls", &s.controls, np, mc),
        ("solution.states", &s.states, np + 1, n),
        ("solution.reactions", &s.reactions, np, sigma),
    ] {
        if rows.len() != len || rows.iter().any(|r| r.len() != width) {
            return Err(bad(
                what,
                field,
                format!("{} rows", rows.len()),
                format!("needs {len} rows of {width} values"),
            ));
        }
        if rows.iter().flatten().any(|v| !v.is_finite()) {
            return Err(bad(what, field, "a non-finite value", "must be finite"));
        }
    }
    if s.held.len() != np {
        return Err(bad(
            what,
            "solution.held",
            format!("{} rows", s.held.len()),
            format!("needs {np} rows"),
        ));
    }
    let t = p.period;
    crate::optimal::consistency::check_durations(what, "solution.durations", &s.durations, t)
}

/// A phase gait's record of its faces: the held faces numbered `1..=sigma`, and a reaction on a
/// held face only (that it is non-negative and the face active is (P)'s check).
fn check_held(
    p: &GeneralProblem,
    s: &crate::optimal::general::GeneralPhaseGait,
    what: &str,
) -> Result<()> {
    let sigma = p.c.faces();
    let scale = p.c.scale();
    for (j, (held, r)) in s.held.iter().zip(&s.reactions).enumerate() {
        if let Some(f) = held.iter().find(|&&f| f == 0 || f > sigma) {
            return Err(bad(
                what,
                &format!("solution.held[{j}]"),
                f,
                format!("faces are numbered 1..={sigma}"),
            ));
        }
        let rmax = r.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let tol = INPUT_TOL * rmax.max(scale / s.durations[j]);
        if let Some(f) = (0..sigma).find(|&f| r[f] > tol && !held.contains(&(f + 1))) {
            return Err(bad(
                what,
                &format!("solution.reactions[{j}][{f}]"),
                r[f],
                format!(
                    "a reaction on face {}, which the phase does not hold",
                    f + 1
                ),
            ));
        }
    }
    Ok(())
}

/// Checks a phase gait against the problem and its exact replay; returns `J` of the replay.
fn check_phase(
    p: &GeneralProblem,
    s: &crate::optimal::general::GeneralPhaseGait,
    transitions: bool,
    local: bool,
    what: &str,
) -> Result<f64> {
    check_phase_shape(p, s, transitions, local, what)?;
    check_held(p, s, what)?;
    // (P)'s conditions on the record, shared with every process (`optimal::process`).
    let rows = ProcessRows {
        kind: ProcessKind::Phase,
        durations: &s.durations,
        x: &s.states,
        u: &s.controls,
        lambda: &s.reactions,
    };
    let at = format!("{what}: solution");
    let names = FieldNames::record(&at);
    // A reaction off its face is reported after the replay, which names a moved state itself.
    let flow = match rows.fault(p, INPUT_TOL) {
        Some(fault @ Fault::Inactive { .. }) => Some(fault),
        Some(fault) => return Err(fault.in_words(&rows, &names)),
        None => None,
    };
    let scale = p.c.scale();
    let (states, sim) = replay_phases(p, &s.durations, &s.controls, &s.states[0], what)?;
    // Replayed states carry the rounding of the phases' increments.
    let rounding = p.rounding(&s.durations, &states, &s.controls);
    for (j, (got, want)) in s.states.iter().zip(&states).enumerate() {
        if max_diff(got, want) > INPUT_TOL * scale + rounding {
            return Err(bad(
                what,
                &format!("solution.states[{j}]"),
                format!("{got:?}"),
                format!("disagrees with the exact replay of the gait ({want:?})"),
            ));
        }
    }
    if let Some(fault) = flow {
        return Err(fault.in_words(&rows, &names));
    }
    // The replay itself periodic, to the states' tolerance (the stored states are, and each is
    // within that of the replay's: twice that for the replay without this check).
    let np = states.len() - 1;
    if p.boundary == crate::model::general::Boundary::Periodic
        && max_diff(&states[np], &states[0]) > INPUT_TOL * scale + rounding
    {
        return Err(bad(
            what,
            &format!("solution.states[{np}]"),
            format!("{:?}", states[np]),
            "the replayed gait is not periodic: it does not end where it began",
        ));
    }
    // A held face lies under the whole phase: active at both of its ends (to 1e-6 of C's
    // scale, looser than the states' check: a MILP holds its faces to its own tolerance).
    for (j, held) in s.held.iter().enumerate() {
        for &f in held {
            let off = [j, j + 1]
                .iter()
                .map(|&k| p.c.slack(f - 1, &states[k]).abs())
                .fold(0.0_f64, f64::max);
            if off > 1e-6 * scale + rounding {
                return Err(bad(
                    what,
                    &format!("solution.held[{j}]"),
                    f,
                    format!("face {f} is not active at both ends of the phase (off by {off:e})"),
                ));
            }
        }
    }
    let close = Close::scaled(p, sim.reward, sim.cost);
    close.check(
        what,
        "solution.actuation_cost",
        s.actuation_cost,
        sim.cost,
        "disagrees with the cost of the controls",
    )?;
    let reward: f64 = s
        .reactions
        .iter()
        .zip(&s.durations)
        .map(|(r, d)| d * p.reward.eval(&p.c.normals, r))
        .sum();
    close.check(
        what,
        "solution.reactions",
        reward,
        sim.reward,
        "int f1 of the stored reactions disagrees with the exact replay's",
    )?;
    // The optimiser keeps a gait only when its replay meets the solver's states within 1e-6 of
    // C's scale.
    if !(s.state_gap.is_finite() && s.state_gap >= 0.0 && s.state_gap <= 1e-6 * scale + rounding) {
        return Err(bad(
            what,
            "solution.state_gap",
            s.state_gap,
            format!(
                "must be finite, non-negative and at most 1e-6 of C's scale and the states' \
                 rounding ({:e}): the optimiser keeps no gait whose replay is farther from the \
                 solver's states",
                1e-6 * scale + rounding
            ),
        ));
    }
    Ok(sim.reward - sim.cost)
}
