//! Is a process one of (P)? The conditions a recorded or computed process must meet before it
//! is shown, replayed or certified, stated once over (P) (paper §2, the discrete process of
//! P_m in §3; theory §11): `x^P = x^0` (or `x^0` the initial state), `x^k in C`, `u^i in U`
//! with zero mean, `lambda >= 0`, each piece's step and a reaction only on an active face.
//!
//! A general process is checked here directly; a crawler's through its instance of (P)
//! ([`crate::model::crawler_as_general`]: states `x~ = K^(-1/2) x`, reaction rates
//! `s_b max(+-D_b, 0) / tau`). The check returns *which* condition fails and where
//! ([`Fault`]), not a message: each kind of problem names it in its own words (a general
//! result's `x[k]`, `lambda[i][j]`; a crawler's `solution.states[k]`, a block and its friction
//! threshold).

use crate::error::Error;
use crate::model::general::{Boundary, ControlSet, GeneralProblem};

/// How the process was discretised, which fixes where a slipping block's face must be active.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProcessKind {
    /// A P_m process (theory §6): `2^m` equal catching-up steps; a block slipping on step `i`
    /// has its face active at the end `x^{i+1}` (implicit Euler).
    Discrete {
        /// `m`.
        m: u32,
    },
    /// A phase gait (theory §7): constant control per phase, exact; a block slipping on a phase
    /// has its face active at both ends (held throughout).
    Phase,
}

/// The rows `(G_k, h_k)` of U: a box as `e_l <= upper_l`, `-e_l <= -lower_l` (in this order per
/// component), a polytope's unit rows as given.
pub(crate) fn control_rows(u: &ControlSet) -> Vec<(Vec<f64>, f64)> {
    match u {
        ControlSet::Box { lower, upper } => {
            let m = lower.len();
            let unit = |l: usize, s: f64| (0..m).map(|k| if k == l { s } else { 0.0 }).collect();
            (0..m)
                .flat_map(|l| [(unit(l, 1.0), upper[l]), (unit(l, -1.0), -lower[l])])
                .collect()
        }
        ControlSet::Polytope(p) => p.normals.iter().cloned().zip(p.offsets.clone()).collect(),
    }
}

/// The scale each component of a control is held to (its bound and its mean): a box's
/// `max(|lower_l|, |upper_l|)` per component, so that a crawler's links whose rate bounds `a_l`
/// are 100 apart are each checked against their own; U's largest offset for every component
/// of a polytope (its unit rows mix them). Never below `1e-9` of U's largest bound (a component
/// fixed at 0 is held to that).
pub(crate) fn control_scales(u: &ControlSet) -> Vec<f64> {
    let largest = control_rows(u)
        .iter()
        .fold(0.0_f64, |s, (_, h)| s.max(h.abs()));
    let floor = 1e-9 * largest;
    match u {
        ControlSet::Box { lower, upper } => lower
            .iter()
            .zip(upper)
            .map(|(lo, hi)| lo.abs().max(hi.abs()).max(floor))
            .collect(),
        ControlSet::Polytope(q) => vec![largest; q.dim()],
    }
}

/// Whether the control `u` lies in U within `tol` times each component's scale `scales`
/// ([`control_scales`]; a polytope's one scale for every row), as a process read back is held.
pub(crate) fn in_u(control: &ControlSet, scales: &[f64], u: &[f64], tol: f64) -> bool {
    match control {
        ControlSet::Box { lower, upper } => u
            .iter()
            .zip(lower.iter().zip(upper))
            .zip(scales)
            .all(|((v, (lo, hi)), s)| *v >= lo - tol * s && *v <= hi + tol * s),
        ControlSet::Polytope(_) => control.contains(u, tol * scales[0]),
    }
}

/// A process of (P) on `P` pieces, borrowed: durations `tau_i`, states `x^0..x^P`, controls
/// `u^i` and reaction rates `lambda^i` per face (the projection's multipliers over the piece's
/// duration). The rows' shapes are the caller's to have checked.
#[derive(Debug, Clone, Copy)]
pub struct ProcessRows<'a> {
    /// P_m or phase gait.
    pub kind: ProcessKind,
    /// `tau_i`.
    pub durations: &'a [f64],
    /// `x^k` (`P + 1` rows).
    pub x: &'a [Vec<f64>],
    /// `u^i` (`P` rows).
    pub u: &'a [Vec<f64>],
    /// `lambda^i` (`P` rows, one value per face of C).
    pub lambda: &'a [Vec<f64>],
}

