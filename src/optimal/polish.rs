//! Polishing a P_m answer: the convex QP of P_m on a fixed complementarity pattern, solved to
//! the solvers' resolution.
//!
//! With a quadratic cost `f2`, the MILPs of P_m (the crawler's, `optimal::discrete`,
//! and the general problem's, [`crate::optimal::general::discrete`]) carry `f2` by an outer
//! approximation: tangent cuts, refined until the incumbent's true objective meets the bound
//! to `optimal::milp::OA_TOL`. A control not at a bound of U is then only
//! accurate to about the cuts' spacing (1e-3 on the examples), and the discrete necessary
//! conditions (Theorem 6.2 (pw): `-B^T p - omega - lambda Df2(u)` in `N_U(u)`) fail at that
//! size although the answer is the MILP's optimum to its gap.
//!
//! With the discrete complementarity fixed (which faces hold, or which blocks slip which way,
//! at every step), P_m is a convex QP: linear dynamics, linear reward, the quadratic cost. Its
//! feasible set holds the MILP's answer, so its optimum is no worse; and every feasible point of
//! it is a feasible point of P_m (the KKT system of the catching-up projection with its signs
//! on the fixed pattern). Each formulation describes that QP as a `Qp` (columns with bounds,
//! rows with ranges, a quadratic and a linear objective, minimised); `Qp::solve` solves it
//! by Clarabel (an interior-point method) and then exactly on the active set Clarabel finds
//! (the KKT system of the equality-constrained QP, dense), keeping the exact point when it is
//! feasible and no worse. The caller replays the polished controls in the simulator, as every
//! optimiser answer, and keeps the polished answer only when the replayed objective is no
//! worse than the MILP's ([`PolishRecord`] says what happened).

use crate::error::{Error, Result};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT, SolverStatus,
    SupportedConeT, ZeroConeT,
};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Polishing is on unless a setting turns it off (`GeneralPmSettings::polish`,
/// `OptimizeSettings::polish`).
pub const POLISH_DEFAULT: bool = true;

/// Largest KKT system (columns plus equality and active rows) solved densely for the exact
/// point; above it the interior-point answer is kept (a dense LU of this size takes about a
/// second).
pub(crate) const MAX_EXACT_KKT: usize = 2500;

/// What polishing did to a P_m answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PolishRecord {
    /// Whether the polished answer replaced the MILP's.
    pub applied: bool,
    /// `J` of the MILP's answer, as the simulator replays it.
    pub objective_before: f64,
    /// `J` of the returned answer, as the simulator replays it (the MILP's when not applied).
    pub objective_after: f64,
    /// `max |u_polished - u_milp|` over steps and components (0 when not applied).
    pub control_change: f64,
    /// How the QP was solved, or why the MILP's answer was kept.
    pub note: String,
}

impl PolishRecord {
    /// The record of an answer kept as the MILP gave it, with the reason.
    pub fn kept(objective: f64, note: impl Into<String>) -> Self {
        PolishRecord {
            applied: false,
            objective_before: objective,
            objective_after: objective,
            control_change: 0.0,
            note: note.into(),
        }
    }
}

/// Whether a polished objective may replace the MILP's: no worse, to the rounding of the
/// replays (`1e-9` relative above the problem's floor of `J`, in units of it below).
pub(crate) fn no_worse(polished: f64, milp: f64, floor: f64) -> bool {
    polished >= milp - 1e-9 * milp.abs().max(floor)
}

/// A row `lo <= sum a_k v_k <= hi`.
#[derive(Debug, Clone)]
struct Row {
    entries: Vec<(usize, f64)>,
    lo: f64,
    hi: f64,
}

/// A convex QP over a column vector `v`: minimise `(1/2) v^T P v + q^T v` subject to column
/// bounds `lo_k <= v_k <= hi_k` and rows `lo <= a v <= hi` (infinite bounds allowed; equal
/// bounds an equality). `P` must be positive semidefinite (the caller's cost is convex).
#[derive(Debug, Clone, Default)]
pub(crate) struct Qp {
    q: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Entries of `P`, `(i, j)` with `i <= j`, summed.
    p: BTreeMap<(usize, usize), f64>,
    rows: Vec<Row>,
    /// Perspective cones `(u, g, tau)`: `u^2 <= g tau` with `g, tau >= 0`.
    cones: Vec<(usize, usize, usize)>,
}

