//! The exact event-driven solution of the general problem (P) where `A = 0` (theory §11) under a
//! piecewise-constant control: between events `g = B u + b` is constant and the solution moves
//! with the constant velocity `x' = Proj_{T_C(x)}(g)` (the projection onto the tangent cone,
//! whose multipliers are the reaction `eta = g - x' = sum_j lambda_j x*_j`), so the motion is
//! piecewise linear and computed without discretisation error. Events: a face hit (the step to
//! the first face the velocity crosses) and the control's knots; a face is released when the
//! cone projection no longer holds it. `J = sum over segments of tau (f1(lambda) - f2(u))`.

use super::general::{ControlInput, GeneralSimulation, InputKind};
use crate::error::{Error, Result};
use crate::model::general::{GeneralProblem, Polyhedron};
use crate::sweep::PolyProjector;

/// Most segments of one period before the integration is declared Zeno-like and stopped.
pub const MAX_EVENTS_PER_PERIOD: usize = 1_000_000;

/// The exact solution (module docs) from `x0`: one horizon for a Cauchy problem, else periods
/// until the state repeats within `tol` times C's scale (at most `max_periods`), then one
/// period recorded at its events.
pub fn simulate_general_exact(
    p: &GeneralProblem,
    input: &ControlInput,
    x0: &[f64],
    max_periods: usize,
    tol: f64,
) -> Result<GeneralSimulation> {
    if !p.dynamics.is_state_independent() {
        return Err(Error::invalid(
            "dynamics.A",
            "non-zero",
            "the exact method needs A = 0 (piecewise-linear motion); use catching-up",
        ));
    }
    if input.kind != InputKind::PiecewiseConstant {
        return Err(Error::invalid(
            "input.kind",
            "piecewise_linear",
            "the exact method needs a piecewise-constant control",
        ));
    }
    super::general::periodic_regime(p, input, x0.to_vec(), max_periods, tol, |x, rec| {
        period(p, input, x, rec)
    })
}

/// One period from `x`; with `rec`, its segments (`t` and `x` at the events, `u` and the
/// reactions `lambda` over each segment).
fn period(
    p: &GeneralProblem,
    input: &ControlInput,
    x: &mut [f64],
    mut rec: Option<&mut GeneralSimulation>,
) -> Result<()> {
    let c = &p.c;
    let (n, sigma) = (p.states(), c.faces());
    // A face is active within the round-off of its own slack, `1e-12 (|c_j| + |x|)` (unit
    // normals): `1e-12` of C's scale held a face 6 away as active on C = [-1e13, 1] (a
    // tolerance of 10, where x moves by 10 in a period), and its reaction gave J = 2.5 where
    // the answer is 0.
    let active_at =
        |j: usize, x: &[f64], norm: f64| c.slack(j, x) >= -1e-12 * (c.offsets[j].abs() + norm);
    let mut g = vec![0.0; n];
    let zero = vec![0.0; n];
    let mut events = 0;
    for k in 0..input.times.len() {
        let t_end = input.times.get(k + 1).copied().unwrap_or(p.period);
        let u = &input.values[k];
        p.dynamics.eval(x, u, &mut g);
        let mut t = input.times[k];
        while t < t_end {
            events += 1;
            if events > MAX_EVENTS_PER_PERIOD {
                return Err(Error::Numerical(format!(
                    "exact method: more than {MAX_EVENTS_PER_PERIOD} events in a period"
                )));
            }
            // The tangent cone at x: the faces active there, with offset 0.
            let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            let active: Vec<usize> = (0..sigma).filter(|&j| active_at(j, x, norm)).collect();
            let (w, lambda, residual) = if active.is_empty() {
                (g.clone(), vec![0.0; sigma], 0.0)
            } else {
                let cone = Polyhedron::new(
                    active.iter().map(|&j| c.normals[j].clone()).collect(),
                    vec![0.0; active.len()],
                    "tangent cone",
                )?;
                let a = PolyProjector::new(cone).project(&zero, &g)?;
                let mut lambda = vec![0.0; sigma];
                for (i, &j) in active.iter().enumerate() {
                    lambda[j] = a.mu[i];
                }
                (a.x, lambda, a.residual)
            };
            // The first face outside the cone that the velocity reaches.
            let to_end = t_end - t;
            let mut tau = to_end;
            for j in (0..sigma).filter(|j| !active.contains(j)) {
                let rate = crate::model::general::dot(&c.normals[j], &w);
                if rate > 0.0 {
                    tau = tau.min((-c.slack(j, x) / rate).max(0.0));
                }
            }
            for i in 0..n {
                x[i] += tau * w[i];
            }
            if let Some(r) = rec.as_deref_mut() {
                r.reward += tau * p.reward.eval(&c.normals, &lambda);
                r.cost += tau * p.cost.eval(u);
                r.max_kkt_residual = r.max_kkt_residual.max(residual);
                r.t.push(if tau >= to_end { t_end } else { t + tau });
                r.x.push(x.to_vec());
                r.u.push(u.clone());
                r.lambda.push(lambda);
            }
            if tau >= to_end {
                break;
            }
            t += tau;
        }
    }
    Ok(())
}
