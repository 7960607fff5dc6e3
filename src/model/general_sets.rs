//! The sets and functions of the general problem (P) (`super::general`, theory §11): the
//! polyhedra C and U, the reward `f1` and the cost `f2`, with the checks of the reward's and the
//! cost's data. Below `super::general`, which assembles them into a problem.

use super::general_checks::{check_finite, check_matrix};
use crate::error::{Error, Result};
use serde::Serialize;

/// Most faces of C (and of a polytope U) a problem may have. The analysis decides redundancy
/// with at most one linear program of `sigma` rows per face (`crate::optimal::general::geometry`;
/// most faces need none), and that worst case (every face a duplicate) takes seconds at this
/// size; the vertex enumeration is capped separately (it is exponential in the dimension).
pub const MAX_FACES: usize = 1000;

/// A polyhedron `{x : <x*_j, x> <= c_j}` with unit normals (paper §2: the `x*_j` are unit
/// vectors; each given row `(x*_j, c_j)` is divided by `|x*_j|`, which leaves the set unchanged).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Polyhedron {
    /// Unit normals `x*_j`, one row per face.
    pub normals: Vec<Vec<f64>>,
    /// Offsets `c_j` (after scaling).
    pub offsets: Vec<f64>,
    /// The lengths `|x*_j|` of the rows as given (the scaling applied).
    pub row_norms: Vec<f64>,
}

impl Polyhedron {
    /// Checks and scales the rows. `field` prefixes the messages (e.g. `sweeping_process`, whose
    /// rows are `normals` and `offsets`).
    pub fn new(normals: Vec<Vec<f64>>, offsets: Vec<f64>, field: &str) -> Result<Self> {
        let (nf, of) = (format!("{field}.normals"), format!("{field}.offsets"));
        if normals.is_empty() {
            return Err(Error::invalid(&nf, "[]", "needs at least one face"));
        }
        if normals.len() > MAX_FACES {
            return Err(Error::invalid(
                &nf,
                format!("{} faces", normals.len()),
                format!("at most {MAX_FACES} faces are accepted (the analysis's limit)"),
            ));
        }
        let n = normals[0].len();
        if n == 0 {
            return Err(Error::invalid(
                format!("{nf}[1]"),
                "[]",
                "a normal needs at least one component",
            ));
        }
        if offsets.len() != normals.len() {
            return Err(Error::invalid(
                &of,
                format!("{} values", offsets.len()),
                format!("needs one offset per face ({})", normals.len()),
            ));
        }
        let mut scaled = Vec::with_capacity(normals.len());
        let mut cs = Vec::with_capacity(normals.len());
        let mut norms = Vec::with_capacity(normals.len());
        for (j, (row, &c)) in normals.iter().zip(&offsets).enumerate() {
            if row.len() != n {
                return Err(Error::invalid(
                    format!("{nf}[{}]", j + 1),
                    format!("{} components", row.len()),
                    format!("every normal needs the dimension of the first ({n})"),
                ));
            }
            check_finite(&format!("{nf}[{}]", j + 1), row)?;
            if !c.is_finite() {
                return Err(Error::invalid(
                    format!("{of}[{}]", j + 1),
                    c,
                    "must be finite",
                ));
            }
            let norm = length(row);
            if norm == 0.0 {
                return Err(Error::invalid(
                    format!("{nf}[{}]", j + 1),
                    format!("{row:?}"),
                    "a normal must be non-zero",
                ));
            }
            if !norm.is_finite() {
                return Err(Error::invalid(
                    format!("{nf}[{}]", j + 1),
                    format!("{row:?}"),
                    "its length overflows the floating-point range",
                ));
            }
            let unit: Vec<f64> = row.iter().map(|v| v / norm).collect();
            let offset = c / norm;
            if !offset.is_finite() {
                return Err(Error::invalid(
                    format!("{of}[{}]", j + 1),
                    c,
                    format!(
                        "divided by the length {norm:e} of normal {} it overflows the \
                         floating-point range (scale the row down)",
                        j + 1
                    ),
                ));
            }
            scaled.push(unit);
            cs.push(offset);
            norms.push(norm);
        }
        Ok(Polyhedron {
            normals: scaled,
            offsets: cs,
            row_norms: norms,
        })
    }

    /// The dimension `n` of the space.
    pub fn dim(&self) -> usize {
        self.normals[0].len()
    }

    /// The number of faces `sigma`.
    pub fn faces(&self) -> usize {
        self.normals.len()
    }

