//! `crawlopt optimize`: the flags as [`OptimizeSettings`], one job of the library for a problem
//! file of either kind ([`crawlopt::api::OptimizeJob`], which holds every policy: method,
//! defaults, starts, growth, time budget), rendered; figures and the report written from the
//! answer.

use crate::output::{file_name, json_line, out, outln};
use crate::parse::{count, count_u32, method};
use crate::progress::Spinner;
use clap::Args;
use crawlopt::api::{self, GaitMethod, Hooks, Naming, OptimizeSettings, Start};
use crawlopt::io::{AtomicFile, ProblemFile};
use crawlopt::present::{self, report, write_figures};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args)]
pub struct OptimizeArgs {
    /// Problem file (TOML): a crawler's model file with a [gait] section, or a general problem
    /// (`[sweeping_process]`).
    pub file: PathBuf,
    /// Formulation; auto: phase gaits with K grown until the value stops improving (the
    /// discrete P_m when the problem bounds TV(u), which phase gaits cannot express).
    #[arg(long, default_value = "auto", value_parser = method())]
    pub method: GaitMethod,
    /// Slip phases allowed in a phase gait (all-stick transitions between them are free; for
    /// a general problem file, slots of a free transition and a phase of constant control by
    /// default, phases with --formulation general, or slip phases where it is a crawler's);
    /// without it K grows from 1 until the value has not improved for --patience K
    /// (or --max-phases, or the time limit).
    #[arg(long, allow_negative_numbers = true, value_parser = count)]
    pub phases: Option<usize>,
    /// Consecutive K without a gain that end the growth of K (the library's default,
    /// `api::DEFAULT_PATIENCE`; --method phase, or auto without a TV bound, without --phases).
    #[arg(long, allow_negative_numbers = true, value_parser = count, help = format!(
        "Consecutive K without a gain that end the growth of K (default {}; --method phase, or \
         auto without a TV bound, without --phases: the start gaits of the other methods stop \
         at the first K without a gain)",
        api::DEFAULT_PATIENCE
    ))]
    pub patience: Option<usize>,
    /// Largest K tried when K grows (the library's default, `api::DEFAULT_MAX_PHASES`, and
    /// `api::DEFAULT_GENERAL_PHASES` in (P)'s own formulations; for --method
    /// phase or auto without --phases, and for the default start gaits, whose growth stops at
    /// --phases for the sequence method).
    #[arg(long = "max-phases", allow_negative_numbers = true, value_parser = count, help = format!(
        "Largest K tried when K grows (default {}; {} for a general problem file unless the \
         chain's formulation runs, which counts slip phases as a crawler does; for --method \
         phase or auto without --phases, and for the default start gaits, whose growth stops \
         at --phases for the sequence method)",
        api::DEFAULT_MAX_PHASES,
        api::DEFAULT_GENERAL_PHASES
    ))]
    pub max_phases: Option<usize>,
    /// The phase MILP's formulation on a general problem file: general (K phases), transitions
    /// (K slots of a free transition and a phase) or chain (a crawler's; K slip phases).
    /// Default: the chain's on a crawler's chain, transitions elsewhere.
    #[arg(long, value_name = "NAME")]
    pub formulation: Option<String>,
    /// The grid of P_m has 2^m steps (--method discrete, default 3; --method local, default
    /// 10).
    #[arg(long, allow_negative_numbers = true, value_parser = count_u32)]
    pub m: Option<u32>,
    /// Solve P_m for m = 1..=M (M = --m) and print the table of J_m (--method discrete).
    #[arg(long)]
    pub convergence: bool,
    /// Start gait: a result file of `optimize --json`. For --method local and sequence
    /// (default: the phase optimum with K grown to the first K without a gain, within half
    /// the time limit), and for --method discrete (default under --time-limit: the local
    /// method's gait on the same grid; see the README), whose MILP takes it, sampled on its
    /// grid, as the first incumbent. On a general problem file, for --method local, and for
    /// discrete or auto (default under --time-limit: the local method's answer on the same grid,
    /// without a cost f2): a general result of the same shape and period, its control averaged
    /// on the grid.
    #[arg(long)]
    pub start: Option<PathBuf>,
    /// Time shifts of the start tried by the local method (--method local, and the default
    /// start of --method discrete under --time-limit when it runs the local method): the
    /// start shifted by j T / N, j = 0..N, each sampled on the grid and searched from; the
    /// best answer is kept (default 8).
    #[arg(long, allow_negative_numbers = true, value_parser = count)]
    pub shifts: Option<usize>,
    /// Stop after this many seconds with the best gait found and its gap.
    #[arg(long = "time-limit", value_name = "S", allow_hyphen_values = true)]
    pub time_limit: Option<f64>,
    /// Also check the necessary conditions (as `certify`); with --json they are added to the
    /// result as "necessary_conditions".
    #[arg(long)]
    pub certify: bool,
    /// Keep a P_m answer of a quadratic cost as the MILP's outer approximation leaves it
    /// (--method discrete; by default it is polished on its fixed slip or face pattern, a QP
    /// solved to the solvers' resolution).
    #[arg(long = "no-polish")]
    pub no_polish: bool,
    #[command(flatten)]
    pub bound: super::bound_flags::BoundArgs,
    /// Write the gait's figures (SVG and PNG) into this directory (with --certify, the
    /// adjoint too; with --convergence, J_m against m); for a general problem file, the
    /// optimum's: C with the orbit, states, controls, reactions, the objective's integrand.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Also write the self-contained HTML report of the gait (as `crawlopt report`) to this
    /// file (of either kind of problem file).
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    pub json: bool,
}

