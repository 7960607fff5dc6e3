//! Closed-form optimum of the one-link crawler (theory §9, paper §4).
//!
//! With `C = [alpha, beta]`, `w = beta - alpha`, on the limit cycle an actuation that rises by
//! `Delta` (force units, `Delta = k Delta L`) and falls back moves the crawler by
//! `max(0, Delta - w) / k` when both extension and contraction move it forward (otherwise no
//! periodic gait moves it forward). Splitting the variation into several rise-and-fall cycles
//! loses `w / k` per extra cycle, so one cycle is optimal; it needs `Delta <= a T / 2` (both
//! halves at most at rate `a`).
//!
//! A total-variation bound `TV(u) <= V` (Theorem 2.1's class; `TV` of the periodic control
//! over one period, jumps summed over links) limits the rates: a rise at rate `r_1` for `t_1`
//! and a fall at `r_2` for `t_2` (`t_1 + t_2 <= T`) sweep `Delta = T r_1 r_2 / (r_1 + r_2)` at
//! most, and `TV(u) >= 2 (max u - min u) >= 2 (r_1 + r_2)`; for a given `r_1 + r_2` the sweep is
//! largest at `r_1 = r_2`, so `Delta <= (T/2) min(a, V/4)` =: `Delta_max` (reached by `+r`
//! then `-r`, `r = min(a, V/4)`, whose `TV` is `4 r`).
//! - `f2 = 0`: `Delta* = Delta_max`, `J* = max(0, (Delta* - w) / k)`; for `V = inf` this is
//!   theory §9's `max(0, (a T - 2 w) / (2 k))`.
//! - `f2 = (c/2) u^2`: for a given `Delta` the cost `(c/2)(Delta^2/t_1 + Delta^2/t_2)`,
//!   `t_1 + t_2 = T`, is least at `t_1 = t_2 = T/2`, where it is `2 c Delta^2 / T`. So
//!   `J(Delta) = (Delta - w)/k - 2 c Delta^2 / T`, concave, stationary at `Delta = T / (4 c k)`;
//!   `J* = max(0, J(clamp(T / (4 c k), w, Delta_max)))` when `Delta_max >= w`, else 0.

use crate::error::{Error, Result};
use crate::integrate::Actuation;
use crate::model::Crawler;
use crate::optimal::{Cost, GaitProblem};
use serde::Serialize;

/// The optimum of (P) for a one-link crawler, with an optimal gait.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OneLinkOptimum {
    /// `J*`.
    pub value: f64,
    /// Displacement per period of the optimal gait.
    pub displacement: f64,
    /// Its actuation cost per period.
    pub cost: f64,
    /// `Delta* = k Delta L`: how far the optimal gait sweeps the link force (0: stay idle).
    pub sweep: f64,
    /// `|u|` on each half period of the optimal gait.
    pub rate: f64,
    /// Why the optimum is what it is, in words.
    pub reason: String,
}

impl OneLinkOptimum {
    /// The optimal gait as an actuation: `L` rises by `sweep / k` at constant speed over the
    /// first half period and falls back over the second (`None` when staying idle is optimal).
    pub fn gait(&self, crawler: &Crawler, period: f64) -> Option<Actuation> {
        (self.sweep > 0.0).then(|| {
            let dl = self.sweep / crawler.stiffness()[0];
            Actuation::piecewise_linear(period, vec![0.0, 0.5 * period], vec![vec![0.0], vec![dl]])
                // Impossible to refuse: knots 0 < T/2 < T, one finite length (sweep <= a T and
                // k is a positive normal number, both checked by Crawler and GaitProblem).
                .expect("valid knots")
        })
    }
}

/// The closed-form optimum of (P) for a crawler with one link (module docs).
pub fn one_link_optimum(crawler: &Crawler, problem: &GaitProblem) -> Result<OneLinkOptimum> {
    crawler.require_unique()?;
    if crawler.blocks() != 2 {
        return Err(Error::invalid(
            "crawler.blocks",
            crawler.blocks(),
            "the closed-form optimum is for one link (2 blocks)",
        ));
    }
    // `analyze` fills `one_link` for every two-block crawler, checked just above.
    let facts = crawler.analyze().one_link.expect("two blocks");
    let (k, a, t) = (
        crawler.stiffness()[0],
        problem.rate_bound[0],
        problem.period,
    );
    let w = facts.width;
    let idle = |reason: String| OneLinkOptimum {
        value: 0.0,
        displacement: 0.0,
        cost: 0.0,
        sweep: 0.0,
        rate: 0.0,
        reason,
    };
    if !(facts.extension_moves_forward && facts.contraction_moves_forward) {
        return Ok(idle(
            "no periodic gait moves this crawler forward (v_m is linear or concave): stay idle"
                .into(),
        ));
    }
    let rate_max = a.min(
        problem
            .max_total_variation
            .map_or(f64::INFINITY, |v| 0.25 * v),
    );
    let dmax = 0.5 * rate_max * t;
    if dmax <= w {
        return Ok(idle(format!(
            "the largest sweep of the link force, {dmax}, does not exceed the width of C, {w}: \
             locomotion needs a T > 2 w (and T TV(u) > 8 w with a total-variation bound)"
        )));
    }
    let sweep = match problem.cost {
        Cost::None => dmax,
        Cost::Quadratic { weight } => (t / (4.0 * weight * k)).clamp(w, dmax),
    };
    let displacement = (sweep - w) / k;
    let rate = 2.0 * sweep / t;
    let cost = problem.cost.eval(&[rate]) * t;
    if displacement - cost <= 0.0 {
        return Ok(idle(
            "the actuation cost exceeds what any gait gains: stay idle".into(),
        ));
    }
    Ok(OneLinkOptimum {
        value: displacement - cost,
        displacement,
        cost,
        sweep,
        rate,
        reason: format!(
            "one rise and fall of the link force by {sweep} at rate {rate} (bound {a}); \
             the crawler moves (sweep - w)/k = {displacement} per period"
        ),
    })
}
