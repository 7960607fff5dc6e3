//! The record of a piecewise-linear gait, such as a structured gait ([`super::structured`]),
//! as a gait result: one period on its periodic orbit recorded by the exact simulator, cut at
//! every knot and event.

use crate::error::{Error, Result};
use crate::integrate::{simulate, Actuation, Method, SimOptions, Simulation};
use crate::model::Crawler;
use crate::optimal::{GaitProblem, GaitResult};

/// The gait result of any piecewise-linear gait given by its knots (times in `[0, T)`, the
/// lengths there), recorded as one period on its periodic orbit by the exact simulator, cut
/// into pieces at every knot and event (one control and one slip pattern per piece), so that it
/// is a process of the problem on its own knots; `origin` names it.
pub fn knots_result(
    crawler: &Crawler,
    problem: &GaitProblem,
    times: Vec<f64>,
    lengths: Vec<Vec<f64>>,
    origin: &str,
) -> Result<GaitResult> {
    let act = Actuation::of_gait(problem.period, times, lengths)?;
    let sim = simulate(
        crawler,
        &act,
        &SimOptions {
            record_periods: 1,
            method: Method::Exact,
            ..SimOptions::default()
        },
    )?;
    pieces_result(crawler, problem, &act, &sim, origin)
}

/// The pieces of a recorded period ([`knots_result`]).
fn pieces_result(
    crawler: &Crawler,
    problem: &GaitProblem,
    act: &Actuation,
    sim: &Simulation,
    origin: &str,
) -> Result<GaitResult> {
    let (Some(d), Some(tr)) = (sim.displacement_per_period, sim.trajectory.as_ref()) else {
        return Err(Error::Numerical(format!(
            "{origin}: the exact simulator found no periodic orbit"
        )));
    };
    let t = problem.period;
    let k = crawler.stiffness();
    let n = crawler.links();
    let a = &problem.rate_bound;
    // Rows at distinct times: a zero-length step (an event at the same instant) moves nothing;
    // the first row at a time carries the slip of the step that ended there.
    let mut keep: Vec<usize> = vec![0];
    for i in 1..tr.t.len() {
        let last = *keep.last().unwrap_or(&0);
        if tr.t[i] - tr.t[last] > 1e-12 * t {
            keep.push(i);
        }
    }
    let mut durations = Vec::new();
    let mut controls = Vec::new();
    let mut states = vec![tr.x[0].clone()];
    let mut block_displacements = Vec::new();
    let mut slip = Vec::new();
    let (mut l0, mut l1) = (vec![0.0; n], vec![0.0; n]);
    for w in keep.windows(2) {
        let (i0, i1) = (w[0], w[1]);
        let (t0, t1) = (tr.t[i0], tr.t[i1]);
        let dur = t1 - t0;
        act.lengths_at(t0, &mut l0);
        act.lengths_at(t1.min(t * (1.0 - 1e-15)), &mut l1);
        if t1 >= t * (1.0 - 1e-15) {
            act.lengths_at(0.0, &mut l1);
        }
        controls.push(
            (0..n)
                .map(|l| rounded_rate(k[l] * (l1[l] - l0[l]), dur, k[l], &[l0[l], l1[l]], a[l]))
                .collect::<Vec<_>>(),
        );
        durations.push(dur);
        states.push(tr.x[i1].clone());
        block_displacements.push(
            tr.positions[i1]
                .iter()
                .zip(&tr.positions[i0])
                .map(|(a, b)| a - b)
                .collect::<Vec<_>>(),
        );
        slip.push(tr.slip[i1].clone());
    }
    // The recorded period closes the orbit: the last state is the first (within the search's
    // tolerance), written as such.
    if let (Some(first), Some(last)) = (states.first().cloned(), states.last_mut()) {
        *last = first;
    }
    let total: f64 = durations.iter().sum();
    if let Some(last) = durations.last_mut() {
        *last += t - total;
    }
    Ok(GaitResult::from_structured(
        crawler,
        problem,
        crate::optimal::StructuredPieces {
            durations,
            controls,
            states,
            block_displacements,
            slip,
            verified_displacement: d,
        },
        origin,
    ))
}

/// The control `dz / dur` of a piece (`dz = k (L(t1) - L(t0))`), kept within the rate bound
/// `a` where it exceeds it by no more than the rounding of the difference quotient: on a piece
/// between an event and a knot a few ulps of `L` divided by a tiny duration can exceed `a`
/// although the actuation's slope there does not. A larger excess is left for the consistency
/// check to report.
fn rounded_rate(dz: f64, dur: f64, k: f64, lengths: &[f64; 2], a: f64) -> f64 {
    let u = dz / dur;
    let rounding = 4.0 * f64::EPSILON * k * (lengths[0].abs() + lengths[1].abs()) / dur;
    if u.abs() > a && u.abs() <= a * (1.0 + 4.0 * f64::EPSILON) + rounding {
        a.copysign(u)
    } else {
        u
    }
}
