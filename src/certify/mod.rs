//! Necessary optimality conditions made checkable: multipliers of a gait and a certificate of
//! the maximum principle (paper Theorem 2.2; its discrete form Theorems 6.1–6.2 — numbered 8.1–8.2
//! in the compiled paper, whose §9 passes to the limit; theory §8).
//!
//! # What is certified
//!
//! A periodic process on knots `0 = t_0 < ... < t_P = T` ([`Process`]): a P_m process (theory §6,
//! `2^m` catching-up steps) or a phase gait (theory §7, exact). Fixing its complementarity branches
//! (which blocks slip, which way; which faces of C are active at each knot) turns the gait problem
//! into a linear program, the *branch LP* in `(x_j, U_j = tau_j u_j, D_{j,b})` with the durations
//! fixed:
//!
//! ```text
//! maximise   sum_{j,b} D_{j,b} / N - sum_j tau_j f2(U_j / tau_j)
//! subject to x_{j+1} - x_j - U_j + K sum_b D_{j,b} nu_b = 0     (dual  q_j = -p_j)
//!            <x*_f, x_j> <= c_f, held as "=" where a block slips   (dual  -xi_{j,f})
//!            |U_{j,l}| <= a_l tau_j,  sum_j U_j = 0                 (duals psi_j, omega)
//!            D_{j,b} >= 0 (slip+), <= 0 (slip-), = 0 (stick)
//! ```
//!
//! with outer normals `x*_f = ±nu_b`, `nu_b = e_{b-1} - e_b` (unnormalised: `xi` is in the units
//! of `nu_b`, not of the paper's unit normals). A face is *held* (an equality) at knot `j` when a
//! block slips against it on the piece ending there (P_m: implicit Euler puts the face at the
//! step's end) or, for a phase, on the piece starting there. At a *biactive* pair (block sticks
//! but its face is active where it would need it) the branch is relaxed to both inequalities,
//! i.e. strong stationarity of the complementarity problem.
//!
//! Its Lagrange (KKT) system at the given process, with the objective multiplier `lambda`, is
//! — in the sign convention of Theorem 2.2, `p = -q`, `xi = -(face dual)` —
//!
//! - **adjoint + transversality** (Thm 6.2 (px), (p2mx); Thm 2.2): `p_j - p_{j-1} =
//!   sum_{f active at x_j} xi_{j,f} x*_f`, indices cyclic, so `p(T) = p(0)`;
//! - **complementarity / support** (Thm 6.1 (necd1); Thm 2.2 support): `xi_{j,f} (c_f -
//!   <x*_f, x_j>) = 0` — the jump of `p` at `t_j` is carried by faces active at `x(t_j)`;
//! - **slip stationarity** (the branch LP's condition in `D`, the discrete counterpart of
//!   Thm 6.2 (pr), `eta in ∂f1`): `<p_j, K nu_b> + lambda/N = 0` for every block slipping on piece
//!   `j`; at a biactive pair `-<p_j, K nu_b> - lambda/N >= 0` (forward face), `<= 0` (backward);
//! - **branch-LP face sign**: `xi_{j,f} <= 0` on a face held by no slip (a true inequality);
//! - **weak maximality** (Thm 6.2 (pw); Thm 2.2): `psi_j = -p_j - omega - lambda Df2(u_j) in
//!   N_U(u_j)`, `U = prod [-a_l, a_l]`;
//! - **sign** (Thm 6.1: `xi in R^sigma_+`; Thm 2.2: `dxi^j >= 0`): `xi_{j,f} >= 0`.
//!
//! The first five are exactly the optimality conditions of the branch LP (LP duality: they hold
//! with `lambda = 1` iff the process is optimal among the processes on its branches, so for a
//! global optimum of P_m they must hold); they form the group "6.2" of the report. The sign is
//! reported with Theorem 2.2 (group "2.2"): Theorem 6.1 states it for the paper's own P_m, whose
//! reactions are frozen to those of the optimal process so that its state constraints are pure
//! inequalities, whereas the branch LP of the computational P_m (theory §6) leaves the multiplier of
//! a held face free. It is a genuine extra check, and it can fail on an optimum of P_m: the
//! three-block P_3 optimum needs `xi = -1/2` somewhere (P_2: `-1`; P_4: satisfied), while the
//! exact three-block phase optimum satisfies it with the durations fixed (tests/certify.rs).
//!
//! Signs: the paper prints `+p` in Thm 6.2 (pw) and in the proof's (pw2) but `-p` in Theorem 2.2
//! and §4. With `xi >= 0` only the latter admits the bang-bang one-link optimum (the adjoint rises
//! at the top face, where the control must turn from `+a` to `-a`), so both groups here use
//! Theorem 2.2's convention.
//!
//! # How the multipliers are computed
//!
//! The multiplier set is a polyhedron; rather than a vertex of it (the dual solution the branch
//! LP's solver happens to return, often degenerate: e.g. `omega` at an end of its interval, so
//! that `p + omega` vanishes on half the period), three small LPs in `(p, xi, omega)` are solved
//! with HiGHS:
//! 1. with `lambda = 1`, minimise the largest violation `r` of the branch LP's KKT system (all
//!    conditions above but the sign; the adjoint equation is imposed exactly, `xi` exists only on
//!    active faces). `r = 0` iff the process is optimal for its branch LP; `r > 0` measures how far
//!    it is from being so (a suboptimal gait has `r > 0`);
//! 2. keeping `r`, minimise the largest violation `s` of `xi >= 0`;
//! 3. keeping `r` and `s`, maximise the non-degeneracy margin `delta`: `-(p_l + omega_l) sign(u_l)
//!    >= delta` wherever `u_l` is at a bound.
//!
//! If stage 1 leaves `r` above tolerance, the degenerate case `lambda = 0` is tried: the
//! conditions are then homogeneous, and a generic linear functional of `(p, omega)` and its
//! opposite are maximised over them in the box `|p|, |omega| <= 1`; a non-zero maximiser, scaled
//! to `max(|p|, |omega|) = 1`, is a degenerate multiplier.
//! Every residual is then recomputed in plain floating point from the multipliers found, not taken
//! from the LP. The branch LP itself is solved too (`f2 = 0`): its optimum minus `J` is reported
//! (`branch_lp.improvement`, positive for a gait beaten on its own branches), and a unit test
//! checks that HiGHS's duals of it, mapped as above, satisfy this KKT system.
//!
//! # Normalisation
//!
//! All conditions are positively homogeneous of degree one (paper §9, before (norm)). When
//! `lambda > 0` is possible the multipliers are reported scaled to **`lambda = 1`** (Thm 6.2
//! (lambda) `lambda_m > 0` makes this the paper's own choice for P_m). The two normalisations of
//! the paper are reported as numbers: `lambda + ||p||_inf` (Thm 2.2 nontriviality: dividing by it
//! gives `lambda + ||p||_inf = 1`) and the sum of (norm), `lambda + |p(T)| + sum_j |sum_f xi x*| +
//! |omega| + int |psi|` (with `omega` and `psi` per unit time, i.e. the paper's `omega_m / h_m` and
//! `psi_m^i / h_m`).
//!
//! # Continuous-time conditions (Theorem 2.2)
//!
//! As in the paper's §9, `p_m` is extended piecewise linearly on a P_m grid (ramping from `p_j` to
//! `p_{j+1}` over step `j`, so the jump at `t_{j+1}` becomes the density `xi_{j+1} / h` on step
//! `j`); on a phase gait `p` is piecewise constant with jumps at the knots. Then:
//! - weak maximality is measured in `L^1(0, T)`: `int dist(psi(t), N_U(u(t))) dt`, computed
//!   exactly (`psi` is linear on each piece). On P_m it is `O(h)`: the ramp crosses
//!   `p + omega = 0` inside the switching steps;
//! - support: the `xi` mass whose density lies on a step where its face is not active throughout
//!   (P_m: face inactive at the step's start); zero for phase gaits by construction;
//! - nontriviality `lambda + ||p||_inf > 0`; non-degeneracy (§4, (nndg)): `min |p_l + omega_l|`
//!   over the pieces, componentwise (what `u_l = -a_l sign(p_l + omega_l)` needs);
//! - the control law the maximality implies: `u_l = proj_[-a_l, a_l](-(p_l + omega_l) /
//!   (lambda c))` for `f2 = (c/2)|u|^2`, and `u_l = -a_l sign(p_l + omega_l)` where `p_l + omega_l
//!   != 0` for `f2 = 0` (§4's bang-bang).
//!
//! With `f2 = 0` the conditions of Theorem 2.2 alone are satisfied by *every* process through
//! `lambda = 1, p = 0, xi = 0, omega = 0, psi = 0` (the objective has cancelled from the
//! Hamiltonian, paper §4.2 remark 1), and by `lambda = 0, p = -omega` (§4): they carry information
//! only with non-degeneracy. The discrete slip stationarity is what ties `p` to the displacement:
//! it fixes `<p, K nu_b> = -lambda/N` while block `b` slips, so `p != 0` as soon as the crawler
//! moves.
//!
//! # Verdict
//!
//! - `holds`: the discrete conditions (group "6.2") hold with `lambda = 1` — for phase gaits the
//!   continuous ones (group "2.2", then exact) too — and `p + omega` vanishes nowhere;
//! - `degenerate`: they hold but only with `p + omega` vanishing on some piece (e.g. an interior
//!   control with `f2 = 0`), or only with `lambda = 0`;
//! - `fails`: no multipliers satisfy them; the reason lists the violated conditions with their
//!   residuals at the least violating multipliers (a min-max solution spreads the violation over
//!   several conditions, so all of them are named).
//!
//! For P_m the continuous group is reported with the same tolerance and is expected to fail at
//! `O(h)`: it is the rate at which the discrete multipliers approach Theorem 2.2's.
//! For phase gaits the durations are variables of the phase LP (theory §7) too; its stationarity in
//! `tau_k` (with `|U| <= a tau`, `sum tau = T`) reads `H_k = sum_l a_l |psi_{k,l}| + lambda
//! (Df2(u_k).u_k - f2(u_k))` equal on every phase: the maximised Hamiltonian is constant, as for
//! an autonomous problem. It is checked (condition `duration_stationarity`, group "6.2") with
//! multipliers of its own, found by the stage-1 LP with these rows added: imposed on the reported
//! multipliers it can conflict with `dxi >= 0` (the three-block phase optimum: `xi = -1/6`
//! somewhere), and Theorem 2.2 does not state it. (Checked with `lambda = 1` only.) The
//! block-speed bound `|D| <= V tau` of the phase MILP is taken as inactive.