/// The solution of a [`Qp`].
#[derive(Debug, Clone)]
pub(crate) struct QpSolution {
    /// `v`.
    pub v: Vec<f64>,
    /// Whether `v` is the exact solution of the KKT system on the active set (else Clarabel's).
    pub exact: bool,
}

/// One constraint in Clarabel's form `a v + s = b`, `s` in its cone.
struct Conic {
    entries: Vec<(usize, f64)>,
    b: f64,
}

impl Qp {
    /// Adds a column of linear cost `cost` and bounds `lo..=hi`; returns its index.
    pub fn add_column(&mut self, cost: f64, lo: f64, hi: f64) -> usize {
        self.q.push(cost);
        self.lo.push(lo);
        self.hi.push(hi);
        self.q.len() - 1
    }

    /// Adds the row `lo <= sum a_k v_k <= hi`.
    pub fn add_row(&mut self, lo: f64, hi: f64, entries: Vec<(usize, f64)>) {
        self.rows.push(Row { entries, lo, hi });
    }

    /// Adds `value` to the entries `(i, j)` and `(j, i)` of the symmetric `P` (once when `i = j`).
    pub fn add_quadratic(&mut self, i: usize, j: usize, value: f64) {
        if value != 0.0 {
            *self.p.entry((i.min(j), i.max(j))).or_insert(0.0) += value;
        }
    }

    /// Adds the perspective cone `v_u^2 <= v_g v_tau` (`v_g, v_tau >= 0`), the epigraph of a
    /// perspective `u^2 / tau` (a rotated second-order cone: Clarabel's second-order cone on
    /// `(v_g + v_tau, v_g - v_tau, 2 v_u)`). With cones the exact step on the active set is
    /// Newton's method on its KKT system ([`Self::newton_on`]).
    pub fn add_perspective(&mut self, u: usize, g: usize, tau: usize) {
        self.cones.push((u, g, tau));
    }

    /// Number of columns.
    pub fn columns(&self) -> usize {
        self.q.len()
    }

    /// `(1/2) v^T P v + q^T v`.
    pub fn objective(&self, v: &[f64]) -> f64 {
        let quad: f64 = self
            .p
            .iter()
            .map(|(&(i, j), &a)| {
                if i == j {
                    0.5 * a * v[i] * v[i]
                } else {
                    a * v[i] * v[j]
                }
            })
            .sum();
        quad + self.q.iter().zip(v).map(|(q, v)| q * v).sum::<f64>()
    }

    /// The constraints as Clarabel's equalities and inequalities (`a v <= b`).
    fn conic(&self) -> (Vec<Conic>, Vec<Conic>) {
        let (mut eq, mut le) = (Vec::new(), Vec::new());
        let mut put = |entries: Vec<(usize, f64)>, lo: f64, hi: f64| {
            if lo == hi {
                eq.push(Conic { entries, b: hi });
                return;
            }
            if hi.is_finite() {
                le.push(Conic {
                    entries: entries.clone(),
                    b: hi,
                });
            }
            if lo.is_finite() {
                le.push(Conic {
                    entries: entries.iter().map(|&(k, a)| (k, -a)).collect(),
                    b: -lo,
                });
            }
        };
        for k in 0..self.columns() {
            put(vec![(k, 1.0)], self.lo[k], self.hi[k]);
        }
        for r in &self.rows {
            put(r.entries.clone(), r.lo, r.hi);
        }
        (eq, le)
    }

