//! `bench`: the simulation cost per time step on a travelling sine gait
//! `L_l = A sin(2 pi t - l phi)`, k = 1, uniform friction, for several numbers of blocks.

use super::settings::{rename_fields, Naming};
use crate::error::{Error, Result};
use crate::integrate::{
    simulate, Actuation, CatchingUp, ExactPwl, Method, PeriodMap, SimOptions, Waveform,
};
use crate::model::Crawler;
use serde::Serialize;
use std::time::Instant;

/// Largest number of blocks of a case with `periods` (a fixed number of periods from rest).
pub const BENCH_MAX_BLOCKS: usize = 100_000;

/// Largest number of blocks of an exact-method case that searches for the periodic regime
/// (beyond it only catching-up is searched): the Newton-Krylov search's period evaluations do
/// not grow with N, but the exact method's period does faster than N (its events): 10^4 blocks
/// took 3.5 s (catching-up) and 11 s (exact) on the loaded 2-core machine, 10^5 blocks on 250
/// steps 4.8 s with catching-up, and one exact period alone 131 s.
pub const BENCH_MAX_EXACT_SEARCH_BLOCKS: usize = 10_000;

/// Largest number of blocks of a case that searches with Anderson acceleration alone
/// ([`BenchSettings::newton`] off): the search on 1000 blocks takes 20 to 50 s per method on
/// the 2-core machine, and grows as N^2 (its periods grow with N).
pub const BENCH_MAX_ANDERSON_BLOCKS: usize = 1000;

/// Most blocks x `steps` of a case: the sampled increments of catching-up, 8 bytes each
/// (the limit of `crawlopt simulate`, 2.5e7).
pub const BENCH_MAX_BLOCK_STEPS: usize = 25_000_000;

/// Most `periods` x blocks x `steps` of one repetition of a case with `periods` (about a
/// minute at the measured 40-60 ns per block-step; the periodic search on 1000 blocks
/// integrates 8e8).
pub const BENCH_MAX_WORK: usize = 1_000_000_000;

/// Largest `min_time`, seconds (per case).
pub const BENCH_MAX_MIN_TIME: f64 = 600.0;

/// The range of `amplitude`, `mu_forward` and `mu_backward` (with k = 1): a benchmark needs no
/// other, and far outside it the runs fail (an amplitude of 1e308 overflows the positions;
/// 1e100 against mu+ = 1e-300 exceeds the exact method's events).
pub const BENCH_VALUE_RANGE: [f64; 2] = [1e-6, 1e6];

/// The cases of a benchmark. Defaults as `crawlopt bench`.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchSettings {
    /// Numbers of blocks (default 3, 10, 100, 1000).
    pub blocks: Vec<usize>,
    /// Time steps per period (default 1000).
    pub steps: usize,
    /// Amplitude A (default 2).
    pub amplitude: f64,
    /// Phase lag phi between consecutive links, degrees (default 90).
    pub phase_deg: f64,
    /// mu^+ on every block (default 1).
    pub mu_forward: f64,
    /// mu^- on every block (default 3.3).
    pub mu_backward: f64,
    /// Minimum measured time per case, seconds (default 1).
    pub min_time: f64,
    /// Integrate exactly this many periods from x = 0 (plain iteration, as a peer would)
    /// instead of searching for the periodic regime.
    pub periods: Option<usize>,
    /// Search with Newton-Krylov steps (default `true`); `false`: Anderson acceleration alone,
    /// the search before issue 15, for comparison.
    pub newton: bool,
    /// How messages name the settings.
    pub naming: Naming,
}

impl Default for BenchSettings {
    fn default() -> Self {
        BenchSettings {
            blocks: vec![3, 10, 100, 1000],
            steps: 1000,
            amplitude: 2.0,
            phase_deg: 90.0,
            mu_forward: 1.0,
            mu_backward: 3.3,
            min_time: 1.0,
            periods: None,
            newton: true,
            naming: Naming::Keywords,
        }
    }
}

