//! Exact continuous-time gaits (SPEC §7): the phase MILP against the one-link closed form, and
//! its monotonicity in the number of phases.

use crawlopt::optimal::{one_link_optimum, solve_phase_global, Cost, GaitProblem, MilpStatus};
use crawlopt::Crawler;
use std::time::Instant;

#[test]
fn one_link_phase_optimum_equals_the_closed_form() {
    for (k, t, mp, mm) in [
        (1.0, 10.0, vec![1.0, 1.0], vec![2.0, 2.0]),
        (2.0, 7.0, vec![1.0, 0.8], vec![2.5, 1.7]),
        (0.5, 3.0, vec![1.0, 0.8], vec![2.5, 1.7]),
        (1.0, 10.0, vec![1.0, 0.5], vec![2.0, 0.8]),
    ] {
        let c = Crawler::new(vec![k], mp, mm).unwrap();
        let p = GaitProblem::new(&c, t, &[1.0], Cost::None, None).unwrap();
        let want = one_link_optimum(&c, &p).unwrap().value;
        // The optimal gait has two slip phases, each after a transition: on the rise the link
        // first loads (stick) then the front slides; on the fall the load reverses, then the
        // rear slides. One slip phase cannot move the crawler.
        for phases in [1, 2, 3, 4] {
            let s = solve_phase_global(&c, &p, phases, Some(60.0)).unwrap();
            assert_eq!(s.certificate.status, MilpStatus::Optimal);
            let expect = if phases >= 2 { want } else { 0.0 };
            assert!(
                (s.verified_displacement - expect).abs() < 1e-8,
                "k {k} T {t} K {phases}: {} vs {expect}",
                s.verified_displacement
            );
            let total: f64 = s.durations.iter().sum();
            assert!((total - t).abs() < 1e-9 * t || s.durations.len() < 2);
            if phases >= 2 && want > 0.0 {
                // Stick, slip forward (front), stick, slip forward (rear), up to rotation.
                let mut modes = s.modes.clone();
                let i = modes.iter().position(|m| m == &vec![0, 1]).unwrap();
                modes.rotate_left(i);
                assert_eq!(modes, vec![vec![0, 1], vec![0, 0], vec![1, 0], vec![0, 0]]);
            }
        }
    }
}

#[test]
fn three_block_optimum_is_non_decreasing_in_the_number_of_phases() {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let mut last = 0.0;
    for phases in 1..=5 {
        let t0 = Instant::now();
        let s = solve_phase_global(&c, &p, phases, Some(120.0)).unwrap();
        println!(
            "N = 3, mu+ = 1, mu- = 1.5, T = 10: K = {phases}: J = {:.12} (gap {:.1e}, {:.2} s, {} phases used)",
            s.verified_displacement,
            s.certificate.gap,
            t0.elapsed().as_secs_f64(),
            s.durations.len()
        );
        assert_eq!(s.certificate.status, MilpStatus::Optimal);
        assert!(
            s.verified_displacement >= last - 1e-8,
            "K = {phases}: {} < {last}",
            s.verified_displacement
        );
        last = s.verified_displacement;
    }
    assert!(last > 0.0);
}
