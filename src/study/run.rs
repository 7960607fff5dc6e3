//! Running the points of a sweep: each through the library (no subprocess), in parallel on a
//! rayon pool, one point per thread (HiGHS single-threaded inside, `optimal::solver`).

use super::settings::setting_error;
use super::spec::{Job, Point, SweepSpec};
use crate::api::{self, Hooks};
use crate::error::{Error, Result};
use crate::io::ProblemFile;
use crate::progress::Cancel;
use serde::Serialize;
use std::collections::BTreeSet;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// The numbers of one point (a row of the output table).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// The point's id ([`Point::id`]).
    pub point: usize,
    /// One value per axis.
    pub values: Vec<f64>,
    /// The job's objective: J of the optimum (optimize), J* of the one-link closed form
    /// (analyze, N = 2 with a `[gait]`); empty otherwise.
    pub objective: Option<f64>,
    /// The displacement per period: of the optimal gait, of the simulated periodic regime, or
    /// of the one-link closed-form optimum.
    pub displacement_per_period: Option<f64>,
    /// The method that ran: the optimiser's (`phase`, `discrete`, `local`, ...), the
    /// simulator's (`exact`, `catching-up`); empty for analyze.
    pub method: Option<String>,
    /// The certificate's kind (optimize: `global`, `global_k_phases` or `local`;
    /// `closed_form` for analyze of one link).
    pub certificate: Option<String>,
    /// The certificate's gap (optimize).
    pub gap: Option<f64>,
    /// The certificate's bound on J (optimize).
    pub bound: Option<f64>,
    /// The status: the optimiser's (`optimal`, `time_limit`, ...: what is proven), the
    /// simulation's (`converged`, `not_converged`), the class of v_m (analyze of a crawler),
    /// `well_posed` (analyze of a general problem), or `error`.
    pub status: String,
    /// The verdict of the necessary conditions on the optimum (`holds`, `fails`,
    /// `degenerate`) when the job certifies (`certify = true`).
    pub verdict: Option<String>,
    /// Wall time of the point, seconds.
    pub seconds: f64,
    /// The error of an ill-posed point (the message names the field).
    pub error: Option<String>,
}

impl Row {
    fn empty(point: &Point) -> Self {
        Row {
            point: point.id,
            values: point.values.clone(),
            objective: None,
            displacement_per_period: None,
            method: None,
            certificate: None,
            gap: None,
            bound: None,
            status: String::new(),
            verdict: None,
            seconds: 0.0,
            error: None,
        }
    }
}

/// A point's row and, when asked for, the job's whole result as JSON (the result file of
/// `optimize --json`, the analysis or the simulation).
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The row.
    pub row: Row,
    /// The full result (`None` for an error, or when not asked for).
    pub full: Option<serde_json::Value>,
}

/// Runs point `point` of `spec` on this thread; an ill-posed point gives a row with its error
/// (never an `Err`, never a panic: a panic inside the job becomes an error row too).
pub fn run_point(spec: &SweepSpec, point: &Point, full: bool, cancel: Option<&Cancel>) -> Outcome {
    let began = Instant::now();
    let mut row = Row::empty(point);
    let done = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        compute(spec, point, &mut row, full, cancel)
    }));
    let full = match done {
        Ok(Ok(v)) => v,
        Ok(Err(e)) => {
            row = Row::empty(point);
            row.status = "error".into();
            row.error = Some(setting_error(e).to_string());
            None
        }
        Err(panic) => {
            let msg = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            row = Row::empty(point);
            row.status = "error".into();
            row.error = Some(format!("internal error (please report it): {msg}"));
            None
        }
    };
    row.seconds = began.elapsed().as_secs_f64();
    Outcome { row, full }
}

fn to_json(v: &impl Serialize) -> Option<serde_json::Value> {
    serde_json::to_value(v).ok()
}

/// The serde name of a unit variant (a status, a verdict, a class).
fn word(v: &impl Serialize) -> Option<String> {
    to_json(v).and_then(|v| v.as_str().map(str::to_string))
}

