//! The work bound (`certify::bound::work_bound`): its closed form on one link, and never below a
//! gait: the known optima, the triangle wave on long chains, random gaits on random chains.

use crawlopt::certify::bound::work_bound;
use crawlopt::integrate::{simulate, Actuation, Method, SimOptions};
use crawlopt::optimal::{grow_phases, phase_gait_of, Cost, GaitProblem, GrowOptions};
use crawlopt::Crawler;
use proptest::prelude::*;

fn problem(c: &Crawler, a: &[f64]) -> GaitProblem {
    GaitProblem::new(c, 10.0, a, Cost::None, None).unwrap()
}

#[test]
fn one_link_closed_form() {
    // C = [-1, 1] (w = 2): T w a / (2 k) / (mu_1^+ + mu_2^+) = 10 * 2 / 2 / 2 = 5, above J* = 3.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    assert!((work_bound(&c, &problem(&c, &[1.0])) - 5.0).abs() < 1e-12);
    // Per-link data: k = 2, |L'| <= 3 (a = k * 3 = 6), mu+ = (1, 0.5), mu- = (2, 4):
    // C = [max(-1, -4), min(2, 0.5)] = [-1, 0.5], w = 1.5: 10 * 1.5 * 6 / 4 / 1.5 = 15.
    let c = Crawler::new(vec![2.0], vec![1.0, 0.5], vec![2.0, 4.0]).unwrap();
    assert!((work_bound(&c, &problem(&c, &[3.0])) - 15.0).abs() < 1e-12);
}

#[test]
fn never_below_the_known_optima_or_the_triangle_wave() {
    // The peers' optima (k = a = 1, T = 10, mu+ = 1).
    for (blocks, mm, j) in [(3, 1.5, 2.6), (4, 1.5, 3.5), (5, 1.6, 3.75)] {
        let c = Crawler::uniform(blocks, 1.0, 1.0, mm).unwrap();
        let b = work_bound(&c, &problem(&c, &vec![1.0; blocks - 1]));
        assert!(b >= j, "N = {blocks}: bound {b} below {j}");
    }
    // The alternating triangle wave moves 4 - 1/(N - 1) (mu- = 1.3).
    for blocks in [10, 20] {
        let n = blocks - 1;
        let c = Crawler::uniform(blocks, 1.0, 1.0, 1.3).unwrap();
        let p = problem(&c, &vec![1.0; n]);
        let sign = |l: usize| if l % 2 == 0 { 2.5 } else { -2.5 };
        let incs: Vec<Vec<f64>> = [1.0, -1.0, -1.0, 1.0]
            .iter()
            .map(|s| (0..n).map(|l| s * sign(l)).collect())
            .collect();
        let g = phase_gait_of(&c, &p, &[2.5; 4], &incs).unwrap();
        assert!(work_bound(&c, &p) >= g.objective());
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    /// Random piecewise-linear gaits at the rate bounds on random chains (N = 2..12, per-link k
    /// and a, per-block friction), simulated exactly: never above the bound.
    #[test]
    fn never_below_a_random_gait(
        blocks in 2usize..12,
        seed in prop::collection::vec(0.0f64..1.0, 64),
        pieces in 2usize..6,
    ) {
        let n = blocks - 1;
        let at = |i: usize| seed[i % seed.len()];
        let k: Vec<f64> = (0..n).map(|l| 0.5 + 1.5 * at(l)).collect();
        // Actuator speed bounds |L_l'| <= s_l (a_l = k_l s_l).
        let a: Vec<f64> = (0..n).map(|l| 0.5 + at(l + 7)).collect();
        let mp: Vec<f64> = (0..blocks).map(|b| 0.5 + at(b + 13)).collect();
        let mm: Vec<f64> = (0..blocks).map(|b| 0.7 + 2.0 * at(b + 29)).collect();
        let Ok(c) = Crawler::new(k.clone(), mp, mm) else { return Ok(()) };
        if c.require_unique().is_err() {
            return Ok(());
        }
        let p = problem(&c, &a);
        // Pieces of equal length h; lengths at the knots: each link goes up and down at its full rate on random pieces,
        // zero in total (L periodic).
        let times: Vec<f64> = (0..pieces).map(|j| 10.0 * j as f64 / pieces as f64).collect();
        let h = 10.0 / pieces as f64;
        let mut lengths = vec![vec![0.0; n]];
        for j in 1..pieces {
            let prev = lengths[j - 1].clone();
            lengths.push(
                (0..n)
                    .map(|l| {
                        let up = at(3 * j + l) > 0.5;
                        let room = a[l] * h;
                        prev[l] + if up { room } else { -room }
                    })
                    .collect(),
            );
        }
        // The closing piece must come back within its rate bound: scale the excursion.
        for l in 0..n {
            let last = lengths[pieces - 1][l];
            let room = a[l] * h;
            if last.abs() > room {
                let f = room / last.abs();
                for row in lengths.iter_mut() {
                    row[l] *= f;
                }
            }
        }
        let act = Actuation::of_gait(10.0, times, lengths).unwrap();
        let opts = SimOptions { method: Method::Exact, ..SimOptions::default() };
        let sim = simulate(&c, &act, &opts).unwrap();
        let j = sim.displacement_per_period.expect("periodic orbit");
        let b = work_bound(&c, &p);
        prop_assert!(j <= b * (1.0 + 1e-12) + 1e-12, "J = {} above the bound {}", j, b);
    }
}

/// The bound against the best gait known here on uniform chains (k = a = 1, T = 10, mu+ = 1,
/// mu- = 1.3): `cargo test --release --test work_bound measure -- --ignored --nocapture`.
#[test]
#[ignore]
fn measure() {
    println!("N,work_bound,best_known,relative_gap");
    for blocks in [2, 3, 4, 5, 10, 20, 50, 100] {
        let n = blocks - 1;
        let c = Crawler::uniform(blocks, 1.0, 1.0, 1.3).unwrap();
        let p = problem(&c, &vec![1.0; n]);
        let b = work_bound(&c, &p);
        // One link: the closed form (aT - 2w) / (2k) = 3 (w = 2). Longer chains: the better
        // of the alternating triangle wave (simulated) and, for N <= 5, the phase growth
        // within 30 s (its gait, certified or not).
        let j = if blocks == 2 {
            3.0
        } else {
            let sign = |l: usize| if l % 2 == 0 { 2.5 } else { -2.5 };
            let incs: Vec<Vec<f64>> = [1.0, -1.0, -1.0, 1.0]
                .iter()
                .map(|s| (0..n).map(|l| s * sign(l)).collect())
                .collect();
            let wave = phase_gait_of(&c, &p, &[2.5; 4], &incs).unwrap().objective();
            let grown = if blocks <= 5 {
                let opts = GrowOptions {
                    time_limit: Some(30.0),
                    ..GrowOptions::default()
                };
                grow_phases(&c, &p, &opts, &mut |_| {})
                    .unwrap()
                    .best
                    .objective()
            } else {
                0.0
            };
            wave.max(grown)
        };
        println!("{blocks},{b:.4},{j:.4},{:.2}", (b - j) / j);
    }
}
