//! A crawler's certificate counted in units of its own scales: force, length and time.
//!
//! The crawler's adjoint `p` is a length per force. Every threshold of the certificate (the
//! residuals' `tol max(1, ||p||)`, the non-degeneracy resolution on `p + omega`, the multiplier
//! LPs' absolute tolerances) is met in the numbers it is computed in, so two exact twins that
//! differ in a unit only got different verdicts, or none:
//! - force: the three-block P_3 answer of a quadratic cost, unpolished (its rates off their
//!   bounds only as accurate as the MILP's outer approximation), `fails` its slip stationarity
//!   by `2.0e-4` with forces of order one, and `held` with forces times `1e6` (its `p` of order
//!   `1e-7`, every residual under `tol max(1, ||p||) = 1e-9`); with forces times `1e-6` it
//!   failed by `2.0e2`;
//! - time and length: the three-block phase optimum (K = 4) with time times `1e-6` and lengths
//!   times `1e6` (rates of `1e12`) was not certified at all: its multiplier LP ended in HiGHS's
//!   status unknown.
//!
//! The certificate is computed in the units (`Scales::of`)
//! - force `F`: the largest friction threshold `mu_max`,
//! - length `L = mu_max / k_max` (so the stiffest spring has `k = F / L = 1`: the unit of `p`,
//!   a length per force, is `1 / k_max` as before),
//! - time: the period (`T = 1`),
//!
//! where the process is the same process of the same crawler (`k L / F`, `mu / F`, states
//! `/ F`, rates and their bounds `T / F`, the total variation bound `T / F`, durations `/ T`,
//! displacements `/ L`, the cost's weight `c F^2 / (T L)`, `J / L`), and every twin that
//! differs in units is the same crawler there. Its numbers are converted back ([`to_user`]):
//! `p`, `p + omega`, `psi`, `omega`, `dxi` and the non-degeneracy margin and resolution (in
//! `p`'s units) times `L / F = 1 / k_max`; the rates `u` times `F / T`; times (knots, switches,
//! arcs) times `T`; `C = [alpha, beta]` times `F`; the branch LP's values (`J`s) times `L`.
//! The verdict, the residuals and the normalisation constants are those of these units (the
//! residuals are relative, but for Theorem 2.2's weak maximality, an integral over time,
//! converted back with its tolerance `tol T`; the normalisation constants count `p` in lengths
//! per `k_max` force as before, and the time integrals of the paper's norm in periods).

use super::process::Process;
use super::records::NecessaryConditions;
use crate::error::Result;
use crate::model::Crawler;
use crate::optimal::{Cost, GaitProblem};

/// The certificate's units (module docs): the user's force, length and time units in them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Scales {
    pub force: f64,
    pub length: f64,
    pub time: f64,
}

impl Scales {
    /// The units of `pr` (module docs): `mu_max`, `mu_max / k_max` and the period.
    pub fn of(pr: &Process) -> Self {
        let max = |v: &[f64]| v.iter().fold(0.0_f64, |m, &x| m.max(x));
        let c = &pr.crawler;
        let force = max(c.mu_forward()).max(max(c.mu_backward()));
        Scales {
            force,
            length: force / max(c.stiffness()),
            time: pr.problem.period,
        }
    }

    /// Whether these are the units of the numbers given (all three one).
    pub fn is_one(&self) -> bool {
        (self.force, self.length, self.time) == (1.0, 1.0, 1.0)
    }
}

/// The process `pr` in the units `u` (module docs): the same process of the same crawler.
pub(super) fn in_units(pr: &Process, u: Scales) -> Result<Process> {
    let times = |v: &[f64], f: f64| -> Vec<f64> { v.iter().map(|x| x * f).collect() };
    let rows =
        |v: &[Vec<f64>], f: f64| -> Vec<Vec<f64>> { v.iter().map(|r| times(r, f)).collect() };
    let (f, l, t) = (u.force, u.length, u.time);
    let c = &pr.crawler;
    let crawler = Crawler::new(
        times(c.stiffness(), l / f),
        times(c.mu_forward(), 1.0 / f),
        times(c.mu_backward(), 1.0 / f),
    )?;
    let problem = GaitProblem {
        period: pr.problem.period / t,
        rate_bound: times(&pr.problem.rate_bound, t / f),
        cost: match pr.problem.cost {
            Cost::None => Cost::None,
            Cost::Quadratic { weight } => Cost::Quadratic {
                weight: weight * f * f / (t * l),
            },
        },
        max_total_variation: pr.problem.max_total_variation.map(|v| v * t / f),
    };
    Ok(Process {
        crawler,
        problem,
        kind: pr.kind,
        durations: times(&pr.durations, 1.0 / t),
        controls: rows(&pr.controls, t / f),
        states: rows(&pr.states, 1.0 / f),
        block_displacements: rows(&pr.block_displacements, 1.0 / l),
    })
}

/// The certificate `c` of the process in the units `u` with its numbers converted back to the
/// user's (module docs).
pub(super) fn to_user(mut c: NecessaryConditions, u: Scales) -> NecessaryConditions {
    if u.is_one() {
        return c;
    }
    let (f, l, t) = (u.force, u.length, u.time);
    let per_force = l / f;
    let scale = |rows: &mut Vec<Vec<f64>>, by: f64| {
        rows.iter_mut().flatten().for_each(|v| *v *= by);
    };
    let m = &mut c.multipliers;
    m.times.iter_mut().for_each(|v| *v *= t);
    scale(&mut m.p, per_force);
    scale(&mut m.p_plus_omega, per_force);
    scale(&mut m.psi, per_force);
    m.omega.iter_mut().for_each(|v| *v *= per_force);
    m.xi.iter_mut().for_each(|x| {
        x.value *= per_force;
        x.time *= t;
    });
    scale(&mut m.u, f / t);
    c.nondegeneracy_margin *= per_force;
    c.nondegeneracy_resolution *= per_force;
    if let Some(o) = c.one_link.as_mut() {
        o.alpha *= f;
        o.beta *= f;
        o.switch_times.iter_mut().for_each(|v| *v *= t);
        o.interior_arcs.iter_mut().for_each(|v| *v *= t);
        o.expected_arc *= t;
    }
    // Theorem 2.2's weak maximality is an integral over time (its tolerance `tol T` too): in
    // the user's time, as (P)'s certificate states it (`h / 4` on the one-link P_m optimum).
    for k in c
        .conditions
        .iter_mut()
        .filter(|k| (k.name.as_str(), k.theorem.as_str()) == ("weak_maximality", "2.2"))
    {
        k.residual *= t;
        k.tolerance *= t;
    }
    if let Some(b) = c.branch_lp.as_mut() {
        b.optimum *= l;
        b.process_objective *= l;
        b.improvement *= l;
    }
    c
}
