//! The paper's discrete problem P_m (theory §6) of a crawler, solved globally: the MILP of (P)'s
//! P_m ([`crate::optimal::general::discrete`]) on the crawler's instance
//! ([`crate::model::crawler_as_general`]: `x~ = K^(-1/2) x`, a pair of faces per block, the
//! multipliers `mu_(b+-) = s_b max(+-D_b, 0)` of its block displacements), with what a crawler
//! adds: a start gait as the first incumbent (the previous `m`'s optimum in the convergence
//! table), a bound on the control's total variation `TV(u) <= V`, and its work bound for a
//! solve cut short before HiGHS had one.
//!
//! On the dyadic grid `h = T / 2^m` (`M = 2^m` steps), in the crawler's terms:
//!
//! ```text
//! maximise   sum_i (1/N) sum_b D^i_b - h sum_i f2(u^i)
//! subject to x^{i+1} = x^i + h u^i - K sum_b D^i_b nu_b,     x^M = x^0         (catching-up)
//!            -mu_b^- <= F_b(x^{i+1}) <= mu_b^+                               (x^{i+1} in C)
//!            a block moves forward (backward) only with F_b(x^{i+1}) at mu_b^+ (-mu_b^-)
//!            |u^i_l| <= a_l,  sum_i u^i = 0,  sum_{i,l} |u^{i+1}_l - u^i_l| <= V (optional)
//! ```
//!
//! The complementarity is (P)'s big-M form per face of the instance, its columns in the chain's
//! order (every step's forward faces, then the backward ones: the order of the crawler's former
//! MILP of its own, which HiGHS searches about as fast), the cost (P)'s outer approximation per
//! link (a tangent of each link's parabola at 17 rates, then at each answer's rates).
//!
//! The dynamics with the sign and complementarity conditions are exactly the KKT system of the
//! catching-up projection (theory §4), which has a unique solution, so every feasible point is a
//! catching-up trajectory. The time-shift symmetry of a periodic gait is left to
//! HiGHS: the rows that break it (step 0 carries the largest displacement; or `x^0_1` is the
//! least `x^i_1`) made the solve slower, not faster, on the three-block instance at `2^m = 16`
//! (143 s and 34 s against 25 s without, one thread; `crawlopt optimize
//! examples/three_blocks_gait.toml --method discrete --m 4`, with the crawler's former MILP of
//! its own), because they cut off the incumbents HiGHS's heuristics find first. So did the
//! crawler's rows `z_(b+) + z_(b-) <= 1` (a block slips one way at most), added to (P)'s MILP
//! for the chain's face pairs (its columns then in the default order): the four-block P_3
//! (`four_blocks_varied_gait.toml`) in 21.4 s against 8.3 s without, the three-block P_4
//! 12.6 s against 10.5 s (one run each); and a per-face bound of the multipliers from the
//! chain's block speed bound changed nothing measurable.
//!
//! Every answer is re-verified by the crawler's own simulator: the returned increments are
//! played by catching-up ([`simulate`](crate::integrate::simulate)) from the returned initial
//! state until the periodic regime, and the verified displacement is the one reported.

use crate::error::{Error, Result};
use crate::model::{crawler_row_norms, Crawler, CrawlerInstance};
use crate::optimal::general::geometry::analyze_polyhedron;
use crate::optimal::general::{solve_pm_milp, PmOptions, PmStart};
use crate::optimal::milp::{certify, control_knots, replay_grid, shift_to_zero_mean, GridReplay};
use crate::optimal::polish::PolishRecord;
use crate::optimal::sample_increments;
use crate::optimal::{Certificate, GaitProblem};
use serde::Serialize;

/// Largest `m` accepted (`2^m` steps).
pub const MAX_M: u32 = 16;

/// A solution of P_m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscreteSolution {
    /// `m` (the grid has `2^m` steps).
    pub m: u32,
    /// `h = T / 2^m`.
    pub step: f64,
    /// What the MILP proves (its bound is on the optimum of P_m).
    pub certificate: Certificate,
    /// Displacement per period, re-verified by simulating the returned gait.
    pub verified_displacement: f64,
    /// `h sum_i f2(u^i)`.
    pub actuation_cost: f64,
    /// Initial state `x^0` (on the limit cycle).
    pub initial_state: Vec<f64>,
    /// States `x^i` at the grid times `i h`, `i = 0..=2^m` (the last equals the first).
    pub states: Vec<Vec<f64>>,
    /// Controls `u^i` (force per time), one row per step.
    pub controls: Vec<Vec<f64>>,
    /// Block displacements `D^i_b` per step, from the simulation.
    pub block_displacements: Vec<Vec<f64>>,
    /// MILP solves (outer-approximation rounds for a quadratic cost, else 1).
    pub rounds: usize,
    /// `J` of the start gait on this grid, when the solve had one
    /// ([`super::solve_discrete_global_from`]).
    pub start_objective: Option<f64>,
    /// What polishing on the fixed slip pattern did ([`crate::optimal::polish`]); `None`
    /// without a quadratic cost (the MILP's answer is then exact) or with polishing off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polish: Option<PolishRecord>,
}

impl DiscreteSolution {
    /// `J_m` = verified displacement minus actuation cost.
    pub fn objective(&self) -> f64 {
        self.verified_displacement - self.actuation_cost
    }

