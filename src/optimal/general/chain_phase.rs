//! The chain's phase formulation for a general problem that is a crawler's gait problem
//! ([`GeneralProblem::as_chain`]): the crawler's growth over `K` *slip* phases (transitions
//! free, [`crate::optimal::grow_phases`]) in place of the general `K`-phase MILP, its gait
//! written back in the problem's own terms and re-verified by the general exact simulator.
//! As on the crawler, the growth starts from the chain's best structured gait, so the answer
//! is never below it ([`structured_start`]).
//!
//! **What the answer claims.** Every general gait of at most `K` phases has at most `K` slip
//! phases, so the chain MILP's bound at `K` bounds every general gait of at most `K` phases;
//! the gait it returns may have up to `2K` phases (a transition before each slip phase) and is
//! then better than any general gait of at most `K` phases could be. So the certificate
//! `optimal_among_k_phases` with `K` says what it says for the general formulation — no gait of
//! at most `K` phases does better — and the value is at least the general MILP's at the same
//! `K` (the three-block crawler: 2.6 with `K = 4`, which the general formulation needs 8
//! phases for). Durations, controls, the held faces and the reaction rates per phase are the
//! crawler gait's through the map of [`crate::model::crawler_as_general`]: `x~ = K^(-1/2) x`
//! (`x~_l = beta_l x_l`), the same controls, the block `b` slipping forward (backward) holds its
//! forward (backward) face with the reaction rate `s_b D_b / tau` (`D_b` the block's
//! displacement over the phase, `s_b` the norm of its row), and `J = lambda J_crawler`.

use super::geometry::{into_u, Geometry};
use super::phase::{check_phase_growth, GeneralPhaseGait};
use super::phase_replay::replay_phases;
use crate::error::{Error, Result};
use crate::model::general::GeneralProblem;
use crate::model::ChainView;
use crate::model::Crawler;
use crate::optimal::growth::{Growth, GrowthRange, PhaseStep};
use crate::optimal::milp::Certificate;
use crate::optimal::structured::{best_structured, StructuredOptions};
use crate::optimal::{
    grow_phases, Cost, GaitProblem, GrowOptions, PhaseSolution, StructuredRecord,
};

/// The crawler's gait problem of a chain view: period from `p`, the rate bounds `a_l` of the
/// box U (the crawler's `k_l` times its actuator speeds, so the speeds are `a_l / k_l`), the
/// cost `c / lambda`. The crawler's checks of its scales name the problem's own fields
/// (`control.upper[l]`, `objective.cost.weight`, `problem.period`).
pub fn chain_gait_problem(p: &GeneralProblem, view: &ChainView) -> Result<GaitProblem> {
    let cost = match view.cost_weight {
        None => Cost::None,
        Some(weight) => Cost::Quadratic { weight },
    };
    let speeds: Vec<f64> = view
        .rate_bounds
        .iter()
        .zip(view.crawler.stiffness())
        .map(|(a, k)| a / k)
        .collect();
    let renamed = |e: Error| match e {
        Error::InvalidParameter {
            field,
            value,
            reason,
        } => {
            let field = if let Some(rest) = field.strip_prefix("gait.max_actuator_speed") {
                format!("control.upper{rest}")
            } else if let Some(rest) = field.strip_prefix("gait.cost") {
                format!("objective.cost{rest}")
            } else if let Some(rest) = field.strip_prefix("gait.") {
                format!("problem.{rest}")
            } else {
                field
            };
            Error::InvalidParameter {
                field,
                value,
                reason,
            }
        }
        other => other,
    };
    let gp = GaitProblem::new(&view.crawler, p.period, &speeds, cost, None).map_err(renamed)?;
    gp.check_scales(&view.crawler).map_err(renamed)?;
    Ok(gp)
}

