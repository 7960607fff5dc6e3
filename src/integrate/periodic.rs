//! The periodic regime (theory §4): the limit cycle of the period map and its displacement.
//!
//! For `T`-periodic actuation the state converges to a periodic orbit (refs [Kre], [CGV]), often
//! only geometrically: the slowest mode of a long chain contracts by a factor close to 1 per
//! period (0.997 for 100 blocks under a travelling sine wave). The search therefore first
//! iterates the period map as the crawler would (the count is then the physical transient), and
//! if that has not converged after [`SimOptions::accelerate_after`] periods it switches to
//! Newton-Krylov steps on `G(x) - x` (see [`super::newton`] for why the iterations then do not
//! grow with N; the exact method, which has no tangent map, takes the Jacobian of catching-up on
//! the same knots), safeguarded by Anderson acceleration of the fixed-point problem `G(x) = x`
//! (mixing the residual preconditioned by the chain's diffusion,
//! [`NewtonOptions::precondition_anderson`], once a Newton step failed), every proposed state
//! projected onto C. Either way a displacement is reported only for a period actually integrated from a
//! state `x` with `|G(x) - x|_inf <= tol * s`, `s` the size of C: acceleration only chooses where to look.

use super::newton::{newton_step, Diffusion, NewtonOptions};
use super::Actuation;
use super::{CatchingUp, ExactPwl, IncrementStorage, Method, PeriodMap, Recorder, Trajectory};
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::sweep::Projector;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::collections::VecDeque;

/// Memory of the Anderson acceleration. Measured on the travelling sine gait (k = 1, mu+ = 1,
/// mu- = 3.3, 1000 catching-up steps): 100 blocks need 197 / 112 / 73 / 71 periods with memory
/// 4 / 8 / 16 / 30, and 1000 blocks 1326 / 917 / 763 with memory 8 / 16 / 30. A least-squares
/// problem of `n x 30` per period is negligible beside the period itself.
const ANDERSON_MEMORY: usize = 30;

/// Largest number of sampled increments (steps per period times links) of catching-up, and of
/// knot lengths of the exact method's interpolant of a smooth actuation: their tables take 16
/// (catching-up) to about 40 (exact) bytes per value, 0.4 to 1 GB.
pub const MAX_SAMPLES: f64 = 2.5e7;
/// Largest `--steps-per-period` (steps of catching-up, knots of the exact method's interpolant
/// of a smooth actuation), whatever the number of links: the exact method's knot table takes
/// about 90 bytes per knot for one or two links.
pub const MAX_STEPS_PER_PERIOD: usize = 10_000_000;
/// Largest number of values in a recorded trajectory, counted as `3 N` per sample (time,
/// states, positions, barycentre and slips): about 400 MB, and several times that as the CSV
/// or JSON text written from it.
pub const MAX_RECORDED: f64 = 5e7;

/// The earliest period after which the search may switch to acceleration before
/// [`SimOptions::accelerate_after`] (when plain iteration is predicted not to converge in time).
/// Five plain periods are enough for the Newton step of the bench gait (N = 100 to 3000: one
/// step of 16 to 19 products lands on the orbit from the sixth period).
pub const EARLY_SWITCH_MIN: usize = 5;

/// Options of [`simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Integration method.
    pub method: Method,
    /// Steps per period (catching-up) or knots of the interpolant of a smooth actuation (exact).
    pub steps_per_period: usize,
    /// Periods recorded on the periodic orbit (0: record nothing).
    pub record_periods: usize,
    /// Give up the search for the periodic regime after this many period integrations.
    pub max_periods: usize,
    /// The state repeats when `max_l |x_l(kT) - x_l((k-1)T)| <= tol * s`, `s` the size of C
    /// ([`Crawler::state_scale`]); in `(0, MAX_TOL]` (default `1e-12`).
    pub tol: f64,
    /// Switch from plain iteration to the accelerated search (Newton-Krylov or Anderson) after
    /// this many periods, or from period [`EARLY_SWITCH_MIN`] on as soon as the contraction of the
    /// last plain period predicts that plain iteration would not converge within them (a long
    /// chain's plain transient runs for `O(N^2)` periods). `None`: never, the search is then the
    /// physical transient.
    pub accelerate_after: Option<usize>,
    /// Newton-Krylov steps in the accelerated search, safeguarded by Anderson (`None`: Anderson
    /// alone). The exact method takes the Jacobian of catching-up on its knots (when they fit
    /// `MAX_SAMPLES`; else Anderson alone). Default [`NewtonOptions::DEFAULT`].
    pub newton: Option<NewtonOptions>,
    /// Initial state `x(0)` (default 0, the unloaded crawler).
    pub initial_state: Option<Vec<f64>>,
    /// Catching-up keeps the period's increments `K (L^{i+1} - L^i)` as a table (8 bytes per
    /// link and step) when it fits in this many bytes, and forms them step by step from the
    /// actuation otherwise (memory `O(N)`, a slower step; bitwise the same results). Default
    /// [`IncrementStorage::DEFAULT_BUDGET`] (64 MiB). A table is refused beyond
    /// `MAX_SAMPLES` increments.
    pub increment_budget: usize,
}

