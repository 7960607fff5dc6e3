//! # crawlopt
//!
//! Simulation and optimal gaits of rate-independent soft crawlers: chains of blocks joined by
//! springs in series with actuators, on a surface with direction-dependent dry friction, moving
//! quasi-statically. The shape follows a Moreau sweeping process in the polytope C of admissible
//! spring forces (see `SPEC.md` and the paper "On the optimal control of rate-independent soft
//! crawlers").
//!
//! Layers, each knowing only those before it:
//! - [`model`]: the crawler, the polytope C, the uniqueness condition, v_m;
//! - [`sweep`]: projections onto C and onto its tangent cones (the hot kernel);
//! - [`integrate`]: actuations, catching-up and exact event-driven integration, periodic regime;
//! - [`io`]: the TOML model file and CSV actuations;
//! - the `crawlopt` binary: a thin command-line layer.

pub mod error;
pub mod integrate;
pub mod io;
pub mod model;
pub mod sweep;

pub use error::{Error, Result};
pub use model::Crawler;
