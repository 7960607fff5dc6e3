//! Pieces shared by the MILP formulations of the gait problem.

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::{Cost, GaitProblem, MilpStatus};
use highs::{Col, HighsModelStatus, HighsSolutionStatus, RowProblem, Sense};

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

/// Refuses what the MILP formulations do not handle yet, and a bad time limit.
pub(crate) fn check_supported(problem: &GaitProblem, time_limit: Option<f64>) -> Result<()> {
    if problem.cost != Cost::None {
        return Err(Error::invalid(
            "gait.cost",
            "quadratic",
            "the MILP solvers handle f2 = 0 only so far",
        ));
    }
    if problem.max_total_variation.is_some() {
        return Err(Error::invalid(
            "gait.max_total_variation",
            "a bound",
            "is not handled by the MILP solvers yet",
        ));
    }
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

/// Solves a maximisation MILP with HiGHS (one thread, tight tolerances, optional time limit):
/// the solution columns, the objective, the dual bound and how it ended.
pub(crate) fn solve_max(
    pb: RowProblem,
    time_limit: Option<f64>,
    what: &str,
) -> Result<(Vec<f64>, f64, f64, MilpStatus)> {
    let mut model = pb.optimise(Sense::Maximise);
    model.make_quiet();
    model.set_option("threads", 1);
    model.set_option("mip_feasibility_tolerance", 1e-9);
    model.set_option("primal_feasibility_tolerance", 1e-9);
    model.set_option("mip_rel_gap", 1e-9);
    if let Some(t) = time_limit {
        model.set_option("time_limit", t);
    }
    let solved = model.solve();
    let status = match solved.status() {
        HighsModelStatus::Optimal => MilpStatus::Optimal,
        HighsModelStatus::ReachedTimeLimit
            if solved.primal_solution_status() == HighsSolutionStatus::Feasible =>
        {
            MilpStatus::TimeLimit
        }
        HighsModelStatus::ReachedTimeLimit => {
            return Err(Error::Numerical(format!(
                "{what}: the time limit was reached before any feasible gait was found"
            )))
        }
        other => {
            return Err(Error::Numerical(format!(
                "{what}: HiGHS ended with status {other:?}"
            )))
        }
    };
    let objective = solved.objective_value();
    let bound = solved
        .double_info_value(c"mip_dual_bound")
        .unwrap_or(objective);
    Ok((
        solved.get_solution().columns().to_vec(),
        objective,
        bound,
        status,
    ))
}
