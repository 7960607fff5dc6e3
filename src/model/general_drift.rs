//! The drift `A x` of the general problem (P) split by how a catching-up step treats it
//! (`crate::integrate::general`): the damping stepped implicitly, the rest explicitly, and the
//! limits of the explicit steps (forward Euler's stability, the spurious growth of a rotation,
//! the precision of a state held by a growing mode).

use super::general::Dynamics;

/// The largest `h * rate` accepted where a part of the drift is stepped explicitly (forward
/// Euler): [`DriftSplit::stiff_rate`] for the paper's explicit P_m, [`DriftSplit::skew_rate`]
/// for the simulator's semi-implicit step. At `h * rate <= 2` the factor `1 + h lambda` of a
/// decaying real mode `lambda in [-rate, 0]` stays in `[-1, 1]`: forward Euler's stability
/// limit (monotone up to `h * rate = 1`, a decaying oscillation between 1 and 2). Beyond it
/// the factor grows the mode each step and the explicit answer is wrong by orders of
/// magnitude (the state thrown between faces of C, each throw a large reaction), so the step
/// is refused, naming the grid (`steps_per_period`, `m`). (A rotating mode `i omega` is not
/// damped by forward Euler at any step; the bound keeps its gain per step at most
/// `sqrt(1 + (h omega)^2) <= sqrt(5)`, the consistency error that refinement removes.)
pub const EXPLICIT_STEP_LIMIT: f64 = 2.0;

/// The largest `h |S_+|_2` the simulator's semi-implicit step accepts: a growing mode is
/// stepped explicitly, by the factor `1 + h mu`, and a state held on a face by it is then
/// projected from `|v| ~ h mu |x|`, whose rounding (`1e-16 |v|`) would reach `1e-10` of C's
/// scale beyond this.
pub const GROWTH_STEP_LIMIT: f64 = 1e6;

/// `A` split by how a step of the catching-up scheme treats it: `A = S_- + S_+ + K` with
/// `S = (A + A^T)/2 = S_- + S_+` (its negative and positive semidefinite parts, from the
/// eigenvalues of `S`) and `K = (A - A^T)/2`.
#[derive(Debug, Clone, PartialEq)]
pub struct DriftSplit {
    /// `S_-` (`n x n`, symmetric negative semidefinite): the damping, stepped implicitly by
    /// the simulator (stable for any step).
    pub damping: Vec<Vec<f64>>,
    /// `A - S_-` (`= S_+ + K`), stepped explicitly by the simulator.
    pub rest: Vec<Vec<f64>>,
    /// `|K|_2`, the rate of the rotating part (the simulator's explicit limit).
    pub skew_rate: f64,
    /// `|S_+|_2`, the rate of the growing part (the simulator's precision limit
    /// [`GROWTH_STEP_LIMIT`]).
    pub growth_rate: f64,
    /// `|S_- + K|_2`, the rate of everything but the growing part `S_+` (the explicit
    /// scheme's limit: forward Euler resolves a growing real mode at any step, as `1 + h mu`
    /// with the projection onto C holding it, but not a decaying or rotating one).
    pub stiff_rate: f64,
}

impl DriftSplit {
    /// Whether `S_- = 0` (then the semi-implicit step is the explicit one).
    pub fn undamped(&self) -> bool {
        self.damping.iter().flatten().all(|v| *v == 0.0)
    }
}

/// The fewest steps `M` of a period `T` with `(T / M) * rate <= EXPLICIT_STEP_LIMIT`
/// (saturating; 1 for a zero rate).
pub fn min_steps(period: f64, rate: f64) -> f64 {
    (period * rate / EXPLICIT_STEP_LIMIT).ceil().max(1.0)
}

impl Dynamics {
    /// [`DriftSplit`] of `A`.
    pub fn split(&self) -> DriftSplit {
        let n = self.a.len();
        if self.is_state_independent() {
            return DriftSplit {
                damping: vec![vec![0.0; n]; n],
                rest: self.a.clone(),
                skew_rate: 0.0,
                growth_rate: 0.0,
                stiff_rate: 0.0,
            };
        }
        let a = nalgebra::DMatrix::from_fn(n, n, |i, k| self.a[i][k]);
        // Halves first: no overflow for entries near the largest float.
        let sym = &a * 0.5 + a.transpose() * 0.5;
        let skew = &a * 0.5 - a.transpose() * 0.5;
        let eig = sym.clone().symmetric_eigen();
        let neg = eig.eigenvalues.map(|l| l.min(0.0));
        let mut damping = &eig.eigenvectors
            * nalgebra::DMatrix::from_diagonal(&neg)
            * eig.eigenvectors.transpose();
        if neg.iter().all(|l| *l == 0.0) {
            damping.fill(0.0);
        } else {
            // Exactly symmetric.
            damping = &damping * 0.5 + damping.transpose() * 0.5;
        }
        let rest = &a - &damping;
        let norm2 = |m: &nalgebra::DMatrix<f64>| {
            if m.iter().all(|v| *v == 0.0) {
                0.0
            } else {
                // The Frobenius norm bounds the spectral norm where the decomposition fails.
                crate::linalg::singular_values(m).map_or_else(|| m.norm(), |s| s.max())
            }
        };
        let rows = |m: &nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
            (0..n).map(|i| m.row(i).iter().copied().collect()).collect()
        };
        DriftSplit {
            growth_rate: eig.eigenvalues.iter().fold(0.0_f64, |m, l| m.max(*l)),
            skew_rate: norm2(&skew),
            stiff_rate: norm2(&(&damping + &skew)),
            damping: rows(&damping),
            rest: rows(&rest),
        }
    }
}
