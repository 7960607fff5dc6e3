//! Polishing a phase gait of a quadratic cost on its own pattern of held faces, for (P) and
//! every instance of it (a crawler's phase gait is polished here on its instance,
//! `optimal::phase::polish`): the outer approximation leaves a rate off the bounds of U only
//! as accurate as its cuts, and the necessary conditions fail at that size.
//!
//! With the faces held on each phase fixed, the phase problem ([`super::phase`]) is convex in
//! the durations `tau_j`, the increments `U_j`, the states and the integrated reactions
//! `L_{j,f}`: the dynamics `x_{j+1} - x_j - B U_j - b tau_j + sum_f L_{j,f} x*_f = 0`, C at every
//! knot, a held face at both ends of its phase, `U_j in tau_j U`, zero mean and `sum tau = T`
//! are linear, and the cost `tau f2(U / tau) = (1/2) |S U|^2 / tau` (`R = S^T S`) is a sum of
//! perspectives, one rotated second-order cone per row of `S` (Clarabel, then Newton's method on
//! the active set, [`crate::optimal::polish`]). Every feasible point is an exact gait of (P)
//! (the phase formulation's argument), and the MILP's is one of them, so the optimum is no
//! worse; the caller replays it and keeps it when the replay agrees and `J` is no worse.

use super::discrete::{big_m, cost_matrix};
use super::geometry::Geometry;
use crate::model::general::{Boundary, ControlSet, GeneralProblem};
use crate::optimal::polish::Qp;

/// A solver's phase gait: the phases of positive duration, in time order.
#[derive(Debug, Clone, Default)]
pub(crate) struct MilpPhases {
    pub durations: Vec<f64>,
    /// `U_j = tau_j u_j`.
    pub increments: Vec<Vec<f64>>,
    /// States at the phase starts and the end.
    pub states: Vec<Vec<f64>>,
    /// Faces held per phase (1-based).
    pub held: Vec<Vec<usize>>,
    /// Integrated reactions `L_{j,f}` per phase and face.
    pub integrated: Vec<Vec<f64>>,
}

/// The best gait on the held faces `held` (1-based, per phase) of a gait of phases `durations`
/// (module docs), as a solver's phases without those of at most `empty` times `T`; `None`
/// without a cost or when the convex problem finds no solution. The reactions' rates are
/// bounded by the phase MILP's big-M (from C's and U's geometry).
pub(super) fn polish_general_phases(
    p: &GeneralProblem,
    g: &Geometry,
    durations: &[f64],
    held: &[Vec<usize>],
    empty: f64,
) -> Option<MilpPhases> {
    let multiplier = big_m(p, g, 1.0).ok()?.multiplier;
    polish_phases_within(p, &vec![multiplier; p.c.faces()], durations, held, empty)
}

/// [`polish_general_phases`] with the rate of the reaction on face `f` bounded by
/// `rate_bounds[f]` (`L_{j,f} <= rate_bounds[f] tau_j`: no reaction in zero time), the bound a
/// phase MILP of the problem's structure imposes: (P)'s big-M, or on a crawler's instance its
/// block speed bound in the face's units (`optimal::phase::polish`).
pub(crate) fn polish_phases_within(
    p: &GeneralProblem,
    rate_bounds: &[f64],
    durations: &[f64],
    held: &[Vec<usize>],
    empty: f64,
) -> Option<MilpPhases> {
    let r = cost_matrix(&p.cost, p.controls())?;
    // After the deadline the MILP's answer stands (the polish is not part of the limit).
    if crate::progress::out_of_time().unwrap_or(true) {
        return None;
    }
    let (n, m, sigma, pieces) = (p.states(), p.controls(), p.c.faces(), durations.len());
    let t = p.period;
    let inf = f64::INFINITY;
    let w = p.face_weights();
    let rows_s = cost_rows(&r, m)?;
    let mut qp = Qp::default();
    let cols = phase_columns(&mut qp, p, pieces, held, &w, rate_bounds);
    let (tau, x, u, lam, knots) = (&cols.tau, &cols.x, &cols.u, &cols.lam, cols.knots);
    let face_row = |x: &[usize], f: usize| -> Vec<(usize, f64)> {
        x.iter()
            .zip(&p.c.normals[f])
            .map(|(&c, &a)| (c, a))
            .collect()
    };
    for j in 0..pieces {
        let (xj, xn) = (&x[j], &x[(j + 1) % knots]);
        for row in 0..n {
            let mut entries = vec![(xn[row], 1.0), (xj[row], -1.0)];
            for c in 0..m {
                entries.push((u[j][c], -p.dynamics.b[row][c]));
            }
            entries.push((tau[j], -p.dynamics.drift[row]));
            for &(f, l) in &lam[j] {
                entries.push((l, p.c.normals[f][row]));
            }
            qp.add_row(0.0, 0.0, entries);
        }
        for &(f, l) in &lam[j] {
            let c = p.c.offsets[f];
            qp.add_row(c, c, face_row(xj, f));
            qp.add_row(c, c, face_row(xn, f));
            qp.add_row(-inf, 0.0, vec![(l, 1.0), (tau[j], -rate_bounds[f])]);
        }
        match &p.control {
            ControlSet::Box { lower, upper } => {
                for c in 0..m {
                    qp.add_row(-inf, 0.0, vec![(u[j][c], 1.0), (tau[j], -upper[c])]);
                    qp.add_row(0.0, inf, vec![(u[j][c], 1.0), (tau[j], -lower[c])]);
                }
            }
            ControlSet::Polytope(set) => {
                for f in 0..set.faces() {
                    let mut row: Vec<(usize, f64)> = u[j]
                        .iter()
                        .zip(&set.normals[f])
                        .map(|(&c, &a)| (c, a))
                        .collect();
                    row.push((tau[j], -set.offsets[f]));
                    qp.add_row(-inf, 0.0, row);
                }
            }
        }
        // (1/2) |S U|^2 / tau: v_k = (S U)_k, v_k^2 <= e_k tau, cost e_k / 2.
        for srow in &rows_s {
            let v = qp.add_column(0.0, -inf, inf);
            let e = qp.add_column(0.5, 0.0, inf);
            let mut entries: Vec<(usize, f64)> =
                u[j].iter().zip(srow).map(|(&c, &a)| (c, a)).collect();
            entries.push((v, -1.0));
            qp.add_row(0.0, 0.0, entries);
            qp.add_perspective(v, e, tau[j]);
        }
    }
    for xk in x {
        for f in 0..sigma {
            qp.add_row(-inf, p.c.offsets[f], face_row(xk, f));
        }
    }
    qp.add_row(t, t, tau.iter().map(|&c| (c, 1.0)).collect());
    if p.zero_mean {
        for c in 0..m {
            qp.add_row(0.0, 0.0, u.iter().map(|r| (r[c], 1.0)).collect());
        }
    }
    let sol = qp.solve("the general phase gait's polish").ok()?;
    Some(solved_phases(&sol.v, &cols, held, sigma, empty, t))
}

