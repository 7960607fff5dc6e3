//! The crawler model (theory §1–3): parameters, the polytope C of admissible spring forces,
//! the uniqueness condition and the displacement function v_m.
//!
//! Conventions. Blocks are indexed `b = 0..N` (0 = rear) and links `l = 0..n`, `n = N - 1`, link
//! `l` joining blocks `l` and `l + 1`; user-facing output numbers both from 1, as the paper does.
//! The state is the link compression in force units `x_l = k_l (L_l - z_l)` and the spring force
//! on block `b` is `F_b(x) = x_{b-1} - x_b` with `x_{-1} = x_n = 0`.
//!
//! This layer knows nothing of integrators or solvers.

mod analysis;
mod crawler;
pub mod general;
mod general_checks;
mod general_crawler;
mod general_drift;
mod general_sets;
mod general_structure;
mod polytope;
mod uniqueness;
mod vm;

pub use analysis::{Analysis, OneLink, MAX_LINKS_FOR_VERTICES};
pub use crawler::Crawler;
pub use general_crawler::{crawler_as_general, crawler_row_norms, CrawlerInstance};
pub use general_structure::ChainView;
pub use polytope::{Face, FaceSign, MAX_LINKS_FOR_NORMALS};
pub use uniqueness::{SubsetSearch, Uniqueness};
pub use vm::{block_velocities, VmAnalysis, VmClass};
