//! The dynamics of the sweeping process face by face (theory §3), as the finitely many motions the
//! storage-function LP must dominate.
//!
//! On the relative interior of a face `F` of C with active signed normals `n_j = s_j nu_{b_j}`
//! (offsets `c_j`), the state stays on `F` exactly for the controls `u` whose reaction
//! multipliers are non-negative, `lambda(u) = G^{-1} N^T u >= 0` with `G = N^T K N` (invertible:
//! under the uniqueness condition any `n` of the `nu_b` are independent, and at most `n` faces are
//! active). For those controls
//!
//! ```text
//! x' = u - K N lambda(u),   l' = K^{-1} u,   y' = (1/N) sum_j s_j lambda_j(u),
//! ```
//!
//! all linear in `u` on the polytope `U_F = { |u_l| <= a_l, lambda(u) >= 0 }`, so an inequality
//! linear in `(x', l', y')` holds on all of `U_F` iff it holds at its vertices, which are listed
//! here ([`FaceMotion::controls`]). The interior of C is the face with no active normal
//! (`x' = u`, `y' = 0`, `U_F` the whole box).

use crate::model::Crawler;
use nalgebra::{DMatrix, DVector};

/// One active half-space of a face: `<n, x> <= c` held with equality, `n = sign * nu_block`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Active {
    /// Block index (0-based).
    pub block: usize,
    /// `+1` (block slides forward against `mu^+`) or `-1` (backward against `mu^-`).
    pub sign: f64,
    /// Offset `c`: `mu^+_b` or `mu^-_b`.
    pub offset: f64,
}

/// A face of C and the motions on its relative interior.
#[derive(Debug, Clone)]
pub(crate) struct FaceMotion {
    /// The active half-spaces (empty: the interior of C).
    #[allow(dead_code)]
    pub active: Vec<Active>,
    /// For each vertex `u` of `U_F`: the direction `(x', l')` (length `2n`) and `y'`.
    pub controls: Vec<(Vec<f64>, f64)>,
}

/// `n_j`: the signed normal of an active half-space, `sign * (e_{b-1} - e_b)`.
pub(crate) fn normal(n: usize, a: &Active) -> Vec<f64> {
    let mut v = vec![0.0; n];
    if a.block > 0 {
        v[a.block - 1] = a.sign;
    }
    if a.block < n {
        v[a.block] = -a.sign;
    }
    v
}

/// The half-spaces of C, forward face of block 1 first (all `2N`, facets or not).
pub(crate) fn half_spaces(crawler: &Crawler) -> Vec<Active> {
    let mut out = Vec::with_capacity(2 * crawler.blocks());
    for b in 0..crawler.blocks() {
        out.push(Active {
            block: b,
            sign: 1.0,
            offset: crawler.mu_forward()[b],
        });
        out.push(Active {
            block: b,
            sign: -1.0,
            offset: crawler.mu_backward()[b],
        });
    }
    out
}

/// Every face of C (the interior included) with the half-spaces active on its relative
/// interior. A non-empty face is the convex hull of the vertices of C it contains, so its
/// active set is the intersection of theirs; faces are generated from the subsets of each
/// vertex's active set (`n` half-spaces, `2^n` subsets) and closed that way.
pub(crate) fn faces(crawler: &Crawler, tol: f64) -> Vec<Vec<usize>> {
    let n = crawler.links();
    let hs = half_spaces(crawler);
    let vertex_sets: Vec<Vec<usize>> = crawler
        .vertices()
        .iter()
        .map(|v| {
            (0..hs.len())
                .filter(|&j| (dot(&normal(n, &hs[j]), v) - hs[j].offset).abs() <= tol)
                .collect()
        })
        .collect();
    let mut out: Vec<Vec<usize>> = Vec::new();
    for set in &vertex_sets {
        for mask in 0u32..(1u32 << set.len()) {
            let sub: Vec<usize> = (0..set.len())
                .filter(|i| mask >> i & 1 == 1)
                .map(|i| set[i])
                .collect();
            let closure: Vec<usize> = (0..hs.len())
                .filter(|j| {
                    vertex_sets
                        .iter()
                        .filter(|s| sub.iter().all(|k| s.contains(k)))
                        .all(|s| s.contains(j))
                })
                .collect();
            if !out.contains(&closure) {
                out.push(closure);
            }
        }
    }
    out
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The quadratic cost `f2(u) = (c/2) |u|^2` as the LP sees it: per link, the largest of the
/// tangents of `(c/2) u_l^2` at the centres of `tangents` equal cells of `[-a_l, a_l]`, a
/// piecewise-linear under-estimator (convexity) that is affine on each cell and below `f2` by
/// at most `c a_l^2 / (2 tangents^2)` per link. `weight = 0`: no cost.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CostModel {
    pub weight: f64,
    pub tangents: usize,
}

impl CostModel {
    /// Cells per link of the control box on which the under-estimator is affine.
    fn cells(&self) -> usize {
        if self.weight > 0.0 {
            self.tangents.max(1)
        } else {
            1
        }
    }

