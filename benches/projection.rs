//! The exact projection onto a general polyhedron (`sweep::polyhedron`, theory §11) against the
//! dedicated crawler projection (`sweep::Projector`) on the same catching-up steps: a crawler of
//! n links (N = n + 1 blocks, sigma = 2N faces), k = 1, mu+ = 1, mu- = 3.3, under the travelling
//! sine `L_l = 2 sin(2 pi t - l pi/2)`, 200 steps a period, from the periodic orbit; the general
//! projector works on the crawler's general form (`model::crawler_as_general`), warm-started
//! like the crawler's; the general form's projector chosen by its structure (`sweep::OntoC`:
//! the crawler's projection behind the general interface, the price of the change of variables
//! and of the general answer); and a generic QP solver, Clarabel (interior point, a fresh solve per
//! step from the same matrices: it has no warm start), on the same general form.
//! `cargo bench --bench projection`; throughput in steps per second.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT};
use crawlopt::integrate::{Actuation, Waveform};
use crawlopt::model::crawler_as_general;
use crawlopt::model::general::GeneralCost;
use crawlopt::sweep::{OntoC, PolyProjector, Projector};
use crawlopt::Crawler;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;

const M: usize = 200;

/// The increments `K (L(t_(i+1)) - L(t_i))` of one period.
fn increments(c: &Crawler) -> Vec<Vec<f64>> {
    let n = c.links();
    let act = Actuation::wave(
        Waveform::Sine,
        1.0,
        vec![0.0; n],
        vec![2.0; n],
        (0..n).map(|l| 90.0 * l as f64).collect(),
    )
    .unwrap();
    let (mut l0, mut l1) = (vec![0.0; n], vec![0.0; n]);
    (0..M)
        .map(|i| {
            act.lengths_at(i as f64 / M as f64, &mut l0);
            act.lengths_at((i + 1) as f64 / M as f64, &mut l1);
            (0..n).map(|l| c.stiffness()[l] * (l1[l] - l0[l])).collect()
        })
        .collect()
}

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

fn bench_projection(c: &mut Criterion) {
    let mut g = c.benchmark_group("projection_per_step");
    g.throughput(Throughput::Elements(M as u64));
    g.sample_size(10);
    for n in [2usize, 5, 10, 20, 50] {
        let crawler = Crawler::uniform(n + 1, 1.0, 1.0, 3.3).unwrap();
        let incs = increments(&crawler);
        let mut proj = Projector::new(&crawler).unwrap();
        let mut x = vec![0.0; n];
        let mut d = vec![0.0; n + 1];
        let mut period = |x: &mut Vec<f64>| {
            for delta in &incs {
                proj.step(x, delta, &mut d).unwrap();
            }
        };
        for _ in 0..50 {
            period(&mut x);
        }
        g.bench_with_input(BenchmarkId::new("crawler", n), &n, |b, _| {
            b.iter(|| period(black_box(&mut x)))
        });
        let inst = crawler_as_general(&crawler, 1.0, &vec![1e3; n], GeneralCost::None).unwrap();
        let mut gp = PolyProjector::new(inst.problem.c.clone());
        let incs_t: Vec<Vec<f64>> = incs.iter().map(|d| inst.to_general(d)).collect();
        let mut xt = vec![0.0; n];
        let mut v = vec![0.0; n];
        let mut period_g = |xt: &mut Vec<f64>| {
            for delta in &incs_t {
                for k in 0..n {
                    v[k] = xt[k] + delta[k];
                }
                *xt = gp.project(xt, &v).unwrap().x;
            }
        };
        for _ in 0..50 {
            period_g(&mut xt);
        }
        g.bench_with_input(BenchmarkId::new("general", n), &n, |b, _| {
            b.iter(|| period_g(black_box(&mut xt)))
        });
        // The general problem's projector chosen by its structure (`sweep::OntoC`): the chain's
        // O(N) method through the change of variables, with the general answer's multipliers
        // and its KKT residual on the problem's own rows.
        let view = inst.problem.as_chain().unwrap();
        let mut sp = OntoC::new(&inst.problem.c, Some(&view));
        assert_eq!(sp.kind(), "chain");
        let mut xs = vec![0.0; n];
        let mut out = crawlopt::sweep::Projection::default();
        let mut period_s = |xs: &mut Vec<f64>| {
            for delta in &incs_t {
                for k in 0..n {
                    v[k] = xs[k] + delta[k];
                }
                sp.project_into(xs, &v, &mut out).unwrap();
                xs.copy_from_slice(&out.x);
            }
        };
        for _ in 0..50 {
            period_s(&mut xs);
        }
        g.bench_with_input(BenchmarkId::new("general_by_structure", n), &n, |b, _| {
            b.iter(|| period_s(black_box(&mut xs)))
        });
        // Clarabel: min (1/2)|x|^2 - <v, x> s.t. N x <= c, its default tolerances (1e-8).
        let cpoly = &inst.problem.c;
        let (p, a) = (CscMatrix::identity(n), csc(&cpoly.normals, n));
        let cones = [NonnegativeConeT(cpoly.faces())];
        let mut xq = xt.clone();
        let mut q = vec![0.0; n];
        let mut period_q = |xq: &mut Vec<f64>| {
            for delta in &incs_t {
                for k in 0..n {
                    q[k] = -(xq[k] + delta[k]);
                }
                let settings = DefaultSettings {
                    verbose: false,
                    ..Default::default()
                };
                let mut s =
                    DefaultSolver::new(&p, &q, &a, &cpoly.offsets, &cones, settings).unwrap();
                s.solve();
                xq.copy_from_slice(&s.solution.x);
            }
        };
        g.bench_with_input(BenchmarkId::new("clarabel", n), &n, |b, _| {
            b.iter(|| period_q(black_box(&mut xq)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench_projection);
criterion_main!(benches);
