//! The chain QP of [`super::ChainQp`] solved exactly from a guessed working set, repaired
//! locally: the projection of a catching-up step near a periodic orbit in one pass over the
//! chain.
//!
//! **Guess and certify.** With the previous step's working set `W` taken as equalities, the
//! minimiser is separable per rigid segment (the links between two consecutive free blocks; see
//! [`super::ChainQp`]): a segment touching an end of the chain is pinned, every other floats at
//! the `1/k`-weighted mean of `v` minus its offsets. The multipliers follow segment by segment
//! from stationarity `D_{b+1} - D_b = (v_b - x_b)/k_b` with `D = 0` on the free blocks (theory §4).
//! One pass (a forward sweep of running sums, a backward one for the rest) computes `x`, `D` and
//! both checks of the KKT conditions: every free block's increment within its bounds (primal),
//! every active block's multiplier of the right sign (`D_b >= 0` on a forward face, `<= 0` on a
//! backward one). When both hold, `(x, D)` is the unique minimiser (a strictly convex QP) and
//! the step cost one pass: on the bench gait near its orbit (N = 1000) this is about 96 % of the
//! steps, and the windows of the others span about three links each.
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

use super::chain::{increment, Bound};
use super::dp::ChainDp;

/// The point to project: given, or `x + delta` formed by the pass into `v`.
enum Input<'a> {
    Point(&'a [f64]),
    Increment { delta: &'a [f64], v: &'a mut [f64] },
}

/// Solver of the chain QP from the previous solution's working set. See the module docs.
#[derive(Debug, Clone)]
pub struct ChainWarm {
    inv_k: Vec<f64>,
    max_inv_k: f64,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// The working set: the guess on entry to [`ChainWarm::solve`], the faces of the solution on
    /// exit.
    ws: Vec<Bound>,
    /// Per block: `+1` on a forward face (needs `D >= 0`), `-1` on a backward one, else `0`.
    sgn: Vec<f64>,
    /// Per link `l`, what the pass reads of link `l` and block `l + 1`, in one record.
    rec: Vec<Rec>,
    /// Running `sum w v` over each link's segment (scratch of the pass).
    swv: Vec<f64>,
    /// Blocks whose check failed in the pass and no window has repaired yet.
    bad: Vec<bool>,
    viol: Vec<usize>,
    /// `x + delta` of [`ChainWarm::solve_increment`].
    v: Vec<f64>,
    dp: ChainDp,
    windows: u64,
    window_links: u64,
    full: u64,
}

/// What the pass reads per link `l` (see `ChainWarm::pass`), from the working set and the
/// data alone: the link's offset `o_l` in its segment, over the segment's links so far `sum w o`
/// and `1 / sum w`, the weight `w_l = 1/k_l`; of block `l + 1`: `1` on a face (the segment goes
/// on) else `0`, the sign its multiplier needs (`+1`, `-1`, `0` when free), its bounds.
#[derive(Debug, Clone, Copy, Default)]
struct Rec {
    off: f64,
    cwo: f64,
    cisw: f64,
    w: f64,
    on: f64,
    sgn: f64,
    lo: f64,
    hi: f64,
}

impl ChainWarm {
    /// A solver for links of stiffness `k` (weights `1/k_l`) and finite bounds `lo < hi` per
    /// block whose feasible set contains a point (for C: `lo = -mu^+`, `hi = mu^-`, and 0), with
    /// an empty working set.
    pub fn new(stiffness: &[f64], lo: &[f64], hi: &[f64]) -> Self {
        let n = stiffness.len();
        debug_assert!(lo.len() == n + 1 && hi.len() == n + 1);
        let mut s = ChainWarm {
            inv_k: stiffness.iter().map(|k| 1.0 / k).collect(),
            max_inv_k: stiffness.iter().fold(0.0_f64, |m, k| m.max(1.0 / k)),
            lo: lo.to_vec(),
            hi: hi.to_vec(),
            ws: vec![Bound::Free; n + 1],
            sgn: vec![0.0; n + 1],
            rec: vec![Rec::default(); n],
            swv: vec![0.0; n],
            bad: vec![false; n + 1],
            viol: Vec::new(),
            v: vec![0.0; n],
            dp: ChainDp::new(stiffness),
            windows: 0,
            window_links: 0,
            full: 0,
        };
        s.sync();
        s
    }

