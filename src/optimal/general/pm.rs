//! P_m of a general problem globally, as a job of two steps: the MILP with its outer
//! approximation ([`super::discrete`]), then, for a quadratic cost, the polish of its answer on
//! the fixed face pattern (`super::polish`). Above both, so that neither calls the other. And
//! the convergence table of P_m over `m` ([`general_convergence`]). A start, as a crawler's P_m
//! takes one: the process of a control on the grid as HiGHS's first incumbent
//! ([`solve_general_pm_from`]).

use super::discrete::GeneralPm;
use super::geometry::Geometry;
use super::pm_milp::{solve_pm_milp, PmOptions, PmRun, PmStart};
use crate::error::{Error, Result};
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
    let sol = solve_milp(p, g, m, &PmOptions::default())?;
    Ok(polished(p, sol, polish))
}

/// [`solve_general_pm_with`] from a start, as a crawler's P_m starts from a gait: `start` holds
/// one control per step of the `2^m` (in U, with zero mean where the problem asks it), whose
/// process on the grid (`local::start_process`, its periodic regime) is HiGHS's first
/// incumbent, so that the answer is never below it and a time limit returns at least it.
/// Returns the answer and `J` of the start's process. A start that is no process of the grid
/// (a control outside U, no periodic regime, another number of steps) is refused naming
/// `start`.
pub fn solve_general_pm_from(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    polish: bool,
    start: &[Vec<f64>],
) -> Result<(GeneralPm, f64)> {
    super::discrete::check(p, g, m)?;
    let steps = 1usize << m;
    if start.len() != steps {
        return Err(Error::invalid(
            "start",
            format!("{} steps", start.len()),
            format!("needs one control per step of P_{m} ({steps})"),
        ));
    }
    let (start_objective, sim) = super::local::start_process(p, g, start)?;
    let h = p.period / steps as f64;
    let opts = PmOptions {
        start: Some(PmStart {
            x: sim.x,
            u: start.to_vec(),
            // The step's multipliers are its reactions' rates times the step.
            mu: sim
                .lambda
                .iter()
                .map(|l| l.iter().map(|v| v * h).collect())
                .collect(),
        }),
        ..PmOptions::default()
    };
    let sol = solve_milp(p, g, m, &opts)?;
    Ok((polished(p, sol, polish), start_objective))
}

/// `sol` polished on its fixed face pattern where `polish` asks it and the cost is quadratic.
fn polished(p: &GeneralProblem, sol: GeneralPm, polish: bool) -> GeneralPm {
    if polish && p.cost != GeneralCost::None {
        super::polish::polish(p, sol)
    } else {
        sol
    }
}

/// The general problem's P_m as a [`PmFamily`]: each `m` solved from scratch, polished as
/// `polish` says. (Started from the previous optimum's controls, as a crawler's table is, the
/// three tables measured were faster on one and slower on two: `general_one_link.toml` to
/// `m = 6` 67 s against 77 s, `general_three_blocks.toml` to 4 12.1 s against 9.5 s,
/// `general_drift.toml` to 4 9.3 s against 9.0 s.)
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

/// The MILP's answer of [`solve_general_pm`] (from the start of `opts`, if any), with its outer
/// approximation ([`super::pm_milp`]), unpolished and re-verified; within the current deadline.
fn solve_milp(p: &GeneralProblem, g: &Geometry, m: u32, opts: &PmOptions) -> Result<GeneralPm> {
    super::discrete::check(p, g, m)?;
    let what = format!("P_{m} of the general problem");
    let run = solve_pm_milp(p, g, m, opts, &what)?;
    verified(p, m, &run, &what)
}

/// Replays the MILP's controls in the simulator from its `x^0` ([`super::discrete::replay`])
/// and certifies the answer.
fn verified(p: &GeneralProblem, m: u32, run: &PmRun, what: &str) -> Result<GeneralPm> {
    let r = super::discrete::replay(p, m, &run.lay, &run.cols, what)?;
    Ok(GeneralPm {
        m,
        objective: r.objective,
        certificate: Certificate {
            status: run.status,
            milp_objective: run.milp_objective,
            bound: run.bound,
            gap: Certificate::gap_of(run.bound, r.objective, p.j_floor()),
        },
        path: r.path,
        polish: None,
    })
}