impl SimOptions {
    /// The defaults (also those of `crawlopt simulate`'s flags and Python's `simulate`).
    pub const DEFAULT: SimOptions = SimOptions {
        method: Method::Exact,
        steps_per_period: 1000,
        record_periods: 1,
        max_periods: 5000,
        tol: 1e-12,
        accelerate_after: Some(50),
        newton: Some(NewtonOptions::DEFAULT),
        initial_state: None,
        increment_budget: IncrementStorage::DEFAULT_BUDGET,
    };
}

/// The largest [`SimOptions::tol`]: the periodic regime is declared when the state changes by at
/// most `tol` times the size of C over a period, so `tol` is a relative error of the state on
/// the orbit. Beyond `1e-3` the test passes before the transient has decayed (`tol = 0.5` on
/// `three_blocks_sine.toml` accepted the first period, `J = 1.833` against the orbit's 1.914,
/// with unequal block displacements): it would report a transient as the periodic regime.
pub const MAX_TOL: f64 = 1e-3;

/// Refuses a periodicity tolerance outside `(0, MAX_TOL]` (shared by the crawler's and the
/// general problems' simulators, whose convergence tests have the same meaning).
pub fn check_tol(tol: f64) -> Result<()> {
    if !(tol > 0.0 && tol <= MAX_TOL) {
        return Err(Error::invalid(
            "tol",
            tol,
            format!(
                "must be in (0, {MAX_TOL:e}]: a relative change of the state over a period \
                 (a larger one would take a transient for the periodic regime)"
            ),
        ));
    }
    Ok(())
}

impl SimOptions {
    /// Refuses, whatever the crawler and the actuation, a value no simulation runs with:
    /// `steps_per_period` beyond `MAX_STEPS_PER_PERIOD`, `max_periods` 0, a `tol` outside
    /// `(0, MAX_TOL]` ([`check_tol`]) (the checks of [`simulate`], made before any work: a sweep
    /// makes them when it reads its file). A `steps_per_period` of 0 is refused where the grid
    /// is used ([`SimOptions::check_steps`]): the exact method on a piecewise-linear actuation
    /// takes none.
    pub fn check(&self) -> Result<()> {
        if self.steps_per_period > MAX_STEPS_PER_PERIOD {
            return self.check_steps();
        }
        if self.max_periods == 0 {
            return Err(Error::invalid("max_periods", 0, "must be at least 1"));
        }
        check_tol(self.tol)
    }

    /// Refuses a `steps_per_period` outside `1..=MAX_STEPS_PER_PERIOD`, for a simulation that
    /// steps on the grid (catching-up, or a smooth actuation sampled by the exact method).
    pub fn check_steps(&self) -> Result<()> {
        if !(1..=MAX_STEPS_PER_PERIOD).contains(&self.steps_per_period) {
            return Err(Error::invalid(
                "steps_per_period",
                self.steps_per_period,
                format!("must be in 1..={MAX_STEPS_PER_PERIOD} (memory)"),
            ));
        }
        Ok(())
    }
}

impl Default for SimOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// How the periodic state was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Search {
    /// Plain iteration of the period map: `periods_to_converge` is the physical transient.
    Iteration,
    /// Anderson-accelerated fixed-point search after the plain periods: `periods_to_converge`
    /// counts period integrations, the physical transient is longer.
    Anderson,
    /// Newton-Krylov steps (safeguarded by Anderson) after the plain periods: as for
    /// `Anderson`, plus [`Simulation::tangent_products`] Jacobian-vector products.
    Newton,
}

