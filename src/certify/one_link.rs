//! §4's structure of a one-link process (theory §9): where the control switches, whether each
//! switch happens at an end of C, the interior arcs and whether the control is bang-bang. It is
//! a property of a process of (P) on a line: `C = [alpha, beta]`, one control with
//! `U = [-a, a]` and `x' in -N_C(x) + beta_u u` (`A = 0`, `b = 0`), along which `x` crosses C
//! in `(beta - alpha) / (|beta_u| a)` at full rate: a general problem where its data say so
//! ([`general`]), and a one-link crawler's instance (`x~ = x / sqrt(k)`, `beta_u = 1 / sqrt(k)`),
//! whose structure the crawler's certificate states with C scaled back to its link's force.

use super::general_process::GeneralProcess;
use super::records::OneLinkStructure;
use crate::model::general::{ControlSet, GeneralProblem};

/// A periodic process on a line, piecewise linear between its knots.
struct Line<'a> {
    /// `C = [alpha, beta]`.
    alpha: f64,
    beta: f64,
    /// The control's bound `a` (`U = [-a, a]`).
    a: f64,
    /// `|beta_u| a`: the rate of `x` at full control.
    rate: f64,
    /// `x` at the knots (`P + 1`).
    x: Vec<f64>,
    /// The control per piece.
    u: Vec<f64>,
    durations: &'a [f64],
    period: f64,
}

/// The structure of a process of (P) on a line: one state and one control, `A = 0`, `b = 0`,
/// `B != 0`, a box `U = [-a, a]` (`a > 0`) and a bounded `C`; `None` otherwise. It describes
/// the process whatever `f1`, `f2` and the zero mean (§4's problem is the case of face weights
/// `1/2`, `f2 = 0` and zero mean, where the arcs of an optimum are the expected arc).
pub(crate) fn general(
    p: &GeneralProblem,
    pr: &GeneralProcess,
    tol: f64,
) -> Option<OneLinkStructure> {
    let d = &p.dynamics;
    if p.states() != 1 || p.controls() != 1 || !d.is_state_independent() || d.drift[0] != 0.0 {
        return None;
    }
    let ControlSet::Box { lower, upper } = &p.control else {
        return None;
    };
    let (a, gain) = (upper[0], d.b[0][0]);
    if !(a > 0.0 && lower[0] == -a && gain != 0.0) {
        return None;
    }
    // C on the line: x <= c / n for n > 0, x >= c / n for n < 0 (unit normals: n = +-1).
    let (mut alpha, mut beta) = (f64::NEG_INFINITY, f64::INFINITY);
    for (n, &c) in p.c.normals.iter().zip(&p.c.offsets) {
        if n[0] > 0.0 {
            beta = beta.min(c / n[0]);
        } else if n[0] < 0.0 {
            alpha = alpha.max(c / n[0]);
        }
    }
    if !(alpha.is_finite() && beta.is_finite() && alpha < beta) {
        return None;
    }
    Some(structure(
        &Line {
            alpha,
            beta,
            a,
            rate: gain.abs() * a,
            x: pr.x.iter().map(|s| s[0]).collect(),
            u: pr.u.iter().map(|u| u[0]).collect(),
            durations: &pr.durations,
            period: p.period,
        },
        tol,
    ))
}

/// Switches of the control's sign (where they happen), interior arcs (`x` strictly inside C
/// between knots, walking from a knot at an end of C) and bang-bang, each to `tol` relative to
/// `beta - alpha` and to `a`.
fn structure(l: &Line, tol: f64) -> OneLinkStructure {
    let (alpha, beta, a) = (l.alpha, l.beta, l.a);
    let etol = tol * (beta - alpha);
    let np = l.durations.len();
    let mut times = vec![0.0];
    for d in l.durations {
        times.push(times.last().unwrap() + d);
    }
    let at_end = |v: f64| v <= alpha + etol || v >= beta - etol;
    let sgn = |u: f64| {
        if u > tol * a {
            1
        } else if u < -tol * a {
            -1
        } else {
            0
        }
    };
    let mut switch_times = Vec::new();
    let mut switch_at_end = Vec::new();
    for j in 0..np {
        let prev = (j + np - 1) % np;
        if sgn(l.u[prev]) != sgn(l.u[j]) {
            switch_times.push(times[j]);
            switch_at_end.push(at_end(l.x[j]));
        }
    }
    let mut arcs: Vec<f64> = Vec::new();
    match (0..np).find(|&j| at_end(l.x[j])) {
        None => arcs.push(l.period),
        Some(s0) => {
            let mut cur = 0.0;
            for step in 0..np {
                let j = (s0 + step) % np;
                let (x0, x1, tau) = (l.x[j], l.x[j + 1], l.durations[j]);
                match (at_end(x0), at_end(x1)) {
                    (true, true) if (x1 - x0).abs() <= etol => {}
                    (true, true) => arcs.push(tau),
                    (_, false) => cur += tau,
                    (false, true) => {
                        arcs.push(cur + tau);
                        cur = 0.0;
                    }
                }
            }
        }
    }
    OneLinkStructure {
        alpha,
        beta,
        switch_times,
        switch_at_end,
        interior_arcs: arcs,
        expected_arc: (beta - alpha) / l.rate,
        bang_bang: l.u.iter().all(|u| (u.abs() - a).abs() <= tol * a),
    }
}
