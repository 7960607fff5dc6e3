//! Polishing the general problem's P_m answer ([`crate::optimal::polish`]): P_m on the answer's
//! fixed face pattern as a [`Qp`].
//!
//! The pattern is read from the replayed process: face `j` is active in step `i` when its
//! reaction `mu^i_j = h lambda^i_j` is positive (beyond `1e-9` of the largest); there
//! `<x*_j, x^(i+1)> = c_j` and `mu^i_j >= 0`, elsewhere `mu^i_j = 0` and `<x*_j, x^(i+1)> <=
//! c_j` (a face held without reaction stays free to be left). Each is the branch of the
//! catching-up KKT system (module docs of [`super::discrete`]), so every feasible point is a
//! catching-up process, and the MILP's answer is one. The QP maximises
//! `sum_i [f1(mu^i) - h f2(u^i)]` with the quadratic `f2` exactly.

use super::discrete::{cost_matrix, replay_controls, GeneralPm};
use crate::error::Result;
use crate::model::general::{Boundary, ControlSet, GeneralProblem};
use crate::optimal::milp::Certificate;
use crate::optimal::polish::{no_worse, PolishRecord, Qp};

/// The columns of the QP: states per knot (`x^M` is `x^0` when periodic), controls, reactions.
pub(crate) struct PmColumns {
    pub x: Vec<Vec<usize>>,
    pub u: Vec<Vec<usize>>,
    pub mu: Vec<Vec<usize>>,
}

/// P_m of `p` on the pattern `active` (`active[i][j]`: face `j` reacts on step `i`, held at its
/// end) as a QP minimising `-J`: (P)'s and every instance's (a crawler's P_m polish is it on
/// the crawler's instance, its slips as the reacting faces, `optimal::discrete_polish`).
pub(crate) fn pm_on_pattern(p: &GeneralProblem, m: u32, active: &[Vec<bool>]) -> (Qp, PmColumns) {
    let (n, sigma, mm) = (p.states(), p.c.faces(), 1usize << m);
    let h = p.period / mm as f64;
    let w = p.face_weights();
    let inf = f64::INFINITY;
    let mut qp = Qp::default();
    let nx = match p.boundary {
        Boundary::Periodic => mm,
        Boundary::Initial(_) => mm + 1,
    };
    let x: Vec<Vec<usize>> = (0..nx)
        .map(|i| match &p.boundary {
            Boundary::Initial(x0) if i == 0 => {
                x0.iter().map(|&v| qp.add_column(0.0, v, v)).collect()
            }
            _ => (0..n).map(|_| qp.add_column(0.0, -inf, inf)).collect(),
        })
        .collect();
    let x_at = |i: usize| &x[i % nx];
    let r = cost_matrix(&p.cost, p.controls());
    let mut u = Vec::with_capacity(mm);
    let mut mu = Vec::with_capacity(mm);
    for i in 0..mm {
        let ui: Vec<usize> = match &p.control {
            ControlSet::Box { lower, upper } => (0..p.controls())
                .map(|k| qp.add_column(0.0, lower[k], upper[k]))
                .collect(),
            ControlSet::Polytope(poly) => {
                let ui: Vec<usize> = (0..p.controls())
                    .map(|_| qp.add_column(0.0, -inf, inf))
                    .collect();
                for (a, &c) in poly.normals.iter().zip(&poly.offsets) {
                    qp.add_row(-inf, c, ui.iter().copied().zip(a.iter().copied()).collect());
                }
                ui
            }
        };
        if let Some(r) = &r {
            // h f2(u) = (h/2) u^T R u, with R's symmetric part.
            for k in 0..ui.len() {
                for l in k..ui.len() {
                    let v = if k == l {
                        r[k][k]
                    } else {
                        0.5 * (r[k][l] + r[l][k])
                    };
                    qp.add_quadratic(ui[k], ui[l], h * v);
                }
            }
        }
        let mui: Vec<usize> = (0..sigma)
            .map(|j| qp.add_column(-w[j], 0.0, if active[i][j] { inf } else { 0.0 }))
            .collect();
        // x^(i+1) - (I + h A) x^i - h B u^i + sum_j mu_j x*_j = h b.
        for row in 0..n {
            let mut e = vec![(x_at(i + 1)[row], 1.0)];
            for k in 0..n {
                let a = -(if k == row { 1.0 } else { 0.0 }) - h * p.dynamics.a[row][k];
                e.push((x_at(i)[k], a));
            }
            for k in 0..p.controls() {
                e.push((ui[k], -h * p.dynamics.b[row][k]));
            }
            for j in 0..sigma {
                e.push((mui[j], p.c.normals[j][row]));
            }
            let rhs = h * p.dynamics.drift[row];
            qp.add_row(rhs, rhs, e);
        }
        for j in 0..sigma {
            let face = x_at(i + 1)
                .iter()
                .copied()
                .zip(p.c.normals[j].iter().copied())
                .collect();
            let c = p.c.offsets[j];
            qp.add_row(if active[i][j] { c } else { -inf }, c, face);
        }
        u.push(ui);
        mu.push(mui);
    }
    if p.zero_mean {
        for k in 0..p.controls() {
            qp.add_row(0.0, 0.0, u.iter().map(|ui| (ui[k], 1.0)).collect());
        }
    }
    let x = (0..=mm).map(|i| x_at(i).clone()).collect();
    (qp, PmColumns { x, u, mu })
}

