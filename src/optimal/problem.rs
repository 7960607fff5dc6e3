//! The gait problem (P) (SPEC §5, paper eqs. 2.4–2.5, §3.4): given the period `T`, rate bounds
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

fn positive(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, v, "must be positive and finite"))
    }
}

impl GaitProblem {
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
