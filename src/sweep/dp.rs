//! The chain QP of [`super::ChainQp`] solved exactly by dynamic programming over the chain, in
//! `O(n)` work whatever the number of faces that become active or inactive.
//!
//! ```text
//! minimise   sum_l (x_l - v_l)^2 / (2 k_l)
//! subject to lo_b <= x_b - x_{b-1} <= hi_b,   b = 0..n,   x_{-1} = x_n = 0
//! ```
//!
//! **Messages.** `f_l(x_l)` is the least cost of links `0..=l` given `x_l`, under the constraints
//! of blocks `0..=l`: `f_l = g_l + q_l`, `q_l(x) = (x - v_l)^2 / (2 k_l)` and
//! `g_l(x) = min { f_{l-1}(y) : x - hi_l <= y <= x - lo_l }` (`f_{-1}` is the point `0`).
//! Each `f_l` is convex and piecewise quadratic, so its derivative `f_l'` is non-decreasing and
//! piecewise linear (with jumps, `-inf`/`+inf` beyond its domain). With `m` the zero of
//! `f_{l-1}'` (its minimiser), the min-convolution with the interval `[lo_l, hi_l]` cuts `f_{l-1}'`
//! at `m`, shifts the left part by `lo_l`, the right part by `hi_l`, and fills `[m + lo_l,
//! m + hi_l]` with zero; adding `q_l` adds the line `(x - v_l) / k_l` everywhere. So the knots of
//! `f_l'` left of its zero only ever move by `lo` and those right of it by `hi`: they live on two
//! stacks with one lazy offset each, store only their jump and change of slope (a shift and the
//! added line leave both unchanged), and the value and slope at the current zero are carried
//! along. Each link pushes two knots; finding the next zero moves knots from one stack to the
//! other (taut-string style).
//!
//! **Backtracking.** `x_{n-1} = clamp(m_{n-1}, -hi_n, -lo_n)` and
//! `x_{l-1} = clamp(m_{l-1}, x_l - hi_l, x_l - lo_l)`: the side a clamp takes is the face of block
//! `l` in the solution (free when `m_{l-1}` lies inside). The multipliers (block displacements,
//! theory §4) follow from stationarity `D_{b+1} - D_b = (v_b - x_b) / k_b` and `D_b = 0` on free
//! blocks, exactly as in the active-set method.

use super::chain::Bound;

/// A knot of the piecewise-linear derivative: `t` relative to its stack's offset, the change of
/// slope across it and the jump of the value (`+inf` at the ends of the domain).
#[derive(Debug, Clone, Copy)]
struct Knot {
    t: f64,
    dslope: f64,
    jump: f64,
}

/// Exact dynamic-programming solver of the chain QP. See the module docs.
#[derive(Debug, Clone)]
pub struct ChainDp {
    inv_k: Vec<f64>,
    left: Vec<Knot>,
    right: Vec<Knot>,
    zeros: Vec<f64>,
    /// Whether the derivative jumps over 0 at the zero (a kink of `f_l`: a prefix of the chain
    /// is rigid there), where a clamp that keeps the zero says nothing about the multiplier.
    kinks: Vec<bool>,
    ws: Vec<Bound>,
    anchors: Vec<bool>,
    crossings: u64,
}

impl ChainDp {
    /// A solver for links of stiffness `k` (weights `1/k_l`).
    pub fn new(stiffness: &[f64]) -> Self {
        let n = stiffness.len();
        ChainDp {
            inv_k: stiffness.iter().map(|k| 1.0 / k).collect(),
            left: Vec::with_capacity(n + 2),
            right: Vec::with_capacity(n + 2),
            zeros: vec![0.0; n],
            kinks: vec![false; n],
            ws: vec![Bound::Free; n + 1],
            anchors: vec![false; n + 1],
            crossings: 0,
        }
    }

    /// The faces of the last solution (one entry per block).
    pub fn working_set(&self) -> &[Bound] {
        &self.ws
    }

    /// Knots moved from one stack to the other so far (the work beyond two knots per link).
    pub fn crossings(&self) -> u64 {
        self.crossings
    }

    /// Solves the QP for finite bounds `lo < hi` whose feasible set contains a point (for C: 0).
    /// `x` receives the minimiser, `d` the multipliers `D_b`.
    pub fn solve(&mut self, lo: &[f64], hi: &[f64], v: &[f64], x: &mut [f64], d: &mut [f64]) {
        let n = self.inv_k.len();
        debug_assert!(lo.len() == n + 1 && hi.len() == n + 1 && v.len() == n && x.len() == n);
        self.solve_window(lo, hi, v, x, d, (0, false), (n, false));
    }

