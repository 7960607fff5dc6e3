//! Newton-Krylov steps for the periodic orbit of a long chain (issue 15).
//!
//! **What is slow.** Near the orbit of the bench gait (travelling sine, k = 1, mu+ = 1,
//! mu- = 3.3, 1000 catching-up steps) the Jacobian `J` of the period map, built densely from
//! tangent products, is a nonnegative matrix with row sums at most 1 (every step's tangent
//! averages the links glued into one segment and pins the segments that reach an end), about
//! half of its eigenvalues are 0 and the others are real. The leading ones follow
//! `lambda_j ~ 1 - c j^2 / N^2` with `c ~ 30`: `1 - lambda_1` = 1.26e-2, 3.06e-3, 7.5e-4 for
//! N = 50, 100, 200; eigenvalues above 0.9: 2, 5, 11; above 0.99: 0, 1, 3. Their eigenvectors
//! are the sine modes `sin(j pi l / N)` of the chain (j - 1 sign changes, more than 98 % of
//! their energy in the 8 lowest cosine modes, spread over the whole chain): the slow part of
//! `I - J` is a diffusion along the chain with the ends pinned, `I - J ~ alpha L` on smooth
//! vectors with `L` the Dirichlet second difference (`alpha ~ 3`). The active pattern over a
//! period settles early: from the 26th plain period from rest on, `J v` is the same as on the
//! orbit to the last bit for N = 50, 100, 200, so the map is affine there and one exact Newton
//! step lands on the orbit. Plain iteration needs `O(N^2)` periods and Anderson (a Krylov method
//! in disguise) `O(N)`. (Measured by building `J` from N tangent products at the orbit found by
//! `simulate`, eigenvalues by nalgebra's Schur form, eigenvectors by inverse iteration;
//! `tests/orbit.rs` checks the structure, the `30 / N^2` gap and the one-signed slowest mode at
//! N = 50 and 100.)
//!
//! **The step.** `(I - J) s = G(x) - x` is solved by GMRES preconditioned on the right by
//! `P^{-1} = (alpha L)^{-1} + I`: on the smooth modes `P ~ alpha L ~ I - J`, on the rough ones
//! `P ~ I ~ I - J` (their eigenvalues of `J` are small), so the preconditioned operator is close
//! to the identity whatever N, and the GMRES iterations do not grow with N. `alpha` is measured
//! with one product on the slowest sine mode. Each product applies the tangent maps recorded
//! during the last period ([`super::PeriodMap::apply_tangent`]), without a projection: the
//! pattern is kept as the blocks that change state step after step, and a product re-averages
//! only the segments around them (catching-up's `PatternLog`; 0.03 ms per product at
//! N = 1000 where applying every step's tangent took 3.4 ms). Memory `O(m N)` for a Krylov
//! basis of `m` vectors and `O(N + M + changes)` for the pattern, nothing `N x N`.
//!
//! **Heterogeneous chains.** On the chain of `tests/orbit.rs` (N = 120, per-link stiffness in
//! [0.5, 2], four friction pairs, 60 degrees per link) the Jacobian at the orbit is the same kind
//! of pinned diffusion (`1 - lambda_1` = 2.9e-3, 41 / N^2) and the preconditioner still works:
//! `alpha` = 5.8, the spectrum of the preconditioned operator lies in [0.49, 1.53] (bench gait:
//! [1.08, 1.66]) and GMRES reaches 1e-10 in 22 iterations (16 on the bench gait, 38 to 42
//! unpreconditioned), so a stiffness-weighted `L` has little to gain. What fails is the
//! linear model: the active pattern does not settle during the search. After 400 plain periods
//! the state is still 0.65 from the orbit and `J v` differs from the orbit's by 2e-2 to 0.25;
//! from random states around the orbit `J v` is the orbit's only within 3e-4 (max norm) of it,
//! against a distance of about `residual / (1 - lambda_1)`, so a Newton step lands only once the
//! residual is about 1e-6, and every step tried before fails (amplified by `(I - J)^{-1}`, of
//! norm ~ N^2 / 40, a pattern error of a fraction of `1 - lambda_1` spoils it). The
//! preconditioner itself does not need the pattern: Anderson mixing the preconditioned residual
//! `P^{-1} (G(x) - x)` ([`NewtonOptions::precondition_anderson`]) finds the orbit in 27 to 52
//! periods for N = 100 to 1000 (random chains), against 62 to 1444 for Anderson on `G(x) - x`.
//! (Measured with dense Jacobians from N tangent products, nalgebra's eigenvalues and
//! unrestarted GMRES on them, and plain periods from rest.)

