//! `crawlopt`: the command-line layer over the library. It parses arguments, calls the library
//! and renders results; errors are printed as one line and exit with status 2.

use clap::{Parser, Subcommand, ValueEnum};
use crawlopt::certify::{certify_result, NecessaryConditions};
use crawlopt::integrate::{
    simulate, Actuation, CatchingUp, ExactPwl, Method, PeriodMap, Search, SimOptions, Simulation,
    Waveform,
};
use crawlopt::io::{write_trajectory_csv, AtomicFile, ModelFile};
use crawlopt::model::{Analysis, FaceSign};
use crawlopt::optimal::{
    check_local, check_shifts, check_size, discrete_convergence, discrete_start, grow_phases,
    one_link_optimum, phase_start, search_sequences, shifted_origin, slip_sequence,
    solve_discrete_global_from, solve_discrete_local_shifted, solve_phase_global, Cost,
    GaitProblem, GaitResult, GrowOptions, GrowthStop, MilpStatus, PhaseGrowth, PhaseStep,
    StartEvent, StartGait, StartRecord, MAX_LOCAL_M, MAX_M, MAX_PHASES,
};
use crawlopt::present::text::{self, list, num};
use crawlopt::present::{self, report, write_figures, PlotInput};
use crawlopt::{Crawler, Error};
use std::cell::RefCell;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// `println!` that ends the process quietly when stdout is closed (`crawlopt ... | head`).
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: cannot write the output: {e}");
            std::process::exit(2);
        }
    }};
}

/// Simulation and optimal gaits of rate-independent soft crawlers.
#[derive(Parser)]
#[command(name = "crawlopt", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, ValueEnum)]
enum MethodArg {
    Exact,
    CatchingUp,
}

#[derive(Subcommand)]
enum Command {
    /// Analyse a crawler: the polytope C, the uniqueness condition, v_m and its directions.
    Analyze {
        /// Model file (TOML).
        file: PathBuf,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Write figures (SVG and PNG) into this directory: C, and v_m for two links.
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
    },
    /// Simulate the actuation of a model file until the periodic regime.
    Simulate {
        /// Model file (TOML) with an [actuation] section.
        file: PathBuf,
        /// Periods recorded on the periodic orbit (trajectory output); 0 records none.
        #[arg(long, default_value_t = 1, allow_negative_numbers = true, value_parser = count)]
        periods: usize,
        /// Steps per period (catching-up), or knots of the interpolant of a sine/triangle (exact).
        #[arg(
            long = "steps-per-period",
            default_value_t = 1000,
            allow_negative_numbers = true,
            value_parser = count
        )]
        steps_per_period: usize,
        /// Integration method.
        #[arg(long, value_enum, default_value = "exact")]
        method: MethodArg,
        /// Give up the search for the periodic regime after this many periods.
        #[arg(
            long = "max-periods",
            default_value_t = 5000,
            allow_negative_numbers = true,
            value_parser = count
        )]
        max_periods: usize,
        /// The state repeats when it changes by at most tol * (size of C) over a period.
        #[arg(long, default_value_t = 1e-12, allow_hyphen_values = true)]
        tol: f64,
        /// Iterate periods plainly this many times, then accelerate the search (Anderson).
        #[arg(
            long = "accelerate-after",
            default_value_t = 50,
            allow_negative_numbers = true,
            value_parser = count
        )]
        accelerate_after: usize,
        /// Never accelerate: the search is the physical transient.
        #[arg(long = "no-accelerate")]
        no_accelerate: bool,
        /// Write the recorded trajectory as CSV.
        #[arg(long, short = 'o')]
        output: Option<PathBuf>,
        /// Print one JSON object (with the recorded trajectory).
        #[arg(long)]
        json: bool,
        /// Write figures (SVG and PNG) into this directory: actuation, space-time diagram over
        /// max(periods, 3) periods, the orbit in C.
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
    },
    /// Compute an optimal gait of the [gait] problem.
    Optimize {
        /// Model file (TOML) with a [gait] section.
        file: PathBuf,
        /// Formulation; auto: phase gaits with K grown until the value stops improving (the
        /// discrete P_m when the problem bounds TV(u), which phase gaits cannot express).
        #[arg(long, value_enum, default_value = "auto")]
        method: OptimizeMethod,
        /// Slip phases allowed in a phase gait (all-stick transitions between them are free);
        /// without it K grows from 1 until the value has not improved for --patience K (or
        /// --max-phases, or the time limit).
        #[arg(long, allow_negative_numbers = true, value_parser = count)]
        phases: Option<usize>,
        /// Consecutive K without a gain that end the growth of K (default 2; --method phase, or
        /// auto without a TV bound, without --phases: the start gaits of the other methods stop
        /// at the first K without a gain).
        #[arg(long, allow_negative_numbers = true, value_parser = count)]
        patience: Option<usize>,
        /// Largest K tried when K grows (default 8; for --method phase or auto without
        /// --phases, and for the default start gaits).
        #[arg(long = "max-phases", allow_negative_numbers = true, value_parser = count)]
        max_phases: Option<usize>,
        /// The grid of P_m has 2^m steps (--method discrete, default 3; --method local, default
        /// 10).
        #[arg(long, allow_negative_numbers = true, value_parser = count_u32)]
        m: Option<u32>,
        /// Solve P_m for m = 1..=M (M = --m) and print the table of J_m (--method discrete).
        #[arg(long)]
        convergence: bool,
        /// Start gait: a result file of `optimize --json`. For --method local and sequence
        /// (default: the phase optimum with K grown to the first K without a gain, within half
        /// the time limit), and for --method discrete (default under --time-limit: the local
        /// method's gait on the same grid; see the README), whose MILP takes it, sampled on its
        /// grid, as the first incumbent.
        #[arg(long)]
        start: Option<PathBuf>,
        /// Time shifts of the start tried by the local method (--method local, and the default
        /// start of --method discrete under --time-limit when it runs the local method): the
        /// start shifted by j T / N, j = 0..N, each sampled on the grid and searched from; the
        /// best answer is kept (default 8).
        #[arg(long, allow_negative_numbers = true, value_parser = count)]
        shifts: Option<usize>,
        /// Stop after this many seconds with the best gait found and its gap.
        #[arg(long = "time-limit", value_name = "S", allow_hyphen_values = true)]
        time_limit: Option<f64>,
        /// Also check the necessary conditions (as `certify`); with --json they are added to the
        /// result as "necessary_conditions".
        #[arg(long)]
        certify: bool,
        /// Write the gait's figures (SVG and PNG) into this directory (with --certify, the
        /// adjoint too; with --convergence, J_m against m).
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Check the necessary optimality conditions (Theorem 2.2, Theorems 6.1-6.2) on a gait
    /// result: multipliers, residuals and a verdict.
    Certify {
        /// A result printed by `optimize --json`.
        file: PathBuf,
        /// Print one JSON object.
        #[arg(long)]
        json: bool,
        /// Write the gait's figures and the adjoint p(t), p + omega, u(t) (SVG and PNG) into
        /// this directory.
        #[arg(long, value_name = "DIR")]
        plot: Option<PathBuf>,
    },
    /// Draw the figures of a result file: a gait result (`optimize --json`) or a J_m table.
    Plot {
        /// RESULT.json.
        file: PathBuf,
        /// Directory for the SVG and PNG files (created if absent).
        #[arg(long, short = 'o', value_name = "DIR")]
        output: PathBuf,
    },
    /// One self-contained HTML report: parameters, analysis, optimal gait, figures, animation.
    Report {
        /// A model file (TOML) with a [gait] section (the optimal gait is computed by the phase
        /// method), or a gait result (.json, from `optimize --json`).
        file: PathBuf,
        /// The HTML file to write.
        #[arg(long, short = 'o', value_name = "FILE", default_value = "report.html")]
        output: PathBuf,
        /// Slip phases allowed when computing the gait from a model file (default: K grown until
        /// the value stops improving, as `optimize`).
        #[arg(long, allow_negative_numbers = true, value_parser = count)]
        phases: Option<usize>,
        /// Time limit in seconds when computing the gait from a model file.
        #[arg(long = "time-limit", value_name = "S", allow_hyphen_values = true)]
        time_limit: Option<f64>,
    },
    /// Measure the simulation cost per time step (sine gait L_l = A sin(2 pi t - l phi)).
    Bench {
        /// Numbers of blocks, comma separated.
        #[arg(
            long,
            value_delimiter = ',',
            default_value = "3,10,100,1000",
            allow_hyphen_values = true,
            value_parser = count
        )]
        blocks: Vec<usize>,
        /// Time steps per period.
        #[arg(long, default_value_t = 1000, allow_negative_numbers = true, value_parser = count)]
        steps: usize,
        /// Amplitude A.
        #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
        amplitude: f64,
        /// Phase lag phi between consecutive links, degrees.
        #[arg(long = "phase-deg", default_value_t = 90.0, allow_hyphen_values = true)]
        phase_deg: f64,
        /// mu^+ on every block.
        #[arg(long = "mu-forward", default_value_t = 1.0, allow_hyphen_values = true)]
        mu_forward: f64,
        /// mu^- on every block.
        #[arg(
            long = "mu-backward",
            default_value_t = 3.3,
            allow_hyphen_values = true
        )]
        mu_backward: f64,
        /// Minimum measured time per case, seconds.
        #[arg(long = "min-time", default_value_t = 1.0, allow_hyphen_values = true)]
        min_time: f64,
        /// Integrate exactly this many periods from x = 0 (plain iteration, as a peer would) and
        /// report the displacement of the last one, instead of searching for the periodic regime.
        #[arg(long, allow_negative_numbers = true, value_parser = count)]
        periods: Option<usize>,
        /// Print JSON lines.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Clone, Copy, PartialEq, ValueEnum)]