pub mod bound;
pub mod general;
mod general_conditions;
mod general_kkt;
mod general_process;
mod general_report;
mod kkt;
mod process;
mod stages;

pub use general::{certify_general, residuals_of, GeneralNecessaryConditions, GeneralProcess};
pub use process::{Process, ProcessKind, INPUT_TOL};

use crate::error::Result;
use crate::optimal::{Cost, GaitResult};
use kkt::{normal, FaceId, Raw, Stage, Structure};
use serde::{Deserialize, Serialize};
use stages::{sign_residual, sup};

/// Value of [`NecessaryConditions::format`].
pub const CERTIFICATE_FORMAT: &str = "crawlopt-necessary-conditions";
/// Version of the certificate format.
pub const CERTIFICATE_VERSION: u32 = 1;

/// Options of [`certify`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CertifyOptions {
    /// Relative tolerance of every residual (pointwise residuals relative to
    /// `max(1, ||p||_inf)`, integrals also to `T`).
    pub tol: f64,
    /// Relative tolerance for recognising active faces, slips and controls at their bounds
    /// (relative to the size of C, to it over the stiffest link, and to `a_l`).
    pub structure_tol: f64,
}

impl Default for CertifyOptions {
    fn default() -> Self {
        CertifyOptions {
            tol: 1e-9,
            structure_tol: INPUT_TOL,
        }
    }
}

