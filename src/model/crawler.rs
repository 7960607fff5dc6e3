//! Crawler parameters (theory §1) with validation.

use crate::error::{Error, Result};
use crate::model::uniqueness::Uniqueness;

/// A chain of `N >= 2` blocks joined by `n = N - 1` links (spring in series with an actuator),
/// with direction-dependent dry friction on every block (theory §1, paper §3.2).
///
/// Units: lengths in any unit L, forces in any unit F, so stiffness is F/L and friction
/// thresholds are F; the state `x` (link compression) is in F.
#[derive(Debug, Clone, PartialEq)]
pub struct Crawler {
    stiffness: Vec<f64>,
    mu_forward: Vec<f64>,
    mu_backward: Vec<f64>,
    uniqueness: Uniqueness,
}

fn check_positive(field: &str, values: &[f64]) -> Result<()> {
    for (i, &v) in values.iter().enumerate() {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(
                format!("{field}[{}]", i + 1),
                v,
                "must be positive and finite",
            ));
        }
    }
    Ok(())
}

impl Crawler {
    /// Builds a crawler from per-link stiffness `k_l` and per-block friction thresholds
    /// `mu_b^+` (against forward motion) and `mu_b^-` (against backward motion).
    ///
    /// Checks lengths, positivity and finiteness, and decides the uniqueness condition
    /// (paper eq. 3.6) once; the result is kept in [`Crawler::uniqueness`]. A crawler that fails
    /// it can still be built and analysed, but [`Crawler::require_unique`] refuses it, and every
    /// simulator calls that.
    pub fn new(stiffness: Vec<f64>, mu_forward: Vec<f64>, mu_backward: Vec<f64>) -> Result<Self> {
        let nb = mu_forward.len();
        if nb < 2 {
            return Err(Error::invalid(
                "crawler.blocks",
                nb,
                "a crawler needs at least 2 blocks",
            ));
        }
        if mu_backward.len() != nb {
            return Err(Error::invalid(
                "crawler.mu_backward",
                format!("{} values", mu_backward.len()),
                format!("needs one value per block ({nb})"),
            ));
        }
        if stiffness.len() != nb - 1 {
            return Err(Error::invalid(
                "crawler.stiffness",
                format!("{} values", stiffness.len()),
                format!("needs one value per link ({})", nb - 1),
            ));
        }
        check_positive("crawler.stiffness", &stiffness)?;
        check_positive("crawler.mu_forward", &mu_forward)?;
        check_positive("crawler.mu_backward", &mu_backward)?;
        let total: f64 = mu_forward.iter().chain(&mu_backward).sum::<f64>()
            + stiffness.iter().map(|k| 1.0 / k).sum::<f64>();
        if !total.is_finite() || stiffness.iter().any(|k| !(1.0 / k).is_normal()) {
            return Err(Error::invalid(
                "crawler",
                "extreme values",
                "the sums of friction thresholds or of 1/stiffness overflow double precision",
            ));
        }
        let uniqueness = Uniqueness::decide(&mu_forward, &mu_backward);
        Ok(Crawler {
            stiffness,
            mu_forward,
            mu_backward,
            uniqueness,
        })
    }

    /// A crawler with the same stiffness on every link and the same friction on every block.
    pub fn uniform(blocks: usize, k: f64, mu_forward: f64, mu_backward: f64) -> Result<Self> {
        Self::new(
            vec![k; blocks.saturating_sub(1)],
            vec![mu_forward; blocks],
            vec![mu_backward; blocks],
        )
    }

    /// Number of blocks `N`.
    pub fn blocks(&self) -> usize {
        self.mu_forward.len()
    }

    /// Number of links `n = N - 1` (the dimension of the state space).
    pub fn links(&self) -> usize {
        self.stiffness.len()
    }

    /// Link stiffness `k_l`.
    pub fn stiffness(&self) -> &[f64] {
        &self.stiffness
    }

    /// Friction thresholds `mu_b^+` against forward motion.
    pub fn mu_forward(&self) -> &[f64] {
        &self.mu_forward
    }

    /// Friction thresholds `mu_b^-` against backward motion.
    pub fn mu_backward(&self) -> &[f64] {
        &self.mu_backward
    }

    /// Every friction threshold, `mu^+` of each block then `mu^-` of each block.
    pub fn friction_thresholds(&self) -> Vec<f64> {
        self.mu_forward
            .iter()
            .chain(&self.mu_backward)
            .copied()
            .collect()
    }

    /// The outcome of the uniqueness check (paper eq. 3.6), decided at construction.
    pub fn uniqueness(&self) -> &Uniqueness {
        &self.uniqueness
    }

    /// `Ok` when the uniqueness condition holds; the error names the violating subset otherwise.
    pub fn require_unique(&self) -> Result<()> {
        match &self.uniqueness {
            Uniqueness::Holds { .. } => Ok(()),
            Uniqueness::Fails { subset } => {
                let (forward_sum, backward_sum) = self.subset_sums(subset);
                Err(Error::NonUnique {
                    subset: subset.iter().map(|b| b + 1).collect(),
                    forward_sum,
                    backward_sum,
                })
            }
            Uniqueness::Undecided { reason } => Err(Error::UniquenessUndecided(reason.clone())),
        }
    }

    /// `(sum_{b in J} mu_b^+, sum_{b not in J} mu_b^-)` for a subset `J` of 0-based blocks.
    pub fn subset_sums(&self, subset: &[usize]) -> (f64, f64) {
        let mut inside = vec![false; self.blocks()];
        for &b in subset {
            inside[b] = true;
        }
        let fwd = subset.iter().map(|&b| self.mu_forward[b]).sum();
        let bwd = (0..self.blocks())
            .filter(|&b| !inside[b])
            .map(|b| self.mu_backward[b])
            .sum();
        (fwd, bwd)
    }

    /// A scale of forces in C (the largest friction threshold), used for relative tolerances.
    pub fn force_scale(&self) -> f64 {
        self.mu_forward
            .iter()
            .chain(&self.mu_backward)
            .fold(0.0_f64, |m, &v| m.max(v))
    }
}