/// Settings of the Newton-Krylov search ([`super::SimOptions::newton`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Most Jacobian-vector products (GMRES iterations) per Newton step (default 60).
    pub max_products: usize,
    /// Krylov basis size before GMRES restarts (default 30): memory `basis x N` values.
    pub basis: usize,
    /// Newton steps that may fail (the residual of the period from the new state not below
    /// half the previous one) before the search continues with Anderson only (default 1). On
    /// the bench gait the first step lands on the orbit. On heterogeneous chains (per-link
    /// stiffness, per-block friction) every step tried before the search is within about
    /// 1e-3 of the orbit fails: the active pattern of the period holds only that close (see the
    /// module docs), and the preconditioned Anderson mixing
    /// ([`NewtonOptions::precondition_anderson`]) is then cheaper than another step.
    pub max_failures: usize,
    /// Periods of Anderson acceleration after a failed Newton step before the next one
    /// (default 10).
    pub retry_after: usize,
    /// Anderson mixes the preconditioned residual `P^{-1} (G(x) - x)` (`P` the chain's
    /// diffusion, below) instead of `G(x) - x` (default `true`): the mixed map contracts by
    /// about a half per period whatever N, where the plain one contracts by `1 - 30 / N^2`. Its
    /// `alpha` is measured once with one product; a residual that doubles halves the weight of
    /// the diffusion part.
    pub precondition_anderson: bool,
}

impl NewtonOptions {
    /// The defaults.
    pub const DEFAULT: NewtonOptions = NewtonOptions {
        max_products: 60,
        basis: 30,
        max_failures: 1,
        retry_after: 10,
        precondition_anderson: true,
    };
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The preconditioner `P^{-1} v = (alpha L)^{-1} v + v`, `L` the Dirichlet second difference
/// (2 on the diagonal, -1 beside it) on the links.
pub(super) struct Diffusion {
    alpha: f64,
    /// Weight of the diffusion part: `P^{-1} v = weight (alpha L)^{-1} v + v`.
    pub(super) weight: f64,
    /// Thomas factors of `L`: the modified super-diagonal.
    c: Vec<f64>,
    w: Vec<f64>,
}

impl Diffusion {
    pub(super) fn new(n: usize) -> Self {
        let mut c = vec![0.0; n];
        let mut denom = 2.0;
        for ci in c.iter_mut() {
            *ci = -1.0 / denom;
            denom = 2.0 + *ci;
        }
        Diffusion {
            alpha: 1.0,
            weight: 1.0,
            c,
            w: vec![0.0; n],
        }
    }

    /// `out <- L v`.
    fn laplacian(v: &[f64], out: &mut [f64]) {
        let n = v.len();
        for i in 0..n {
            let left = if i > 0 { v[i - 1] } else { 0.0 };
            let right = if i + 1 < n { v[i + 1] } else { 0.0 };
            out[i] = 2.0 * v[i] - left - right;
        }
    }

    /// The preconditioner with `alpha` measured by one product `jac` on the slowest sine mode:
    /// `alpha = <v, (I - J) v> / <v, L v>` (1 where that is not positive).
    pub(super) fn measured(n: usize, jac: &mut dyn FnMut(&mut [f64])) -> Self {
        let mut pre = Diffusion::new(n);
        let v: Vec<f64> = (0..n)
            .map(|l| (std::f64::consts::PI * (l + 1) as f64 / (n + 1) as f64).sin())
            .collect();
        let mut jv = v.clone();
        jac(&mut jv);
        let mut lv = vec![0.0; n];
        Diffusion::laplacian(&v, &mut lv);
        let num: f64 = v.iter().zip(&jv).map(|(a, b)| a * (a - b)).sum();
        let den: f64 = v.iter().zip(&lv).map(|(a, b)| a * b).sum();
        if num.is_finite() && num > 0.0 && den > 0.0 {
            pre.alpha = num / den;
        }
        pre
    }

