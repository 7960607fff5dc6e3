//! The paper's discrete approximations P_m for `m = 1, 2, ...` (theory §6; paper §5, whose
//! Theorem 5.1 has the optima of P_m converge to that of (P)), solved in turn and tabulated,
//! written once for every formulation of P_m: the crawler's
//! ([`crate::optimal::discrete_convergence`]) and the general problem's
//! ([`crate::optimal::general::general_convergence`]), each behind [`PmFamily`].

use crate::error::{Error, Result};
use crate::optimal::milp::{Certificate, MilpStatus};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// One row of a convergence table: the optimum `J_m` of P_m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceRow {
    /// `m`.
    pub m: u32,
    /// `2^m`.
    pub steps: usize,
    /// `J_m` (verified).
    pub objective: f64,
    /// The MILP's bound on `J_m`.
    pub bound: f64,
    /// Its gap.
    pub gap: f64,
    /// How the solve ended.
    pub status: MilpStatus,
    /// Wall time, seconds.
    pub seconds: f64,
}

/// A formulation of P_m solved globally for each `m`: what [`converge`] is written against.
pub trait PmFamily {
    /// A verified P_m optimum with its certificate.
    type Solution;
    /// The global optimum of P_m (or the best found and its gap when the job's deadline cuts
    /// the MILP short); `previous`, the optimum of `P_(m-1)`, is its first incumbent where the
    /// family takes one (every step cut in two is a gait of P_m).
    fn solve(&self, m: u32, previous: Option<&Self::Solution>) -> Result<Self::Solution>;
    /// `J_m` of a solution, as re-verified, and its certificate.
    fn value(s: &Self::Solution) -> (f64, &Certificate);
}

/// Solves P_m for `m` in `ms` (usually `1..=max_m`) within the job's deadline, each from the
/// previous optimum where the family takes it; returns the table and the finest solution.
/// Stops early, keeping what was solved, when the time runs out (a time-limit error when it
/// ran out before the first `m` was solved). `progress` sees each row as it is solved.
pub fn converge<F: PmFamily>(
    family: &F,
    ms: std::ops::RangeInclusive<u32>,
    progress: &mut dyn FnMut(&ConvergenceRow),
) -> Result<(Vec<ConvergenceRow>, F::Solution)> {
    let mut table = Vec::new();
    let mut finest: Option<F::Solution> = None;
    let last = *ms.end();
    for m in ms {
        // The first m always runs: a limit spent before it is its time-limit error.
        if finest.is_some() && crate::progress::out_of_time()? {
            break;
        }
        let t0 = Instant::now();
        let s = match family.solve(m, finest.as_ref()) {
            Ok(s) => s,
            Err(Error::TimeLimit(_)) if finest.is_some() => break,
            Err(e) => return Err(e),
        };
        let (objective, c) = F::value(&s);
        let row = ConvergenceRow {
            m,
            steps: 1 << m,
            objective,
            bound: c.bound,
            gap: c.gap,
            status: c.status,
            seconds: t0.elapsed().as_secs_f64(),
        };
        let timed_out = c.status == MilpStatus::TimeLimit;
        progress(&row);
        table.push(row);
        finest = Some(s);
        if timed_out {
            break;
        }
    }
    let finest = finest.ok_or_else(|| Error::invalid("m", last, "must be at least 1"))?;
    Ok((table, finest))
}
