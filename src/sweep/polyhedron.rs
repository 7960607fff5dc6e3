//! The exact Euclidean projection onto a general polyhedron `C = {x : <x*_j, x> <= c_j}` with
//! unit normals (theory §11): `Proj_C(v) = argmin_{x in C} (1/2)|x - v|^2`.
//!
//! A primal active-set method: from a feasible point `x` and a working set `W` of faces active
//! there (linearly independent), the equality-constrained problem on `W` is solved exactly,
//! `z = v - N_W^T mu` with `(N_W N_W^T) mu = N_W v - c_W`; the step toward `z` stops at the first
//! face it would cross (added to `W`), and at `z` a face with a negative multiplier leaves `W`.
//! A face that blocks a step is independent of `W` (the step keeps `N_W x` fixed and crosses
//! it), so `N_W N_W^T` stays positive definite. A multiplier in `(-1e-14 s, 0)` (`s` the
//! largest of `|v|`, the point's and the working faces' offsets: the numbers it is made of, not
//! C's scale) counts as zero (clamped to it in the answer): dropping its face would cycle
//! between adding and dropping a face through the answer. Faces nearly parallel to each other
//! may still cycle (a multiplier rounded beyond that margin by the ill-conditioned
//! `N_W N_W^T`); the budget then ends it with an error, never an answer. The answer is the
//! solution of the KKT system of the final active set, so its residual is that of one small
//! dense solve (the tests ask `<= 1e-12` relative to `max(|v|, max_j |c_j|)`), not an
//! interior-point tolerance.
//!
//! The catching-up scheme warm-starts each step from the previous point and working set: the
//! previous projection is feasible and lies on those faces.

use crate::error::{Error, Result};
use crate::model::general::{dot, Polyhedron};
use nalgebra::{DMatrix, DVector};

/// A projection onto C and its certificate.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Projection {
    /// `Proj_C(v)`.
    pub x: Vec<f64>,
    /// The multiplier of every face: `v - x = sum_j mu_j x*_j`, `mu >= 0`, zero off `active`.
    pub mu: Vec<f64>,
    /// The final working set (faces, 0-based).
    pub active: Vec<usize>,
    /// The KKT residual: the largest of stationarity, primal and dual infeasibility and
    /// complementarity, each in absolute terms.
    pub residual: f64,
    /// Active-set iterations.
    pub iterations: usize,
}

/// The projector onto one polyhedron, keeping the working set between calls (warm start).
#[derive(Debug, Clone)]
pub struct PolyProjector {
    c: Polyhedron,
    working: Vec<usize>,
}

impl PolyProjector {
    /// A projector onto `c`.
    pub fn new(c: Polyhedron) -> Self {
        PolyProjector { c, working: vec![] }
    }

    /// The polyhedron.
    pub fn polyhedron(&self) -> &Polyhedron {
        &self.c
    }

    /// Forgets the working set (the next start point is then taken with no face held).
    pub fn reset(&mut self) {
        self.working.clear();
    }

