//! Internal units of the optimisers: every LP and MILP is built in units where the problem is
//! well conditioned, and its answer converted back before anything is reported.
//!
//! HiGHS's tolerances are absolute (1e-9), so a crawler whose friction thresholds are 1e9 or
//! 1e-9, a period of 1e-12 or a displacement of 1e-9 would be mis-solved in the user's units,
//! although a change of units makes each of them the reference instance. The optimisers
//! therefore solve in the units
//! - force: the geometric mean of the friction thresholds (so `mu^±` are of order 1),
//! - time: the period (so `T = 1`),
//! - length: the problem's length unit `min_l w_l / k_l` (so the smallest elongation that
//!   crosses C is 1, and displacements and `J` are of order 1),
//!
//! and what no change of units can fix, the dimensionless ratios, is checked by
//! [`GaitProblem::check_scales`]. A change of units maps gaits to gaits and `J` to `J` times the
//! length unit, so an optimum in one set of units is the optimum in the other, and a bound is a
//! bound: only the numbers are converted (gaps are recomputed in the user's units).

use crate::error::Result;
use crate::model::Crawler;
use crate::optimal::{Certificate, Cost, GaitProblem};

/// A unit system: the user's force, time and length units expressed in the internal ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Units {
    pub(crate) force: f64,
    pub(crate) time: f64,
    pub(crate) length: f64,
}

pub(crate) fn scale_rows(rows: &[Vec<f64>], f: f64) -> Vec<Vec<f64>> {
    rows.iter()
        .map(|r| r.iter().map(|v| v * f).collect())
        .collect()
}

pub(crate) fn scale_all(v: &[f64], f: f64) -> Vec<f64> {
    v.iter().map(|x| x * f).collect()
}

impl Units {
    /// The user's own units: each factor 1.
    pub(crate) const ONE: Units = Units {
        force: 1.0,
        time: 1.0,
        length: 1.0,
    };

    /// The internal units of a problem (module docs).
    pub fn of(crawler: &Crawler, problem: &GaitProblem) -> Self {
        let mus = crawler.friction_thresholds();
        let log_mean = mus.iter().map(|m| m.ln()).sum::<f64>() / mus.len() as f64;
        Units {
            force: log_mean.exp(),
            time: problem.period,
            length: problem.length_scale(crawler),
        }
    }

    /// The crawler in internal units: `mu / F`, `k L / F`.
    pub fn crawler(&self, c: &Crawler) -> Result<Crawler> {
        Crawler::new(
            scale_all(c.stiffness(), self.length / self.force),
            scale_all(c.mu_forward(), 1.0 / self.force),
            scale_all(c.mu_backward(), 1.0 / self.force),
        )
    }

    /// The problem in internal units: `T / T = 1`, `a T / F`, `c F^2 / (T L)`, `TV T / F`.
    pub fn problem(&self, p: &GaitProblem) -> GaitProblem {
        let (f, t, l) = (self.force, self.time, self.length);
        GaitProblem {
            period: p.period / t,
            rate_bound: scale_all(&p.rate_bound, t / f),
            cost: match p.cost {
                Cost::None => Cost::None,
                Cost::Quadratic { weight } => Cost::Quadratic {
                    weight: weight * f * f / (t * l),
                },
            },
            max_total_variation: p.max_total_variation.map(|v| v * t / f),
        }
    }

    /// Knots of a start gait (times, actuator lengths) into internal units.
    pub fn knots_in(&self, times: &[f64], lengths: &[Vec<f64>]) -> (Vec<f64>, Vec<Vec<f64>>) {
        (
            scale_all(times, 1.0 / self.time),
            scale_rows(lengths, 1.0 / self.length),
        )
    }

    /// The factor from an objective in internal units to the user's (the length unit): for the
    /// MILP progress reported while a solve runs ([`crate::progress::with_objective_scale`]).
    pub fn objective_scale(&self) -> f64 {
        self.length
    }

    /// Conversion factors (force, time, length) towards the user's units or away from them.
    pub(crate) fn factors(&self, to_user: bool) -> (f64, f64, f64) {
        if to_user {
            (self.force, self.time, self.length)
        } else {
            (1.0 / self.force, 1.0 / self.time, 1.0 / self.length)
        }
    }

    /// A certificate with its values in length units scaled by `l` (gap recomputed over the
    /// target units' floor of `J`, [`Certificate::gap_of`]).
    pub(crate) fn certificate_scaled(
        &self,
        c: &Certificate,
        objective: f64,
        l: f64,
        floor: f64,
    ) -> Certificate {
        let bound = c.bound * l;
        Certificate {
            status: c.status,
            milp_objective: c.milp_objective * l,
            bound,
            gap: Certificate::gap_of(bound, objective, floor),
        }
    }
}