/// The library's settings of the flags (both kinds of problem file take the same ones; the
/// library decides which apply).
fn settings_of(a: &OptimizeArgs) -> Result<OptimizeSettings, Error> {
    Ok(OptimizeSettings {
        method: a.method,
        phases: a.phases,
        patience: a.patience,
        max_phases: a.max_phases,
        m: a.m,
        convergence: a.convergence,
        start: a.start.clone().map(Start::File),
        shifts: a.shifts,
        time_limit: a.time_limit,
        certify: a.certify,
        polish: a.no_polish.then_some(false),
        formulation: a
            .formulation
            .as_deref()
            .map(api::PhaseFormulation::from_name)
            .transpose()
            .map_err(|e| Naming::Flags.name_settings(e))?,
        naming: Naming::Flags,
        bound: a.bound.settings()?,
    })
}

pub fn run(a: OptimizeArgs) -> Result<ExitCode, Error> {
    let file = ProblemFile::load(&a.file)?;
    let settings = settings_of(&a)?;
    // The input refused first (the library's checks of the file and of the settings for it),
    // then the output paths, both before the work.
    let job = api::OptimizeJob::new(&file, &settings)?;
    if let Some(path) = &a.report {
        AtomicFile::check(path)?;
    }
    if let Some(dir) = &a.plot {
        present::check_figure_dir(dir)?;
    }
    // Progress on stderr, the values shown in the problem's own length.
    let mut spinner = Spinner::new(job.progress_length());
    let mut show = |e: &api::Event, _: f64| spinner.show(e);
    let hooks = Hooks {
        events: Some(&mut show),
        cancel: None,
    };
    let answer = job.run(hooks);
    spinner.finish(answer.as_ref().map_or(&[][..], |r| r.notes()));
    let answer = answer?;
    if let Some(dir) = &a.plot {
        write_figures(dir, &answer.figures()?)?;
    }
    if let Some(path) = &a.report {
        let source = file_name(&a.file);
        let command = format!(
            "crawlopt optimize {source}{}{} --report {}",
            match settings.method {
                GaitMethod::Auto => String::new(),
                m => format!(" --method {}", m.name()),
            },
            if a.certify { " --certify" } else { "" },
            file_name(path)
        );
        report::write_report(path, &answer.report_html(&source, &command)?)?;
    }
    if a.json {
        json_line(&answer);
    } else {
        out(&answer.text());
    }
    said_report(&a);
    Ok(ExitCode::SUCCESS)
}

/// `wrote FILE` once the report is written: on stdout, or on stderr when stdout is JSON.
fn said_report(a: &OptimizeArgs) {
    if let Some(path) = &a.report {
        let line = format!("wrote {}", path.display());
        if a.json {
            eprintln!("{line}");
        } else {
            outln(&line);
        }
    }
}