    /// `out <- P^{-1} v`.
    pub(super) fn apply(&mut self, v: &[f64], out: &mut [f64]) {
        let n = v.len();
        // Forward sweep of the Thomas algorithm on L w = v (diagonal 2, off-diagonals -1).
        let mut denom = 2.0;
        for i in 0..n {
            let prev = if i > 0 { self.w[i - 1] } else { 0.0 };
            self.w[i] = (v[i] + prev) / denom;
            denom = 2.0 + self.c[i];
        }
        for i in (0..n.saturating_sub(1)).rev() {
            self.w[i] -= self.c[i] * self.w[i + 1];
        }
        for i in 0..n {
            out[i] = self.weight * self.w[i] / self.alpha + v[i];
        }
    }
}

/// A Newton step: the solution `s` of `(I - J) s = r` found by right-preconditioned restarted
/// GMRES, `jac(v)` applying `v <- J v`. Stops when `|r - (I - J) s|_2 <= rel_tol |r|_2` or after
/// `opts.max_products` products. Returns the step, the products used (including the one that
/// measures the preconditioner's `alpha`) and the relative residual reached.
pub(super) fn newton_step(
    jac: &mut dyn FnMut(&mut [f64]),
    r: &[f64],
    rel_tol: f64,
    opts: &NewtonOptions,
) -> (Vec<f64>, usize, f64) {
    let n = r.len();
    let mut pre = Diffusion::measured(n, jac);
    let mut products = 1;
    let norm = |a: &[f64]| a.iter().map(|x| x * x).sum::<f64>().sqrt();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let r_norm = norm(r);
    let mut s = vec![0.0; n];
    if !(r_norm > 0.0 && r_norm.is_finite()) {
        return (s, products, 0.0);
    }
    let m = opts.basis.max(1);
    let mut res = r.to_vec();
    let mut rel = 1.0;
    let mut z = vec![0.0; n];
    while products < opts.max_products && rel > rel_tol {
        // One cycle of GMRES(m) from the current s, residual res = r - (I - J) s.
        let beta = norm(&res);
        let mut basis: Vec<Vec<f64>> = vec![res.iter().map(|x| x / beta).collect()];
        let mut h: Vec<Vec<f64>> = Vec::new(); // columns of the Hessenberg matrix, rotated
        let (mut cs, mut sn): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
        let mut g = vec![beta];
        for j in 0..m {
            if products >= opts.max_products {
                break;
            }
            pre.apply(&basis[j], &mut z);
            let mut w = z.clone();
            jac(&mut w);
            products += 1;
            w.iter_mut().zip(&z).for_each(|(wi, zi)| *wi = zi - *wi);
            let mut col = vec![0.0; j + 2];
            for (i, b) in basis.iter().enumerate() {
                col[i] = dot(&w, b);
                w.iter_mut().zip(b).for_each(|(wi, bi)| *wi -= col[i] * bi);
            }
            col[j + 1] = norm(&w);
            for i in 0..j {
                let t = cs[i] * col[i] + sn[i] * col[i + 1];
                col[i + 1] = -sn[i] * col[i] + cs[i] * col[i + 1];
                col[i] = t;
            }
            let d = col[j].hypot(col[j + 1]);
            let (c, s_) = if d > 0.0 {
                (col[j] / d, col[j + 1] / d)
            } else {
                (1.0, 0.0)
            };
            col[j] = d;
            col[j + 1] = 0.0;
            g.push(-s_ * g[j]);
            g[j] *= c;
            cs.push(c);
            sn.push(s_);
            let next = col_norm_tail(&w, &mut basis);
            h.push(col);
            rel = g[j + 1].abs() / r_norm;
            if rel <= rel_tol || !next {
                break;
            }
        }
        let k = h.len();
        if k == 0 {
            break;
        }
        // Back substitution of the rotated (upper triangular) system, then s += P^{-1} V y.
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let mut t = g[i];
            for (jj, yj) in y.iter().enumerate().skip(i + 1) {
                t -= h[jj][i] * yj;
            }
            y[i] = if h[i][i] != 0.0 { t / h[i][i] } else { 0.0 };
        }
        let mut comb = vec![0.0; n];
        for (b, yi) in basis.iter().zip(&y) {
            comb.iter_mut().zip(b).for_each(|(c, bi)| *c += yi * bi);
        }
        pre.apply(&comb, &mut z);
        s.iter_mut().zip(&z).for_each(|(si, zi)| *si += zi);
        // The true residual for the restart (one more product).
        if rel > rel_tol && products < opts.max_products {
            let mut js = s.clone();
            jac(&mut js);
            products += 1;
            for i in 0..n {
                res[i] = r[i] - (s[i] - js[i]);
            }
            rel = norm(&res) / r_norm;
        }
    }
    (s, products, rel)
}

