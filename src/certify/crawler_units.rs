//! A crawler's certificate counted with forces in units of its stiffest spring.
//!
//! The crawler's adjoint `p` is a length per force. Every threshold of the certificate (the
//! residuals' `tol max(1, ||p||)`, the non-degeneracy resolution on `p + omega`, the multiplier
//! LPs' absolute tolerances) is met in the crawler's own numbers, so two exact twins that
//! differ in the unit of force only got different verdicts: the three-block P_3 answer of a
//! quadratic cost, unpolished (its rates off their bounds only as accurate as the MILP's outer
//! approximation), `fails` its slip stationarity by `2.0e-4` with forces of order one, and
//! `holds` with forces times `1e6` (its `p` of order `1e-7`, every residual under
//! `tol max(1, ||p||) = 1e-9`); with forces times `1e-6` it fails by `2.0e2`.
//!
//! Forces divided by `k_max` (the stiffest spring's stiffness times one length) make
//! `k_max = 1`: the process is the same process of the crawler in those units (lengths and
//! time unchanged: `k / k_max`, `mu / k_max`, rates and their bounds `/ k_max`, the cost's
//! weight `c k_max^2`, `J` unchanged), and every twin that differs in the unit of force is the
//! same crawler there. The certificate is computed there ([`super::certify`]) and its numbers
//! in forces converted back ([`to_forces`]): `p`, `p + omega`, `psi`, `omega` and `dxi` (a
//! length per force) divided by `k_max`, the rates `u` and `C = [alpha, beta]` times `k_max`,
//! the non-degeneracy margin and its resolution (in `p`'s units) divided by `k_max`. The
//! residuals, the verdict and the normalisation constants are those of the units of order one
//! (the residuals are relative, the normalisation constants count `p` in lengths per `k_max`
//! force). A crawler whose stiffest spring has `k = 1` is certified exactly as before.

use super::process::Process;
use super::records::NecessaryConditions;
use crate::error::Result;
use crate::model::Crawler;
use crate::optimal::{Cost, GaitProblem};

/// `k_max`, the force unit of the certificate (module docs).
pub(super) fn force_unit(pr: &Process) -> f64 {
    pr.crawler
        .stiffness()
        .iter()
        .fold(0.0_f64, |m, &k| m.max(k))
}

/// The process `pr` with forces in units of `unit` (module docs): the same process of the same
/// crawler, every force (`k`, `mu`, states) and force rate (controls, rate bounds, the total
/// variation bound) divided by `unit`, the cost's weight (a length times a time per force
/// squared) multiplied by `unit^2`; lengths and times unchanged.
pub(super) fn with_forces_in(pr: &Process, unit: f64) -> Result<Process> {
    let div = |v: &[f64]| -> Vec<f64> { v.iter().map(|x| x / unit).collect() };
    let c = &pr.crawler;
    let crawler = Crawler::new(
        div(c.stiffness()),
        div(c.mu_forward()),
        div(c.mu_backward()),
    )?;
    let problem = GaitProblem {
        period: pr.problem.period,
        rate_bound: div(&pr.problem.rate_bound),
        cost: match pr.problem.cost {
            Cost::None => Cost::None,
            Cost::Quadratic { weight } => Cost::Quadratic {
                weight: weight * unit * unit,
            },
        },
        max_total_variation: pr.problem.max_total_variation.map(|v| v / unit),
    };
    Ok(Process {
        crawler,
        problem,
        kind: pr.kind,
        durations: pr.durations.clone(),
        controls: pr.controls.iter().map(|u| div(u)).collect(),
        states: pr.states.iter().map(|x| div(x)).collect(),
        block_displacements: pr.block_displacements.clone(),
    })
}

/// The certificate `c` of the process in forces of units `unit` with its numbers in forces
/// converted back (module docs).
pub(super) fn to_forces(mut c: NecessaryConditions, unit: f64) -> NecessaryConditions {
    if unit == 1.0 {
        return c;
    }
    let per_force = |rows: &mut Vec<Vec<f64>>| {
        rows.iter_mut().flatten().for_each(|v| *v /= unit);
    };
    let m = &mut c.multipliers;
    per_force(&mut m.p);
    per_force(&mut m.p_plus_omega);
    per_force(&mut m.psi);
    m.omega.iter_mut().for_each(|v| *v /= unit);
    m.xi.iter_mut().for_each(|x| x.value /= unit);
    m.u.iter_mut().flatten().for_each(|v| *v *= unit);
    c.nondegeneracy_margin /= unit;
    c.nondegeneracy_resolution /= unit;
    if let Some(o) = c.one_link.as_mut() {
        o.alpha *= unit;
        o.beta *= unit;
    }
    c
}
