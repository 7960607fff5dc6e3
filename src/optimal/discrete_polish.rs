//! Polishing the crawler's P_m answer ([`crate::optimal::polish`]): P_m on the answer's fixed
//! slip pattern as a [`Qp`], in the optimisers' internal units.
//!
//! The pattern is read from the replayed gait: block `b` slips forward in step `i` when its
//! displacement `D^i_b` is positive (beyond `1e-9` of the largest), backward when negative,
//! else sticks. Slipping forward: `D^i_b = P^i_b >= 0` and `F_b(x^(i+1)) = mu_b^+`; backward:
//! `D^i_b = -Q^i_b <= 0` and `F_b(x^(i+1)) = -mu_b^-`; sticking: `D^i_b = 0` and
//! `-mu_b^- <= F_b(x^(i+1)) <= mu_b^+` (a face held without slip stays free to be left). These
//! are the branches of the catching-up KKT system of the MILP (module docs of
//! [`super::discrete`]), so every feasible point is a catching-up gait and the MILP's answer is
//! one. The QP maximises `(1/N) sum D - (c/2) sum_{i,l} (U^i_l)^2 / h` with the cost exact,
//! under the same rate bounds, zero mean and TV bound.

use super::discrete::{grid_cost, DiscreteSolution};
use super::milp::{certify, replay_grid};
use super::polish::{no_worse, PolishRecord, Qp};
use super::{Cost, GaitProblem};
use crate::error::Result;
use crate::model::Crawler;

/// The columns of the QP.
struct Columns {
    /// States `x^i`, `i = 0..M` (`x^M` is `x^0`).
    x: Vec<Vec<usize>>,
    /// Increments `U^i = h u^i`.
    u: Vec<Vec<usize>>,
    /// Block displacements `P^i_b - Q^i_b`, as `(P, Q)`.
    d: Vec<Vec<(usize, usize)>>,
}

/// The slip of a block in a step: +1 forward, -1 backward, 0 stuck.
fn pattern(s: &DiscreteSolution) -> Vec<Vec<i8>> {
    let largest = s
        .block_displacements
        .iter()
        .flatten()
        .fold(0.0_f64, |a, d| a.max(d.abs()));
    let tol = 1e-9 * largest.max(1e-300);
    s.block_displacements
        .iter()
        .map(|r| {
            r.iter()
                .map(|&d| {
                    if d > tol {
                        1
                    } else if d < -tol {
                        -1
                    } else {
                        0
                    }
                })
                .collect()
        })
        .collect()
}

/// A crawler's state and increment columns of `pieces` pieces of a polish: per piece the link
/// forces `x_l` in their ranges over C and the increments `U_l` in `[-a_l span, a_l span]`
/// (`span` the longest a piece may last).
fn link_columns(
    qp: &mut Qp,
    crawler: &Crawler,
    problem: &GaitProblem,
    pieces: usize,
    span: f64,
) -> (Vec<Vec<usize>>, Vec<Vec<usize>>) {
    let ranges = crawler.link_force_ranges();
    let x = (0..pieces)
        .map(|_| {
            ranges
                .iter()
                .map(|r| qp.add_column(0.0, r[0], r[1]))
                .collect()
        })
        .collect();
    let u = (0..pieces)
        .map(|_| {
            problem
                .rate_bound
                .iter()
                .map(|&al| qp.add_column(0.0, -al * span, al * span))
                .collect()
        })
        .collect();
    (x, u)
}

/// P_m on the slip pattern `slip` as a QP (minimising `-J`).
fn build(crawler: &Crawler, problem: &GaitProblem, slip: &[Vec<i8>]) -> (Qp, Columns) {
    let steps = slip.len();
    let (n, nb) = (crawler.links(), crawler.blocks());
    let h = problem.period / steps as f64;
    let (k, mp, mm) = (
        crawler.stiffness(),
        crawler.mu_forward(),
        crawler.mu_backward(),
    );
    let inf = f64::INFINITY;
    let mut qp = Qp::default();
    let (x, u) = link_columns(&mut qp, crawler, problem, steps, h);
    if let Cost::Quadratic { weight } = problem.cost {
        // (c/2) U^2 / h per step and link.
        for c in u.iter().flatten() {
            qp.add_quadratic(*c, *c, weight / h);
        }
    }
    let inv_n = 1.0 / nb as f64;
    let d: Vec<Vec<(usize, usize)>> = slip
        .iter()
        .map(|r| {
            r.iter()
                .map(|&s| {
                    let p = qp.add_column(-inv_n, 0.0, if s > 0 { inf } else { 0.0 });
                    let q = qp.add_column(inv_n, 0.0, if s < 0 { inf } else { 0.0 });
                    (p, q)
                })
                .collect()
        })
        .collect();
    for i in 0..steps {
        let next = &x[(i + 1) % steps];
        // x^{i+1}_l - x^i_l - U^i_l + k_l (D_{l+1} - D_l) = 0.
        for l in 0..n {
            let (p0, q0) = d[i][l];
            let (p1, q1) = d[i][l + 1];
            qp.add_row(
                0.0,
                0.0,
                vec![
                    (next[l], 1.0),
                    (x[i][l], -1.0),
                    (u[i][l], -1.0),
                    (p1, k[l]),
                    (q1, -k[l]),
                    (p0, -k[l]),
                    (q0, k[l]),
                ],
            );
        }
        for b in 0..nb {
            // F_b(x) = x_{b-1} - x_b.
            let mut f = Vec::with_capacity(2);
            if b > 0 {
                f.push((next[b - 1], 1.0));
            }
            if b < n {
                f.push((next[b], -1.0));
            }
            let (lo, hi) = match slip[i][b] {
                1 => (mp[b], mp[b]),
                -1 => (-mm[b], -mm[b]),
                _ => (-mm[b], mp[b]),
            };
            qp.add_row(lo, hi, f);
        }
    }
    for l in 0..n {
        qp.add_row(0.0, 0.0, u.iter().map(|r| (r[l], 1.0)).collect());
    }
    if let Some(v) = problem.max_total_variation {
        // |U^{i+1}_l - U^i_l| <= s^i_l, sum s <= h V.
        let mut total = Vec::with_capacity(steps * n);
        for i in 0..steps {
            for l in 0..n {
                let s = qp.add_column(0.0, 0.0, inf);
                let (u0, u1) = (u[i][l], u[(i + 1) % steps][l]);
                qp.add_row(0.0, inf, vec![(s, 1.0), (u1, -1.0), (u0, 1.0)]);
                qp.add_row(0.0, inf, vec![(s, 1.0), (u1, 1.0), (u0, -1.0)]);
                total.push((s, 1.0));
            }
        }
        qp.add_row(-inf, h * v, total);
    }
    let mut xs = x.clone();
    xs.push(x[0].clone());
    (qp, Columns { x: xs, u, d })
}

