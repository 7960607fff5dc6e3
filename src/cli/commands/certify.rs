//! `crawlopt certify`: the necessary conditions of a result file of either kind, rendered.

use crate::output::{json_line, out, read_text};
use clap::Args;
use crawlopt::api::{certify_result_file, Certified};
use crawlopt::io::ResultFile;
use crawlopt::optimal::ResultKind;
use crawlopt::present::{self, text, write_figures};
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
    /// Write the gait's figures and the adjoint p(t), p + omega, u(t) (SVG and PNG) into
    /// this directory (crawler results).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

pub fn run(a: CertifyArgs) -> Result<ExitCode, Error> {
    let what = a.file.display().to_string();
    let file = ResultFile::from_json(&read_text(&a.file)?, &what)?;
    if a.plot.is_some() && file.kind() == ResultKind::General {
        return Err(Error::invalid(
            "--plot",
            "given",
            "applies to crawler results: a general problem's figures are not drawn by certify",
        ));
    }
    match (&file, certify_result_file(&file, &what)?) {
        (ResultFile::Crawler(result), Certified::Crawler(cert)) => {
            if let Some(dir) = &a.plot {
                let mut figs = present::gait_figures(result)?;
                figs.push(present::adjoint_figure_of(&cert.multipliers)?);
                write_figures(dir, &figs)?;
            }
            if a.json {
                json_line(&cert);
            } else {
                out(&text::certificate(&cert, result));
            }
        }
        (_, Certified::General(c)) if !a.json => out(&text::general_certificate(&c)),
        (_, cert) => json_line(&cert),
    }
    Ok(ExitCode::SUCCESS)
}
