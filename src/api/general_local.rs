//! The general problem's P_m solved locally as a job ([`optimize_general_local`]): the start
//! policy (the file's `[input]`, else square waves along each control axis, each at several
//! time shifts), the time budget across starts, progress and cancellation; and the global
//! job with hooks ([`optimize_general_with_hooks`]).

use super::events::{run_with, Hooks};
use super::settings::{DEFAULT_M_LOCAL, DEFAULT_SHIFTS};
use crate::error::{Error, Result};
use crate::io::GeneralFile;
pub use crate::io::GeneralLocalOptimized;
use crate::optimal::general::{
    check_general_local, default_starts, grid_controls, solve_general_local, GeneralLocal,
};

/// [`super::optimize_general`] with `hooks`: cancellable (within a HiGHS callback) and
/// reporting its stage and the MILP's incumbent and bound as events.
pub fn optimize_general_with_hooks(
    file: &GeneralFile,
    s: &super::GeneralPmSettings,
    hooks: Hooks<'_>,
) -> Result<super::GeneralOptimized> {
    run_with(hooks, |em| {
        em.stage(if s.convergence {
            format!("P_1..P_{} of the general problem, global MILPs", s.m)
        } else {
            format!(
                "P_{} of the general problem ({} steps), global MILP",
                s.m,
                1u64 << s.m.min(63)
            )
        });
        super::general::pm_job(file, s, em)
    })
}

/// Settings of [`optimize_general_local`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralLocalSettings {
    /// `m`: P_m on `2^m` steps (default [`DEFAULT_M_LOCAL`], as for crawlers).
    pub m: u32,
    /// Each start is tried rotated by `j 2^m / shifts` steps, `j = 0..shifts` (default
    /// [`DEFAULT_SHIFTS`], as for crawlers).
    pub shifts: usize,
    /// Seconds for all starts (`None`: no limit): the best answer so far when it runs out.
    pub time_limit: Option<f64>,
}

impl Default for GeneralLocalSettings {
    fn default() -> Self {
        GeneralLocalSettings {
            m: DEFAULT_M_LOCAL,
            shifts: DEFAULT_SHIFTS,
            time_limit: None,
        }
    }
}

/// P_m of a problem file, locally ([`crate::optimal::general::local`]), from every start of
/// the policy (module docs), keeping the best verified answer. Cancellable through `hooks`;
/// a stage event per start.
pub fn optimize_general_local(
    file: &GeneralFile,
    s: &GeneralLocalSettings,
    hooks: Hooks<'_>,
) -> Result<GeneralLocalOptimized> {
    let (p, g) = super::general::general_problem(file)?;
    check_general_local(&p, &g, s.m)?;
    crate::optimal::check_shifts(s.shifts)?;
    crate::optimal::check_time_limit(s.time_limit)?;
    let (starts, start_from) = match &file.input {
        Some(_) => {
            let grid = grid_controls(&file.input(&p)?, s.m);
            let mm = grid.len();
            let mut rotations: Vec<usize> = (0..s.shifts).map(|j| j * mm / s.shifts).collect();
            rotations.dedup();
            let starts = rotations
                .into_iter()
                .map(|r| {
                    let mut w = grid.clone();
                    w.rotate_right(r);
                    w
                })
                .collect();
            (starts, "input")
        }
        None => (default_starts(&p, s.m, s.shifts), "square_waves"),
    };
    if starts.is_empty() {
        return Err(Error::invalid(
            "control",
            "U",
            "holds no segment through 0 along any control axis: no square-wave start; give \
             one as [input]",
        ));
    }
    run_with(hooks, |em| {
        crate::progress::within(s.time_limit, || {
            let n = starts.len();
            let mut best: Option<(GeneralLocal, usize)> = None;
            let mut tried = 0;
            for (k, start) in starts.iter().enumerate() {
                if best.is_some() && crate::progress::out_of_time()? {
                    break;
                }
                em.stage(format!(
                    "local LPCC method on P_{} ({} steps), start {} of {n}",
                    s.m,
                    1usize << s.m,
                    k + 1
                ));
                let sol = match solve_general_local(&p, &g, s.m, start) {
                    Ok(sol) => sol,
                    Err(Error::TimeLimit(_)) if best.is_some() => break,
                    Err(e) => return Err(e),
                };
                tried += 1;
                let out_of_time = sol.stop == crate::optimal::LocalStop::TimeLimit;
                if best.as_ref().is_none_or(|(b, _)| {
                    sol.objective > b.objective + 1e-9 * (1.0 + b.objective.abs())
                }) {
                    best = Some((sol, k));
                }
                if out_of_time {
                    break;
                }
            }
            // The first start either stores its answer or returns its error.
            let (solution, best_start) = best.expect("the first start solved or an error returned");
            Ok(GeneralLocalOptimized::new(
                file,
                p.period,
                (start_from, tried, best_start),
                solution,
            ))
        })
    })
}
