//! The records of a certificate (module docs of [`crate::certify`]), of (P) and of a crawler
//! alike: the options, the conditions with their residuals, the multipliers and the verdict, as
//! written to JSON.

use super::process::INPUT_TOL;
use serde::{Deserialize, Serialize};

/// Value of [`NecessaryConditions::format`] for a crawler's certificate
/// ([`GENERAL_CERTIFICATE_FORMAT`](super::general::GENERAL_CERTIFICATE_FORMAT) for (P)'s).
pub const CERTIFICATE_FORMAT: &str = "crawlopt-necessary-conditions";
/// Version of the certificate format.
pub const CERTIFICATE_VERSION: u32 = 1;

/// Options of [`super::certify`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CertifyOptions {
    /// Relative tolerance of every residual (pointwise residuals relative to
    /// `max(1, ||p||_inf)`, integrals also to `T`).
    pub tol: f64,
    /// Relative tolerance for recognising active faces, reactions (a crawler's slips) and
    /// controls at their bounds (relative to the size of C, `max |c_f|` with unit normals, on
    /// (P) or a crawler's instance of it; and to the largest bound of U).
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

/// Files of earlier builds asked the non-degeneracy margin of every cost.
fn margin_required_before() -> bool {
    true
}

/// The normalisation constants (module docs); a crawler's count `p` with forces in units of
/// its stiffest spring and time in periods (`super::crawler_units`), the same for its twins in
/// any units.
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

/// §4 of the paper for one link (a one-link crawler, or (P) on a line with `A = 0`, `b = 0` and
/// `U = [-a, a]`: `certify::one_link`): switches, interior arcs and where the switches happen.
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
    /// `(beta - alpha) / (|B| a)` (a crawler's `(beta - alpha) / a`), §4's arc length: the time
    /// `x` takes to cross C at full control.
    pub expected_arc: f64,
    /// Whether the control is bang-bang (`|u| = a` on every piece).
    pub bang_bang: bool,
}

/// The certificate of a process (module docs): one record for (P) and for every instance of
/// it, `M` its multipliers as the problem names them: a crawler's per link, block and side
/// ([`MultiplierData`], the default), (P)'s per component and face
/// ([`super::general::GeneralMultipliers`]). A crawler's certificate is (P)'s on its instance
/// with the multipliers read back in the crawler's names: the conditions, residuals,
/// margin, normalisations and verdict are (P)'s.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NecessaryConditions<M = MultiplierData> {
    /// [`CERTIFICATE_FORMAT`] for a crawler,
    /// [`GENERAL_CERTIFICATE_FORMAT`](super::general::GENERAL_CERTIFICATE_FORMAT) for (P).
    pub format: String,
    /// [`CERTIFICATE_VERSION`].
    pub version: u32,
    /// `"discrete"` (a P_m process) or `"phase"` (an exact phase gait).
    pub method: String,
    /// `m` of P_m (absent for a phase gait).
    pub m: Option<u32>,
    /// The verdict.
    pub verdict: Verdict,
    /// One sentence explaining it.
    pub reason: String,
    /// `lambda` of the reported multipliers (1, or 0 in the degenerate case).
    pub lambda: f64,
    /// `J` of the process (a crawler's: displacement per period minus the actuation cost).
    pub objective: f64,
    /// The non-degeneracy margin, as measured: for a box U the least `|sigma_l|` of the
    /// switching function `sigma = B^T p + omega` over pieces and components (a crawler's
    /// `min |p_l + omega_l|`), for a polytope U the least weight `rho` of U's active rows at the
    /// pieces at a vertex of U. `0` when it is within the solver's resolution
    /// [`NecessaryConditions::nondegeneracy_resolution`] (the multiplier LPs carry a slack of
    /// `1e-12` that is no measured value).
    pub nondegeneracy_margin: f64,
    /// The resolution at which the margin is known: the conditions' tolerance times the
    /// adjoint's scale `max(1, ||p||_inf)`, that of every other residual, times the unit of the
    /// switching function per unit of `p` (`max |B_ij|` for (P); 1 for a crawler, whose margin
    /// and resolution are then divided by `k_max`, as its `p`: `super::crawler_units`).
    /// (Absent, 0, in files of earlier builds.)
    #[serde(default)]
    pub nondegeneracy_resolution: f64,
    /// Whether the verdict requires that margin: unless `f2` is strictly convex and
    /// `lambda > 0` (with a quadratic cost the control `proj_U(-(p + omega) / (lambda c))` is
    /// then unique wherever `p + omega` vanishes).
    /// (Absent, true, in files of earlier builds, which asked the margin of every cost.)
    #[serde(default = "margin_required_before")]
    pub margin_required: bool,
    /// Normalisation constants.
    pub normalisation: Normalisation,
    /// Every condition with its residual.
    pub conditions: Vec<ConditionCheck>,
    /// The multipliers.
    pub multipliers: M,
    /// §4's structure of the process where the problem lives on a line (theory §9: a one-link
    /// crawler, or (P) with one state and one control, `A = 0`, `b = 0`, `U = [-a, a]`);
    /// `null` otherwise.
    #[serde(default)]
    pub one_link: Option<OneLinkStructure>,
    /// The branch LP solved as such (`f2 = 0` only).
    pub branch_lp: Option<BranchLp>,
}