    /// `<x*_j, x> - c_j`, positive outside face `j`'s half-space.
    pub fn slack(&self, j: usize, x: &[f64]) -> f64 {
        dot(&self.normals[j], x) - self.offsets[j]
    }

    /// The most violated face and by how much (`None` inside C within `tol`).
    pub fn violation(&self, x: &[f64], tol: f64) -> Option<(usize, f64)> {
        (0..self.faces())
            .map(|j| (j, self.slack(j, x)))
            .filter(|&(_, s)| s > tol)
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// A length scale of C: the largest `|c_j|`, at least 1e-300 (tolerances are relative to it).
    pub fn scale(&self) -> f64 {
        self.offsets
            .iter()
            .fold(0.0_f64, |m, c| m.max(c.abs()))
            .max(1e-300)
    }

    /// The least singular value of the normals of `faces` (0-based), stacked as rows: how far
    /// those faces are from linear dependence. A reaction's multipliers on them are bounded by
    /// `|eta| / sigma_min` (the MILPs' big-M); 0 when the decomposition fails.
    pub fn least_singular_value(&self, faces: &[usize]) -> f64 {
        let a =
            nalgebra::DMatrix::from_fn(faces.len(), self.dim(), |i, k| self.normals[faces[i]][k]);
        // A decomposition that fails counts as dependent rows (0).
        crate::linalg::singular_values(&a)
            .map_or(0.0, |s| s.iter().copied().fold(f64::INFINITY, f64::min))
    }
}

/// The control set `U`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ControlSet {
    /// `lower <= u <= upper` componentwise.
    Box {
        /// Lower bounds.
        lower: Vec<f64>,
        /// Upper bounds.
        upper: Vec<f64>,
    },
    /// `{u : <G_k, u> <= h_k}`, rows scaled to unit length as for C.
    Polytope(Polyhedron),
}

impl ControlSet {
    /// The dimension of `u`.
    pub fn dim(&self) -> usize {
        match self {
            ControlSet::Box { lower, .. } => lower.len(),
            ControlSet::Polytope(p) => p.dim(),
        }
    }

    /// Whether `u` lies in U within `tol` (absolute, on the unit rows or the bounds).
    pub fn contains(&self, u: &[f64], tol: f64) -> bool {
        match self {
            ControlSet::Box { lower, upper } => u
                .iter()
                .zip(lower.iter().zip(upper))
                .all(|(v, (lo, hi))| *v >= lo - tol && *v <= hi + tol),
            ControlSet::Polytope(p) => p.violation(u, tol).is_none(),
        }
    }
}

/// The reward `f1` of the reaction `eta in N_C(x)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", content = "weights", rename_all = "snake_case")]
pub enum Reward {
    /// `f1(eta) = sum_j w_j lambda_j` with `eta = sum_j lambda_j x*_j`, `lambda >= 0` supported on
    /// the active faces: well defined when the active normals are independent everywhere (checked
    /// at the vertices by the geometry). The weights are those of the unit normals: a row given
    /// as `s x*_j` has the same weight (the reaction's multiplier of the unit row).
    FaceWeights(Vec<f64>),
    /// `f1(eta) = <q, eta>`.
    ReactionWeights(Vec<f64>),
}

impl Reward {
    /// `f1` of the reaction with multipliers `lambda` (one per face of unit normals `normals`).
    pub fn eval(&self, normals: &[Vec<f64>], lambda: &[f64]) -> f64 {
        match self {
            Reward::FaceWeights(w) => dot(w, lambda),
            Reward::ReactionWeights(q) => lambda
                .iter()
                .zip(normals)
                .map(|(l, nj)| l * dot(q, nj))
                .sum(),
        }
    }
}

/// The cost `f2(u)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum GeneralCost {
    /// `f2 = 0`.
    None,
    /// `f2(u) = (c/2) |u|^2`, `c >= 0`.
    Quadratic {
        /// `c`.
        weight: f64,
    },
    /// `f2(u) = (1/2) u^T R u`, `R` symmetric positive semidefinite.
    Matrix {
        /// `R`, one row per component.
        matrix: Vec<Vec<f64>>,
    },
}

impl GeneralCost {
    /// `f2(u)`.
    pub fn eval(&self, u: &[f64]) -> f64 {
        match self {
            GeneralCost::None => 0.0,
            GeneralCost::Quadratic { weight } => 0.5 * weight * dot(u, u),
            GeneralCost::Matrix { matrix } => {
                0.5 * matrix
                    .iter()
                    .zip(u)
                    .map(|(row, ui)| ui * dot(row, u))
                    .sum::<f64>()
            }
        }
    }
}

