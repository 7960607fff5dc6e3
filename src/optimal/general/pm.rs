//! P_m of a general problem globally, as a job of two steps: the MILP with its outer
//! approximation ([`super::discrete`]), then, for a quadratic cost, the polish of its answer on
//! the fixed face pattern (`super::polish`). Above both, so that neither calls the other.

use super::discrete::{solve_milp, GeneralPm};
use super::geometry::Geometry;
use crate::error::Result;
use crate::model::general::{GeneralCost, GeneralProblem};
use crate::optimal::polish::POLISH_DEFAULT;

/// Solves P_m globally ([`super::discrete`]'s module docs); `time_limit` in seconds. A quadratic cost's answer is
/// polished ([`solve_general_pm_with`], [`POLISH_DEFAULT`]).
pub fn solve_general_pm(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    time_limit: Option<f64>,
) -> Result<GeneralPm> {
    solve_general_pm_with(p, g, m, time_limit, POLISH_DEFAULT)
}

/// [`solve_general_pm`], with `polish` saying whether the answer of a quadratic cost is
/// polished on its fixed face pattern ([`crate::optimal::polish`]): the outer approximation
/// leaves a control off the bounds of U accurate only to the cuts' spacing.
pub fn solve_general_pm_with(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    time_limit: Option<f64>,
    polish: bool,
) -> Result<GeneralPm> {
    crate::optimal::check_time_limit(time_limit)?;
    let sol = crate::progress::within(time_limit, || solve_milp(p, g, m))?;
    Ok(if polish && p.cost != GeneralCost::None {
        super::polish::polish(p, sol)
    } else {
        sol
    })
}
