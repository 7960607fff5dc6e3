//! The report of a crawler's certificate: every condition with its residual, the multipliers
//! in the paper's form, the continuous group of Theorem 2.2, the verdict and its reason; `J` of
//! a process and the one-link structure (theory §9).

use super::crawler_general::AsGeneral;
use super::kkt::{normal, FaceId, Raw, Structure};
use super::process::{Process, ProcessKind};
use super::records::*;
use super::residuals::discrete_residuals;
use super::stages::sup;
use super::verdict::{
    check, discrete_group, misplaced_mass, norm2, normalisation, significant_multipliers, verdict,
};

pub(super) fn report(
    pr: &Process,
    st: &Structure,
    general: &AsGeneral,
    raw: Raw,
    scaled_by: String,
    opts: &CertifyOptions,
) -> NecessaryConditions {
    let (n, np) = (st.n, st.np);
    let tol = opts.tol;
    let times = pr.times();
    let discrete = matches!(pr.kind, ProcessKind::Discrete { .. });
    let sup_p = sup(&raw.p);
    let pscale = sup_p.max(1.0);
    let disc = discrete_residuals(pr, general, &raw, false);
    let mut conditions = discrete_group(&disc, tol * pscale, raw.lambda);

    // Continuous time (Theorem 2.2) with the paper's extension.
    let p_plus_omega: Vec<Vec<f64>> = raw
        .p
        .iter()
        .map(|p| (0..n).map(|l| p[l] + raw.omega[l]).collect())
        .collect();
    // The multipliers solve LPs to the conditions' tolerance: below it, |p + omega| is zero at
    // the solver's resolution (the margin LP's slack of 1e-12 showed as `p + omega = 1e-12`).
    let resolution = tol * pscale;
    let margin = p_plus_omega
        .iter()
        .flatten()
        .fold(f64::INFINITY, |m, v| m.min(v.abs()));
    let margin = if margin <= resolution { 0.0 } else { margin };
    // Relative to |p + omega|, or to the natural unit of p (|<p, K nu_b>| = lambda/N while block
    // b slips) when p + omega vanishes identically.
    let kmax = st.k.iter().fold(0.0_f64, |m, &k| m.max(k));
    let nd_tol = 1e-6 * sup(&p_plus_omega).max(1.0 / (st.nb as f64 * kmax));
    let residuals = ContinuousResiduals {
        adjoint: disc[0].2,
        sign: disc[5].2,
        support: misplaced_mass(&st.active, &raw.xi, discrete),
        l1: general.l1_maximality(&raw),
        nontrivial: raw.lambda + sup_p,
        nondegenerate: margin > nd_tol,
        law: general.control_law_residual(&pr.controls, raw.lambda, &p_plus_omega, nd_tol),
    };
    conditions.extend(residuals.checks(tol * pscale, pr.problem.period, tol));

    let (verdict, reason) = verdict(
        &conditions,
        discrete,
        raw.lambda,
        residuals.nondegenerate,
        "the necessary conditions hold with lambda = 1 and p + omega vanishes nowhere",
        || degenerate_reason(&p_plus_omega, margin, resolution, &times),
    );
    let psi: Vec<Vec<f64>> = (0..np)
        .map(|j| (0..n).map(|l| psi_at(st, &raw, &raw.p[j], j, l)).collect())
        .collect();
    let paper = paper_norm(pr, st, &raw, &psi);
    let multipliers = MultiplierData {
        extension: if discrete {
            "piecewise_linear"
        } else {
            "piecewise_constant"
        }
        .into(),
        xi: face_multipliers(st, &raw, &times),
        times,
        psi,
        p: raw.p.clone(),
        p_plus_omega,
        u: pr.controls.clone(),
        omega: raw.omega.clone(),
    };
    NecessaryConditions {
        format: CERTIFICATE_FORMAT.into(),
        version: CERTIFICATE_VERSION,
        method: if discrete { "discrete" } else { "phase" }.into(),
        m: match pr.kind {
            ProcessKind::Discrete { m } => Some(m),
            ProcessKind::Phase => None,
        },
        verdict,
        reason,
        lambda: raw.lambda,
        objective: process_objective(pr),
        nondegeneracy_margin: margin,
        nondegeneracy_resolution: resolution,
        normalisation: normalisation(scaled_by, raw.lambda, sup_p, paper),
        conditions,
        multipliers,
        one_link: one_link_structure(pr, opts.structure_tol),
        branch_lp: None,
    }
}