impl<M> NecessaryConditions<M> {
    /// The same certificate with its multipliers named by `name` (an instance's certificate of
    /// (P) read back in the instance's own names): every condition, residual, the margin and
    /// the verdict unchanged.
    pub(crate) fn named<N>(self, name: impl FnOnce(M) -> N) -> NecessaryConditions<N> {
        NecessaryConditions {
            format: self.format,
            version: self.version,
            method: self.method,
            m: self.m,
            verdict: self.verdict,
            reason: self.reason,
            lambda: self.lambda,
            objective: self.objective,
            nondegeneracy_margin: self.nondegeneracy_margin,
            nondegeneracy_resolution: self.nondegeneracy_resolution,
            margin_required: self.margin_required,
            normalisation: self.normalisation,
            conditions: self.conditions,
            multipliers: name(self.multipliers),
            one_link: self.one_link,
            branch_lp: self.branch_lp,
        }
    }
}

/// The branch LP (fixed active faces and slips, so every point of it a process) solved by
/// HiGHS: whether the process is optimal among the processes on its branch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchLp {
    /// Its optimum.
    pub optimum: f64,
    /// `J` of the process.
    pub process_objective: f64,
    /// `optimum - J`: positive when a process on one of the branches solved does better.
    pub improvement: f64,
    /// The biactive pairs of the process (a face active with no slip or reaction on it): each
    /// is two branches through it, sticking and slipping on the face.
    #[serde(default)]
    pub biactive: usize,
    /// The branch LPs solved: its own (biactive pairs sticking), and all `2^biactive` branches
    /// through it within [`branches_enumerated`]'s budget. `optimum` is the best of them.
    #[serde(default = "one")]
    pub branches: usize,
}

fn one() -> usize {
    1
}

impl BranchLp {
    /// Whether every branch through the process was solved (`2^biactive` of them).
    pub fn all_solved(&self) -> bool {
        self.biactive < usize::BITS as usize && self.branches == 1 << self.biactive
    }

    /// What was solved, for text output: "branch LP (slips fixed)" for a process without
    /// biactive pairs, else how many of the branches through it.
    pub fn describe(&self, fixed: &str) -> String {
        let b = self.biactive;
        if b == 0 {
            format!("branch LP ({fixed} fixed)")
        } else if self.all_solved() {
            format!(
                "branch LPs ({fixed} fixed; all {} branches through its {b} biactive pairs)",
                self.branches
            )
        } else {
            format!(
                "branch LPs ({fixed} fixed; {} of the 2^{b} branches through its {b} biactive \
                 pairs: the others beyond the budget or without an optimum)",
                self.branches
            )
        }
    }
}

/// The most biactive pairs whose `2^b` branches a certificate enumerates (256 LPs).
pub const MAX_BRANCH_PAIRS: usize = 8;

/// The budget of the enumeration: `2^b` times the columns of one branch LP at most this, so
/// that a long process enumerates fewer pairs (the three-block P_3 all 8 of its pairs, in 0.2
/// s; P_8 up to 4 pairs; P_10 of four blocks one).
pub const MAX_BRANCH_COLUMNS: usize = 1 << 15;

