//! Exact event-driven integration for piecewise-linear actuation (theory §4).
//!
//! On a phase where the actuation moves linearly, `u` is constant and, between events,
//! `x' = P_{T_C(x)}(u)` (projection onto the tangent cone in the `K^{-1}` metric) is constant too:
//! the faces active at `x` are kept or released by that projection, and the next event is the
//! first free face that the straight motion hits. The trajectory is therefore piecewise linear
//! and each piece is computed in closed form: no discretisation error. Block velocities are the
//! multipliers of the cone projection (they obey the flow rule by construction).
//!
//! Time inside a phase is measured by its progress `s in [0, 1]` (the increment `U = K ΔL` is
//! played at unit rate): the process is rate-independent.

use super::{slip_of, Actuation, PeriodMap, Recorder};
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::sweep::{increment as inc, Bound, ConeProjector};

/// Exact integrator of a periodic piecewise-linear actuation.
#[derive(Debug, Clone)]
pub struct ExactPwl {
    cone: ConeProjector,
    /// Phase start times, plus `T` at the end.
    times: Vec<f64>,
    /// `U_j = K (L_{j+1} - L_j)`, row-major.
    incs: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    tol_face: f64,
    active: Vec<Bound>,
    w: Vec<f64>,
    vel: Vec<f64>,
    n: usize,
    max_events: usize,
    events: u64,
}

impl ExactPwl {
    /// The exact integrator of the actuation's knots (see [`Actuation::knots`]; `m` is used only
    /// for a smooth actuation).
    pub fn new(crawler: &Crawler, act: &Actuation, m: usize) -> Result<Self> {
        let (mut times, lengths) = act.knots(m);
        let n = crawler.links();
        let k = crawler.stiffness();
        let kk = times.len();
        let mut incs = Vec::with_capacity(kk * n);
        for j in 0..kk {
            let (a, b) = (&lengths[j], &lengths[(j + 1) % kk]);
            incs.extend((0..n).map(|l| k[l] * (b[l] - a[l])));
        }
        times.push(act.period());
        super::check_increments(&incs)?;
        Ok(ExactPwl {
            cone: ConeProjector::new(crawler)?,
            times,
            incs,
            lo: crawler.mu_forward().iter().map(|m| -m).collect(),
            hi: crawler.mu_backward().to_vec(),
            tol_face: 1e-13 * crawler.state_scale(),
            active: vec![Bound::Free; crawler.blocks()],
            w: vec![0.0; n],
            vel: vec![0.0; crawler.blocks()],
            n,
            max_events: 1000 + 100 * crawler.blocks(),
            events: 0,
        })
    }

    /// Total events (face hits) so far.
    pub fn events(&self) -> u64 {
        self.events
    }

    fn phase(
        &mut self,
        j: usize,
        x: &mut [f64],
        acc: &mut [f64],
        rec: &mut Option<&mut Recorder>,
    ) -> Result<()> {
        let n = self.n;
        let nb = n + 1;
        let u = &self.incs[j * n..(j + 1) * n];
        let (t0, dur) = (self.times[j], self.times[j + 1] - self.times[j]);
        let umax = u.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if umax == 0.0 {
            if let Some(r) = rec.as_deref_mut() {
                r.push(t0 + dur, x, acc, std::iter::repeat_n(0, nb));
            }
            return Ok(());
        }
        let mut s = 0.0;
        for _ in 0..self.max_events {
            // One-sided tests: a face crossed by rounding stays active, so x cannot leak out of C.
            for b in 0..nb {
                let d = inc(x, b);
                self.active[b] = if d - self.lo[b] <= self.tol_face {
                    Bound::Lower
                } else if self.hi[b] - d <= self.tol_face {
                    Bound::Upper
                } else {
                    Bound::Free
                };
            }
            self.cone
                .project(&self.active, u, &mut self.w, &mut self.vel)?;
            // First face hit by the straight motion x + tau w.
            let mut tau = 1.0 - s;
            let mut hit = false;
            for b in 0..nb {
                let dd = inc(&self.w, b);
                let d = inc(x, b);
                // Every approach counts, however slow: a slow approach over a long phase still
                // reaches the face.
                let t = if dd < 0.0 && d - self.lo[b] > self.tol_face {
                    (self.lo[b] - d) / dd
                } else if dd > 0.0 && self.hi[b] - d > self.tol_face {
                    (self.hi[b] - d) / dd
                } else {
                    continue;
                };
                if t < tau {
                    tau = t.max(0.0);
                    hit = true;
                }
            }
            for (xi, wi) in x.iter_mut().zip(&self.w) {
                *xi += tau * wi;
            }
            for (a, v) in acc.iter_mut().zip(&self.vel) {
                *a += tau * v;
            }
            s += tau;
            if let Some(r) = rec.as_deref_mut() {
                let vtol = 1e-12 * umax;
                r.push(
                    t0 + s.min(1.0) * dur,
                    x,
                    acc,
                    self.vel.iter().map(|&v| slip_of(v, vtol)),
                );
            }
            if !hit {
                return Ok(());
            }
            self.events += 1;
        }
        Err(Error::Numerical(format!(
            "exact integration: more than {} events in one phase (t = {t0})",
            self.max_events
        )))
    }
}

impl PeriodMap for ExactPwl {
    fn run_period(
        &mut self,
        x: &mut [f64],
        acc: &mut [f64],
        mut rec: Option<&mut Recorder>,
    ) -> Result<()> {
        for j in 0..self.times.len() - 1 {
            self.phase(j, x, acc, &mut rec)?;
        }
        Ok(())
    }
}
