//! The general problem (P) of the paper's §2 (SPEC §11): the geometry of its polyhedron by
//! linear programs (the Chebyshev centre, boundedness, redundant faces, vertices) and the
//! checks that need them.

pub mod geometry;

pub use geometry::{
    analyze_polyhedron, check_problem, check_with, Geometry, Vertex, MAX_VERTEX_SUBSETS,
};
