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
//! The first five are exactly the optimality conditions of the branch LP with its biactive pairs
//! relaxed (LP duality: they hold with `lambda = 1` iff the process is optimal for that relaxed
//! LP): strong stationarity. Where no pair is biactive, that LP is the branch LP itself and a
//! global optimum of P_m must satisfy them; at a biactive pair the relaxed LP admits slips off
//! their face, which no process makes, so a global optimum may fail them (the three-block P_3
//! optimum the general formulation returns does, tests/certify.rs). They form the group "6.2"
//! of the report. The sign is
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
//! that `p + omega` vanishes on half the period), three small LPs are solved with HiGHS. There is
//! one formulation of them, the general problem's ([`general`]): the crawler's branch LP *is* the
//! branch LP of its exact instance of (P) ([`crate::model::crawler_as_general`]: `x~ =
//! K^(-1/2) x`, unit normals `x~*_(b+-) = +-K^(1/2) nu_b / s_b` with `s_b = sqrt(k_(b-1) + k_b)`,
//! face weights `+-1/(N s_b)`, `B = K^(-1/2)`, `A = 0`), so the LPs are solved in `(p~, xi~,
//! omega)` with the structure of the crawler's process on that instance (its active, held and
//! biactive faces, slipping blocks' faces reacting, rates at a bound, in (P)'s face numbering:
//! face `2 b` is block `b`'s side `+`, `2 b + 1` its side `-`, 0-based), counted in the
//! crawler's units, and read back in the crawler's names:
//! `p = K^(-1/2) p~`, `omega` unchanged (`B^T p~ = p`, so `psi` is unchanged too) and `xi_(b+-) =
//! xi~_(b+-) / s_b` (the Lagrangian term `<q, dynamics>` is invariant under the change of
//! variables; `certify::crawler_general`). The box's bounds are axis rows of U, whose
//! normal-cone weights are `psi`'s own (no columns for them), so the LPs have the crawler's size:
//! 1. with `lambda = 1`, minimise the largest violation `r` of the branch LP's KKT system (all
//!    conditions above but the sign; the adjoint equation is imposed exactly, `xi` exists only on
//!    active faces). `r = 0` iff the process is optimal for its branch LP; `r > 0` measures how far
//!    it is from being so (a suboptimal gait has `r > 0`). The rows are (P)'s, with `r` counted
//!    in the crawler's units on each face (`face_scale = s_b`: the unit row's slip stationarity
//!    is `(<p, K nu_b> + lambda/N) / s_b`), so that the least violation is the crawler's;
//! 2. keeping `r`, minimise the largest violation `s` of `xi >= 0`, again in the crawler's units
//!    (`xi~ >= -s_b s`);
//! 3. keeping `r` and `s`, maximise the non-degeneracy margin `delta`: `-(p_l + omega_l)
//!    sign(u_l) >= delta` wherever `u_l` is at a bound.
//!
//! Where the multipliers are unique (e.g. every `holds` verdict of the tests) the weights are
//! immaterial; where they are not, the residuals and the margin reported are those of the
//! multipliers these stages pick, recomputed in the crawler's own units.
//!
//! If stage 1 leaves `r` above tolerance, the degenerate case `lambda = 0` is tried: the
//! conditions are then homogeneous, and a generic linear functional of `(p, omega)` and its
//! opposite are maximised over them in the box `|p~|, |omega| <= 1`; a non-zero maximiser, read
//! back and scaled to `max(|p|, |omega|) = 1`, is a degenerate multiplier.
//! Every residual is then recomputed in plain floating point from the multipliers found, not taken
//! from the LP, by (P)'s residuals on the instance (`certify::general_conditions::residuals`,
//! the same code as a general certificate's) in the crawler's units (the adjoint row of link `l`
//! times `1 / sqrt(k_l)`, a face's rows and `xi` by `s_b`) and stated in the crawler's words
//! (`slip_stationarity` is (P)'s reaction stationarity on a slipping block's face). The
//! maximised Hamiltonian of a phase gait is (P)'s, `sum_r rho_r h_r`: `a_l |psi_l|` on the rates
//! at their bound (where `psi` lies in the box's normal cone; an interior rate's `psi`, zero up
//! to the maximality residual, adds nothing). The branch LPs themselves are solved too (`f2 = 0`;
//! (P)'s branch LPs on the instance, `certify::branch`), each with its slips fixed
//! so that every point of it is a process: the gait's own branch (biactive blocks sticking)
//! and, within a budget ([`branches_enumerated`]), every branch through it (each
//! biactive block sticking or slipping on its face). The best optimum minus `J` is reported
//! (`branch_lp.improvement`, positive when a process on one of them does better; `biactive`,
//! `branches`), and a unit test checks that HiGHS's duals of the own branch, mapped as above,
//! satisfy this KKT system at the P_m optima it runs on. Optimal on every branch through it, a
//! P_m process is a local optimum of P_m: a `fails` verdict there says in its reason that the
//! failure does not show it suboptimal.
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
//!   continuous ones (group "2.2", then exact) too — and `p + omega` vanishes nowhere (not
//!   required with a quadratic cost and `lambda = 1`: `f2` strictly convex makes the control
//!   unique);
//! - `degenerate`: they hold but only with `p + omega` vanishing on some piece (e.g. an interior
//!   control with `f2 = 0`), or only with `lambda = 0`;
//! - `fails`: no multipliers satisfy them; the reason lists the violated conditions with their
//!   residuals at the least violating multipliers (a min-max solution spreads the violation over
//!   several conditions, so all of them are named).
//!
//! There is one driver and one report, (P)'s (`general::certify_structured`, `general_report`):
//! a crawler's certificate is (P)'s certificate of its process on its instance (the process
//! `GeneralProcess::of_crawler`, its structure `GeneralStructure::of`, in `crawler_general`),
//! with every residual in the crawler's units (`GeneralStructure::state_scale`, `face_scale`,
//! `switching_unit`, `margin_cap`) and every condition in the crawler's words
//! (`crawler_words::crawler_words`), read back in the crawler's names (`report.rs`: `p` and
//! `p + omega` per link, `dxi` per block and side, the one-link structure). The verdict, the
//! groups' bookkeeping, the support of `dxi`, the L^1 weak maximality of a step and the
//! normalisations are `verdict.rs`.
//!
//! For P_m the continuous group is reported with the same tolerance and is expected to fail at
//! `O(h)`: it is the rate at which the discrete multipliers approach Theorem 2.2's.
//! For phase gaits the durations are variables of the phase LP (theory §7) too; its stationarity in
//! `tau_k` (with `|U| <= a tau`, `sum tau = T`) reads `H_k = sum_l a_l |psi_{k,l}| + lambda
//! (Df2(u_k).u_k - f2(u_k))` equal on every phase: the maximised Hamiltonian is constant, as for
//! an autonomous problem. It is checked (condition `duration_stationarity`, group "6.2") with
//! multipliers of its own, found by the stage-1 LP with these rows added (the general phase LP's
//! `H_i = sum_r rho_(i,r) h_r`, for the box `sum_l a_l |psi_(i,l)|`): imposed on the reported
//! multipliers it can conflict with `dxi >= 0` (the three-block phase optimum: `xi = -1/6`
//! somewhere), and Theorem 2.2 does not state it. It is checked with `lambda = 1` where the
//! other conditions hold with it, else with multipliers of the same search at `lambda = 0`. The
//! block-speed bound `|D| <= V tau` of the phase MILP is taken as inactive.

