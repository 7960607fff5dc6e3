//! Cost of one simulation time step (catching-up: one projection onto C; exact: the events of
//! one knot interval) on the travelling sine gait `L_l = 2 sin(2 pi t - l pi/2)`, k = 1,
//! mu+ = 1, mu- = 3.3, 1000 steps per period, measured on the periodic orbit; catching-up with
//! its increments stored and streamed.
//! `cargo bench --bench step`; throughput is reported in steps per second.

use crawlopt::integrate::{Actuation, CatchingUp, ExactPwl, IncrementStorage, PeriodMap, Waveform};
use crawlopt::sweep::ProjectionMethod;
use crawlopt::Crawler;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use std::hint::black_box;

const M: usize = 1000;

fn setup(nb: usize) -> (Crawler, Actuation) {
    let c = Crawler::uniform(nb, 1.0, 1.0, 3.3).unwrap();
    let n = c.links();
    let a = Actuation::wave(
        Waveform::Sine,
        1.0,
        vec![0.0; n],
        vec![2.0; n],
        (0..n).map(|l| 90.0 * l as f64).collect(),
    )
    .unwrap();
    (c, a)
}

fn bench_period(c: &mut Criterion) {
    let mut g = c.benchmark_group("period_of_1000_steps");
    g.throughput(Throughput::Elements(M as u64));
    g.sample_size(20);
    for nb in [3usize, 10, 100, 1000] {
        let (crawler, act) = setup(nb);
        let n = crawler.links();
        let mut acc = vec![0.0; nb];
        // The increments as a table, and formed step by step (memory O(N)).
        for (name, storage) in [
            ("catching-up", IncrementStorage::Stored),
            ("catching-up-streamed", IncrementStorage::Streamed),
        ] {
            let mut cu = CatchingUp::with_storage(&crawler, &act, M, storage).unwrap();
            let mut x = vec![0.0; n];
            for _ in 0..50 {
                cu.run_period(&mut x, &mut acc, None).unwrap();
            }
            g.bench_with_input(BenchmarkId::new(name, nb), &nb, |b, _| {
                b.iter(|| cu.run_period(black_box(&mut x), &mut acc, None).unwrap())
            });
        }
        let mut ex = ExactPwl::new(&crawler, &act, M).unwrap();
        let mut x = vec![0.0; n];
        for _ in 0..50 {
            ex.run_period(&mut x, &mut acc, None).unwrap();
        }
        g.bench_with_input(BenchmarkId::new("exact", nb), &nb, |b, _| {
            b.iter(|| ex.run_period(black_box(&mut x), &mut acc, None).unwrap())
        });
    }
    g.finish();
}

/// One period of catching-up with each projection method (the warm guess-and-repair default, the
/// exact dynamic programme and the warm-started active-set method), near the orbit (after ten
/// periods) and from rest (the first period from x = 0 with an empty working set), N = 3 to 10^4.
fn bench_projection(c: &mut Criterion) {
    let mut g = c.benchmark_group("projection");
    g.throughput(Throughput::Elements(M as u64));
    g.sample_size(10);
    for nb in [3usize, 10, 100, 1000, 10000] {
        let (crawler, act) = setup(nb);
        let n = crawler.links();
        let mut acc = vec![0.0; nb];
        // Near the orbit: ten periods from rest with the (faster) dynamic programme, shared.
        let mut near = vec![0.0; n];
        let stored = IncrementStorage::Stored;
        let mut warm = CatchingUp::with_storage(&crawler, &act, M, stored).unwrap();
        for _ in 0..10 {
            warm.run_period(&mut near, &mut acc, None).unwrap();
        }
        for (name, method) in [
            ("warm", ProjectionMethod::Warm),
            ("dp", ProjectionMethod::Dp),
            ("active-set", ProjectionMethod::ActiveSet),
        ] {
            let mut cu = CatchingUp::with_storage(&crawler, &act, M, stored).unwrap();
            let mut x = vec![0.0; n];
            g.bench_with_input(
                BenchmarkId::new(format!("{name}/from-rest"), nb),
                &nb,
                |b, _| {
                    b.iter(|| {
                        // Cold: x = 0 and an empty working set (set_method resets it).
                        cu.set_method(ProjectionMethod::Dp);
                        cu.set_method(method);
                        x.iter_mut().for_each(|v| *v = 0.0);
                        cu.run_period(black_box(&mut x), &mut acc, None).unwrap()
                    })
                },
            );
            cu.set_method(method);
            x.copy_from_slice(&near);
            g.bench_with_input(
                BenchmarkId::new(format!("{name}/orbit"), nb),
                &nb,
                |b, _| b.iter(|| cu.run_period(black_box(&mut x), &mut acc, None).unwrap()),
            );
        }
    }
    g.finish();
}

criterion_group!(benches, bench_period, bench_projection);
criterion_main!(benches);