/// Whether all `2^biactive` branches through a process are solved, each LP of about `columns`
/// columns: at most [`MAX_BRANCH_PAIRS`] pairs, within [`MAX_BRANCH_COLUMNS`] (without a
/// biactive pair, the one branch is the process's own).
pub fn branches_enumerated(biactive: usize, columns: usize) -> bool {
    biactive == 0
        || (biactive <= MAX_BRANCH_PAIRS
            && (1usize << biactive).saturating_mul(columns) <= MAX_BRANCH_COLUMNS)
}

/// The branch LPs of a process of objective `j` with `biactive` biactive pairs, each LP of
/// about `columns` columns: its own branch (every pair sticking) and, where
/// [`branches_enumerated`], every branch through it (each pair sticking or slipping on its
/// face), each an LP whose points are all processes; `solve(choice)` is one branch's optimum
/// (`None` when HiGHS gives none). The best of them, `None` when the own branch gives none.
/// Optimal on every branch through it, a P_m process is a local optimum of P_m, whatever its
/// multipliers. Cancellable between LPs.
pub(crate) fn best_branch(
    biactive: usize,
    columns: usize,
    j: f64,
    mut solve: impl FnMut(&[bool]) -> crate::error::Result<Option<f64>>,
) -> crate::error::Result<Option<BranchLp>> {
    let Some(mut optimum) = solve(&vec![false; biactive])? else {
        return Ok(None);
    };
    let mut branches = 1;
    if branches_enumerated(biactive, columns) {
        for mask in 1..1usize << biactive {
            crate::progress::check()?;
            let choice: Vec<bool> = (0..biactive).map(|i| mask >> i & 1 == 1).collect();
            if let Some(v) = solve(&choice)? {
                optimum = optimum.max(v);
                branches += 1;
            }
        }
    }
    Ok(Some(BranchLp {
        optimum,
        process_objective: j,
        improvement: optimum - j,
        biactive,
        branches,
    }))
}

/// The phase LP's stationarity in the durations (a phase gait's condition
/// `duration_stationarity`, group "6.2"), with its residual `r` (relative to `max(1, ||p||)`;
/// the Hamiltonian's own spread relative to its unit, `certify::general`'s `kkt_residual`)
/// from multipliers of its own: inserted after the five conditions with the durations fixed,
/// and a verdict that held turned into `fails` when it does not hold. `hamiltonian` states the
/// phase's maximised Hamiltonian `H_k` in the problem's terms.
fn duration_condition(
    conditions: &mut Vec<ConditionCheck>,
    verdict: &mut Verdict,
    reason: &mut String,
    hamiltonian: &str,
    r: f64,
    tol: f64,
) {
    conditions.insert(
        5.min(conditions.len()),
        ConditionCheck {
            name: "duration_stationarity".into(),
            theorem: "6.2".into(),
            statement: format!(
                "the phase LP is stationary in the durations too: multipliers (of their own) \
                 satisfying the conditions above with {hamiltonian} equal on every phase (the \
                 maximised Hamiltonian is constant); residual of the KKT system with it, \
                 relative to max(1, ||p||_inf), the Hamiltonian's spread to its own unit"
            ),
            residual: r,
            tolerance: tol,
            holds: r <= tol,
        },
    );
    if r > tol && *verdict != Verdict::Fails {
        *verdict = Verdict::Fails;
        *reason = format!(
            "the conditions with the durations fixed hold, but the phase LP is not stationary in \
             the durations: duration_stationarity (Thm 6.2, residual {r:.3e})"
        );
    }
}

impl<M> NecessaryConditions<M> {
    /// [`duration_condition`] on this certificate.
    pub(crate) fn add_duration_condition(&mut self, hamiltonian: &str, r: f64, tol: f64) {
        duration_condition(
            &mut self.conditions,
            &mut self.verdict,
            &mut self.reason,
            hamiltonian,
            r,
            tol,
        );
    }

    /// Completes the reason of a failing phase gait of a quadratic cost
    /// ([`note_approximate_cost`]); a certificate that does not fail is left as it is.
    pub(crate) fn note_approximate_cost(&mut self) {
        if self.verdict == Verdict::Fails {
            note_approximate_cost(&self.conditions, &mut self.reason);
        }
    }

    /// Records the best branch LP through the process; on a P_m process (`p_m`) a failure
    /// that it does not show suboptimal says so ([`note_biactive`]; a phase gait's branch
    /// LPs fix its durations, so they do not make it a local optimum).
    pub(crate) fn set_branch_lp(&mut self, branch: Option<BranchLp>, p_m: bool, tol: f64) {
        self.branch_lp = branch;
        if p_m {
            note_biactive(self.verdict, self.branch_lp.as_ref(), tol, &mut self.reason);
        }
    }
}

