//! The crawler as an instance of the general problem (P) (theory §11), exactly.
//!
//! The crawler's sweeping process `x' in u - K N_C(x)` (theory §3) is Euclidean after the change
//! of variables `x = K^(1/2) x~`: `x~' in K^(-1/2) u - N_{C~}(x~)` with
//! `C~ = K^(-1/2) C = {x~ : <K^(1/2) nu_b, x~> <= mu_b^+, <-K^(1/2) nu_b, x~> <= mu_b^-}`,
//! since `N_{C~}(x~) = K^(1/2) N_C(K^(1/2) x~)`. So `n = N - 1`, `A = 0`, `B = K^(-1/2)`,
//! `b = 0`, `U = [-a, a]` and the faces come in pairs per block `b` (forward `b+` first), with
//! `K^(1/2) nu_b = sqrt(k_(b-1)) e_(b-1) - sqrt(k_b) e_b` of length
//! `s_b = sqrt(k_(b-1) + k_b)` (`k_0 = k_N = 0` in 1-based links: end blocks have one link).
//!
//! Face weights of the barycentre's displacement. The catching-up step of the crawler is
//! `K^(-1)(v - x+) = sum_b (lambda_b^+ - lambda_b^-) nu_b` with block displacements
//! `D_b = lambda_b^+ - lambda_b^-` (theory §4). In `x~`, `v~ - x~+ = K^(-1/2)(v - x+) =
//! sum_b (lambda_b^+ - lambda_b^-) K^(1/2) nu_b = sum_b s_b (lambda_b^+ x*_(b+) + lambda_b^- x*_(b-))`
//! with the unit normals `x*_(b+-) = +-K^(1/2) nu_b / s_b`, so the multipliers of the unit rows
//! are `mu_(b+-) = s_b lambda_b^+-` and `D_b = (mu_(b+) - mu_(b-)) / s_b`. The displacement
//! `(1/N) sum_b D_b` is therefore `f1` with face weights `w_(b+) = 1 / (N s_b)`,
//! `w_(b-) = -1 / (N s_b)` (for `k = 1`: `+-1/(N sqrt 2)` inside, `+-1/N` at the ends).

use super::general::{GeneralCost, GeneralParts, GeneralProblem};
use super::Crawler;
use crate::error::Result;

/// A crawler's general form and the change of variables.
#[derive(Debug, Clone, PartialEq)]
pub struct CrawlerInstance {
    /// The problem (P) in the variables `x~ = K^(-1/2) x`.
    pub problem: GeneralProblem,
    /// `sqrt(k_l)`.
    pub sqrt_k: Vec<f64>,
}

impl CrawlerInstance {
    /// `x~ = K^(-1/2) x`.
    pub fn to_general(&self, x: &[f64]) -> Vec<f64> {
        x.iter().zip(&self.sqrt_k).map(|(x, s)| x / s).collect()
    }

    /// `x = K^(1/2) x~`.
    pub fn to_crawler(&self, xt: &[f64]) -> Vec<f64> {
        xt.iter().zip(&self.sqrt_k).map(|(x, s)| x * s).collect()
    }
}

/// `s_b = |K^(1/2) nu_b| = sqrt(k_(b-1) + k_b)` per block (`k` of the missing link of an end
/// block 0): the norm of block `b`'s rows in the instance ([`crawler_as_general`]), by which its
/// unit rows' reactions and multipliers differ from the crawler's (in the units of `nu_b`):
/// `L_(b+-) = s_b max(+-D_b, 0)` for a block displacement `D_b`, `xi~ = s_b xi`.
pub fn crawler_row_norms(k: &[f64]) -> Vec<f64> {
    (0..=k.len())
        .map(|b| (b.checked_sub(1).map_or(0.0, |l| k[l]) + k.get(b).copied().unwrap_or(0.0)).sqrt())
        .collect()
}

/// The crawler's gait problem as (P): period `T`, rate bounds `a_l` (`|u_l| <= a_l`), cost `f2`
/// of `u` (unchanged: the control is the crawler's), periodic with zero-mean controls.
pub fn crawler_as_general(
    c: &Crawler,
    period: f64,
    rate_bounds: &[f64],
    cost: GeneralCost,
) -> Result<CrawlerInstance> {
    let (nb, n) = (c.blocks(), c.links());
    let sqrt_k: Vec<f64> = c.stiffness().iter().map(|k| k.sqrt()).collect();
    let s_b = crawler_row_norms(c.stiffness());
    let mut normals = Vec::with_capacity(2 * nb);
    let mut offsets = Vec::with_capacity(2 * nb);
    let mut weights = Vec::with_capacity(2 * nb);
    for b in 0..nb {
        // K^(1/2) nu_b with nu_b = e_(b-1) - e_b (links 0-based: link b-1 behind, b in front).
        let mut row = vec![0.0; n];
        if b >= 1 {
            row[b - 1] = sqrt_k[b - 1];
        }
        if b < n {
            row[b] = -sqrt_k[b];
        }
        let s = s_b[b];
        let w = 1.0 / (nb as f64 * s);
        normals.push(row.clone());
        offsets.push(c.mu_forward()[b]);
        weights.push(w);
        normals.push(row.iter().map(|v| -v).collect());
        offsets.push(c.mu_backward()[b]);
        weights.push(-w);
    }
    let b_mat = (0..n)
        .map(|l| {
            (0..n)
                .map(|k| if k == l { 1.0 / sqrt_k[l] } else { 0.0 })
                .collect()
        })
        .collect();
    let problem = GeneralProblem::new(GeneralParts {
        normals,
        offsets,
        b: b_mat,
        lower: Some(rate_bounds.iter().map(|a| -a).collect()),
        upper: Some(rate_bounds.to_vec()),
        zero_mean: true,
        face_weights: Some(weights),
        cost: Some(cost),
        period,
        periodic: true,
        ..Default::default()
    })?;
    Ok(CrawlerInstance { problem, sqrt_k })
}