/// The first condition of a process that fails ([`ProcessRows::fault`]), with its place
/// (indices 0-based).
#[derive(Debug, Clone, PartialEq)]
pub enum Fault {
    /// `x^P` differs from `x^0` by `gap` (largest component).
    NotPeriodic {
        /// `max |x^P - x^0|`.
        gap: f64,
    },
    /// `x^0` differs from the problem's initial state by `gap`.
    NotInitial {
        /// `max |x^0 - x(0)|`.
        gap: f64,
    },
    /// `x^k` lies outside face `face` of C by `by`.
    Outside {
        /// The knot.
        k: usize,
        /// The face most violated.
        face: usize,
        /// `<x*_face, x^k> - c_face`.
        by: f64,
    },
    /// `u^i` lies outside U.
    ControlOutside {
        /// The piece.
        i: usize,
    },
    /// The control's mean over the period is not zero where the problem asks it.
    Mean {
        /// `(1/T) int u`.
        mean: Vec<f64>,
    },
    /// A negative reaction rate.
    Negative {
        /// The piece.
        i: usize,
        /// The face.
        face: usize,
    },
    /// `x^(i+1)` does not follow from `x^i`, `u^i` and `lambda^i` by the piece's step.
    Step {
        /// The piece.
        i: usize,
        /// The largest component of the residual.
        residual: f64,
    },
    /// A reaction on a face that is not active where the flow rule needs it (at the step's
    /// end for P_m, at both ends of a phase).
    Inactive {
        /// The piece.
        i: usize,
        /// The face.
        face: usize,
    },
}

impl ProcessRows<'_> {
    /// The first condition of `p` the process breaks within the relative tolerance `tol`, in
    /// the order periodicity (or the initial state), states in C, controls in U and of zero
    /// mean, then piece by piece the reactions' sign, the step and the flow rule; `None` when
    /// it is a process of `p`. States are compared to `tol` times C's scale plus the rounding
    /// of the increments that made them ([`GeneralProblem::rounding`]), a step's residual also
    /// to `tol` times its largest term (`tau_i |g|` or a reaction `tau_i lambda_j`); controls
    /// to `tol` times each component's scale (a box's bound per component, U's largest offset
    /// for a polytope); a reaction's face
    /// must be active to the states' tolerance (the product with the reaction for a reaction
    /// below C's scale).
    pub fn fault(&self, p: &GeneralProblem, tol: f64) -> Option<Fault> {
        let steps = self.durations.len();
        let scale = p.c.scale();
        let allowed = tol * scale + p.rounding(self.durations, self.x, self.u);
        match &p.boundary {
            Boundary::Periodic => {
                let gap = max_diff(&self.x[steps], &self.x[0]);
                if gap > allowed {
                    return Some(Fault::NotPeriodic { gap });
                }
            }
            Boundary::Initial(x0) => {
                let gap = max_diff(&self.x[0], x0);
                if gap > tol * scale {
                    return Some(Fault::NotInitial { gap });
                }
            }
        }
        for (k, x) in self.x.iter().enumerate() {
            if let Some((face, by)) = p.c.violation(x, allowed) {
                return Some(Fault::Outside { k, face, by });
            }
        }
        self.control_fault(p, tol)
            .or_else(|| self.step_fault(p, tol, allowed))
    }

    /// The controls: in U, and of zero mean where the problem asks it, each component to `tol`
    /// times its own scale (`control_scales`).
    fn control_fault(&self, p: &GeneralProblem, tol: f64) -> Option<Fault> {
        let scales = control_scales(&p.control);
        let mut mean = vec![0.0; p.controls()];
        for (i, u) in self.u.iter().enumerate() {
            if !in_u(&p.control, &scales, u, tol) {
                return Some(Fault::ControlOutside { i });
            }
            for (m, v) in mean.iter_mut().zip(u) {
                *m += v * self.durations[i] / p.period;
            }
        }
        let off = mean.iter().zip(&scales).any(|(v, s)| v.abs() > tol * s);
        (p.zero_mean && off).then_some(Fault::Mean { mean })
    }

    /// Each piece: reactions non-negative, the state following from the previous one, the
    /// control and the reactions by the scheme (catching-up for P_m, the exact segment for a
    /// phase), and a reaction only on an active face (states to `allowed`).
    fn step_fault(&self, p: &GeneralProblem, tol: f64, allowed: f64) -> Option<Fault> {
        let (n, sigma) = (p.states(), p.c.faces());
        let scale = p.c.scale();
        let mut g = vec![0.0; n];
        for i in 0..self.durations.len() {
            let (lam, h) = (&self.lambda[i], self.durations[i]);
            if let Some(face) = lam.iter().position(|&l| h * l < -tol * scale) {
                return Some(Fault::Negative { i, face });
            }
            p.dynamics.eval(&self.x[i], &self.u[i], &mut g);
            let mut residual = 0.0_f64;
            for l in 0..n {
                let react: f64 = (0..sigma).map(|j| lam[j] * p.c.normals[j][l]).sum();
                let v = self.x[i][l] + h * (g[l] - react) - self.x[i + 1][l];
                residual = residual.max(v.abs());
            }
            // A residual relative to the largest term of the step too, `tau g` or a reaction's
            // `tau lambda_j` (unit normals): a piece that moves far beyond C's size (a long
            // phase, a rigid slide of a whole chain) carries its digits' error at that scale.
            let increment = h * g.iter().chain(lam).fold(0.0_f64, |m, v| m.max(v.abs()));
            if residual > allowed.max(tol * increment) {
                return Some(Fault::Step { i, residual });
            }
            for face in 0..sigma {
                let mut off = -p.c.slack(face, &self.x[i + 1]);
                if self.kind == ProcessKind::Phase {
                    off = off.max(-p.c.slack(face, &self.x[i]));
                }
                if h * lam[face] * off > allowed * (h * lam[face]).max(scale) {
                    return Some(Fault::Inactive { i, face });
                }
            }
        }
        None
    }
}

