//! The implicit catching-up scheme (SPEC §4): with `u` constant on each step,
//! `x^{i+1} = argmin_{x in C} |x - (x^i + h u^i)|^2_{K^{-1}}`, and the block displacements over the
//! step are the multipliers `D_b`. Here `h u^i = K (L(t_{i+1}) - L(t_i))`: the exact increment of
//! the actuation over the step, so the scheme is rate-independent.

use super::{slip_of, Actuation, PeriodMap, Recorder};
use crate::error::Result;
use crate::model::Crawler;
use crate::sweep::{tangent, Bound, ProjectionMethod, Projector};

/// Catching-up on `m` uniform steps per period.
#[derive(Debug, Clone)]
pub struct CatchingUp {
    proj: Projector,
    /// `K (L^{i+1} - L^i)`, row-major `m x n`.
    deltas: Vec<f64>,
    times: Vec<f64>,
    d: Vec<f64>,
    n: usize,
    iterations: u64,
    /// The working set of every step of the last period (row-major `m x (n + 1)`) when
    /// recording ([`PeriodMap::record_tangent`]), else empty.
    pattern: Vec<Bound>,
    recording: bool,
    inv_k: Vec<f64>,
}

impl CatchingUp {
    /// Samples the actuation at `t_i = i T / m`, `i = 0..=m` (with `L(t_m) = L(t_0)` exactly, so
    /// the increments sum to zero).
    pub fn new(crawler: &Crawler, act: &Actuation, m: usize) -> Result<Self> {
        let n = crawler.links();
        let period = act.period();
        let mut samples = vec![0.0; (m + 1) * n];
        for i in 0..m {
            act.lengths_at(
                (i as f64 / m as f64) * period,
                &mut samples[i * n..(i + 1) * n],
            );
        }
        let (head, tail) = samples.split_at_mut(m * n);
        tail.copy_from_slice(&head[..n]);
        let k = crawler.stiffness();
        let deltas = (0..m * n)
            .map(|j| k[j % n] * (samples[j + n] - samples[j]))
            .collect();
        Self::from_increments(crawler, deltas, period)
    }

    /// Catching-up on given increments `K (L^{i+1} - L^i)` (row-major `m x n`) over a period.
    pub fn from_increments(crawler: &Crawler, deltas: Vec<f64>, period: f64) -> Result<Self> {
        let n = crawler.links();
        let m = deltas.len() / n;
        super::check_increments(&deltas)?;
        Ok(CatchingUp {
            proj: Projector::new(crawler)?,
            deltas,
            times: (0..=m).map(|i| (i as f64 / m as f64) * period).collect(),
            d: vec![0.0; crawler.blocks()],
            n,
            iterations: 0,
            pattern: Vec::new(),
            recording: false,
            inv_k: crawler.stiffness().iter().map(|k| 1.0 / k).collect(),
        })
    }

    /// Total active-set iterations so far (a cost measure of the projection kernel).
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// Projects with this method whatever the length of the chain (default:
    /// [`ProjectionMethod::Warm`]; all give the same steps).
    pub fn set_method(&mut self, method: ProjectionMethod) {
        self.proj.set_method(method);
    }

    /// Work counters of the warm projection (see [`crate::sweep::ChainWarm::counters`]).
    pub fn warm_counters(&self) -> (u64, u64, u64) {
        self.proj.warm_counters()
    }
}

impl PeriodMap for CatchingUp {
    fn run_period(
        &mut self,
        x: &mut [f64],
        acc: &mut [f64],
        mut rec: Option<&mut Recorder>,
    ) -> Result<()> {
        let n = self.n;
        self.pattern.clear();
        for (i, delta) in self.deltas.chunks_exact(n).enumerate() {
            self.iterations += self.proj.step(x, delta, &mut self.d)? as u64;
            if self.recording {
                self.pattern.extend_from_slice(self.proj.active());
            }
            for (a, d) in acc.iter_mut().zip(&self.d) {
                *a += d;
            }
            if let Some(r) = rec.as_deref_mut() {
                let tol = 1e-12 * delta.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                r.push(
                    self.times[i + 1],
                    x,
                    acc,
                    self.d.iter().map(|&d| slip_of(d, tol)),
                );
            }
        }
        Ok(())
    }

    fn run_period_tangent(&mut self, x: &mut [f64], dx: &mut [f64]) -> Result<bool> {
        let n = self.n;
        for delta in self.deltas.chunks_exact(n) {
            self.iterations += self.proj.step(x, delta, &mut self.d)? as u64;
            self.proj.tangent(dx);
        }
        Ok(true)
    }

    fn record_tangent(&mut self, on: bool) -> bool {
        self.recording = on;
        if !on {
            self.pattern = Vec::new();
        }
        true
    }

    fn apply_tangent(&self, dx: &mut [f64]) {
        for ws in self.pattern.chunks_exact(self.n + 1) {
            tangent(ws, &self.inv_k, dx);
        }
    }
}
