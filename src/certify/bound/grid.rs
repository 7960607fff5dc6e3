//! The simplicial grid of `C x box` and the LP rows on it.
//!
//! The grid is the Kuhn (Freudenthal) triangulation of a rectangular lattice in the `2n`
//! coordinates `(x_1..x_n, l_1..l_n)`: the `x` nodes lie on `h Z^n` (origin 0, one step `h` for
//! every link), the `l` nodes split `[0, lmax_l]` evenly. A lattice cell with lower corner `c`
//! splits into `(2n)!` simplices, one per order `sigma` of the axes: vertices `p_0 = c`,
//! `p_k = p_{k-1} + e_{sigma_k}`. On such a simplex a piecewise-linear `V` has the gradient
//! `g_{sigma_k} = (V(p_k) - V(p_{k-1})) / h_{sigma_k}`, so `<g, d>` is a sparse row in the node
//! values. The faces of the triangulation include the hyperplanes `x_i - x_j = const` and
//! `x_i = const` of the lattice, so when every friction threshold is a multiple of `h` the
//! simplices tile C exactly (C is alcoved); otherwise simplices stick out of C, which costs
//! tightness, not validity.

use super::faces::{dot, half_spaces, normal, FaceMotion};
use crate::model::Crawler;

/// The lattice: `2n` axes, node counts, origins and steps.
pub(crate) struct Grid {
    pub dims: usize,
    pub counts: Vec<usize>,
    pub origin: Vec<f64>,
    pub step: Vec<f64>,
    /// Every friction threshold is a multiple of the `x` step: the simplices inside C tile it,
    /// the others are dropped and the face test is exact.
    pub aligned: bool,
}

