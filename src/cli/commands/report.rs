//! `crawlopt report`: the HTML report of a result file, or of the optimal gait of a model file.

use crate::output::{file_name, outln, read_text};
use crate::parse::count;
use clap::Args;
use crawlopt::api::Hooks;
use crawlopt::io::{AtomicFile, ModelFile};
use crawlopt::optimal::GaitResult;
use crawlopt::present::report;
use crawlopt::present::text::{num, GaitScales};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct ReportArgs {
    /// A model file (TOML) with a [gait] section (the optimal gait is computed by the phase
    /// method), or a gait result (.json, from `optimize --json`).
    pub file: PathBuf,
    /// The HTML file to write.
    #[arg(long, short = 'o', value_name = "FILE", default_value = "report.html")]
    pub output: PathBuf,
    /// Slip phases allowed when computing the gait from a model file (default: K grown until
    /// the value stops improving, as `optimize`).
    #[arg(long, allow_negative_numbers = true, value_parser = count)]
    pub phases: Option<usize>,
    /// Time limit in seconds when computing the gait from a model file.
    #[arg(long = "time-limit", value_name = "S", allow_hyphen_values = true)]
    pub time_limit: Option<f64>,
}

pub fn run(a: ReportArgs) -> Result<ExitCode, Error> {
    // A directory (the default report.html may be one) is refused before the work.
    AtomicFile::check(&a.output)?;
    let name = file_name(&a.file);
    let result = if a.file.extension().is_some_and(|e| e == "json") {
        GaitResult::from_json(&read_text(&a.file)?, &name)?
    } else {
        let model = ModelFile::load(&a.file)?;
        crawlopt::api::optimize_model(&model, a.phases, a.time_limit, Hooks::default())?
    };
    report::write_report(&a.output, &report::build_report(&result, &name)?)?;
    let length = GaitScales::of(&result).length;
    outln(&format!(
        "wrote {} (objective J = {}, displacement per period {})",
        a.output.display(),
        num(result.objective, length),
        num(result.displacement_per_period, length)
    ));
    Ok(ExitCode::SUCCESS)
}
