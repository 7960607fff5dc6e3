//! Time integration of the sweeping process (theory §3–4) and the periodic regime.
//!
//! - [`Method::CatchingUp`]: the implicit catching-up scheme `x^{i+1} = Proj_C(x^i + h u^i)` on
//!   `M` uniform steps per period; exact for `N = 2`, first order at corners of C otherwise.
//! - [`Method::Exact`]: event-driven integration of a piecewise-linear actuation (piecewise-
//!   constant `u`): between events `x' = P_{T_C(x)}(u)` is constant, so the trajectory is piecewise
//!   linear and computed without discretisation error; events are face hits and releases.
//!
//! [`simulate`] iterates periods until the state repeats (the limit cycle, refs \[Kre\], \[CGV\]) and
//! only then reports a displacement per period.

mod actuation;
mod catching_up;
pub mod chain_regime;
mod exact;
pub mod general;
pub mod general_exact;
mod increments;
mod newton;
mod periodic;
mod replay;

pub use actuation::{Actuation, TravellingWave, WaveDirection, Waveform, MAX_OFFSET_RATIO};
pub use catching_up::CatchingUp;
pub use chain_regime::{chain_regime, ChainRegime};
pub use exact::ExactPwl;
pub(crate) use general::simulate_general_on;
pub use general::{
    simulate_general, ControlInput, DriftStep, GeneralMethod, GeneralSimOptions, GeneralSimulation,
    InputKind,
};
pub use general_exact::simulate_general_exact;
pub use increments::IncrementStorage;
pub use newton::NewtonOptions;
pub use periodic::{
    check_tol, simulate, Search, SimOptions, Simulation, EARLY_SWITCH_MIN, MAX_TOL,
};
pub use replay::replay;

use crate::error::Result;
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

impl Method {
    /// Every method, in the order front ends list them.
    pub const ALL: [Method; 2] = [Method::Exact, Method::CatchingUp];

    /// Its name, as the command line, result files and sweep files spell it (`"catching-up"`).
    pub fn name(self) -> &'static str {
        match self {
            Method::Exact => "exact",
            Method::CatchingUp => "catching-up",
        }
    }

    /// One line on what the method does, for a front end's list of methods (the command
    /// line's `--help`).
    pub fn summary(self) -> &'static str {
        match self {
            Method::Exact => {
                "Event-driven, exact for piecewise-linear actuation (a general problem: where A = 0 \
                 and the input is piecewise constant, else catching-up)"
            }
            Method::CatchingUp => "Implicit catching-up on a uniform grid of the steps per period",
        }
    }

    /// The method of a name ([`Method::name`]; Python's `"catching_up"` too): one reader, so
    /// that every front end refuses another name in the same words, naming `method`.
    pub fn from_name(name: &str) -> Result<Self> {
        match name {
            "catching_up" => Ok(Method::CatchingUp),
            _ => Self::ALL
                .into_iter()
                .find(|m| m.name() == name)
                .ok_or_else(|| {
                    crate::Error::invalid("method", name, "must be \"exact\" or \"catching-up\"")
                }),
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
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

/// Appends samples to a trajectory: positions are `base + accumulated displacement`. At most
/// `max_rows` rows are kept: beyond them `overflow` is set and nothing more is recorded (the
/// exact method records every event, which the size estimated before a run cannot know).
pub struct Recorder<'a> {
    traj: &'a mut Trajectory,
    base: Vec<f64>,
    t0: f64,
    max_rows: usize,
    overflow: bool,
}

impl Recorder<'_> {
    /// Records the state at local time `t` of the current period.
    pub fn push(&mut self, t: f64, x: &[f64], acc: &[f64], slip: impl Iterator<Item = Slip>) {
        if self.traj.t.len() >= self.max_rows {
            self.overflow = true;
            return;
        }
        let pos: Vec<f64> = self.base.iter().zip(acc).map(|(b, a)| b + a).collect();
        self.traj.t.push(self.t0 + t);
        self.traj.x.push(x.to_vec());
        self.traj
            .barycentre
            .push(pos.iter().sum::<f64>() / pos.len() as f64);
        self.traj.positions.push(pos);
        self.traj.slip.push(slip.collect());
    }
}

/// Refuses increments `K (L' - L)` that overflow double precision (huge stiffness or lengths).
fn check_increments(incs: &[f64]) -> Result<()> {
    match incs.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(crate::Error::invalid(
            "actuation",
            v,
            "the increments k * (L(t') - L(t)) overflow double precision: reduce stiffness or lengths",
        )),
        None => Ok(()),
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
    fn run_period(
        &mut self,
        x: &mut [f64],
        acc: &mut [f64],
        rec: Option<&mut Recorder>,
    ) -> Result<()>;

    /// The period from `x` (advanced in place) with its tangent map applied to `dx` in place:
    /// `dx <- J dx`, `J` the Jacobian of the period map on the active pattern of every step.
    /// `Ok(false)` (and nothing changed) where the integrator has none.
    fn run_period_tangent(&mut self, _x: &mut [f64], _dx: &mut [f64]) -> Result<bool> {
        Ok(false)
    }

    /// Whether the following [`PeriodMap::run_period`] calls record the tangent map of every
    /// step (its active pattern), for [`PeriodMap::apply_tangent`]. Returns whether the
    /// integrator can (`false`: it has no tangent map, nothing is recorded).
    fn record_tangent(&mut self, _on: bool) -> bool {
        false
    }

    /// `dx <- J dx`, `J` the Jacobian of the period map on the active pattern recorded during the
    /// last [`PeriodMap::run_period`] with recording on: the cost of the tangent maps alone, no
    /// projection. Does nothing where nothing was recorded.
    fn apply_tangent(&self, _dx: &mut [f64]) {}
}