/// One measured case.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchCase {
    /// Blocks.
    #[serde(rename = "N")]
    pub blocks: usize,
    /// The integrator.
    pub method: String,
    /// Steps per period.
    pub steps_per_period: usize,
    /// Displacement per period (`None`: the periodic regime was not reached).
    pub disp_per_period: Option<f64>,
    /// Periods integrated per repetition (plain period evaluations).
    pub periods: usize,
    /// Jacobian-vector products of the period map per repetition (the Newton-Krylov search's
    /// tangent period evaluations, each cheaper than a period: no projection).
    pub tangent_products: usize,
    /// Whether the periodic regime was reached.
    pub converged: bool,
    /// Whether a fixed number of periods was integrated.
    pub fixed_periods: bool,
    /// Wall time per time step, microseconds: the whole wall time (tangent products included)
    /// over the plain periods' steps.
    pub us_per_step: f64,
    /// Links x steps per second.
    pub link_steps_per_s: f64,
    /// Repetitions timed.
    pub repetitions: usize,
    /// Wall time of one repetition, seconds: the time to the answer (the whole periodic search,
    /// or the fixed periods).
    pub seconds: f64,
}

impl BenchSettings {
    /// Refuses, naming the setting, cases that would not end within minutes (or at all: a
    /// `min_time` of NaN or infinity) or would mean nothing (`periods = 0`).
    pub fn check(&self) -> Result<()> {
        let n = |s: &str| self.naming.setting(s);
        let min_time = self.min_time;
        if !(min_time.is_finite() && min_time > 0.0 && min_time <= BENCH_MAX_MIN_TIME) {
            return Err(Error::invalid(
                n("min_time"),
                min_time,
                format!("must be a number of seconds in (0, {BENCH_MAX_MIN_TIME}]"),
            ));
        }
        let Some(&largest) = self.blocks.iter().max() else {
            return Err(Error::invalid(
                n("blocks"),
                "nothing",
                "give at least one N",
            ));
        };
        if let Some(&nb) = self
            .blocks
            .iter()
            .find(|&&nb| !(2..=BENCH_MAX_BLOCKS).contains(&nb))
        {
            return Err(Error::invalid(
                n("blocks"),
                nb,
                format!("must be in 2..={BENCH_MAX_BLOCKS}"),
            ));
        }
        let max_search = BENCH_MAX_ANDERSON_BLOCKS;
        if self.periods.is_none() && !self.newton && largest > max_search {
            return Err(Error::invalid(
                n("blocks"),
                largest,
                format!(
                    "must be at most {max_search} without {} {}: the search for the periodic \
                     regime would run for hours; give a number of periods",
                    n("periods"),
                    match self.naming {
                        Naming::Flags => "with --no-newton",
                        Naming::Keywords => "with newton = false",
                    }
                ),
            ));
        }
        let steps = self.steps;
        if steps == 0 || largest.saturating_mul(steps) > BENCH_MAX_BLOCK_STEPS {
            return Err(Error::invalid(
                n("steps"),
                steps,
                format!(
                    "must be at least 1, and at most {BENCH_MAX_BLOCK_STEPS} / N ({largest} \
                     blocks): the increments of a period are held in memory"
                ),
            ));
        }
        if let Some(k) = self.periods {
            let work = k.saturating_mul(largest).saturating_mul(steps);
            if k == 0 || work > BENCH_MAX_WORK {
                return Err(Error::invalid(
                    n("periods"),
                    k,
                    format!(
                        "must be at least 1, and periods x blocks x steps ({largest} x {steps}) \
                         at most {BENCH_MAX_WORK:e} so that a repetition ends within about a \
                         minute"
                    ),
                ));
            }
        }
        for (name, v) in [
            ("amplitude", self.amplitude),
            ("mu_forward", self.mu_forward),
            ("mu_backward", self.mu_backward),
        ] {
            if !(BENCH_VALUE_RANGE[0]..=BENCH_VALUE_RANGE[1]).contains(&v) {
                return Err(Error::invalid(
                    n(name),
                    v,
                    format!(
                        "must be in [{:e}, {:e}] (k = 1: a benchmark needs no other scale)",
                        BENCH_VALUE_RANGE[0], BENCH_VALUE_RANGE[1]
                    ),
                ));
            }
        }
        if !self.phase_deg.is_finite() {
            return Err(Error::invalid(
                n("phase_deg"),
                self.phase_deg,
                "must be finite",
            ));
        }
        Ok(())
    }

