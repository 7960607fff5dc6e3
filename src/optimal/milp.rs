//! Pieces shared by the MILP formulations of the gait problem.

use super::solver::{Highs, SolveStatus};
use crate::error::{Error, Result};
use crate::integrate::{simulate, Actuation, Method, SimOptions, Simulation};
use crate::model::Crawler;
use crate::optimal::GaitProblem;
use highs::{Col, RowProblem, Sense};
use serde::{Deserialize, Serialize};

/// How a solve ended (the MILPs, and the local method's last two variants): what was proven,
/// the same word in every front end ([`MilpStatus::as_str`], the serde name).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MilpStatus {
    /// Proven optimal for the problem solved (gap within HiGHS's tolerance): P_m for the
    /// discrete method.
    Optimal,
    /// Proven optimal among the gaits of at most `K` slip phases, `K` the certificate's
    /// `phases` (phase gaits: nothing is claimed about gaits of more phases).
    OptimalAmongKPhases,
    /// The answer has more slip phases than `K` (a known start, e.g. the best structured gait,
    /// that the `K`-phase MILP cannot hold) and the MILP proved that no gait of at most `K`
    /// slip phases does better: the bound (the answer's own `J`) is global over that class,
    /// which the answer lies outside. Nothing is claimed about the answer's own class.
    DominatesKPhases,
    /// The time limit was reached with a feasible incumbent; see the gap and the bound (for a
    /// phase growth, the bound of the `K` the limit cut short, `K` the certificate's `phases`).
    TimeLimit,
    /// The outer approximation of a quadratic cost stopped (round limit) before the incumbent
    /// met the bound; see the gap.
    ApproximationLimit,
    /// The local method ended at a point where no switch of modes pays (no global claim).
    Stationary,
    /// The local method stopped improving before its stationarity test held (no global claim).
    Stalled,
}

impl MilpStatus {
    /// The status word: the serde name, shown as such by the text, JSON, Python and sweep
    /// tables.
    pub fn as_str(self) -> &'static str {
        match self {
            MilpStatus::Optimal => "optimal",
            MilpStatus::OptimalAmongKPhases => "optimal_among_k_phases",
            MilpStatus::DominatesKPhases => "dominates_k_phases",
            MilpStatus::TimeLimit => "time_limit",
            MilpStatus::ApproximationLimit => "approximation_limit",
            MilpStatus::Stationary => "stationary",
            MilpStatus::Stalled => "stalled",
        }
    }

    /// Whether the answer is proven optimal for its class (P_m, or gaits of at most `K` slip
    /// phases). Not [`MilpStatus::DominatesKPhases`]: that answer is outside the class its
    /// bound covers.
    pub fn is_optimal(self) -> bool {
        matches!(self, MilpStatus::Optimal | MilpStatus::OptimalAmongKPhases)
    }
}

/// What a MILP solve proves about the gait it returns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    /// Solver outcome.
    pub status: MilpStatus,
    /// The MILP's objective.
    pub milp_objective: f64,
    /// The MILP's upper bound on the optimum of its problem (NaN, written `null`, for a local
    /// method's answer, which proves no bound).
    #[serde(deserialize_with = "nan_if_null")]
    pub bound: f64,
    /// Gap `(bound - verified) / max(|verified|, floor)`, `floor` the problem's own scale of
    /// `J` capped at 1 ([`Certificate::gap_of`]): relative above it, in units of it below (NaN,
    /// written `null`, without a bound).
    #[serde(deserialize_with = "nan_if_null")]
    pub gap: f64,
}

/// A number written by `serde_json`, which writes NaN as `null`: `null` reads back as NaN.
fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// The certificate of a MILP answer: the MILP moved the crawler `milp_displacement` per
/// period, the simulator `verified`; the gait costs `cost` (exactly evaluated), and the MILP's
/// dual `bound` is on the objective `J`. An error when the two displacements disagree beyond the
/// MILP's tolerances.
#[allow(clippy::too_many_arguments)]
pub(crate) fn certify(
    what: &str,
    scale: f64,
    status: MilpStatus,
    milp_displacement: f64,
    bound: f64,
    verified: f64,
    cost: f64,
) -> Result<Certificate> {
    check_verified(what, milp_displacement, verified, scale)?;
    let objective = verified - cost;
    Ok(Certificate {
        status,
        milp_objective: milp_displacement,
        bound,
        gap: Certificate::gap_of(bound, objective, scale.min(1.0)),
    })
}

