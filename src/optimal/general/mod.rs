//! The general problem (P) of the paper's §2 (theory §11): the geometry of its polyhedron by
//! linear programs (the Chebyshev centre, boundedness, redundant faces, vertices) and the
//! checks that need them; the paper's P_m globally as a MILP and locally by the active-set
//! method on its LPCC, both re-verified by the general simulator; where `A = 0`, exact
//! continuous-time gaits of at most `K` phases globally ([`phase`]), re-verified by the exact
//! simulator.

mod branch_lp;
mod chain_phase;
pub mod discrete;
mod discrete_rows;
pub mod geometry;
pub mod local;
pub mod phase;
mod phase_growth;
mod phase_polish;
mod phase_replay;
mod pm;
mod pm_milp;
mod polish;
pub mod projection;
mod units;

pub use chain_phase::{
    chain_gait, chain_gait_problem, chain_phase_gait, grow_chain_phases, ChainPieces,
};
pub use discrete::check as check_general_pm;
pub use discrete::{
    simulate_grid, solve_general_branch, GeneralPm, PmPath, MAX_GENERAL_M, PM_DATA_RANGE,
};
pub use geometry::{
    analyze_polyhedron, check_problem, check_with, Geometry, Vertex, MAX_VERTEX_SUBSETS,
};
pub use local::{
    check_general_local, default_starts, grid_controls, phase_grid, rotated, rotation_shift,
    solve_general_local, solve_general_local_best, BestLocal, GeneralLocal, LocalRules, MultiStart,
    Pivoting, StartFaces, MAX_GENERAL_LOCAL_M,
};
pub use phase::{
    check_general_phase, solve_general_phase, solve_general_transitions, GeneralPhaseGait,
    MAX_GENERAL_PHASES,
};
pub use phase_growth::{grow_general_phases, grow_general_transitions};
pub(crate) use phase_polish::{polish_phases_within, MilpPhases};
pub use phase_replay::replay_phases;
pub use pm::{general_convergence, solve_general_pm, solve_general_pm_from, solve_general_pm_with};
pub(crate) use pm_milp::{solve_pm_milp, PmOptions, PmStart};
pub(crate) use polish::{pm_on_pattern, PmColumns};
pub use projection::{project_polyhedron, ProjectedVertex, MAX_PROJECTED_VERTICES};
pub use units::control_and_speed;
pub(crate) use units::Units;
