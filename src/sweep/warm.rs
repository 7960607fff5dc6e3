//! The chain QP of [`super::ChainQp`] solved exactly from a guessed working set, repaired
//! locally: the projection of a catching-up step near a periodic orbit in one pass over the
//! chain.
//!
//! **Guess and certify.** With the previous step's working set `W` taken as equalities, the
//! minimiser is separable per rigid segment (the links between two consecutive free blocks; see
//! [`super::ChainQp`]): a segment touching an end of the chain is pinned, every other floats at
//! the `1/k`-weighted mean of `v` minus its offsets. The multipliers follow segment by segment
//! from stationarity `D_{b+1} - D_b = (v_b - x_b)/k_b` with `D = 0` on the free blocks (SPEC §4).
//! One fused pass computes `x`, `D` and both checks of the KKT conditions: every free block's
//! increment within its bounds (primal), every active block's multiplier of the right sign
//! (`D_b >= 0` on a forward face, `<= 0` on a backward one). When both hold, `(x, D)` is the
//! unique minimiser (a strictly convex QP) and the step cost one pass: on the bench gait near
//! its orbit this is 95% of the steps.
//!
//! **Local repair.** A block that is free in the solution decouples the QP: with its constraint
//! dropped the problem splits into two independent ones, and if their solutions satisfy the
//! dropped constraint they form the solution (`D = 0` there is a valid multiplier). So a
//! violation at block `p` is repaired by a window of links between two free blocks of `W` (the
//! cuts) around `p`: the sub-chain is solved exactly by the dynamic programme
//! ([`super::ChainDp`]) with the cut constraints dropped, and the cut blocks' increments are
//! checked against their bounds; the side whose cut fails is widened (doubling the number of
//! segments it spans) until it holds or reaches an end of the chain, where the end's own
//! constraint is kept. Outside the windows the guess is certified by the pass, inside each
//! window the DP is exact and its cuts are checked, so the answer never depends on the guess: a
//! bad guess only costs time. Windows are `O(size)` each; once they have covered twice the
//! chain the whole chain is solved by the DP instead, so a step is `O(n)` in the worst case.

use super::chain::Bound;
use super::dp::ChainDp;

/// Solver of the chain QP from the previous solution's working set. See the module docs.
#[derive(Debug, Clone)]
pub struct ChainWarm {
    inv_k: Vec<f64>,
    max_inv_k: f64,
    /// The working set: the guess on entry to [`ChainWarm::solve`], the faces of the solution on
    /// exit.
    ws: Vec<Bound>,
    /// Blocks whose check failed in the pass and no window has repaired yet.
    bad: Vec<bool>,
    viol: Vec<usize>,
    dp: ChainDp,
    windows: u64,
    window_links: u64,
    full: u64,
}

impl ChainWarm {
    /// A solver for links of stiffness `k` (weights `1/k_l`), with an empty working set.
    pub fn new(stiffness: &[f64]) -> Self {
        let n = stiffness.len();
        ChainWarm {
            inv_k: stiffness.iter().map(|k| 1.0 / k).collect(),
            max_inv_k: stiffness.iter().fold(0.0_f64, |m, k| m.max(1.0 / k)),
            ws: vec![Bound::Free; n + 1],
            bad: vec![false; n + 1],
            viol: Vec::new(),
            dp: ChainDp::new(stiffness),
            windows: 0,
            window_links: 0,
            full: 0,
        }
    }

    /// The faces of the last solution (one entry per block).
    pub fn working_set(&self) -> &[Bound] {
        &self.ws
    }

    /// Replaces the working set used as the next guess.
    pub fn set_working_set(&mut self, ws: &[Bound]) {
        self.ws.copy_from_slice(ws);
    }

    /// Work counters so far: windows solved by the DP, links in them, and whole-chain DP solves.
    pub fn counters(&self) -> (u64, u64, u64) {
        (self.windows, self.window_links, self.full)
    }