    /// `Proj_C(v)` starting from `start`, a point of C (within rounding) on which the faces of
    /// the current working set are active (the previous answer, or any point of C after
    /// [`PolyProjector::reset`]).
    pub fn project(&mut self, start: &[f64], v: &[f64]) -> Result<Projection> {
        let c = &self.c;
        let (sigma, n) = (c.faces(), c.dim());
        let mut x = start.to_vec();
        let mut w = std::mem::take(&mut self.working);
        let budget = 20 * (sigma + n) + 100;
        // A multiplier above `-tiny` is a rounding of zero: dropping its face would let the
        // step back cross it at `alpha = 0` and cycle (a face through the answer whose
        // multiplier is zero in exact arithmetic). The rounding is of the numbers it is made
        // of, `v`, the point and the working faces' offsets, not of C's scale: `1e-14` of
        // that held the face x <= 1 of C = [-1e13, 1] against a step of -0.01 inward (a
        // multiplier of -0.01 above -0.1), and catching-up never left the face.
        let largest = |u: &[f64]| u.iter().fold(0.0_f64, |s, a| s.max(a.abs()));
        let v_size = largest(v);
        for it in 1..=budget {
            let offsets = w.iter().fold(0.0_f64, |s, &j| s.max(c.offsets[j].abs()));
            let tiny = 1e-14 * offsets.max(v_size).max(largest(&x));
            let (z, mu) = equality_solution(c, &w, v)?;
            // The step x -> z, stopped by the first face outside W that it would cross.
            let d: Vec<f64> = z.iter().zip(&x).map(|(a, b)| a - b).collect();
            let mut block: Option<(usize, f64)> = None;
            for j in (0..sigma).filter(|j| !w.contains(j)) {
                let nd = dot(&c.normals[j], &d);
                if nd <= 0.0 {
                    continue;
                }
                let alpha = ((c.offsets[j] - dot(&c.normals[j], &x)) / nd).max(0.0);
                if alpha < 1.0 && block.is_none_or(|(_, a)| alpha < a) {
                    block = Some((j, alpha));
                }
            }
            if let Some((j, alpha)) = block {
                if w.len() < n {
                    for (xi, di) in x.iter_mut().zip(&d) {
                        *xi += alpha * di;
                    }
                    w.push(j);
                    continue;
                }
            }
            x = z;
            match mu
                .iter()
                .enumerate()
                .filter(|(_, m)| **m < -tiny)
                .min_by(|a, b| a.1.total_cmp(b.1))
            {
                Some((k, _)) => {
                    w.remove(k);
                }
                None => {
                    let mut full = vec![0.0; sigma];
                    for (k, &j) in w.iter().enumerate() {
                        full[j] = mu[k].max(0.0);
                    }
                    let residual = kkt_residual(c, v, &x, &full);
                    self.working = w.clone();
                    return Ok(Projection {
                        x,
                        mu: full,
                        active: w,
                        residual,
                        iterations: it,
                    });
                }
            }
        }
        Err(Error::Numerical(format!(
            "projection onto C: no active set found in {budget} iterations (degenerate \
             faces cycling)"
        )))
    }
}

/// `z = argmin |z - v|^2` s.t. `<x*_j, z> = c_j` for `j in w`, and its multipliers.
fn equality_solution(c: &Polyhedron, w: &[usize], v: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
    if w.is_empty() {
        return Ok((v.to_vec(), vec![]));
    }
    let k = w.len();
    let gram = DMatrix::from_fn(k, k, |a, b| dot(&c.normals[w[a]], &c.normals[w[b]]));
    let rhs = DVector::from_iterator(k, w.iter().map(|&j| dot(&c.normals[j], v) - c.offsets[j]));
    let mu = gram.cholesky().map(|ch| ch.solve(&rhs)).ok_or_else(|| {
        Error::Numerical(
            "projection onto C: the active normals became dependent (a degenerate vertex)".into(),
        )
    })?;
    let mut z = v.to_vec();
    for (a, &j) in w.iter().enumerate() {
        for (zi, ni) in z.iter_mut().zip(&c.normals[j]) {
            *zi -= mu[a] * ni;
        }
    }
    Ok((z, mu.iter().copied().collect()))
}

/// The KKT residual of `x = Proj_C(v)` with multipliers `mu` (one per face).
pub fn kkt_residual(c: &Polyhedron, v: &[f64], x: &[f64], mu: &[f64]) -> f64 {
    let mut r = 0.0_f64;
    for i in 0..x.len() {
        let s: f64 = (0..c.faces()).map(|j| mu[j] * c.normals[j][i]).sum();
        r = r.max((v[i] - x[i] - s).abs());
    }
    for j in 0..c.faces() {
        let slack = c.slack(j, x);
        r = r.max(slack.max(0.0)).max((-mu[j]).max(0.0));
        r = r.max((mu[j] * slack).abs());
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projections_onto_a_square() {
        let c = Polyhedron::new(
            vec![
                vec![1.0, 0.0],
                vec![0.0, 1.0],
                vec![-1.0, 0.0],
                vec![0.0, -1.0],
            ],
            vec![1.0; 4],
            "C",
        )
        .unwrap();
        let mut p = PolyProjector::new(c);
        let a = p.project(&[0.0, 0.0], &[3.0, 0.5]).unwrap();
        assert_eq!(a.x, vec![1.0, 0.5]);
        assert_eq!(a.mu, vec![2.0, 0.0, 0.0, 0.0]);
        // Warm start from there into the corner, then back inside (the face is released).
        let a = p.project(&a.x.clone(), &[2.0, 4.0]).unwrap();
        assert_eq!(a.x, vec![1.0, 1.0]);
        assert_eq!(a.mu, vec![1.0, 3.0, 0.0, 0.0]);
        let a = p.project(&a.x.clone(), &[0.5, -0.25]).unwrap();
        assert_eq!(a.x, vec![0.5, -0.25]);
        assert!(a.active.is_empty() && a.residual == 0.0);
    }
}
