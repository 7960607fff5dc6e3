//! The checks of a general problem's data (`super::general`): finite entries, consistent
//! lengths and matrix shapes, a cost that is convex, and weights whose size keeps `J` within
//! the floating-point range; each error names the file's field.

use super::general::{ControlSet, GeneralCost, Reward};
use crate::error::{Error, Result};

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
            let eig = r.symmetric_eigenvalues();
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

pub(super) fn rename(e: Error, from: &str, to: &str) -> Error {
    match e {
        Error::InvalidParameter {
            field,
            value,
            reason,
        } => Error::InvalidParameter {
            field: field.replacen(from, to, 1),
            value,
            reason,
        },
        other => other,
    }
}

pub(super) fn check_len(field: &str, v: &[f64], len: usize, what: &str) -> Result<()> {
    if v.len() == len {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            format!("{} values", v.len()),
            format!("needs one value per {what} ({len})"),
        ))
    }
}

pub(super) fn check_finite(field: &str, v: &[f64]) -> Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::invalid(
            format!("{field}[{}]", i + 1),
            v[i],
            "must be finite",
        )),
    }
}

/// A `rows x cols` matrix of finite entries (`cols = None`: as the first row).
pub(super) fn check_matrix(
    field: &str,
    m: &[Vec<f64>],
    rows: usize,
    cols: Option<usize>,
    cols_what: &str,
) -> Result<()> {
    if m.len() != rows {
        return Err(Error::invalid(
            field,
            format!("{} rows", m.len()),
            format!("needs {rows} rows"),
        ));
    }
    let cols = cols.unwrap_or_else(|| m.first().map_or(0, Vec::len));
    for (i, row) in m.iter().enumerate() {
        let f = format!("{field}[{}]", i + 1);
        if row.len() != cols {
            return Err(Error::invalid(
                &f,
                format!("{} values", row.len()),
                format!("needs {cols} columns ({cols_what} dimension)"),
            ));
        }
        check_finite(&f, row)?;
    }
    Ok(())
}