/// Refuses weights whose size alone takes `J` out of the floating-point range: the sum of
/// `|w_j|` (or `|q|`) times the period `T` (a reaction rate of 1 on every face over the
/// period), and for a box U the cost weight times the largest `|u|^2` times `T` (the largest
/// `int f2`). Where no such bound can be read off the data (the reactions' size, a polytope
/// U), the computed numbers are checked instead (`crate::integrate::general`).
pub(super) fn check_scales(
    reward: &Reward,
    cost: &GeneralCost,
    u: &ControlSet,
    period: f64,
) -> Result<()> {
    let (field, w) = match reward {
        Reward::FaceWeights(w) => ("objective.face_weights", w),
        Reward::ReactionWeights(q) => ("objective.reaction_weights", q),
    };
    let total = w.iter().map(|v| v.abs()).sum::<f64>() * period;
    if !total.is_finite() {
        return Err(Error::invalid(
            field,
            format!("{w:?}"),
            format!(
                "the sum of their sizes times the period ({period}) overflows the \
                 floating-point range, so J could not be represented; scale f1 down"
            ),
        ));
    }
    if let ControlSet::Box { lower, upper } = u {
        let u2: f64 = lower
            .iter()
            .zip(upper)
            .map(|(lo, hi)| lo.abs().max(hi.abs()).powi(2))
            .sum();
        let (field, size) = match cost {
            GeneralCost::None => return Ok(()),
            GeneralCost::Quadratic { weight } => ("objective.cost.weight", weight.abs()),
            GeneralCost::Matrix { matrix } => (
                "objective.cost.matrix",
                matrix.iter().flatten().map(|v| v.abs()).sum::<f64>(),
            ),
        };
        if !(0.5 * size * u2 * period).is_finite() {
            return Err(Error::invalid(
                field,
                size,
                format!(
                    "times the largest |u|^2 of U ({u2:e}) and the period it overflows the \
                     floating-point range, so int f2 could not be represented; scale f2 down"
                ),
            ));
        }
    }
    Ok(())
}

pub(super) fn check_cost(cost: &GeneralCost, m: usize) -> Result<()> {
    match cost {
        GeneralCost::None => Ok(()),
        GeneralCost::Quadratic { weight } => {
            if weight.is_finite() && *weight >= 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(
                    "objective.cost.weight",
                    weight,
                    "must be non-negative and finite",
                ))
            }
        }
        GeneralCost::Matrix { matrix } => {
            check_matrix("objective.cost.matrix", matrix, m, Some(m), "the controls'")?;
            for i in 0..m {
                for k in 0..i {
                    let (a, b) = (matrix[i][k], matrix[k][i]);
                    if (a - b).abs() > 1e-12 * a.abs().max(b.abs()) {
                        return Err(Error::invalid(
                            format!("objective.cost.matrix[{}][{}]", i + 1, k + 1),
                            a,
                            format!("R must be symmetric (entry [{}][{}] is {b})", k + 1, i + 1),
                        ));
                    }
                }
            }
            let r = nalgebra::DMatrix::from_fn(m, m, |i, k| matrix[i][k]);
            let eig = crate::linalg::symmetric_eigen(r)
                .ok_or_else(|| {
                    Error::invalid(
                        "objective.cost.matrix",
                        "R",
                        "its eigenvalues could not be computed (the decomposition did not \
                         converge)",
                    )
                })?
                .eigenvalues;
            let scale = eig.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let min = eig.iter().copied().fold(f64::INFINITY, f64::min);
            if min < -1e-12 * scale {
                return Err(Error::invalid(
                    "objective.cost.matrix",
                    format!("smallest eigenvalue {min:e}"),
                    "R must be positive semidefinite (f2 convex)",
                ));
            }
            Ok(())
        }
    }
}

/// `<a, b>`.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The Euclidean length of `v`, without overflow or underflow in the squares: computed on
/// `v / max_i |v_i|`, so that a row `[1e308]` has length 1e308 and `[1e-300]` length 1e-300
/// (both are then scaled to the unit normal `[1]`, with the offset divided alike).
pub(crate) fn length(v: &[f64]) -> f64 {
    let top = v.iter().fold(0.0_f64, |t, x| t.max(x.abs()));
    if top == 0.0 || !top.is_finite() {
        return top;
    }
    top * v.iter().map(|x| (x / top) * (x / top)).sum::<f64>().sqrt()
}