    /// Solves the QP (module docs); `what` names it in errors. An error when Clarabel finds no
    /// solution (an infeasible pattern, or numerical trouble).
    pub fn solve(&self, what: &str) -> Result<QpSolution> {
        let n = self.columns();
        let (eq, le) = self.conic();
        // Each cone as `s = -A v` in Clarabel's second-order cone of dimension 3.
        let cone_rows: Vec<Conic> = self
            .cones
            .iter()
            .flat_map(|&(u, g, tau)| {
                [
                    vec![(g, -1.0), (tau, -1.0)],
                    vec![(g, -1.0), (tau, 1.0)],
                    vec![(u, -2.0)],
                ]
            })
            .map(|entries| Conic { entries, b: 0.0 })
            .collect();
        let all: Vec<&Conic> = eq.iter().chain(&le).chain(&cone_rows).collect();
        let a = csc(&all, n);
        let b: Vec<f64> = all.iter().map(|c| c.b).collect();
        let (pi, pj, pv): (Vec<usize>, Vec<usize>, Vec<f64>) = {
            let mut cols: Vec<(usize, usize, f64)> =
                self.p.iter().map(|(&(i, j), &v)| (j, i, v)).collect();
            cols.sort_by_key(|&(j, i, _)| (j, i));
            (
                cols.iter().map(|c| c.1).collect(),
                cols.iter().map(|c| c.0).collect(),
                cols.iter().map(|c| c.2).collect(),
            )
        };
        let p = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
        let mut cones: Vec<SupportedConeT<f64>> =
            vec![ZeroConeT(eq.len()), NonnegativeConeT(le.len())];
        cones.extend(self.cones.iter().map(|_| SecondOrderConeT(3)));
        let settings = DefaultSettings {
            verbose: false,
            tol_gap_abs: 1e-10,
            tol_gap_rel: 1e-10,
            tol_feas: 1e-10,
            max_iter: 400,
            ..Default::default()
        };
        let mut s = DefaultSolver::new(&p, &self.q, &a, &b, &cones, settings)
            .map_err(|e| Error::Numerical(format!("{what}: the QP solver refused it ({e})")))?;
        s.solve();
        let sol = &s.solution;
        if !matches!(
            sol.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        ) {
            return Err(Error::Numerical(format!(
                "{what}: no solution of the QP on the fixed pattern ({:?})",
                sol.status
            )));
        }
        let interior = sol.x.clone();
        // The active set: the inequalities whose slack is below their multiplier.
        let active: Vec<&Conic> = le
            .iter()
            .enumerate()
            .filter(|&(k, _)| sol.s[eq.len() + k] <= sol.z[eq.len() + k])
            .map(|(_, c)| c)
            .collect();
        let exact = if self.cones.is_empty() {
            self.exact_on(&eq, &active, n)
        } else {
            self.newton_on(&eq, &active, &interior)
        };
        // The exact point must be feasible and no worse than the interior-point answer, which
        // may lie below the optimum by its own infeasibility: to its tolerance for a QP, but
        // only about its square root with cones (measured: 1.4e-7 relative on one link with a
        // quadratic cost, where a margin of 1e-9 kept the inexact answer and it `fails`).
        let margin = if self.cones.is_empty() { 1e-9 } else { 1e-6 };
        let exact = exact.filter(|v| {
            let reference = self.objective(&interior);
            self.feasible(v) && self.objective(v) <= reference + margin * reference.abs().max(1.0)
        });
        Ok(match exact {
            Some(v) => QpSolution { v, exact: true },
            None => QpSolution {
                v: interior,
                exact: false,
            },
        })
    }

    /// The minimiser of the objective on `{eq, active}` as equalities: the KKT system
    /// `[P E^T; E 0] [v; y] = [-q; e]`, dense (LU, then least squares by SVD when singular);
    /// `None` when too large or without a consistent solution.
    fn exact_on(&self, eq: &[Conic], active: &[&Conic], n: usize) -> Option<Vec<f64>> {
        let rows: Vec<&Conic> = eq.iter().chain(active.iter().copied()).collect();
        let dim = n + rows.len();
        if dim > MAX_EXACT_KKT {
            return None;
        }
        let mut k = DMatrix::<f64>::zeros(dim, dim);
        for (&(i, j), &a) in &self.p {
            k[(i, j)] += a;
            if i != j {
                k[(j, i)] += a;
            }
        }
        let mut rhs = DVector::<f64>::zeros(dim);
        for (i, q) in self.q.iter().enumerate() {
            rhs[i] = -q;
        }
        for (r, c) in rows.iter().enumerate() {
            for &(j, a) in &c.entries {
                k[(n + r, j)] += a;
                k[(j, n + r)] += a;
            }
            rhs[n + r] = c.b;
        }
        let norm = k.amax().max(rhs.amax()).max(1e-300);
        let close = |x: &DVector<f64>| (&k * x - &rhs).amax() <= 1e-11 * norm * x.amax().max(1.0);
        if let Some(x) = k.clone().lu().solve(&rhs).filter(|x| close(x)) {
            return Some(x.rows(0, n).iter().copied().collect());
        }
        if dim > MAX_EXACT_KKT / 4 {
            return None;
        }
        let x = crate::linalg::svd(k.clone(), true, true)?
            .solve(&rhs, 1e-12 * norm)
            .ok()?;
        close(&x).then(|| x.rows(0, n).iter().copied().collect())
    }

