//! The library's entry points: one call per job, each taking a settings struct with documented
//! defaults and returning one result type. The command line (`src/cli/`) and the Python package
//! (`python/`) only translate arguments into these and render what they return; every decision
//! (defaults, which options apply, start policies, growth of K, re-verification) lives here or
//! below.
//!
//! - [`analyze_file`], [`simulate_file`], [`optimize_file`] (or [`OptimizeJob`], checked before
//!   its work) and [`report_file`]: each job on a problem file of either kind, one answer type
//!   each (text, figures, trajectory file or report, verdict or summary), so that no front end
//!   forks on the kind of file;
//! - [`analyze`]: a model file's crawler analysed, its gait problem and, for one link, the
//!   closed-form optimum (paper §4);
//! - [`simulate`] with [`SimOptions`]: the periodic regime of an actuation (cancellable);
//! - [`optimize`] with [`OptimizeSettings`]: an optimal gait, verified, optionally certified;
//! - [`certify_result_file`]: the necessary conditions (Theorem 2.2) of a result file of either
//!   kind ([`crate::io::ResultFile`]);
//! - [`crate::present`]: figures and the report ([`report_file`]: the optimum a report of a
//!   problem file shows; [`report_result`]: the report of a result file, the settings that
//!   compute a gait refused);
//! - [`bench`](fn@bench): the simulation cost per step;
//! - [`fit`] with [`crate::fit::FitSettings`]: a crawler identified from a measured trajectory,
//!   with the exact interval of every parameter (see [`crate::fit`]);
//! - [`general`]: the general problem (P) of the paper's §2 (`[sweeping_process]` files):
//!   [`analyze_general`], [`simulate_general`], [`optimize_general_plan`] (the plan of
//!   [`OptimizeSettings`] for it, run; [`optimize_file`] plans and runs),
//!   [`optimize_general`] (P_m, globally), [`optimize_general_local`] (P_m, locally), [`optimize_general_phase`] (exact gaits of at
//!   most `K` phases where `A = 0`, globally, `K` fixed or grown as for crawlers),
//!   [`optimize_general_on_chain`] (the crawler's sequence and chain methods where the
//!   problem is a crawler's).
//!
//! A parameter study (a job over a grid of model parameters) is one layer above, in
//! [`crate::study`]: it runs these jobs per point.
//!
//! Progress arrives as [`Event`]s through [`Hooks`], which also carry a
//! [`crate::progress::Cancel`] token that stops a job within a HiGHS callback.
//!
//! ```no_run
//! use crawlopt::api::{optimize, GaitMethod, Hooks, OptimizeSettings};
//! use crawlopt::io::ModelFile;
//!
//! let model = ModelFile::load("examples/three_blocks_gait.toml".as_ref())?;
//! let (crawler, problem) = crawlopt::api::gait_problem(&model)?;
//! let settings = OptimizeSettings { method: GaitMethod::Phase, phases: Some(3), ..Default::default() };
//! let best = optimize(&crawler, &problem, &settings, Hooks::default())?;
//! println!("J = {}", best.result.head.objective);
//! # Ok::<(), crawlopt::Error>(())
//! ```

mod bench;
mod certify_file;
mod events;
mod fit;
pub mod general;
mod general_chain;
mod general_local;
mod general_phase;
mod general_plan;
mod general_pm;
mod general_start;
mod keys;
mod optimize;
mod optimize_file;
mod problem_file;
mod settings;

pub use crate::io::{GeneralSolution, LocalStarts};
pub use bench::{bench, BenchCase, BenchSettings};
pub use certify_file::{certify_result_file, Certified};
pub use events::{Event, Hooks, Observer};
pub use fit::fit;
pub use general::{
    analyze_general, general_problem, general_sim_options, simulate_general, GeneralAnalysis,
    GeneralSimulated,
};
pub use general_chain::{optimize_general_on_chain, GeneralChainSettings};
pub use general_local::{optimize_general_local, GeneralLocalSettings};
pub use general_phase::{optimize_general_phase, GeneralPhaseSettings, DEFAULT_GENERAL_PHASES};
pub use general_plan::{optimize_general_plan, GeneralAnswer, GeneralPlan};
pub use general_pm::{optimize_general, GeneralPmSettings};
pub use optimize::{optimize, Optimized};
pub use optimize_file::{
    optimize_file, report_file, report_result, OptimizeJob, OptimizedFile, ReportSettings,
};
pub use problem_file::{analyze_file, simulate_file, Analyzed, Simulated};
pub use settings::{
    rename_fields, GaitMethod, Naming, OptimizeSettings, PhaseFormulation, Plan, Start,
    DEFAULT_MAX_PHASES, DEFAULT_M_DISCRETE, DEFAULT_M_LOCAL, DEFAULT_PATIENCE, DEFAULT_SHIFTS,
};