impl Grid {
    /// The lattice for `x` step `h` over C's bounding box and `cells` steps over `[0, lmax_l]`.
    pub fn new(crawler: &Crawler, h: f64, lmax: &[f64], cells: usize, aligned: bool) -> Self {
        let n = crawler.links();
        let mut counts = Vec::with_capacity(2 * n);
        let mut origin = Vec::with_capacity(2 * n);
        let mut step = Vec::with_capacity(2 * n);
        for r in crawler.link_force_ranges() {
            let lo = (r[0] / h + 1e-9).floor();
            let hi = (r[1] / h - 1e-9).ceil();
            counts.push((hi - lo) as usize + 1);
            origin.push(lo * h);
            step.push(h);
        }
        for &lm in lmax {
            counts.push(cells + 1);
            origin.push(0.0);
            step.push(lm / cells as f64);
        }
        Grid {
            dims: 2 * n,
            counts,
            origin,
            step,
            aligned,
        }
    }

    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.counts.iter().product()
    }

    /// Number of lattice cells.
    pub fn cells(&self) -> usize {
        self.counts.iter().map(|c| c.saturating_sub(1)).product()
    }

    /// Linear index of a node.
    fn index(&self, idx: &[usize]) -> usize {
        idx.iter()
            .zip(&self.counts)
            .rev()
            .fold(0, |acc, (&i, &c)| acc * c + i)
    }

    /// Calls `row(nodes, coefficients, y)` for every row `<g_S, d> + rho >= y` of the LP:
    /// every kept simplex `S`, every face of C that `S` may meet, every control vertex of that
    /// face. Aligned grid: the simplices inside C are kept (each Kuhn simplex's `x` part lies in
    /// one alcove, so it is inside C or meets C only on its boundary, and those inside tile C),
    /// and a face is taken when a vertex of the simplex lies on all its hyperplanes (exact).
    /// Otherwise a simplex is kept when no half-space of C excludes all its `x` vertices, and a
    /// face is taken when none of its hyperplanes separates the simplex's `x` vertices strictly:
    /// supersets of the simplices and faces that meet, which is what validity needs.
    pub fn for_each_row(
        &self,
        crawler: &Crawler,
        faces: &[(Vec<usize>, FaceMotion)],
        tol: f64,
        mut row: impl FnMut(&[usize], &[f64], f64),
    ) {
        let n = self.dims / 2;
        let hs = half_spaces(crawler);
        let normals: Vec<Vec<f64>> = hs.iter().map(|a| normal(n, a)).collect();
        let perms = permutations(self.dims);
        let mut cell = vec![0usize; self.dims];
        let cell_counts: Vec<usize> = self.counts.iter().map(|c| c - 1).collect();
        let mut nodes = vec![0usize; self.dims + 1];
        let mut coefs = vec![0.0; self.dims + 1];
        let mut xs = vec![vec![0.0; n]; self.dims + 1];
        let (mut lo, mut hi) = (vec![0.0; hs.len()], vec![0.0; hs.len()]);
        'cells: loop {
            // Cell test: its x box meets every half-space.
            for (j, a) in hs.iter().enumerate() {
                let mut m = 0.0;
                for i in 0..n {
                    let c0 = self.origin[i] + cell[i] as f64 * self.step[i];
                    let v = normals[j][i];
                    m += (v * c0).min(v * (c0 + self.step[i]));
                }
                if m > a.offset + tol {
                    if !advance(&mut cell, &cell_counts) {
                        break 'cells;
                    }
                    continue 'cells;
                }
            }
            for perm in &perms {
                let mut idx = cell.clone();
                for k in 0..=self.dims {
                    if k > 0 {
                        idx[perm[k - 1]] += 1;
                    }
                    nodes[k] = self.index(&idx);
                    for i in 0..n {
                        xs[k][i] = self.origin[i] + idx[i] as f64 * self.step[i];
                    }
                }
                for j in 0..hs.len() {
                    lo[j] = f64::INFINITY;
                    hi[j] = f64::NEG_INFINITY;
                    for x in &xs {
                        let v = dot(&normals[j], x);
                        lo[j] = lo[j].min(v);
                        hi[j] = hi[j].max(v);
                    }
                }
                let outside = |j: usize| {
                    lo[j] > hs[j].offset + tol || (self.aligned && hi[j] > hs[j].offset + tol)
                };
                if (0..hs.len()).any(outside) {
                    continue;
                }
                for (active, motion) in faces {
                    let meets = if self.aligned {
                        // S_x in C: S_x meets F iff a vertex of S_x lies on all of F's
                        // hyperplanes (each cuts S_x in the face spanned by its tight vertices).
                        xs.iter().any(|x| {
                            active
                                .iter()
                                .all(|&j| (dot(&normals[j], x) - hs[j].offset).abs() <= tol)
                        })
                    } else {
                        active
                            .iter()
                            .all(|&j| lo[j] <= hs[j].offset + tol && hi[j] >= hs[j].offset - tol)
                    };
                    if !meets {
                        continue;
                    }
                    for (d, y) in &motion.controls {
                        for k in 0..=self.dims {
                            let mut c = 0.0;
                            if k > 0 {
                                c += d[perm[k - 1]] / self.step[perm[k - 1]];
                            }
                            if k < self.dims {
                                c -= d[perm[k]] / self.step[perm[k]];
                            }
                            coefs[k] = c;
                        }
                        row(&nodes, &coefs, *y);
                    }
                }
            }
            if !advance(&mut cell, &cell_counts) {
                break;
            }
        }
    }
}

/// Next multi-index below `counts` (odometer); `false` after the last.
fn advance(idx: &mut [usize], counts: &[usize]) -> bool {
    for (i, c) in idx.iter_mut().zip(counts) {
        *i += 1;
        if *i < *c {
            return true;
        }
        *i = 0;
    }
    false
}

/// All orders of `0..d` (Heap's algorithm would do; `d <= 6` here).
fn permutations(d: usize) -> Vec<Vec<usize>> {
    if d == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for p in permutations(d - 1) {
        for pos in 0..=p.len() {
            let mut q = p.clone();
            q.insert(pos, d - 1);
            out.push(q);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kuhn_simplices_tile_the_cell() {
        // (2n)! simplices of volume 1/(2n)! each fill the unit cell.
        for d in 1..=4 {
            let ps = permutations(d);
            let fact: usize = (1..=d).product();
            assert_eq!(ps.len(), fact);
            let mut seen = ps.clone();
            seen.sort();
            seen.dedup();
            assert_eq!(seen.len(), fact);
        }
    }
}