    /// Solves the QP for finite bounds `lo < hi` whose feasible set contains a point (for C: 0).
    /// `x` receives the minimiser (its content on entry is not used), `d` the multipliers `D_b`;
    /// the working set becomes the solution's faces. Returns the number of windows solved
    /// (0 when the guess was right).
    pub fn solve(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &mut [f64],
        d: &mut [f64],
    ) -> usize {
        let n = v.len();
        debug_assert!(lo.len() == n + 1 && hi.len() == n + 1 && x.len() == n && d.len() == n + 1);
        let scale = v.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        // Rounding of an increment (two values of size `scale`) and of a multiplier summed along
        // a segment of a few links; the DP settles anything within these anyway.
        let tol_p = 8.0 * f64::EPSILON * scale;
        let tol_d = 64.0 * f64::EPSILON * scale * self.max_inv_k;
        self.viol.clear();
        if !self.pass(lo, hi, v, x, d, tol_p, tol_d) {
            self.full_dp(lo, hi, v, x, d);
            return 1;
        }
        if self.viol.is_empty() {
            self.clean(d);
            return 0;
        }
        let windows = self.repair(lo, hi, v, x, d, tol_p);
        self.clean(d);
        windows
    }

    /// The fused pass: `x` and `D` of the working set, and the blocks that violate a KKT
    /// condition (flagged in `bad`, listed in `viol`). `false` when no block is free.
    #[allow(clippy::too_many_arguments)]
    fn pass(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &mut [f64],
        d: &mut [f64],
        tol_p: f64,
        tol_d: f64,
    ) -> bool {
        let n = v.len();
        let ws = &self.ws;
        let w = &self.inv_k;
        let bound = |b: usize| match ws[b] {
            Bound::Lower => lo[b],
            Bound::Upper => hi[b],
            Bound::Free => 0.0,
        };
        let wrong = |b: usize, db: f64| match ws[b] {
            Bound::Lower => db < -tol_d,
            Bound::Upper => db > tol_d,
            Bound::Free => false,
        };
        let Some(f0) = ws.iter().position(|&b| b == Bound::Free) else {
            return false;
        };
        let viol = &mut self.viol;
        let bad = &mut self.bad;
        let mut flag = |b: usize| {
            bad[b] = true;
            viol.push(b);
        };
        // Links 0..f0 pinned to x_{-1} = 0; D backward from D_f0 = 0.
        let mut p = 0.0;
        for l in 0..f0 {
            p += bound(l);
            x[l] = p;
        }
        d[f0] = 0.0;
        let mut dl = 0.0;
        for b in (0..f0).rev() {
            dl += (x[b] - v[b]) * w[b];
            d[b] = dl;
            if wrong(b, dl) {
                flag(b);
            }
        }
        // Segments start..e closed by free blocks: floating, then the last one pinned to x_n = 0.
        let mut start = f0;
        loop {
            let e = (start + 1..=n)
                .find(|&b| ws[b] == Bound::Free)
                .unwrap_or(n + 1);
            let end = e.min(n);
            if e <= n {
                // Floating: x_l = c + o_l over links start..e.
                let (mut o, mut sw, mut swv) = (0.0, 0.0, 0.0);
                for l in start..e {
                    if l > start {
                        o += bound(l);
                    }
                    x[l] = o;
                    sw += w[l];
                    swv += w[l] * (v[l] - o);
                }
                let c = swv / sw;
                for xl in &mut x[start..e] {
                    *xl += c;
                }
            } else {
                // Pinned to x_n = 0 from the right.
                let mut p = 0.0;
                for l in (start..n).rev() {
                    p -= bound(l + 1);
                    x[l] = p;
                }
            }
            // The free block `start`: its increment within bounds.
            let left = if start > 0 { x[start - 1] } else { 0.0 };
            let right = if start < n { x[start] } else { 0.0 };
            let inc = right - left;
            if inc < lo[start] - tol_p || inc > hi[start] + tol_p {
                flag(start);
            }
            // D forward from D_start = 0 over the segment's active blocks.
            let mut dl = 0.0;
            for b in start + 1..=end {
                dl += (v[b - 1] - x[b - 1]) * w[b - 1];
                if b == e {
                    break;
                }
                d[b] = dl;
                if wrong(b, dl) {
                    flag(b);
                }
            }
            if e > n {
                break;
            }
            d[e] = 0.0;
            start = e;
        }
        true
    }