/// Result of [`simulate`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Simulation {
    /// Integration method.
    pub method: Method,
    /// Steps per period (catching-up) or knots per period (exact).
    pub steps_per_period: usize,
    /// What was integrated, in words (the exact method on a smooth actuation plays its
    /// piecewise-linear interpolant).
    pub actuation_model: String,
    /// Period `T`.
    pub period: f64,
    /// Whether a state repeating within tolerance was found.
    pub converged: bool,
    /// Index of the first period integrated from a state that repeated (1 when the initial
    /// state is on the orbit); see [`Search`] for what it counts.
    pub periods_to_converge: Option<usize>,
    /// How the periodic state was searched for.
    pub search: Search,
    /// Periods integrated in the search.
    pub periods_simulated: usize,
    /// Jacobian-vector products of the period map in the search (Newton-Krylov): each applies
    /// the tangent maps of a period's steps recorded in the last period, without projections.
    /// With the exact method (no tangent map) the Jacobian is that of catching-up on the same
    /// knots, and each Newton step's catching-up period that records it counts as one more.
    pub tangent_products: usize,
    /// Newton steps taken in the search.
    pub newton_steps: usize,
    /// `max_l |G(x)_l - x_l|` for the last period integrated in the search.
    pub period_residual: f64,
    /// The same residual after every period of the search (convergence history).
    pub residual_history: Vec<f64>,
    /// Displacement of the barycentre per period on the periodic orbit; `None` when the search
    /// did not converge (a transient value is never reported as periodic).
    pub displacement_per_period: Option<f64>,
    /// Displacement over the last period integrated (periodic or not).
    pub last_period_displacement: f64,
    /// Displacement of every block over that period.
    pub block_displacement_per_period: Vec<f64>,
    /// The initial state used (after an exact projection onto C).
    pub initial_state: Vec<f64>,
    /// The state at the start of that period (on the orbit when converged).
    pub orbit_state: Vec<f64>,
    /// Recorded periods from `orbit_state`: times from 0, barycentre 0 at the start.
    pub trajectory: Option<Trajectory>,
}

/// Anderson acceleration (type II, memory `m`) of a fixed-point iteration `x <- G(x)`.
struct Anderson {
    m: usize,
    df: VecDeque<Vec<f64>>,
    dg: VecDeque<Vec<f64>>,
    prev: Option<(Vec<f64>, Vec<f64>)>,
}

impl Anderson {
    fn new(m: usize) -> Self {
        Anderson {
            m,
            df: VecDeque::new(),
            dg: VecDeque::new(),
            prev: None,
        }
    }

    fn reset(&mut self) {
        self.df.clear();
        self.dg.clear();
        self.prev = None;
    }

    /// Next iterate from `x` and `g = G(x)`: `g - dG gamma`, `gamma = argmin |f - dF gamma|`.
    fn next(&mut self, x: &[f64], g: &[f64]) -> Vec<f64> {
        let f: Vec<f64> = g.iter().zip(x).map(|(a, b)| a - b).collect();
        if let Some((fp, gp)) = self.prev.take() {
            self.df
                .push_back(f.iter().zip(&fp).map(|(a, b)| a - b).collect());
            self.dg
                .push_back(g.iter().zip(&gp).map(|(a, b)| a - b).collect());
            if self.df.len() > self.m {
                self.df.pop_front();
                self.dg.pop_front();
            }
        }
        self.prev = Some((f.clone(), g.to_vec()));
        if self.df.is_empty() {
            return g.to_vec();
        }
        let n = f.len();
        let a = DMatrix::from_fn(n, self.df.len(), |i, j| self.df[j][i]);
        let Some(svd) = crate::linalg::svd(a, true, true) else {
            return g.to_vec();
        };
        let smax = svd.singular_values.max();
        let Ok(gamma) = svd.solve(&DVector::from_column_slice(&f), 1e-10 * smax) else {
            return g.to_vec();
        };
        let mut out = g.to_vec();
        for (j, col) in self.dg.iter().enumerate() {
            for (o, c) in out.iter_mut().zip(col) {
                *o -= gamma[j] * c;
            }
        }
        out
    }
}

