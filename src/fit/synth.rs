//! Synthetic recordings: a crawler simulated on its periodic orbit and filmed by a camera at a
//! fixed frame rate, with optional Gaussian noise on the positions. For round trips (tests,
//! the example data, the documentation): fit what was simulated and compare.

use super::data::FitData;
use crate::error::{Error, Result};
use crate::integrate::{simulate, Actuation, Method, SimOptions};
use crate::model::Crawler;

/// How to film a simulated crawler.
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// Frames per period (uniform; the first at the start of the orbit's period).
    pub frames_per_period: usize,
    /// Periods filmed on the periodic orbit.
    pub periods: usize,
    /// Standard deviation of Gaussian noise added to every position (0: exact data).
    pub noise: f64,
    /// Seed of the noise (a fixed generator: the same seed gives the same data everywhere).
    pub seed: u64,
}

/// The crawler's periodic regime under `act` (played exactly as its piecewise-linear
/// interpolant on 1000 knots when smooth, and the lengths recorded are that interpolant's),
/// filmed as `rec` says.
pub fn record(crawler: &Crawler, act: &Actuation, rec: &Recording) -> Result<FitData> {
    if rec.frames_per_period < 2 || rec.periods == 0 {
        return Err(Error::invalid(
            "recording",
            format!("{} frames, {} periods", rec.frames_per_period, rec.periods),
            "needs at least 2 frames per period and 1 period",
        ));
    }
    if !(rec.noise.is_finite() && rec.noise >= 0.0) {
        return Err(Error::invalid(
            "noise",
            rec.noise,
            "must be finite and >= 0",
        ));
    }
    let (times, lengths) = act.knots(SimOptions::DEFAULT.steps_per_period);
    let act = Actuation::piecewise_linear(act.period(), times, lengths)?;
    let sim = simulate(
        crawler,
        &act,
        &SimOptions {
            method: Method::Exact,
            record_periods: rec.periods,
            ..SimOptions::DEFAULT
        },
    )?;
    let traj = match (sim.converged, sim.trajectory) {
        (true, Some(t)) => t,
        _ => {
            return Err(Error::Numerical(
                "recording: the periodic regime was not reached".into(),
            ))
        }
    };
    let period = act.period();
    let frames = rec.frames_per_period * rec.periods + 1;
    let mut rng = Normal::new(rec.seed);
    let (mut t, mut ls, mut xs) = (Vec::new(), Vec::new(), Vec::new());
    let mut r = 0;
    for f in 0..frames {
        let tau = f as f64 * period / rec.frames_per_period as f64;
        // The trajectory is linear between its records: interpolate (the last record at or
        // before tau, and the next).
        while r + 1 < traj.t.len() && traj.t[r + 1] <= tau {
            r += 1;
        }
        let s = if r + 1 < traj.t.len() && traj.t[r + 1] > traj.t[r] {
            ((tau - traj.t[r]) / (traj.t[r + 1] - traj.t[r])).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let next = &traj.positions[(r + 1).min(traj.t.len() - 1)];
        let pos: Vec<f64> = traj.positions[r]
            .iter()
            .zip(next)
            .map(|(a, b)| a + s * (b - a) + rec.noise * rng.sample())
            .collect();
        let mut l = vec![0.0; crawler.links()];
        act.lengths_at(tau, &mut l);
        t.push(tau);
        ls.push(l);
        xs.push(pos);
    }
    FitData::new(crawler.blocks(), t, ls, xs)
}

/// Standard normal numbers from a fixed generator (SplitMix64 and Box–Muller).
struct Normal {
    state: u64,
    spare: Option<f64>,
}

impl Normal {
    fn new(seed: u64) -> Self {
        Normal {
            state: seed,
            spare: None,
        }
    }

    fn uniform(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn sample(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let (u, v) = (self.uniform(), self.uniform());
        let r = (-2.0 * u.ln()).sqrt();
        let th = 2.0 * std::f64::consts::PI * v;
        self.spare = Some(r * th.sin());
        r * th.cos()
    }
}
