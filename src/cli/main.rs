//! `crawlopt`: the command-line layer over the library. Each command translates its arguments
//! into the library's settings, calls the library once ([`crawlopt::api`] and the modules it
//! names) and renders the result; errors are printed as one line and exit with status 2.

mod commands;
mod output;
mod parse;
mod progress;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Simulation and optimal gaits of rate-independent soft crawlers.
#[derive(Parser)]
#[command(name = "crawlopt", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Analyse a problem file: a crawler's polytope C, uniqueness condition, v_m and directions;
    /// a general problem's C, U and the conditions (P) asks of them.
    Analyze(commands::analyze::AnalyzeArgs),
    /// Simulate a problem file's control until the periodic regime: a crawler's [actuation], a
    /// general problem's [input].
    Simulate(commands::simulate::SimulateArgs),
    /// Compute an optimal gait: of a crawler's [gait] problem, or of a general problem (P).
    Optimize(commands::optimize::OptimizeArgs),
    /// Check the necessary optimality conditions (Theorem 2.2, Theorems 6.1-6.2) on a gait
    /// result: multipliers, residuals and a verdict.
    Certify(commands::certify::CertifyArgs),
    /// Draw the figures of a result file (`optimize --json`, a crawler's or a general
    /// problem's), a J_m table or a sweep's table.
    Plot(commands::plot::PlotArgs),
    /// One self-contained HTML report of a problem file or a result: parameters, analysis,
    /// optimal gait, figures (and a crawler's animation).
    Report(commands::report::ReportArgs),
    /// Measure the simulation cost per time step (sine gait L_l = A sin(2 pi t - l phi)).
    Bench(commands::bench::BenchArgs),
    /// Run a job over a grid of model parameters (a sweep file), in parallel, one row per
    /// point; `sweep merge` joins the tables of shards.
    Sweep(commands::sweep::SweepArgs),
    /// Identify a crawler's stiffnesses and friction thresholds from a measured trajectory:
    /// estimates, the exact interval of each at the noise level, the fitted model file.
    Fit(commands::fit::FitArgs),
}

/// Exit status after Ctrl-C or SIGTERM (128 + SIGINT, the shell's convention for an
/// interrupted command).
const EXIT_INTERRUPTED: i32 = 130;

/// On Ctrl-C or SIGTERM (handled on a thread of its own, not inside the signal handler): the
/// temporary files of outputs not yet complete are removed
/// ([`crawlopt::io::remove_staged_files`]), then the process ends with [`EXIT_INTERRUPTED`].
/// A sweep's table keeps its finished rows (each is written whole and flushed), as after
/// kill -9, and `--resume` continues it.
fn on_interrupt() {
    let _ = ctrlc::set_handler(|| {
        crawlopt::io::remove_staged_files();
        std::process::exit(EXIT_INTERRUPTED);
    });
}

fn main() -> ExitCode {
    on_interrupt();
    let result = match Cli::parse().command {
        Command::Analyze(a) => commands::analyze::run(a),
        Command::Simulate(a) => commands::simulate::run(a),
        Command::Optimize(a) => commands::optimize::run(a),
        Command::Certify(a) => commands::certify::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::Report(a) => commands::report::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Sweep(a) => commands::sweep::run(a),
        Command::Fit(a) => commands::fit::run(a),
    };
    result.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        ExitCode::from(2)
    })
}
