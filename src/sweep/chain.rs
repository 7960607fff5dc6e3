//! The structured QP behind every projection of the sweeping process:
//!
//! ```text
//! minimise   sum_l (x_l - v_l)^2 / (2 k_l)
//! subject to lo_b <= x_b - x_{b-1} <= hi_b,   b = 0..N,   x_{-1} = x_n = 0,
//! ```
//!
//! i.e. the `K^{-1}`-projection of `v` onto C written in increments (`x_b - x_{b-1} = -F_b`,
//! `lo = -mu^+`, `hi = mu^-`), or onto a tangent cone of C (bounds `0` or `±inf`).
//!
//! **Method.** A primal active-set method started from a feasible point and a warm working set.
//! With the working set `W` fixed, active increments glue consecutive nodes of the path
//! `0 = p_0, x_0, .., x_{n-1}, p_N = 0` into rigid segments: the segment touching `p_0` and the one
//! touching `p_N` are pinned, every other one floats at the `1/k`-weighted mean of `v - offsets`.
//! So the equality-constrained subproblem costs `O(n)`, and so do the ratio test and the
//! multipliers. The multipliers are the block displacements:
//! `K^{-1}(v - x) = sum_b D_b nu_b`, i.e. `D_{b+1} - D_b = (v_b - x_b)/k_b`, `D_b = 0` on free
//! increments (theory §4); a forward face (`x_b - x_{b-1} = lo_b`) needs `D_b >= 0`, a backward
//! face `D_b <= 0`. Under the uniqueness condition at most `n` increments are active, so at least
//! one is free and the `D_b` are unique.
//!
//! Warm-started from the previous step's working set, a catching-up step usually costs one
//! subproblem and one multiplier pass: `O(n)` with a small constant.

use crate::error::{Error, Result};

/// State of one increment constraint in the working set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// Not in the working set.
    Free,
    /// At its lower bound `lo_b` (for C: `F_b = mu_b^+`, the forward face).
    Lower,
    /// At its upper bound `hi_b` (for C: `F_b = -mu_b^-`, the backward face).
    Upper,
}

/// Solver of the chain QP with a persistent (warm) working set. See the module docs.
#[derive(Debug, Clone)]
pub struct ChainQp {
    inv_k: Vec<f64>,
    max_inv_k: f64,
    ws: Vec<Bound>,
    xw: Vec<f64>,
    max_iter: usize,
}

/// Increment of block `b` along the path `0, x_0, .., x_{n-1}, 0`: `x_b - x_{b-1} = -F_b(x)`.
#[inline]
pub fn increment(x: &[f64], b: usize) -> f64 {
    let n = x.len();
    let right = if b < n { x[b] } else { 0.0 };
    let left = if b > 0 { x[b - 1] } else { 0.0 };
    right - left
}

impl ChainQp {
    /// A solver for links of stiffness `k` (weights `1/k_l`).
    pub fn new(stiffness: &[f64]) -> Self {
        let n = stiffness.len();
        ChainQp {
            inv_k: stiffness.iter().map(|k| 1.0 / k).collect(),
            max_inv_k: stiffness.iter().fold(0.0_f64, |m, k| m.max(1.0 / k)),
            ws: vec![Bound::Free; n + 1],
            xw: vec![0.0; n],
            max_iter: 64 + 8 * (n + 1),
        }
    }

    /// Empties the working set.
    pub fn reset(&mut self) {
        self.ws.iter_mut().for_each(|w| *w = Bound::Free);
    }

    /// The working set (one entry per block).
    pub fn working_set(&self) -> &[Bound] {
        &self.ws
    }

    /// Replaces the working set (entries must be active at the next starting point).
    pub fn set_working_set(&mut self, ws: &[Bound]) {
        self.ws.copy_from_slice(ws);
    }