/// Polishes `s` (module docs), in internal units: the polished answer when it replays to an
/// objective no worse than the MILP's, else `s` with the reason in its record. Never an error.
pub(super) fn polish(
    crawler: &Crawler,
    problem: &GaitProblem,
    s: DiscreteSolution,
) -> DiscreteSolution {
    let before = s.objective();
    match polished(crawler, problem, &s) {
        Ok(Ok(mut better)) => {
            let change = s
                .controls
                .iter()
                .flatten()
                .zip(better.controls.iter().flatten())
                .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
            if let Some(r) = better.polish.as_mut() {
                r.control_change = change;
            }
            better
        }
        Ok(Err(note)) => DiscreteSolution {
            polish: Some(PolishRecord::kept(before, note)),
            ..s
        },
        Err(e) => DiscreteSolution {
            polish: Some(PolishRecord::kept(before, e.to_string())),
            ..s
        },
    }
}

/// The polished answer, or why it is not taken.
fn polished(
    crawler: &Crawler,
    problem: &GaitProblem,
    s: &DiscreteSolution,
) -> Result<std::result::Result<DiscreteSolution, String>> {
    let what = format!("polishing P_{}", s.m);
    let slip = pattern(s);
    let steps = slip.len();
    let h = problem.period / steps as f64;
    let (qp, cols) = build(crawler, problem, &slip);
    let sol = qp.solve(&what)?;
    let val = |c: &usize| sol.v[*c];
    let mut incs: Vec<Vec<f64>> = cols.u.iter().map(|r| r.iter().map(val).collect()).collect();
    // An exact zero mean (the QP's is within its tolerance), as for the MILP's increments.
    for l in 0..crawler.links() {
        let mean = incs.iter().map(|u| u[l]).sum::<f64>() / steps as f64;
        for u in &mut incs {
            u[l] -= mean;
        }
    }
    let x0: Vec<f64> = cols.x[0].iter().map(val).collect();
    let displacement = cols
        .d
        .iter()
        .flatten()
        .map(|&(p, q)| val(&p) - val(&q))
        .sum::<f64>()
        / crawler.blocks() as f64;
    let g = replay_grid(crawler, problem.period, &incs, &x0, &what)?;
    let qp_x: Vec<Vec<f64>> = cols.x.iter().map(|r| r.iter().map(val).collect()).collect();
    let force_scale = (0..crawler.blocks())
        .map(|b| crawler.mu_forward()[b] + crawler.mu_backward()[b])
        .fold(0.0_f64, f64::max);
    let moved = g
        .states
        .iter()
        .flatten()
        .zip(qp_x.iter().flatten())
        .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
    // The replayed orbit starts where the QP's does (the replay plays from x0 to the regime,
    // and on the pattern's orbit x0 is periodic): a state far from the QP's is a pattern left.
    if moved > 1e-7 * force_scale {
        return Ok(Err(format!(
            "the polished controls' process leaves the QP's by {moved:e}: the slip pattern \
             does not hold (the MILP's answer kept)"
        )));
    }
    let cost = grid_cost(problem, &incs, h);
    let objective = g.verified - cost;
    if !no_worse(objective, s.objective()) {
        return Ok(Err(format!(
            "the polished objective {objective} is below the MILP's {} (the MILP's answer kept)",
            s.objective()
        )));
    }
    let mut certificate = certify(
        &what,
        problem.length_scale(crawler),
        s.certificate.status,
        displacement,
        s.certificate.bound,
        g.verified,
        cost,
    )?;
    certificate.milp_objective = s.certificate.milp_objective;
    let how = if sol.exact {
        "exact on the active set"
    } else {
        "interior point"
    };
    Ok(Ok(DiscreteSolution {
        certificate,
        verified_displacement: g.verified,
        actuation_cost: cost,
        initial_state: g.initial_state,
        states: g.states,
        controls: g.controls,
        block_displacements: g.block_displacements,
        polish: Some(PolishRecord {
            applied: true,
            objective_before: s.objective(),
            objective_after: objective,
            control_change: 0.0,
            note: how.into(),
        }),
        ..s.clone()
    }))
}