/// The verdict on a process.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// The conditions hold with `lambda = 1` and `p + omega` vanishes nowhere.
    Holds,
    /// No multipliers satisfy the conditions.
    Fails,
    /// They hold only degenerately: `lambda = 0`, or `p + omega` vanishing somewhere.
    Degenerate,
}

/// One condition with its residual.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConditionCheck {
    /// Short name, e.g. `adjoint`, `weak_maximality`.
    pub name: String,
    /// `"6.2"` (discrete, P_m / branch LP) or `"2.2"` (continuous time).
    pub theorem: String,
    /// The condition in words with the paper's equation.
    pub statement: String,
    /// Its residual (0 when exactly satisfied).
    pub residual: f64,
    /// The tolerance it is compared with.
    pub tolerance: f64,
    /// `residual <= tolerance`.
    pub holds: bool,
}

/// The mass of `dxi` at one knot on one face.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FaceMultiplier {
    /// Knot index `j` (`0..P`).
    pub knot: usize,
    /// `t_j`.
    pub time: f64,
    /// Block, 1-based.
    pub block: usize,
    /// `"+"` (`F_b = mu_b^+`, normal `nu_b`) or `"-"` (`F_b = -mu_b^-`, normal `-nu_b`).
    pub side: String,
    /// `xi_{j,f}` (Theorem 2.2 sign: `>= 0`).
    pub value: f64,
}