    /// Solves the sub-chain of links `ls..le` exactly: the constraints of blocks `ls + 1..le`,
    /// and of block `ls` (with `x_{ls-1} = 0`, so `ls = 0`) unless `left.1` (the block is cut:
    /// its constraint dropped, `D_ls = 0`), of block `le` (with `x_le = 0`, so `le = n`) unless
    /// `right.1`. With both ends cut the sub-chain floats. Writes `x[ls..le]`, `d[ls..=le]` and
    /// the faces of blocks `ls..=le` (a cut block is free). `O(le - ls)`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_window(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &mut [f64],
        d: &mut [f64],
        (ls, left_cut): (usize, bool),
        (le, right_cut): (usize, bool),
    ) {
        let n = self.inv_k.len();
        debug_assert!(ls < le && le <= n && (left_cut || ls == 0) && (right_cut || le == n));
        self.forward(lo, hi, v, (ls, left_cut), le);
        self.backtrack(lo, hi, x, (ls, left_cut), (le, right_cut));
        self.multipliers(lo, hi, v, x, d, (ls, left_cut), le);
    }

    /// The forward pass of [`Self::solve_window`] over links `ls..le`: the derivative of the
    /// cost-to-go as two stacks of knots, each link's min-convolution with `[lo_l, hi_l]` and
    /// its `q_l'` added, and the zero `z_l` of the sum found by popping knots (recorded in
    /// `zeros`, with whether it sits on a kink in `kinks`). `O(le - ls)` amortised.
    fn forward(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        (ls, left_cut): (usize, bool),
        le: usize,
    ) {
        self.left.clear();
        self.right.clear();
        let (mut off_l, mut off_r) = (0.0_f64, 0.0_f64);
        // The zero z of the current derivative, its one-sided values and slopes.
        let (mut z, mut g_l, mut g_r, mut s_l, mut s_r) =
            (0.0_f64, f64::NEG_INFINITY, f64::INFINITY, 0.0_f64, 0.0_f64);
        let mut crossings = 0u64;
        for l in ls..le {
            let mut r;
            if l == ls && left_cut {
                // A free left end: the domain is the whole line (end knots at infinity).
                self.left.push(Knot {
                    t: f64::NEG_INFINITY,
                    dslope: 0.0,
                    jump: f64::INFINITY,
                });
                self.right.push(Knot {
                    t: f64::INFINITY,
                    dslope: 0.0,
                    jump: f64::INFINITY,
                });
                r = 0.0;
            } else {
                // Min-convolution with [lo_l, hi_l]: the cut at z becomes two knots and a flat
                // piece.
                self.left.push(Knot {
                    t: z - off_l,
                    dslope: -s_l,
                    jump: -g_l,
                });
                self.right.push(Knot {
                    t: z - off_r,
                    dslope: s_r,
                    jump: g_r,
                });
                off_l += lo[l];
                off_r += hi[l];
                r = z + lo[l];
            }
            // Add q_l' = (x - v_l) / k_l: the value at the reference point r and the slope there.
            let ik = self.inv_k[l];
            let mut g = (r - v[l]) * ik;
            let mut s = ik;
            // Find the zero.
            loop {
                let kr = *self.right.last().expect("the domain's right end stays");
                let tr = kr.t + off_r;
                let at_r = g + s * (tr - r);
                if at_r < 0.0 {
                    let after = at_r + kr.jump;
                    self.right.pop();
                    if after >= 0.0 {
                        (z, g_l, g_r, s_l, s_r) = (tr, at_r, after, s, s + kr.dslope);
                        break;
                    }
                    crossings += 1;
                    (r, g, s) = (tr, after, s + kr.dslope);
                    self.left.push(Knot {
                        t: tr - off_l,
                        ..kr
                    });
                    continue;
                }
                let kl = *self.left.last().expect("the domain's left end stays");
                let tl = kl.t + off_l;
                let at_l = g + s * (tl - r);
                if at_l > 0.0 {
                    let before = at_l - kl.jump;
                    self.left.pop();
                    if before <= 0.0 {
                        (z, g_l, g_r, s_l, s_r) = (tl, before, at_l, s - kl.dslope, s);
                        break;
                    }
                    crossings += 1;
                    (r, g, s) = (tl, before, s - kl.dslope);
                    self.right.push(Knot {
                        t: tl - off_r,
                        ..kl
                    });
                    continue;
                }
                // Inside the segment (tl, tr), where the slope is s > 0.
                z = (r - g / s).clamp(tl, tr);
                (g_l, g_r, s_l, s_r) = (0.0, 0.0, s, s);
                break;
            }
            self.zeros[l] = z;
            self.kinks[l] = g_l < 0.0 || g_r > 0.0;
        }
        self.crossings += crossings;
    }

    /// The backtracking of [`Self::solve_window`]: the clamps of the zeros give `x[ls..le]` and
    /// the face of every block `b > ls` (a cut end block is free and anchors `D`).
    fn backtrack(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        x: &mut [f64],
        (ls, left_cut): (usize, bool),
        (le, right_cut): (usize, bool),
    ) {
        let mut top = le;
        let mut xl = 0.0;
        if right_cut {
            xl = self.zeros[le - 1];
            x[le - 1] = xl;
            self.ws[le] = Bound::Free;
            self.anchors[le] = true;
            top = le - 1;
        }
        for b in (ls + 1..=top).rev() {
            let (a, c) = (xl - hi[b], xl - lo[b]);
            let m = self.zeros[b - 1];
            let (xv, w) = if m < a {
                (a, Bound::Upper)
            } else if m > c {
                (c, Bound::Lower)
            } else if (m - a).min(c - m) <= 1e-12 * m.abs().max(a.abs()).max(c.abs()) {
                // A zero on (within rounding of) a bound: the face, whose multiplier is not 0 in
                // general, is set by stationarity. At a kink the zero says nothing about it; at a
                // smooth zero on the bound (an exact tie: the state and the step on vertices of
                // C, as in an optimal gait's orbit) rounding decides which side the zero falls,
                // and taking the block as free anchored D = 0 where the rest of the chain needs
                // it slipping (a six-block step: D = 7.36 reported as 0, the state right).
                (
                    m,
                    if m - a <= c - m {
                        Bound::Upper
                    } else {
                        Bound::Lower
                    },
                )
            } else {
                (m, Bound::Free)
            };
            x[b - 1] = xv;
            self.ws[b] = w;
            self.anchors[b] = w == Bound::Free;
            xl = xv;
        }
        if left_cut {
            self.ws[ls] = Bound::Free;
            self.anchors[ls] = true;
        }
    }

    /// `D` from stationarity `D_{b+1} = D_b - (x_b - v_b) / k_b` over blocks `ls..=le`,
    /// anchored at `D = 0` on a block that is free for certain (a clamp that kept a smooth zero,
    /// or a cut end); the face of block 0 when the window starts there uncut.
    #[allow(clippy::too_many_arguments)]
    fn multipliers(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &[f64],
        d: &mut [f64],
        (ls, left_cut): (usize, bool),
        le: usize,
    ) {
        if !left_cut {
            let scale = v[ls..le]
                .iter()
                .chain(x[ls..le].iter())
                .chain(lo[ls..=le].iter())
                .chain(hi[ls..=le].iter())
                .fold(0.0_f64, |m, a| m.max(a.abs()));
            let tol = 1e-12 * scale;
            let x0 = x[0];
            self.ws[0] = if x0 - lo[0] <= tol {
                Bound::Lower
            } else if hi[0] - x0 <= tol {
                Bound::Upper
            } else {
                Bound::Free
            };
            self.anchors[0] = self.ws[0] == Bound::Free && !self.anchors[1..=le].contains(&true);
        }
        // D up to a constant: P_0 = 0, P_{b+1} = P_b - g_b, restarted at every anchor.
        let g = |l: usize| (x[l] - v[l]) * self.inv_k[l];
        let first = (ls..=le).find(|&b| self.anchors[b]);
        let f0 = first.unwrap_or(ls);
        d[f0] = 0.0;
        for b in f0 + 1..=le {
            d[b] = if self.anchors[b] {
                0.0
            } else {
                d[b - 1] - g(b - 1)
            };
        }
        for b in (ls..f0).rev() {
            d[b] = d[b + 1] + g(b);
        }
        if first.is_none() {
            // Every block within rounding of a face (only when the uniqueness condition holds
            // by a margin near the rounding): the constant that best fits the signs of the faces.
            let (mut lo_c, mut hi_c) = (f64::NEG_INFINITY, f64::INFINITY);
            for b in ls..=le {
                match self.ws[b] {
                    Bound::Lower => lo_c = lo_c.max(-d[b]),
                    Bound::Upper => hi_c = hi_c.min(-d[b]),
                    Bound::Free => {}
                }
            }
            let c = match (lo_c.is_finite(), hi_c.is_finite()) {
                (true, true) => 0.5 * (lo_c + hi_c),
                (true, false) => lo_c,
                (false, true) => hi_c,
                (false, false) => 0.0,
            };
            d[ls..=le].iter_mut().for_each(|di| *di += c);
        }
        // Tiny wrong-signed multipliers of degenerate faces (rounding) are zero.
        for b in ls..=le {
            match self.ws[b] {
                Bound::Lower if d[b] < 0.0 => d[b] = 0.0,
                Bound::Upper if d[b] > 0.0 => d[b] = 0.0,
                _ => {}
            }
        }
    }
}