pub mod bound;
mod branch;
mod crawler_general;
mod crawler_units;
mod crawler_words;
pub mod general;
mod general_conditions;
mod general_kkt;
mod general_process;
mod general_report;
mod one_link;
mod process;
mod records;
mod report;
mod stages;
mod verdict;

pub use general::{certify_general, residuals_of, GeneralNecessaryConditions, GeneralProcess};
pub use process::{Process, ProcessKind, INPUT_TOL};

pub use records::{
    branches_enumerated, BranchLp, CertifyOptions, ConditionCheck, FaceMultiplier, MultiplierData,
    NecessaryConditions, Normalisation, OneLinkStructure, Verdict, CERTIFICATE_FORMAT,
    CERTIFICATE_VERSION, MAX_BRANCH_COLUMNS, MAX_BRANCH_PAIRS,
};
pub use report::process_objective;

use crate::error::Result;
use crate::optimal::GaitResult;

/// Certifies the process of an optimizer result (`crawlopt certify`); `what` names the source.
pub fn certify_result(r: &GaitResult, what: &str) -> Result<NecessaryConditions> {
    let p = Process::from_result(r, what)?;
    certify(&p, &CertifyOptions::default())
}

/// Computes multipliers of a process and checks the necessary conditions (module docs): (P)'s
/// one certificate ([`general`]) of the process on the crawler's instance, counted in the
/// crawler's units of its own scales (`crawler_units`: force `mu_max`, length
/// `mu_max / k_max`, time the period, so that twins in other units get the same verdict), and
/// read back in its names and units.
pub fn certify(pr: &Process, opts: &CertifyOptions) -> Result<NecessaryConditions> {
    pr.check("process", opts.structure_tol)?;
    let units = crawler_units::units_of(pr);
    let scaled = crawler_units::in_units(pr, units)?;
    let general = crawler_general::AsGeneral::of(&scaled, opts.structure_tol, units)?;
    let (rep, raw) = general.certify(opts)?;
    let mut c = crawler_units::to_user(report::report(&scaled, rep, raw), units);
    // `J` of the process as given.
    c.objective = report::process_objective(pr);
    Ok(c)
}
