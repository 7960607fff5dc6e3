//! The gait problem (P) (theory §5, paper eqs. 2.2–2.3, §3.4): given the period `T`, rate bounds
//! `|u_l| <= a_l` (`a_l = k_l * max_actuator_speed_l`) and an actuation cost `f2`, maximise
//! `J = y(T) - y(0) - int_0^T f2(u) dt` over `T`-periodic actuations (`int u = 0`) on a limit
//! cycle (`x(0) = x(T)`).

use crate::error::{Error, Result};
use crate::model::Crawler;
use serde::{Deserialize, Serialize};

/// The actuation cost `f2(u)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Cost {
    /// `f2 = 0`.
    None,
    /// `f2(u) = (c/2) |u|^2`, `c = weight`, with `u = k L'` in force per time; `c` is in
    /// length * time / force^2, so that `int f2 dt` is a length like the displacement.
    Quadratic {
        /// `c > 0`.
        weight: f64,
    },
}

/// A crawler's cost as the cost of its instance of (P) ([`crate::model::crawler_as_general`]):
/// the same `f2` of the same control.
impl From<Cost> for crate::model::general::GeneralCost {
    fn from(c: Cost) -> Self {
        match c {
            Cost::None => Self::None,
            Cost::Quadratic { weight } => Self::Quadratic { weight },
        }
    }
}

impl Cost {
    /// `f2(u)`.
    pub fn eval(&self, u: &[f64]) -> f64 {
        match self {
            Cost::None => 0.0,
            Cost::Quadratic { weight } => 0.5 * weight * u.iter().map(|v| v * v).sum::<f64>(),
        }
    }
}

/// Problem data of (P) for a given crawler.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaitProblem {
    /// Period `T`.
    pub period: f64,
    /// Rate bounds `a_l` on `u_l = k_l L_l'` (force per time).
    pub rate_bound: Vec<f64>,
    /// Actuation cost.
    pub cost: Cost,
    /// Optional bound on the total variation of `u` over a period (Theorem 2.1's class U_K).
    pub max_total_variation: Option<f64>,
}

/// Largest ratio of two stiffnesses, or of two friction thresholds, the solvers accept: beyond
/// it the weakest link's (or block's) forces drown in the tolerances of the strongest.
pub const MAX_RATIO: f64 = 1e6;

/// Largest sweep ratio `a_l T / w_l` (how many times the rate bound can cross C's range `w_l`
/// of link `l` within a period) the solvers accept. The crossing of C then takes a fraction
/// `1 / (a T / w)` of the period; measured on the one-link problem (`a T / w = 10 k / 3`):
/// right up to 3e5, gaps of 1e-7 at 3e6, HiGHS solve errors at 3e7 and a wrong J = 0 at 3e9.
pub const MAX_SWEEP: f64 = 1e6;

/// Largest cost ratio `c a_l k_l` (the cost of moving link `l` at its rate bound against the
/// displacement that motion can buy) the solvers accept: beyond it the optimum is to stay
/// idle by a factor the cost's outer approximation cannot represent.
pub const MAX_COST_RATIO: f64 = 1e6;

fn positive(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, v, "must be positive and finite"))
    }
}

impl GaitProblem {
    /// The crawler's gait problem as (P) ([`crate::model::crawler_as_general`]): its period,
    /// rate bounds and cost on the crawler's instance (the TV bound, which (P) has not, stays
    /// the caller's).
    pub fn instance(&self, crawler: &Crawler) -> Result<crate::model::CrawlerInstance> {
        crate::model::crawler_as_general(crawler, self.period, &self.rate_bound, self.cost.into())
    }

    /// Builds and validates the problem for `crawler`: `max_actuator_speed` bounds `|L_l'|`, one
    /// per link, so `a_l = k_l * max_actuator_speed_l`.
    pub fn new(
        crawler: &Crawler,
        period: f64,
        max_actuator_speed: &[f64],
        cost: Cost,
        max_total_variation: Option<f64>,
    ) -> Result<Self> {
        positive("gait.period", period)?;
        if max_actuator_speed.len() != crawler.links() {
            return Err(Error::invalid(
                "gait.max_actuator_speed",
                format!("{} values", max_actuator_speed.len()),
                format!("needs a number or one value per link ({})", crawler.links()),
            ));
        }
        for (l, &s) in max_actuator_speed.iter().enumerate() {
            positive(&format!("gait.max_actuator_speed[{}]", l + 1), s)?;
        }
        if let Cost::Quadratic { weight } = cost {
            positive("gait.cost.weight", weight)?;
        }
        if let Some(tv) = max_total_variation {
            positive("gait.max_total_variation", tv)?;
        }
        let rate_bound: Vec<f64> = crawler
            .stiffness()
            .iter()
            .zip(max_actuator_speed)
            .map(|(k, s)| k * s)
            .collect();
        if let Some(l) = rate_bound.iter().position(|a| !a.is_finite()) {
            return Err(Error::invalid(
                format!("gait.max_actuator_speed[{}]", l + 1),
                max_actuator_speed[l],
                "times the stiffness overflows double precision",
            ));
        }
        Ok(GaitProblem {
            period,
            rate_bound,
            cost,
            max_total_variation,
        })
    }

