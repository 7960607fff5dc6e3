//! The exact replay of a phase gait of (P) ([`super::phase`]'s MILPs and their polish, the
//! chain's gaits in the problem's terms, and a result file read back): the process of the
//! gait's controls simulated exactly ([`replay_phases`]), its reactions averaged per phase
//! ([`phase_reactions`]), and a solver's gait verified by it and stored as the replay has it
//! ([`verified_gait`]), a periodic one on the orbit its controls make ([`replay_orbit`]).

use super::discrete::replay_periodic;
use super::geometry::into_u;
use super::phase_polish::MilpPhases;
use crate::error::{Error, Result};
use crate::integrate::{simulate_general_exact, ControlInput, GeneralSimulation, InputKind};
use crate::model::general::{Boundary, GeneralProblem};
use crate::optimal::milp::{Certificate, MilpStatus};
use crate::optimal::process::max_diff;
use serde::{Deserialize, Serialize};

/// A globally optimal gait among those of at most `K` phases, re-verified.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralPhaseGait {
    /// `K`, the phases allowed.
    pub max_phases: usize,
    /// `J` of the gait as the exact simulator replays it (written once, as the result's
    /// `objective`; filled from it on reading).
    #[serde(skip_serializing)]
    pub objective: f64,
    /// The MILP's status, objective, bound (on `J` over gaits of at most `K` phases) and gap
    /// (written once, as the result's `status`, `solver_objective` and `certificate`; filled
    /// from them on reading).
    #[serde(skip_serializing)]
    pub certificate: Certificate,
    /// Durations `tau_j` of the phases used (empty ones removed), in time order.
    pub durations: Vec<f64>,
    /// Controls `u_j = U_j / tau_j` per phase.
    pub controls: Vec<Vec<f64>>,
    /// States `x_j` at the phase starts and the end, as replayed.
    pub states: Vec<Vec<f64>>,
    /// Faces held per phase (1-based).
    pub held: Vec<Vec<usize>>,
    /// Reaction rates per phase and face: of the phase MILPs, the exact replay's averaged over
    /// the phase (the MILP's `L_{j,f} / tau_j` to its tolerance); of the crawler's methods on a
    /// chain, its block displacements' (`s_b |D_b| / tau`).
    pub reactions: Vec<Vec<f64>>,
    /// The largest difference between the MILP's states and the replayed ones.
    pub state_gap: f64,
    /// `int f2(u) dt` of the gait (0 without a cost).
    pub actuation_cost: f64,
    /// MILP solves (outer-approximation rounds for a quadratic cost, else 1).
    pub rounds: usize,
}

/// The exact process of a phase gait (constant control `controls[j]` for `durations[j]`) from
/// `x0`, over the durations' sum as a Cauchy problem: the states at the phase boundaries and
/// the end (`durations.len() + 1` rows) and the simulation (its `reward`, `cost` and
/// `objective` those of the gait). What a phase answer is verified by, here and when a result
/// file is read back; `what` names the gait in errors.
pub fn replay_phases(
    p: &GeneralProblem,
    durations: &[f64],
    controls: &[Vec<f64>],
    x0: &[f64],
    what: &str,
) -> Result<(Vec<Vec<f64>>, crate::integrate::GeneralSimulation)> {
    let total: f64 = durations.iter().sum();
    let mut times = Vec::with_capacity(durations.len());
    let mut at = 0.0;
    for d in durations {
        times.push(at);
        at += d;
    }
    let input = ControlInput::new(
        InputKind::PiecewiseConstant,
        total,
        times.clone(),
        controls.to_vec(),
        &p.control,
        "phase controls",
    )?;
    let mut cauchy = p.clone();
    cauchy.period = total;
    cauchy.boundary = Boundary::Initial(x0.to_vec());
    let sim = simulate_general_exact(&cauchy, &input, x0, 1, 1e-12)?;
    // The states at the knots (the simulator records each knot's time exactly) and the end.
    let mut states = Vec::with_capacity(durations.len() + 1);
    states.push(sim.x[0].clone());
    for &tk in times.iter().skip(1) {
        let i = sim.t.iter().position(|&s| s == tk).ok_or_else(|| {
            Error::Numerical(format!("{what}: the replay has no state at t = {tk}"))
        })?;
        states.push(sim.x[i].clone());
    }
    states.push(sim.x.last().expect("events").clone());
    Ok((states, sim))
}

/// The replay's reaction rates averaged over each phase, `(1/tau_j) int lambda dt` over the
/// phase, on its held faces (1-based) only and at least 0: the stored rates then give each
/// phase's segment `x_{j+1} = x_j + tau_j (g - sum lambda x*)` and `int f1` as the replay has
/// them, to rounding (the replay's rounding-level reactions on a face it touches, `6e-14`
/// seen, are not kept). The MILP's own rates `L_{j,f} / tau_j` hold to its feasibility
/// tolerance only: on a period of `1e-3` they were `1 + 1e-6` where the replay's are 1, and
/// the result's reader refused them.
fn phase_reactions(
    durations: &[f64],
    held: &[Vec<usize>],
    sim: &crate::integrate::GeneralSimulation,
    sigma: usize,
) -> Vec<Vec<f64>> {
    let starts: Vec<f64> = durations
        .iter()
        .scan(0.0, |at, d| {
            let t = *at;
            *at += d;
            Some(t)
        })
        .collect();
    let mut out = vec![vec![0.0; sigma]; durations.len()];
    for (i, lam) in sim.lambda.iter().enumerate() {
        let (a, b) = (sim.t[i], sim.t[i + 1]);
        // The replay's events include every phase's start, so a segment lies in one phase.
        let j = starts
            .partition_point(|&t| t <= 0.5 * (a + b))
            .saturating_sub(1);
        for (o, l) in out[j].iter_mut().zip(lam) {
            *o += (b - a) * l;
        }
    }
    for ((row, d), h) in out.iter_mut().zip(durations).zip(held) {
        for (f, v) in row.iter_mut().enumerate() {
            *v = if h.contains(&(f + 1)) {
                (*v / d).max(0.0)
            } else {
                0.0
            };
        }
    }
    out
}

