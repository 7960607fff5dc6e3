//! `crawlopt certify`: the necessary conditions of a result file, rendered.

use crate::output::{json_line, out, read_text};
use clap::Args;
use crawlopt::certify::certify_result;
use crawlopt::optimal::GaitResult;
use crawlopt::present::{self, text, write_figures};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct CertifyArgs {
    /// A result printed by `optimize --json`.
    pub file: PathBuf,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write the gait's figures and the adjoint p(t), p + omega, u(t) (SVG and PNG) into
    /// this directory.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

pub fn run(a: CertifyArgs) -> Result<ExitCode, Error> {
    let what = a.file.display().to_string();
    let result = GaitResult::from_json(&read_text(&a.file)?, &what)?;
    let cert = certify_result(&result, &what)?;
    if let Some(dir) = &a.plot {
        let mut figs = present::gait_figures(&result)?;
        figs.push(present::adjoint_figure_of(&cert.multipliers)?);
        write_figures(dir, &figs)?;
    }
    if a.json {
        json_line(&cert);
    } else {
        out(&text::certificate(&cert, &result));
    }
    Ok(ExitCode::SUCCESS)
}
