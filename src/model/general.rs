//! The general problem (P) of the paper's §2 (theory §11): a sweeping process
//! `x' in -N_C(x) + g(x, u)` in a polyhedron `C = {x : <x*_j, x> <= c_j, j = 1..sigma}`, affine
//! dynamics `g(x, u) = A x + B u + b`, controls in a box or a polytope `U` (with zero mean over a
//! period when imposed), the reward `f1` of the reaction `eta = g - x'` and the cost `f2(u)`.
//!
//! This module holds the data and the checks that need no solver: dimensions, finiteness, rows
//! scaled to unit normals, `U` non-empty with `0` in its interior under the zero-mean
//! constraint, a positive semidefinite cost matrix. The checks that need linear programs (the
//! interior of C, redundant faces, boundedness, vertices and the face weights' well-posedness)
//! are [`crate::optimal::general::geometry`]'s; `crate::api::general_problem` runs both.
//!
//! Indices are 0-based here; every message and output numbers faces, components and vertices
//! from 1.

use crate::error::{Error, Result};
use serde::Serialize;

use super::general_checks::{check_finite, check_len, check_matrix, rename};
pub use super::general_drift::{min_steps, DriftSplit, EXPLICIT_STEP_LIMIT, GROWTH_STEP_LIMIT};
pub(crate) use super::general_sets::dot;
use super::general_sets::{check_cost, check_scales};
pub use super::general_sets::{ControlSet, GeneralCost, Polyhedron, Reward, MAX_FACES};

/// The affine dynamics `g(x, u) = A x + B u + b`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Dynamics {
    /// `A` (`n x n`; all zero when omitted).
    pub a: Vec<Vec<f64>>,
    /// `B` (`n x m`).
    pub b: Vec<Vec<f64>>,
    /// `b` (`n`; zero when omitted).
    pub drift: Vec<f64>,
}

impl Dynamics {
    /// `g(x, u)` into `out`.
    pub fn eval(&self, x: &[f64], u: &[f64], out: &mut [f64]) {
        for i in 0..out.len() {
            out[i] = dot(&self.a[i], x) + dot(&self.b[i], u) + self.drift[i];
        }
    }

    /// Whether `A = 0` (the motion is then piecewise linear under piecewise-constant `u`).
    pub fn is_state_independent(&self) -> bool {
        self.a.iter().all(|r| r.iter().all(|v| *v == 0.0))
    }
}

/// The end conditions of the horizon `[0, T]`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", content = "state", rename_all = "snake_case")]
pub enum Boundary {
    /// `x(0) = x(T)` (the paper's (P)).
    Periodic,
    /// A Cauchy problem from the given `x(0)` (in C: checked by the geometry's tolerance).
    Initial(Vec<f64>),
}

/// The general problem (P) (theory §11), checked as far as no linear program is needed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralProblem {
    /// `C`.
    pub c: Polyhedron,
    /// `g`.
    pub dynamics: Dynamics,
    /// `U`.
    pub control: ControlSet,
    /// `int_0^T u dt = 0` imposed.
    pub zero_mean: bool,
    /// `f1`.
    pub reward: Reward,
    /// `f2`.
    pub cost: GeneralCost,
    /// `T`.
    pub period: f64,
    /// Periodic or Cauchy.
    pub boundary: Boundary,
}

/// The raw pieces of a [`GeneralProblem`] as a file or a caller gives them (rows not yet
/// scaled); [`GeneralProblem::new`] checks them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GeneralParts {
    /// Rows `x*_j`.
    pub normals: Vec<Vec<f64>>,
    /// `c_j`.
    pub offsets: Vec<f64>,
    /// `A` (`None`: 0).
    pub a: Option<Vec<Vec<f64>>>,
    /// `B`.
    pub b: Vec<Vec<f64>>,
    /// `b` (`None`: 0).
    pub drift: Option<Vec<f64>>,
    /// Box bounds of U.
    pub lower: Option<Vec<f64>>,
    /// Box bounds of U.
    pub upper: Option<Vec<f64>>,
    /// Polytope U: rows `G_k`.
    pub g: Option<Vec<Vec<f64>>>,
    /// Polytope U: `h_k`.
    pub h: Option<Vec<f64>>,
    /// Zero-mean constraint.
    pub zero_mean: bool,
    /// `f1` as face weights.
    pub face_weights: Option<Vec<f64>>,
    /// `f1` as `<q, eta>`.
    pub reaction_weights: Option<Vec<f64>>,
    /// `f2`.
    pub cost: Option<GeneralCost>,
    /// `T`.
    pub period: f64,
    /// `x(0) = x(T)`.
    pub periodic: bool,
    /// `x(0)` of a Cauchy problem.
    pub initial_state: Option<Vec<f64>>,
}