/// Why the conditions hold only degenerately: where `p + omega` is least (§4 (nndg)).
fn degenerate_reason(
    p_plus_omega: &[Vec<f64>],
    margin: f64,
    resolution: f64,
    times: &[f64],
) -> String {
    let (j, l) = argmin_abs(p_plus_omega);
    format!(
        "the conditions hold with lambda = 1 but only degenerately: p + omega = {} on piece {j} \
         (t = {:.6}), link {} (§4 (nndg) fails)",
        if margin == 0.0 {
            format!("0 at the solver's resolution {resolution:.1e}")
        } else {
            format!("{:.3e}", p_plus_omega[j][l])
        },
        times[j],
        l + 1
    )
}

/// `psi_l = -p_l - omega_l - lambda Df2(u_j)_l` at the adjoint value `p` on piece `j`.
fn psi_at(st: &Structure, raw: &Raw, p: &[f64], j: usize, l: usize) -> f64 {
    -p[l] - raw.omega[l] - raw.lambda * st.grad_f2[j][l]
}

/// The residuals of Theorem 2.2's continuous group, before they are checked.
struct ContinuousResiduals {
    adjoint: f64,
    sign: f64,
    support: f64,
    l1: f64,
    nontrivial: f64,
    nondegenerate: bool,
    law: f64,
}

impl ContinuousResiduals {
    /// The checks, in the report's order, at the tolerance `ptol` of p's scale (the L^1
    /// maximality over the period `t_total`, the control law at the conditions' `tol`).
    fn checks(&self, ptol: f64, t_total: f64, tol: f64) -> Vec<ConditionCheck> {
        [
            (
                "adjoint",
                "dp = sum_j x*_j dxi^j, p(T) = p(0) (Thm 2.2 adjoint, transversality)",
                self.adjoint,
                ptol,
            ),
            (
                "sign",
                "dxi^j >= 0 (Thm 2.2; Thm 6.1 for the paper's P_m, whose state constraints are \
                 pure inequalities: the branch LP of the computational P_m leaves it free on held \
                 faces)",
                self.sign,
                ptol,
            ),
            (
                "support",
                "supp dxi^j in {t : face j active at x(t)}: dxi mass on steps where the face is \
                 not active throughout (Thm 2.2 support)",
                self.support,
                ptol,
            ),
            (
                "weak_maximality",
                "int_0^T dist(psi(t), N_U(u(t))) dt, psi = -p - omega - lambda Df2(u) (Thm 2.2)",
                self.l1,
                ptol * t_total,
            ),
            (
                "nontriviality",
                "lambda + ||p||_inf > 0, scaled to 1 (Thm 2.2)",
                if self.nontrivial > 0.0 { 0.0 } else { 1.0 },
                0.0,
            ),
            (
                "nondegeneracy",
                "p_l(t) + omega_l != 0 for all t and l (§4 (nndg)): min |p + omega| above 1e-6 \
                 max(sup|p + omega|, 1/(N k_max)) and the solver's resolution; residual 1 when \
                 it is not (min |p + omega| is reported beside J)",
                if self.nondegenerate { 0.0 } else { 1.0 },
                0.0,
            ),
            (
                "control_law",
                "u = -a sign(p + omega) where p + omega != 0 (f2 = 0, §4), u = proj_U(-(p + \
                 omega)/(lambda c)) (f2 = (c/2)|u|^2): max |u - law| / a",
                self.law,
                tol.max(1e-9) * 10.0,
            ),
        ]
        .into_iter()
        .map(|(name, statement, residual, tolerance)| {
            check(name, "2.2", statement, residual, tolerance)
        })
        .collect()
    }
}