    /// Refuses, naming the field and the supported range, an instance whose scale the LP/MILP
    /// solvers cannot honour with their tolerances (README, "Supported range"): stiffness,
    /// friction or rate-bound (`a_l = k_l` times the actuator's speed) ratios above
    /// [`MAX_RATIO`], a sweep ratio `a_l T / w_l` above [`MAX_SWEEP`], a
    /// cost ratio `c a_l k_l` above [`MAX_COST_RATIO`]. These are the dimensionless numbers of
    /// the problem: the units themselves (how large the forces, the period or the displacements
    /// are) are no limit, since the optimisers solve in internal units (`optimal::units`). The
    /// simulators and the one-link closed form are exact and need none of this; every optimiser
    /// calls it before building a model.
    pub fn check_scales(&self, crawler: &Crawler) -> Result<()> {
        self.validate(crawler)?;
        let out = |field: String, v: f64, why: String| Err(Error::invalid(field, v, why));
        let ratio = |v: &[f64]| {
            let (lo, hi) = v.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
            hi / lo
        };
        let mus = crawler.friction_thresholds();
        for (field, of, r) in [
            ("crawler.stiffness", "value", ratio(crawler.stiffness())),
            (
                "crawler.mu_forward, crawler.mu_backward",
                "value",
                ratio(&mus),
            ),
            (
                "gait.max_actuator_speed",
                "rate bound a_l = k_l x speed_l",
                ratio(&self.rate_bound),
            ),
        ] {
            if r > MAX_RATIO {
                return out(
                    field.into(),
                    r,
                    format!(
                        "the ratio of the largest to the smallest {of} exceeds {MAX_RATIO:e}, \
                         beyond which the optimisers' tolerances lose the weakest"
                    ),
                );
            }
        }
        let t = self.period;
        let k = crawler.stiffness();
        for (l, w) in crawler.link_force_ranges().iter().enumerate() {
            let sweep = self.rate_bound[l] * t / (w[1] - w[0]);
            let within = sweep <= MAX_SWEEP; // false for NaN and infinity too
            if !within {
                let sweep = if sweep.is_finite() {
                    format!("{sweep:.3e}")
                } else {
                    "more than 1e308".into()
                };
                return out(
                    format!("gait.max_actuator_speed[{}]", l + 1),
                    self.rate_bound[l] / k[l],
                    format!(
                        "with the stiffness and the period the actuator can sweep the force \
                         range of link {} {sweep} times per period (a T / w), above \
                         {MAX_SWEEP:e}: crossing C would take less of the period than the \
                         optimisers resolve (a slower actuator, a shorter period or softer \
                         springs)",
                        l + 1
                    ),
                );
            }
            if let Cost::Quadratic { weight } = self.cost {
                let q = weight * self.rate_bound[l] * k[l];
                let within = q <= MAX_COST_RATIO;
                if !within {
                    return out(
                        "gait.cost.weight".into(),
                        weight,
                        format!(
                            "the cost of link {} at its rate bound outweighs the displacement \
                         it buys by c a k = {q:.3e}, above {MAX_COST_RATIO:e}: the optimum \
                         is to stay idle, by a margin the solvers cannot represent",
                            l + 1
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    /// The problem's length unit: the smallest elongation `w_l / k_l` that crosses C's range
    /// of a link. Displacements and `J` are measured against it (the absolute gap of the
    /// MILPs is a small multiple of it).
    pub fn length_scale(&self, crawler: &Crawler) -> f64 {
        crawler
            .link_force_ranges()
            .iter()
            .zip(crawler.stiffness())
            .map(|(w, k)| (w[1] - w[0]) / k)
            .fold(f64::INFINITY, f64::min)
    }

    /// The floor of `J`'s scale for gaps and ties: the length unit ([`Self::length_scale`]),
    /// the unit the MILPs prove their answers in (they are solved in internal units, where it
    /// is 1: `optimal::units`), so that a crawler of tiny lengths compares relatively
    /// and every exact twin states the same gaps and makes the same choices. (Capped at 1, a
    /// gap stated over it could exceed what a reader accepts of a claim the MILP proved over
    /// the length unit: a phase claim at a length unit of 1000 was written with a gap of
    /// `2.2e-4` and refused by `certify`.)
    pub fn j_floor(&self, crawler: &Crawler) -> f64 {
        self.length_scale(crawler)
    }

    /// Checks problem data that did not come through [`GaitProblem::new`] (e.g. read back from
    /// a result file): one positive finite rate bound per link, positive period, weight and
    /// total-variation bound.
    pub fn validate(&self, crawler: &Crawler) -> Result<()> {
        positive("gait.period", self.period)?;
        if self.rate_bound.len() != crawler.links() {
            return Err(Error::invalid(
                "gait.rate_bound",
                format!("{} values", self.rate_bound.len()),
                format!("needs one value per link ({})", crawler.links()),
            ));
        }
        for (l, &a) in self.rate_bound.iter().enumerate() {
            positive(&format!("gait.rate_bound[{}]", l + 1), a)?;
        }
        if let Cost::Quadratic { weight } = self.cost {
            positive("gait.cost.weight", weight)?;
        }
        if let Some(tv) = self.max_total_variation {
            positive("gait.max_total_variation", tv)?;
        }
        Ok(())
    }
}