impl GeneralProblem {
    /// The floor of `J`'s scale in the problem's units: the problem's own scale of `J`, the
    /// largest face weight times C's scale (C's scale where no face has a weight), where it is
    /// below 1, else 1. Both MILPs' outer approximations stop when the bound is
    /// within `optimal::milp::OA_TOL` of `J` relative to the larger of `|J|` and this, and every
    /// gap is stated over it (`optimal::Certificate::gap_of`). An absolute `1e-6` had P_3 of a
    /// problem of C's scale `1e-6` stop `1.5e-3` below its bound as `optimal`; the floor is
    /// never above 1, so no stop is looser than that rule's (whose gap a reader holds a phase
    /// claim to, `optimal::consistency::PHASE_CLAIM_GAP`).
    pub fn j_floor(&self) -> f64 {
        let s = self.j_scale();
        if s > 0.0 { s } else { self.c.scale() }.min(1.0)
    }

    /// `J`'s scale: the largest face weight times C's scale (`J = int sum_f w_f lambda_f dt`,
    /// the reactions integrated to lengths of C); 0 where no face has a weight.
    pub fn j_scale(&self) -> f64 {
        let w = self
            .face_weights()
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        w * self.c.scale()
    }

    /// The coefficient `w_f` of `lambda_f` in `f1`, per face (`<q, x*_f>` for reaction
    /// weights).
    pub fn face_weights(&self) -> Vec<f64> {
        match &self.reward {
            Reward::FaceWeights(w) => w.clone(),
            Reward::ReactionWeights(q) => self.c.normals.iter().map(|n| dot(q, n)).collect(),
        }
    }

    /// The rounding a computed state of a process can carry: `1e3` units in the last place of
    /// the largest change a piece makes to the state, `max_i tau_i |g(x_i, u_i)|_inf` over
    /// pieces of durations `tau_i` from states `x_i` under controls `u_i` (a state is a sum of
    /// such increments less the reactions). It can be far above a tolerance relative to C
    /// (controls of 1000 over a period of 300 in a C of size 1: states off by 2e-10, where
    /// `1e-7` of a C of size `1e-4` is `1e-11`), so checks of computed states allow their
    /// tolerance relative to C plus this, and nothing more (a state moved by a fraction of C is
    /// still refused).
    pub fn rounding(&self, durations: &[f64], x: &[Vec<f64>], u: &[Vec<f64>]) -> f64 {
        let mut g = vec![0.0; self.states()];
        durations
            .iter()
            .zip(x)
            .zip(u)
            .map(|((tau, x), u)| {
                self.dynamics.eval(x, u, &mut g);
                tau * g.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
            })
            .fold(0.0_f64, f64::max)
            * 1e3
            * f64::EPSILON
    }

    /// Checks the parts (every message names the file's field) and scales the rows of C and of
    /// a polytope U to unit normals.
    pub fn new(p: GeneralParts) -> Result<Self> {
        let c = Polyhedron::new(p.normals, p.offsets, "sweeping_process")?;
        let n = c.dim();
        let a = match p.a {
            None => vec![vec![0.0; n]; n],
            Some(a) => {
                check_matrix("dynamics.A", &a, n, Some(n), "the state's")?;
                a
            }
        };
        if p.b.is_empty() {
            return Err(Error::invalid(
                "dynamics.B",
                "[]",
                format!("needs one row per state component ({n})"),
            ));
        }
        let m = p.b[0].len();
        if m == 0 {
            return Err(Error::invalid(
                "dynamics.B[1]",
                "[]",
                "needs at least one control",
            ));
        }
        check_matrix("dynamics.B", &p.b, n, Some(m), "the first row's")?;
        let drift = match p.drift {
            None => vec![0.0; n],
            Some(d) => {
                check_len("dynamics.b", &d, n, "state component")?;
                check_finite("dynamics.b", &d)?;
                d
            }
        };
        let control = control_set([p.lower, p.upper], (p.g, p.h), m, p.zero_mean)?;
        let reward = reward_of(p.face_weights, p.reaction_weights, c.faces(), n)?;
        let cost = p.cost.unwrap_or(GeneralCost::None);
        check_cost(&cost, m)?;
        if !(p.period.is_finite() && p.period > 0.0) {
            return Err(Error::invalid(
                "problem.period",
                p.period,
                "must be positive and finite",
            ));
        }
        check_scales(&reward, &cost, &control, p.period)?;
        let boundary = boundary_of(p.periodic, p.initial_state, &c)?;
        Ok(GeneralProblem {
            c,
            dynamics: Dynamics { a, b: p.b, drift },
            control,
            zero_mean: p.zero_mean,
            reward,
            cost,
            period: p.period,
            boundary,
        })
    }

