//! Optimal gaits (theory §5–7): the gait problem (P) and what is known of its optimum.
//!
//! This layer holds the problem data ([`GaitProblem`]: period, rate bounds, actuation cost,
//! optional total-variation bound) and the closed-form optimum of the one-link crawler
//! ([`one_link_optimum`], theory §9, paper §4), against which every solver is tested, and the
//! global solver of the paper's discrete problems P_m ([`solve_discrete_global`], theory §6).

mod active_set;
pub mod bound_record;
pub mod chain;
pub mod consistency;
mod discrete;
mod discrete_global;
mod discrete_polish;
pub mod envelope;
mod gait_process;
pub mod general;
pub mod growth;
mod limits;
mod local;
mod milp;
mod one_link;
mod phase;
pub mod polish;
mod problem;
pub mod process;
mod records;
pub mod refinement;
mod result;
mod result_wire;
pub(crate) mod solver;
mod start;
pub mod structured;
mod structured_record;
pub(crate) mod units;

pub use discrete::{DiscreteSolution, MAX_M};
pub use discrete_global::{
    discrete_convergence, solve_discrete_global, solve_discrete_global_from,
    solve_discrete_global_with, ConvergenceRow,
};
pub use envelope::{local_status, read_envelope, ResultCertificate, ResultKind};
pub use limits::{check_shifts, check_size, MAX_BLOCK_STEPS, MAX_OPT_BLOCKS, MAX_SHIFTS};
pub use local::{
    check_local, sample_increments, shift_knots, solve_discrete_local,
    solve_discrete_local_shifted, LocalSolution, LocalStop, MAX_LOCAL_M,
};
pub(crate) use milp::replay;
pub use milp::{check_time_limit, gait_knots, Certificate, MilpStatus};
pub use one_link::{one_link_optimum, OneLinkOptimum};
pub(crate) use phase::work_limit;
pub use phase::{
    grow_phases, phase_gait_of, search_sequences, slip_mode_is_valid, slip_sequence,
    solve_phase_from, solve_phase_global, solve_phase_with, Formulation, GrowOptions, GrowthStop,
    PhaseGrowth, PhaseOptions, PhaseSolution, PhaseStep, SequenceSearch, DEFAULT_MAX_PHASES,
    DEFAULT_PATIENCE, DISSIPATION_ROW_BLOCKS, MAX_PHASES,
};
pub use problem::{Cost, GaitProblem, MAX_COST_RATIO, MAX_RATIO, MAX_SWEEP};
pub use records::{PhaseGrowthRecord, ResultRecords, StructuredRecord};
pub use result::{
    CrawlerParams, GaitData, GaitResult, LocalRecord, StartRecord, StructuredPieces, RESULT_FORMAT,
    RESULT_VERSION,
};
pub use start::{
    discrete_start, phase_start, pm_start, shifted_origin, Named, StartEvent, StartGait,
    StartKernels,
};