    /// The faces of the last solution (one entry per block).
    pub fn working_set(&self) -> &[Bound] {
        &self.ws
    }

    /// Replaces the working set used as the next guess.
    pub fn set_working_set(&mut self, ws: &[Bound]) {
        self.ws.copy_from_slice(ws);
        self.sync();
    }

    /// Work counters so far: windows solved by the DP, links in them, and whole-chain DP solves.
    pub fn counters(&self) -> (u64, u64, u64) {
        (self.windows, self.window_links, self.full)
    }

    /// Projects `v`: `x` receives the minimiser (its content on entry is not used), `d` the
    /// multipliers `D_b`; the working set becomes the solution's faces. Returns the number of
    /// windows solved (0 when the guess was right).
    pub fn solve(&mut self, v: &[f64], x: &mut [f64], d: &mut [f64]) -> usize {
        let n = v.len();
        assert!(n == self.inv_k.len() && x.len() == n && d.len() == n + 1);
        self.viol.clear();
        let res = self.pass(Input::Point(v), x, d);
        self.finish(res, v, x, d)
    }

    /// A catching-up step: projects `v = x + delta` (`x` the state on entry, in C), as
    /// [`ChainWarm::solve`]. `v` is formed inside the pass's forward sweep, whose running sums
    /// leave the memory system time to stream `delta` (a separate sum over it was about a fifth
    /// of a step at N = 1000, the period's increments being read from memory).
    pub fn solve_increment(&mut self, x: &mut [f64], delta: &[f64], d: &mut [f64]) -> usize {
        let n = x.len();
        assert!(n == self.inv_k.len() && delta.len() == n && d.len() == n + 1);
        self.viol.clear();
        let mut v = std::mem::take(&mut self.v);
        let res = self.pass(Input::Increment { delta, v: &mut v }, x, d);
        let windows = self.finish(res, &v, x, d);
        self.v = v;
        windows
    }

    /// After the pass: the whole-chain DP when no block is free, else the windows' repair.
    fn finish(&mut self, res: Option<f64>, v: &[f64], x: &mut [f64], d: &mut [f64]) -> usize {
        let Some(tol_p) = res else {
            self.full_dp(v, x, d);
            self.sync();
            return 1;
        };
        if self.viol.is_empty() {
            return 0;
        }
        let windows = self.repair(v, x, d, tol_p);
        self.sync();
        self.clean(d);
        windows
    }