    /// The state dimension `n`.
    pub fn states(&self) -> usize {
        self.c.dim()
    }

    /// The control dimension `m`.
    pub fn controls(&self) -> usize {
        self.control.dim()
    }
}

/// The control set U of `p` (`m` controls): a box (`lower`, `upper`) or a polytope (`G`, `h`),
/// each with 0 in its interior where the controls have zero mean.
fn control_set(
    [lower, upper]: [Option<Vec<f64>>; 2],
    (g, h): (Option<Vec<Vec<f64>>>, Option<Vec<f64>>),
    m: usize,
    zero_mean: bool,
) -> Result<ControlSet> {
    match (lower, upper, g, h) {
        (Some(lower), Some(upper), None, None) => {
            check_len("control.lower", &lower, m, "control (columns of B)")?;
            check_len("control.upper", &upper, m, "control (columns of B)")?;
            check_finite("control.lower", &lower)?;
            check_finite("control.upper", &upper)?;
            for i in 0..m {
                let field = format!("control.upper[{}]", i + 1);
                if upper[i] < lower[i] {
                    return Err(Error::invalid(
                        field,
                        upper[i],
                        format!("must be at least control.lower[{}]", i + 1),
                    ));
                }
                if zero_mean && !(lower[i] < 0.0 && 0.0 < upper[i]) {
                    return Err(Error::invalid(
                        format!("control.lower[{}], control.upper[{}]", i + 1, i + 1),
                        format!("[{}, {}]", lower[i], upper[i]),
                        "zero_mean needs 0 in the interior of U (lower < 0 < upper)",
                    ));
                }
            }
            Ok(ControlSet::Box { lower, upper })
        }
        (None, None, Some(g), Some(h)) => {
            let u = Polyhedron::new(g, h, "control")
                .map_err(|e| rename(e, "control.normals", "control.G"))
                .map_err(|e| rename(e, "control.offsets", "control.h"))?;
            if u.dim() != m {
                return Err(Error::invalid(
                    "control.G",
                    format!("{} columns", u.dim()),
                    format!("needs one column per control (columns of B: {m})"),
                ));
            }
            if zero_mean {
                if let Some(k) = (0..u.faces()).find(|&k| u.offsets[k] <= 0.0) {
                    return Err(Error::invalid(
                        format!("control.h[{}]", k + 1),
                        u.offsets[k] * u.row_norms[k],
                        "zero_mean needs 0 in the interior of U (every h_k > 0)",
                    ));
                }
            }
            Ok(ControlSet::Polytope(u))
        }
        (None, None, None, None) => Err(Error::invalid(
            "control",
            "nothing",
            "needs a box (lower, upper) or a polytope (G, h)",
        )),
        _ => Err(Error::invalid(
            "control",
            "a mixture",
            "give either lower and upper (a box) or G and h (a polytope), both of a pair",
        )),
    }
}

/// The reward f1 of `p`: face weights (one per face of C, `faces`) or reaction weights (one per
/// state component, `n`), exactly one of them.
fn reward_of(
    face_weights: Option<Vec<f64>>,
    reaction_weights: Option<Vec<f64>>,
    faces: usize,
    n: usize,
) -> Result<Reward> {
    match (face_weights, reaction_weights) {
        (Some(w), None) => {
            check_len("objective.face_weights", &w, faces, "face")?;
            check_finite("objective.face_weights", &w)?;
            Ok(Reward::FaceWeights(w))
        }
        (None, Some(q)) => {
            check_len("objective.reaction_weights", &q, n, "state component")?;
            check_finite("objective.reaction_weights", &q)?;
            Ok(Reward::ReactionWeights(q))
        }
        (None, None) => Err(Error::invalid(
            "objective",
            "nothing",
            "needs face_weights or reaction_weights (f1)",
        )),
        (Some(_), Some(_)) => Err(Error::invalid(
            "objective",
            "face_weights and reaction_weights",
            "give one form of f1, not both",
        )),
    }
}