    /// A library error renamed after the setting that set the value (the library names
    /// model-file fields such as `crawler.mu_forward[1]`).
    fn named(&self, e: Error) -> Error {
        let n = |s: &str| self.naming.setting(s);
        let names = [
            ("crawler.mu_forward", n("mu_forward")),
            ("crawler.mu_backward", n("mu_backward")),
            ("crawler.blocks", n("blocks")),
            (
                "crawler",
                format!("{}, {}", n("mu_forward"), n("mu_backward")),
            ),
            ("actuation.amplitude", n("amplitude")),
            ("actuation.phase_deg", n("phase_deg")),
            ("actuation", n("amplitude")),
            ("steps_per_period", n("steps")),
            ("periods", n("periods")),
        ];
        rename_fields(e, &names)
    }
}

/// Runs the benchmark: every crawler is built and checked before the first case is timed;
/// `on_case` receives each case as it is measured (catching-up, then exact, per N; a search
/// beyond `BENCH_MAX_EXACT_SEARCH_BLOCKS` blocks is catching-up's only).
pub fn bench(settings: &BenchSettings, on_case: &mut dyn FnMut(&BenchCase)) -> Result<()> {
    settings.check()?;
    let s = settings;
    let mut cases = Vec::with_capacity(s.blocks.len());
    for &nb in &s.blocks {
        let crawler =
            Crawler::uniform(nb, 1.0, s.mu_forward, s.mu_backward).map_err(|e| s.named(e))?;
        crawler.require_unique().map_err(|e| {
            let n = |x: &str| s.naming.setting(x);
            Error::invalid(
                format!("{}, {}", n("mu_forward"), n("mu_backward")),
                format!("{}, {}", s.mu_forward, s.mu_backward),
                format!("with {} {nb}: {e}", n("blocks")),
            )
        })?;
        let links = crawler.links();
        let act = Actuation::wave(
            Waveform::Sine,
            1.0,
            vec![0.0; links],
            vec![s.amplitude; links],
            (0..links).map(|l| l as f64 * s.phase_deg).collect(),
        )
        .map_err(|e| s.named(e))?;
        cases.push((crawler, act));
    }
    for (crawler, act) in &cases {
        for method in [Method::CatchingUp, Method::Exact] {
            if method == Method::Exact
                && s.periods.is_none()
                && crawler.blocks() > BENCH_MAX_EXACT_SEARCH_BLOCKS
            {
                continue;
            }
            let case = bench_case(crawler, act, method, s, s.min_time).map_err(|e| s.named(e))?;
            on_case(&case);
        }
    }
    Ok(())
}

/// Times one case, repeated until `min_time` has passed: either the whole periodic search, or
/// exactly `periods` plain periods from x = 0 (what the peers do).
fn bench_case(
    crawler: &Crawler,
    act: &Actuation,
    method: Method,
    s: &BenchSettings,
    min_time: f64,
) -> Result<BenchCase> {
    let (steps, periods) = (s.steps, s.periods);
    let (n, nb) = (crawler.links(), crawler.blocks());
    let t0 = Instant::now();
    let mut reps = 0;
    loop {
        crate::progress::check()?;
        let (disp, done, products, converged) = match periods {
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
                (Some(acc.iter().sum::<f64>() / nb as f64), k, 0, false)
            }
            None => {
                let opts = SimOptions {
                    method,
                    steps_per_period: steps,
                    record_periods: 0,
                    newton: if s.newton {
                        SimOptions::DEFAULT.newton
                    } else {
                        None
                    },
                    ..SimOptions::default()
                };
                let sim = simulate(crawler, act, &opts)?;
                (
                    sim.displacement_per_period,
                    sim.periods_simulated,
                    sim.tangent_products,
                    sim.converged,
                )
            }
        };
        reps += 1;
        let wall = t0.elapsed().as_secs_f64();
        if wall >= min_time {
            let us_per_step = 1e6 * wall / (reps * done * steps) as f64;
            return Ok(BenchCase {
                blocks: nb,
                method: method.to_string(),
                steps_per_period: steps,
                disp_per_period: disp,
                periods: done,
                tangent_products: products,
                converged,
                fixed_periods: periods.is_some(),
                us_per_step,
                link_steps_per_s: us_per_step.recip() * 1e6 * n as f64,
                repetitions: reps,
                seconds: wall / reps as f64,
            });
        }
    }
}
