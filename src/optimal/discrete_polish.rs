//! Polishing the crawler's P_m answer ([`crate::optimal::polish`]): P_m on the answer's fixed
//! slip pattern as a [`Qp`], which is (P)'s P_m polish on the crawler's instance
//! ([`crate::model::crawler_as_general`], `x~ = K^(-1/2) x`; the QP of
//! [`super::general::pm_on_pattern`]) with the crawler's TV bound added.
//!
//! The pattern is read from the replayed gait: block `b` slips forward in step `i` when its
//! displacement `D^i_b` is positive (beyond `1e-9` of the largest), backward when negative,
//! else sticks. Slipping forward, the block's forward face reacts on step `i` (`mu^i_(b+) >= 0`)
//! and is held at `x^(i+1)`; backward, its backward face; sticking, neither reacts and both
//! stay free to be left (a face held without slip). These are the branches of the catching-up
//! KKT system of the MILP (module docs of [`super::discrete`]), so every feasible point is a
//! catching-up gait and the MILP's answer is one. The QP maximises
//! `(1/N) sum D - (c/2) sum_{i,l} (U^i_l)^2 / h` (`D_b = (mu_(b+) - mu_(b-)) / s_b`) with the
//! cost exact, under the same rate bounds, zero mean and TV bound; its answer is replayed by
//! the crawler's simulator.

use super::discrete::{grid_cost, DiscreteSolution};
use super::general::{pm_on_pattern, PmColumns};
use super::milp::{certify, replay_grid, shift_to_zero_mean};
use super::polish::{no_worse, PolishRecord, Qp};
use super::GaitProblem;
use crate::error::Result;
use crate::model::{crawler_row_norms, Crawler, CrawlerInstance};

/// The slip of a block in a step: +1 forward, -1 backward, 0 stuck.
fn pattern(s: &DiscreteSolution) -> Vec<Vec<i8>> {
    let largest = s
        .block_displacements
        .iter()
        .flatten()
        .fold(0.0_f64, |a, d| a.max(d.abs()));
    let tol = 1e-9 * largest.max(1e-300);
    s.block_displacements
        .iter()
        .map(|r| {
            r.iter()
                .map(|&d| {
                    if d > tol {
                        1
                    } else if d < -tol {
                        -1
                    } else {
                        0
                    }
                })
                .collect()
        })
        .collect()
}

/// P_m on the slip pattern `slip` as a QP (minimising `-J`): (P)'s ([`pm_on_pattern`]) on the
/// crawler's instance, block `b` slipping forward (backward) its face `2b` (`2b + 1`, 0-based)
/// reacting, with the TV bound `sum_{i,l} |u^(i+1)_l - u^i_l| <= V` added. Its controls are
/// the crawler's rates, its states `x~ = K^(-1/2) x`.
fn build(
    inst: &CrawlerInstance,
    problem: &GaitProblem,
    m: u32,
    slip: &[Vec<i8>],
) -> (Qp, PmColumns) {
    let active: Vec<Vec<bool>> = slip
        .iter()
        .map(|r| r.iter().flat_map(|&s| [s > 0, s < 0]).collect())
        .collect();
    let (mut qp, cols) = pm_on_pattern(&inst.problem, m, &active);
    if let Some(v) = problem.max_total_variation {
        // |u^{i+1}_l - u^i_l| <= s^i_l, sum s <= V.
        let inf = f64::INFINITY;
        let steps = cols.u.len();
        let mut total = Vec::new();
        for i in 0..steps {
            for l in 0..cols.u[i].len() {
                let s = qp.add_column(0.0, 0.0, inf);
                let (u0, u1) = (cols.u[i][l], cols.u[(i + 1) % steps][l]);
                qp.add_row(0.0, inf, vec![(s, 1.0), (u1, -1.0), (u0, 1.0)]);
                qp.add_row(0.0, inf, vec![(s, 1.0), (u1, 1.0), (u0, -1.0)]);
                total.push((s, 1.0));
            }
        }
        qp.add_row(-inf, v, total);
    }
    (qp, cols)
}

