//! The necessary conditions of Theorem 2.2 (discrete form Theorems 6.1–6.2) for an optimum of
//! the general problem's P_m or an exact phase gait (theory §11): `x' in -N_C(x) + A x + B u + b`, `u in U` (a box or a
//! polytope `{G u <= h}`) with zero mean, `f1` linear in the reaction, `f2(u) = (1/2) u^T R u`.
//! The crawler's certificate ([`crate::certify`], whose module docs explain the method, the
//! stages and the verdict) is the instance `A = 0, B = K^(-1/2)` after the change of variables
//! `x = K^(1/2) x~`; both share the types ([`super::ConditionCheck`], [`super::Verdict`],
//! [`super::Normalisation`], [`super::BranchLp`], [`CertifyOptions`], the one record
//! [`super::NecessaryConditions`]), the staged search for multipliers (`certify::stages`) and
//! the branch LPs (`certify::branch`, solved for P_m processes and phase gaits alike); this
//! module states the conditions for the general data (its multiplier LP in
//! `certify::general_kkt`, its report in `certify::general_report`) and holds the one driver
//! (`certify_structured`). That driver is the only one: the crawler's certificate runs it on the
//! crawler's process on its instance, with the structure found there counted in the crawler's
//! units, and reads the multipliers back
//! (`certify::crawler_general`, the change of variables below).
//!
//! # The branch LP and its KKT system
//!
//! P_m's step (explicit in `g`, implicit projection) is, with `mu^i = h lambda^i` the
//! projection's multipliers,
//!
//! ```text
//! maximise   sum_i [ sum_f w_f mu^i_f - h f2(u^i) ]                (w_f: face weights of f1)
//! subject to x^(i+1) - (I + h A) x^i - h B u^i + sum_f mu^i_f x*_f = h b   (dual q_i = -p_i)
//!            <x*_f, x^(i+1)> <= c_f, held as "=" where mu^i_f > 0          (dual -xi_{i+1,f})
//!            u^i in U,  sum_i u^i = 0                                       (h psi_i, h omega)
//!            mu^i_f >= 0 on held faces and biactive ones, = 0 elsewhere
//! ```
//!
//! (`w_f = <q, x*_f>` for `f1 = <q, eta>`). A face is *held* at knot `k` when the step ending
//! there has a reaction on it; an active face without one is *biactive* and the branch is relaxed
//! to both inequalities (strong stationarity), as for crawlers. Stationarity of its Lagrangian in
//! `x^k`, `mu^i`, `u^i` at the given process, with the objective multiplier `lambda`, gives in
//! Theorem 2.2's signs (`p = -q`, `xi = -(face dual)`, knots and steps cyclic):
//!
//! - **adjoint + transversality** (Thm 6.2 (px), (p2mx); Thm 2.2 `dp = -A^T p dt + sum_j
//!   x*_j dxi^j`): `p_k - p_(k-1) = -h A^T p_k + sum_{f active at x^k} xi_{k,f} x*_f`,
//!   `k = 0..M-1` with `p_(-1) = p_(M-1)`, so `p(T) = p(0)`. The explicit Euler step in `x` makes
//!   the adjoint implicit: `p_(k-1) = (I + h A^T) p_k - sum xi x*`, and `p_k` (the adjoint on
//!   step `k`, `[t_k, t_(k+1)]`) carries the drift term;
//! - **complementarity / support** (Thm 6.1 (necd1)): `xi_{k,f} (c_f - <x*_f, x^k>) = 0`;
//! - **reaction stationarity** (the branch LP in `mu`; Thm 6.2 (pr), `eta in ∂f1`):
//!   `lambda w_f + <p_i, x*_f> = 0` for every face with a reaction on step `i`, `<= 0` at a
//!   biactive face; for the crawler this is its slip stationarity `<p, K nu_b> + lambda/N = 0`;
//! - **branch-LP face sign**: `xi_{k,f} <= 0` on a biactive face;
//! - **weak maximality** (Thm 6.2 (pw); Thm 2.2): `psi_i = -B^T p_i - omega - lambda R u^i in
//!   N_U(u^i)`, i.e. `psi_i = sum_r rho_{i,r} G_r` with `rho >= 0` on the rows of U active at
//!   `u^i` (a box: the rows `+-e_l`); `omega = 0` without the zero-mean constraint;
//! - **sign** (Thm 6.1, Thm 2.2, reported separately as for crawlers): `xi_{k,f} >= 0`.
//!
//! With them, in the group "2.2" as for crawlers (not part of a P_m verdict): support of `dxi`
//! with `p` extended piecewise linearly (§9), nontriviality, non-degeneracy, the control law
//! weak maximality implies (a box U, `f2 = 0` or `(c/2)|u|^2`) and, for a box U, weak maximality
//! in `L^1(0, T)` on that extension (`O(h)` on P_m grids, as for crawlers).
//!
//! The multipliers are found by the shared staged search (least violation `r` of the first
//! five, then least violation of the sign, then the largest margin `delta`: every `rho_{i,r} >=
//! delta` on the active rows of U where `u^i` is a vertex of U, and on a box's bound the
//! switching function `-sign(u_l) sigma_{i,l} >= delta`, the margin its verdict reads), or with
//! `lambda = 0` by the same generic functional;
//! every residual is then recomputed in floating point. Only periodic problems are certified.
//!
//! # Phase gaits
//!
//! An exact phase gait (`A = 0`, [`crate::optimal::general::phase`]) is certified on its own
//! phases: piece `i` lasts `tau_i` (in place of `h`), `U_i = tau_i u^i`, and the phase LP is
//!
//! ```text
//! maximise   sum_i [ sum_f w_f L_{i,f} - tau_i f2(U_i / tau_i) ]
//! subject to x^(i+1) - x^i - B U_i - b tau_i + sum_f L_{i,f} x*_f = 0       (dual q_i = -p_i)
//!            <x*_f, x^i> <= c_f, held as "=" at both ends of a phase with L_{i,f} > 0
//!            G U_i <= h tau_i (rho_i),  sum_i U_i = 0 (omega),  sum_i tau_i = T (H)
//! ```
//!
//! With the durations fixed its KKT system is the one above with `tau_i` for `h` and no drift
//! term; a face may react on phase `i` only if active at both of its ends (the segment lies on
//! it), so a face is *held* at a knot when the phase ending or the phase starting there reacts
//! on it, and a face active at both ends of a phase without a reaction is biactive. The
//! durations are variables too: stationarity in `tau_i` reads
//! `H_i = sum_r rho_{i,r} h_r - <p_i, b> + lambda (Df2(u^i).u^i - f2(u^i)) = H` on every phase
//! (the maximised Hamiltonian is constant; for a box `|u_l| <= a_l` the first term is the
//! crawler's `sum_l a_l |psi_{i,l}|`). As for crawlers it is checked with multipliers of its
//! own (`duration_stationarity`, group "6.2"; a violation makes the verdict `fails`), since
//! imposing it on the reported ones can conflict with `dxi >= 0`. `p` is constant on a phase,
//! so the support condition is void and the `L^1` maximality is exact. A phase at most
//! [`EMPTY_PHASE`] `T` long (a MILP's
//! rounding) is dropped first: its duration is 0 for the phase LP, at the bound `tau >= 0`, where
//! its control is not asked to maximise anything (`U = 0`) nor its Hamiltonian to equal the
//! others'.
//!
//! # Changes of variables
//!
//! For a crawler ([`crate::model::crawler_as_general`]: `x~ = K^(-1/2) x`, unit normals
//! `x~*_(b+-) = +-K^(1/2) nu_b / s_b`, `s_b = |K^(1/2) nu_b|`, `B = K^(-1/2)`), the Lagrangian
//! term `<q, dynamics>` is invariant, so the multipliers correspond as `p~ = K^(1/2) p` (then
//! `B^T p~ = p`: `omega` and `psi` are unchanged) and `xi~_(b+-) = s_b xi_(b+-)` (the crawler's
//! `xi` is in the units of the unnormalised `+-nu_b`).
//!
//! # Verdict and non-degeneracy
//!
//! As for crawlers: `holds` when the discrete conditions hold with `lambda = 1` (for a phase
//! gait, an exact process of (P), also Theorem 2.2's own: the sign `dxi >= 0`, the support, the
//! `L^1` maximality, the adjoint and nontriviality) and the switching function
//! `sigma_i = B^T p_i + omega` leaves the control unique; `degenerate` when
//! they hold only with `sigma` vanishing or only with `lambda = 0`; `fails` otherwise. The
//! margin is, for a box U, `min_{i,l} |sigma_{i,l}|` (the crawler's `min |p + omega|`), for a
//! polytope the least `rho` over the steps at vertices of U (0 if a step is not at a vertex).
//! For a strictly convex `f2` (`R` positive definite) the maximiser of the Hamiltonian is unique
//! whatever `sigma`, so the margin is reported but not required (a crawler's certificate is this
//! report on its instance: the same rule).

