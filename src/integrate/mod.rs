//! Time integration of the sweeping process (SPEC §3–4) and the periodic regime.
//!
//! - [`Method::CatchingUp`]: the implicit catching-up scheme `x^{i+1} = Proj_C(x^i + h u^i)` on
//!   `M` uniform steps per period; exact for `N = 2`, first order at corners of C otherwise.
//! - [`Method::Exact`]: event-driven integration of a piecewise-linear actuation (piecewise-
//!   constant `u`): between events `x' = P_{T_C(x)}(u)` is constant, so the trajectory is piecewise
//!   linear and computed without discretisation error; events are face hits and releases.
//!
//! [`simulate`] iterates periods until the state repeats (the limit cycle, refs [Kre], [CGV]) and
//! only then reports a displacement per period.

mod actuation;
mod catching_up;
mod exact;

pub use actuation::{Actuation, Waveform};
pub use catching_up::CatchingUp;
pub use exact::ExactPwl;

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::sweep::Projector;
use serde::Serialize;

/// Integration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Method {
    /// Event-driven, exact for piecewise-linear actuation.
    #[serde(rename = "exact")]
    Exact,
    /// Implicit catching-up on a uniform grid.
    #[serde(rename = "catching-up")]
    CatchingUp,
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Method::Exact => "exact",
            Method::CatchingUp => "catching-up",
        })
    }
}

/// Slip state of a block over an interval: `-1` backward, `0` stick, `1` forward.
pub type Slip = i8;

/// Samples of a simulated motion. Row `i` is the state at `t[i]`; `slip[i]` is the slip state over
/// the interval ending at `t[i]` (all zero on the first row). Positions satisfy
/// `X_{b+1} - X_b = z_b = L_b - x_b / k_b` and `y(0) = 0` at the start of the simulation.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Trajectory {
    /// Times.
    pub t: Vec<f64>,
    /// Link compressions `x_l` (force units).
    pub x: Vec<Vec<f64>>,
    /// Block positions `X_b` (length units).
    pub positions: Vec<Vec<f64>>,
    /// Barycentre `y = mean_b X_b`.
    pub barycentre: Vec<f64>,
    /// Slip state per block.
    pub slip: Vec<Vec<Slip>>,
}

/// Appends samples to a trajectory: positions are `base + accumulated displacement`.
pub struct Recorder<'a> {
    traj: &'a mut Trajectory,
    base: Vec<f64>,
    t0: f64,
}

impl Recorder<'_> {
    /// Records the state at local time `t` of the current period.
    pub fn push(&mut self, t: f64, x: &[f64], acc: &[f64], slip: impl Iterator<Item = Slip>) {
        let pos: Vec<f64> = self.base.iter().zip(acc).map(|(b, a)| b + a).collect();
        self.traj.t.push(self.t0 + t);
        self.traj.x.push(x.to_vec());
        self.traj.barycentre.push(pos.iter().sum::<f64>() / pos.len() as f64);
        self.traj.positions.push(pos);
        self.traj.slip.push(slip.collect());
    }
}

/// Slip state of a displacement or velocity, with a tolerance.
pub fn slip_of(v: f64, tol: f64) -> Slip {
    if v > tol {
        1
    } else if v < -tol {
        -1
    } else {
        0
    }
}

/// One period of an integrator, as a map of the state.
pub trait PeriodMap {
    /// Advances `x` over one period, adds every block's displacement to `acc`, and records the
    /// samples (period-local times) when `rec` is given.
    fn run_period(&mut self, x: &mut [f64], acc: &mut [f64], rec: Option<&mut Recorder>) -> Result<()>;
}

/// Options of [`simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    /// Integration method.
    pub method: Method,
    /// Steps per period (catching-up) or knots of the interpolant of a smooth actuation (exact).
    pub steps_per_period: usize,
    /// Periods recorded on the periodic orbit (0: record nothing).
    pub record_periods: usize,
    /// Give up the search for the periodic regime after this many periods.
    pub max_periods: usize,
    /// The state repeats when `max_l |x_l(kT) - x_l((k-1)T)| <= tol * max mu`.
    pub tol: f64,
    /// Initial state `x(0)` (default 0, the unloaded crawler).
    pub initial_state: Option<Vec<f64>>,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            method: Method::Exact,
            steps_per_period: 1000,
            record_periods: 1,
            max_periods: 1000,
            tol: 1e-12,
            initial_state: None,
        }
    }
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
    /// Whether the state repeated within tolerance.
    pub converged: bool,
    /// Index of the first period whose end state equals its start state (1 when the initial
    /// state is on the orbit).
    pub periods_to_converge: Option<usize>,
    /// Periods integrated in the search.
    pub periods_simulated: usize,
    /// `max_l |x_l(kT) - x_l((k-1)T)|` over the last period of the search.
    pub period_residual: f64,
    /// Displacement of the barycentre per period on the periodic orbit; `None` when the search
    /// did not converge (a transient value is never reported as periodic).
    pub displacement_per_period: Option<f64>,
    /// Displacement over the last period simulated (periodic or not).
    pub last_period_displacement: f64,
    /// Displacement of every block over the last period simulated.
    pub block_displacement_per_period: Vec<f64>,
    /// The initial state used (after an exact projection onto C).
    pub initial_state: Vec<f64>,
    /// The state at the start of the last period simulated (on the orbit when converged).
    pub orbit_state: Vec<f64>,
    /// Recorded periods on the orbit (absolute times), if any.
    pub trajectory: Option<Trajectory>,
}