/// Polishes `sol` (module docs): the polished answer when it replays to an objective no worse
/// than the MILP's, else `sol` with the reason in its record. Never an error: a polish that
/// fails leaves the MILP's answer, said so.
pub(super) fn polish(p: &GeneralProblem, sol: GeneralPm) -> GeneralPm {
    let before = sol.objective;
    match polished(p, &sol) {
        Ok(Ok(mut better)) => {
            if let Some(rec) = better.polish.as_mut() {
                rec.control_change = max_diff(&better.path.u, &sol.path.u);
            }
            better
        }
        Ok(Err(note)) => GeneralPm {
            polish: Some(PolishRecord::kept(before, note)),
            ..sol
        },
        Err(e) => GeneralPm {
            polish: Some(PolishRecord::kept(before, e.to_string())),
            ..sol
        },
    }
}

/// The polished answer, or why it is not taken.
fn polished(p: &GeneralProblem, sol: &GeneralPm) -> Result<std::result::Result<GeneralPm, String>> {
    let m = sol.m;
    let largest = sol
        .path
        .lambda
        .iter()
        .flatten()
        .fold(0.0_f64, |a, l| a.max(l.abs()));
    let tol = 1e-9 * largest.max(1e-300);
    let active: Vec<Vec<bool>> = sol
        .path
        .lambda
        .iter()
        .map(|r| r.iter().map(|l| *l > tol).collect())
        .collect();
    let what = format!("polishing P_{m} of the general problem");
    let (qp, cols) = pm_on_pattern(p, m, &active);
    let s = qp.solve(&what)?;
    let val = |c: &usize| s.v[*c];
    let x0: Vec<f64> = cols.x[0].iter().map(val).collect();
    let u: Vec<Vec<f64>> = cols.u.iter().map(|r| r.iter().map(val).collect()).collect();
    let w = p.face_weights();
    let reward: f64 = cols
        .mu
        .iter()
        .map(|r| r.iter().zip(&w).map(|(c, w)| w * val(c)).sum::<f64>())
        .sum();
    let r = replay_controls(p, m, &x0, u, reward, &what)?;
    let qp_x: Vec<Vec<f64>> = cols.x.iter().map(|r| r.iter().map(val).collect()).collect();
    let scale = p.c.scale();
    let moved = max_diff(&r.path.x, &qp_x);
    if moved > 1e-7 * scale {
        return Ok(Err(format!(
            "the polished controls' process leaves the QP's by {moved:e}: the pattern does not \
             hold (the MILP's answer kept)"
        )));
    }
    if !no_worse(r.objective, sol.objective, p.j_floor()) {
        return Ok(Err(format!(
            "the polished objective {} is below the MILP's {} (the MILP's answer kept)",
            r.objective, sol.objective
        )));
    }
    let how = if s.exact {
        "exact on the active set"
    } else {
        "interior point"
    };
    Ok(Ok(GeneralPm {
        m,
        objective: r.objective,
        certificate: Certificate {
            gap: Certificate::gap_of(sol.certificate.bound, r.objective, p.j_floor()),
            ..sol.certificate.clone()
        },
        path: r.path,
        polish: Some(PolishRecord {
            applied: true,
            objective_before: sol.objective,
            objective_after: r.objective,
            control_change: 0.0,
            note: how.into(),
        }),
    }))
}

/// `max |a - b|` over rows and components.
fn max_diff(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0_f64, |d, (x, y)| d.max((x - y).abs()))
}
