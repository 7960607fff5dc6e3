//! The exact projection onto a general polyhedron (`sweep::polyhedron`, theory §11) against a
//! generic QP solver, Clarabel (an interior-point method, independent of the active-set
//! method): `min (1/2)|x - v|^2` s.t. `<x*_j, x> <= c_j` on random polytopes. Clarabel's answer
//! is accurate to its tolerances; ours is exact (the KKT system of its active set).

mod common;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};
use common::Rng;
use crawlopt::model::general::Polyhedron;
use crawlopt::sweep::PolyProjector;

/// `rows` (dense, one per constraint) as a compressed-column matrix.
fn csc(rows: &[Vec<f64>], n: usize) -> CscMatrix<f64> {
    let (mut colptr, mut rowval, mut nzval) = (vec![0], vec![], vec![]);
    for k in 0..n {
        for (i, r) in rows.iter().enumerate() {
            if r[k] != 0.0 {
                rowval.push(i);
                nzval.push(r[k]);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows.len(), n, colptr, rowval, nzval)
}

/// `Proj_C(v)` and the multipliers by Clarabel.
fn project_qp(c: &Polyhedron, v: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = v.len();
    let p = CscMatrix::identity(n);
    let q: Vec<f64> = v.iter().map(|a| -a).collect();
    let a = csc(&c.normals, n);
    let settings = DefaultSettings {
        verbose: false,
        tol_gap_abs: 1e-10,
        tol_gap_rel: 1e-10,
        tol_feas: 1e-10,
        ..Default::default()
    };
    let cones = [NonnegativeConeT(c.faces())];
    let mut s = DefaultSolver::new(&p, &q, &a, &c.offsets, &cones, settings).unwrap();
    s.solve();
    assert_eq!(s.solution.status, SolverStatus::Solved);
    (s.solution.x.clone(), s.solution.z.clone())
}

#[test]
fn the_projection_agrees_with_a_generic_qp_solver_on_random_polytopes() {
    let mut rng = Rng(0xd1b5_4a32_d192_ed03);
    let mut active = 0;
    let mut cases = 0;
    for n in [2usize, 3, 5, 10] {
        for sigma in (n + 1)..=(2 * n).max(8) {
            for _ in 0..4 {
                let normals = (0..sigma)
                    .map(|_| (0..n).map(|_| rng.range(-1.0, 1.0)).collect())
                    .collect();
                let offsets = (0..sigma).map(|_| rng.range(0.3, 2.0)).collect();
                let c = Polyhedron::new(normals, offsets, "C").unwrap();
                let mut proj = PolyProjector::new(c.clone());
                let mut x = vec![0.0; n];
                for _ in 0..4 {
                    let v: Vec<f64> = (0..n).map(|_| rng.range(-4.0, 4.0)).collect();
                    let a = proj.project(&x, &v).unwrap();
                    let scale = v.iter().fold(2.0_f64, |m, t| m.max(t.abs()));
                    // Ours is exact: the KKT residual of its active set.
                    assert!(a.residual <= 1e-12 * scale, "KKT residual {}", a.residual);
                    // Clarabel's to its tolerances (1e-10 on gap and feasibility: about 1e-7
                    // on x and the multipliers near degenerate faces).
                    let (xq, zq) = project_qp(&c, &v);
                    for i in 0..n {
                        assert!(
                            (a.x[i] - xq[i]).abs() <= 1e-7 * scale,
                            "n = {n}, sigma = {sigma}: {:?} vs {xq:?}",
                            a.x
                        );
                    }
                    for j in 0..sigma {
                        assert!(
                            (a.mu[j] - zq[j]).abs() <= 1e-6 * scale,
                            "n = {n}, sigma = {sigma}, face {j}: {} vs {}",
                            a.mu[j],
                            zq[j]
                        );
                    }
                    active += usize::from(!a.active.is_empty());
                    cases += 1;
                    x = a.x;
                }
            }
        }
    }
    // Most points lie outside C: the projections hold faces.
    assert!(active * 2 > cases, "{active} of {cases}");
}
