//! The active-set loop on the LPCC of P_m (theory §6), that of (P)'s local method
//! ([`crate::optimal::general::local`], two branches per step and face), which a crawler's
//! ([`crate::optimal::local`]) runs on the crawler's instance.
//!
//! With every complementarity pair on a fixed branch, P_m is a linear program whose branches
//! are column bounds, so one HiGHS model is re-solved from its previous basis after each
//! change of branches. After each LP the caller's `pivot` reads the columns and their reduced
//! costs, moves every *degenerate* pair (both sides of its complementarity zero, so that the
//! current point satisfies both branches and the next LP is at least as good) whose reduced
//! cost says that its other branch pays (the caller may also solve neighbouring LPs on `model`
//! where the reduced costs of a degenerate LP say nothing), and tells how many it moved. The
//! loop ends when none moves (stationary as far as the caller's tests see), when the objective
//! no longer improves (a guard against degenerate cycling), at the round limit or the time
//! limit (also when it ran out while `pivot` searched).

use super::solver::{Highs, SolveStatus};
use crate::error::{Error, Result};
use crate::progress;
use serde::{Deserialize, Serialize};

/// Why the local method stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LocalStop {
    /// No switch gains by the pivoting's test (`optimal::general::Pivoting`). Every answer a
    /// job reports, a crawler's or (P)'s (`Finish`, as `Neighbours` tests), passed the same
    /// test: no single switch gains, by the reduced costs of the last basis nor by a
    /// neighbouring LP (each that can gain). Under `ReducedCosts`, a screen of many starts,
    /// only the former.
    Stationary,
    /// Switches no longer improved the objective (degenerate cycling guard).
    Stalled,
    /// The round limit.
    RoundLimit,
    /// The time limit.
    TimeLimit,
}

/// What [`run`] ends with.
pub(crate) struct Outcome {
    /// The columns of the last LP optimum (the best one kept on a time limit).
    pub cols: Vec<f64>,
    /// Its objective, `J`.
    pub objective: f64,
    /// Why the loop stopped.
    pub stop: LocalStop,
    /// LPs solved.
    pub lp_solves: usize,
    /// Pairs moved in all.
    pub switches: usize,
}

/// Runs the active-set loop (module docs) on `model`, which maximises `J` and whose branches
/// the caller has set; `pivot(model, columns, reduced_costs, J)` moves the
/// profitable degenerate pairs and returns how many; `max_stalls` consecutive LPs without a gain
/// (by `1e-12` of `J`, or of `j_floor`, the problem's floor of `J`, where `|J|` is below it)
/// end the loop ([`LocalStop::Stalled`]); the job's deadline ([`crate::progress`]) ends it with
/// the last LP's answer ([`LocalStop::TimeLimit`]). `what` names P_m in errors.
pub(crate) fn run(
    model: &mut Highs,
    max_rounds: usize,
    max_stalls: usize,
    j_floor: f64,
    what: &str,
    mut pivot: impl FnMut(&mut Highs, &[f64], &[f64], f64) -> Result<usize>,
) -> Result<Outcome> {
    let mut lp_solves = 0;
    let mut switches = 0;
    let mut best = f64::NEG_INFINITY;
    let mut stalls = 0;
    let mut last: Option<(Vec<f64>, f64)> = None;
    let end = |cols, objective, stop, lp_solves, switches| {
        Ok(Outcome {
            cols,
            objective,
            stop,
            lp_solves,
            switches,
        })
    };
    model.until_deadline();
    loop {
        if progress::out_of_time()? {
            return match last {
                Some((cols, j)) => end(cols, j, LocalStop::TimeLimit, lp_solves, switches),
                None => Err(Error::TimeLimit(format!(
                    "{what}: the time limit was reached before the first LP"
                ))),
            };
        }
        let solved = model.solve()?;
        lp_solves += 1;
        match solved.status {
            SolveStatus::Optimal => {}
            SolveStatus::TimeLimit { .. } => {
                return match last {
                    Some((cols, j)) => end(cols, j, LocalStop::TimeLimit, lp_solves, switches),
                    None => Err(Error::TimeLimit(format!(
                        "{what}: the time limit was reached in the first LP"
                    ))),
                }
            }
            SolveStatus::Infeasible => {
                return Err(Error::Numerical(format!(
                    "{what}: an LP of fixed branches has no feasible point"
                )))
            }
        }
        let cols = solved.columns;
        let objective = solved.objective;
        if !best.is_finite() || objective > best + 1e-12 * best.abs().max(j_floor) {
            best = objective;
            stalls = 0;
        } else {
            stalls += 1;
        }
        if stalls >= max_stalls {
            return end(cols, objective, LocalStop::Stalled, lp_solves, switches);
        }
        if lp_solves >= max_rounds {
            return end(cols, objective, LocalStop::RoundLimit, lp_solves, switches);
        }
        let changed = pivot(model, &cols, &solved.column_duals, objective)?;
        switches += changed;
        if changed == 0 {
            let stop = if progress::out_of_time()? {
                LocalStop::TimeLimit
            } else {
                LocalStop::Stationary
            };
            return end(cols, objective, stop, lp_solves, switches);
        }
        last = Some((cols, objective));
    }
}
