//! `crawlopt simulate`: [`crawlopt::api::simulate`] with the flags as its options, rendered;
//! the trajectory as CSV and the figures written only once the periodic regime is reached.

use crate::output::{json_line, out};
use crate::parse::{count, sim_method};
use clap::Args;
use crawlopt::api::{self, rename_fields, Hooks};
use crawlopt::integrate::{Method, SimOptions};
use crawlopt::io::{AtomicFile, ProblemFile};
use crawlopt::present::{self, write_figures};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

/// The library's defaults, shown and used as the flags' defaults.
const DEFAULTS: SimOptions = SimOptions::DEFAULT;

/// `--accelerate-after` unless given: the library's.
const DEFAULT_ACCELERATE_AFTER: usize = match SimOptions::DEFAULT.accelerate_after {
    Some(k) => k,
    None => 0,
};

/// Exit status of a simulation whose periodic regime was not reached.
const EXIT_NOT_CONVERGED: u8 = 3;

#[derive(Args)]
pub struct SimulateArgs {
    /// Problem file (TOML): a crawler's model file with an [actuation] section, or a general
    /// problem with an [input] section.
    pub file: PathBuf,
    /// Periods recorded on the periodic orbit (trajectory output); 0 records none (refused
    /// with -o, which would get nothing).
    #[arg(long, default_value_t = DEFAULTS.record_periods, allow_negative_numbers = true, value_parser = count)]
    pub periods: usize,
    /// Steps per period (catching-up), or knots of the interpolant of a sine/triangle (exact).
    #[arg(
        long = "steps-per-period",
        default_value_t = DEFAULTS.steps_per_period,
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub steps_per_period: usize,
    /// Integration method.
    #[arg(long, default_value = "exact", value_parser = sim_method())]
    pub method: Method,
    /// Give up the search for the periodic regime after this many periods.
    #[arg(
        long = "max-periods",
        default_value_t = DEFAULTS.max_periods,
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub max_periods: usize,
    /// The state repeats when it changes by at most tol * (size of C) over a period.
    #[arg(long, default_value_t = DEFAULTS.tol, allow_hyphen_values = true)]
    pub tol: f64,
    /// Iterate periods plainly this many times (fewer when plain iteration is predicted not to
    /// converge in time), then accelerate the search (Newton-Krylov, safeguarded by Anderson).
    #[arg(
        long = "accelerate-after",
        default_value_t = DEFAULT_ACCELERATE_AFTER,
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub accelerate_after: usize,
    /// Never accelerate: the search is the physical transient.
    #[arg(long = "no-accelerate")]
    pub no_accelerate: bool,
    /// Accelerate with Anderson alone, without Newton-Krylov steps (the search before them).
    #[arg(long = "no-newton")]
    pub no_newton: bool,
    /// Catching-up keeps the period's increments as a table (8 bytes per link and step) up to
    /// this many bytes, and forms them step by step beyond (memory O(N), the same result).
    #[arg(
        long = "increment-budget",
        value_name = "BYTES",
        default_value_t = DEFAULTS.increment_budget,
        allow_negative_numbers = true,
        value_parser = count
    )]
    pub increment_budget: usize,
    /// Write the recorded trajectory as CSV.
    #[arg(long, short = 'o')]
    pub output: Option<PathBuf>,
    /// Print one JSON object (with the recorded trajectory).
    #[arg(long)]
    pub json: bool,
    /// Write figures (SVG and PNG) into this directory: actuation, space-time diagram over
    /// max(periods, 3) periods, the orbit in C; for a general problem file C with the orbit,
    /// the states, controls, reactions and the objective's integrand.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

/// A library error renamed after the flag that set the value (both kinds of problem file).
fn flags(e: Error, a: &SimulateArgs) -> Error {
    let names = [
        ("steps_per_period", "--steps-per-period"),
        ("periods", "--periods"),
        ("max_periods", "--max-periods"),
        ("tol", "--tol"),
        ("increment_budget", "--increment-budget"),
        ("newton", "--no-newton"),
        (
            "accelerate_after",
            if a.no_accelerate {
                "--no-accelerate"
            } else {
                "--accelerate-after"
            },
        ),
    ];
    rename_fields(e, &names.map(|(f, flag)| (f, flag.to_string())))
}

/// `crawlopt simulate` of either kind of problem file ([`api::simulate_file`]): a crawler's
/// actuation, or a general problem's `[input]` (exactly where `A = 0` and the input is
/// piecewise constant unless `--method catching-up`, the library deciding which flags apply).
pub fn run(a: SimulateArgs) -> Result<ExitCode, Error> {
    let file = ProblemFile::load(&a.file)?;
    // Output paths are checked before the work: a directory for -o, a file for --plot.
    if let Some(path) = &a.output {
        if a.periods == 0 {
            return Err(Error::invalid(
                "--periods",
                0,
                format!(
                    "records no trajectory, so -o {} would get nothing: record at least one \
                     period, or leave out -o",
                    path.display()
                ),
            ));
        }
        AtomicFile::check(path)?;
    }
    if let Some(dir) = &a.plot {
        present::check_figure_dir(dir)?;
    }
    let sim =
        api::simulate_file(&file, &sim_options(&a), Hooks::default()).map_err(|e| flags(e, &a))?;
    // Without a periodic regime nothing is written (exit 3 below says so). The figures are
    // computed before anything is written, so that their failure leaves no CSV.
    let figs = match (&a.plot, sim.converged()) {
        (Some(_), true) => Some(sim.figures(a.periods).map_err(|e| flags(e, &a))?),
        _ => None,
    };
    let written = match &a.output {
        Some(path) if sim.write_csv(path)? => Some(path.as_path()),
        _ => None,
    };
    if let (Some(dir), Some(figs)) = (&a.plot, &figs) {
        write_figures(dir, figs)?;
    }
    if a.json {
        json_line(&sim);
    } else {
        out(&sim.text(written));
    }
    match sim.not_converged() {
        None => Ok(ExitCode::SUCCESS),
        Some(what) => {
            eprintln!(
                "error: {what}{} (raise --max-periods or --tol)",
                unwritten(&a)
            );
            Ok(ExitCode::from(EXIT_NOT_CONVERGED))
        }
    }
}

/// What a simulation that did not reach its periodic regime left unwritten, for its error line
/// (`, no trajectory written to F, no figures written to D`; empty when nothing was asked).
fn unwritten(a: &SimulateArgs) -> String {
    let trajectory = a
        .output
        .as_ref()
        .map(|p| format!(", no trajectory written to {}", p.display()));
    let figures = a
        .plot
        .as_ref()
        .map(|d| format!(", no figures written to {}", d.display()));
    trajectory.into_iter().chain(figures).collect()
}

/// The library's options of the flags (both kinds of problem file take the same ones; a
/// crawler's initial state comes from its file, [`api::simulate_file`]).
fn sim_options(a: &SimulateArgs) -> SimOptions {
    SimOptions {
        method: a.method,
        steps_per_period: a.steps_per_period,
        record_periods: a.periods,
        max_periods: a.max_periods,
        tol: a.tol,
        accelerate_after: (!a.no_accelerate).then_some(a.accelerate_after),
        newton: SimOptions::DEFAULT.newton.filter(|_| !a.no_newton),
        initial_state: None,
        increment_budget: a.increment_budget,
    }
}
