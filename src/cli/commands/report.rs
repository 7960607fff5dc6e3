//! `crawlopt report`: the HTML report of a result file, or of the optimal gait of a model file.

use crate::output::{file_name, outln, read_text};
use crate::parse::count;
use clap::Args;
use crawlopt::api::{self, Hooks, Naming};
use crawlopt::io::{AtomicFile, ProblemFile};
use crawlopt::present::{self, report};
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
    /// Slip phases allowed when computing the gait from a crawler's model file (default: K
    /// grown until the value stops improving, as `optimize`).
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
    let settings = api::ReportSettings {
        phases: a.phases,
        time_limit: a.time_limit,
        naming: Naming::Flags,
    };
    let summary = if a.file.extension().is_some_and(|e| e == "json") {
        let (r, html) = api::report_result(&read_text(&a.file)?, &name, &settings)?;
        report::write_report(&a.output, &html)?;
        present::result_summary(&r)
    } else {
        let file = ProblemFile::load(&a.file)?;
        let answer = api::report_file(&file, &settings, Hooks::default())?;
        let command = format!("crawlopt report {name}");
        report::write_report(&a.output, &answer.report_html(&name, &command)?)?;
        answer.summary()
    };
    outln(&format!("wrote {} ({summary})", a.output.display()));
    Ok(ExitCode::SUCCESS)
}