/// Appended to the reason of a phase gait of a quadratic cost that fails by little
/// ([`note_approximate_cost`]).
const APPROXIMATE_COST: &str = " (f2 is quadratic and every violation is within 1e6 times its \
     tolerance: if the gait is a phase MILP's whose polish on its slip modes did not apply, its \
     controls are only as accurate as the MILP's outer approximation of f2, about 1e-6 in J, \
     so violations of this size are expected of an optimum)";

/// The reason of a failed certificate, completed when the failure does not show the process
/// suboptimal: the discrete conditions checked are strong stationarity, necessary at an optimum
/// of P_m only where no pair is biactive. When every branch through a P_m process was solved
/// ([`best_branch`]) and none does better, it is a local optimum of P_m, and the reason says
/// so: improvements up to `tol` (the certificate's tolerance) relative to `max(1, |optimum|)`
/// count as none. Shared by a crawler's certificate and a general one (P_m processes only: a
/// phase gait's branch LPs fix its durations).
fn note_biactive(verdict: Verdict, branch: Option<&BranchLp>, tol: f64, reason: &mut String) {
    let Some(b) = branch else { return };
    if verdict != Verdict::Fails
        || b.biactive == 0
        || !b.all_solved()
        || b.improvement > tol * b.optimum.abs().max(1.0)
    {
        return;
    }
    reason.push_str(&format!(
        "; the process has {} biactive pair{} (a face active with no slip or reaction on it), \
         where these conditions (strong stationarity) need not hold at an optimum, and it is \
         optimal on each of the {} branches through it (branch LPs, improvement {:.3e}): this \
         failure does not show it suboptimal",
        b.biactive,
        if b.biactive == 1 { "" } else { "s" },
        b.branches,
        b.improvement
    ));
}

/// Says in `reason` why a failing phase gait of a quadratic cost may still be an optimum: when
/// every failing condition of the verdict is within `1e6` times its tolerance (the size the
/// phase MILP's outer approximation leaves); a larger violation gets no note.
fn note_approximate_cost(conditions: &[ConditionCheck], reason: &mut String) {
    let counted = |c: &&ConditionCheck| {
        !c.holds
            && !matches!(
                c.name.as_str(),
                "nondegeneracy" | "control_law" | "lambda_positive"
            )
    };
    let small = conditions
        .iter()
        .filter(counted)
        .all(|c| c.residual <= 1e6 * c.tolerance.max(1e-15));
    if small {
        reason.push_str(APPROXIMATE_COST);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn branch(improvement: f64, biactive: usize, branches: usize) -> BranchLp {
        BranchLp {
            optimum: 2.0,
            process_objective: 2.0 - improvement,
            improvement,
            biactive,
            branches,
        }
    }

    /// The enumeration's budget: all 8 pairs of the three-block P_3 (8 pieces of 7 columns),
    /// at most 4 on its P_8 (256 pieces), none past 8 pairs however small the LPs.
    #[test]
    fn the_budget_shrinks_with_the_process() {
        assert!(branches_enumerated(8, 8 * 7));
        assert!(branches_enumerated(4, 256 * 7) && !branches_enumerated(5, 256 * 7));
        assert!(!branches_enumerated(9, 1));
        assert!(branches_enumerated(0, usize::MAX));
    }

    /// The note needs a failure, biactive pairs, every branch solved and no gain beyond the
    /// certificate's tolerance (a gain of 1.8e-7, a branch that beats the process, is one).
    #[test]
    fn the_note_is_added_only_when_every_branch_is_no_better() {
        let note = |v: Verdict, b: BranchLp| {
            let mut reason = String::from("no multipliers");
            note_biactive(v, Some(&b), 1e-9, &mut reason);
            reason.contains("does not show it suboptimal")
        };
        assert!(note(Verdict::Fails, branch(-5e-15, 8, 256)));
        assert!(!note(Verdict::Fails, branch(1.76e-7, 5, 32)));
        assert!(!note(Verdict::Fails, branch(0.0, 8, 1)));
        assert!(!note(Verdict::Fails, branch(0.0, 0, 1)));
        assert!(!note(Verdict::Degenerate, branch(0.0, 3, 8)));
    }
}