/// A point's job on its problem, dispatched once on the job and the problem's kind: optimize
/// runs on either kind alike ([`optimize_point`]); analyze and simulate are each kind's own
/// call (a crawler's simulation options on a general problem, and the reverse, are refused).
fn compute(
    spec: &SweepSpec,
    point: &Point,
    row: &mut Row,
    full: bool,
    cancel: Option<&Cancel>,
) -> Result<Option<serde_json::Value>> {
    let file = spec.problem_at(point)?;
    match (&spec.job, &file) {
        (Job::Optimize(settings), _) => optimize_point(&file, settings, row, full, cancel),
        (Job::Analyze, ProblemFile::Crawler(model)) => {
            let a = api::analyze(model)?;
            row.status = match a.analysis.vm_class {
                Some(c) => word(&c).unwrap_or_default(),
                None => "not_unique".into(),
            };
            if let Some(o) = a.gait.as_ref().and_then(|g| g.one_link_optimum.as_ref()) {
                row.objective = Some(o.value);
                row.displacement_per_period = Some(o.displacement);
                row.certificate = Some("closed_form".into());
                row.gap = Some(0.0);
                row.bound = Some(o.value);
            }
            Ok(full.then(|| to_json(&a)).flatten())
        }
        (Job::Analyze, ProblemFile::General(general)) => {
            let a = api::analyze_general(general)?;
            if let Some(e) = a.failure {
                return Err(e);
            }
            row.status = "well_posed".into();
            Ok(full.then(|| to_json(&a)).flatten())
        }
        (Job::Simulate(options), ProblemFile::Crawler(model)) => {
            let crawler = model.crawler()?;
            let act = model.actuation(crawler.links())?;
            let mut options = options.clone();
            options.initial_state = model.simulation.initial_state.clone();
            let hooks = Hooks {
                events: None,
                cancel,
            };
            let sim = api::simulate(&crawler, &act, &options, hooks)?;
            row.displacement_per_period = sim.displacement_per_period;
            row.method = Some(options.method.to_string());
            row.status = converged(sim.converged);
            Ok(full.then(|| to_json(&sim)).flatten())
        }
        (Job::SimulateGeneral(options), ProblemFile::General(general)) => {
            let s = api::simulate_general(general, options)?;
            row.objective = s.simulation.objective;
            row.method = Some(s.method.into());
            row.status = converged(s.simulation.converged);
            Ok(full.then(|| to_json(&s)).flatten())
        }
        (Job::Simulate(_), ProblemFile::General(_)) => Err(Error::invalid(
            "job",
            "simulate",
            "the options of a crawler's simulation, on a general problem",
        )),
        (Job::SimulateGeneral(_), ProblemFile::Crawler(_)) => Err(Error::invalid(
            "job",
            "simulate",
            "the options of a general problem's simulation, on a crawler's model",
        )),
    }
}

/// A simulation's status word.
fn converged(yes: bool) -> String {
    if yes { "converged" } else { "not_converged" }.into()
}

/// A point of an optimize sweep, of either kind: the one optimisation of a problem file
/// ([`api::optimize_file`], as `crawlopt optimize` runs it) and its row, read from the result's
/// envelope, the same for every method and both kinds: `J`, the method, the certificate's
/// kind (`global`, `global_k_phases` or `local`), gap, bound and status (what was proven), the
/// verdict when certified, and a crawler's displacement per period.
fn optimize_point(
    file: &ProblemFile,
    settings: &api::OptimizeSettings,
    row: &mut Row,
    full: bool,
    cancel: Option<&Cancel>,
) -> Result<Option<serde_json::Value>> {
    let hooks = Hooks {
        events: None,
        cancel,
    };
    let done = api::optimize_file(file, settings, hooks)?;
    let r = &done.result;
    let (head, c) = (r.head(), &r.head().certificate);
    row.objective = Some(head.objective);
    row.displacement_per_period = r.displacement_per_period();
    row.method = Some(head.method.clone());
    row.certificate = Some(c.kind.clone());
    row.gap = c.gap;
    row.bound = c.bound;
    row.status = head.status.as_str().into();
    row.verdict = r.verdict().and_then(|v| word(&v));
    Ok(full.then(|| to_json(&done)).flatten())
}

/// A deterministic share of a sweep's points: shard `index` of `count` (1-based) holds the
/// points whose id is `index - 1` modulo `count` (so every shard gets points from the whole
/// grid, and cheap and dear regions are spread).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// 1..=count.
    pub index: usize,
    /// The number of shards.
    pub count: usize,
}

impl Shard {
    /// `I/N` with 1 <= I <= N (errors name `shard`).
    pub fn parse(s: &str) -> Result<Self> {
        let bad = || Error::invalid("shard", s, "must be I/N with 1 <= I <= N, e.g. 2/8");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count): (usize, usize) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        let shard = Shard { index, count };
        shard.check()?;
        Ok(shard)
    }

    /// Checks 1 <= index <= count.
    pub fn check(&self) -> Result<()> {
        if self.count == 0 || self.index == 0 || self.index > self.count {
            return Err(Error::invalid(
                "shard",
                format!("{}/{}", self.index, self.count),
                "must be I/N with 1 <= I <= N, e.g. 2/8",
            ));
        }
        Ok(())
    }

    /// The shard holding point `id`.
    pub fn of(id: usize, count: usize) -> Self {
        Shard {
            index: id % count + 1,
            count,
        }
    }

    /// Whether point `id` belongs to this shard.
    pub fn holds(&self, id: usize) -> bool {
        id % self.count == self.index - 1
    }
}

/// Most worker threads a sweep may be asked for ([`SweepSettings::threads`]): more is a
/// mistake (a sweep never runs more threads than points or cores anyway).
pub const MAX_THREADS: usize = 4096;

