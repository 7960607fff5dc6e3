//! The multiplier linear programs of the general problem's P_m (module docs of
//! [`crate::certify::general`] for the mathematics): the combinatorial structure of a process
//! (active faces, held faces, active rows of U) and the KKT system of its branch LP, solved by
//! HiGHS for multipliers that violate it least, in the stages of the crawler's certificate
//! ([`crate::certify`]: [`Stage`], [`Norm`], the same generic functional).

use super::general_process::{control_rows, GeneralProcess};
use super::kkt::{adjoint_columns, functional, norm_box, solve_multiplier_lp, Norm, Stage};
use crate::error::Result;
use crate::model::general::{dot, GeneralCost, GeneralProblem, Reward};
use highs::{Col, RowProblem};

/// The cost's Hessian `R` (`f2 = (1/2) u^T R u`; zero for `f2 = 0`).
pub(crate) fn cost_hessian(cost: &GeneralCost, m: usize) -> Vec<Vec<f64>> {
    let diag = |c: f64| {
        (0..m)
            .map(|i| (0..m).map(|k| if i == k { c } else { 0.0 }).collect())
            .collect()
    };
    match cost {
        GeneralCost::None => diag(0.0),
        GeneralCost::Quadratic { weight } => diag(*weight),
        GeneralCost::Matrix { matrix } => matrix.clone(),
    }
}

/// The coefficient `w_j` of `lambda_j` in `f1` (`<q, x*_j>` for reaction weights).
pub(crate) fn face_weights(p: &GeneralProblem) -> Vec<f64> {
    match &p.reward {
        Reward::FaceWeights(w) => w.clone(),
        Reward::ReactionWeights(q) => p.c.normals.iter().map(|n| dot(q, n)).collect(),
    }
}

/// What the KKT system needs besides the numbers.
pub(crate) struct GeneralStructure {
    /// States `n`, controls `m`, steps `M`.
    pub n: usize,
    pub m: usize,
    pub steps: usize,
    /// `h = T / M`.
    pub h: f64,
    /// Faces active at knot `k = 0..M-1` (knot `M` is knot 0), 0-based.
    pub active: Vec<Vec<usize>>,
    /// Whether the face is held (the step ending at knot `k` has a reaction on it): its
    /// multiplier is then free in the branch LP; otherwise the pair is biactive.
    pub held: Vec<Vec<bool>>,
    /// `c_j - <x*_j, x^k>` of each active face.
    pub slack: Vec<Vec<f64>>,
    /// Rows of U active at `u^i`, per step.
    pub urows_active: Vec<Vec<usize>>,
    /// Whether those rows span `R^m` (`u^i` a vertex of U).
    pub at_vertex: Vec<bool>,
    /// `R u^i` per step.
    pub grad_f2: Vec<Vec<f64>>,
    /// `w_j`.
    pub w: Vec<f64>,
    /// The rows of U.
    pub urows: Vec<(Vec<f64>, f64)>,
}

impl GeneralStructure {
    /// The structure of `pr` at relative tolerance `tol` (faces relative to C's scale, rows of
    /// U to U's, reactions `h lambda` to C's scale).
    pub fn of(p: &GeneralProblem, pr: &GeneralProcess, tol: f64) -> Self {
        let (n, m, steps) = (p.states(), p.controls(), pr.u.len());
        let h = p.period / steps as f64;
        let scale = p.c.scale();
        let (mut active, mut held, mut slack) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..steps {
            let prev = (k + steps - 1) % steps;
            let (mut a, mut hd, mut sl) = (Vec::new(), Vec::new(), Vec::new());
            for j in 0..p.c.faces() {
                let s = -p.c.slack(j, &pr.x[k]);
                if s <= tol * scale {
                    a.push(j);
                    hd.push(h * pr.lambda[prev][j] > tol * scale);
                    sl.push(s.max(0.0));
                }
            }
            active.push(a);
            held.push(hd);
            slack.push(sl);
        }
        let urows = control_rows(&p.control);
        let uscale = urows
            .iter()
            .fold(0.0_f64, |s, (_, h)| s.max(h.abs()))
            .max(1e-300);
        let (mut urows_active, mut at_vertex) = (Vec::new(), Vec::new());
        for u in &pr.u {
            let act: Vec<usize> = (0..urows.len())
                .filter(|&r| dot(&urows[r].0, u) >= urows[r].1 - tol * uscale)
                .collect();
            let mat = nalgebra::DMatrix::from_fn(act.len(), m, |i, k| urows[act[i]].0[k]);
            at_vertex.push(act.len() >= m && mat.rank(1e-9) == m);
            urows_active.push(act);
        }
        let r = cost_hessian(&p.cost, m);
        let grad_f2 =
            pr.u.iter()
                .map(|u| r.iter().map(|row| dot(row, u)).collect())
                .collect();
        GeneralStructure {
            n,
            m,
            steps,
            h,
            active,
            held,
            slack,
            urows_active,
            at_vertex,
            grad_f2,
            w: face_weights(p),
            urows,
        }
    }
}

/// Raw multipliers at the given `lambda`: `p_i` per step, `xi` per active face of every knot
/// (layout of [`GeneralStructure::active`]), `omega`, and the normal-cone weights `rho` of
/// `psi_i` on the active rows of U (layout of [`GeneralStructure::urows_active`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GeneralRaw {
    pub lambda: f64,
    pub p: Vec<Vec<f64>>,
    pub xi: Vec<Vec<f64>>,
    pub omega: Vec<f64>,
    pub rho: Vec<Vec<f64>>,
}