/// The tangent maps for a Newton step or the preconditioner: those the period map recorded in
/// its last period, or (the exact method) those of catching-up on the same knots recorded in one
/// catching-up period from `x_start`, counted as one more product.
fn tangent_source<'a>(
    map: &'a dyn PeriodMap,
    surrogate: Option<&'a mut CatchingUp>,
    x_start: &[f64],
    products: &mut usize,
) -> Result<&'a dyn PeriodMap> {
    Ok(match surrogate {
        Some(cu) => {
            let nb = x_start.len() + 1;
            let (mut xs, mut a) = (x_start.to_vec(), vec![0.0; nb]);
            cu.run_period(&mut xs, &mut a, None)?;
            *products += 1;
            cu
        }
        None => map,
    })
}

/// The error of a recording beyond [`MAX_RECORDED`] values.
fn recording_limit(periods: usize, per_period: usize, nb: usize) -> Error {
    Error::invalid(
        "periods",
        periods,
        format!(
            "recording that many periods of about {per_period} samples of {nb} blocks exceeds \
             {MAX_RECORDED:e} values (3 per block and sample): record fewer periods or steps"
        ),
    )
}

/// Simulates the crawler under the actuation until the periodic regime (theory §4).
pub fn simulate(crawler: &Crawler, act: &Actuation, opts: &SimOptions) -> Result<Simulation> {
    let storage = check_sizes(crawler, act, opts)?;
    let nb = crawler.blocks();
    let mut proj = Projector::new(crawler)?;
    let mut scratch_d = vec![0.0; nb];
    let mut x = start_state(crawler, opts, &mut proj, &mut scratch_d)?;
    let initial_state = x.clone();
    let (mut map, steps_per_period, actuation_model) = period_map(crawler, act, opts, storage)?;
    let tol_abs = opts.tol * crawler.state_scale();
    let mut plain = opts.accelerate_after.unwrap_or(usize::MAX).max(1);
    let (newton, mut surrogate) = newton_setup(map.as_mut(), crawler, act, opts, storage);
    let mut mixing = Mixing {
        anderson: Anderson::new(ANDERSON_MEMORY),
        preconditioner: None,
        precondition: newton.is_some_and(|o| o.precondition_anderson),
    };
    // Tangent products, Newton steps, failed ones, and the period Newton may resume from.
    let (mut products, mut newton_steps, mut failures, mut newton_from) = (0, 0, 0, 0);
    // The residual before the last Newton step and the state a plain period gave there.
    let mut pending_newton: Option<(f64, Vec<f64>)> = None;
    let mut search = Search::Iteration;
    let mut acc = vec![0.0; nb];
    let mut x_start = x.clone();
    let mut converged_at = None;
    let mut history: Vec<f64> = Vec::new();
    let mut k = 0;
    while k < opts.max_periods {
        // A cancelled job stops between periods (crate::progress).
        crate::progress::check()?;
        k += 1;
        let residual = one_period(map.as_mut(), (&mut x, &mut x_start), &mut acc, &mut history)?;
        if residual <= tol_abs {
            converged_at = Some(k);
            break;
        }
        // A Newton step that did not halve the residual counts as failed: Anderson takes over
        // for a while, from the plain period before the step when the residual grew.
        if let (Some((before, plain_next)), Some(o)) = (pending_newton.take(), newton) {
            if residual > 0.5 * before {
                failures += 1;
                newton_from = k + o.retry_after;
                if residual > before {
                    x = plain_next;
                    continue;
                }
            }
        }
        // Plain iteration predicted (from the last contraction) not to converge within
        // `accelerate_after` periods: accelerate now.
        if k < plain && k >= EARLY_SWITCH_MIN && opts.accelerate_after.is_some() {
            plain = switch_at(k, plain, &history, tol_abs);
        }
        if k >= plain {
            let proposal = match newton {
                Some(o) if failures < o.max_failures && k >= newton_from => {
                    search = Search::Newton;
                    let tangents = (map.as_ref(), surrogate.as_mut());
                    let proposal =
                        newton_proposal(tangents, &x_start, &x, tol_abs, &o, &mut products)?;
                    newton_steps += 1;
                    pending_newton = Some((residual, x.clone()));
                    proposal
                }
                _ => {
                    if search == Search::Iteration {
                        search = Search::Anderson;
                    }
                    let tangents = (map.as_ref(), surrogate.as_mut());
                    mixing.proposal(tangents, &history, &x_start, &x, &mut products)?
                }
            };
            proj.project_from_origin(&proposal, &mut x, &mut scratch_d)?;
        }
    }
    map.record_tangent(false);
    let last = acc.iter().sum::<f64>() / nb as f64;
    let trajectory = (opts.record_periods > 0)
        .then(|| record_periods(crawler, act, map.as_mut(), &x_start, opts.record_periods))
        .transpose()?;
    Ok(Simulation {
        method: opts.method,
        steps_per_period,
        actuation_model,
        period: act.period(),
        converged: converged_at.is_some(),
        periods_to_converge: converged_at,
        search,
        periods_simulated: k,
        tangent_products: products,
        newton_steps,
        period_residual: history.last().copied().unwrap_or(f64::INFINITY),
        residual_history: history,
        displacement_per_period: converged_at.map(|_| last),
        last_period_displacement: last,
        block_displacement_per_period: acc,
        initial_state,
        orbit_state: x_start,
        trajectory,
    })
}

