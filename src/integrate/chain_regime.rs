//! The periodic regime of a general problem that is a crawler's chain
//! ([`GeneralProblem::as_chain`]), searched by the crawler's own simulator: its exact method on
//! the O(N) chain kernels with the Newton-Krylov search (`super::periodic`), where the general
//! exact simulator ([`super::general_exact`]) iterates the period map plainly through `O(N^2)`
//! transient periods of a long chain (50 blocks: 3782 periods).
//!
//! The same holds for the catching-up scheme: the crawler's step increment `K (L(t_(i+1)) -
//! L(t_i))` is `int u dt` over the step, the general scheme's `h B u^i` in the crawler's
//! variables, so both iterate the same period map (to rounding) and the crawler's Newton
//! steps replace the general scheme's plain iteration.
//!
//! The control `u` of (P) is the crawler's `K L'` (`model::general_crawler`: `x' in u - K
//! N_C(x)`), so a piecewise-constant `u` is the piecewise-linear actuation with
//! `L_l(t_(k+1)) = L_l(t_k) + u_(k,l) (t_(k+1) - t_k) / k_l`, periodic when `u` has zero mean;
//! the crawler's state `x` is `K^(1/2) x~`. The state found is only a start: the caller plays
//! the period from it with the general simulator, which checks that it repeats and records the
//! period in the problem's own terms, so no number of the answer comes from the crawler's
//! kernels.

use super::general::{ControlInput, InputKind};
use super::periodic::{simulate, SimOptions};
use super::Actuation;
use crate::error::{Error, Result};
use crate::model::general::{Boundary, GeneralProblem};
use crate::model::ChainView;

/// Periods the general simulator is given to confirm, from the crawler's state, that the regime
/// repeats (one or two suffice at the default tolerance); beyond them the state is not taken.
pub const REPLAY_PERIODS: usize = 20;

/// What the crawler's search found.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainRegime {
    /// A state of the periodic orbit at `t = 0`, in the problem's variables `x~`.
    pub state: Vec<f64>,
    /// Periods the crawler's simulator integrated (its transient and Newton steps' periods).
    pub periods: usize,
}

/// The periodic regime of `p` under `input` from the origin, by the crawler's simulator
/// (module docs) with the exact method, or with `catching_up = Some(M)` the catching-up scheme
/// of `M` steps a period, to the periodicity tolerance `tol` within `max_periods`; `None` where it does
/// not apply (not a periodic chain, a piecewise-linear input, an input without zero mean, an
/// input or option the crawler's simulator refuses) or the search did not converge: the caller
/// then iterates the general period map itself. Errors: a cancellation or the deadline only.
pub fn chain_regime(
    p: &GeneralProblem,
    view: &ChainView,
    input: &ControlInput,
    catching_up: Option<usize>,
    max_periods: usize,
    tol: f64,
) -> Result<Option<ChainRegime>> {
    if p.boundary != Boundary::Periodic || input.kind != InputKind::PiecewiseConstant {
        return Ok(None);
    }
    let k = view.crawler.stiffness();
    let n = k.len();
    let mut lengths = Vec::with_capacity(input.times.len());
    let mut l = vec![0.0; n];
    for (i, u) in input.values.iter().enumerate() {
        lengths.push(l.clone());
        let end = input.times.get(i + 1).copied().unwrap_or(input.period);
        let dt = end - input.times[i];
        for ((l, u), k) in l.iter_mut().zip(u).zip(k) {
            *l += u * dt / k;
        }
    }
    // Zero mean: the lengths close up over the period (to the rounding of the sums).
    let size = lengths
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    if l.iter().any(|v| v.abs() > 1e-12 * size) {
        return Ok(None);
    }
    // Whatever the crawler's actuation or simulator refuses (a single knot, an option out of
    // its range) leaves the search to the general simulator; only a stop is passed on.
    let Ok(act) = Actuation::piecewise_linear(input.period, input.times.clone(), lengths) else {
        return Ok(None);
    };
    // The crawler stops when its state `x = K^(1/2) x~` changes by `tol_c` times its own scale
    // (the widest link-force range) over a period; the general simulator's confirmation asks
    // `x~` to change by `tol` times C's scale, which can be N times tighter: `|dx~| <=
    // |dx| / min sqrt(k_l)`, so the crawler is held to the general criterion, with a margin of
    // 2 (else its state was confirmed only after the slow plain iteration it was to spare, or
    // not at all: 30 blocks of alternating stiffness, 2662 periods).
    let min_sqrt_k = k.iter().fold(f64::INFINITY, |m, v| m.min(v.sqrt()));
    let tol_c = (0.5 * tol * p.c.scale() * min_sqrt_k / view.crawler.state_scale())
        .min(super::periodic::MAX_TOL);
    if tol_c.is_nan() || tol_c <= 0.0 {
        return Ok(None);
    }
    let opts = SimOptions {
        method: catching_up.map_or(super::Method::Exact, |_| super::Method::CatchingUp),
        steps_per_period: catching_up.unwrap_or(SimOptions::DEFAULT.steps_per_period),
        record_periods: 0,
        max_periods,
        tol: tol_c,
        ..SimOptions::DEFAULT
    };
    let sim = match simulate(&view.crawler, &act, &opts) {
        Ok(sim) if sim.converged => sim,
        Err(e @ (Error::Cancelled | Error::TimeLimit(_))) => return Err(e),
        _ => return Ok(None),
    };
    Ok(Some(ChainRegime {
        state: sim
            .orbit_state
            .iter()
            .zip(k)
            .map(|(x, k)| x / k.sqrt())
            .collect(),
        periods: sim.periods_simulated,
    }))
}