impl Certificate {
    /// The gap of a bound over a verified objective, relative to the larger of `|J|` and
    /// `floor`, the problem's own scale of `J` (a crawler's length unit,
    /// [`GaitProblem::j_floor`]; (P)'s capped at 1,
    /// [`GeneralProblem::j_floor`](crate::model::general::GeneralProblem::j_floor)): relative
    /// where `|J|` is above it, in units of it below. A floor of 1 in every problem made the
    /// gap absolute below `|J| = 1`, so a crawler of displacements `1e-12` stated a gap of
    /// `1e-12` for a bound twice its `J`.
    pub fn gap_of(bound: f64, objective: f64, floor: f64) -> f64 {
        ((bound - objective) / objective.abs().max(floor)).max(0.0)
    }
}

/// The outer approximation stops when the incumbent's true objective is within this of the
/// MILP's bound (relative above the problem's floor of `J`, in units of it below).
pub(crate) const OA_TOL: f64 = 1e-6;

/// The independent re-verification: the solver's displacement per period must be the one the
/// simulator finds for the returned gait, to the solvers' tolerances, relative to the problem's
/// length unit `scale` ([`GaitProblem::length_scale`]) or to the displacement if larger.
pub(crate) fn check_verified(what: &str, solver: f64, verified: f64, scale: f64) -> Result<()> {
    let within = (solver - verified).abs() <= 1e-6 * (scale + verified.abs());
    if !within {
        return Err(Error::Numerical(format!(
            "{what}: the gait moves the crawler {verified} per period when simulated, not {solver}"
        )));
    }
    Ok(())
}

/// Outer approximation of the quadratic cost inside a MILP (theory §7: the cost of a piece of
/// duration `tau` with increment `U` is the perspective `(c/2) U^2 / tau`, convex).
///
/// An epigraph variable `g >= U^2 / tau` is cut by tangents `g >= 2 r U - r^2 tau` at rates
/// `r` (exact at `U = r tau`, below elsewhere since `(U - r tau)^2 >= 0`). With fewer cuts the
/// MILP under-estimates the cost, so its dual bound stays a valid bound on `J`; rates of each
/// solution are added until the true objective of the incumbent meets the bound.
#[derive(Debug, Clone)]
pub(crate) struct TangentRates {
    /// Rates per link.
    pub rates: Vec<Vec<f64>>,
}

impl TangentRates {
    /// Starts from 17 rates evenly spread over `[-a_l, a_l]`.
    pub fn new(a: &[f64]) -> Self {
        TangentRates {
            rates: a
                .iter()
                .map(|&al| (0..17).map(|i| al * (i as f64 / 8.0 - 1.0)).collect())
                .collect(),
        }
    }

    /// Adds rate `r` for link `l` unless a rate within `1e-9 a` is there; true if added.
    pub fn add(&mut self, l: usize, r: f64, a: f64) -> bool {
        if self.rates[l].iter().any(|q| (q - r).abs() <= 1e-9 * a) {
            return false;
        }
        self.rates[l].push(r);
        true
    }

    /// Adds the cuts of link `l` for epigraph column `g`, increment `u` and duration `tau`
    /// (a column, or a fixed step when `tau_col` is `None`).
    pub fn add_cuts(
        &self,
        pb: &mut RowProblem,
        l: usize,
        g: Col,
        u: Col,
        tau_col: Option<Col>,
        tau: f64,
    ) {
        for &r in &self.rates[l] {
            match tau_col {
                Some(t) => pb.add_row(0.0.., [(g, 1.0), (u, -2.0 * r), (t, r * r)]),
                None => pb.add_row(-r * r * tau.., [(g, 1.0), (u, -2.0 * r)]),
            }
        }
    }
}

/// Knot times (from 0) and actuator lengths (from `L(0) = 0`) of a gait given by phase
/// durations and increments `U_j = K (L_{j+1} - L_j)`; one knot more than phases.
pub fn gait_knots(
    durations: &[f64],
    increments: &[Vec<f64>],
    stiffness: &[f64],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let mut times = vec![0.0];
    let mut lengths = vec![vec![0.0; stiffness.len()]];
    for (d, u) in durations.iter().zip(increments) {
        times.push(times[times.len() - 1] + d);
        let last = &lengths[lengths.len() - 1];
        let next = last
            .iter()
            .zip(u)
            .zip(stiffness)
            .map(|((l, u), k)| l + u / k)
            .collect();
        lengths.push(next);
    }
    (times, lengths)
}

