//! Exact continuous-time gaits of a general problem where `A = 0`
//! ([`crate::optimal::general::phase`]) as a job.

use crate::error::Result;
use crate::io::GeneralFile;
pub use crate::io::GeneralPhaseOptimized;
use crate::optimal::general::solve_general_phase;

/// Default `K` of [`GeneralPhaseSettings`]: 4 phases, what the paper's §4 one-link optimum
/// needs (free rise, slide on one face, free fall, slide on the other).
pub const DEFAULT_GENERAL_PHASES: usize = 4;

/// Settings of [`optimize_general_phase`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralPhaseSettings {
    /// `K`, the phases allowed (default [`DEFAULT_GENERAL_PHASES`]; at most
    /// [`crate::optimal::general::MAX_GENERAL_PHASES`]).
    pub max_phases: usize,
    /// Seconds for the MILP (`None`, the default: no limit).
    pub time_limit: Option<f64>,
}

impl Default for GeneralPhaseSettings {
    fn default() -> Self {
        GeneralPhaseSettings {
            max_phases: DEFAULT_GENERAL_PHASES,
            time_limit: None,
        }
    }
}

/// The globally optimal exact gait of at most `K` phases of a problem file (`A = 0`; a
/// quadratic `f2` by outer approximation), re-verified by the exact simulator. Errors name
/// `dynamics.A`, `max_phases` or `time_limit`.
pub fn optimize_general_phase(
    file: &GeneralFile,
    s: &GeneralPhaseSettings,
) -> Result<GeneralPhaseOptimized> {
    let (p, g) = super::general_problem(file)?;
    let solution = solve_general_phase(&p, &g, s.max_phases, s.time_limit)?;
    Ok(GeneralPhaseOptimized::new(file, p.period, solution))
}
