//! The work bound: over a period the friction dissipates exactly the work the actuators put in,
//! and that work is bounded by the force ranges of C and the rate bounds (docs: guide, "The
//! upper bound", the work bound). Closed form, any `N`; far from the optimum on long chains
//! (measured there), because the force ranges of C grow with the chain.
//!
//! # The argument
//!
//! With `E = sum_l x_l^2 / (2 k_l)` and `x_l' = u_l - k_l z_l'`,
//! `E' = sum_l x_l L_l' - sum_l x_l z_l'`, and `sum_l x_l z_l' = sum_b F_b X_b'` (sum by parts,
//! `x_0 = x_N = 0`), which the flow rule makes the dissipation
//! `sum_b (mu_b^+ (X_b')^+ + mu_b^- (X_b')^-)`. Over a period `E` returns, so the dissipation
//! equals the work `sum_l int x_l dL_l`. For each link, `int x_l dL_l = int (x_l - m_l) dL_l`
//! with `m_l` the middle of the range `[lo_l, hi_l]` of `x_l` over C, so it is at most
//! `(w_l / 2) TV(L_l) <= w_l a_l T / (2 k_l)`, `w_l = hi_l - lo_l`. Every block moves `d` per
//! period (the chain comes back to its shape), forward at least `d` when `d > 0`, so it
//! dissipates at least `mu_b^+ d`. Hence `d sum_b mu_b^+ <= T sum_l w_l a_l / (2 k_l)`, and
//! `J <= d` (the cost is non-negative).

use crate::model::Crawler;
use crate::optimal::GaitProblem;

/// The work bound on `J` over every `T`-periodic gait (module docs):
/// `T sum_l w_l a_l / (2 k_l) / sum_b mu_b^+`, `w_l` the width of link `l`'s force range over
/// C.
pub fn work_bound(crawler: &Crawler, problem: &GaitProblem) -> f64 {
    crate::optimal::work_limit(crawler, problem)
}