/// The state the simulation starts from: `opts.initial_state` (checked admissible) projected
/// onto C from the origin, else the origin.
fn start_state(
    crawler: &Crawler,
    opts: &SimOptions,
    proj: &mut Projector,
    scratch_d: &mut [f64],
) -> Result<Vec<f64>> {
    let mut x = vec![0.0; crawler.links()];
    if let Some(x0) = &opts.initial_state {
        crawler.check_admissible("simulation.initial_state", x0, 1e-9)?;
        proj.project_from_origin(x0, &mut x, scratch_d)?;
    }
    Ok(x)
}

/// The period from which the search accelerates, `plain` unless plain iteration is predicted
/// (from the last contraction, `history` the residuals up to period `k`) not to converge
/// within it: then now.
fn switch_at(k: usize, plain: usize, history: &[f64], tol_abs: f64) -> usize {
    let residual = history[k - 1];
    let rho = residual / history[k - 2];
    let needed = (tol_abs / residual).ln() / rho.ln();
    if rho >= 1.0 || k as f64 + needed > plain as f64 {
        k
    } else {
        plain
    }
}

/// One more period of `map` from `x` (kept in `x_start`), the blocks' displacements summed in
/// `acc`; returns the period's residual `max |x_k - x_(k-1)|`, recorded in `history`. An error
/// when the state or the displacement stops being finite.
fn one_period(
    map: &mut dyn PeriodMap,
    (x, x_start): (&mut [f64], &mut [f64]),
    acc: &mut [f64],
    history: &mut Vec<f64>,
) -> Result<f64> {
    let k = history.len() + 1;
    x_start.copy_from_slice(x);
    acc.iter_mut().for_each(|a| *a = 0.0);
    map.run_period(x, acc, None)?;
    if x.iter().chain(acc.iter()).any(|v| !v.is_finite()) {
        return Err(Error::Numerical(format!(
            "the state or the displacement is no longer finite after period {k}: \
             the parameters or the actuation exceed double precision"
        )));
    }
    let residual = x
        .iter()
        .zip(x_start.iter())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    history.push(residual);
    Ok(residual)
}

/// A Newton step on the fixed point of the period map from the period `x_start -> x`
/// (tangents from the map or its surrogate, [`tangent_source`]), solved to a tolerance
/// relative to the residual that aims a tenth below `tol_abs`; the tangent products it uses
/// are counted in `products`.
fn newton_proposal(
    (map, surrogate): (&dyn PeriodMap, Option<&mut CatchingUp>),
    x_start: &[f64],
    x: &[f64],
    tol_abs: f64,
    o: &NewtonOptions,
    products: &mut usize,
) -> Result<Vec<f64>> {
    let tangents = tangent_source(map, surrogate, x_start, products)?;
    let r: Vec<f64> = x.iter().zip(x_start).map(|(a, b)| a - b).collect();
    let r2 = r.iter().map(|v| v * v).sum::<f64>().sqrt();
    let rel_tol = (0.1 * tol_abs / r2).clamp(1e-13, 1e-2);
    let (step, used, _) = newton_step(
        &mut |v: &mut [f64]| tangents.apply_tangent(v),
        &r,
        rel_tol,
        o,
    );
    *products += used;
    Ok(x_start.iter().zip(&step).map(|(a, b)| a + b).collect())
}

