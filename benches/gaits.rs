//! Wall time of the optimal-gait solvers on the peers' instances (k = a = 1, T = 10, mu+ = 1,
//! mu- = 1.5; five blocks mu- = 1.6, since 1.5 is degenerate there), one HiGHS thread, against
//! the targets of the optimal-gait work:
//!
//! | case | what | target |
//! |---|---|---|
//! | `phase_growth/3` | continuous-time optimum, certified among K-phase gaits for the K where J stops improving (patience 1) | < 1 s |
//! | `phase_growth/4` | the same, four blocks | < 5 s |
//! | `phase_growth/5` | the same, five blocks | < 60 s |
//! | `local_p1024/5` | a local optimum of P_m on 1024 steps from the phase start (8 shifts), within 1 % of the continuous optimum 3.75 | < 10 s |
//! | `discrete_global/3x8` | P_m on 8 steps, certified | the plain MILP of `shared/peers` (0.9 s) |
//!
//! The global P_m targets (three blocks on 16 steps 20 times faster than the plain MILP; on 32
//! steps, and four blocks on 16, certified within 60 s) are not met; `scripts/bench-gaits`
//! runs those instances side by side with the peers (README, "Benchmarks").
//!
//! `cargo bench --bench gaits`. Every iteration also checks the value it computes, so a
//! faster but wrong solver does not pass for a faster one.

use crawlopt::optimal::{
    grow_phases, phase_start, solve_discrete_global, solve_discrete_local_shifted, Cost,
    GaitProblem, GrowOptions, MilpStatus,
};
use crawlopt::Crawler;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, SamplingMode};
use std::time::Duration;

fn instance(blocks: usize) -> (Crawler, GaitProblem) {
    let mu_backward = if blocks == 5 { 1.6 } else { 1.5 };
    let c = Crawler::uniform(blocks, 1.0, 1.0, mu_backward).unwrap();
    let p = GaitProblem::new(&c, 10.0, &vec![1.0; blocks - 1], Cost::None, None).unwrap();
    (c, p)
}

fn bench_gaits(c: &mut Criterion) {
    let mut g = c.benchmark_group("gaits");
    // Iterations of about a second: ten of them, each timed alone.
    g.sample_size(10);
    g.sampling_mode(SamplingMode::Flat);
    g.measurement_time(Duration::from_secs(10));
    // The optima (README, "Optimal gaits against the peers"): J = 2.6, 3.5, 3.75.
    for (blocks, optimum) in [(3usize, 2.6), (4, 3.5), (5, 3.75)] {
        let (crawler, problem) = instance(blocks);
        let opts = GrowOptions {
            patience: 1,
            ..GrowOptions::default()
        };
        g.bench_with_input(BenchmarkId::new("phase_growth", blocks), &blocks, |b, _| {
            b.iter(|| {
                let r = grow_phases(&crawler, &problem, &opts, &mut |_| {}).unwrap();
                assert!((r.best.objective() - optimum).abs() < 1e-6);
            })
        });
    }
    let (crawler, problem) = instance(5);
    g.bench_function(BenchmarkId::new("local_p1024", 5), |b| {
        // The start is not timed (and not computed when a filter skips this case).
        let start = phase_start(&crawler, &problem, &GrowOptions::default(), &mut |_| {}).unwrap();
        b.iter(|| {
            let (s, _) = solve_discrete_local_shifted(
                &crawler,
                &problem,
                10,
                start.times(),
                start.lengths(),
                8,
            )
            .unwrap();
            assert!(s.objective() >= 0.99 * 3.75);
        })
    });
    let (crawler, problem) = instance(3);
    g.bench_function(BenchmarkId::new("discrete_global", "3x8"), |b| {
        b.iter(|| {
            let s = solve_discrete_global(&crawler, &problem, 3).unwrap();
            assert_eq!(s.certificate.status, MilpStatus::Optimal);
            assert!((s.objective() - 2.0).abs() < 1e-6);
        })
    });
    g.finish();
}

criterion_group!(benches, bench_gaits);
criterion_main!(benches);