use super::general_conditions::residuals;
pub use super::general_conditions::{
    residuals_of, GeneralFaceMultiplier, GeneralMultipliers, GeneralNecessaryConditions,
    GENERAL_CERTIFICATE_FORMAT,
};
use super::general_kkt::{solve_general, GeneralRaw, GeneralStructure, Stage};
pub use super::general_process::{GeneralProcess, EMPTY_PHASE};
use super::general_report::{report, Words};
use super::stages::{scaled_sup, search};
use super::CertifyOptions;
use crate::error::Result;
use crate::model::general::{GeneralCost, GeneralProblem};

/// Computes multipliers of a general P_m process and checks the necessary conditions.
pub fn certify_general(
    p: &GeneralProblem,
    pr: &GeneralProcess,
    opts: &CertifyOptions,
) -> Result<GeneralNecessaryConditions> {
    certify_with(p, pr, opts, true)
}

/// [`certify_general`], with the adjoint's drift term `-h A^T p` dropped when `drift_term` is
/// false (tests: the term matters).
pub(crate) fn certify_with(
    p: &GeneralProblem,
    pr: &GeneralProcess,
    opts: &CertifyOptions,
    drift_term: bool,
) -> Result<GeneralNecessaryConditions> {
    let pr = &pr.without_empty_phases(p.period);
    pr.check(p, opts.structure_tol)?;
    let st = GeneralStructure::of(p, pr, opts.structure_tol);
    let words = &super::general_report::GENERAL_WORDS;
    Ok(certify_structured(p, pr, &st, words, opts, drift_term)?.0)
}