/// [`gait_knots`] of a gait given by piece durations and controls `u_j` (force per time).
pub(crate) fn control_knots(
    durations: &[f64],
    controls: &[Vec<f64>],
    stiffness: &[f64],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    let increments: Vec<Vec<f64>> = durations
        .iter()
        .zip(controls)
        .map(|(d, u)| u.iter().map(|v| v * d).collect())
        .collect();
    gait_knots(durations, &increments, stiffness)
}

/// Plays a gait (durations and increments over one period) with the given method from `x0`
/// (or from rest) until the periodic regime, recording one period: the independent
/// re-verification of every optimizer answer, and the process `certify` checks.
pub(crate) fn replay(
    crawler: &Crawler,
    period: f64,
    durations: &[f64],
    increments: &[Vec<f64>],
    x0: Option<&[f64]>,
    method: Method,
    what: &str,
) -> Result<Simulation> {
    // The durations a solver returns sum to the period only within its tolerance; a sum
    // above it would put the last knots at or past the period (a gait at the threshold of
    // locomotion, a T = 2w, once failed so). The process is rate-independent, so scaling the
    // times to sum to the period exactly leaves the displacement as it is.
    let total: f64 = durations.iter().sum();
    let scaled: Vec<f64>;
    let durations = if total > 0.0 && total != period {
        scaled = durations.iter().map(|d| d * (period / total)).collect();
        &scaled[..]
    } else {
        durations
    };
    let (mut times, mut lengths) = gait_knots(durations, increments, crawler.stiffness());
    times.pop();
    lengths.pop();
    let act = Actuation::of_gait(period, times, lengths)?;
    let sim = simulate(
        crawler,
        &act,
        &SimOptions {
            method,
            steps_per_period: durations.len(),
            record_periods: 1,
            initial_state: x0.map(<[f64]>::to_vec),
            ..SimOptions::default()
        },
    )?;
    if !sim.converged {
        return Err(Error::Numerical(format!(
            "{what}: the returned gait did not reach a periodic regime"
        )));
    }
    Ok(sim)
}

/// Shifts each column of equal-step increments (one row per step) by its mean, to an exact zero
/// mean: a solver's increments have theirs only within its tolerance.
pub(crate) fn shift_to_zero_mean(rows: &mut [Vec<f64>]) {
    let steps = rows.len() as f64;
    for l in 0..rows.first().map_or(0, Vec::len) {
        let mean = rows.iter().map(|u| u[l]).sum::<f64>() / steps;
        for u in rows.iter_mut() {
            u[l] -= mean;
        }
    }
}

/// A P_m gait replayed by catching-up on its grid (the re-verification): verified displacement,
/// orbit state, states, per-step block displacements and controls.
pub(crate) struct GridReplay {
    pub verified: f64,
    pub initial_state: Vec<f64>,
    pub states: Vec<Vec<f64>>,
    pub block_displacements: Vec<Vec<f64>>,
    pub controls: Vec<Vec<f64>>,
}

/// Replays grid increments from `x0` (see [`replay`]).
pub(crate) fn replay_grid(
    crawler: &Crawler,
    period: f64,
    increments: &[Vec<f64>],
    x0: &[f64],
    what: &str,
) -> Result<GridReplay> {
    let h = period / increments.len() as f64;
    let sim = replay(
        crawler,
        period,
        &vec![h; increments.len()],
        increments,
        Some(x0),
        Method::CatchingUp,
        what,
    )?;
    let (Some(verified), Some(tr)) = (sim.displacement_per_period, sim.trajectory) else {
        return Err(Error::Numerical(format!(
            "{what}: the replay recorded no period on the orbit"
        )));
    };
    Ok(GridReplay {
        verified,
        initial_state: sim.orbit_state,
        block_displacements: tr
            .positions
            .windows(2)
            .map(|w| w[1].iter().zip(&w[0]).map(|(a, b)| a - b).collect())
            .collect(),
        states: tr.x,
        controls: increments
            .iter()
            .map(|r| r.iter().map(|v| v / h).collect())
            .collect(),
    })
}

/// `F_b(x) = x_{b-1} - x_b` as `(column, coefficient)` pairs (`x_{-1} = x_n = 0`).
pub(crate) fn force_row(x: &[Col], b: usize) -> Vec<(Col, f64)> {
    let n = x.len();
    let mut f = Vec::with_capacity(2);
    if b > 0 {
        f.push((x[b - 1], 1.0));
    }
    if b < n {
        f.push((x[b], -1.0));
    }
    f
}

