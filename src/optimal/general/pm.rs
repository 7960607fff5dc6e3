//! P_m of a general problem globally, as a job of two steps: the MILP with its outer
//! approximation ([`super::discrete`]), then, for a quadratic cost, the polish of its answer on
//! the fixed face pattern (`super::polish`). Above both, so that neither calls the other. And
//! the convergence table of P_m over `m` ([`general_convergence`]).

use super::discrete::{solve_milp, GeneralPm};
use super::geometry::Geometry;
use crate::error::Result;
use crate::model::general::{GeneralCost, GeneralProblem};
use crate::optimal::milp::Certificate;
use crate::optimal::polish::POLISH_DEFAULT;
use crate::optimal::refinement::{converge, ConvergenceRow, PmFamily};

/// Solves P_m globally ([`super::discrete`]'s module docs), within the job's deadline
/// ([`crate::progress::within`]). A quadratic cost's answer is polished ([`solve_general_pm_with`],
/// [`POLISH_DEFAULT`]).
pub fn solve_general_pm(p: &GeneralProblem, g: &Geometry, m: u32) -> Result<GeneralPm> {
    solve_general_pm_with(p, g, m, POLISH_DEFAULT)
}

/// [`solve_general_pm`], with `polish` saying whether the answer of a quadratic cost is
/// polished on its fixed face pattern ([`crate::optimal::polish`]): the outer approximation
/// leaves a control off the bounds of U accurate only to the cuts' spacing.
pub fn solve_general_pm_with(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    polish: bool,
) -> Result<GeneralPm> {
    let sol = solve_milp(p, g, m)?;
    Ok(if polish && p.cost != GeneralCost::None {
        super::polish::polish(p, sol)
    } else {
        sol
    })
}

/// The general problem's P_m as a [`PmFamily`]: each `m` solved from scratch (the general
/// MILP takes no start), polished as `polish` says.
struct GeneralPms<'a> {
    p: &'a GeneralProblem,
    g: &'a Geometry,
    polish: bool,
}

impl PmFamily for GeneralPms<'_> {
    type Solution = GeneralPm;

    fn solve(&self, m: u32, _previous: Option<&GeneralPm>) -> Result<GeneralPm> {
        solve_general_pm_with(self.p, self.g, m, self.polish)
    }
    fn value(s: &GeneralPm) -> (f64, &Certificate) {
        (s.objective, &s.certificate)
    }
}

/// Solves the general problem's P_m for `m = 1..=max_m` (paper §5: the optima of P_m converge to
/// that of (P)) by the loop the crawler's table runs ([`crate::optimal::refinement::converge`]),
/// all within the job's deadline ([`crate::progress::within`]); returns the table and the finest
/// solution, stopping early (keeping what was solved) when the time runs out. `max_m` is checked
/// first, naming `m`. The table starts at the coarsest `m` whose explicit step is stable for `A` (1
/// when `A = 0`; a stiff drift refuses coarser grids).
pub fn general_convergence(
    p: &GeneralProblem,
    g: &Geometry,
    max_m: u32,
    polish: bool,
    progress: &mut dyn FnMut(&ConvergenceRow),
) -> Result<(Vec<ConvergenceRow>, GeneralPm)> {
    super::discrete::check(p, g, max_m)?;
    let first = (1..=max_m)
        .find(|&m| super::discrete::check_explicit_step(p, m).is_ok())
        .unwrap_or(max_m);
    let family = GeneralPms { p, g, polish };
    converge(&family, first..=max_m, progress)
}