/// Appends the normalised `w` to the basis; `false` (nothing appended) on a breakdown, when `w`
/// vanished (the Krylov space is invariant and the solution exact in it).
fn col_norm_tail(w: &[f64], basis: &mut Vec<Vec<f64>>) -> bool {
    let nw = w.iter().map(|x| x * x).sum::<f64>().sqrt();
    if nw > 0.0 && nw.is_finite() {
        basis.push(w.iter().map(|x| x / nw).collect());
        true
    } else {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// A substochastic averaging matrix like the period map's Jacobian: a product of tangent
    /// maps of random working sets of a chain.
    fn jacobian(n: usize, seed: u64) -> DMatrix<f64> {
        use crate::sweep::{tangent, Bound};
        let mut state = seed;
        let mut j = DMatrix::identity(n, n);
        let inv_k = vec![1.0; n];
        for _ in 0..40 {
            let ws: Vec<Bound> = (0..=n)
                .map(|_| {
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    match state >> 62 {
                        0 => Bound::Lower,
                        1 => Bound::Upper,
                        _ => Bound::Free,
                    }
                })
                .collect();
            for c in 0..n {
                let mut col: Vec<f64> = j.column(c).iter().copied().collect();
                tangent(&ws, &inv_k, &mut col);
                j.set_column(c, &DVector::from_vec(col));
            }
        }
        j
    }

    #[test]
    fn step_solves_the_newton_system() {
        for (n, seed) in [(7, 1u64), (40, 2), (120, 3)] {
            let j = jacobian(n, seed);
            let r: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
            let opts = NewtonOptions {
                max_products: 400,
                ..NewtonOptions::DEFAULT
            };
            let mut jac = |v: &mut [f64]| {
                let out = &j * DVector::from_column_slice(v);
                v.copy_from_slice(out.as_slice());
            };
            let (s, products, rel) = newton_step(&mut jac, &r, 1e-12, &opts);
            let a = DMatrix::identity(n, n) - &j;
            let exact = a.lu().solve(&DVector::from_column_slice(&r)).unwrap();
            let err = s
                .iter()
                .zip(exact.iter())
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let scale = exact.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
            assert!(rel <= 1e-12, "n = {n}: relative residual {rel}");
            assert!(
                err <= 1e-8 * scale,
                "n = {n}: error {err} ({products} products)"
            );
        }
    }

    #[test]
    fn preconditioner_inverts_alpha_laplacian_plus_identity_inverse() {
        let n = 9;
        let mut p = Diffusion::new(n);
        p.alpha = 2.5;
        let v: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 0.3).collect();
        let mut out = vec![0.0; n];
        p.apply(&v, &mut out);
        // out - v = (alpha L)^{-1} v, so alpha L (out - v) = v.
        let diff: Vec<f64> = out.iter().zip(&v).map(|(a, b)| a - b).collect();
        let mut back = vec![0.0; n];
        Diffusion::laplacian(&diff, &mut back);
        for (b, vi) in back.iter().zip(&v) {
            assert!((2.5 * b - vi).abs() < 1e-12);
        }
    }
}
