//! `crawlopt analyze`: [`crawlopt::api::analyze_file`] rendered, for either kind of problem
//! file.

use crate::output::{out, write_json};
use clap::Args;
use crawlopt::api;
use crawlopt::io::ProblemFile;
use crawlopt::present::{self, write_figures};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct AnalyzeArgs {
    /// Problem file (TOML): a crawler's model file or a general problem (`[sweeping_process]`).
    pub file: PathBuf,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write figures (SVG and PNG) into this directory: C, and v_m for two links (a general
    /// problem file: C, projected onto pairs of state components beyond two).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

pub fn run(a: AnalyzeArgs) -> Result<ExitCode, Error> {
    let file = ProblemFile::load(&a.file)?;
    // The output directory is checked before the work.
    if let Some(dir) = &a.plot {
        present::check_figure_dir(dir)?;
    }
    let found = api::analyze_file(&file)?;
    if let Some(dir) = &a.plot {
        write_figures(dir, &found.figures()?)?;
    }
    if a.json {
        // Streamed: a document of 10^7 blocks is gigabytes as a serde_json::Value tree.
        write_json(&found);
    } else {
        out(&found.text());
    }
    // The figures and the analysis are written first, then the verdict: exit 2 when the
    // crawler fails the uniqueness condition or the general problem a check.
    if let Err(e) = found.verdict() {
        eprintln!("error: {e}");
        return Ok(ExitCode::from(2));
    }
    Ok(ExitCode::SUCCESS)
}