/// The boundary condition of `p`: periodic, or an initial state in `c`, exactly one of them.
fn boundary_of(
    periodic: bool,
    initial_state: Option<Vec<f64>>,
    c: &Polyhedron,
) -> Result<Boundary> {
    let n = c.dim();
    match (periodic, initial_state) {
        (true, None) => Ok(Boundary::Periodic),
        (false, Some(x0)) => {
            check_len("problem.initial_state", &x0, n, "state component")?;
            check_finite("problem.initial_state", &x0)?;
            if let Some((j, s)) = c.violation(&x0, 1e-9 * c.scale()) {
                return Err(Error::Inadmissible {
                    what: "problem.initial_state".into(),
                    detail: format!("face {} is exceeded by {s:e}", j + 1),
                });
            }
            Ok(Boundary::Initial(x0))
        }
        (true, Some(_)) => Err(Error::invalid(
            "problem.initial_state",
            "a state",
            "a periodic problem has no initial state (set periodic = false)",
        )),
        (false, None) => Err(Error::invalid(
            "problem.initial_state",
            "nothing",
            "a problem that is not periodic needs x(0)",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_link() -> GeneralParts {
        GeneralParts {
            normals: vec![vec![2.0], vec![-1.0]],
            offsets: vec![2.0, 1.0],
            b: vec![vec![1.0]],
            lower: Some(vec![-1.0]),
            upper: Some(vec![1.0]),
            zero_mean: true,
            face_weights: Some(vec![0.5, 0.5]),
            period: 10.0,
            periodic: true,
            ..Default::default()
        }
    }

    #[test]
    fn rows_are_scaled_to_unit_normals() {
        let p = GeneralProblem::new(one_link()).unwrap();
        assert_eq!(p.c.normals, vec![vec![1.0], vec![-1.0]]);
        assert_eq!(p.c.offsets, vec![1.0, 1.0]);
        assert_eq!(p.c.row_norms, vec![2.0, 1.0]);
        assert!(p.dynamics.is_state_independent());
        assert_eq!(p.dynamics.drift, vec![0.0]);
    }

    #[test]
    fn every_check_names_its_field() {
        type Edit = Box<dyn Fn(&mut GeneralParts)>;
        let cases: Vec<(Edit, &str)> = vec![
            (
                Box::new(|p| p.offsets.push(1.0)),
                "sweeping_process.offsets",
            ),
            (
                Box::new(|p| p.normals[1] = vec![0.0]),
                "sweeping_process.normals[2]",
            ),
            (
                Box::new(|p| p.normals[0] = vec![f64::NAN]),
                "sweeping_process.normals[1][1]",
            ),
            (
                Box::new(|p| p.offsets[1] = f64::INFINITY),
                "sweeping_process.offsets[2]",
            ),
            (
                Box::new(|p| p.a = Some(vec![vec![1.0, 2.0]])),
                "dynamics.A[1]",
            ),
            (Box::new(|p| p.b = vec![]), "dynamics.B"),
            (Box::new(|p| p.drift = Some(vec![1.0, 2.0])), "dynamics.b"),
            (Box::new(|p| p.lower = Some(vec![0.5])), "control.lower[1]"),
            (Box::new(|p| p.upper = Some(vec![-2.0])), "control.upper[1]"),
            (Box::new(|p| p.upper = None), "control"),
            (
                Box::new(|p| {
                    (p.lower, p.upper) = (None, None);
                    (p.g, p.h) = (Some(vec![vec![1.0], vec![-1.0]]), Some(vec![1.0, 0.0]));
                }),
                "control.h[2]",
            ),
            (
                Box::new(|p| p.face_weights = Some(vec![1.0])),
                "objective.face_weights",
            ),
            (
                Box::new(|p| p.reaction_weights = Some(vec![1.0])),
                "objective",
            ),
            (
                Box::new(|p| p.cost = Some(GeneralCost::Quadratic { weight: -1.0 })),
                "objective.cost.weight",
            ),
            (
                Box::new(|p| {
                    p.cost = Some(GeneralCost::Matrix {
                        matrix: vec![vec![-1.0]],
                    })
                }),
                "objective.cost.matrix",
            ),
            (Box::new(|p| p.period = 0.0), "problem.period"),
            (
                Box::new(|p| p.initial_state = Some(vec![0.0])),
                "problem.initial_state",
            ),
            (
                Box::new(|p| {
                    p.periodic = false;
                    p.initial_state = Some(vec![3.0]);
                }),
                "problem.initial_state",
            ),
        ];
        for (edit, field) in cases {
            let mut p = one_link();
            edit(&mut p);
            let e = GeneralProblem::new(p).unwrap_err().to_string();
            assert!(e.starts_with(field), "{field}: {e}");
        }
    }

    #[test]
    fn costs_and_rewards_evaluate() {
        let r = GeneralCost::Matrix {
            matrix: vec![vec![2.0, 1.0], vec![1.0, 2.0]],
        };
        assert_eq!(r.eval(&[1.0, -1.0]), 1.0);
        assert_eq!(
            GeneralCost::Quadratic { weight: 4.0 }.eval(&[1.0, 1.0]),
            4.0
        );
        let normals = vec![vec![1.0, 0.0], vec![0.0, 1.0]];
        assert_eq!(
            Reward::ReactionWeights(vec![2.0, 3.0]).eval(&normals, &[1.0, 1.0]),
            5.0
        );
        assert_eq!(
            Reward::FaceWeights(vec![0.5, -1.0]).eval(&normals, &[2.0, 1.0]),
            0.0
        );
    }
}