enum OptimizeMethod {
    /// Phase gaits with K grown until no gain; discrete when TV(u) is bounded.
    Auto,
    /// The paper's discrete problem P_m on 2^m steps, solved globally (MILP).
    Discrete,
    /// P_m on 2^m steps by the local LPCC active-set method, from a phase gait or --start.
    Local,
    /// Exact continuous-time gaits of at most K slip phases, solved globally (MILP).
    Phase,
    /// Local search over the slip-mode sequences of phase gaits (exact gaits, each optimal
    /// for its sequence; no global claim), from a phase gait or --start: for crawlers or K
    /// where the MILP is too slow.
    Sequence,
}

/// A count flag (`--m`, `--phases`, `--periods`, ...): a whole number, 0 or more. Parsed here
/// so that the message says why a value is refused (std's "invalid digit found in string" for
/// `-1` does not); clap names the flag.
fn count(s: &str) -> Result<usize, String> {
    whole(s, usize::MAX as u64).map(|v| v as usize)
}

/// [`count`] for a `u32` flag (`--m`).
fn count_u32(s: &str) -> Result<u32, String> {
    whole(s, u32::MAX.into()).map(|v| v as u32)
}

/// A whole number in `0..=max`.
fn whole(s: &str, max: u64) -> Result<u64, String> {
    let too_large = || format!("too large (at most {max})");
    match s.parse::<u64>() {
        Ok(v) if v <= max => Ok(v),
        Ok(_) => Err(too_large()),
        Err(e) if *e.kind() == std::num::IntErrorKind::PosOverflow => Err(too_large()),
        Err(_) if s.parse::<f64>().is_ok_and(|v| v < 0.0) => {
            Err("must not be negative (a whole number, 0 or more)".into())
        }
        Err(_) => Err("not a whole number (0, 1, 2, ...)".into()),
    }
}

/// The scales of a gait problem's quantities: text output shows a value smaller than
/// [`text::SNAP`] times its quantity's scale as 0 (solver noise).
struct GaitScales {
    /// Lengths, displacements and the objective: the largest stroke an actuator can make in a
    /// period, `T max_l a_l / k_l`.
    length: f64,
    /// Times: the period.
    time: f64,
    /// Computed forces (states, the ends of C): the smallest friction threshold, the smallest
    /// force the model tells apart ([`force_scale`]).
    force: f64,
}

impl GaitScales {
    fn new(stiffness: &[f64], mu: impl IntoIterator<Item = f64>, problem: &GaitProblem) -> Self {
        let sweep = problem.rate_bound.iter().zip(stiffness);
        GaitScales {
            length: problem.period * sweep.fold(0.0_f64, |m, (a, k)| m.max(a / k)),
            time: problem.period,
            force: mu.into_iter().fold(f64::INFINITY, f64::min),
        }
    }

    /// Of a problem posed for a crawler.
    fn of_problem(crawler: &Crawler, problem: &GaitProblem) -> Self {
        let mu = crawler.mu_forward().iter().chain(crawler.mu_backward());
        Self::new(crawler.stiffness(), mu.copied(), problem)
    }

    /// Of a result (its crawler and problem).
    fn of(r: &GaitResult) -> Self {
        let c = &r.crawler;
        let mu = c.mu_forward.iter().chain(&c.mu_backward);
        Self::new(&c.stiffness, mu.copied(), &r.problem)
    }
}

/// The scale of computed forces of a crawler (states, the ends of C, vertices): its smallest
/// friction threshold. The exact ones are sums of thresholds, so a force smaller than
/// [`text::SNAP`] times the smallest threshold is rounding noise of a zero. (Not the largest
/// threshold: with mu+ = 1e300 and mu- = 3, C spans [-6, 3].)
fn force_scale(crawler: &Crawler) -> f64 {
    let mu = crawler.mu_forward().iter().chain(crawler.mu_backward());
    mu.fold(f64::INFINITY, |m, &v| m.min(v))
}

/// The start of a local method: the result file `path` (checked to be of this crawler and
/// period), or [`phase_start`]; with the time left of `growth.time_limit`.
fn start_gait(
    path: Option<&std::path::Path>,
    (crawler, problem): &(&Crawler, &GaitProblem),
    growth: &GrowOptions,
    progress: &Progress,
) -> Result<(StartGait, Option<f64>), Error> {
    let began = Instant::now();
    let start = match path {
        Some(path) => start_file(path, crawler, problem)?,
        None => phase_start(crawler, problem, growth, &mut |e| progress.start_event(e))?,
    };
    let left = growth.time_limit.map(|t| t - began.elapsed().as_secs_f64());
    if left.is_some_and(|l| l <= 0.0) {
        return Err(Error::TimeLimit(
            "the time limit was reached while computing the start gait".into(),
        ));
    }
    Ok((start, left))
}