/// The multipliers, per piece, for plotting the adjoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MultiplierData {
    /// `"piecewise_linear"` (P_m: `p` ramps from `p_j` to `p_{j+1}` over piece `j`, paper §9)
    /// or `"piecewise_constant"` (phase gaits: `p = p_j` on piece `j`, jumps at the knots).
    pub extension: String,
    /// Knot times `t_0 = 0, ..., t_P = T`.
    pub times: Vec<f64>,
    /// `p_j`, one row per piece (`p(t_j^+)`).
    pub p: Vec<Vec<f64>>,
    /// `p_j + omega`, one row per piece (§4: `u = -a sign(p + omega)`).
    pub p_plus_omega: Vec<Vec<f64>>,
    /// `psi_j = -p_j - omega - lambda Df2(u_j)`, one row per piece.
    pub psi: Vec<Vec<f64>>,
    /// `u_j`, one row per piece.
    pub u: Vec<Vec<f64>>,
    /// `omega` (per unit time: the paper's `omega_m / h_m`).
    pub omega: Vec<f64>,
    /// The non-zero masses of `dxi` (above `1e-14` times the largest).
    pub xi: Vec<FaceMultiplier>,
}

/// The normalisation constants (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Normalisation {
    /// How the reported multipliers are scaled: `"lambda = 1"`, or for `lambda = 0` the
    /// component fixed to `±1`.
    pub scaled_by: String,
    /// `lambda + ||p||_inf` (Theorem 2.2 nontriviality before scaling it to 1).
    pub lambda_plus_sup_p: f64,
    /// `lambda / (lambda + ||p||_inf)`: `lambda` in Theorem 2.2's normalisation.
    pub lambda_theorem_2_2: f64,
    /// The sum of the paper's (norm) (§9).
    pub paper_norm: f64,
    /// `lambda` divided by that sum.
    pub lambda_paper_norm: f64,
}

/// §4 of the paper for one link: switches, interior arcs and where the switches happen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OneLinkStructure {
    /// `C = [alpha, beta]`.
    pub alpha: f64,
    /// `C = [alpha, beta]`.
    pub beta: f64,
    /// Times where the control changes sign.
    pub switch_times: Vec<f64>,
    /// Whether each switch happens with `x` at an end of C.
    pub switch_at_end: Vec<bool>,
    /// Lengths of the maximal intervals with `alpha < x < beta` (the first and the last joined
    /// across `T`).
    pub interior_arcs: Vec<f64>,
    /// `(beta - alpha) / a`, §4's arc length.
    pub expected_arc: f64,
    /// Whether the control is bang-bang (`|u| = a` on every piece).
    pub bang_bang: bool,
}

