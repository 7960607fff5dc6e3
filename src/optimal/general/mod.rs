//! The general problem (P) of the paper's §2 (SPEC §11): the geometry of its polyhedron by
//! linear programs (the Chebyshev centre, boundedness, redundant faces, vertices) and the
//! checks that need them; the paper's P_m globally as a MILP, re-verified by the general
//! simulator.

pub mod discrete;
pub mod geometry;

pub use discrete::{solve_general_branch, solve_general_pm, GeneralPm, MAX_GENERAL_M};
pub use geometry::{
    analyze_polyhedron, check_problem, check_with, Geometry, Vertex, MAX_VERTEX_SUBSETS,
};