/// What a record of (P)'s process calls its fields, for [`Fault::in_words`]: a result file's
/// `states`, `controls`, `reactions` ([`FieldNames::record`], every method's since result
/// version 3), or the process's own `x`, `u`, `lambda` (theory §6, [`FieldNames::process`]),
/// each under the path `at` (such as `"result.json: solution"`).
#[derive(Debug, Clone, Copy)]
pub struct FieldNames<'a> {
    /// The path of the record; a field is named `{at}.{x}[k]`.
    pub at: &'a str,
    /// The states `x^k`.
    pub x: &'a str,
    /// The controls `u^i`.
    pub u: &'a str,
    /// The reaction rates `lambda^i`.
    pub lambda: &'a str,
}

impl<'a> FieldNames<'a> {
    /// The names of a result file's solution: `states`, `controls`, `reactions`.
    pub fn record(at: &'a str) -> Self {
        FieldNames {
            at,
            x: "states",
            u: "controls",
            lambda: "reactions",
        }
    }

    /// The names of the process's own fields: `x`, `u`, `lambda`.
    pub fn process(at: &'a str) -> Self {
        FieldNames {
            at,
            x: "x",
            u: "u",
            lambda: "lambda",
        }
    }
}

impl Fault {
    /// The fault of `rows` as an error naming the record's field (indices 0-based, as in the
    /// record's arrays; faces in the words 1-based, as C's faces are numbered).
    pub fn in_words(&self, rows: &ProcessRows, names: &FieldNames) -> Error {
        let FieldNames { at, x, u, lambda } = *names;
        let bad = |field: String, got: String, why: &str| {
            Error::invalid(format!("{at}.{field}"), got, why)
        };
        let steps = rows.durations.len();
        match self {
            Fault::NotPeriodic { gap } => bad(
                format!("{x}[{steps}]"),
                format!("{gap:e} from {x}[0]"),
                "not periodic: the process does not end where it began",
            ),
            Fault::NotInitial { gap } => bad(
                format!("{x}[0]"),
                format!("{gap:e} from problem.initial_state"),
                "must be the initial state",
            ),
            Fault::Outside { k, face, by } => bad(
                format!("{x}[{k}]"),
                format!("{by:e}"),
                &format!("outside face {}", face + 1),
            ),
            Fault::ControlOutside { i } => bad(
                format!("{u}[{i}]"),
                format!("{:?}", rows.u[*i]),
                "outside U",
            ),
            Fault::Mean { mean } => bad(u.into(), format!("mean {mean:?}"), "must have zero mean"),
            Fault::Negative { i, face } => bad(
                format!("{lambda}[{i}][{face}]"),
                rows.lambda[*i][*face].to_string(),
                "negative",
            ),
            Fault::Step { i, residual } => {
                let step = match rows.kind {
                    ProcessKind::Discrete { .. } => {
                        "the catching-up step x^(i+1) = x^i + h (g - sum lambda x*)"
                    }
                    ProcessKind::Phase => {
                        "the phase's segment x^(i+1) = x^i + tau_i (g - sum lambda x*)"
                    }
                };
                let s = at.rsplit(": ").next().unwrap_or(at);
                bad(
                    format!("{x}[{}]", i + 1),
                    format!("{residual:e}"),
                    &format!(
                        "does not follow from {s}.{x}[{i}], {s}.{u}[{i}] and {s}.{lambda}[{i}] \
                         by {step}"
                    ),
                )
            }
            Fault::Inactive { i, face } => {
                let ends = match rows.kind {
                    ProcessKind::Discrete { .. } => "which is not active at the step's end",
                    ProcessKind::Phase => "which is not active at both ends of the phase",
                };
                bad(
                    format!("{lambda}[{i}][{face}]"),
                    rows.lambda[*i][*face].to_string(),
                    &format!("a reaction on face {}, {ends}", face + 1),
                )
            }
        }
    }
}

/// `max_l |a_l - b_l|` (infinite when the lengths differ).
pub(crate) fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}