/// How a sweep runs.
#[derive(Clone, Debug, Default)]
pub struct SweepSettings {
    /// Worker threads asked for, one point each (0: one per core, the default). A sweep runs
    /// at most one thread per point to do and per core ([`SweepSettings::threads_for`]);
    /// more than [`MAX_THREADS`] is refused.
    pub threads: usize,
    /// Run only this share of the points (default all).
    pub shard: Option<Shard>,
    /// Points not to run (already in the output: `--resume`).
    pub skip: BTreeSet<usize>,
    /// Keep each point's full result JSON ([`Outcome::full`]).
    pub full_results: bool,
    /// Tripped to stop: no new point starts, and running ones stop at their next check.
    pub cancel: Option<Cancel>,
}

impl SweepSettings {
    /// Refuses what no sweep runs with: more than [`MAX_THREADS`] threads (field `threads`),
    /// a shard outside `1..=count`.
    pub fn check(&self) -> Result<()> {
        if self.threads > MAX_THREADS {
            return Err(Error::invalid(
                "threads",
                self.threads,
                format!(
                    "must be at most {MAX_THREADS} (0: one per core; a sweep runs at most one \
                     thread per point and per core)"
                ),
            ));
        }
        if let Some(s) = self.shard {
            s.check()?;
        }
        Ok(())
    }

    /// The threads that run `points` points: the number asked for (all cores for 0), but
    /// never more than the points or the cores (`std::thread::available_parallelism`), and at
    /// least one. Each point is single-threaded (HiGHS with one thread), so more threads than
    /// cores only share them, and more than points stay idle.
    pub fn threads_for(&self, points: usize) -> usize {
        let cores = std::thread::available_parallelism().map_or(1, usize::from);
        let asked = if self.threads == 0 {
            cores
        } else {
            self.threads
        };
        asked.min(cores).min(points).max(1)
    }
}

/// Progress of a running sweep, sent with each finished point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepProgress {
    /// Points finished in this run.
    pub done: usize,
    /// Points this run has to do.
    pub total: usize,
    /// Seconds since the run began.
    pub elapsed: f64,
    /// Estimated seconds left (elapsed per finished point times the points left).
    pub eta: f64,
}

/// What a sweep run did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SweepSummary {
    /// Points of the whole sweep.
    pub points: usize,
    /// Points of this run's share.
    pub in_share: usize,
    /// Of them, already done (skipped).
    pub skipped: usize,
    /// Computed now.
    pub computed: usize,
    /// Of them, rows with an error.
    pub errors: usize,
    /// Wall time, seconds.
    pub seconds: f64,
}

/// Runs the points of `spec` (this shard's, less those to skip) in parallel under `settings`.
/// `on_point` is called with each outcome as it finishes (from the worker threads, one at a
/// time is up to the caller: it should write and flush the row). Errors: a thread pool that
/// cannot start, or cancellation (`Error::Cancelled`, after the running points stopped).
pub fn run(
    spec: &SweepSpec,
    settings: &SweepSettings,
    on_point: &(dyn Fn(Outcome, SweepProgress) + Sync),
) -> Result<SweepSummary> {
    let began = Instant::now();
    let n = spec.len()?;
    settings.check()?;
    let in_share: Vec<usize> = (0..n)
        .filter(|&id| settings.shard.is_none_or(|s| s.holds(id)))
        .collect();
    let todo: Vec<usize> = in_share
        .iter()
        .copied()
        .filter(|id| !settings.skip.contains(id))
        .collect();
    let total = todo.len();
    let (done, errors) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let threads = settings.threads_for(total);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::invalid("threads", threads, e.to_string()))?;
    let cancel = settings.cancel.as_ref();
    pool.install(|| {
        use rayon::prelude::*;
        todo.par_iter().with_max_len(1).for_each(|&id| {
            if cancel.is_some_and(Cancel::is_cancelled) {
                return;
            }
            let out = run_point(spec, &spec.point(id), settings.full_results, cancel);
            // A point stopped by cancellation is not a result.
            if cancel.is_some_and(Cancel::is_cancelled)
                && out.row.error.as_deref() == Some(&Error::Cancelled.to_string())
            {
                return;
            }
            if out.row.error.is_some() {
                errors.fetch_add(1, Ordering::SeqCst);
            }
            let k = done.fetch_add(1, Ordering::SeqCst) + 1;
            let elapsed = began.elapsed().as_secs_f64();
            let eta = elapsed / k as f64 * (total - k) as f64;
            on_point(
                out,
                SweepProgress {
                    done: k,
                    total,
                    elapsed,
                    eta,
                },
            );
        });
    });
    if cancel.is_some_and(Cancel::is_cancelled) {
        return Err(Error::Cancelled);
    }
    Ok(SweepSummary {
        points: n,
        in_share: in_share.len(),
        skipped: in_share.len() - total,
        computed: done.into_inner(),
        errors: errors.into_inner(),
        seconds: began.elapsed().as_secs_f64(),
    })
}