    /// The minimiser on `{eq, active}` as equalities with the cones as equalities `u^2 = g tau`
    /// (each held at the interior-point answer `v0` wherever `tau > 0`; a cone whose `tau`
    /// vanishes is `u = g = tau = 0`): Newton's method on that KKT system from `v0`, the
    /// multipliers started by least squares, dense; `None` when too large, singular or not
    /// converged to the rounding of its data. The interior-point answer of a flat objective
    /// (a perspective's minimum) is only accurate to about the square root of its tolerance;
    /// this step makes it exact, as [`Self::exact_on`] does for a QP.
    fn newton_on(&self, eq: &[Conic], active: &[&Conic], v0: &[f64]) -> Option<Vec<f64>> {
        let n = self.columns();
        let scale = v0.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        let (live, flat): (Vec<_>, Vec<_>) = self
            .cones
            .iter()
            .partition(|&&(_, _, tau)| v0[tau] > 1e-9 * scale);
        let mut rows: Vec<(Vec<(usize, f64)>, f64)> = eq
            .iter()
            .chain(active.iter().copied())
            .map(|c| (c.entries.clone(), c.b))
            .collect();
        for &(u, g, tau) in &flat {
            rows.extend([u, g, tau].map(|c| (vec![(c, 1.0)], 0.0)));
        }
        if n + rows.len() > 2 * MAX_EXACT_KKT {
            return None;
        }
        // Redundant rows (a held face's equality beside its active range, the rate rows and
        // `tau = 0` of an empty piece) would make the KKT system singular.
        let rows = independent_rows(rows, n);
        let sys = NewtonKkt {
            qp: self,
            m: rows.len(),
            rows,
            live,
            n,
        };
        let dim = sys.dim();
        // Dense, up to a quarter of MAX_EXACT_KKT: the multipliers' least squares below needs
        // an SVD, which costs seconds beyond that (as in `exact_on`).
        if dim > MAX_EXACT_KKT / 4 || crate::progress::out_of_time().unwrap_or(true) {
            return None;
        }
        let mut v = v0.to_vec();
        // Multipliers: least squares of grad + J^T w = 0 at v0.
        let jt = sys.jacobian(&v).transpose();
        let mut w = crate::linalg::svd(jt.clone(), true, true)?
            .solve(&(-sys.grad(&v)), 1e-12 * jt.amax().max(1e-300))
            .ok()?;
        let (m, nc) = (sys.m, sys.live.len());
        for _ in 0..30 {
            // Within the job's deadline and cancellation: the answer then stays Clarabel's.
            if crate::progress::out_of_time().unwrap_or(true) {
                return None;
            }
            let step = sys.step(&v, &w)?;
            // A step (or its half, or quarter) is taken only if it lowers the KKT residual:
            // where the optimum is not unique (a flat objective along a face: one link with a
            // quadratic cost, two pieces of the same rate) the system is singular at it, and a
            // step solved from it can throw a converged point far away (measured: 5e-5, then
            // 0.46); the iteration then stops where it is.
            let now = sys.residual_max(&v, &w);
            let taken = [1.0, 0.5, 0.25].into_iter().find_map(|alpha| {
                let mut next = v.clone();
                for (x, d) in next.iter_mut().zip(step.rows(0, n).iter()) {
                    *x += alpha * d;
                }
                let next_w = &w + alpha * step.rows(n, m + nc);
                (sys.residual_max(&next, &next_w) < now).then_some((next, next_w, alpha))
            });
            let Some((next, next_w, alpha)) = taken else {
                break;
            };
            (v, w) = (next, next_w);
            if alpha * step.rows(0, n).amax() <= 1e-15 * scale {
                break;
            }
        }
        let cones_hold = self
            .cones
            .iter()
            .all(|&(u, g, tau)| v[u] * v[u] <= v[g] * v[tau] + 1e-12 * scale * scale);
        let stationary = (sys.grad(&v) + sys.jacobian(&v).transpose() * &w).amax()
            <= 1e-9 * sys.grad(v0).amax().max(1.0);
        (cones_hold && stationary && v.iter().all(|x| x.is_finite())).then_some(v)
    }