use crate::error::{Error, Result};
use crate::integrate::{Actuation, SimOptions, Simulation};
use crate::io::ModelFile;
use crate::model::{Analysis, Crawler};
use crate::optimal::{one_link_optimum, GaitProblem, OneLinkOptimum};
use serde::Serialize;

/// The crawler of a model file, checked for uniqueness (paper eq. 3.6), and its `[gait]`
/// problem (an error naming `gait` when the file has none).
pub fn gait_problem(model: &ModelFile) -> Result<(Crawler, GaitProblem)> {
    let crawler = model.crawler()?;
    crawler.require_unique()?;
    let problem = model
        .gait(&crawler)?
        .ok_or_else(|| Error::invalid("gait", "nothing", "the model file has no [gait] section"))?;
    Ok((crawler, problem))
}

/// What [`analyze`] finds in a model file.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelAnalysis {
    /// The crawler.
    #[serde(skip)]
    pub crawler: Crawler,
    /// Its analysis: C, uniqueness, v_m and its directions.
    #[serde(flatten)]
    pub analysis: Analysis,
    /// The `[gait]` problem, with the one-link closed form where it applies.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gait: Option<GaitAnalysis>,
}

/// A model file's gait problem, as `analyze` reports it (`analyze --json`'s `gait`: each part
/// with its keys in alphabetical order, as the command has always written them).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GaitAnalysis {
    /// For one link with a unique motion, J* and an optimal gait in closed form (theory §9,
    /// paper §4); `None` otherwise.
    #[serde(serialize_with = "sorted_keys")]
    pub one_link_optimum: Option<OneLinkOptimum>,
    /// The problem.
    #[serde(serialize_with = "sorted_keys")]
    pub problem: GaitProblem,
}

/// Serialises `v` with the keys of its objects in alphabetical order (through a
/// `serde_json::Value`).
fn sorted_keys<T: Serialize, S: serde::Serializer>(
    v: &T,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::Error as _;
    serde_json::to_value(v)
        .map_err(S::Error::custom)?
        .serialize(s)
}

/// The analysis of a model file's crawler (the polytope C, the uniqueness condition, v_m and
/// its directions) and, when the file poses a gait problem, that problem with the one-link
/// closed form (theory §9). A crawler that violates the uniqueness condition is analysed (the
/// analysis says so in `uniqueness_ok`), not refused.
pub fn analyze(model: &ModelFile) -> Result<ModelAnalysis> {
    let crawler = model.crawler()?;
    let analysis = crawler.analyze();
    let gait = match model.gait(&crawler)? {
        Some(problem) => {
            let one_link_optimum = if analysis.uniqueness_ok && crawler.blocks() == 2 {
                Some(one_link_optimum(&crawler, &problem)?)
            } else {
                None
            };
            Some(GaitAnalysis {
                problem,
                one_link_optimum,
            })
        }
        None => None,
    };
    Ok(ModelAnalysis {
        crawler,
        analysis,
        gait,
    })
}

/// [`crate::integrate::simulate`] under `hooks`: the periodic regime of `act` for `crawler`
/// (theory §3–4), stopped by the hooks' token between periods. `options` are checked by the
/// simulator (errors name the field, e.g. `steps_per_period`).
pub fn simulate(
    crawler: &Crawler,
    act: &Actuation,
    options: &SimOptions,
    hooks: Hooks<'_>,
) -> Result<Simulation> {
    crawler.require_unique()?;
    events::run_with(hooks, |em| {
        crate::progress::check()?;
        em.stage("simulating to the periodic regime");
        crate::integrate::simulate(crawler, act, options)
    })
}
