//! `crawlopt certify`: the necessary conditions of a result file of either kind, rendered.

use crate::output::{json_line, out, read_text};
use clap::Args;
use crawlopt::api::certify_result_file;
use crawlopt::io::ResultFile;
use crawlopt::present::write_figures;
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct CertifyArgs {
    /// A result printed by `optimize --json` (a crawler's or a general problem's).
    pub file: PathBuf,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write the result's figures and the adjoint p(t) (a crawler's with p + omega and u(t))
    /// (SVG and PNG) into this directory.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

pub fn run(a: CertifyArgs) -> Result<ExitCode, Error> {
    let what = a.file.display().to_string();
    let file = ResultFile::from_json(&read_text(&a.file)?, &what)?;
    let cert = certify_result_file(file, &what)?;
    if let Some(dir) = &a.plot {
        write_figures(dir, &cert.figures()?)?;
    }
    if a.json {
        json_line(&cert)
    } else {
        out(&cert.text())
    }
    Ok(ExitCode::SUCCESS)
}