/// Solves one multiplier LP (`None` when HiGHS reports no optimum). `drift_term = false` drops
/// `h A^T p_k` from the adjoint equation: only for showing, in tests, that the term matters.
pub(crate) fn solve_general(
    p: &GeneralProblem,
    st: &GeneralStructure,
    lambda: f64,
    stage: Stage,
    norm: Option<Norm>,
    drift_term: bool,
) -> Result<Option<GeneralRaw>> {
    let (n, m, steps, h) = (st.n, st.m, st.steps, st.h);
    const INF: f64 = f64::INFINITY;
    let mut pb = RowProblem::default();
    let (pc, xi) = adjoint_columns(&mut pb, norm, steps, n, &st.active);
    let (box_, weight) = norm_box(norm);
    let om_box = if p.zero_mean { box_ } else { 0.0 };
    let omega: Vec<Col> = (0..m)
        .map(|l| pb.add_column(-weight * functional(steps, l), -om_box..=om_box))
        .collect();
    let rho: Vec<Vec<Col>> = st
        .urows_active
        .iter()
        .map(|a| a.iter().map(|_| pb.add_column(0.0, 0.0..=INF)).collect())
        .collect();
    let (r, s, delta) = stage.columns(&mut pb, norm);
    let a = &p.dynamics.a;
    // Adjoint with transversality (cyclic): p_k - p_{k-1} + h A^T p_k - sum xi_{k,f} x*_f = 0.
    for k in 0..steps {
        let prev = (k + steps - 1) % steps;
        for l in 0..n {
            // Coefficients of p_k and p_(k-1), merged (HiGHS refuses repeated columns in a row).
            let mut coef = vec![0.0; n];
            coef[l] = 1.0;
            if drift_term {
                for (q, arow) in a.iter().enumerate() {
                    coef[q] += h * arow[l];
                }
            }
            let mut row: Vec<(Col, f64)> = Vec::new();
            if prev == k {
                coef[l] -= 1.0;
            } else {
                row.push((pc[prev][l], -1.0));
            }
            row.extend(
                (0..n)
                    .filter(|&q| coef[q] != 0.0)
                    .map(|q| (pc[k][q], coef[q])),
            );
            for (fi, &f) in st.active[k].iter().enumerate() {
                let v = p.c.normals[f][l];
                if v != 0.0 {
                    row.push((xi[k][fi], -v));
                }
            }
            pb.add_row(0.0..=0.0, row);
        }
    }
    for i in 0..steps {
        // Reaction stationarity on the faces active at x^(i+1): lambda w_f + <p_i, x*_f>.
        let k = (i + 1) % steps;
        for (fi, &f) in st.active[k].iter().enumerate() {
            let lw = lambda * st.w[f];
            let dot_row = |extra: (Col, f64)| {
                let mut row: Vec<(Col, f64)> = (0..n)
                    .filter(|&l| p.c.normals[f][l] != 0.0)
                    .map(|l| (pc[i][l], p.c.normals[f][l]))
                    .collect();
                row.push(extra);
                row
            };
            pb.add_row(..=-lw, dot_row((r, -1.0)));
            if st.held[k][fi] {
                pb.add_row(-lw.., dot_row((r, 1.0)));
            } else {
                // A biactive face: an inequality of the relaxed branch, xi <= 0 (up to r).
                pb.add_row(..=0.0, [(xi[k][fi], 1.0), (r, -1.0)]);
            }
        }
        // Weak maximality: psi = -B^T p_i - omega - lambda R u_i = sum rho G (up to r).
        for l in 0..m {
            let g = lambda * st.grad_f2[i][l];
            let mut row: Vec<(Col, f64)> = (0..n)
                .filter(|&q| p.dynamics.b[q][l] != 0.0)
                .map(|q| (pc[i][q], -p.dynamics.b[q][l]))
                .collect();
            row.push((omega[l], -1.0));
            for (ri, &rr) in st.urows_active[i].iter().enumerate() {
                let v = st.urows[rr].0[l];
                if v != 0.0 {
                    row.push((rho[i][ri], -v));
                }
            }
            let mut lo = row.clone();
            lo.push((r, 1.0));
            row.push((r, -1.0));
            pb.add_row(..=g, row);
            pb.add_row(g.., lo);
        }
        if st.at_vertex[i] {
            // Margin: psi in the interior of N_U(u_i), every weight at least delta.
            for &c in &rho[i] {
                pb.add_row(0.0.., [(c, 1.0), (delta, -1.0)]);
            }
        }
    }
    // Theorem 2.2 / 6.1 sign: xi >= -s.
    for row in &xi {
        for &c in row {
            pb.add_row(0.0.., [(c, 1.0), (s, 1.0)]);
        }
    }
    let Some(cols) = solve_multiplier_lp(pb, "certify: the general multiplier LP")? else {
        return Ok(None);
    };
    let val = |c: &Col| cols[c.index()];
    let vals = |rows: &Vec<Vec<Col>>| -> Vec<Vec<f64>> {
        rows.iter().map(|r| r.iter().map(val).collect()).collect()
    };
    Ok(Some(GeneralRaw {
        lambda,
        p: vals(&pc),
        xi: vals(&xi),
        omega: omega.iter().map(val).collect(),
        rho: vals(&rho),
    }))
}
