//! Parameter studies: one job (analyze, simulate or optimize) over a grid of the numbers of a
//! problem file, a crawler's model or a general problem (P) (theory §11), each point through
//! the library, in parallel, one row per point. (The name `sweep` is taken
//! by the projections of the sweeping process, [`crate::sweep`]; the command is
//! `crawlopt sweep`.)
//!
//! A sweep file (TOML):
//!
//! ```toml
//! base = "one_link_gait.toml"      # a model file, relative to this one (or an inline [model])
//! job = "optimize"                 # analyze | simulate | optimize
//! combine = "product"              # or "zip" (axes of one length, taken together)
//! [settings]                       # the job's options, named as the command's flags
//! time_limit = 30.0                # (time_limit or time-limit)
//! [[axis]]
//! field = "crawler.mu_backward"    # a list field takes a 1-based index: crawler.mu_backward[2]
//! values = [1.5, 2.0, 3.0]
//! [[axis]]
//! field = "gait.period"
//! range = { from = 2.0, to = 20.0, count = 10, scale = "linear" }   # or "log"
//! ```
//!
//! With a general problem file as the base (`[sweeping_process]`, [`Kind::General`]) the axes
//! are over its own fields: `problem.period`, `sweeping_process.offsets[j]` (`c_j`),
//! `control.lower[i]`, `objective.face_weights[j]`, `objective.cost.weight`, a matrix entry
//! `dynamics.A[i][k]`, ... (a list without an index has every entry set); each entry must be
//! in the base (the axes change numbers, never dimensions). Each point runs the API call of
//! its job ([`crate::api::simulate_general`]; [`crate::api::optimize_file`], the one
//! optimisation of both kinds, with the same [`crate::api::OptimizeSettings`]), into the same
//! table.
//!
//! - [`SweepSpec`]: the parsed file; its points ([`Point`]) have deterministic ids (the place
//!   in the expansion; in a product the first axis varies slowest), the same on every machine.
//! - [`run`] with [`SweepSettings`] (threads, [`Shard`], points to skip, full results,
//!   cancellation): every point through [`crate::api`] on a rayon pool, one point per thread;
//!   each finished point is handed to the caller with the progress (done, total, ETA). An
//!   ill-posed point is a [`Row`] with its error, never the end of the sweep.
//! - [`TableWriter`], [`read_table`], [`merge`], [`write_table`]: the table (CSV or JSON Lines:
//!   `point`, one column per axis, then [`RESULT_COLUMNS`]), appended and flushed row by row;
//!   resumed; shards joined with every point checked present exactly once.
//! - [`figures`]: the value against one axis (a line per value of a second), and the heat map
//!   over two axes with the boundary of the no-locomotion region.

mod axis;
mod plot;
mod run;
mod settings;
mod spec;
mod table;

pub use axis::{Axis, Kind, MAX_POINTS};
pub use plot::figures;
pub use run::{
    run, run_point, Outcome, Row, Shard, SweepProgress, SweepSettings, SweepSummary, MAX_THREADS,
};
pub use spec::{Combine, Job, Point, SweepSpec};
pub use table::{
    axes_of_header, check_rows, header, line, merge, read_any_table, read_table, write_full,
    write_table, Format, MergeProblems, TableWriter, RESULT_COLUMNS,
};
