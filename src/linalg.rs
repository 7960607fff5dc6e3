//! Dense singular value decompositions with bounded effort. nalgebra's `svd` and
//! `singular_values` iterate until convergence with no limit; on a matrix whose entries span
//! many orders of magnitude (measured: the phase polish's KKT matrix of a quadratic cost of
//! 1e-6 beside controls of 800, where `optimize --time-limit 5` ran on past 120 s) or that is
//! not finite, they can iterate for ever, out of reach of any deadline. Every SVD and rank of
//! the library, and the symmetric eigen-decompositions of the solvers' paths (the cost's
//! factor in the phase polish, the cost checks), go through here: non-finite input is refused
//! and the iterations are capped, and the caller decides what a failed decomposition means.
//! (The split of a drift `A` into its damping keeps nalgebra's own: it runs once on the
//! user's finite matrix, before any job.)

use nalgebra::{DMatrix, DVector, Dyn, SymmetricEigen, SVD};

/// The cap on the total iterations of one decomposition of an `r x c` matrix: far above what
/// a convergent one takes (a few per singular value).
fn max_iterations(r: usize, c: usize) -> usize {
    1000 + 100 * r.max(c)
}

/// The SVD of `a` (with `U` and/or `V^T` as asked), or `None` when `a` has a non-finite entry
/// or the iteration does not converge within its cap.
pub fn svd(a: DMatrix<f64>, u: bool, v: bool) -> Option<SVD<f64, Dyn, Dyn>> {
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let cap = max_iterations(a.nrows(), a.ncols());
    a.try_svd(u, v, f64::EPSILON, cap)
}

/// The numerical rank of `a` (singular values above `eps`), or `None` as for [`svd`].
pub fn rank(a: &DMatrix<f64>, eps: f64) -> Option<usize> {
    svd(a.clone(), false, false).map(|s| s.rank(eps))
}

/// The eigen-decomposition of a symmetric `a`, or `None` when `a` has a non-finite entry or
/// the iteration does not converge within its cap (nalgebra's `symmetric_eigen` has none).
pub fn symmetric_eigen(a: DMatrix<f64>) -> Option<SymmetricEigen<f64, Dyn>> {
    if a.iter().any(|x| !x.is_finite()) {
        return None;
    }
    let cap = max_iterations(a.nrows(), a.ncols());
    a.try_symmetric_eigen(f64::EPSILON, cap)
}

/// The singular values of `a` (unsorted as nalgebra returns them), or `None` as for [`svd`].
pub fn singular_values(a: &DMatrix<f64>) -> Option<DVector<f64>> {
    svd(a.clone(), false, false).map(|s| s.singular_values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decomposes_and_refuses_non_finite_input() {
        let a = DMatrix::from_row_slice(2, 2, &[3.0, 0.0, 0.0, 4.0]);
        let mut s: Vec<f64> = singular_values(&a).unwrap().iter().copied().collect();
        s.sort_by(f64::total_cmp);
        assert_eq!(s, vec![3.0, 4.0]);
        let b = DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0]);
        assert!(svd(b, true, true).is_none());
    }
}
