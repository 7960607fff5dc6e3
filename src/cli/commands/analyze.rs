//! `crawlopt analyze`: [`crawlopt::api::analyze`] rendered.

use crate::output::{out, write_json};
use clap::Args;
use crawlopt::api;
use crawlopt::io::{GeneralFile, ProblemFile};
use crawlopt::present::{self, text, write_figures};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct AnalyzeArgs {
    /// Model file (TOML).
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
    let model = match ProblemFile::load(&a.file)? {
        ProblemFile::General(general) => return run_general(&general, &a),
        ProblemFile::Crawler(model) => model,
    };
    let found = api::analyze(&model)?;
    if let Some(dir) = &a.plot {
        write_figures(dir, &present::analysis_figures(&found.crawler)?)?;
    }
    if a.json {
        // Streamed: a document of 10^7 blocks is gigabytes as a serde_json::Value tree.
        write_json(&found);
    } else {
        out(&text::analysis(&found.crawler, &found.analysis));
        if let Some(g) = &found.gait {
            let optimum = g.one_link_optimum.as_ref();
            out(&text::gait_problem(&found.crawler, &g.problem, optimum));
        }
    }
    if let Err(e) = found.crawler.require_unique() {
        eprintln!("error: {e}");
        return Ok(ExitCode::from(2));
    }
    Ok(ExitCode::SUCCESS)
}

/// `crawlopt analyze` of a general problem: the figure of C written, the analysis printed, then
/// exit 2 with the first failed check's message if any.
fn run_general(file: &GeneralFile, a: &AnalyzeArgs) -> Result<ExitCode, Error> {
    if let Some(dir) = &a.plot {
        present::check_figure_dir(dir)?;
    }
    let found = api::analyze_general(file)?;
    if let Some(dir) = &a.plot {
        write_figures(dir, &present::general_analysis_figures(&found)?)?;
    }
    if a.json {
        write_json(&found);
    } else {
        out(&text::general_analysis(&found));
    }
    match found.failure {
        Some(e) => {
            eprintln!("error: {e}");
            Ok(ExitCode::from(2))
        }
        None => Ok(ExitCode::SUCCESS),
    }
}
