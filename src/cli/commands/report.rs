//! `crawlopt report`: the HTML report of a result file, or of the optimal gait of a model file.

use crate::output::{file_name, outln, read_text};
use crate::parse::count;
use clap::Args;
use crawlopt::api::{Hooks, Naming, OptimizedFile};
use crawlopt::io::{AtomicFile, ProblemFile, ResultFile};
use crawlopt::optimal::GaitResult;
use crawlopt::present::build_result_report;
use crawlopt::present::report;
use crawlopt::present::text::{num, GaitScales};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct ReportArgs {
    /// A model file (TOML) with a [gait] section (the optimal gait is computed by the phase
    /// method), a general problem file (its optimum is computed as `optimize` computes it), or
    /// a gait result (.json, from `optimize --json`).
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
    if a.file.extension().is_some_and(|e| e == "json") {
        // A result of either kind, read back and checked as `certify` reads it.
        let r = ResultFile::from_json(&read_text(&a.file)?, &name)?;
        report::write_report(&a.output, &build_result_report(&r, &name)?)?;
        return Ok(match r {
            ResultFile::Crawler(result) => wrote_gait(&a, &result),
            ResultFile::General(_) => wrote_general(&a, r.objective()),
        });
    }
    let file = ProblemFile::load(&a.file)?;
    let answer = crawlopt::api::report_file(
        &file,
        a.phases,
        a.time_limit,
        Naming::Flags,
        Hooks::default(),
    )?;
    let command = format!("crawlopt report {name}");
    report::write_report(&a.output, &answer.report_html(&name, &command)?)?;
    Ok(match &answer {
        OptimizedFile::Crawler(o) => wrote_gait(&a, &o.result),
        OptimizedFile::General { .. } => wrote_general(&a, answer.objective()),
    })
}

/// The line saying a crawler's report was written, with its numbers in the gait's units.
fn wrote_gait(a: &ReportArgs, result: &GaitResult) -> ExitCode {
    let length = GaitScales::of(result).length;
    outln(&format!(
        "wrote {} (objective J = {}, displacement per period {})",
        a.output.display(),
        num(result.objective, length),
        num(result.displacement_per_period, length)
    ));
    ExitCode::SUCCESS
}

/// The line saying a general problem's report was written.
fn wrote_general(a: &ReportArgs, objective: f64) -> ExitCode {
    outln(&format!(
        "wrote {} (objective J = {})",
        a.output.display(),
        num(objective, objective.abs())
    ));
    ExitCode::SUCCESS
}