/// Simulates the crawler under the actuation until the periodic regime (SPEC §4).
pub fn simulate(crawler: &Crawler, act: &Actuation, opts: &SimOptions) -> Result<Simulation> {
    crawler.require_unique()?;
    if act.links() != crawler.links() {
        return Err(Error::invalid(
            "actuation",
            format!("{} links", act.links()),
            format!("the crawler has {} links", crawler.links()),
        ));
    }
    if opts.steps_per_period == 0 || opts.steps_per_period > 100_000_000 {
        return Err(Error::invalid("steps_per_period", opts.steps_per_period, "must be in 1..=100000000"));
    }
    if opts.max_periods == 0 {
        return Err(Error::invalid("max_periods", 0, "must be at least 1"));
    }
    if !(opts.tol.is_finite() && opts.tol > 0.0) {
        return Err(Error::invalid("tol", opts.tol, "must be positive and finite"));
    }
    let (n, nb) = (crawler.links(), crawler.blocks());
    let mut x = vec![0.0; n];
    if let Some(x0) = &opts.initial_state {
        crawler.check_admissible("simulation.initial_state", x0, 1e-9)?;
        let mut p = Projector::new(crawler)?;
        let mut d = vec![0.0; nb];
        p.project_from_origin(x0, &mut x, &mut d)?;
    }
    let initial_state = x.clone();
    let mut map: Box<dyn PeriodMap> = match opts.method {
        Method::CatchingUp => Box::new(CatchingUp::new(crawler, act, opts.steps_per_period)?),
        Method::Exact => Box::new(ExactPwl::new(crawler, act, opts.steps_per_period)?),
    };
    let steps_per_period = match opts.method {
        Method::Exact => act.knots(opts.steps_per_period).0.len(),
        Method::CatchingUp => opts.steps_per_period,
    };
    let actuation_model = match opts.method {
        Method::Exact => act.exact_description(opts.steps_per_period),
        Method::CatchingUp => format!("the actuation sampled at {} uniform steps per period", opts.steps_per_period),
    };
    let tol_abs = opts.tol * crawler.force_scale();
    let mut acc = vec![0.0; nb];
    let mut acc_start = acc.clone();
    let mut x_start = x.clone();
    let mut converged_at = None;
    let mut residual = f64::INFINITY;
    let mut k = 0;
    while k < opts.max_periods {
        k += 1;
        x_start.copy_from_slice(&x);
        acc_start.copy_from_slice(&acc);
        map.run_period(&mut x, &mut acc, None)?;
        residual = x.iter().zip(&x_start).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        if residual <= tol_abs {
            converged_at = Some(k);
            break;
        }
    }
    let block_disp: Vec<f64> = acc.iter().zip(&acc_start).map(|(a, b)| a - b).collect();
    let last = block_disp.iter().sum::<f64>() / nb as f64;
    let trajectory = if opts.record_periods > 0 {
        // Initial positions: y(0) = 0 and X_{b+1} - X_b = L_b(0) - x_b(0)/k_b.
        let mut l0 = vec![0.0; n];
        act.lengths_at(0.0, &mut l0);
        let mut x0 = vec![0.0; nb];
        for l in 0..n {
            x0[l + 1] = x0[l] + l0[l] - initial_state[l] / crawler.stiffness()[l];
        }
        let y0 = x0.iter().sum::<f64>() / nb as f64;
        let mut traj = Trajectory::default();
        let mut xr = x_start.clone();
        let mut accr = acc_start.clone();
        let t_first = (k - 1) as f64 * act.period();
        for p in 0..opts.record_periods {
            let mut rec = Recorder {
                traj: &mut traj,
                base: x0.iter().map(|v| v - y0).collect(),
                t0: t_first + p as f64 * act.period(),
            };
            if p == 0 {
                rec.push(0.0, &xr, &accr, std::iter::repeat_n(0, nb));
            }
            map.run_period(&mut xr, &mut accr, Some(&mut rec))?;
        }
        Some(traj)
    } else {
        None
    };
    Ok(Simulation {
        method: opts.method,
        steps_per_period,
        actuation_model,
        period: act.period(),
        converged: converged_at.is_some(),
        periods_to_converge: converged_at,
        periods_simulated: k,
        period_residual: residual,
        displacement_per_period: converged_at.map(|_| last),
        last_period_displacement: last,
        block_displacement_per_period: block_disp,
        initial_state,
        orbit_state: x_start,
        trajectory,
    })
}
