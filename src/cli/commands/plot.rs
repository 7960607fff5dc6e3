//! `crawlopt plot`: the figures of a result file.

use crate::output::{file_name, outln, read_text};
use clap::Args;
use crawlopt::present::{write_figures, PlotInput};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct PlotArgs {
    /// RESULT.json (either kind), a J_m table (.json), or a sweep's table (TABLE.csv or
    /// .jsonl).
    pub file: PathBuf,
    /// Directory for the SVG and PNG files (created if absent).
    #[arg(long, short = 'o', value_name = "DIR")]
    pub output: PathBuf,
}

pub fn run(a: PlotArgs) -> Result<ExitCode, Error> {
    // A sweep's table (`crawlopt sweep -o`): its figures.
    let ext = a.file.extension().and_then(|e| e.to_str());
    if matches!(ext, Some("csv" | "jsonl" | "ndjson")) {
        let (axes, rows) = crawlopt::study::read_any_table(&a.file)?;
        for p in write_figures(&a.output, &crawlopt::study::figures(&axes, &rows)?)? {
            outln(&format!("wrote {}", p.display()));
        }
        return Ok(ExitCode::SUCCESS);
    }
    let input = PlotInput::from_json(&read_text(&a.file)?, &file_name(&a.file))?;
    for p in write_figures(&a.output, &input.figures()?)? {
        outln(&format!("wrote {}", p.display()));
    }
    Ok(ExitCode::SUCCESS)
}