/// The certificate of a process (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NecessaryConditions {
    /// Always [`CERTIFICATE_FORMAT`].
    pub format: String,
    /// [`CERTIFICATE_VERSION`].
    pub version: u32,
    /// `"discrete"` or `"phase"`.
    pub method: String,
    /// `m` of P_m.
    pub m: Option<u32>,
    /// The verdict.
    pub verdict: Verdict,
    /// One sentence explaining it.
    pub reason: String,
    /// `lambda` of the reported multipliers (1, or 0 in the degenerate case).
    pub lambda: f64,
    /// `J` of the process: displacement per period minus the actuation cost.
    pub objective: f64,
    /// `min |p_l + omega_l|` over pieces and links, as measured: `0` when it is within the
    /// solver's resolution [`NecessaryConditions::nondegeneracy_resolution`] (the multiplier
    /// LPs carry a slack of `1e-12` that is no measured value).
    pub nondegeneracy_margin: f64,
    /// The resolution at which `p + omega` is known: the conditions' tolerance times the
    /// adjoint's scale `max(1, ||p||_inf)`, that of every other residual. (Absent, 0, in files
    /// of earlier builds.)
    #[serde(default)]
    pub nondegeneracy_resolution: f64,
    /// Normalisation constants.
    pub normalisation: Normalisation,
    /// Every condition with its residual.
    pub conditions: Vec<ConditionCheck>,
    /// The multipliers.
    pub multipliers: MultiplierData,
    /// §4's structure (one link only).
    pub one_link: Option<OneLinkStructure>,
    /// The branch LP solved as such (`f2 = 0` only).
    pub branch_lp: Option<BranchLp>,
}

/// The branch LP (fixed active faces and slips) solved by HiGHS: whether the process is optimal
/// among the processes on its branches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchLp {
    /// Its optimum.
    pub optimum: f64,
    /// `J` of the process.
    pub process_objective: f64,
    /// `optimum - J`: positive when a process on the same branches does better.
    pub improvement: f64,
}

/// Certifies the process of an optimizer result (`crawlopt certify`); `what` names the source.
pub fn certify_result(r: &GaitResult, what: &str) -> Result<NecessaryConditions> {
    let p = Process::from_result(r, what)?;
    certify(&p, &CertifyOptions::default())
}

/// Computes multipliers of a process and checks the necessary conditions (module docs).
pub fn certify(pr: &Process, opts: &CertifyOptions) -> Result<NecessaryConditions> {
    pr.check("process", opts.structure_tol)?;
    let st = Structure::of(pr, opts.structure_tol);
    let cap = 10.0 / (st.nb as f64 * st.k.iter().cloned().fold(f64::INFINITY, f64::min));
    let chosen = stages::search(
        |lambda, stage, norm| kkt::solve(&st, lambda, stage, norm, false),
        |raw| kkt_residual(pr, &st, raw),
        opts.tol,
        cap,
        pr.kind == ProcessKind::Phase,
    )?;
    let branch = match kkt::branch_lp(pr, &st)? {
        Some((optimum, _)) => {
            let j = process_objective(pr);
            Some(BranchLp {
                optimum,
                process_objective: j,
                improvement: optimum - j,
            })
        }
        None => None,
    };
    // Phase gaits: the phase LP is stationary in the durations too, with multipliers of their own
    // (imposing it on the reported ones can conflict with dxi >= 0: three-block phase optimum).
    let duration = if pr.kind == ProcessKind::Phase && chosen.0.lambda > 0.0 {
        let raw = kkt::solve(&st, 1.0, Stage::Kkt, None, true)?.ok_or_else(|| {
            crate::Error::Numerical("certify: HiGHS found the multiplier LP infeasible".into())
        })?;
        Some(kkt_residual_with(pr, &st, &raw, true) / sup(&raw.p).max(1.0))
    } else {
        None
    };
    let mut rep = report(pr, &st, chosen.0, chosen.1, opts);
    if let Some(r) = duration {
        let tol = opts.tol;
        rep.conditions.insert(
            5,
            ConditionCheck {
                name: "duration_stationarity".into(),
                theorem: "6.2".into(),
                statement: "the phase LP is stationary in the durations too: multipliers (of \
                            their own) satisfying the conditions above with H_k = sum_l a_l \
                            |psi_{k,l}| + lambda (Df2(u_k).u_k - f2(u_k)) equal on every phase \
                            (the maximised Hamiltonian is constant); residual of the KKT system \
                            with it, relative to max(1, ||p||_inf)"
                    .into(),
                residual: r,
                tolerance: tol,
                holds: r <= tol,
            },
        );
        if r > tol && rep.verdict != Verdict::Fails {
            rep.verdict = Verdict::Fails;
            rep.reason = format!(
                "the conditions with the durations fixed hold, but the phase LP is not stationary \
                 in the durations: duration_stationarity (Thm 6.2, residual {r:.3e})"
            );
        }
    }
    rep.branch_lp = branch;
    Ok(rep)
}

