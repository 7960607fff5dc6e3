//! `crawlopt sweep`: a parameter study ([`crawlopt::study`]): the sweep file parsed, the
//! output opened (resumed), one call of [`crawlopt::study::run`] writing each row as it
//! finishes, a progress bar with ETA; `crawlopt sweep merge` joins the tables of shards.

use crate::output::{json_line, outln};
use clap::{Args, Subcommand};
use crawlopt::api;
use crawlopt::present::{self, write_figures};
use crawlopt::study::{self, Format, Shard, SweepSettings, SweepSpec, TableWriter};
use crawlopt::Error;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    pub command: Option<SweepCommand>,
    #[command(flatten)]
    pub run: RunArgs,
}

#[derive(Subcommand)]
pub enum SweepCommand {
    /// Join the tables of the shards of a sweep (--shard I/N runs) into one, sorted by point;
    /// every point must be present exactly once, else the missing shards and points are named
    /// (exit 2, nothing written).
    Merge(MergeArgs),
}

#[derive(Args)]
pub struct RunArgs {
    /// Sweep file (TOML): base model, job, settings, axes (see the README).
    #[arg(required = true)]
    pub file: Option<PathBuf>,
    /// Worker threads, one point each (default: one per core); at most one per point and per
    /// core run, more than 4096 is refused.
    #[arg(short = 'j', long = "jobs", default_value_t = 0)]
    pub jobs: usize,
    /// The table: CSV, or JSON Lines for .jsonl; rows appended and flushed as each point
    /// finishes (default: standard output).
    #[arg(short = 'o', long)]
    pub output: Option<PathBuf>,
    /// Continue the table of -o: the points already in it are skipped.
    #[arg(long, requires = "output")]
    pub resume: bool,
    /// Run a deterministic share of the points: shard I of N holds the points whose id is
    /// I-1 modulo N (for job arrays).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Rows as JSON Lines on standard output (without -o); with -o the summary as JSON.
    #[arg(long)]
    pub json: bool,
    /// Also write each point's full result as DIR/point-ID.json.
    #[arg(long, value_name = "DIR")]
    pub results: Option<PathBuf>,
    /// Write the figures of the table (SVG and PNG) into this directory: the value against
    /// the second axis (a line per value of the first), the heat map over both.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

#[derive(Args)]
pub struct MergeArgs {
    /// The sweep file the shards ran.
    pub file: PathBuf,
    /// The shards' tables.
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// The number of shards N (to name the shards with missing points).
    #[arg(long, default_value_t = 1)]
    pub shards: usize,
    /// The merged table (CSV, or JSON Lines for .jsonl).
    #[arg(short = 'o', long)]
    pub output: PathBuf,
}

pub fn run(a: SweepArgs) -> Result<ExitCode, Error> {
    match a.command {
        Some(SweepCommand::Merge(m)) => merge(m),
        None => run_sweep(a.run),
    }
}

fn run_sweep(a: RunArgs) -> Result<ExitCode, Error> {
    let file = a.file.as_ref().expect("required by clap");
    let spec = SweepSpec::load(file)?;
    let mut settings = settings_of(&a)?;
    let format = if a.json {
        Format::JsonLines
    } else {
        Format::Csv
    };
    let (writer, skip) = TableWriter::open(&spec, a.output.as_deref(), format, a.resume)?;
    settings.skip = skip;
    let writer = Mutex::new(writer);
    let rows = Mutex::new(Vec::new());
    let failed: Mutex<Option<Error>> = Mutex::new(None);
    let bar = progress_bar();
    let on_point = |out: study::Outcome, p: study::SweepProgress| {
        let mut result = writer.lock().map_err(|_| ()).and_then(|mut w| {
            w.write(&out.row).map_err(|e| {
                *failed.lock().expect("not poisoned") = Some(e);
            })
        });
        if let (Ok(()), Some(dir), Some(full)) = (&result, &a.results, &out.full) {
            if let Err(e) = study::write_full(dir, out.row.point, full) {
                *failed.lock().expect("not poisoned") = Some(e);
                result = Err(());
            }
        }
        if result.is_err() {
            if let Some(c) = &settings.cancel {
                c.cancel();
            }
        }
        if a.plot.is_some() && a.output.is_none() {
            rows.lock().expect("not poisoned").push(out.row.clone());
        }
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(format!("{:.0} s", p.eta));
    };
    let done = study::run(&spec, &settings, &on_point);
    bar.finish_and_clear();
    if let Some(e) = failed.into_inner().expect("not poisoned") {
        return Err(e);
    }
    let rows = rows.into_inner().expect("not poisoned");
    summarise(&a, &spec, &done?, rows)?;
    Ok(ExitCode::SUCCESS)
}

/// The sweep's settings of the flags, checked before the output is opened (a resumed table is
/// trimmed when opened): the shard, the results and figure directories, the threads.
fn settings_of(a: &RunArgs) -> Result<SweepSettings, Error> {
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    if let Some(dir) = &a.results {
        if !dir.is_dir() {
            return Err(Error::invalid(
                "--results",
                dir.display(),
                "must be an existing directory",
            ));
        }
    }
    if let Some(dir) = &a.plot {
        present::check_figure_dir(dir)?;
    }
    let settings = SweepSettings {
        threads: a.jobs,
        shard,
        skip: Default::default(),
        full_results: a.results.is_some(),
        cancel: Some(Default::default()),
    };
    settings
        .check()
        .map_err(|e| api::rename_fields(e, &[("threads", "--jobs".to_string())]))?;
    Ok(settings)
}

/// The progress bar of the points, with the run's ETA as its message.
fn progress_bar() -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:30} {pos}/{len} points [{elapsed_precise}, ETA {msg}]",
        )
        .expect("valid template"),
    );
    bar
}