    /// Whether `v` satisfies every bound and row to `1e-10` of the row's size.
    fn feasible(&self, v: &[f64]) -> bool {
        let ok = |value: f64, size: f64, lo: f64, hi: f64| {
            let tol = 1e-10 * (1.0 + size + lo.abs().min(hi.abs()));
            value >= lo - tol && value <= hi + tol
        };
        let cols = v
            .iter()
            .enumerate()
            .all(|(k, &x)| x.is_finite() && ok(x, x.abs(), self.lo[k], self.hi[k]));
        cols && self.rows.iter().all(|r| {
            let value: f64 = r.entries.iter().map(|&(k, a)| a * v[k]).sum();
            let size: f64 = r.entries.iter().map(|&(k, a)| (a * v[k]).abs()).sum();
            ok(value, size, r.lo, r.hi)
        })
    }
}

/// The KKT system that [`Qp::newton_on`] solves by Newton's method: the QP's objective, the
/// independent equality `rows` (`m` of them) and the `live` cones held as `u^2 = g tau`, over
/// `n` columns; the unknowns are `v`, then the rows' multipliers, then the cones'.
struct NewtonKkt<'a> {
    qp: &'a Qp,
    rows: Vec<(Vec<(usize, f64)>, f64)>,
    live: Vec<(usize, usize, usize)>,
    n: usize,
    m: usize,
}

impl NewtonKkt<'_> {
    /// The size of the system: columns, rows and live cones.
    fn dim(&self) -> usize {
        self.n + self.m + self.live.len()
    }

    /// The objective's gradient `P v + q` at `v`.
    fn grad(&self, v: &[f64]) -> DVector<f64> {
        let mut g = DVector::from_column_slice(&self.qp.q);
        for (&(i, j), &a) in &self.qp.p {
            g[i] += a * v[j];
            if i != j {
                g[j] += a * v[i];
            }
        }
        g
    }

    /// The constraints' Jacobian at `v` (rows, then cones: d(u^2 - g tau) = (2u, -tau, -g)).
    fn jacobian(&self, v: &[f64]) -> DMatrix<f64> {
        let (m, nc) = (self.m, self.live.len());
        let mut j = DMatrix::<f64>::zeros(m + nc, self.n);
        for (r, (entries, _)) in self.rows.iter().enumerate() {
            for &(c, a) in entries {
                j[(r, c)] += a;
            }
        }
        for (k, &(u, g, tau)) in self.live.iter().enumerate() {
            j[(m + k, u)] += 2.0 * v[u];
            j[(m + k, g)] -= v[tau];
            j[(m + k, tau)] -= v[g];
        }
        j
    }

    /// The KKT residual at `(v, w)` (`jac` the Jacobian at `v`): stationarity `grad + J^T w`,
    /// then the rows' and the cones' values.
    fn residual(&self, v: &[f64], w: &DVector<f64>, jac: &DMatrix<f64>) -> DVector<f64> {
        let (n, m) = (self.n, self.m);
        let mut f = DVector::<f64>::zeros(self.dim());
        let stat = self.grad(v) + jac.transpose() * w;
        f.rows_mut(0, n).copy_from(&stat);
        for (r, (entries, b)) in self.rows.iter().enumerate() {
            f[n + r] = entries.iter().map(|&(c, a)| a * v[c]).sum::<f64>() - b;
        }
        for (c, &(u, g, tau)) in self.live.iter().enumerate() {
            f[n + m + c] = v[u] * v[u] - v[g] * v[tau];
        }
        f
    }

    /// The largest entry of [`Self::residual`] at `(v, w)`.
    fn residual_max(&self, v: &[f64], w: &DVector<f64>) -> f64 {
        self.residual(v, w, &self.jacobian(v)).amax()
    }

    /// One Newton step at `(v, w)`: the KKT matrix (the Lagrangian's Hessian, the Jacobian
    /// and its transpose) solved against the residual (stationarity, the rows, the cones) by
    /// LU, else by least squares; `None` when neither solves it.
    fn step(&self, v: &[f64], w: &DVector<f64>) -> Option<DVector<f64>> {
        let (n, m, nc, dim) = (self.n, self.m, self.live.len(), self.dim());
        let jac = self.jacobian(v);
        let mut k = DMatrix::<f64>::zeros(dim, dim);
        for (&(i, j), &a) in &self.qp.p {
            k[(i, j)] += a;
            if i != j {
                k[(j, i)] += a;
            }
        }
        for (c, &(u, g, tau)) in self.live.iter().enumerate() {
            // The cone's Hessian times its multiplier: 2 on (u, u), -1 on (g, tau).
            let z = w[m + c];
            k[(u, u)] += 2.0 * z;
            k[(g, tau)] -= z;
            k[(tau, g)] -= z;
        }
        k.view_mut((n, 0), (m + nc, n)).copy_from(&jac);
        k.view_mut((0, n), (n, m + nc)).copy_from(&jac.transpose());
        let f = self.residual(v, w, &jac);
        let norm = k.amax().max(1e-300);
        k.clone().lu().solve(&(-&f)).or_else(|| {
            crate::linalg::svd(k, true, true)?
                .solve(&(-&f), 1e-13 * norm)
                .ok()
        })
    }
}