impl stages::Multipliers for Raw {
    fn p(&self) -> &[Vec<f64>] {
        &self.p
    }
    fn omega(&self) -> &[f64] {
        &self.omega
    }
    fn xi(&self) -> &[Vec<f64>] {
        &self.xi
    }
    fn degenerate(self, by: f64) -> Self {
        let div = |rows| stages::divided(rows, by);
        Raw {
            lambda: 0.0,
            p: div(self.p),
            xi: div(self.xi),
            omega: self.omega.into_iter().map(|v| v / by).collect(),
        }
    }
}

/// The discrete residuals, each as (name, statement, residual).
fn discrete_residuals(
    pr: &Process,
    st: &Structure,
    raw: &Raw,
    durations_free: bool,
) -> Vec<(&'static str, String, f64)> {
    let (n, np) = (st.n, st.np);
    let lam_n = raw.lambda / st.nb as f64;
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

/// Largest residual of the branch-LP KKT system (all discrete conditions but the sign).
fn kkt_residual(pr: &Process, st: &Structure, raw: &Raw) -> f64 {
    kkt_residual_with(pr, st, raw, false)
}

/// The same, with the stationarity in the durations of a phase gait when `durations_free`.
fn kkt_residual_with(pr: &Process, st: &Structure, raw: &Raw, durations_free: bool) -> f64 {
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

fn report(
    pr: &Process,
    st: &Structure,
    raw: Raw,
    scaled_by: String,
    opts: &CertifyOptions,
) -> NecessaryConditions {
    let (n, np) = (st.n, st.np);
    let tol = opts.tol;
    let t_total = pr.problem.period;
    let times = pr.times();
    let discrete = matches!(pr.kind, ProcessKind::Discrete { .. });
    let sup_p = sup(&raw.p);
    let pscale = sup_p.max(1.0);
    let disc = discrete_residuals(pr, st, &raw, false);
    let cont_adj = disc[0].2;
    let cont_sign = disc[5].2;
    let mut conditions: Vec<ConditionCheck> = disc
        .into_iter()
        .filter(|(name, _, _)| *name != "sign")
        .map(|(name, statement, residual)| ConditionCheck {
            name: name.into(),
            theorem: "6.2".into(),
            statement,
            residual,
            tolerance: tol * pscale,
            holds: residual <= tol * pscale,
        })
        .collect();
    let lambda_ok = raw.lambda > 0.0;
    conditions.push(ConditionCheck {
        name: "lambda_positive".into(),
        theorem: "6.2".into(),
        statement: "lambda > 0 (Thm 6.2 (lambda))".into(),
        residual: if lambda_ok { 0.0 } else { 1.0 },
        tolerance: 0.0,
        holds: lambda_ok,
    });

    // Continuous time (Theorem 2.2) with the paper's extension.
    let p_plus_omega: Vec<Vec<f64>> = raw
        .p
        .iter()
        .map(|p| (0..n).map(|l| p[l] + raw.omega[l]).collect())
        .collect();
    let psi_at =
        |p: &[f64], j: usize, l: usize| -p[l] - raw.omega[l] - raw.lambda * st.grad_f2[j][l];
    let mut l1 = 0.0;
    for j in 0..np {
        let next = if discrete { (j + 1) % np } else { j };
        for l in 0..n {
            let (a, b) = (psi_at(&raw.p[j], j, l), psi_at(&raw.p[next], j, l));
            let tau = pr.durations[j];
            l1 += match st.bound[j][l] {
                1 => int_pos(-a, -b, tau),
                -1 => int_pos(a, b, tau),
                _ => int_pos(a, b, tau) + int_pos(-a, -b, tau),
            };
        }
    }
    let mut misplaced = 0.0;
    if discrete {
        for j in 0..np {
            let start = (j + np - 1) % np;
            for (fi, f) in st.active[j].iter().enumerate() {
                if !st.active[start].contains(f) {
                    misplaced += raw.xi[j][fi].abs();
                }
            }
        }
    }
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
    let a = &pr.problem.rate_bound;
    let mut law = 0.0_f64;
    for j in 0..np {
        for l in 0..n {
            let s = p_plus_omega[j][l];
            let u = pr.controls[j][l];
            let want = match pr.problem.cost {
                Cost::Quadratic { weight } if raw.lambda > 0.0 => {
                    Some((-s / (raw.lambda * weight)).clamp(-a[l], a[l]))
                }
                _ if s.abs() > nd_tol => Some(-a[l] * s.signum()),
                _ => None,
            };
            if let Some(w) = want {
                law = law.max((u - w).abs() / a[l]);
            }
        }
    }
    let nontrivial = raw.lambda + sup_p;
    for (name, statement, residual, tolerance) in [
        (
            "adjoint",
            "dp = sum_j x*_j dxi^j, p(T) = p(0) (Thm 2.2 adjoint, transversality)",
            cont_adj,
            tol * pscale,
        ),
        (
            "sign",
            "dxi^j >= 0 (Thm 2.2; Thm 6.1 for the paper's P_m, whose state constraints are pure \
             inequalities: the branch LP of the computational P_m leaves it free on held faces)",
            cont_sign,
            tol * pscale,
        ),
        (
            "support",
            "supp dxi^j in {t : face j active at x(t)}: dxi mass on steps where the face is not \
             active throughout (Thm 2.2 support)",
            misplaced,
            tol * pscale,
        ),
        (
            "weak_maximality",
            "int_0^T dist(psi(t), N_U(u(t))) dt, psi = -p - omega - lambda Df2(u) (Thm 2.2)",
            l1,
            tol * pscale * t_total,
        ),
        (
            "nontriviality",
            "lambda + ||p||_inf > 0, scaled to 1 (Thm 2.2)",
            if nontrivial > 0.0 { 0.0 } else { 1.0 },
            0.0,
        ),
        (
            "nondegeneracy",
            "p_l(t) + omega_l != 0 for all t and l (§4 (nndg)): min |p + omega| above 1e-6 \
             max(sup|p + omega|, 1/(N k_max)) and the solver's resolution; residual 1 when it is \
             not (min |p + omega| is reported beside J)",
            if margin > nd_tol { 0.0 } else { 1.0 },
            0.0,
        ),
        (
            "control_law",
            "u = -a sign(p + omega) where p + omega != 0 (f2 = 0, §4), u = proj_U(-(p + \
             omega)/(lambda c)) (f2 = (c/2)|u|^2): max |u - law| / a",
            law,
            tol.max(1e-9) * 10.0,
        ),
    ] {
        conditions.push(ConditionCheck {
            name: name.into(),
            theorem: "2.2".into(),
            statement: statement.into(),
            residual,
            tolerance,
            holds: residual <= tolerance,
        });
    }

    // Verdict.
    let group_ok = |th: &str| {
        conditions
            .iter()
            .filter(|c| c.theorem == th && c.name != "nondegeneracy" && c.name != "control_law")
            .all(|c| c.holds)
    };
    let disc_ok = conditions
        .iter()
        .filter(|c| c.theorem == "6.2" && c.name != "lambda_positive")
        .all(|c| c.holds);
    let cont_ok = discrete || group_ok("2.2");
    let nondeg = margin > nd_tol;
    let (verdict, reason) = if disc_ok && cont_ok && lambda_ok && nondeg {
        (
            Verdict::Holds,
            "the necessary conditions hold with lambda = 1 and p + omega vanishes nowhere".into(),
        )
    } else if disc_ok && cont_ok && lambda_ok {
        let (j, l) = argmin_abs(&p_plus_omega);
        (
            Verdict::Degenerate,
            format!(
                "the conditions hold with lambda = 1 but only degenerately: p + omega = {} on \
                 piece {j} (t = {:.6}), link {} (§4 (nndg) fails)",
                if margin == 0.0 {
                    format!("0 at the solver's resolution {resolution:.1e}")
                } else {
                    format!("{:.3e}", p_plus_omega[j][l])
                },
                times[j],
                l + 1
            ),
        )
    } else if disc_ok && cont_ok {
        (
            Verdict::Degenerate,
            "no multipliers with lambda > 0 exist; the conditions hold only with lambda = 0".into(),
        )
    } else {
        let failing = |th: &str| -> Vec<&ConditionCheck> {
            conditions
                .iter()
                .filter(|c| {
                    !c.holds
                        && c.theorem == th
                        && !matches!(
                            c.name.as_str(),
                            "nondegeneracy" | "control_law" | "lambda_positive"
                        )
                })
                .collect()
        };
        let mut bad = failing("6.2");
        if bad.is_empty() {
            bad = failing("2.2");
        }
        let names: Vec<String> = bad
            .iter()
            .map(|c| {
                format!(
                    "{} (Thm {}, residual {:.3e})",
                    c.name, c.theorem, c.residual
                )
            })
            .collect();
        (
            Verdict::Fails,
            format!(
                "no multipliers satisfy the necessary conditions, with lambda = 1 or 0; at the \
                 least violating ones with lambda = 1: {}",
                names.join(", ")
            ),
        )
    };

    // Normalisations.
    let mut paper = raw.lambda + norm2(&raw.p[0]) + norm2(&raw.omega);
    for j in 0..np {
        let mut v = vec![0.0; n];
        for (fi, &f) in st.active[j].iter().enumerate() {
            for (l, c) in normal(n, f) {
                v[l] += raw.xi[j][fi] * c;
            }
        }
        paper += norm2(&v);
        let psi: Vec<f64> = (0..n).map(|l| psi_at(&raw.p[j], j, l)).collect();
        paper += pr.durations[j] * norm2(&psi);
    }
    let xmax = raw.xi.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut xi = Vec::new();
    for j in 0..np {
        for (fi, &FaceId { b, s }) in st.active[j].iter().enumerate() {
            let v = raw.xi[j][fi];
            if v.abs() > 1e-14 * xmax {
                xi.push(FaceMultiplier {
                    knot: j,
                    time: times[j],
                    block: b + 1,
                    side: if s > 0 { "+" } else { "-" }.into(),
                    value: v,
                });
            }
        }
    }
    let multipliers = MultiplierData {
        extension: if discrete {
            "piecewise_linear"
        } else {
            "piecewise_constant"
        }
        .into(),
        times: times.clone(),
        psi: (0..np)
            .map(|j| (0..n).map(|l| psi_at(&raw.p[j], j, l)).collect())
            .collect(),
        p: raw.p.clone(),
        p_plus_omega,
        u: pr.controls.clone(),
        omega: raw.omega.clone(),
        xi,
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
        normalisation: Normalisation {
            scaled_by,
            lambda_plus_sup_p: nontrivial,
            lambda_theorem_2_2: raw.lambda / nontrivial,
            paper_norm: paper,
            lambda_paper_norm: raw.lambda / paper,
        },
        conditions,
        multipliers,
        one_link: one_link_structure(pr, opts.structure_tol),
        branch_lp: None,
    }
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

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimal::{solve_discrete_global, GaitProblem};
    use crate::Crawler;

    /// The duals HiGHS returns for the branch LP satisfy the KKT system as written here (the
    /// independent check of the derivation and its signs), at the global optimum of P_m.
    #[test]
    fn branch_lp_duals_satisfy_the_kkt_system() {
        for (nb, mm, m) in [(2, 2.0, 3), (3, 1.5, 3)] {
            let c = Crawler::uniform(nb, 1.0, 1.0, mm).unwrap();
            let pb = GaitProblem::new(&c, 10.0, &vec![1.0; nb - 1], Cost::None, None).unwrap();
            let s = solve_discrete_global(&c, &pb, m, Some(60.0)).unwrap();
            let r = GaitResult::from_discrete(&c, &pb, &s);
            let pr = Process::from_result(&r, "test").unwrap();
            let st = Structure::of(&pr, INPUT_TOL);
            let (opt, raw) = kkt::branch_lp(&pr, &st).unwrap().unwrap();
            assert!((opt - r.objective).abs() < 1e-9, "{opt} vs {}", r.objective);
            let res = discrete_residuals(&pr, &st, &raw, false);
            for (name, _, v) in &res {
                println!("N = {nb}: {name} {v:.3e}");
            }
            assert!(kkt_residual(&pr, &st, &raw) < 1e-9);
        }
    }
}
