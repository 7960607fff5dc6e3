//! # crawlopt
//!
//! Simulation and optimal gaits of rate-independent soft crawlers: chains of blocks joined by
//! springs in series with actuators, on a surface with direction-dependent dry friction, moving
//! quasi-statically. The shape follows a Moreau sweeping process in the polytope C of admissible
//! spring forces (paper "On the optimal control of rate-independent soft crawlers").
//!
//! Citations "theory §N" throughout the code are to the sections of `docs/theory.md`, the
//! project's own account of the mathematics (conventions, formulations, reference values), which
//! in turn cites the paper's sections and equations.
//!
//! Layers, each knowing only those before it (no module imports from a layer above its own,
//! and no modules import each other in a cycle: `tests/layers.rs` checks both):
//! - [`error`], [`progress`], [`number`] and [`linalg`] at the bottom: the typed errors,
//!   cancellation and in-solve progress, the one formatter of human-readable numbers, dense
//!   decompositions with bounded effort;
//! - [`model`]: the crawler, the polytope C, the uniqueness condition, v_m; the general
//!   problem (P) of the paper's §2;
//! - [`sweep`]: projections onto C and onto its tangent cones (the hot kernel);
//! - [`integrate`]: actuations, catching-up and exact event-driven integration, periodic regime;
//! - [`optimal`]: the gait problem and its optimum (closed form for one link, the phase and P_m
//!   MILPs, the local method), and the same for (P);
//! - [`certify`]: necessary optimality conditions (Theorem 2.2, Theorems 6.1–6.2): multipliers
//!   of a gait and a checkable certificate; the upper bound over all periodic gaits;
//! - [`fit`]: identification of a crawler's stiffnesses and friction thresholds from a
//!   measured trajectory (least absolute deviations and exact parameter intervals, by LPs);
//! - [`io`] and [`present`], one layer: the TOML model and problem files, CSV files, the
//!   records of the general jobs; figures (SVG, PNG), text and the self-contained HTML report
//!   (presentation renders results, it runs no jobs);
//! - [`api`]: one call per job (analyze, simulate, optimize, bench, and the general problem's)
//!   with settings, events and cancellation ([`progress`]);
//! - [`study`]: parameter studies (`crawlopt sweep`): a job of the API over a grid of model
//!   parameters, in parallel, one row per point;
//! - the `crawlopt` binary (`src/cli/`) and the Python package (`python/`): thin layers that
//!   translate arguments and render results.
//!
//! ```
//! use crawlopt::integrate::{simulate, Actuation, Method, SimOptions, Waveform};
//! use crawlopt::Crawler;
//!
//! // One link, mu+ = 1 and mu- = 2 on both blocks, L = 3 sin(2 pi t): theory §10 gives
//! // max(0, 2A - 2) = 4 per period.
//! let crawler = Crawler::uniform(2, 1.0, 1.0, 2.0)?;
//! let act = Actuation::wave(Waveform::Sine, 1.0, vec![0.0], vec![3.0], vec![0.0])?;
//! let sim = simulate(&crawler, &act, &SimOptions { method: Method::Exact, ..SimOptions::default() })?;
//! assert!((sim.displacement_per_period.unwrap() - 4.0).abs() < 1e-12);
//! # Ok::<(), crawlopt::Error>(())
//! ```

pub mod api;
pub mod certify;
pub mod error;
pub mod fit;
pub mod integrate;
pub mod io;
pub mod linalg;
pub mod model;
pub mod number;
pub mod optimal;
pub mod present;
pub mod progress;
pub mod study;
pub mod sweep;

pub use error::{Error, Result};
pub use model::Crawler;

/// The README's Rust examples, compiled and run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