/// `K` grown over `range` (slip phases) by the crawler's growth on the chain of `p` (module
/// docs), each `K` reported to `progress` in the problem's units; the best gait written back
/// as a general phase gait, with the record of the structured start where the growth kept it
/// (as a crawler's answer records it). Checked as [`super::grow_general_phases`] is (errors name
/// `max_phases`, `patience`), within the job's deadline ([`crate::progress::within`]).
pub fn grow_chain_phases(
    p: &GeneralProblem,
    g: &Geometry,
    view: &ChainView,
    range: GrowthRange,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<(Growth<GeneralPhaseGait>, Option<StructuredRecord>)> {
    check_phase_growth(p, g, range)?;
    grow_chain(p, view, range, progress)
}

/// [`grow_chain_phases`], checked, within the deadline.
fn grow_chain(
    p: &GeneralProblem,
    view: &ChainView,
    range: GrowthRange,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<(Growth<GeneralPhaseGait>, Option<StructuredRecord>)> {
    let gp = chain_gait_problem(p, view)?;
    let (start, origin) = structured_start(&view.crawler, &gp)?.unzip();
    let lambda = view.objective_scale;
    let floor = p.j_floor();
    let opts = GrowOptions {
        min_phases: range.min_phases,
        max_phases: range.max_phases,
        patience: range.patience,
        start: start.clone(),
        ..GrowOptions::default()
    };
    let scaled = |st: &PhaseStep| PhaseStep {
        objective: lambda * st.objective,
        bound: lambda * st.bound,
        gap: Certificate::gap_of(lambda * st.bound, lambda * st.objective, floor),
        ..st.clone()
    };
    let g = grow_phases(&view.crawler, &gp, &opts, &mut |st| progress(&scaled(st)))?;
    let kept = start.is_some_and(|s| s.durations == g.best.durations && s.states == g.best.states);
    let record = origin.filter(|_| kept).map(|origin| StructuredRecord {
        origin,
        replaced: None,
    });
    let growth = Growth {
        best: chain_phase_gait(p, view, &g.best)?,
        table: g.table.iter().map(scaled).collect(),
        stop: g.stop,
    };
    Ok((growth, record))
}

/// The best structured gait of the chain's crawler (travelling, alternating and grouped
/// waves, [`best_structured`]) in phase form: the growth's start, so that every MILP takes it
/// as its incumbent where it fits `K` and as its cutoff where it has more slip phases. As on
/// the crawler, the answer is then at least that gait, and a `K` it beats says
/// `dominates_k_phases` (three blocks at `K = 2`: J = 1.5 where the 2-phase MILP alone finds
/// only the idle gait). `None` where no structured gait reached a periodic orbit or it has no
/// phase form (the growth then starts from nothing, as before); with the gait, its origin in
/// words.
fn structured_start(
    crawler: &Crawler,
    gp: &GaitProblem,
) -> Result<Option<(PhaseSolution, String)>> {
    let Some(found) = best_structured(crawler, gp, &StructuredOptions::default())? else {
        return Ok(None);
    };
    let form = found.best.phase_form(crawler, gp).ok();
    Ok(form.map(|f| (f, found.best.origin)))
}

/// A crawler's exact gait on its own pieces (a phase MILP's, or a local method's): durations,
/// controls, states at the knots, block displacements and slip modes per piece, and its `J`.
#[derive(Debug, Clone, Copy)]
pub struct ChainPieces<'a> {
    /// Piece durations.
    pub durations: &'a [f64],
    /// Controls per piece (the crawler's `u = k L'`).
    pub controls: &'a [Vec<f64>],
    /// The crawler's states at the knots.
    pub states: &'a [Vec<f64>],
    /// Block displacements per piece.
    pub block_displacements: &'a [Vec<f64>],
    /// Slip modes per piece and block (-1, 0, 1).
    pub modes: &'a [Vec<i8>],
    /// The crawler's `J`.
    pub objective: f64,
}

impl<'a> ChainPieces<'a> {
    /// The pieces of a phase MILP's solution.
    pub fn of_phase(s: &'a PhaseSolution) -> Self {
        ChainPieces {
            durations: &s.durations,
            controls: &s.controls,
            states: &s.states,
            block_displacements: &s.block_displacements,
            modes: &s.modes,
            objective: s.objective(),
        }
    }
}

/// A crawler's phase gait on the chain of `p` as a general phase gait (module docs), replayed
/// by the general exact simulator; an error if the replay's `J` is not `lambda` times the
/// crawler's or its states are not the crawler's mapped.
pub fn chain_phase_gait(
    p: &GeneralProblem,
    view: &ChainView,
    s: &PhaseSolution,
) -> Result<GeneralPhaseGait> {
    let lambda = view.objective_scale;
    let bound = lambda * s.certificate.bound;
    let mut g = chain_gait(p, view, ChainPieces::of_phase(s))?;
    g.max_phases = s.phases;
    g.certificate = Certificate {
        status: s.certificate.status,
        // The crawler's MILP records its displacement; (P)'s certificate records the MILP's J:
        // the replayed J with the MILP's own displacement (the displacement alone, 2.17, was
        // above the bound 1.55 with a quadratic cost, and the file was refused on reading).
        milp_objective: g.objective
            + lambda * (s.certificate.milp_objective - s.verified_displacement),
        bound,
        gap: Certificate::gap_of(bound, g.objective, p.j_floor()),
    };
    g.rounds = s.rounds;
    Ok(g)
}

/// A crawler's exact gait on the chain of `p` as a general phase gait of as many phases as it
/// has pieces, replayed by the general exact simulator (module docs; an error if the replay's
/// `J` is not `lambda` times the crawler's or its states are not the crawler's mapped), with no
/// claim: its certificate has no bound (NaN) and the status `stalled` until the caller says
/// what its method proved.
pub fn chain_gait(
    p: &GeneralProblem,
    view: &ChainView,
    s: ChainPieces<'_>,
) -> Result<GeneralPhaseGait> {
    let beta: Vec<f64> = (0..p.states()).map(|l| p.dynamics.b[l][l]).collect();
    let to_general = |x: &[f64]| -> Vec<f64> { x.iter().zip(&beta).map(|(x, b)| x * b).collect() };
    let what = "the chain's gait";
    let x0 = to_general(&s.states[0]);
    // The crawler's rates lie in its box to its own tolerance, which may exceed the replay's
    // (measured: 5.4e-10 above a bound of 4.45, refused as "outside U"): clipped into U.
    let mut centre = None;
    let controls = s
        .controls
        .iter()
        .map(|u| into_u(&p.control, &mut centre, u.clone()))
        .collect::<Result<Vec<_>>>()?;
    let (states, sim) = replay_phases(p, s.durations, &controls, &x0, what)?;
    let objective = sim.objective.unwrap_or(sim.reward - sim.cost);
    let lambda = view.objective_scale;
    let want = lambda * s.objective;
    let scale = p.c.scale();
    let state_gap = states
        .iter()
        .zip(s.states)
        .flat_map(|(a, b)| {
            let b = to_general(b);
            a.iter()
                .zip(b)
                .map(|(a, b)| (a - b).abs())
                .collect::<Vec<_>>()
        })
        .fold(0.0_f64, f64::max);
    if (objective - want).abs() > 1e-9 * want.abs().max(p.j_floor()) || state_gap > 1e-9 * scale {
        return Err(Error::Numerical(format!(
            "{what}: the general replay gives J = {objective} for the crawler's {want} and \
             states off by {state_gap:e}"
        )));
    }
    // Each block's row norm s_b (the bracket e_(b-1) / beta_(b-1) - e_b / beta_b).
    let n = p.states();
    let s_b: Vec<f64> = (0..=n)
        .map(|b| {
            let back = if b >= 1 { beta[b - 1].powi(-2) } else { 0.0 };
            let front = if b < n { beta[b].powi(-2) } else { 0.0 };
            (back + front).sqrt()
        })
        .collect();
    let sigma = p.c.faces();
    let mut held = Vec::with_capacity(s.durations.len());
    let mut reactions = Vec::with_capacity(s.durations.len());
    for (j, tau) in s.durations.iter().enumerate() {
        let mut h = Vec::new();
        let mut r = vec![0.0; sigma];
        for (b, &mode) in s.modes[j].iter().enumerate() {
            let d = s.block_displacements[j][b];
            if mode != 0 {
                let f = view.faces[b][usize::from(mode < 0)];
                h.push(f + 1);
                r[f] = s_b[b] * d.abs() / tau;
            }
        }
        h.sort_unstable();
        held.push(h);
        reactions.push(r);
    }
    Ok(GeneralPhaseGait {
        max_phases: s.durations.len(),
        objective,
        certificate: Certificate {
            status: crate::optimal::MilpStatus::Stalled,
            milp_objective: objective,
            bound: f64::NAN,
            gap: f64::NAN,
        },
        durations: s.durations.to_vec(),
        controls,
        states,
        held,
        reactions,
        state_gap,
        actuation_cost: sim.cost,
        rounds: 0,
    })
}
