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
//! The certificate is computed in the units ([`units_of`], as the optimisers' `Units`)
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
//! `p`'s units) times `L / F = 1 / k_max`; the rates `u` times `F / T`; times (switches, arcs)
//! times `T` (the knot times, the time a degenerate reason quotes and the paper's norm's
//! `sum tau |psi|` are stated in the crawler's time by (P)'s report itself,
//! `ResidualUnits::time`); `C = [alpha, beta]` times `F`; the branch LP's values (`J`s) times `L`.
//! The verdict, the residuals and the normalisation constants are those of these units (the
//! residuals are relative, but for Theorem 2.2's weak maximality, an integral over time, which
//! (P)'s report states in the crawler's time with its tolerance `tol T`; the normalisation
//! constants count `p` in lengths per `k_max` force as before, and its time integral in the
//! crawler's time).

use super::process::Process;
use super::records::NecessaryConditions;
use crate::error::Result;
use crate::optimal::units::{scale_all, scale_rows, Units};

/// The certificate's units of `pr` (module docs): force `mu_max`, length `mu_max / k_max`, time
/// the period, as the optimisers' [`Units`] (their conversions of the crawler and the problem).
pub(super) fn units_of(pr: &Process) -> Units {
    let max = |v: &[f64]| v.iter().fold(0.0_f64, |m, &x| m.max(x));
    let c = &pr.crawler;
    let force = max(c.mu_forward()).max(max(c.mu_backward()));
    Units {
        force,
        time: pr.problem.period,
        length: force / max(c.stiffness()),
    }
}

/// The process `pr` in the units `u` (module docs): the same process of the same crawler
/// ([`Units::crawler`], [`Units::problem`]), its durations, rates, states and displacements
/// converted.
pub(super) fn in_units(pr: &Process, u: Units) -> Result<Process> {
    let (f, t, l) = u.factors(false);
    Ok(Process {
        crawler: u.crawler(&pr.crawler)?,
        problem: u.problem(&pr.problem),
        kind: pr.kind,
        durations: scale_all(&pr.durations, t),
        controls: scale_rows(&pr.controls, f / t),
        states: scale_rows(&pr.states, f),
        block_displacements: scale_rows(&pr.block_displacements, l),
    })
}

/// The certificate `c` of the process in the units `u` with its numbers converted back to the
/// user's (module docs).
pub(super) fn to_user(mut c: NecessaryConditions, u: Units) -> NecessaryConditions {
    if u == Units::ONE {
        return c;
    }
    let (f, t, l) = u.factors(true);
    let per_force = l / f;
    let scale = |rows: &mut Vec<Vec<f64>>, by: f64| {
        rows.iter_mut().flatten().for_each(|v| *v *= by);
    };
    let m = &mut c.multipliers;
    scale(&mut m.p, per_force);
    scale(&mut m.p_plus_omega, per_force);
    scale(&mut m.psi, per_force);
    m.omega.iter_mut().for_each(|v| *v *= per_force);
    // (Knot times and Theorem 2.2's weak maximality, an integral over time, are stated in the
    // crawler's time already: `ResidualUnits::time`.)
    m.xi.iter_mut().for_each(|x| x.value *= per_force);
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
    if let Some(b) = c.branch_lp.as_mut() {
        b.optimum *= l;
        b.process_objective *= l;
        b.improvement *= l;
    }
    c
}
