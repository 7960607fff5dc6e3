//! `crawlopt plot`: the figures of a result file.

use crate::output::{file_name, outln, read_text};
use clap::Args;
use crawlopt::present::{write_figures, PlotInput};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct PlotArgs {
    /// RESULT.json.
    pub file: PathBuf,
    /// Directory for the SVG and PNG files (created if absent).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub output: PathBuf,
}

pub fn run(a: PlotArgs) -> Result<ExitCode, Error> {
    let input = PlotInput::from_json(&read_text(&a.file)?, &file_name(&a.file))?;
    for p in write_figures(&a.output, &input.figures()?)? {
        outln(&format!("wrote {}", p.display()));
    }
    Ok(ExitCode::SUCCESS)
}