    /// Solves the QP. `x` holds a feasible starting point on entry and the minimiser on exit;
    /// `d` receives the multipliers `D_b`. The working set is kept for the next call (it is
    /// pruned first to the constraints active at `x`). Returns the number of iterations.
    pub fn solve(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &mut [f64],
        d: &mut [f64],
    ) -> Result<usize> {
        let nb = self.ws.len();
        debug_assert!(lo.len() == nb && hi.len() == nb && v.len() == nb - 1 && x.len() == nb - 1);
        // Scale for "active" and for multiplier signs.
        let scale = v
            .iter()
            .chain(x.iter())
            .fold(1e-300_f64, |m, a| m.max(a.abs()));
        self.prune(lo, hi, x, 1e-12 * scale);
        for it in 1..=self.max_iter {
            self.solve_equality(lo, hi, v);
            let (alpha, block) = self.ratio_test(lo, hi, x);
            if let Some((b, side)) = block {
                for (xi, wi) in x.iter_mut().zip(&self.xw) {
                    *xi += alpha * (wi - *xi);
                }
                self.ws[b] = side;
                if self.ws.iter().all(|&w| w != Bound::Free) {
                    return Err(Error::Numerical(
                        "projection onto C: every friction face became active at once; \
                         the crawler is numerically too close to violating the uniqueness condition"
                            .into(),
                    ));
                }
                continue;
            }
            x.copy_from_slice(&self.xw);
            self.multipliers(v, x, d);
            // Rounding in D is at most ~ nb * eps * scale / k.
            let tol_d = 1e-14 * nb as f64 * scale * self.max_inv_k;
            let mut worst = (tol_d, None);
            for b in 0..nb {
                let wrong = match self.ws[b] {
                    Bound::Free => 0.0,
                    Bound::Lower => -d[b],
                    Bound::Upper => d[b],
                };
                if wrong > worst.0 {
                    worst = (wrong, Some(b));
                }
            }
            match worst.1 {
                None => {
                    // Clean tiny wrong-signed multipliers on degenerate faces.
                    for b in 0..nb {
                        match self.ws[b] {
                            Bound::Lower if d[b] < 0.0 => d[b] = 0.0,
                            Bound::Upper if d[b] > 0.0 => d[b] = 0.0,
                            _ => {}
                        }
                    }
                    return Ok(it);
                }
                Some(b) => self.ws[b] = Bound::Free,
            }
        }
        Err(Error::Numerical(format!(
            "projection onto C did not converge in {} active-set iterations",
            self.max_iter
        )))
    }

    /// The working set pruned to the constraints active at `x` (within `tol_act`), with one
    /// block freed if every one is active (the equality system is singular then).
    fn prune(&mut self, lo: &[f64], hi: &[f64], x: &[f64], tol_act: f64) {
        let nb = self.ws.len();
        for b in 0..nb {
            let keep = match self.ws[b] {
                Bound::Free => true,
                Bound::Lower => (increment(x, b) - lo[b]).abs() <= tol_act,
                Bound::Upper => (increment(x, b) - hi[b]).abs() <= tol_act,
            };
            if !keep {
                self.ws[b] = Bound::Free;
            }
        }
        if self.ws.iter().all(|&w| w != Bound::Free) {
            self.ws[nb - 1] = Bound::Free;
        }
    }

    /// The ratio test along `p = xw - x` over the free increments: the longest step
    /// `alpha <= 1` that stays in C, and the block and face that stop it (`None` at 1).
    fn ratio_test(&self, lo: &[f64], hi: &[f64], x: &[f64]) -> (f64, Option<(usize, Bound)>) {
        let mut alpha = 1.0;
        let mut block: Option<(usize, Bound)> = None;
        for b in 0..self.ws.len() {
            if self.ws[b] != Bound::Free {
                continue;
            }
            let dp = increment(&self.xw, b) - increment(x, b);
            if dp < 0.0 && lo[b] > f64::NEG_INFINITY {
                let a = ((lo[b] - increment(x, b)) / dp).max(0.0);
                if a < alpha {
                    alpha = a;
                    block = Some((b, Bound::Lower));
                }
            } else if dp > 0.0 && hi[b] < f64::INFINITY {
                let a = ((hi[b] - increment(x, b)) / dp).max(0.0);
                if a < alpha {
                    alpha = a;
                    block = Some((b, Bound::Upper));
                }
            }
        }
        (alpha, block)
    }

    #[inline]
    fn bound(&self, lo: &[f64], hi: &[f64], b: usize) -> f64 {
        match self.ws[b] {
            Bound::Lower => lo[b],
            Bound::Upper => hi[b],
            Bound::Free => 0.0,
        }
    }

    /// Minimiser `xw` of the objective with the working-set constraints as equalities.
    fn solve_equality(&mut self, lo: &[f64], hi: &[f64], v: &[f64]) {
        let n = self.xw.len();
        let nb = n + 1;
        let mut start = 0;
        let mut pinned_left = true;
        for b in 0..nb {
            if self.ws[b] != Bound::Free {
                continue;
            }
            // Links start..b form one segment, closed on the right by the free increment b.
            if pinned_left {
                let mut p = 0.0;
                for l in start..b {
                    p += self.bound(lo, hi, l);
                    self.xw[l] = p;
                }
                pinned_left = false;
            } else if b > start {
                // Floating: x_l = c + o_l, o_start = 0, o_l = o_{l-1} + bound_l.
                let (mut o, mut sw, mut swv) = (0.0, 0.0, 0.0);
                for l in start..b {
                    if l > start {
                        o += self.bound(lo, hi, l);
                    }
                    self.xw[l] = o;
                    sw += self.inv_k[l];
                    swv += self.inv_k[l] * (v[l] - o);
                }
                let c = swv / sw;
                for l in start..b {
                    self.xw[l] += c;
                }
            }
            start = b;
        }
        // Links start..n are pinned to p_N = 0 from the right.
        let mut p = 0.0;
        for l in (start..n).rev() {
            p -= self.bound(lo, hi, l + 1);
            self.xw[l] = p;
        }
    }