/// Replays a solver's gait in the exact simulator from its `x_0` (a Cauchy problem over one
/// period) and checks the replay against the solver: `int f1` and the states at the phase
/// boundaries (and `x(T) = x(0)` when periodic), within `1e-6` relative; a disagreement is an
/// error naming `what`. The controls `U_j / tau_j` are clipped into a box U against the
/// solver's feasibility tolerance, and into a polytope U by the Euclidean projection
/// ([`into_u`]); a periodic gait is replayed on its orbit ([`replay_orbit`]); the stored
/// reactions are the replay's ([`phase_reactions`]).
pub(super) fn verified_gait(
    p: &GeneralProblem,
    phases: &MilpPhases,
    milp_objective: f64,
    bound: f64,
    status: MilpStatus,
    k: usize,
    what: &str,
) -> Result<GeneralPhaseGait> {
    let scale = p.c.scale();
    let durations = phases.durations.clone();
    let held = phases.held.clone();
    let milp_states = &phases.states;
    let mut centre = None;
    let controls: Vec<Vec<f64>> = phases
        .increments
        .iter()
        .zip(&durations)
        .map(|(u, tau)| into_u(&p.control, &mut centre, u.iter().map(|v| v / tau).collect()))
        .collect::<Result<_>>()?;
    if durations.is_empty() {
        return Err(Error::Numerical(format!(
            "{what}: no phase of positive duration"
        )));
    }
    let (states, sim) = replay_orbit(p, &durations, &controls, &milp_states[0], what)?;
    let reactions = phase_reactions(&durations, &held, &sim, p.c.faces());
    let state_gap = states
        .iter()
        .zip(milp_states)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(a, b)| (a - b).abs()))
        .fold(0.0_f64, f64::max);
    let objective = sim.objective.unwrap_or(sim.reward - sim.cost);
    // The replay's states carry the rounding of the phases' increments.
    let rounding = p.rounding(&durations, &states, &controls);
    let w = p.face_weights();
    let lp_reward: f64 = phases
        .integrated
        .iter()
        .map(|r| r.iter().zip(&w).map(|(l, w)| w * l).sum::<f64>())
        .sum();
    if (sim.reward - lp_reward).abs() > 1e-6 * (scale + lp_reward.abs())
        || state_gap > 1e-6 * scale + rounding
    {
        return Err(Error::Numerical(format!(
            "{what}: the gait replayed gives int f1 = {} (MILP {lp_reward}) and states off by \
             {state_gap:e}",
            sim.reward
        )));
    }
    replay_periodic(
        p,
        states.last().expect("states"),
        &states[0],
        1e-6 * scale + rounding,
        what,
        "replayed gait",
    )?;
    // What the MILP proved is optimality among gaits of at most `k` phases (as for crawlers).
    let status = match status {
        MilpStatus::Optimal => MilpStatus::OptimalAmongKPhases,
        s => s,
    };
    Ok(GeneralPhaseGait {
        max_phases: k,
        objective,
        certificate: Certificate {
            status,
            milp_objective,
            bound,
            gap: Certificate::gap_of(bound, objective, p.j_floor()),
        },
        durations,
        controls,
        states,
        held,
        reactions,
        state_gap,
        actuation_cost: sim.cost,
        rounds: 1,
    })
}

/// [`replay_phases`] from `x0`, and for a periodic problem also from where that replay ends:
/// the replay that ends nearer its start. The solver's `x0` lies on its faces to the MILP's
/// tolerance (`1e-9` of C's size), and the replay from it ends that far away; a gait that
/// holds a face forgets where it began along the face's normal, so the replay from the first
/// one's end is periodic to rounding there (seen: `1.04e-9` on §4's one link, then 0).
fn replay_orbit(
    p: &GeneralProblem,
    durations: &[f64],
    controls: &[Vec<f64>],
    x0: &[f64],
    what: &str,
) -> Result<(Vec<Vec<f64>>, GeneralSimulation)> {
    let first = replay_phases(p, durations, controls, x0, what)?;
    if p.boundary != Boundary::Periodic {
        return Ok(first);
    }
    let gap = |states: &[Vec<f64>]| max_diff(states.last().expect("states"), &states[0]);
    let before = gap(&first.0);
    if before == 0.0 {
        return Ok(first);
    }
    let end = first.0.last().expect("states").clone();
    let second = replay_phases(p, durations, controls, &end, what)?;
    Ok(if gap(&second.0) < before {
        second
    } else {
        first
    })
}