/// The run's summary line (on stdout with a table file, else on stderr), then its figures
/// when asked, drawn from the table file or from `rows`, the rows kept in memory.
fn summarise(
    a: &RunArgs,
    spec: &SweepSpec,
    s: &study::SweepSummary,
    rows: Vec<study::Row>,
) -> Result<(), Error> {
    let wrote = a
        .output
        .as_ref()
        .map_or(String::new(), |p| format!("; table {}", p.display()));
    let line = format!(
        "{} points (this share {}): {} computed ({} with an error), {} already done, {:.2} s{wrote}",
        s.points, s.in_share, s.computed, s.errors, s.skipped, s.seconds
    );
    match (&a.output, a.json) {
        (Some(_), true) => json_line(s),
        (Some(_), false) => outln(&line),
        (None, _) => eprintln!("{line}"),
    }
    if let Some(dir) = &a.plot {
        let rows = match &a.output {
            Some(path) => study::read_table(path, &study::header(spec))?.0,
            None => rows,
        };
        let axes: Vec<String> = spec.axes.iter().map(|x| x.field.clone()).collect();
        for p in write_figures(dir, &study::figures(&axes, &rows)?)? {
            let msg = format!("wrote {}", p.display());
            match (&a.output, a.json) {
                (Some(_), false) => outln(&msg),
                _ => eprintln!("{msg}"),
            }
        }
    }
    Ok(())
}

fn merge(m: MergeArgs) -> Result<ExitCode, Error> {
    let spec = SweepSpec::load(&m.file)?;
    match study::merge(&spec, &m.inputs, m.shards)? {
        Ok(rows) => {
            study::write_table(&spec, &rows, &m.output)?;
            outln(&format!(
                "merged {} points from {} tables into {}",
                rows.len(),
                m.inputs.len(),
                m.output.display()
            ));
            Ok(ExitCode::SUCCESS)
        }
        Err(problems) => {
            for l in problems.lines(m.shards) {
                eprintln!("error: {l}");
            }
            eprintln!(
                "error: not merged: every point of the sweep must be present exactly once \
                 (nothing written to {})",
                m.output.display()
            );
            Ok(ExitCode::from(2))
        }
    }
}