    /// The pass: `x` and `D` of the working set, and the blocks that violate a KKT condition
    /// (flagged in `bad`, listed in `viol`). Returns the primal tolerance, or `None` when no
    /// block is free.
    ///
    /// Between the first and the last free block the segments float; they are swept without a
    /// branch on the segment structure (segments are short near an orbit, so branches on their
    /// ends would mispredict), with what depends on the working set alone cached by `sync`:
    /// forward, the running `sum w v` restarted (masked) at free blocks; backward, the mean of
    /// the segment's last link carried over it, `x = o + c`, `D` summed from `D = 0` at the
    /// segment's right end, and both checks or-ed into one flag. Only when the flag is up is
    /// the chain scanned again for the blocks to repair.
    fn pass(&mut self, input: Input<'_>, x: &mut [f64], d: &mut [f64]) -> Option<f64> {
        let n = x.len();
        let Some(f0) = self.ws.iter().position(|&b| b == Bound::Free) else {
            if let Input::Increment { delta, v } = input {
                for ((vl, xl), dl) in v.iter_mut().zip(x.iter()).zip(delta) {
                    *vl = xl + dl;
                }
            }
            return None;
        };
        let fl = self
            .ws
            .iter()
            .rposition(|&b| b == Bound::Free)
            .unwrap_or(f0);
        let (w, lo, hi) = (&self.inv_k[..n], &self.lo[..=n], &self.hi[..=n]);
        let bnd = |b: usize| match self.ws[b] {
            Bound::Lower => lo[b],
            Bound::Upper => hi[b],
            Bound::Free => 0.0,
        };
        let wrong = |b: usize, db: f64, tol: f64| wrong_sign(self.ws[b], db, tol);
        // Floating segments over links f0..fl, forward: the running sum restarts after a link
        // whose right block is free (`on = 0`); block f0 is free.
        let rec = &self.rec[f0..fl];
        let v = floating_sums(rec, &mut self.swv[f0..fl], input, x, (f0, fl));
        let vm = &v[f0..fl];
        let scale = max_abs(v);
        // Rounding of an increment (two values of size `scale`) and of a multiplier summed along
        // a segment of a few links; the DP settles anything within these anyway.
        let tol_p = 8.0 * f64::EPSILON * scale;
        let tol_d = 64.0 * f64::EPSILON * scale * self.max_inv_k;
        // Links fl..n pinned to x_n = 0; D forward from D_fl = 0.
        let mut p = 0.0;
        for l in (fl..n).rev() {
            p -= bnd(l + 1);
            x[l] = p;
        }
        d[fl] = 0.0;
        let mut dl = 0.0;
        let mut bad = false;
        for b in fl + 1..=n {
            dl += (v[b - 1] - x[b - 1]) * w[b - 1];
            d[b] = dl;
            bad |= wrong(b, dl, tol_d);
        }
        // Backward over links fl - 1..f0: x, D and the checks of blocks f0 + 1..=fl.
        let (mut c, mut db) = (0.0_f64, 0.0_f64);
        let mut right = if fl < n { x[fl] } else { 0.0 };
        let (xm, dm) = (&mut x[f0..fl], &mut d[f0 + 1..=fl]);
        let swv = &self.swv[f0..fl];
        // The least of `sgn D`, of `inc - lo` and of `hi - inc` (three independent minima).
        let (mut min_d, mut min_lo, mut min_hi) = (0.0_f64, f64::INFINITY, f64::INFINITY);
        for i in (0..fl - f0).rev() {
            let r = rec[i];
            let on = r.on != 0.0;
            c = if on { c } else { (swv[i] - r.cwo) * r.cisw };
            let xl = r.off + c;
            xm[i] = xl;
            let dn = if on { db } else { 0.0 };
            dm[i] = dn;
            let inc = right - xl;
            // Both checks on every block: on a face the increment is its bound (to rounding).
            let (sd, dlo, dhi) = (r.sgn * dn, inc - r.lo, r.hi - inc);
            min_d = if sd < min_d { sd } else { min_d };
            min_lo = if dlo < min_lo { dlo } else { min_lo };
            min_hi = if dhi < min_hi { dhi } else { min_hi };
            db = dn + (xl - vm[i]) * r.w;
            right = xl;
        }
        bad |= min_d < -tol_d || min_lo < -tol_p || min_hi < -tol_p;
        d[f0] = 0.0;
        // Links 0..f0 pinned to x_{-1} = 0; D backward from D_f0 = 0.
        let mut p = 0.0;
        for (l, xl) in x[..f0].iter_mut().enumerate() {
            p += bnd(l);
            *xl = p;
        }
        let mut dl = 0.0;
        for b in (0..f0).rev() {
            dl += (x[b] - v[b]) * w[b];
            d[b] = dl;
            bad |= wrong(b, dl, tol_d);
        }
        let inc = increment(x, f0);
        bad |= inc < lo[f0] - tol_p || inc > hi[f0] + tol_p;
        if bad {
            self.flag_violations(x, d, tol_p, tol_d);
        }
        // Tiny wrong-signed multipliers of degenerate faces (rounding) are zero (after a repair,
        // once the faces are final).
        if self.viol.is_empty() {
            for (db, sb) in d.iter_mut().zip(&self.sgn[..=n]) {
                *db = if sb * *db < 0.0 { 0.0 } else { *db };
            }
        }
        Some(tol_p)
    }

