//! Structure recognised in a general problem (P) (theory §11), once, the way a conic solver
//! recognises a run of cones it can treat faster: whether (P) is a crawler's gait problem in
//! disguise ([`GeneralProblem::as_chain`]), which selects the chain's kernels and stronger
//! formulations for it.
//!
//! **The chain.** [`super::crawler_as_general`] writes a crawler of `N` blocks as (P) in the
//! variables `x~ = K^(-1/2) x`: `n = m = N - 1`, `A = 0`, `b = 0`, `B = K^(-1/2)` (diagonal),
//! `U = [-a, a]` with zero mean, periodic, and two faces per block `b` with unit normals
//! `+-(e_(b-1) / beta_(b-1) - e_b / beta_b) / s_b` (`beta_l = 1 / sqrt(k_l)`, the diagonal of
//! `B`; `s_b` the norm of the bracket; an end block has one term), offsets `mu_b^+- / s_b` and
//! face weights `+-1 / (N s_b)` (`f1` the barycentre's displacement). The recogniser inverts
//! that map for any order of the faces and any positive scale `lambda` of the objective:
//! weights `+-lambda / (N s_b)` and a quadratic cost `f2 = (c/2)|u|^2` are the crawler's problem
//! with `J = lambda J_crawler` and cost weight `c / lambda`. Everything else about the problem
//! must match within a relative `1e-12`; anything that does not (a drift, a polytope U, a face
//! that is not a block's, a weight off the pattern, a matrix cost) is not a chain.

use super::general::{Boundary, GeneralCost, GeneralProblem};
use super::general_sets::Polyhedron;
use super::general_sets::{ControlSet, Reward};
use super::Crawler;
use crate::error::{Error, Result};

/// Relative tolerance of the recognition (the map's own round-off is about `1e-16`).
const MATCH_TOL: f64 = 1e-12;

/// A general problem recognised as a crawler's gait problem ([`GeneralProblem::as_chain`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ChainView {
    /// The crawler: stiffness `1 / beta_l^2`, friction thresholds `s_b c_(b+-)`.
    pub crawler: Crawler,
    /// Its rate bounds `a_l` (the box U).
    pub rate_bounds: Vec<f64>,
    /// `lambda > 0`: the general objective is `lambda` times the crawler's.
    pub objective_scale: f64,
    /// The crawler's cost weight `c / lambda` (`None` without a cost).
    pub cost_weight: Option<f64>,
    /// For each block `b`, the general faces (0-based) of its forward and backward thresholds.
    pub faces: Vec<[usize; 2]>,
}

/// C's faces matched to a chain's blocks ([`GeneralProblem::as_chain`]).
struct ChainFaces {
    /// For each block, its forward and backward faces.
    faces: Vec<[usize; 2]>,
    /// For each block, its thresholds `mu_b^+` and `mu_b^-`.
    mu: Vec<[f64; 2]>,
    /// The objective's scale `lambda > 0`.
    lambda: f64,
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= MATCH_TOL * a.abs().max(b.abs()).max(1e-300)
}

impl GeneralProblem {
    /// The crawler whose gait problem this is, when it is one (module docs); `None` otherwise.
    pub fn as_chain(&self) -> Option<ChainView> {
        let (beta, rate_bounds) = self.chain_dynamics()?;
        let n = beta.len();
        let blocks = n + 1;
        if self.c.faces() != 2 * blocks {
            return None;
        }
        let ChainFaces { faces, mu, lambda } = self.chain_faces(&beta)?;
        let cost_weight = match &self.cost {
            GeneralCost::None => None,
            GeneralCost::Quadratic { weight } if *weight == 0.0 => None,
            GeneralCost::Quadratic { weight } => Some(weight / lambda),
            GeneralCost::Matrix { .. } => return None,
        };
        let stiffness = beta.iter().map(|b| 1.0 / (b * b)).collect();
        let crawler = Crawler::new(
            stiffness,
            mu.iter().map(|m| m[0]).collect(),
            mu.iter().map(|m| m[1]).collect(),
        )
        .ok()?;
        Some(ChainView {
            crawler,
            rate_bounds,
            objective_scale: lambda,
            cost_weight,
            faces,
        })
    }

    /// The chain's dynamics, when (P)'s are a chain's: `beta_l = 1 / sqrt(k_l)` (the positive
    /// diagonal of `B`, with `A = 0`, no drift, `m = n`, periodic, zero-mean controls) and the
    /// rate bounds `a_l` of a symmetric box U; `None` otherwise.
    fn chain_dynamics(&self) -> Option<(Vec<f64>, Vec<f64>)> {
        let n = self.states();
        let d = &self.dynamics;
        if n == 0
            || self.controls() != n
            || !self.zero_mean
            || self.boundary != Boundary::Periodic
            || d.a.iter().flatten().any(|&v| v != 0.0)
            || d.drift.iter().any(|&v| v != 0.0)
        {
            return None;
        }
        // B diagonal and positive: beta_l = 1 / sqrt(k_l).
        let mut beta = Vec::with_capacity(n);
        for (l, row) in d.b.iter().enumerate() {
            if row.iter().enumerate().any(|(k, &v)| k != l && v != 0.0) || row[l] <= 0.0 {
                return None;
            }
            beta.push(row[l]);
        }
        let rate_bounds = match &self.control {
            ControlSet::Box { lower, upper }
                if lower
                    .iter()
                    .zip(upper)
                    .all(|(lo, up)| *up > 0.0 && close(-lo, *up)) =>
            {
                upper.clone()
            }
            _ => return None,
        };
        Some((beta, rate_bounds))
    }

