//! P_m solved globally as a job (theory §6): the arguments checked, the MILP of
//! [`super::discrete`] solved in the optimisers' internal units ([`Units`]), a quadratic cost's
//! answer polished on its fixed slip pattern (`super::discrete_polish`), the answer converted
//! back to the user's units; and the convergence table over `m`. Above the formulation and the
//! polish, so that neither calls the other.

use super::discrete::{solve_discrete_in, DiscreteSolution, MAX_M};
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::polish::PolishRecord;
use crate::optimal::polish::POLISH_DEFAULT;
pub use crate::optimal::refinement::ConvergenceRow;
use crate::optimal::refinement::{converge, PmFamily};
use crate::optimal::units::{scale_all, scale_rows, Units};
use crate::optimal::Certificate;
use crate::optimal::{Cost, GaitProblem};

/// Solves P_m globally (module docs), within the job's deadline ([`crate::progress::within`]).
pub fn solve_discrete_global(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
) -> Result<DiscreteSolution> {
    solve_discrete_global_from(crawler, problem, m, None)
}

/// [`solve_discrete_global`] from a start gait given by its knots (`times` from 0 to the
/// period, `lengths` with the last row equal to the first, as in a [`GaitResult`]'s gait).
///
/// The start's actuation is sampled on the grid ([`super::local::sample_increments`]) and played by
/// catching-up to its periodic orbit; that trajectory is a feasible point of the MILP and
/// becomes HiGHS's first incumbent, so a solve cut short by the time limit returns at least
/// the start (its value is [`DiscreteSolution::start_objective`]). A start whose sampled control
/// breaks the problem's TV bound is refused (an error naming it), as HiGHS would drop it
/// unsaid; every other sampled start is a feasible point.
///
/// [`GaitResult`]: crate::optimal::GaitResult
pub fn solve_discrete_global_from(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start: Option<(&[f64], &[Vec<f64>])>,
) -> Result<DiscreteSolution> {
    solve_discrete_global_with(crawler, problem, m, start, POLISH_DEFAULT)
}

/// [`solve_discrete_global_from`], with `polish` saying whether the answer of a quadratic cost
/// is polished on its fixed slip pattern ([`crate::optimal::polish`]; the default,
/// [`POLISH_DEFAULT`], is on): the outer approximation leaves a rate off its bounds accurate
/// only to the cuts' spacing.
pub fn solve_discrete_global_with(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start: Option<(&[f64], &[Vec<f64>])>,
    polish: bool,
) -> Result<DiscreteSolution> {
    crawler.require_unique()?;
    problem.check_scales(crawler)?;
    if !(1..=MAX_M).contains(&m) {
        return Err(Error::invalid(
            "m",
            m,
            format!("must be in 1..={MAX_M} (a periodic gait needs two steps)"),
        ));
    }
    crate::optimal::check_size(crawler, 1 << m, "m", m)?;
    // Solved in the optimisers' internal units ([`Units`]), answered in the user's.
    let units = Units::of(crawler, problem);
    let (c, p) = (units.crawler(crawler)?, units.problem(problem));
    let start = start.map(|(t, l)| units.knots_in(t, l));
    let start = start.as_ref().map(|(t, l)| (t.as_slice(), l.as_slice()));
    let s = crate::progress::with_objective_scale(units.objective_scale(), || {
        solve_discrete_in(&c, &p, m, start)
    })?;
    let s = match p.cost {
        Cost::Quadratic { .. } if polish => super::discrete_polish::polish(&c, &p, s),
        _ => s,
    };
    Ok(units.discrete(&s))
}

/// Solves P_m for `m = 1..=max_m` (the paper's discrete approximations, §6), all within the job's
/// deadline ([`crate::progress::within`]) (each within what is left) and each started from the
/// previous optimum (every step of `P_{m-1}` cut in two: a gait of `P_m`); returns the table and
/// the finest solution. Stops early, keeping what was solved, when the time runs out (a time-limit
/// error when it ran out before `P_1` was solved).
pub fn discrete_convergence(
    crawler: &Crawler,
    problem: &GaitProblem,
    max_m: u32,
    progress: &mut dyn FnMut(&ConvergenceRow),
) -> Result<(Vec<ConvergenceRow>, DiscreteSolution)> {
    if !(1..=MAX_M).contains(&max_m) {
        return Err(Error::invalid(
            "m",
            max_m,
            format!("must be in 1..={MAX_M}"),
        ));
    }
    crate::optimal::check_size(crawler, 1 << max_m, "m", max_m)?;
    let family = ChainPm { crawler, problem };
    converge(&family, 1..=max_m, progress)
}

/// The crawler's P_m as a [`PmFamily`]: each `m` started from the previous optimum.
struct ChainPm<'a> {
    crawler: &'a Crawler,
    problem: &'a GaitProblem,
}

impl PmFamily for ChainPm<'_> {
    type Solution = DiscreteSolution;

    fn solve(&self, m: u32, previous: Option<&DiscreteSolution>) -> Result<DiscreteSolution> {
        let knots = previous.map(|s| s.knots(self.crawler.stiffness()));
        let start = knots.as_ref().map(|(t, l)| (&t[..], &l[..]));
        solve_discrete_global_from(self.crawler, self.problem, m, start)
    }
    fn value(s: &DiscreteSolution) -> (f64, &Certificate) {
        (s.objective(), &s.certificate)
    }
}

/// A P_m solution's conversion between unit systems ([`Units`]): here, beside the job that
/// solves in internal units, so that the unit system needs not know the formulation.
impl Units {
    /// A P_m solution from internal units to the user's.
    pub fn discrete(&self, s: &DiscreteSolution) -> DiscreteSolution {
        let (f, t, l) = (self.force, self.time, self.length);
        let mut out = DiscreteSolution {
            m: s.m,
            step: s.step * t,
            certificate: s.certificate.clone(),
            verified_displacement: s.verified_displacement * l,
            actuation_cost: s.actuation_cost * l,
            initial_state: scale_all(&s.initial_state, f),
            states: scale_rows(&s.states, f),
            controls: scale_rows(&s.controls, f / t),
            block_displacements: scale_rows(&s.block_displacements, l),
            rounds: s.rounds,
            start_objective: s.start_objective.map(|j| j * l),
            polish: s.polish.as_ref().map(|r| PolishRecord {
                objective_before: r.objective_before * l,
                objective_after: r.objective_after * l,
                control_change: r.control_change * f / t,
                ..r.clone()
            }),
        };
        out.certificate = self.certificate_scaled(&s.certificate, out.objective(), l, l);
        out
    }
}