/// The one certificate driver: the multipliers of `pr` with the structure `st` (its active,
/// held and biactive faces, its rates at their bounds, and the units the violations are
/// counted in: (P)'s own from [`GeneralStructure::of`], or an instance's, such as a
/// crawler's), its report in `words`, the duration condition of a phase gait and the branch
/// LPs through it. Returns the report and the multipliers it states (for an instance to read
/// back in its own names).
pub(super) fn certify_structured(
    p: &GeneralProblem,
    pr: &GeneralProcess,
    st: &GeneralStructure,
    words: &Words,
    opts: &CertifyOptions,
    drift_term: bool,
) -> Result<(GeneralNecessaryConditions, GeneralRaw)> {
    let chosen = search(
        |lambda, stage, norm| solve_general(p, st, lambda, stage, norm, drift_term, false),
        |raw| kkt_residual(p, st, raw, drift_term, false),
        st,
        opts.tol,
        st.phase,
    )?;
    let mut rep = report(p, pr, st, &chosen.0, chosen.1, opts, drift_term, words);
    if st.phase {
        // The phase LP is stationary in the durations too, with multipliers of their own
        // (imposing it on the reported ones could conflict with dxi >= 0: the three-block
        // crawler's phase optimum): with lambda = 1 where the conditions hold with it, else by
        // the same search (lambda = 0).
        let raw = if chosen.0.lambda > 0.0 {
            solve_general(p, st, 1.0, Stage::Kkt, None, drift_term, true)?.ok_or_else(|| {
                crate::Error::Numerical("certify: HiGHS found the multiplier LP infeasible".into())
            })?
        } else {
            search(
                |lambda, stage, norm| solve_general(p, st, lambda, stage, norm, drift_term, true),
                |raw| kkt_residual(p, st, raw, drift_term, true),
                st,
                opts.tol,
                true,
            )?
            .0
        };
        let r = kkt_residual(p, st, &raw, drift_term, true)
            / scaled_sup(&raw.p, &st.state_scale).max(1.0);
        rep.add_duration_condition(words.hamiltonian, r, opts.tol);
        if p.cost != GeneralCost::None {
            rep.note_approximate_cost();
        }
    }
    // The branch LPs through the process (f2 = 0 only: none otherwise): its own and, within
    // the budget, every choice of its biactive pairs reacting or not; on a P_m process a
    // failure that they do not show suboptimal says so (a phase gait's fix its durations).
    let biactive = st.reacting.iter().flatten().filter(|(_, r)| !r).count();
    let columns = super::branch::columns(st);
    let lps = super::branch::BranchLps::new(p, st);
    let branch = super::records::best_branch(biactive, columns, pr.objective(p), |choice| {
        Ok(lps.optimum(choice))
    })?;
    rep.set_branch_lp(branch, !st.phase, opts.tol);
    Ok((rep, chosen.0))
}

