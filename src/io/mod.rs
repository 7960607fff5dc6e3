//! Input and output files: the TOML model file (a contract: fields are only ever added; written
//! for a fitted crawler by [`crawler_toml`]) and CSV actuations and trajectories (measured ones
//! read by [`read_fit_csv`]).
//!
//! ```toml
//! [crawler]
//! blocks = 3            # N >= 2
//! stiffness = 1.0       # k, a number or one per link                 (force / length)
//! mu_forward = 1.0      # mu^+, a number or one per block             (force)
//! mu_backward = 3.0     # mu^-, a number or one per block             (force)
//!
//! [actuation]           # what `simulate` plays
//! kind = "sine"         # sine | triangle | piecewise_linear | csv
//! period = 1.0          #                                              (time)
//! amplitude = [2.0, 2.0]   # a number or one per link                 (length)
//! phase_deg = [0.0, 90.0]  # L_l(t) = mean_l + amplitude_l * s(2 pi t / period - phase_l)
//! mean = 0.0               # (length)
//! # piecewise_linear: times = [...], lengths = [[L_1, .., L_n] per knot] (periodic)
//! # csv: path = "gait.csv" (relative to this file): columns t, L_1, .., L_n; header optional
//!
//! [simulation]          # optional
//! initial_state = [0.0, 0.0]  # x(0), link compressions (force); default 0
//!
//! [gait]                # the optimal-gait problem (P)
//! period = 10.0
//! max_actuator_speed = 1.0   # |L_l'| <= this (a number or one per link); a_l = k_l * speed
//! cost = { kind = "none" }   # or { kind = "quadratic", weight = c }: f2(u) = (c/2)|u|^2
//! # optional: max_total_variation = V  (Theorem 2.1's class U_K)
//! ```

mod config;
mod csv_io;
pub mod general;
mod general_claims;
mod general_consistency;
mod general_results;
pub mod json;
mod model_toml;
mod problem_file;
mod result_file;
mod simulation_doc;

pub(crate) use config::escape_controls;
pub use config::{
    ActuationSpec, CostSpec, CrawlerSpec, GaitSpec, ModelFile, NumberOrList, SimulationSpec,
    MAX_BLOCKS,
};
pub use csv_io::{read_actuation_csv, remove_staged_files, write_trajectory_csv, AtomicFile};
pub use general::{write_general_csv, GeneralFile};
pub use general_results::{
    Check, CheckStatus, GeneralAnalysis, GeneralAnswer, GeneralSimulated, GeneralSolution,
    LocalStarts,
};
pub use model_toml::{crawler_toml, read_fit_csv, write_text, MAX_FIT_CSV_BYTES};
pub use problem_file::ProblemFile;
pub use result_file::{GaitAnswer, ResultFile};
pub use simulation_doc::{
    SimulationBody, SimulationDocument, SIMULATION_FORMAT, SIMULATION_VERSION,
};

use crate::error::{Error, Result};

/// Largest result file or J_m table read (bytes): a gait at the optimisers' size limit (2^18
/// block-steps) is tens of MiB as JSON.
pub const MAX_RESULT_BYTES: u64 = 256 << 20;

/// The text of an input file of at most `limit` bytes (a gait result, a J_m table). Only
/// regular files (or links to one) are read, so a FIFO or a device (`/dev/zero`) is refused
/// before it is opened instead of blocking or filling memory; errors name the file.
pub fn read_input_text(path: &std::path::Path, limit: u64) -> Result<String> {
    let io = |reason: String| Error::Io {
        path: path.display().to_string(),
        reason,
    };
    let bytes =
        csv_io::read_input_file(path, limit).map_err(|e| io(format!("cannot read: {e}")))?;
    String::from_utf8(bytes).map_err(|_| io("cannot read: not UTF-8 text".into()))
}