/// The paper's normalisation of the multipliers: `lambda + |p(0)| + |omega| + sum_j (|sum_b
/// xi_j^b K nu_b| + tau_j |psi_j|)`.
fn paper_norm(pr: &Process, st: &Structure, raw: &Raw, psi: &[Vec<f64>]) -> f64 {
    let n = st.n;
    let mut paper = raw.lambda + norm2(&raw.p[0]) + norm2(&raw.omega);
    for j in 0..st.np {
        let mut v = vec![0.0; n];
        for (fi, &f) in st.active[j].iter().enumerate() {
            for (l, c) in normal(n, f) {
                v[l] += raw.xi[j][fi] * c;
            }
        }
        paper += norm2(&v);
        paper += pr.durations[j] * norm2(&psi[j]);
    }
    paper
}

/// The face multipliers `dxi` per knot, block and side ([`significant_multipliers`]).
fn face_multipliers(st: &Structure, raw: &Raw, times: &[f64]) -> Vec<FaceMultiplier> {
    significant_multipliers(&st.active, &raw.xi, |j, FaceId { b, s }, value| {
        FaceMultiplier {
            knot: j,
            time: times[j],
            block: b + 1,
            side: if s > 0 { "+" } else { "-" }.into(),
            value,
        }
    })
}

/// `J` of a process: displacement per period minus `int f2(u) dt`.
pub fn process_objective(pr: &Process) -> f64 {
    let nb = pr.crawler.blocks() as f64;
    let displacement: f64 = pr.block_displacements.iter().flatten().sum::<f64>() / nb;
    let cost: f64 = pr
        .controls
        .iter()
        .zip(&pr.durations)
        .map(|(u, d)| d * pr.problem.cost.eval(u))
        .sum();
    displacement - cost
}

fn argmin_abs(rows: &[Vec<f64>]) -> (usize, usize) {
    let mut best = (0, 0, f64::INFINITY);
    for (j, r) in rows.iter().enumerate() {
        for (l, v) in r.iter().enumerate() {
            if v.abs() < best.2 {
                best = (j, l, v.abs());
            }
        }
    }
    (best.0, best.1)
}

/// §4's structure of a one-link process: switches of the control, where they happen, interior
/// arcs (`x` linear between knots). `None` for more than one link.
pub fn one_link_structure(pr: &Process, tol: f64) -> Option<OneLinkStructure> {
    if pr.crawler.links() != 1 {
        return None;
    }
    let r = pr.crawler.link_force_ranges()[0];
    let (alpha, beta) = (r[0], r[1]);
    let a = pr.problem.rate_bound[0];
    let etol = tol * (beta - alpha);
    let times = pr.times();
    let np = pr.durations.len();
    let x: Vec<f64> = pr.states.iter().map(|s| s[0]).collect();
    let at_end = |v: f64| v <= alpha + etol || v >= beta - etol;
    let sgn = |u: f64| {
        if u > tol * a {
            1
        } else if u < -tol * a {
            -1
        } else {
            0
        }
    };
    let mut switch_times = Vec::new();
    let mut switch_at_end = Vec::new();
    for j in 0..np {
        let prev = (j + np - 1) % np;
        let (s0, s1) = (sgn(pr.controls[prev][0]), sgn(pr.controls[j][0]));
        if s0 != s1 {
            switch_times.push(times[j]);
            switch_at_end.push(at_end(x[j]));
        }
    }
    // Interior arcs, x linear between knots, walking from a knot at an end of C.
    let mut arcs: Vec<f64> = Vec::new();
    match (0..np).find(|&j| at_end(x[j])) {
        None => arcs.push(pr.problem.period),
        Some(s0) => {
            let mut cur = 0.0;
            for step in 0..np {
                let j = (s0 + step) % np;
                let (x0, x1, tau) = (x[j], x[j + 1], pr.durations[j]);
                match (at_end(x0), at_end(x1)) {
                    (true, true) if (x1 - x0).abs() <= etol => {}
                    (true, true) => arcs.push(tau),
                    (_, false) => cur += tau,
                    (false, true) => {
                        arcs.push(cur + tau);
                        cur = 0.0;
                    }
                }
            }
        }
    }
    Some(OneLinkStructure {
        alpha,
        beta,
        switch_times,
        switch_at_end,
        interior_arcs: arcs,
        expected_arc: (beta - alpha) / a,
        bang_bang: pr
            .controls
            .iter()
            .all(|u| (u[0].abs() - a).abs() <= tol * a),
    })
}