    /// Block displacements `D` from the stationarity condition, given the working set.
    fn multipliers(&self, v: &[f64], x: &[f64], d: &mut [f64]) {
        let nb = self.ws.len();
        let g = |l: usize| (x[l] - v[l]) * self.inv_k[l];
        let f0 = self
            .ws
            .iter()
            .position(|&w| w == Bound::Free)
            .unwrap_or(nb - 1);
        d[f0] = 0.0;
        for b in f0 + 1..nb {
            d[b] = if self.ws[b] == Bound::Free {
                0.0
            } else {
                d[b - 1] - g(b - 1)
            };
        }
        for b in (0..f0).rev() {
            d[b] = d[b + 1] + g(b);
        }
    }
}

/// Moves the links of one floating segment rigidly: every entry of `dv` becomes its
/// `1/k`-weighted mean (weights `inv_k`), the tangent of the projection on that segment.
pub fn rigid_mean(inv_k: &[f64], dv: &mut [f64]) {
    let (mut sw, mut swv) = (0.0, 0.0);
    for (d, w) in dv.iter().zip(inv_k) {
        sw += w;
        swv += w * d;
    }
    let c = swv / sw;
    dv.iter_mut().for_each(|d| *d = c);
}

/// The derivative of the projection with respect to `v` on a fixed working set `ws` (one entry per
/// block), applied in place to `dv`: links glued by active increments into a segment that reaches
/// an end of the chain are pinned (`dx = 0`), every other segment moves rigidly with the
/// `1/k`-weighted mean of `dv` over it (theory §4: the minimiser of the equality-constrained
/// subproblem is affine in `v`). On a degenerate face any choice is an element of the
/// generalised Jacobian of the piecewise-affine projection. `O(n)`.
pub fn tangent(ws: &[Bound], inv_k: &[f64], dv: &mut [f64]) {
    let n = dv.len();
    debug_assert!(ws.len() == n + 1 && inv_k.len() == n);
    let mut start: Option<usize> = None;
    let mut pinned_left = true;
    for b in 0..=n {
        if ws[b] != Bound::Free {
            continue;
        }
        // Links start..b form one segment, closed on the right by the free block b.
        let s = start.unwrap_or(0);
        if pinned_left {
            dv[..b].iter_mut().for_each(|d| *d = 0.0);
            pinned_left = false;
        } else if b > s {
            rigid_mean(&inv_k[s..b], &mut dv[s..b]);
        }
        start = Some(b);
    }
    match start {
        Some(s) => dv[s..].iter_mut().for_each(|d| *d = 0.0),
        None => dv.iter_mut().for_each(|d| *d = 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks the KKT conditions of the projection: feasibility, stationarity, signs and
    /// complementarity. Together they certify optimality of a strictly convex QP.
    pub(crate) fn kkt_residual(
        k: &[f64],
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &[f64],
        d: &[f64],
    ) -> f64 {
        let nb = lo.len();
        let mut r: f64 = 0.0;
        for b in 0..nb {
            let i = increment(x, b);
            r = r.max(lo[b] - i).max(i - hi[b]);
            if d[b] > 0.0 {
                r = r.max((i - lo[b]).abs());
            }
            if d[b] < 0.0 {
                r = r.max((hi[b] - i).abs());
            }
        }
        for l in 0..k.len() {
            r = r.max(((v[l] - x[l]) / k[l] - (d[l + 1] - d[l])).abs());
        }
        r
    }

    #[test]
    fn projection_satisfies_kkt_cold_and_warm() {
        let k = [1.0, 0.5, 2.0, 1.5];
        let lo = [-1.0, -0.8, -1.2, -0.9, -1.1];
        let hi = [2.0, 3.0, 1.5, 2.5, 2.2];
        let mut qp = ChainQp::new(&k);
        let mut x = vec![0.0; 4];
        let mut d = vec![0.0; 5];
        let mut seed = 7u64;
        for _ in 0..2000 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
            let v: Vec<f64> = (0..4)
                .map(|i| x[i] + ((seed >> (8 + 10 * i)) & 1023) as f64 / 256.0 - 2.0)
                .collect();
            qp.solve(&lo, &hi, &v, &mut x, &mut d).unwrap();
            assert!(kkt_residual(&k, &lo, &hi, &v, &x, &d) < 1e-12);
        }
    }
}
