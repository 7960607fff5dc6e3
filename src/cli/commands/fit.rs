//! `crawlopt fit`: [`crawlopt::api::fit`] on a measured trajectory, rendered; the fitted
//! crawler written as a model file, the figures drawn.

use crate::output::{out, write_json};
use clap::Args;
use crawlopt::api::{self, Hooks};
use crawlopt::fit::{FitSettings, Param};
use crawlopt::io::{crawler_toml, read_fit_csv, write_text, AtomicFile};
use crawlopt::present::{self, text, write_figures};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct FitArgs {
    /// Measured trajectory (CSV) with the header t,L_1,...,L_n,X_1,...,X_N.
    pub data: PathBuf,
    /// Number of blocks N of the crawler.
    #[arg(long)]
    pub blocks: usize,
    /// A known parameter, NAME[i]=VALUE with NAME one of stiffness, mu_forward, mu_backward
    /// (i from 1); sets the force scale. Repeatable. Without one, every force parameter is a
    /// ratio to stiffness[1].
    #[arg(long, value_name = "NAME[i]=VALUE")]
    pub fix: Vec<String>,
    /// Standard deviation of the noise on the positions (default: estimated from the data).
    #[arg(long, value_name = "SIGMA", allow_hyphen_values = true)]
    pub noise: Option<f64>,
    /// The intervals assume every position error is at most this many sigma.
    #[arg(long = "noise-bound", default_value_t = FitSettings::NOISE_BOUND, allow_hyphen_values = true)]
    pub noise_bound: f64,
    /// Write the fitted crawler as a model file (TOML, its [crawler] section).
    #[arg(long, short = 'o', value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Write figures (SVG and PNG) into this directory: measured against fitted trajectories,
    /// and per block the force against the velocity with the fitted thresholds.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

/// `NAME[i]=VALUE` of `--fix`.
fn parse_fix(s: &str) -> Result<(Param, f64), Error> {
    let (name, value) = s
        .split_once('=')
        .ok_or_else(|| Error::invalid("--fix", s, "expected NAME[i]=VALUE, e.g. stiffness[1]=1"))?;
    let p: Param = name.parse().map_err(|_| {
        Error::invalid(
            "--fix",
            s,
            "expected NAME[i]=VALUE with NAME one of stiffness, mu_forward, mu_backward",
        )
    })?;
    let v: f64 = value
        .trim()
        .parse()
        .map_err(|_| Error::invalid(format!("--fix {p}"), value, "not a number"))?;
    Ok((p, v))
}

pub fn run(a: FitArgs) -> Result<ExitCode, Error> {
    let settings = FitSettings {
        fixes: a
            .fix
            .iter()
            .map(|s| parse_fix(s))
            .collect::<Result<_, _>>()?,
        noise: a.noise,
        noise_bound: a.noise_bound,
        ..FitSettings::default()
    };
    settings.check(a.blocks.max(2)).map_err(|e| {
        api::rename_fields(
            e,
            &[
                ("noise", "--noise".into()),
                ("noise_bound", "--noise-bound".into()),
            ],
        )
    })?;
    if let Some(path) = &a.output {
        AtomicFile::check(path)?;
    }
    if let Some(dir) = &a.plot {
        present::check_figure_dir(dir)?;
    }
    let data = read_fit_csv(&a.data, a.blocks)
        .map_err(|e| api::rename_fields(e, &[("blocks", "--blocks".into())]))?;
    let r = api::fit(&data, &settings, Hooks::default())?;
    let figs = match &a.plot {
        Some(_) => Some(present::figures::fit::fit_figures(&data, &r)?),
        None => None,
    };
    let written = match (&a.output, &r.fitted) {
        (Some(path), Some(c)) => {
            let mut notes = vec![format!(
                "Fitted by crawlopt fit from {} ({} samples).",
                crate::output::file_name(&a.data),
                data.samples()
            )];
            if let Some(p) = &r.scale.ratios_to {
                notes.push(format!(
                    "Forces are ratios to {p}: no force scale was given."
                ));
            }
            notes.extend(r.warnings.iter().cloned());
            write_text(path, &crawler_toml(c, &notes)?)?;
            Some(path.as_path())
        }
        (Some(path), None) => {
            return Err(Error::invalid(
                "-o",
                path.display(),
                format!("no fitted crawler to write: {}", r.warnings.join("; ")),
            ))
        }
        _ => None,
    };
    if let (Some(dir), Some(figs)) = (&a.plot, &figs) {
        write_figures(dir, figs)?;
    }
    if a.json {
        write_json(&r);
    } else {
        out(&text::fit(&r, written));
    }
    Ok(ExitCode::SUCCESS)
}