/// The period map of `opts.method` with the step count and the description of the actuation
/// its results report: catching-up on `opts.steps_per_period` uniform steps, or the exact
/// method on the actuation's knots.
fn period_map(
    crawler: &Crawler,
    act: &Actuation,
    opts: &SimOptions,
    storage: IncrementStorage,
) -> Result<(Box<dyn PeriodMap>, usize, String)> {
    Ok(match opts.method {
        Method::CatchingUp => (
            Box::new(CatchingUp::with_storage(
                crawler,
                act,
                opts.steps_per_period,
                storage,
            )?),
            opts.steps_per_period,
            format!(
                "the actuation sampled at {} uniform steps per period",
                opts.steps_per_period
            ),
        ),
        Method::Exact => (
            Box::new(ExactPwl::new(crawler, act, opts.steps_per_period)?),
            act.knots(opts.steps_per_period).0.len(),
            act.exact_description(opts.steps_per_period),
        ),
    })
}

/// The Newton options that apply to `map` (none without acceleration), and the surrogate whose
/// tangents the Newton steps take when `map` records none. The exact method has no tangent
/// map: its Newton steps take the Jacobian of catching-up on the same knots (a surrogate; the
/// safeguard catches a step it spoils), one catching-up period from the current state per
/// step; increments that overflow leave it to Anderson alone.
fn newton_setup(
    map: &mut dyn PeriodMap,
    crawler: &Crawler,
    act: &Actuation,
    opts: &SimOptions,
    storage: IncrementStorage,
) -> (Option<NewtonOptions>, Option<CatchingUp>) {
    let Some(o) = opts.newton.filter(|_| opts.accelerate_after.is_some()) else {
        return (None, None);
    };
    if map.record_tangent(true) {
        return (Some(o), None);
    }
    if opts.method == Method::Exact
        && opts.steps_per_period >= 1
        && (opts.steps_per_period as f64) * (crawler.links() as f64) <= MAX_SAMPLES
    {
        let mut surrogate =
            CatchingUp::with_storage(crawler, act, opts.steps_per_period, storage).ok();
        let newton = surrogate.as_mut().map(|cu| {
            cu.record_tangent(true);
            o
        });
        return (newton, surrogate);
    }
    (None, None)
}

/// Anderson's mixing of the period map, with its optional preconditioner
/// (`NewtonOptions::precondition_anderson`), measured once at the first Anderson period.
struct Mixing {
    anderson: Anderson,
    preconditioner: Option<Diffusion>,
    precondition: bool,
}

impl Mixing {
    /// The next proposal from the period `x_start -> x` (`history` the residuals so far, the
    /// last this period's); tangents from the map or its surrogate ([`tangent_source`]).
    fn proposal(
        &mut self,
        (map, surrogate): (&dyn PeriodMap, Option<&mut CatchingUp>),
        history: &[f64],
        x_start: &[f64],
        x: &[f64],
        products: &mut usize,
    ) -> Result<Vec<f64>> {
        // Safeguard: a residual that grew restarts the acceleration from a plain step.
        let residual = history[history.len() - 1];
        let best = history[..history.len() - 1]
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        let grew = residual > 2.0 * best;
        if grew {
            self.anderson.reset();
        }
        if !self.precondition {
            return Ok(self.anderson.next(x_start, x));
        }
        // Mix x + P^{-1} (G(x) - x), P the chain's diffusion (newton.rs): the mixed map
        // contracts by about a half per period whatever N.
        let n = x.len();
        let pre = match self.preconditioner.as_mut() {
            Some(pre) => pre,
            None => {
                let tangents = tangent_source(map, surrogate, x_start, products)?;
                *products += 1;
                self.preconditioner
                    .insert(Diffusion::measured(n, &mut |v: &mut [f64]| {
                        tangents.apply_tangent(v)
                    }))
            }
        };
        // A residual that grew: the model overshoots (far from the orbit the chain's slow
        // modes contract less than measured), damp it.
        if grew {
            pre.weight *= 0.5;
        }
        let r: Vec<f64> = x.iter().zip(x_start).map(|(a, b)| a - b).collect();
        let mut z = vec![0.0; n];
        pre.apply(&r, &mut z);
        let h: Vec<f64> = x_start.iter().zip(&z).map(|(a, b)| a + b).collect();
        Ok(self.anderson.next(x_start, &h))
    }
}