    /// C's faces matched to the chain's blocks (`beta` from [`Self::chain_dynamics`]): for each
    /// block its forward and backward faces, its thresholds `mu_b^+-` (offset times `s_b`), and
    /// the objective's common scale `lambda` (weights `+-lambda / (N s_b)`); `None` when a face
    /// is not a block's, a block lacks one of its two, or a weight is off the pattern.
    fn chain_faces(&self, beta: &[f64]) -> Option<ChainFaces> {
        let n = beta.len();
        let blocks = n + 1;
        // Each block's bracket e_(b-1) / beta_(b-1) - e_b / beta_b and its norm s_b.
        let bracket = |b: usize| -> Vec<f64> {
            let mut r = vec![0.0; n];
            if b >= 1 {
                r[b - 1] = 1.0 / beta[b - 1];
            }
            if b < n {
                r[b] = -1.0 / beta[b];
            }
            r
        };
        let weights = match &self.reward {
            Reward::FaceWeights(w) => w.clone(),
            Reward::ReactionWeights(q) => self
                .c
                .normals
                .iter()
                .map(|x| x.iter().zip(q).map(|(a, b)| a * b).sum())
                .collect(),
        };
        let mut faces: Vec<[Option<usize>; 2]> = vec![[None, None]; blocks];
        let mut mu = vec![[0.0_f64; 2]; blocks];
        let mut lambda: Option<f64> = None;
        for (f, x) in self.c.normals.iter().enumerate() {
            // The blocks whose brackets have this face's support: {b - 1, b} for an inner block;
            // one entry, 0 or n - 1, for an end block (with one link both ends have entry 0,
            // and the weight's sign tells forward from backward).
            let support: Vec<usize> = (0..n).filter(|&l| x[l] != 0.0).collect();
            let candidates: Vec<usize> = match support[..] {
                [i, j] if j == i + 1 => vec![j],
                [i] => [(i == 0).then_some(0), (i + 1 == n).then_some(n)]
                    .into_iter()
                    .flatten()
                    .collect(),
                _ => return None,
            };
            let forward = weights[f] > 0.0;
            let (b, dir, s) = candidates.into_iter().find_map(|b| {
                let br = bracket(b);
                let s = br.iter().map(|v| v * v).sum::<f64>().sqrt();
                let dir = if x.iter().zip(&br).all(|(a, c)| close(*a, c / s)) {
                    0
                } else if x.iter().zip(&br).all(|(a, c)| close(*a, -c / s)) {
                    1
                } else {
                    return None;
                };
                (forward == (dir == 0)).then_some((b, dir, s))
            })?;
            if faces[b][dir].replace(f).is_some() {
                return None;
            }
            mu[b][dir] = self.c.offsets[f] * s;
            // w = +-lambda / (N s_b).
            let l = weights[f] * blocks as f64 * s * if dir == 0 { 1.0 } else { -1.0 };
            match lambda {
                None if l > 0.0 => lambda = Some(l),
                Some(l0) if close(l, l0) => {}
                _ => return None,
            }
        }
        let lambda = lambda?;
        let faces: Vec<[usize; 2]> = faces
            .into_iter()
            .map(|p| Some([p[0]?, p[1]?]))
            .collect::<Option<_>>()?;
        Some(ChainFaces { faces, mu, lambda })
    }
}

impl ChainView {
    /// Whether face weights define `f1` uniquely on this chain, decided by its structure in
    /// place of C's vertex enumeration (exponential in `N`): the active faces at a state are
    /// the thresholds reached, at most one per block (both would need `mu_b^+ = -mu_b^-`), and
    /// their normals `+-K^(1/2) nu_b / s_b` are dependent only when all `N` blocks are at a
    /// threshold (`sum_b nu_b = 0`), i.e. when `sum_(b in J) mu_b^+ = sum_(b not in J) mu_b^-`
    /// for some subset `J`: exactly what the crawler's uniqueness condition (paper eq. 3.6)
    /// excludes. The error names `objective.face_weights` with the violating subset.
    pub fn check_face_weights(&self) -> Result<()> {
        self.crawler.require_unique().map_err(|e| {
            Error::invalid(
                "objective.face_weights",
                format!("a chain of {} blocks", self.crawler.blocks()),
                format!(
                    "are not well defined: every block can be at a threshold at once, where the \
                     active normals are dependent ({e}); use reaction_weights or change a \
                     threshold"
                ),
            )
        })
    }

    /// The least singular value of the active normals over every state of C (the big-M of a
    /// reaction's multipliers divides by it), without enumerating C's vertices: under the
    /// uniqueness condition ([`Self::check_face_weights`]) every active set is a subset of the
    /// faces of `N - 1` blocks, one face each; a face's sign and dropping rows do not lower a
    /// least singular value, so the minimum over the `N` sets "every block but `b`" (forward
    /// faces) bounds it from below. `O(N^4)`: for the MILPs, whose own size limits `N`.
    pub fn least_active_singular_value(&self, c: &Polyhedron) -> f64 {
        let blocks = self.faces.len();
        (0..blocks)
            .map(|omit| {
                let rows: Vec<usize> = (0..blocks)
                    .filter(|&b| b != omit)
                    .map(|b| self.faces[b][0])
                    .collect();
                c.least_singular_value(&rows)
            })
            .fold(f64::INFINITY, f64::min)
    }
}