/// A maximal linearly independent subset of `rows` (in order, by Gram-Schmidt on the dense
/// rows of `n` columns, a row dropped when its residual is below `1e-10` of its norm); the
/// rows come from a feasible point, so those dropped are implied by those kept.
fn independent_rows(
    rows: Vec<(Vec<(usize, f64)>, f64)>,
    n: usize,
) -> Vec<(Vec<(usize, f64)>, f64)> {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let mut kept = Vec::with_capacity(rows.len());
    for (entries, b) in rows {
        let mut r = DVector::<f64>::zeros(n);
        for &(c, a) in &entries {
            r[c] += a;
        }
        let size = r.norm();
        if size == 0.0 {
            continue;
        }
        for q in &basis {
            let d = q.dot(&r);
            r.axpy(-d, q, 1.0);
        }
        let rest = r.norm();
        if rest > 1e-10 * size {
            basis.push(r / rest);
            kept.push((entries, b));
        }
    }
    kept
}

/// The constraint rows as a compressed-column matrix.
fn csc(rows: &[&Conic], n: usize) -> CscMatrix<f64> {
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for (i, r) in rows.iter().enumerate() {
        let mut merged: BTreeMap<usize, f64> = BTreeMap::new();
        for &(j, a) in &r.entries {
            *merged.entry(j).or_insert(0.0) += a;
        }
        for (j, a) in merged {
            if a != 0.0 {
                cols[j].push((i, a));
            }
        }
    }
    let (mut colptr, mut rowval, mut nzval) = (vec![0], Vec::new(), Vec::new());
    for c in cols {
        for (i, a) in c {
            rowval.push(i);
            nzval.push(a);
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows.len(), n, colptr, rowval, nzval)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_qp_is_solved_exactly_on_its_active_set() {
        // min (1/2)(v0^2 + v1^2) - 3 v0 - v1 s.t. v0 + v1 = 1, v0 <= 0.75: the unconstrained
        // minimiser on the line is v0 = 1.5, cut by the bound to (0.75, 0.25).
        let mut qp = Qp::default();
        let a = qp.add_column(-3.0, f64::NEG_INFINITY, 0.75);
        let b = qp.add_column(-1.0, f64::NEG_INFINITY, f64::INFINITY);
        qp.add_quadratic(a, a, 1.0);
        qp.add_quadratic(b, b, 1.0);
        qp.add_row(1.0, 1.0, vec![(a, 1.0), (b, 1.0)]);
        let s = qp.solve("test").unwrap();
        assert!(s.exact);
        assert!((s.v[0] - 0.75).abs() <= 1e-14, "{:?}", s.v);
        assert!((s.v[1] - 0.25).abs() <= 1e-14, "{:?}", s.v);
    }

    #[test]
    fn a_perspective_cone_is_its_epigraph() {
        // min g - u s.t. u^2 <= g tau with tau = 0.5: g = 2 u^2 at the optimum, and 2 u^2 - u
        // is least at u = 1/4 (g = 1/8).
        let mut qp = Qp::default();
        let u = qp.add_column(-1.0, f64::NEG_INFINITY, f64::INFINITY);
        let g = qp.add_column(1.0, 0.0, f64::INFINITY);
        let tau = qp.add_column(0.0, 0.5, 0.5);
        qp.add_perspective(u, g, tau);
        let s = qp.solve("test").unwrap();
        assert!(s.exact);
        assert!((s.v[u] - 0.25).abs() <= 1e-15, "{:?}", s.v);
        assert!((s.v[g] - 0.125).abs() <= 1e-15, "{:?}", s.v);
    }

    #[test]
    fn an_infeasible_qp_is_an_error() {
        let mut qp = Qp::default();
        let a = qp.add_column(1.0, 0.0, 1.0);
        qp.add_quadratic(a, a, 1.0);
        qp.add_row(2.0, 3.0, vec![(a, 1.0)]);
        assert!(qp.solve("test").is_err());
    }
}
