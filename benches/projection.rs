//! The exact projection onto a general polyhedron (`sweep::polyhedron`, SPEC §11) against the
//! dedicated crawler projection (`sweep::Projector`) on the same catching-up steps: a crawler of
//! n links (N = n + 1 blocks, sigma = 2N faces), k = 1, mu+ = 1, mu- = 3.3, under the travelling
//! sine `L_l = 2 sin(2 pi t - l pi/2)`, 200 steps a period, from the periodic orbit; the general
//! projector works on the crawler's general form (`model::crawler_as_general`), warm-started
//! like the crawler's. `cargo bench --bench projection`; throughput in steps per second.

use crawlopt::integrate::{Actuation, Waveform};
use crawlopt::model::crawler_as_general;
use crawlopt::model::general::GeneralCost;
use crawlopt::sweep::{PolyProjector, Projector};
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
    }
    g.finish();
}

criterion_group!(benches, bench_projection);
criterion_main!(benches);
