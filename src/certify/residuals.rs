//! The discrete residuals of a crawler's necessary conditions (Theorems 6.1–6.2), recomputed
//! in floating point from the multipliers, and the integrals the continuous group needs.

use super::kkt;
use super::kkt::{normal, Raw, Structure};
use super::process::{Process, ProcessKind};
use super::stages::sign_residual;

/// The discrete residuals, each as (name, statement, residual).
pub(super) fn discrete_residuals(
    pr: &Process,
    st: &Structure,
    raw: &Raw,
    durations_free: bool,
) -> Vec<(&'static str, String, f64)> {
    let (adj, comp, lp_sign) = adjoint_terms(st, raw);
    let (slip_res, bi, maxim) = stationarity_terms(st, raw);
    let (ham_lo, ham_hi) = hamiltonian_range(st, raw);
    let mut out = vec![
        (
            "adjoint",
            "adjoint equation and transversality: p_j - p_{j-1} = sum_f xi_{j,f} x*_f, p(T) = \
             p(0) (Thm 6.2 (px), (p2mx))"
                .into(),
            adj,
        ),
        (
            "complementarity",
            "xi_{j,f} (c_f - <x*_f, x_j>) = 0: dxi only where its face is active (Thm 6.1 (necd1))"
                .into(),
            comp,
        ),
        (
            "slip_stationarity",
            "<p_j, K nu_b> + lambda/N = 0 while block b slips; relaxed sign at biactive faces \
             (branch LP in D; Thm 6.2 (pr), eta in df1)"
                .into(),
            slip_res.max(bi.max(0.0)),
        ),
        (
            "branch_face_sign",
            "xi_{j,f} <= 0 on an active face no slip holds (a true inequality of the branch LP)"
                .into(),
            lp_sign.max(0.0),
        ),
        (
            "weak_maximality",
            "psi_j = -p_j - omega - lambda Df2(u_j) in N_U(u_j) (Thm 6.2 (pw))".into(),
            maxim,
        ),
        ("sign", "xi_{j,f} >= 0".into(), sign_residual(raw).max(0.0)),
    ];
    if durations_free && pr.kind == ProcessKind::Phase {
        out.push((
            "duration_stationarity",
            "H_j = sum_l a_l |psi_{j,l}| + lambda (Df2(u_j).u_j - f2(u_j)) is the same on every \
             phase (phase LP stationary in the durations: the maximised Hamiltonian is constant); \
             residual (max H - min H)/2"
                .into(),
            0.5 * (ham_hi - ham_lo),
        ));
    }
    out
}

/// The residuals at the knots (Theorem 6.2 (px), (p2mx); Theorem 6.1 (necd1)): the adjoint
/// equation's jump `p_j - p_{j-1} - sum_f xi_{j,f} x*_f`, the complementarity `|xi| slack` and
/// the largest `xi` on a face no slip holds, each the largest over the knots.
fn adjoint_terms(st: &Structure, raw: &Raw) -> (f64, f64, f64) {
    let (n, np) = (st.n, st.np);
    let mut adj = 0.0_f64;
    let mut comp = 0.0_f64;
    let mut lp_sign = 0.0_f64;
    for j in 0..np {
        let prev = (j + np - 1) % np;
        let mut jump: Vec<f64> = (0..n).map(|l| raw.p[j][l] - raw.p[prev][l]).collect();
        for (fi, &f) in st.active[j].iter().enumerate() {
            let x = raw.xi[j][fi];
            for (l, v) in normal(n, f) {
                jump[l] -= x * v;
            }
            comp = comp.max(x.abs() * st.slack[j][fi]);
            if !st.held[j][fi] {
                lp_sign = lp_sign.max(x);
            }
        }
        adj = jump.iter().fold(adj, |m, v| m.max(v.abs()));
    }
    (adj, comp, lp_sign)
}

/// The residuals on the pieces (Theorem 6.2 (pr), (pw)): slip stationarity `|<p_j, K nu_b> +
/// lambda/N|` of the slipping blocks, the relaxed sign at the biactive pairs (not yet clipped at
/// 0), and the distance of `psi_j` from the normal cone of the box.
fn stationarity_terms(st: &Structure, raw: &Raw) -> (f64, f64, f64) {
    let (n, np) = (st.n, st.np);
    let lam_n = raw.lambda / st.nb as f64;
    let mut slip_res = 0.0_f64;
    let mut bi = 0.0_f64;
    let mut maxim = 0.0_f64;
    for j in 0..np {
        for b in 0..st.nb {
            let dot: f64 = kkt::k_nu(n, &st.k, b)
                .iter()
                .map(|&(l, v)| raw.p[j][l] * v)
                .sum();
            if st.slips[j][b] != 0 {
                slip_res = slip_res.max((dot + lam_n).abs());
            }
            for &(bb, dir) in &st.biactive[j] {
                if bb == b {
                    let g = -dot - lam_n;
                    bi = bi.max(if dir > 0 { -g } else { g });
                }
            }
        }
        for l in 0..n {
            let psi = -raw.p[j][l] - raw.omega[l] - raw.lambda * st.grad_f2[j][l];
            maxim = maxim.max(dist_normal(psi, st.bound[j][l]));
        }
    }
    (slip_res, bi, maxim)
}

/// The smallest and largest maximised Hamiltonian `H_j = sum_l a_l |psi_{j,l}| + lambda
/// cost_h_j` over the pieces (phase gaits: it is the same on every phase).
fn hamiltonian_range(st: &Structure, raw: &Raw) -> (f64, f64) {
    let (n, np) = (st.n, st.np);
    // Phase gaits: the maximised Hamiltonian is the same on every phase.
    let mut ham_lo = f64::INFINITY;
    let mut ham_hi = f64::NEG_INFINITY;
    for j in 0..np {
        let h: f64 = (0..n)
            .map(|l| {
                let psi = -raw.p[j][l] - raw.omega[l] - raw.lambda * st.grad_f2[j][l];
                st.a[l] * psi.abs()
            })
            .sum::<f64>()
            + raw.lambda * st.cost_h[j];
        ham_lo = ham_lo.min(h);
        ham_hi = ham_hi.max(h);
    }
    (ham_lo, ham_hi)
}

/// Largest residual of the branch-LP KKT system (all discrete conditions but the sign).
pub(super) fn kkt_residual(pr: &Process, st: &Structure, raw: &Raw) -> f64 {
    kkt_residual_with(pr, st, raw, false)
}

/// The same, with the stationarity in the durations of a phase gait when `durations_free`.
pub(super) fn kkt_residual_with(
    pr: &Process,
    st: &Structure,
    raw: &Raw,
    durations_free: bool,
) -> f64 {
    discrete_residuals(pr, st, raw, durations_free)
        .iter()
        .filter(|(name, _, _)| *name != "sign")
        .fold(0.0_f64, |m, (_, _, r)| m.max(*r))
}

/// Distance of `psi` from the normal cone of `[-a, a]` at a point at the upper bound (`1`),
/// the lower bound (`-1`) or inside (`0`).
fn dist_normal(psi: f64, bound: i8) -> f64 {
    match bound {
        1 => (-psi).max(0.0),
        -1 => psi.max(0.0),
        _ => psi.abs(),
    }
}

/// `int_0^tau max(0, linear from a to b) ds`.
pub(crate) fn int_pos(a: f64, b: f64, tau: f64) -> f64 {
    if a >= 0.0 && b >= 0.0 {
        0.5 * tau * (a + b)
    } else if a <= 0.0 && b <= 0.0 {
        0.0
    } else {
        let hi = a.max(b);
        0.5 * tau * hi * hi / (b - a).abs()
    }
}