/// Polishes `s` (module docs), in internal units: the polished answer when it replays to an
/// objective no worse than the MILP's, else `s` with the reason in its record. Never an error.
pub(super) fn polish(
    crawler: &Crawler,
    problem: &GaitProblem,
    s: DiscreteSolution,
) -> DiscreteSolution {
    let before = s.objective();
    match polished(crawler, problem, &s) {
        Ok(Ok(mut better)) => {
            let change = s
                .controls
                .iter()
                .flatten()
                .zip(better.controls.iter().flatten())
                .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
            if let Some(r) = better.polish.as_mut() {
                r.control_change = change;
            }
            better
        }
        Ok(Err(note)) => DiscreteSolution {
            polish: Some(PolishRecord::kept(before, note)),
            ..s
        },
        Err(e) => DiscreteSolution {
            polish: Some(PolishRecord::kept(before, e.to_string())),
            ..s
        },
    }
}

/// The polished answer, or why it is not taken.
fn polished(
    crawler: &Crawler,
    problem: &GaitProblem,
    s: &DiscreteSolution,
) -> Result<std::result::Result<DiscreteSolution, String>> {
    let what = format!("polishing P_{}", s.m);
    let slip = pattern(s);
    let steps = slip.len();
    let h = problem.period / steps as f64;
    let inst = problem.instance(crawler)?;
    let (qp, cols) = build(&inst, problem, s.m, &slip);
    let sol = qp.solve(&what)?;
    let val = |c: &usize| sol.v[*c];
    // The instance's controls are the crawler's rates: the increments are h u.
    let mut incs: Vec<Vec<f64>> = cols
        .u
        .iter()
        .map(|r| r.iter().map(|c| h * val(c)).collect())
        .collect();
    // An exact zero mean (the QP's is within its tolerance), as for the MILP's increments.
    shift_to_zero_mean(&mut incs);
    let state = |x: &Vec<usize>| inst.to_crawler(&x.iter().map(val).collect::<Vec<_>>());
    let x0 = state(&cols.x[0]);
    // D_b = (mu_(b+) - mu_(b-)) / s_b.
    let s_b = crawler_row_norms(crawler.stiffness());
    let displacement = cols
        .mu
        .iter()
        .map(|mu| {
            s_b.iter()
                .enumerate()
                .map(|(b, s)| (val(&mu[2 * b]) - val(&mu[2 * b + 1])) / s)
                .sum::<f64>()
        })
        .sum::<f64>()
        / crawler.blocks() as f64;
    let g = replay_grid(crawler, problem.period, &incs, &x0, &what)?;
    let qp_x: Vec<Vec<f64>> = cols.x.iter().map(state).collect();
    let force_scale = (0..crawler.blocks())
        .map(|b| crawler.mu_forward()[b] + crawler.mu_backward()[b])
        .fold(0.0_f64, f64::max);
    let moved = g
        .states
        .iter()
        .flatten()
        .zip(qp_x.iter().flatten())
        .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
    // The replayed orbit starts where the QP's does (the replay plays from x0 to the regime,
    // and on the pattern's orbit x0 is periodic): a state far from the QP's is a pattern left.
    if moved > 1e-7 * force_scale {
        return Ok(Err(format!(
            "the polished controls' process leaves the QP's by {moved:e}: the slip pattern \
             does not hold (the MILP's answer kept)"
        )));
    }
    let cost = grid_cost(problem, &incs, h);
    let objective = g.verified - cost;
    if !no_worse(objective, s.objective(), problem.j_floor(crawler)) {
        return Ok(Err(format!(
            "the polished objective {objective} is below the MILP's {} (the MILP's answer kept)",
            s.objective()
        )));
    }
    let mut certificate = certify(
        &what,
        problem.length_scale(crawler),
        s.certificate.status,
        displacement,
        s.certificate.bound,
        g.verified,
        cost,
    )?;
    certificate.milp_objective = s.certificate.milp_objective;
    let how = if sol.exact {
        "exact on the active set"
    } else {
        "interior point"
    };
    Ok(Ok(DiscreteSolution {
        certificate,
        verified_displacement: g.verified,
        actuation_cost: cost,
        initial_state: g.initial_state,
        states: g.states,
        controls: g.controls,
        block_displacements: g.block_displacements,
        polish: Some(PolishRecord {
            applied: true,
            objective_before: s.objective(),
            objective_after: objective,
            control_change: 0.0,
            note: how.into(),
        }),
        ..s.clone()
    }))
}