    /// Repairs every flagged block by windows solved with the DP (see the module docs).
    /// Returns the number of windows.
    fn repair(
        &mut self,
        lo: &[f64],
        hi: &[f64],
        v: &[f64],
        x: &mut [f64],
        d: &mut [f64],
        tol_p: f64,
    ) -> usize {
        let n = v.len();
        let budget = 2 * (n as u64 + 1);
        let mut spent = 0u64;
        let mut windows = 0;
        let viol = std::mem::take(&mut self.viol);
        for &p in &viol {
            if !self.bad[p] {
                continue;
            }
            // Cuts: free, unflagged blocks strictly around p (None: the end of the chain).
            let (mut s, mut e) = (self.cut_left(p, 1), self.cut_right(p, 1, n));
            let (mut rl, mut rr) = (1, 1);
            loop {
                let (ls, le) = (s.unwrap_or(0), e.unwrap_or(n));
                spent += (le - ls) as u64;
                windows += 1;
                if spent > budget {
                    self.viol = viol;
                    self.full_dp(lo, hi, v, x, d);
                    return windows;
                }
                self.dp
                    .solve_window(lo, hi, v, x, d, (ls, s.is_some()), (le, e.is_some()));
                self.windows += 1;
                self.window_links += (le - ls) as u64;
                let inc = |b: usize| {
                    let right = if b < n { x[b] } else { 0.0 };
                    let left = if b > 0 { x[b - 1] } else { 0.0 };
                    right - left
                };
                let ok = |b: usize| {
                    let i = inc(b);
                    i >= lo[b] - tol_p && i <= hi[b] + tol_p
                };
                let left_ok = s.is_none_or(ok);
                let right_ok = e.is_none_or(ok);
                // The window's faces (its cuts stay free).
                self.ws[ls + 1..le].copy_from_slice(&self.dp.working_set()[ls + 1..le]);
                if let Some(b) = s {
                    self.ws[b] = Bound::Free;
                }
                if let Some(b) = e {
                    self.ws[b] = Bound::Free;
                }
                if s.is_none() {
                    self.ws[0] = self.dp.working_set()[0];
                }
                if e.is_none() {
                    self.ws[n] = self.dp.working_set()[n];
                }
                if left_ok && right_ok {
                    self.bad[ls..=le].iter_mut().for_each(|f| *f = false);
                    break;
                }
                if !left_ok {
                    rl *= 2;
                    s = s.and_then(|b| self.cut_left(b, rl));
                }
                if !right_ok {
                    rr *= 2;
                    e = e.and_then(|b| self.cut_right(b, rr, n));
                }
            }
        }
        self.viol = viol;
        windows
    }

    /// The `r`-th free, unflagged block left of `p`, or `None` (the chain's left end).
    fn cut_left(&self, p: usize, r: usize) -> Option<usize> {
        let mut left = r;
        for b in (0..p).rev() {
            if self.ws[b] == Bound::Free && !self.bad[b] {
                left -= 1;
                if left == 0 {
                    return Some(b);
                }
            }
        }
        None
    }

    /// The `r`-th free, unflagged block right of `p`, or `None` (the chain's right end).
    fn cut_right(&self, p: usize, r: usize, n: usize) -> Option<usize> {
        let mut left = r;
        for b in p + 1..=n {
            if self.ws[b] == Bound::Free && !self.bad[b] {
                left -= 1;
                if left == 0 {
                    return Some(b);
                }
            }
        }
        None
    }

    fn full_dp(&mut self, lo: &[f64], hi: &[f64], v: &[f64], x: &mut [f64], d: &mut [f64]) {
        self.dp.solve(lo, hi, v, x, d);
        self.ws.copy_from_slice(self.dp.working_set());
        self.bad.iter_mut().for_each(|f| *f = false);
        self.full += 1;
    }

    /// Tiny wrong-signed multipliers of degenerate faces (rounding) are zero.
    fn clean(&self, d: &mut [f64]) {
        for (db, w) in d.iter_mut().zip(&self.ws) {
            match w {
                Bound::Lower if *db < 0.0 => *db = 0.0,
                Bound::Upper if *db > 0.0 => *db = 0.0,
                _ => {}
            }
        }
    }
}