    /// The under-estimator at `u` (0 without a cost).
    pub fn under(&self, rate: &[f64], u: &[f64]) -> f64 {
        if self.weight <= 0.0 {
            return 0.0;
        }
        let m = self.cells() as f64;
        u.iter()
            .zip(rate)
            .map(|(&v, &a)| {
                (0..self.cells())
                    .map(|i| {
                        let centre = -a + a * (2 * i + 1) as f64 / m;
                        self.weight * centre * (v - 0.5 * centre)
                    })
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .sum()
    }
}

/// The motions on the face with active half-spaces `active` (indices into [`half_spaces`]);
/// with a cost, `y'` is replaced by `y' - f2_low(u)` and the controls are the vertices of `U_F`
/// cut by each cell of the cost's under-estimator (on each cut the row is affine in `u`).
pub(crate) fn face_motion(
    crawler: &Crawler,
    rate: &[f64],
    active: &[usize],
    cost: CostModel,
) -> FaceMotion {
    let n = crawler.links();
    let nb = crawler.blocks() as f64;
    let k = crawler.stiffness();
    let hs = half_spaces(crawler);
    let act: Vec<Active> = active.iter().map(|&j| hs[j].clone()).collect();
    let m = act.len();
    let nmat = DMatrix::from_fn(n, m, |i, j| normal(n, &act[j])[i]);
    let kn = DMatrix::from_fn(n, m, |i, j| k[i] * nmat[(i, j)]);
    // lambda(u) = G^{-1} N^T u: the rows of `lam` (m x n).
    let lam = if m == 0 {
        DMatrix::zeros(0, n)
    } else {
        let g = nmat.transpose() * &kn;
        let ginv = g.try_inverse().unwrap_or_else(|| DMatrix::zeros(m, m));
        ginv * nmat.transpose()
    };
    // Constraints a.u <= b of U_F cut to one cell: the cell's box, then -lambda_j(u) <= 0.
    let cells = cost.cells();
    let scale = rate.iter().fold(0.0_f64, |s, v| s.max(*v));
    let tol = 1e-10 * scale;
    let mut verts: Vec<Vec<f64>> = Vec::new();
    let mut cell = vec![0usize; n];
    loop {
        let mut rows: Vec<(Vec<f64>, f64)> = Vec::new();
        for l in 0..n {
            let edge = |i: usize| -rate[l] + 2.0 * rate[l] * i as f64 / cells as f64;
            let mut e = vec![0.0; n];
            e[l] = 1.0;
            rows.push((e.clone(), edge(cell[l] + 1)));
            e[l] = -1.0;
            rows.push((e, -edge(cell[l])));
        }
        for j in 0..m {
            rows.push(((0..n).map(|i| -lam[(j, i)]).collect(), 0.0));
        }
        for u in polytope_vertices(n, &rows, tol) {
            if !verts
                .iter()
                .any(|w| w.iter().zip(&u).all(|(p, q)| (p - q).abs() <= tol))
            {
                verts.push(u);
            }
        }
        // Next cell (odometer over the links).
        let mut l = 0;
        while l < n {
            cell[l] += 1;
            if cell[l] < cells {
                break;
            }
            cell[l] = 0;
            l += 1;
        }
        if l == n {
            break;
        }
    }
    let controls = verts
        .into_iter()
        .map(|u| {
            let lv = &lam * DVector::from_column_slice(&u);
            let react = &kn * &lv;
            let mut d: Vec<f64> = (0..n).map(|i| u[i] - react[i]).collect();
            d.extend((0..n).map(|i| u[i] / k[i]));
            let y = (0..m).map(|j| act[j].sign * lv[j]).sum::<f64>() / nb;
            (d, y - cost.under(rate, &u))
        })
        .collect();
    FaceMotion {
        active: act,
        controls,
    }
}

/// Vertices of `{ u in R^n : a_i . u <= b_i }` (bounded), by solving every choice of `n` rows:
/// `n <= 3` here, so at most a few hundred small systems.
fn polytope_vertices(n: usize, rows: &[(Vec<f64>, f64)], tol: f64) -> Vec<Vec<f64>> {
    let mut out: Vec<Vec<f64>> = Vec::new();
    let mut pick = vec![0usize; n];
    fn rec(
        n: usize,
        start: usize,
        depth: usize,
        pick: &mut Vec<usize>,
        rows: &[(Vec<f64>, f64)],
        tol: f64,
        out: &mut Vec<Vec<f64>>,
    ) {
        if depth == n {
            let a = DMatrix::from_fn(n, n, |i, j| rows[pick[i]].0[j]);
            let b = DVector::from_fn(n, |i, _| rows[pick[i]].1);
            let Some(u) = a.lu().solve(&b) else { return };
            let u: Vec<f64> = u.iter().copied().collect();
            if u.iter().any(|v| !v.is_finite()) {
                return;
            }
            if rows.iter().all(|(a, b)| dot(a, &u) <= b + tol)
                && !out
                    .iter()
                    .any(|w| w.iter().zip(&u).all(|(p, q)| (p - q).abs() <= tol))
            {
                out.push(u);
            }
            return;
        }
        for i in start..rows.len() {
            pick[depth] = i;
            rec(n, i + 1, depth + 1, pick, rows, tol, out);
        }
    }
    rec(n, 0, 0, &mut pick, rows, tol, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_link_faces_and_motions() {
        // N = 2, mu^+ = 1, mu^- = 2: C = [-1, 1] (theory §9: alpha = max(-1, -2), beta = min(2, 1)).
        let c = Crawler::uniform(2, 2.0, 1.0, 2.0).unwrap();
        let fs = faces(&c, 1e-9);
        assert_eq!(fs.len(), 3, "{fs:?}");
        assert!(fs.contains(&vec![]));
        for f in &fs {
            let none = CostModel {
                weight: 0.0,
                tangents: 4,
            };
            let m = face_motion(&c, &[1.0], f, none);
            if f.is_empty() {
                assert_eq!(m.controls.len(), 2);
                continue;
            }
            // At an end of C the state stays only for the control pushing outward, then
            // x' = 0, l' = u/k and the crawler moves |z'|/2 = |u|/(2k) forward (theory §9).
            let moving: Vec<_> = m.controls.iter().filter(|(_, y)| *y != 0.0).collect();
            assert_eq!(moving.len(), 1);
            let (d, y) = moving[0];
            assert!(d[0].abs() < 1e-12);
            assert!((d[1].abs() - 0.5).abs() < 1e-12);
            assert!((y - 0.25).abs() < 1e-12);
        }
    }

    #[test]
    fn cost_under_estimator() {
        // Below (c/2)|u|^2 by at most c a^2 / (2 m^2) per link, exact at the cell centres.
        let (c, rate) = (0.8, [1.5, 0.5]);
        for m in [1, 2, 5] {
            let cost = CostModel {
                weight: c,
                tangents: m,
            };
            for i in 0..=40 {
                for j in 0..=40 {
                    let u = [
                        rate[0] * (i as f64 / 20.0 - 1.0),
                        rate[1] * (j as f64 / 20.0 - 1.0),
                    ];
                    let f2 = 0.5 * c * (u[0] * u[0] + u[1] * u[1]);
                    let gap = f2 - cost.under(&rate, &u);
                    let most = rate.iter().map(|a| c * a * a).sum::<f64>() / (2 * m * m) as f64;
                    assert!(
                        gap >= -1e-12 && gap <= most + 1e-12,
                        "m = {m}, u = {u:?}: {gap}"
                    );
                }
            }
            let centre = [
                rate[0] * (1.0 / m as f64 - 1.0),
                rate[1] * (1.0 / m as f64 - 1.0),
            ];
            let f2 = 0.5 * c * (centre[0] * centre[0] + centre[1] * centre[1]);
            assert!((f2 - cost.under(&rate, &centre)).abs() < 1e-12);
        }
        let none = CostModel {
            weight: 0.0,
            tangents: 3,
        };
        assert_eq!(none.under(&rate, &[1.0, -0.5]), 0.0);
    }

    #[test]
    fn quadratic_cost_adds_the_cell_edges_as_controls() {
        // N = 2 (k = 2), interior of C: U_F = [-1, 1] cut into 4 cells gives 5 controls (the
        // cell edges), l' = u / k, and y' = -f2_low(u), the largest tangent of 0.4 u^2 at the
        // centres +-0.25, +-0.75.
        let c = Crawler::uniform(2, 2.0, 1.0, 2.0).unwrap();
        let cost = CostModel {
            weight: 0.8,
            tangents: 4,
        };
        let m = face_motion(&c, &[1.0], &[], cost);
        assert_eq!(m.controls.len(), 5);
        for (d, y) in &m.controls {
            let u = d[0];
            assert!((d[1] - u / 2.0).abs() < 1e-12);
            let low = [0.25_f64, 0.75]
                .iter()
                .flat_map(|&v| [v, -v])
                .map(|u0| 0.8 * u0 * (u - 0.5 * u0))
                .fold(f64::NEG_INFINITY, f64::max);
            assert!((y + low).abs() < 1e-12, "u = {u}: {y}");
        }
    }

    #[test]
    fn two_link_faces_count() {
        // N = 3, mu^+ = 1, mu^- = 1.5: C is a hexagon: 1 interior, 6 edges, 6 vertices.
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        let fs = faces(&c, 1e-9);
        assert_eq!(fs.iter().filter(|f| f.is_empty()).count(), 1);
        assert_eq!(fs.iter().filter(|f| f.len() == 1).count(), 6);
        assert_eq!(fs.iter().filter(|f| f.len() == 2).count(), 6);
        assert_eq!(c.vertices().len(), 6);
    }
}