    /// The gait's knots: times `i h` and actuator lengths from `L(0) = 0` (see
    /// [`gait_knots`](crate::optimal::gait_knots)).
    pub fn knots(&self, stiffness: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
        control_knots(
            &vec![self.step; self.controls.len()],
            &self.controls,
            stiffness,
        )
    }
}

/// [`super::solve_discrete_global_from`] in internal units, arguments checked: (P)'s P_m MILP
/// on the crawler's instance (module docs), its answer replayed by the crawler's simulator.
pub(super) fn solve_discrete_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start: Option<(&[f64], &[Vec<f64>])>,
) -> Result<DiscreteSolution> {
    let steps = 1usize << m;
    let h = problem.period / steps as f64;
    let what = format!("P_{m}");
    let inst = problem.instance(crawler)?;
    let geometry = analyze_polyhedron(&inst.problem.c)?;
    let start = match start {
        Some((times, lengths)) => Some(grid_start(crawler, problem, m, times, lengths, &what)?),
        None => None,
    };
    let opts = PmOptions {
        start: start
            .as_ref()
            .map(|(incs, traj, _)| pm_start(crawler, &inst, incs, h, traj)),
        total_variation: problem.max_total_variation,
        abs_gap: Some(problem.length_scale(crawler) * 1e-9),
        bound_hint: Some(crate::optimal::work_limit(crawler, problem)),
        // The instance is in the crawler's internal units already.
        keep_units: true,
    };
    let run = solve_pm_milp(&inst.problem, &geometry, m, &opts, &what)?;
    let mut incs: Vec<Vec<f64>> = run
        .controls()
        .iter()
        .map(|u| u.iter().map(|v| v * h).collect())
        .collect();
    shift_to_zero_mean(&mut incs);
    let x0 = inst.to_crawler(&run.states()[0]);
    let cost = grid_cost(problem, &incs, h);
    let g = replay_grid(crawler, problem.period, &incs, &x0, &what)?;
    Ok(DiscreteSolution {
        m,
        step: h,
        certificate: certify(
            &what,
            problem.length_scale(crawler),
            run.status,
            run.reward(&inst.problem),
            run.bound,
            g.verified,
            cost,
        )?,
        verified_displacement: g.verified,
        actuation_cost: cost,
        initial_state: g.initial_state,
        block_displacements: g.block_displacements,
        states: g.states,
        controls: g.controls,
        rounds: run.rounds,
        start_objective: start.map(|s| s.2),
        polish: None,
    })
}

/// A gait on P_m's grid (increments `incs` of steps `h`, replayed as `traj`) as a process of
/// the crawler's instance: `x~ = K^(-1/2) x`, `u = U / h` and the multipliers
/// `mu_(b+-) = s_b max(+-D_b, 0)` of its block displacements.
pub(crate) fn pm_start(
    crawler: &Crawler,
    inst: &CrawlerInstance,
    incs: &[Vec<f64>],
    h: f64,
    traj: &GridReplay,
) -> PmStart {
    let s_b = crawler_row_norms(crawler.stiffness());
    PmStart {
        x: traj.states.iter().map(|x| inst.to_general(x)).collect(),
        u: incs
            .iter()
            .map(|u| u.iter().map(|v| v / h).collect())
            .collect(),
        mu: traj
            .block_displacements
            .iter()
            .map(|d| {
                d.iter()
                    .zip(&s_b)
                    .flat_map(|(&v, &s)| [s * v.max(0.0), s * (-v).max(0.0)])
                    .collect()
            })
            .collect(),
    }
}

/// The start gait `(times, lengths)` on the grid of P_m: its increments (checked against a bound
/// on TV(u)), its trajectory from rest and its objective `J` there; the MILP's first incumbent.
fn grid_start(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    times: &[f64],
    lengths: &[Vec<f64>],
    what: &str,
) -> Result<(Vec<Vec<f64>>, GridReplay, f64)> {
    let big_m = 1usize << m;
    let h = problem.period / big_m as f64;
    let a = &problem.rate_bound;
    let incs = sample_increments(
        times,
        lengths,
        crawler.stiffness(),
        a,
        problem.period,
        big_m,
    );
    // Sampling keeps the rate bounds and the zero mean; a TV bound it may break, and
    // HiGHS would drop such a start without a word.
    if let Some(v) = problem.max_total_variation {
        let tv: f64 = (0..big_m)
            .flat_map(|i| {
                let next = &incs[(i + 1) % big_m];
                incs[i].iter().zip(next).map(|(u0, u1)| (u1 - u0).abs())
            })
            .sum::<f64>()
            / h;
        if tv > v * (1.0 + 1e-9) {
            return Err(Error::invalid(
                "start",
                format!("TV(u) = {tv}"),
                format!("exceeds gait.max_total_variation = {v} on the grid of P_{m}"),
            ));
        }
    }
    let from_rest = vec![0.0; crawler.links()];
    let traj = replay_grid(crawler, problem.period, &incs, &from_rest, what)?;
    let objective = traj.verified - grid_cost(problem, &incs, h);
    Ok((incs, traj, objective))
}

/// `h sum_i f2(U^i / h)`.
pub(super) fn grid_cost(problem: &GaitProblem, increments: &[Vec<f64>], h: f64) -> f64 {
    increments
        .iter()
        .map(|u| {
            let rate: Vec<f64> = u.iter().map(|v| v / h).collect();
            h * problem.cost.eval(&rate)
        })
        .sum()
}