/// The largest residual of the branch LP's KKT system (all discrete conditions but the sign;
/// with `durations_free`, the stationarity in the durations too), which the search and the
/// report divide by `max(1, ||p||)`. The Hamiltonian's spread is counted in units of `speed`
/// (the Hamiltonian at `|p|` of `p`'s unit, [`super::general_kkt::ResidualUnits`]) and relative
/// to `max(p_unit, ||p||) / p_unit`, so that after that division it is
/// `(max H - min H) / 2 / (speed max(p_unit, ||p||) / p_unit)`, the same for a crawler in any
/// units; for (P), `p_unit = 1` and the factor is 1.
fn kkt_residual(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    drift: bool,
    durations_free: bool,
) -> f64 {
    let sup = scaled_sup(&raw.p, &st.state_scale);
    let unit = st.units.p;
    residuals(p, st, raw, drift, durations_free)
        .iter()
        .filter(|(name, _, _)| *name != "sign")
        .map(|&(name, _, r)| {
            if name == "duration_stationarity" {
                r * unit * sup.max(1.0) / sup.max(unit)
            } else {
                r
            }
        })
        .fold(0.0_f64, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certify::Verdict;
    use crate::model::general::GeneralParts;

    /// The drift problem of tests/general_certify.rs (c) at its hand-derived P_1 optimum: the
    /// certificate holds, and without the adjoint's `-h A^T p` term it fails (`p_1 = p_0 = -1`
    /// then asks `omega in [1 + c, 1 - c]`): the least violation of the KKT system is `c`, in the
    /// weak maximality.
    #[test]
    fn the_drift_term_of_the_adjoint_matters() {
        let c = 0.05;
        let p = GeneralProblem::new(GeneralParts {
            normals: vec![
                vec![1.0, 0.0],
                vec![0.0, 1.0],
                vec![-1.0, 0.0],
                vec![0.0, -1.0],
            ],
            offsets: vec![1.0, 1.0, 2.0, 2.0],
            a: Some(vec![vec![-0.25, 0.0], vec![0.0, -0.2]]),
            b: vec![vec![1.0, 0.0], vec![0.0, 1.0]],
            lower: Some(vec![-1.0, -1.0]),
            upper: Some(vec![1.0, 1.0]),
            zero_mean: true,
            face_weights: Some(vec![1.0, 1.0, 0.0, 0.0]),
            cost: Some(GeneralCost::Quadratic { weight: c }),
            period: 4.0,
            periodic: true,
            ..Default::default()
        })
        .unwrap();
        let u = [vec![1.0, 1.0], vec![-1.0, -1.0]];
        let pr = GeneralProcess::from_controls(&p, 1, &u, &[0.0, 0.0]).unwrap();
        let opts = CertifyOptions::default();
        let with = certify_with(&p, &pr, &opts, true).unwrap();
        assert_eq!(with.verdict, Verdict::Holds, "{}", with.reason);
        let without = certify_with(&p, &pr, &opts, false).unwrap();
        assert_eq!(without.verdict, Verdict::Fails, "{}", without.reason);
        let maxim = without
            .conditions
            .iter()
            .find(|k| k.name == "weak_maximality")
            .unwrap();
        assert!((maxim.residual - c).abs() < 1e-9, "{}", maxim.residual);
    }
}