    /// The blocks that violate a KKT condition after a pass whose flag is up: a free block's
    /// increment out of its bounds, or a face's `D` of the wrong sign (by more than the
    /// tolerances), flagged in `bad` and listed in `viol`.
    fn flag_violations(&mut self, x: &[f64], d: &[f64], tol_p: f64, tol_d: f64) {
        let (lo, hi) = (&self.lo, &self.hi);
        for b in 0..x.len() + 1 {
            let inc = increment(x, b);
            let wrong_p = self.ws[b] == Bound::Free && (inc < lo[b] - tol_p || inc > hi[b] + tol_p);
            if wrong_p || wrong_sign(self.ws[b], d[b], tol_d) {
                self.bad[b] = true;
                self.viol.push(b);
            }
        }
    }

    /// The per-link records of the pass, which depend on the working set alone (see `pass`).
    fn sync(&mut self) {
        let n = self.rec.len();
        for (b, ws) in self.ws.iter().enumerate() {
            self.sgn[b] = match ws {
                Bound::Free => 0.0,
                Bound::Lower => 1.0,
                Bound::Upper => -1.0,
            };
        }
        let (mut o, mut swo, mut sw) = (0.0, 0.0, 0.0);
        for l in 0..n {
            match self.ws[l] {
                Bound::Lower => o += self.lo[l],
                Bound::Upper => o += self.hi[l],
                Bound::Free => (o, swo, sw) = (0.0, 0.0, 0.0),
            }
            let w = self.inv_k[l];
            sw += w;
            swo += w * o;
            self.rec[l] = Rec {
                off: o,
                cwo: swo,
                cisw: 1.0 / sw,
                w,
                on: if self.ws[l + 1] == Bound::Free {
                    0.0
                } else {
                    1.0
                },
                sgn: self.sgn[l + 1],
                lo: self.lo[l + 1],
                hi: self.hi[l + 1],
            };
        }
    }

