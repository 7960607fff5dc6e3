//! The text of a simulation (`crawlopt simulate`).

use super::{force_scale, list, num, wln};
use crate::integrate::{Actuation, Search, Simulation};
use crate::model::Crawler;
use std::path::Path;

/// The human form of a simulation of `act` on `crawler`: displacements at the scale of the
/// actuation's stroke (the largest range of an actuator length over a period), states at
/// [`force_scale`].
pub fn simulation(
    s: &Simulation,
    crawler: &Crawler,
    act: &Actuation,
    csv: Option<&Path>,
) -> String {
    let mut out = String::new();
    let (_, knots) = act.knots(s.steps_per_period.clamp(2, 1024));
    let stroke = (0..act.links())
        .map(|l| {
            let (lo, hi) = knots
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
                    (lo.min(r[l]), hi.max(r[l]))
                });
            hi - lo
        })
        .filter(|w| w.is_finite())
        .fold(0.0, f64::max);
    let force = force_scale(crawler);
    wln!(
        out,
        "method: {} ({} per period): {}",
        s.method,
        s.steps_per_period,
        s.actuation_model
    );
    match s.displacement_per_period {
        Some(d) => wln!(out, "displacement per period: {}", num(d, stroke)),
        None => wln!(
            out,
            "displacement per period: not reached (last period: {})",
            num(s.last_period_displacement, stroke)
        ),
    }
    wln!(
        out,
        "periodic regime: {} after {} period(s) (residual {:.3e}, {})",
        if s.converged {
            "reached"
        } else {
            "NOT reached"
        },
        s.periods_to_converge.unwrap_or(s.periods_simulated),
        s.period_residual,
        match s.search {
            Search::Iteration => "plain iteration: the physical transient",
            Search::Anderson => "Anderson-accelerated search",
            Search::Newton => "Newton-Krylov search",
        }
    );
    if s.search != Search::Iteration {
        wln!(
            out,
            "search cost: {} period(s) integrated, {} Newton step(s), {} Jacobian-vector product(s)",
            s.periods_simulated,
            s.newton_steps,
            s.tangent_products
        );
    }
    wln!(
        out,
        "block displacement per period: {}",
        list(&s.block_displacement_per_period, stroke)
    );
    wln!(
        out,
        "state at the start of the periodic period: {}",
        list(&s.orbit_state, force)
    );
    if let Some(p) = csv {
        wln!(out, "trajectory written to {}", p.display());
    }
    out
}