/// The checks of [`simulate`]'s crawler (a unique periodic regime), its options against the
/// actuation and the memory guards: the
/// sampled increments (catching-up, unless streamed), the exact method's knots and the
/// recorded trajectory. Returns how the increments are stored.
fn check_sizes(crawler: &Crawler, act: &Actuation, opts: &SimOptions) -> Result<IncrementStorage> {
    crawler.require_unique()?;
    if act.links() != crawler.links() {
        return Err(Error::invalid(
            "actuation",
            format!("{} links", act.links()),
            format!("the crawler has {} links", crawler.links()),
        ));
    }
    let uses_m = opts.method == Method::CatchingUp || !act.is_piecewise_linear();
    if uses_m {
        opts.check_steps()?;
    }
    opts.check()?;
    let (n, nb) = (crawler.links(), crawler.blocks());
    // Memory guards: the sampled increments (catching-up, unless streamed), the exact method's
    // knots and the recorded trajectory.
    let per_period = if opts.method == Method::CatchingUp || !act.is_piecewise_linear() {
        opts.steps_per_period
    } else {
        act.knots(0).0.len()
    };
    let storage = IncrementStorage::within(opts.increment_budget, n, opts.steps_per_period);
    let streamed = opts.method == Method::CatchingUp && storage == IncrementStorage::Streamed;
    if uses_m && !streamed && (per_period as f64) * (n as f64) > MAX_SAMPLES {
        let (field, value, also) = match opts.method {
            Method::CatchingUp => (
                "increment_budget",
                opts.increment_budget,
                ": a smaller budget streams them",
            ),
            Method::Exact => ("steps_per_period", per_period, ""),
        };
        return Err(Error::invalid(
            field,
            value,
            format!(
                "holds {per_period} steps per period times {n} links, at most {MAX_SAMPLES:e} are \
                 held (memory){also}"
            ),
        ));
    }
    let recorded = opts.record_periods as f64 * per_period as f64 * (3 * nb) as f64;
    if recorded > MAX_RECORDED {
        return Err(recording_limit(opts.record_periods, per_period, nb));
    }
    Ok(storage)
}

/// Records `periods` periods of the orbit from its state `x_start` (the trajectory of
/// [`Simulation::trajectory`]), positions starting at `y = 0`.
fn record_periods(
    crawler: &Crawler,
    act: &Actuation,
    map: &mut dyn PeriodMap,
    x_start: &[f64],
    periods: usize,
) -> Result<Trajectory> {
    let (n, nb) = (crawler.links(), crawler.blocks());
    // Positions at the start of the recording: y = 0 and X_{b+1} - X_b = L_b(0) - x_b / k_b.
    let mut l0 = vec![0.0; n];
    act.lengths_at(0.0, &mut l0);
    let mut base = vec![0.0; nb];
    for l in 0..n {
        base[l + 1] = base[l] + l0[l] - x_start[l] / crawler.stiffness()[l];
    }
    let y0 = base.iter().sum::<f64>() / nb as f64;
    base.iter_mut().for_each(|b| *b -= y0);
    let mut traj = Trajectory::default();
    let mut xr = x_start.to_vec();
    let mut accr = vec![0.0; nb];
    let max_rows = (MAX_RECORDED / (3 * nb) as f64) as usize;
    for p in 0..periods {
        let mut rec = Recorder {
            traj: &mut traj,
            base: base.clone(),
            t0: p as f64 * act.period(),
            max_rows,
            overflow: false,
        };
        if p == 0 {
            rec.push(0.0, &xr, &accr, std::iter::repeat_n(0, nb));
        }
        map.run_period(&mut xr, &mut accr, Some(&mut rec))?;
        if rec.overflow {
            // The exact method records its events too: more samples than knots.
            return Err(recording_limit(periods, traj.t.len() / (p + 1), nb));
        }
    }
    Ok(traj)
}
