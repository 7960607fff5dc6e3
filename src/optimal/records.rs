//! The records a result may carry beside its solution, whatever its kind and method: how `K`
//! was grown, the table of `J_m` over the grids, and the structured gait kept as the answer.
//! One struct, flattened into the crawler's [`GaitResult`](super::GaitResult) and (P)'s
//! answers (`crate::io::GeneralAnswer`) as [`ResultHead`](super::envelope::ResultHead) is, so
//! that a reader asks one place for them and one check reads them back
//! (`crate::optimal::consistency::check_records`).

use super::{ConvergenceRow, GrowthStop, PhaseStep};
use serde::{Deserialize, Serialize};

/// The records of a result (module docs); each is absent where the job kept none.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct ResultRecords {
    /// How `K` was grown ([`grow_phases`](crate::optimal::grow_phases) and its general twin),
    /// when a phase gait came from growing `K`: one row per `K` solved and why it stopped.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase_growth: Option<PhaseGrowthRecord>,
    /// The table of `J_m`, `m = 1..` up to the answer's (a global P_m answer), when asked
    /// (`--convergence`): the paper's discrete approximations P_m, grid by grid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<Vec<ConvergenceRow>>,
    /// The best structured gait ([`crate::optimal::structured`]) when it is the answer: the
    /// method's own gait was below it (the floor of every answer; `replaced` says what the
    /// method found), it was the start of a local method that did not improve on it, or the
    /// phase MILPs kept it as their start (no gait of at most `K` slip phases beats it). Its
    /// `J` is in the crawler's units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structured: Option<StructuredRecord>,
}

/// How `K` was grown ([`grow_phases`](crate::optimal::grow_phases)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PhaseGrowthRecord {
    /// One row per `K` solved.
    pub table: Vec<PhaseStep>,
    /// Why the growth stopped.
    pub stop: GrowthStop,
}

/// Why a structured gait is the answer ([`ResultRecords::structured`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StructuredRecord {
    /// The gait, in words (e.g. `structured: alternating triangle wave (odd links against even
    /// links)`).
    pub origin: String,
    /// What the method itself found and why it was not kept (e.g. `phase growth: J = 3.8889
    /// (K = 2), below the structured gait`).
    pub replaced: Option<String>,
}