/// The start gait stored in the result file `path`.
fn start_file(
    path: &std::path::Path,
    crawler: &Crawler,
    problem: &GaitProblem,
) -> Result<StartGait, Error> {
    let what = path.display().to_string();
    let r = GaitResult::from_json(&read_text(path)?, &what)?;
    StartGait::from_result(crawler, problem, r, &what)
}

/// `--m` of the discrete method unless given (8 steps).
const DEFAULT_M_DISCRETE: u32 = 3;

/// `--m` of the local method unless given (1024 steps).
const DEFAULT_M_LOCAL: u32 = 10;

/// Time shifts of the start tried by the local method unless `--shifts` says otherwise.
const DEFAULT_SHIFTS: usize = 8;

/// Exit status of a simulation whose periodic regime was not reached.
const EXIT_NOT_CONVERGED: u8 = 3;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(cmd: Command) -> Result<ExitCode, Error> {
    match cmd {
        Command::Analyze { file, json, plot } => {
            let model = ModelFile::load(&file)?;
            let crawler = model.crawler()?;
            let a = crawler.analyze();
            if let Some(dir) = &plot {
                write_figures(dir, &present::analysis_figures(&crawler)?)?;
            }
            let gait = model.gait(&crawler)?;
            // The one-link closed form (SPEC §9) when the file poses the gait problem.
            let optimum = match &gait {
                Some(g) if a.uniqueness_ok && crawler.blocks() == 2 => {
                    Some(one_link_optimum(&crawler, g)?)
                }
                _ => None,
            };
            if json {
                // Streamed: a document of 10^7 blocks is gigabytes as a serde_json::Value tree.
                #[derive(serde::Serialize)]
                struct Doc<'a> {
                    #[serde(flatten)]
                    analysis: &'a Analysis,
                    #[serde(skip_serializing_if = "Option::is_none")]
                    gait: Option<serde_json::Value>,
                }
                let doc = Doc {
                    analysis: &a,
                    gait: gait
                        .as_ref()
                        .map(|g| serde_json::json!({ "problem": g, "one_link_optimum": optimum })),
                };
                write_json(&doc);
            } else {
                print_analysis(&crawler, &a);
                if let Some(g) = &gait {
                    outln!(
                        "gait problem: period {}, rate bounds a = {}, cost {}{}",
                        num(g.period, 0.0),
                        list(&g.rate_bound, 0.0),
                        match g.cost {
                            Cost::None => "none".to_string(),
                            Cost::Quadratic { weight } =>
                                format!("(c/2)|u|^2 with c = {}", num(weight, 0.0)),
                        },
                        g.max_total_variation.map_or(String::new(), |v| format!(
                            ", total variation <= {}",
                            num(v, 0.0)
                        ))
                    );
                    if let Some(o) = &optimum {
                        outln!(
                            "  closed-form optimum (one link): J* = {} ({})",
                            num(o.value, GaitScales::of_problem(&crawler, g).length),
                            o.reason
                        );
                    }
                }
            }
            if !a.uniqueness_ok {
                if let Err(e) = crawler.require_unique() {
                    eprintln!("error: {e}");
                }
                return Ok(ExitCode::from(2));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Simulate {
            file,
            periods,
            steps_per_period,
            method,
            max_periods,
            tol,
            accelerate_after,
            no_accelerate,
            output,
            json,
            plot,
        } => {
            let model = ModelFile::load(&file)?;
            let crawler = model.crawler()?;
            crawler.require_unique()?;
            let act = model.actuation(crawler.links())?;
            let opts = SimOptions {
                method: match method {
                    MethodArg::Exact => Method::Exact,
                    MethodArg::CatchingUp => Method::CatchingUp,
                },
                steps_per_period,
                record_periods: periods,
                max_periods,
                tol,
                accelerate_after: (!no_accelerate).then_some(accelerate_after),
                initial_state: model.simulation.initial_state.clone(),
            };
            // Output paths are checked before the work: a directory for -o, a file for --plot.
            if let Some(path) = &output {
                AtomicFile::check(path)?;
            }
            if let Some(dir) = &plot {
                present::check_figure_dir(dir)?;
            }
            let sim = simulate(&crawler, &act, &opts).map_err(simulate_flags)?;
            // Without a periodic regime nothing is written (exit 3 below says so). The figures
            // are computed before anything is written, so that their failure leaves no CSV.
            let figs = match (&plot, sim.converged) {
                (Some(_), true) => Some(
                    present::simulation_figures(&crawler, &act, &sim, periods.max(3))
                        .map_err(simulate_flags)?,
                ),
                _ => None,
            };
            let written = match (&output, &sim.trajectory, sim.converged) {
                (Some(path), Some(traj), true) => {
                    write_trajectory_csv(path, traj)?;
                    Some(path)
                }
                _ => None,
            };
            if let (Some(dir), Some(figs)) = (&plot, &figs) {
                write_figures(dir, figs)?;
            }
            if json {
                outln!("{}", serde_json::to_string(&sim).expect("serialisable"));
            } else {
                print_simulation(&sim, &crawler, &act, written);
            }
            if !sim.converged {
                let unwritten: Vec<String> = [
                    output
                        .as_ref()
                        .map(|p| format!("no trajectory written to {}", p.display())),
                    plot.as_ref()
                        .map(|d| format!("no figures written to {}", d.display())),
                ]
                .into_iter()
                .flatten()
                .collect();
                eprintln!(
                    "error: the periodic regime was not reached within {} periods (residual {:.3e}); \
                     displacement_per_period is not reported{} (raise --max-periods or --tol)",
                    sim.periods_simulated,
                    sim.period_residual,
                    if unwritten.is_empty() {
                        String::new()
                    } else {
                        format!(", {}", unwritten.join(", "))
                    }
                );
                return Ok(ExitCode::from(EXIT_NOT_CONVERGED));
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Optimize {
            file,
            method,
            phases,
            patience,
            max_phases,
            m,
            convergence,
            start,
            shifts,
            time_limit,
            certify,
            json,
            plot,
        } => {
            let model = ModelFile::load(&file)?;
            let crawler = model.crawler()?;
            crawler.require_unique()?;
            let problem = model.gait(&crawler)?.ok_or_else(|| {
                Error::invalid("gait", "nothing", "the model file has no [gait] section")
            })?;
            let method = match method {
                OptimizeMethod::Auto if problem.max_total_variation.is_some() => {
                    OptimizeMethod::Discrete
                }
                OptimizeMethod::Auto => OptimizeMethod::Phase,
                other => other,
            };
            if start.is_some()
                && !matches!(
                    method,
                    OptimizeMethod::Local | OptimizeMethod::Sequence | OptimizeMethod::Discrete
                )
            {
                return Err(Error::invalid(
                    "start",
                    "a file",
                    "applies to --method local, sequence and discrete only",
                ));
            }
            // K grows for a certified answer (auto, phase), or for a default start gait.
            let grows = match method {
                OptimizeMethod::Auto | OptimizeMethod::Phase => phases.is_none(),
                OptimizeMethod::Local | OptimizeMethod::Sequence => start.is_none(),
                OptimizeMethod::Discrete => {
                    start.is_none()
                        && !convergence
                        && time_limit.is_some()
                        && problem.max_total_variation.is_none()
                }
            };
            let certified_growth = method == OptimizeMethod::Phase && grows;
            // The local method runs for --method local, and in discrete's default start unless
            // the start is the phase gait itself (a quadratic cost, grids beyond the method).
            let local_search = method == OptimizeMethod::Local
                || (method == OptimizeMethod::Discrete
                    && grows
                    && problem.cost == Cost::None
                    && m.unwrap_or(DEFAULT_M_DISCRETE) <= MAX_LOCAL_M);
            for (given, applies, flag, value) in [
                (
                    patience,
                    certified_growth,
                    "patience",
                    "a certified growth of K: --method phase, or auto without a TV bound, without \
                     --phases (start gaits stop at the first K without a gain)",
                ),
                (
                    max_phases,
                    grows,
                    "max-phases",
                    "a growth of K: --method phase, or auto without a TV bound, without --phases; \
                     or a default start gait (no --start; for discrete, under --time-limit and \
                     without a TV bound)",
                ),
                (
                    shifts,
                    local_search,
                    "shifts",
                    "the local method: --method local, or the default start of --method \
                     discrete (under --time-limit, without a TV bound or a quadratic cost, m <= \
                     14)",
                ),
            ] {
                if let (Some(v), false) = (given, applies) {
                    return Err(Error::invalid(flag, v, format!("applies only to {value}")));
                }
            }
            let defaults = GrowOptions::default();
            let growth = GrowOptions {
                max_phases: max_phases.unwrap_or(defaults.max_phases),
                patience: patience.unwrap_or(defaults.patience),
                time_limit,
                ..defaults
            };
            // Values are checked before any solve, so that a bad one is not found after a start
            // gait was computed, or turned into a note by a start policy.
            growth.check()?;
            if let Some(s) = shifts {
                check_shifts(s)?;
            }
            if method == OptimizeMethod::Local {
                check_local(&problem, m.unwrap_or(DEFAULT_M_LOCAL))?;
            }
            // The size of the models (blocks, blocks x grid steps), before any allocation.
            match method {
                OptimizeMethod::Local | OptimizeMethod::Discrete => {
                    let m = m.unwrap_or(if method == OptimizeMethod::Local {
                        DEFAULT_M_LOCAL
                    } else {
                        DEFAULT_M_DISCRETE
                    });
                    // An m beyond the grids is refused by the solver's own range check.
                    let steps = if m <= MAX_M { 1usize << m } else { 1 };
                    check_size(&crawler, steps, "m", m)?;
                }
                _ => {
                    let k = phases.unwrap_or(growth.max_phases);
                    check_size(&crawler, k, "phases", k)?;
                }
            }
            let shifts = shifts.unwrap_or(DEFAULT_SHIFTS);
            let progress = Progress::new(GaitScales::of_problem(&crawler, &problem).length);
            let problem_of = (&crawler, &problem);
            let result = match method {
                OptimizeMethod::Local => {
                    if phases.is_some() || convergence {
                        return Err(Error::invalid(
                            "phases/convergence",
                            "set",
                            "do not apply to --method local",
                        ));
                    }
                    let m = m.unwrap_or(DEFAULT_M_LOCAL);
                    let (from, left) =
                        start_gait(start.as_deref(), &problem_of, &growth, &progress)?;
                    progress.say(format!("local LPCC method on P_{m} ({} steps)", 1u64 << m));
                    let (s, shift) = solve_discrete_local_shifted(
                        &crawler,
                        &problem,
                        m,
                        from.times(),
                        from.lengths(),
                        shifts,
                        left,
                    )?;
                    GaitResult::from_local(
                        &crawler,
                        &problem,
                        &s,
                        &shifted_origin(&from.origin, shift),
                    )
                }
                OptimizeMethod::Sequence => {
                    if m.is_some() || convergence {
                        return Err(Error::invalid(
                            "m/convergence",
                            "set",
                            "do not apply to --method sequence",
                        ));
                    }
                    let (from, left) =
                        start_gait(start.as_deref(), &problem_of, &growth, &progress)?;
                    let (seq, origin) = (slip_sequence(&from.result.gait.slip), from.origin);
                    let k = phases.unwrap_or((seq.len().max(1) + 2).min(MAX_PHASES));
                    progress.say(format!(
                        "local search over sequences of {k} slip modes, from {} of {origin}",
                        seq.len()
                    ));
                    let s = search_sequences(&crawler, &problem, &seq, k, left)?;
                    GaitResult::from_sequence(&crawler, &problem, &s, &origin)
                }
                OptimizeMethod::Phase | OptimizeMethod::Auto => {
                    if let Some(m) = m {
                        return Err(Error::invalid("m", m, "applies to --method discrete only"));
                    }
                    if convergence {
                        return Err(Error::invalid(
                            "convergence",
                            "set",
                            "applies to --method discrete only",
                        ));
                    }
                    match phases {
                        Some(k) => {
                            progress.say(format!("solving the {k}-phase MILP"));
                            let s = solve_phase_global(&crawler, &problem, k, time_limit)?;
                            GaitResult::from_phase(&crawler, &problem, &s)
                        }
                        None => {
                            let g = progress.grow(&crawler, &problem, &growth)?;
                            GaitResult::from_growth(&crawler, &problem, &g)
                        }
                    }
                }
                OptimizeMethod::Discrete => {
                    if let Some(k) = phases {
                        return Err(Error::invalid(
                            "phases",
                            k,
                            "applies to --method phase only",
                        ));
                    }
                    let m = m.unwrap_or(DEFAULT_M_DISCRETE);
                    if m == 0 {
                        return Err(Error::invalid(
                            "m",
                            0,
                            "must be at least 1 (a periodic gait needs two steps)",
                        ));
                    }
                    if convergence && start.is_some() {
                        return Err(Error::invalid(
                            "start",
                            "a file",
                            "does not apply to --convergence (each m starts from the optimum of \
                             m - 1)",
                        ));
                    }
                    if convergence {
                        progress.say("m = 1".into());
                        let (table, s) =
                            discrete_convergence(&crawler, &problem, m, time_limit, &mut |row| {
                                progress.say(format!(
                                    "m = {}: J = {} (gap {:.1e}, {:.2} s); m = {} next",
                                    row.m,
                                    progress.num(row.objective),
                                    row.gap,
                                    row.seconds,
                                    row.m + 1
                                ))
                            })?;
                        let mut r = GaitResult::from_discrete(&crawler, &problem, &s);
                        r.convergence = Some(table);
                        r
                    } else {
                        let began = Instant::now();
                        let from = match start.as_deref() {
                            Some(path) => Some(start_file(path, &crawler, &problem)?),
                            None => {
                                discrete_start(&crawler, &problem, m, shifts, &growth, &mut |e| {
                                    progress.start_event(e)
                                })?
                            }
                        };
                        let left = time_limit.map(|t| t - began.elapsed().as_secs_f64());
                        if left.is_some_and(|l| l <= 0.0) {
                            return Err(Error::TimeLimit(format!(
                                "P_{m}: the time limit was reached while computing the start gait"
                            )));
                        }
                        progress.say(format!("solving P_{m} ({} steps)", 1u64 << m));
                        let s = solve_discrete_global_from(
                            &crawler,
                            &problem,
                            m,
                            left,
                            from.as_ref().map(|f| (f.times(), f.lengths())),
                        )?;
                        let mut r = GaitResult::from_discrete(&crawler, &problem, &s);
                        r.discrete_start = from.zip(s.start_objective).map(|(f, j)| StartRecord {
                            start: f.origin,
                            start_objective: j,
                        });
                        r
                    }
                }
            };
            progress.finish();
            let cert = if certify {
                Some(certify_result(&result, "optimize")?)
            } else {
                None
            };
            if let Some(dir) = &plot {
                let mut figs = present::gait_figures(&result)?;
                if let Some(c) = &cert {
                    figs.push(present::adjoint_figure_of(&c.multipliers)?);
                }
                write_figures(dir, &figs)?;
            }
            if json {
                let mut v = serde_json::to_value(&result).expect("serialisable");
                if let Some(c) = &cert {
                    v["necessary_conditions"] = serde_json::to_value(c).expect("serialisable");
                }
                outln!("{}", serde_json::to_string(&v).expect("serialisable"));
            } else {
                print_gait_result(&result);
                if let Some(c) = &cert {
                    print_certificate(c, &result);
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Certify { file, json, plot } => {
            let what = file.display().to_string();
            let result = GaitResult::from_json(&read_text(&file)?, &what)?;
            let cert = certify_result(&result, &what)?;
            if let Some(dir) = &plot {
                let mut figs = present::gait_figures(&result)?;
                figs.push(present::adjoint_figure_of(&cert.multipliers)?);
                write_figures(dir, &figs)?;
            }
            if json {
                outln!("{}", serde_json::to_string(&cert).expect("serialisable"));
            } else {
                print_certificate(&cert, &result);
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Plot { file, output } => {
            let input = PlotInput::from_json(&read_text(&file)?, &file_name(&file))?;
            let written = write_figures(&output, &input.figures()?)?;
            for p in written {
                outln!("wrote {}", p.display());
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Report {
            file,
            output,
            phases,
            time_limit,
        } => {
            // A directory (the default report.html may be one) is refused before the work.
            AtomicFile::check(&output)?;
            let name = file_name(&file);
            let result = if file.extension().is_some_and(|e| e == "json") {
                GaitResult::from_json(&read_text(&file)?, &name)?
            } else {
                report::optimize_model(
                    &ModelFile::load(&file)?,
                    phases,
                    time_limit,
                    Default::default(),
                )?
            };
            let html = report::build_report(&result, &name)?;
            report::write_report(&output, &html)?;
            let length = GaitScales::of(&result).length;
            outln!(
                "wrote {} (objective J = {}, displacement per period {})",
                output.display(),
                num(result.objective, length),
                num(result.displacement_per_period, length)
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Bench {
            blocks,
            steps,
            amplitude,
            phase_deg,
            mu_forward,
            mu_backward,
            min_time,
            periods,
            json,
        } => {
            check_bench_flags(&blocks, steps, min_time, periods)?;
            for (flag, v) in [
                ("--amplitude", amplitude),
                ("--mu-forward", mu_forward),
                ("--mu-backward", mu_backward),
            ] {
                if !(BENCH_VALUE_RANGE[0]..=BENCH_VALUE_RANGE[1]).contains(&v) {
                    return Err(Error::invalid(
                        flag,
                        v,
                        format!(
                            "must be in [{:e}, {:e}] (k = 1: a benchmark needs no other scale)",
                            BENCH_VALUE_RANGE[0], BENCH_VALUE_RANGE[1]
                        ),
                    ));
                }
            }
            if !phase_deg.is_finite() {
                return Err(Error::invalid("--phase-deg", phase_deg, "must be finite"));
            }
            // Every crawler is built and checked before the first case is timed.
            let mut cases = Vec::with_capacity(blocks.len());
            for &nb in &blocks {
                let crawler =
                    Crawler::uniform(nb, 1.0, mu_forward, mu_backward).map_err(bench_flags)?;
                crawler.require_unique().map_err(|e| {
                    Error::invalid(
                        "--mu-forward, --mu-backward",
                        format!("{mu_forward}, {mu_backward}"),
                        format!("with --blocks {nb}: {e}"),
                    )
                })?;
                let n = crawler.links();
                let act = Actuation::wave(
                    Waveform::Sine,
                    1.0,
                    vec![0.0; n],
                    vec![amplitude; n],
                    (0..n).map(|l| l as f64 * phase_deg).collect(),
                )
                .map_err(bench_flags)?;
                cases.push((nb, crawler, act));
            }
            if !json {
                outln!(
                    "sine gait L_l = {} sin(2 pi t - l {} deg), k = 1, mu+ = {}, mu- = {}, {steps} steps/period",
                    num(amplitude, 0.0),
                    num(phase_deg, 0.0),
                    num(mu_forward, 0.0),
                    num(mu_backward, 0.0)
                );
                outln!("| N | method | disp/period | periods | steps | us/step | link-steps/s |");
                outln!("|---|---|---|---|---|---|---|");
            }
            for (nb, crawler, act) in &cases {
                let (nb, n) = (*nb, crawler.links());
                for method in [Method::CatchingUp, Method::Exact] {
                    let r = bench_case(crawler, act, method, steps, periods, min_time)
                        .map_err(bench_flags)?;
                    if json {
                        outln!(
                            "{}",
                            serde_json::json!({
                                "N": nb, "method": method.to_string(), "steps_per_period": steps,
                                "disp_per_period": r.disp, "periods": r.periods, "converged": r.converged,
                                "fixed_periods": periods.is_some(),
                                "us_per_step": r.us_per_step, "link_steps_per_s": r.us_per_step.recip() * 1e6 * n as f64,
                                "repetitions": r.reps,
                            })
                        );
                    } else {
                        outln!(
                            "| {nb} | {method} | {} | {} | {} | {:.3} | {:.3e} |",
                            r.disp
                                .map_or("not converged".into(), |d| format!("{d:.15}")),
                            r.periods,
                            r.periods * steps,
                            r.us_per_step,
                            r.us_per_step.recip() * 1e6 * n as f64,
                        );
                    }
                }
            }
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// Writes `value` as pretty JSON and a newline to stdout without building it in memory first;
/// ends the process quietly when stdout is closed, like `outln!`.
fn write_json(value: &impl serde::Serialize) {
    use std::io::Write as _;
    let mut w = std::io::BufWriter::new(std::io::stdout().lock());
    let done = serde_json::to_writer_pretty(&mut w, value)
        .map_err(std::io::Error::from)
        .and_then(|()| writeln!(w))
        .and_then(|()| w.flush());
    if let Err(e) = done {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write the output: {e}");
        std::process::exit(2);
    }
}

/// The text of an input file (errors name the file).
fn read_text(path: &std::path::Path) -> Result<String, Error> {
    crawlopt::io::read_input_text(path, crawlopt::io::MAX_RESULT_BYTES)
}

/// The file name of a path, for messages and the report (no directories).
fn file_name(path: &std::path::Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

fn status_word(s: MilpStatus) -> &'static str {
    match s {
        MilpStatus::Optimal => "optimal",
        MilpStatus::TimeLimit => "time_limit",
        MilpStatus::ApproximationLimit => "approximation_limit",
        MilpStatus::Stationary => "stationary",
        MilpStatus::Stalled => "stalled",
    }
}

/// Progress of long solves on stderr (a spinner with the elapsed time; hidden when stderr is
/// not a terminal).
struct Progress {
    bar: indicatif::ProgressBar,
    /// Notes held until the solve succeeds ([`Progress::note`]).
    notes: RefCell<Vec<String>>,
    /// The length scale of the problem, for the values shown ([`GaitScales::length`]).
    length: f64,
}

impl Progress {
    fn new(length: f64) -> Self {
        let bar = indicatif::ProgressBar::new_spinner();
        bar.set_style(
            indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .expect("valid template"),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        Progress {
            bar,
            notes: RefCell::new(Vec::new()),
            length,
        }
    }

    fn say(&self, msg: String) {
        self.bar.set_message(msg);
    }

    /// A value of the objective's kind (J, a bound) as text shows it.
    fn num(&self, v: f64) -> String {
        num(v, self.length)
    }

    /// A note on how the solve goes on (e.g. without a start gait): shown on the spinner now,
    /// printed on stderr (`note: ...`) by [`Progress::finish`] once the solve has succeeded. A
    /// solve that ends in an error drops its notes: the error is the one line that explains
    /// it, not preceded by a note saying how the solve would go on.
    fn note(&self, msg: String) {
        self.say(format!("note: {msg}"));
        self.notes.borrow_mut().push(msg);
    }

    /// Clears the spinner and prints the notes.
    fn finish(&self) {
        self.bar.finish_and_clear();
        for msg in self.notes.borrow_mut().drain(..) {
            eprintln!("note: {msg}");
        }
    }

    /// Shows what a start policy is doing; its notes are printed by [`Progress::finish`].
    fn start_event(&self, e: StartEvent) {
        match e {
            StartEvent::Stage(s) => self.say(s.to_string()),
            StartEvent::Phase(st) => self.say(format!(
                "start: phase gait, {}",
                phase_step(st, self.length)
            )),
            StartEvent::Note(s) => self.note(s.to_string()),
        }
    }

    /// [`grow_phases`] showing each K as it is solved.
    fn grow(
        &self,
        crawler: &Crawler,
        problem: &GaitProblem,
        opts: &GrowOptions,
    ) -> Result<PhaseGrowth, Error> {
        self.say(format!("K = {}", opts.min_phases));
        grow_phases(crawler, problem, opts, &mut |st| {
            self.say(phase_step(st, self.length))
        })
    }
}

/// One solved K of a phase growth, for the progress line (J and the bound at the problem's
/// length scale `length`).
fn phase_step(st: &PhaseStep, length: f64) -> String {
    format!(
        "K = {}: J = {} (bound {}, {:.2} s); K = {} next",
        st.phases,
        num(st.objective, length),
        num(st.bound, length),
        st.seconds,
        st.phases + 1
    )
}

/// The human form of an optimal-gait result: the same content as the JSON.
fn print_gait_result(r: &GaitResult) {
    let c = &r.certificate;
    let sc = GaitScales::of(r);
    let len = |v: f64| num(v, sc.length);
    outln!("method {}: {}", r.method, status_word(r.status));
    outln!(
        "objective J = {} (displacement per period {}, actuation cost {})",
        len(r.objective),
        len(r.displacement_per_period),
        len(r.actuation_cost)
    );
    let proven = r.status == MilpStatus::Optimal && c.gap.is_some_and(|g| g <= 1e-6);
    // Zero as the text shows it (below the snap of the length scale).
    let zero = |v: f64| v.abs() < text::SNAP * sc.length;
    if proven && zero(r.objective) && zero(r.displacement_per_period) {
        outln!("no gait of this class moves the crawler forward: the optimum is 0 (stay idle)");
    }
    let scope = match (c.kind.as_str(), c.phases, r.m) {
        ("global_k_phases", Some(k), _) => format!("gaits of at most {k} slip phases"),
        ("global", _, Some(m)) => format!("P_{m} ({} steps)", 1u64 << m),
        (kind, _, _) => kind.to_string(),
    };
    let what = match (r.status, c.kind.as_str()) {
        (_, "local") => format!("local ({})", status_word(r.status)),
        (MilpStatus::Optimal, _) => format!("global among {scope}"),
        (status, _) => format!(
            "not proven ({}); the bound is over {scope}",
            status_word(status)
        ),
    };
    match (c.gap, c.bound) {
        (Some(gap), Some(bound)) => {
            outln!("certificate: {what}, gap {gap:.3e} (bound {})", len(bound))
        }
        _ => outln!("certificate: {what}"),
    }
    outln!(
        "verified by simulation: {} (solver: {})",
        len(r.verified_displacement),
        len(r.solver_objective)
    );
    if let Some(pg) = &r.phase_growth {
        outln!(
            "phases grown until {}:",
            match pg.stop {
                GrowthStop::NoGain => "the value stopped improving",
                GrowthStop::MaxPhases => "--max-phases (the value was still improving or still 0)",
                GrowthStop::NoForwardMotion =>
                    "K = 1: v_m <= 0 for every shape rate, so no gait moves this crawler forward",
                GrowthStop::TimeLimit => "the time limit",
            }
        );
        outln!("  | K | J_K | bound | status | seconds |");
        for st in &pg.table {
            outln!(
                "  | {} | {} | {} | {} | {:.2} |",
                st.phases,
                len(st.objective),
                len(st.bound),
                status_word(st.status),
                st.seconds
            );
        }
    }
    if let Some(st) = &r.discrete_start {
        outln!(
            "the MILP started from {} (J = {} on this grid)",
            st.start,
            len(st.start_objective)
        );
    }
    match (&r.local, r.m) {
        (Some(l), Some(_)) => outln!(
            "local method: from {} (J = {} on this grid), {} LP solves, {} mode switches, stopped: {:?}",
            l.start,
            len(l.start_objective),
            l.lp_solves,
            l.switches,
            l.stop
        ),
        (Some(l), None) => outln!(
            "sequence search: from {} (J = {} for its sequence of slip modes), {} LP solves, {} improving moves, stopped: {:?}",
            l.start,
            len(l.start_objective),
            l.lp_solves,
            l.switches,
            l.stop
        ),
        (None, _) => {}
    }
    if let Some(table) = &r.convergence {
        outln!("convergence of the discrete problems P_m:");
        outln!("  | m | steps | J_m | gap | status | seconds |");
        for row in table {
            outln!(
                "  | {} | {} | {} | {:.1e} | {} | {:.2} |",
                row.m,
                row.steps,
                len(row.objective),
                row.gap,
                status_word(row.status),
                row.seconds
            );
        }
    }
    let g = &r.gait;
    for (j, u) in g.controls.iter().enumerate() {
        outln!(
            "  {j:>4}: t = [{}, {}]  u = {}  slip = {:?}",
            num(g.times[j], sc.time),
            num(g.times[j + 1], sc.time),
            text::list_each(u, &r.problem.rate_bound),
            g.slip[j]
        );
    }
}

/// The human form of a certificate of the gait of `r`: the same content as its JSON,
/// multipliers abridged.
fn print_certificate(c: &NecessaryConditions, r: &GaitResult) {
    let sc = GaitScales::of(r);
    let m = &c.multipliers;
    // The adjoint's own scale (lambda + ||p||_inf is normalised, but omega shifts it).
    let adjoint = text::max_abs(m.p_plus_omega.iter().flatten().chain(&m.omega));
    outln!(
        "necessary conditions (Theorem 2.2; discrete form Theorems 6.1-6.2): {}",
        serde_json::to_string(&c.verdict)
            .expect("enum")
            .trim_matches('"')
    );
    outln!("  {}", c.reason);
    let n = &c.normalisation;
    outln!(
        "  lambda = {} (scaled: {}); lambda + ||p||_inf = {}; sum of the paper's (norm) = {}",
        num(c.lambda, 1.0),
        n.scaled_by,
        num(n.lambda_plus_sup_p, 0.0),
        num(n.paper_norm, 0.0)
    );
    outln!(
        "  J = {}; min |p + omega| = {:.3e}; omega = {}",
        num(c.objective, sc.length),
        c.nondegeneracy_margin,
        list(&m.omega, adjoint)
    );
    if let Some(b) = &c.branch_lp {
        outln!(
            "  branch LP (active faces and slips fixed): optimum {}, improvement over the gait {:.3e}",
            num(b.optimum, sc.length),
            b.improvement
        );
    }
    for k in &c.conditions {
        outln!(
            "  [Thm {}] {:<18} residual {:>10.3e}  tol {:.1e}  {}  {}",
            k.theorem,
            k.name,
            k.residual,
            k.tolerance,
            if k.holds { "holds" } else { "FAILS" },
            k.statement
        );
    }
    let rows = m.p.len();
    let show = rows.min(64);
    outln!(
        "  multipliers per piece ({}{}):",
        m.extension,
        if show < rows {
            format!(", first {show} of {rows}")
        } else {
            String::new()
        }
    );
    for j in 0..show {
        outln!(
            "    t = {}  u = {}  p + omega = {}",
            num(m.times[j], sc.time),
            text::list_each(&m.u[j], &r.problem.rate_bound),
            list(&m.p_plus_omega[j], adjoint)
        );
    }
    let mass = text::max_abs(m.xi.iter().map(|x| &x.value));
    for x in m.xi.iter().take(64) {
        outln!(
            "    dxi at t = {} (knot {}): face {}{} mass {}",
            num(x.time, sc.time),
            x.knot,
            x.block,
            x.side,
            num(x.value, mass)
        );
    }
    if let Some(o) = &c.one_link {
        outln!(
            "  one link (§4): C = [{}, {}], bang-bang {}, switches at t = {} (at an end of C: {:?})",
            num(o.alpha, sc.force),
            num(o.beta, sc.force),
            o.bang_bang,
            list(&o.switch_times, sc.time),
            o.switch_at_end
        );
        outln!(
            "    interior arcs {} vs (beta - alpha)/a = {}",
            list(&o.interior_arcs, sc.time),
            num(o.expected_arc, sc.time)
        );
    }
}

/// Most blocks of a `bench` case: the whole periodic search on 1000 blocks (the default's
/// largest case) takes 30 to 50 s per method on the 2-core machine, and grows as N^2 (the
/// periods to the regime grow with N).
const BENCH_MAX_BLOCKS: usize = 1000;

/// Most blocks x `--steps` of a `bench` case (1000 x 1000, the default's largest case).
const BENCH_MAX_BLOCK_STEPS: usize = 1_000_000;

/// Most `--periods` x blocks x `--steps` of one repetition of a `bench` case with `--periods`
/// (about a minute at the measured 40-60 ns per block-step; the periodic search on 1000
/// blocks integrates 8e8).
const BENCH_MAX_WORK: usize = 1_000_000_000;

/// Largest `--min-time` of `bench`, seconds (per case).
const BENCH_MAX_MIN_TIME: f64 = 600.0;

/// The range of `--amplitude`, `--mu-forward` and `--mu-backward` of `bench` (with k = 1): a
/// benchmark needs no other, and far outside it the runs fail (an amplitude of 1e308
/// overflows the positions; 1e100 against mu+ = 1e-300 exceeds the exact method's events).
const BENCH_VALUE_RANGE: [f64; 2] = [1e-6, 1e6];

/// Refuses, naming the flag, `bench` flags whose cases would not end within minutes (or at
/// all: a `--min-time` of NaN or infinity) or would mean nothing (`--periods 0`).
fn check_bench_flags(
    blocks: &[usize],
    steps: usize,
    min_time: f64,
    periods: Option<usize>,
) -> Result<(), Error> {
    if !(min_time.is_finite() && min_time > 0.0 && min_time <= BENCH_MAX_MIN_TIME) {
        return Err(Error::invalid(
            "--min-time",
            min_time,
            format!("must be a number of seconds in (0, {BENCH_MAX_MIN_TIME}]"),
        ));
    }
    let Some(&largest) = blocks.iter().max() else {
        return Err(Error::invalid("--blocks", "nothing", "give at least one N"));
    };
    if let Some(&nb) = blocks
        .iter()
        .find(|&&nb| !(2..=BENCH_MAX_BLOCKS).contains(&nb))
    {
        return Err(Error::invalid(
            "--blocks",
            nb,
            format!(
                "must be in 2..={BENCH_MAX_BLOCKS} (a case of more would run for hours: the \
                 periodic search grows as N^2)"
            ),
        ));
    }
    if steps == 0 || largest.saturating_mul(steps) > BENCH_MAX_BLOCK_STEPS {
        return Err(Error::invalid(
            "--steps",
            steps,
            format!(
                "must be at least 1, and at most {BENCH_MAX_BLOCK_STEPS} / N ({largest} blocks) \
                 so that a case ends within minutes"
            ),
        ));
    }
    if let Some(k) = periods {
        let work = k.saturating_mul(largest).saturating_mul(steps);
        if k == 0 || work > BENCH_MAX_WORK {
            return Err(Error::invalid(
                "--periods",
                k,
                format!(
                    "must be at least 1, and periods x blocks x steps ({largest} x {steps}) at \
                     most {BENCH_MAX_WORK:e} so that a repetition ends within about a minute"
                ),
            ));
        }
    }
    Ok(())
}

/// A library error of `bench` renamed after the flag that set the value (the library names
/// model-file fields such as `crawler.mu_forward[1]`).
fn bench_flags(e: Error) -> Error {
    rename_fields(
        e,
        &[
            ("crawler.mu_forward", "--mu-forward"),
            ("crawler.mu_backward", "--mu-backward"),
            ("crawler.blocks", "--blocks"),
            ("crawler", "--mu-forward, --mu-backward"),
            ("actuation.amplitude", "--amplitude"),
            ("actuation.phase_deg", "--phase-deg"),
            ("actuation", "--amplitude"),
            ("steps_per_period", "--steps"),
            ("periods", "--periods"),
        ],
    )
}

/// A library error of `simulate` renamed after the flag that set the value.
fn simulate_flags(e: Error) -> Error {
    rename_fields(
        e,
        &[
            ("steps_per_period", "--steps-per-period"),
            ("periods", "--periods"),
            ("max_periods", "--max-periods"),
            ("tol", "--tol"),
        ],
    )
}

/// `e` with the field of an [`Error::InvalidParameter`] renamed by `names` (`(field, flag)`;
/// a field matches itself and its indexed entries `field[i]`).
fn rename_fields(e: Error, names: &[(&str, &str)]) -> Error {
    match e {
        Error::InvalidParameter {
            field,
            value,
            reason,
        } => {
            let flag = names.iter().find(|(name, _)| {
                field
                    .strip_prefix(name)
                    .is_some_and(|rest| rest.is_empty() || rest.starts_with('['))
            });
            Error::InvalidParameter {
                field: flag.map_or(field, |(_, f)| f.to_string()),
                value,
                reason,
            }
        }
        other => other,
    }
}

struct BenchResult {
    disp: Option<f64>,
    periods: usize,
    converged: bool,
    us_per_step: f64,
    reps: usize,
}

/// Times one benchmark case, repeated until `min_time` has passed: either the whole periodic
/// search, or exactly `periods` plain periods from x = 0 (what the peers do).
fn bench_case(
    crawler: &Crawler,
    act: &Actuation,
    method: Method,
    steps: usize,
    periods: Option<usize>,
    min_time: f64,
) -> Result<BenchResult, Error> {
    let (n, nb) = (crawler.links(), crawler.blocks());
    let t0 = Instant::now();
    let mut reps = 0;
    loop {
        let r = match periods {
            Some(k) => {
                let mut map: Box<dyn PeriodMap> = match method {
                    Method::CatchingUp => Box::new(CatchingUp::new(crawler, act, steps)?),
                    Method::Exact => Box::new(ExactPwl::new(crawler, act, steps)?),
                };
                let (mut x, mut acc) = (vec![0.0; n], vec![0.0; nb]);
                for _ in 0..k {
                    acc.iter_mut().for_each(|a| *a = 0.0);
                    map.run_period(&mut x, &mut acc, None)?;
                }
                (Some(acc.iter().sum::<f64>() / nb as f64), k, false)
            }
            None => {
                let opts = SimOptions {
                    method,
                    steps_per_period: steps,
                    record_periods: 0,
                    ..SimOptions::default()
                };
                let sim = simulate(crawler, act, &opts)?;
                (
                    sim.displacement_per_period,
                    sim.periods_simulated,
                    sim.converged,
                )
            }
        };
        reps += 1;
        let wall = t0.elapsed().as_secs_f64();
        if wall >= min_time {
            return Ok(BenchResult {
                disp: r.0,
                periods: r.1,
                converged: r.2,
                us_per_step: 1e6 * wall / (reps * r.1 * steps) as f64,
                reps,
            });
        }
    }
}

/// The human form of an analysis. Parameters and the faces of C (sums of them) are shown
/// without snapping; computed forces (link ranges, vertices) at [`force_scale`].
fn print_analysis(c: &Crawler, a: &Analysis) {
    let force = force_scale(c);
    outln!("crawler: N = {} blocks, n = {} links", a.blocks, a.links);
    outln!("  stiffness k    = {}", list(c.stiffness(), 0.0));
    outln!("  mu_forward     = {}", list(c.mu_forward(), 0.0));
    outln!("  mu_backward    = {}", list(c.mu_backward(), 0.0));
    outln!("uniqueness condition (eq. 3.5):");
    match (&a.violating_subset, &a.uniqueness_undecided) {
        (Some(j), _) => outln!("  FAILS for J = {j:?}: the motion is not unique"),
        (None, Some(r)) => outln!("  undecided: {r}"),
        (None, None) => outln!(
            "  holds; margin {} (closest subset J = {:?})",
            num(a.uniqueness_margin.unwrap_or(f64::NAN), 0.0),
            a.closest_subset.clone().unwrap_or_default()
        ),
    }
    outln!("polytope C (F_b = x_(b-1) - x_b; facets marked *):");
    for f in &a.faces {
        let (rel, bound) = match f.sign {
            FaceSign::Forward => ("<=", num(f.offset, 0.0)),
            FaceSign::Backward => (">=", num(-f.offset, 0.0)),
        };
        outln!(
            "  {} block {:>3} {}: F_{} {rel} {bound}",
            if f.facet { "*" } else { " " },
            f.block,
            match f.sign {
                FaceSign::Forward => "+ (slides forward) ",
                FaceSign::Backward => "- (slides backward)",
            },
            f.block
        );
    }
    for (l, r) in a.link_force_ranges.iter().enumerate() {
        outln!(
            "  link {:>3}: x in [{}, {}]",
            l + 1,
            num(r[0], force),
            num(r[1], force)
        );
    }
    if let Some(v) = &a.vertices {
        outln!("  {} vertices:", v.len());
        for x in v {
            outln!("    {}", list(x, force));
        }
    }
    if let Some(class) = a.vm_class {
        outln!("displacement function v_m (exact):");
        outln!(
            "  class: {}",
            serde_json::to_string(&class)
                .expect("enum")
                .trim_matches('"')
        );
        outln!(
            "  moves forward: {}   moves backward: {}",
            a.moves_forward.unwrap_or(false),
            a.moves_backward.unwrap_or(false)
        );
    }
    if let Some(o) = &a.one_link {
        outln!(
            "one link (SPEC §9): C = [{}, {}], width w = {}",
            num(o.alpha, force),
            num(o.beta, force),
            num(o.width, force)
        );
        outln!(
            "  extension moves forward: {}   contraction moves forward: {}",
            o.extension_moves_forward,
            o.contraction_moves_forward
        );
        match (o.min_at_forward, o.min_at_backward) {
            (Some(m), _) => outln!(
                "  forward locomotion needs a*T > {} (rate bound x period)",
                num(m, force)
            ),
            (None, Some(m)) => outln!(
                "  no periodic gait moves it forward; backward locomotion needs a*T > {}",
                num(m, force)
            ),
            _ => outln!("  v_m is linear: no periodic gait moves it"),
        }
    }
}

/// The human form of a simulation of `act` on `crawler`: displacements at the scale of the
/// actuation's stroke (the largest range of an actuator length over a period), states at
/// [`force_scale`].
fn print_simulation(s: &Simulation, crawler: &Crawler, act: &Actuation, csv: Option<&PathBuf>) {
    let (_, knots) = act.knots(s.steps_per_period.clamp(2, 1024));
    let stroke = (0..act.links())
        .map(|l| {
            let (lo, hi) = knots
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                    (lo.min(r[l]), hi.max(r[l]))
                });
            hi - lo
        })
        .filter(|w| w.is_finite())
        .fold(0.0, f64::max);
    let force = force_scale(crawler);
    outln!(
        "method: {} ({} per period): {}",
        s.method,
        s.steps_per_period,
        s.actuation_model
    );
    match s.displacement_per_period {
        Some(d) => outln!("displacement per period: {}", num(d, stroke)),
        None => outln!(
            "displacement per period: not reached (last period: {})",
            num(s.last_period_displacement, stroke)
        ),
    }
    outln!(
        "periodic regime: {} after {} period(s) (residual {:.3e}, {})",
        if s.converged {
            "reached"
        } else {
            "NOT reached"
        },
        s.periods_to_converge.unwrap_or(s.periods_simulated),
        s.period_residual,
        match s.search {
            Search::Iteration => "plain iteration: the physical transient",
            Search::Anderson => "Anderson-accelerated search",
        }
    );
    outln!(
        "block displacement per period: {}",
        list(&s.block_displacement_per_period, stroke)
    );
    outln!(
        "state at the start of the periodic period: {}",
        list(&s.orbit_state, force)
    );
    if let Some(p) = csv {
        outln!("trajectory written to {}", p.display());
    }
}