/// The rows of `S` with `R = S^T S`: the eigenvectors scaled by the square roots of `R`'s
/// eigenvalues (those above `1e-14` of the largest); one rotated cone per row (module docs).
/// `None` when the eigendecomposition fails.
fn cost_rows(r: &[Vec<f64>], m: usize) -> Option<Vec<Vec<f64>>> {
    let eig = crate::linalg::symmetric_eigen(nalgebra::DMatrix::from_fn(m, m, |i, k| r[i][k]))?;
    Some(
        (0..m)
            .filter(|&k| eig.eigenvalues[k] > 1e-14 * eig.eigenvalues.amax())
            .map(|k| {
                let s = eig.eigenvalues[k].sqrt();
                (0..m).map(|i| s * eig.eigenvectors[(i, k)]).collect()
            })
            .collect(),
    )
}

/// The polish's columns (module docs): durations `tau_j`, the states at the knots (`x_0`
/// fixed for a Cauchy problem, the last knot the first when periodic), increments `U_j` and
/// the integrated reactions `L_{j,f}` on the held faces only, `(face, column)` per phase.
struct PhaseColumns {
    tau: Vec<usize>,
    x: Vec<Vec<usize>>,
    u: Vec<Vec<usize>>,
    lam: Vec<Vec<(usize, usize)>>,
    knots: usize,
}

/// Adds the [`PhaseColumns`] of `pieces` phases holding `held` (1-based) to `qp`: `L_{j,f}`
/// costs `-w_f` and is at most `rate_bounds[f] T`.
fn phase_columns(
    qp: &mut Qp,
    p: &GeneralProblem,
    pieces: usize,
    held: &[Vec<usize>],
    w: &[f64],
    rate_bounds: &[f64],
) -> PhaseColumns {
    let (n, m, t, inf) = (p.states(), p.controls(), p.period, f64::INFINITY);
    let tau: Vec<usize> = (0..pieces).map(|_| qp.add_column(0.0, 0.0, t)).collect();
    let knots = match p.boundary {
        Boundary::Periodic => pieces,
        Boundary::Initial(_) => pieces + 1,
    };
    let x: Vec<Vec<usize>> = (0..knots)
        .map(|i| match &p.boundary {
            Boundary::Initial(x0) if i == 0 => {
                x0.iter().map(|&v| qp.add_column(0.0, v, v)).collect()
            }
            _ => (0..n).map(|_| qp.add_column(0.0, -inf, inf)).collect(),
        })
        .collect();
    let u: Vec<Vec<usize>> = (0..pieces)
        .map(|_| (0..m).map(|_| qp.add_column(0.0, -inf, inf)).collect())
        .collect();
    // Integrated reactions on the held faces only.
    let lam: Vec<Vec<(usize, usize)>> = held
        .iter()
        .map(|h| {
            h.iter()
                .map(|&f| (f - 1, qp.add_column(-w[f - 1], 0.0, rate_bounds[f - 1] * t)))
                .collect()
        })
        .collect();
    PhaseColumns {
        tau,
        x,
        u,
        lam,
        knots,
    }
}

/// The polished gait read off the solution `v` as a solver's phases, dropping those of at most
/// `empty` times the period `t` (their increments and reactions vanish with them).
fn solved_phases(
    v: &[f64],
    cols: &PhaseColumns,
    held: &[Vec<usize>],
    sigma: usize,
    empty: f64,
    t: f64,
) -> MilpPhases {
    let (tau, x, u, lam, knots) = (&cols.tau, &cols.x, &cols.u, &cols.lam, cols.knots);
    let val = |c: usize| v[c];
    let mut out = MilpPhases {
        states: vec![x[0].iter().map(|&c| val(c)).collect()],
        ..MilpPhases::default()
    };
    for j in 0..tau.len() {
        let d = val(tau[j]);
        if d <= empty * t {
            continue;
        }
        out.durations.push(d);
        out.increments.push(u[j].iter().map(|&c| val(c)).collect());
        out.held.push(held[j].clone());
        let mut integrated = vec![0.0; sigma];
        for &(f, l) in &lam[j] {
            // Non-negative as in the MILP's reading (Clarabel meets `L >= 0` to its tolerance).
            integrated[f] = val(l).max(0.0);
        }
        out.integrated.push(integrated);
        out.states
            .push(x[(j + 1) % knots].iter().map(|&c| val(c)).collect());
    }
    out
}