/// A bound on every block speed: `|X'_b| <= sqrt(sum_l 1/k_l) sqrt(sum_l a_l^2 / k_l)`.
///
/// Some block sticks and `X'_{b+1} - X'_b = (u_b - x'_b)/k_b`, so
/// `|X'_b| <= sum_l |u_l - x'_l| / k_l <= sqrt(sum 1/k) |u - x'|_{K^-1}`; `x'` is the
/// `K^-1`-projection of `u` onto a cone containing 0, so `|u - x'|_{K^-1} <= |u|_{K^-1}`.
pub(crate) fn block_speed_bound(crawler: &Crawler, problem: &GaitProblem) -> f64 {
    let k = crawler.stiffness();
    let s1: f64 = k.iter().map(|k| 1.0 / k).sum();
    let s2: f64 = problem
        .rate_bound
        .iter()
        .zip(k)
        .map(|(a, k)| a * a / k)
        .sum();
    (s1 * s2).sqrt()
}

/// Refuses a time limit that is not positive and finite (field `time_limit`).
pub fn check_time_limit(time_limit: Option<f64>) -> Result<()> {
    if let Some(t) = time_limit {
        if !(t.is_finite() && t > 0.0) {
            return Err(Error::invalid(
                "time_limit",
                t,
                "must be positive and finite",
            ));
        }
    }
    Ok(())
}

/// Solves a maximisation MILP with HiGHS (one thread, tight tolerances, within what is left of
/// the job's deadline, [`crate::progress::within`]): the solution columns, the objective, the
/// dual bound and how it ended. The bound is HiGHS's; an optimal solve without one (an LP) is
/// its own bound, and a solve the time limit cut short before HiGHS had one proves none (`None`:
/// the caller says what else is known, never the incumbent's own value).
///
/// `start` is a feasible point (all columns) that HiGHS takes as its first incumbent.
/// `abs_gap` is the absolute gap at which the proof stops, in the objective's units: HiGHS's
/// default (1e-6) would certify a gait whose whole displacement is 1e-6 as optimal, so callers
/// pass a fraction of the problem's length scale ([`GaitProblem::length_scale`]).
pub(crate) fn solve_max(
    pb: RowProblem,
    what: &str,
    start: Option<&[f64]>,
    abs_gap: f64,
) -> Result<(Vec<f64>, f64, Option<f64>, MilpStatus)> {
    let mut h = Highs::new(pb, Sense::Maximise, what)?;
    if let Some(x) = start {
        // A start that does not fit is only a lost hint, never a wrong answer.
        h.start(x);
    }
    h.option("mip_feasibility_tolerance", 1e-9)?;
    h.option("primal_feasibility_tolerance", 1e-9)?;
    h.option("mip_rel_gap", 1e-9)?;
    h.option("mip_abs_gap", abs_gap)?;
    // RINS and RENS, HiGHS's sub-MIP heuristics around the incumbent and the LP solution, cost
    // more than they find here: the MILPs' optima are found early (or given as the start) and
    // the time goes into the proof. Without them (one thread, idle machine): the three-block
    // phase growth to K = 5 in 0.55 s instead of 1.0 s (K = 5 alone 0.34 s, was 0.62 s), P_3 (8
    // steps) in 0.66 s (1.08 s) and P_4 (16 steps) in 10.4 s (13.9 s), the four-block P_3 in
    // 10.7 s (16.7 s), P_m then with the crawler's former MILP of its own; the other heuristics
    // (feasibility jump, shifting, ZI rounding, root reduced cost) changed nothing measurable.
    h.option("mip_heuristic_run_rins", false)?;
    h.option("mip_heuristic_run_rens", false)?;
    h.until_deadline();
    let a = h.solve()?;
    let status = match a.status {
        SolveStatus::Optimal => MilpStatus::Optimal,
        SolveStatus::TimeLimit { feasible: true } => MilpStatus::TimeLimit,
        SolveStatus::TimeLimit { feasible: false } => {
            return Err(Error::TimeLimit(format!(
                "{what}: the time limit was reached before any feasible gait was found"
            )))
        }
        SolveStatus::Infeasible => {
            return Err(Error::Infeasible(format!("{what}: no feasible point")))
        }
    };
    let bound = a
        .dual_bound
        .or((status == MilpStatus::Optimal).then_some(a.objective));
    Ok((a.columns, a.objective, bound, status))
}