    /// Repairs every flagged block by windows solved with the DP (see the module docs).
    /// Returns the number of windows.
    fn repair(&mut self, v: &[f64], x: &mut [f64], d: &mut [f64], tol_p: f64) -> usize {
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
                    self.full_dp(v, x, d);
                    return windows;
                }
                self.dp.solve_window(
                    &self.lo,
                    &self.hi,
                    v,
                    x,
                    d,
                    (ls, s.is_some()),
                    (le, e.is_some()),
                );
                self.windows += 1;
                self.window_links += (le - ls) as u64;
                let inc = |b: usize| {
                    let right = if b < n { x[b] } else { 0.0 };
                    let left = if b > 0 { x[b - 1] } else { 0.0 };
                    right - left
                };
                let ok = |b: usize| {
                    let i = inc(b);
                    i >= self.lo[b] - tol_p && i <= self.hi[b] + tol_p
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

    fn full_dp(&mut self, v: &[f64], x: &mut [f64], d: &mut [f64]) {
        self.dp.solve(&self.lo, &self.hi, v, x, d);
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

/// The pass's forward sweep over the floating links `f0..fl` (block `f0` free): the running
/// `sum w v` of each segment into `swv`, restarted after a link whose right block is free
/// (`on = 0`). For an increment input, `v = x + delta` is formed on the way (and on the pinned
/// links outside). Returns `v`.
fn floating_sums<'a>(
    rec: &[Rec],
    swv: &mut [f64],
    input: Input<'a>,
    x: &[f64],
    (f0, fl): (usize, usize),
) -> &'a [f64] {
    let n = x.len();
    let mut s = 0.0_f64;
    let mut on = 0.0_f64;
    match input {
        Input::Point(v) => {
            for ((r, &vl), sl) in rec.iter().zip(&v[f0..fl]).zip(swv.iter_mut()) {
                s = if on != 0.0 { s } else { 0.0 } + r.w * vl;
                *sl = s;
                on = r.on;
            }
            v
        }
        Input::Increment { delta, v } => {
            for l in (0..f0).chain(fl..n) {
                v[l] = x[l] + delta[l];
            }
            let it = rec.iter().zip(swv.iter_mut()).zip(&mut v[f0..fl]);
            for (((r, sl), vl), (xl, dl)) in it.zip(x[f0..fl].iter().zip(&delta[f0..fl])) {
                *vl = xl + dl;
                s = if on != 0.0 { s } else { 0.0 } + r.w * *vl;
                *sl = s;
                on = r.on;
            }
            v
        }
    }
}

/// Whether `D_b = db` has the wrong sign for a block on face `ws`, by more than `tol`.
#[inline]
fn wrong_sign(ws: Bound, db: f64, tol: f64) -> bool {
    match ws {
        Bound::Lower => db < -tol,
        Bound::Upper => db > tol,
        Bound::Free => false,
    }
}

/// `max |v|` in four independent lanes (no loop-carried chain through one register).
fn max_abs(v: &[f64]) -> f64 {
    let mut lanes = [0.0_f64; 4];
    let chunks = v.chunks_exact(4);
    for a in chunks.remainder() {
        lanes[0] = if a.abs() > lanes[0] {
            a.abs()
        } else {
            lanes[0]
        };
    }
    for ch in chunks {
        for (m, a) in lanes.iter_mut().zip(ch) {
            *m = if a.abs() > *m { a.abs() } else { *m };
        }
    }
    lanes.iter().fold(0.0_f64, |m, &a| m.max(a))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tiny chains (1 to 6 links, thresholds on a grid of 1/4 plus 0.01 so that the uniqueness
    /// condition holds) along steps of random size: the same minimiser as the DP.
    #[test]
    fn matches_dp_on_small_chains_along_steps() {
        let mut seed = 11u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / (1u64 << 53) as f64
        };
        for case in 0..2000 {
            let n = 1 + (rnd() * 6.0) as usize;
            let k: Vec<f64> = (0..n).map(|_| 0.5 + rnd()).collect();
            let lo: Vec<f64> = (0..=n)
                .map(|_| -(0.25 + (rnd() * 8.0).floor() / 4.0))
                .collect();
            let hi: Vec<f64> = (0..=n)
                .map(|_| 0.25 + (rnd() * 8.0).floor() / 4.0 + 0.01)
                .collect();
            let mut warm = ChainWarm::new(&k, &lo, &hi);
            let mut dp = ChainDp::new(&k);
            for step in 0..5 {
                let v: Vec<f64> = (0..n).map(|_| 4.0 * rnd() - 2.0).collect();
                let ws0 = warm.working_set().to_vec();
                let (mut x1, mut d1) = (vec![0.0; n], vec![0.0; n + 1]);
                let (mut x2, mut d2) = (vec![0.0; n], vec![0.0; n + 1]);
                dp.solve(&lo, &hi, &v, &mut x1, &mut d1);
                let w = warm.solve(&v, &mut x2, &mut d2);
                let e = x1
                    .iter()
                    .zip(&x2)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                let ed = d1
                    .iter()
                    .zip(&d2)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(
                    e < 1e-12 && ed < 1e-12,
                    "case {case} step {step} ({w} windows) from {ws0:?}: x {x2:?} against {x1:?}"
                );
            }
        }
    }
}
