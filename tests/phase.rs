//! Exact continuous-time gaits (theory §7): the phase MILP against the one-link closed form, and
//! its monotonicity in the number of phases.

use crawlopt::optimal::{
    one_link_optimum, search_sequences, slip_mode_is_valid, slip_sequence, solve_phase_global,
    Cost, GaitProblem, LocalStop, MilpStatus,
};
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
            let s = solve_phase_global(&c, &p, phases).unwrap();
            assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
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
        let s = solve_phase_global(&c, &p, phases).unwrap();
        println!(
            "N = 3, mu+ = 1, mu- = 1.5, T = 10: K = {phases}: J = {:.12} (gap {:.1e}, {:.2} s, {} phases used)",
            s.verified_displacement,
            s.certificate.gap,
            t0.elapsed().as_secs_f64(),
            s.durations.len()
        );
        assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
        assert!(
            s.verified_displacement >= last - 1e-8,
            "K = {phases}: {} < {last}",
            s.verified_displacement
        );
        last = s.verified_displacement;
    }
    assert!(last > 0.0);
}

#[test]
fn sequence_search_climbs_from_a_smaller_optimum_to_the_global_one() {
    // From the best 3-slip-phase gait (J = 13/6), with room for 4 slip phases, the search over
    // slip-mode sequences reaches the global optimum among 4 (J = 2.6, certified by the MILP):
    // each candidate is an LP for its sequence, so the value never drops below the start.
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let k3 = solve_phase_global(&c, &p, 3).unwrap();
    assert!((k3.objective() - 13.0 / 6.0).abs() < 1e-7);
    let seq = slip_sequence(&k3.modes);
    assert_eq!(seq.len(), 3);
    let k4 = solve_phase_global(&c, &p, 4).unwrap();
    let s = search_sequences(&c, &p, &seq, 4).unwrap();
    eprintln!(
        "sequence search: {} -> {} ({} LPs, {} moves, {:?}); MILP K = 4: {}",
        s.start_objective,
        s.best.objective(),
        s.lp_solves,
        s.moves,
        s.stop,
        k4.objective()
    );
    assert!(s.start_objective >= k3.objective() - 1e-9);
    assert!(s.moves >= 1);
    assert_eq!(s.stop, LocalStop::Stationary);
    assert!((s.best.objective() - k4.objective()).abs() < 1e-7);
    assert!(s.best.objective() <= k4.certificate.bound + 1e-7);
    assert_eq!(s.sequence.len(), 4);
    assert!(s.sequence.iter().all(|m| slip_mode_is_valid(&c, m)));
    // The returned gait follows the returned sequence (empty steps aside), transitions between.
    let used = slip_sequence(&s.best.modes);
    assert!(used.len() <= 4 && used.iter().all(|m| s.sequence.contains(m)));

    // An idle start is seeded with a peristaltic wave (each block forward in turn, from the
    // front); its LP alone already moves the crawler.
    let idle = search_sequences(&c, &p, &[], 4).unwrap();
    eprintln!(
        "from idle: {} -> {} ({} moves)",
        idle.start_objective,
        idle.best.objective(),
        idle.moves
    );
    assert_eq!(idle.sequence.len(), 4);
    assert!(idle.start_objective > 2.0, "{}", idle.start_objective);
    assert!(idle.best.objective() >= idle.start_objective - 1e-9);
    // Refusals: too many slip phases, a mode that is no face of C.
    assert!(search_sequences(&c, &p, &seq, 2).is_err());
    let e = search_sequences(&c, &p, &[vec![1, 1, 0]], 2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not a slip mode of a face of C"), "{e}");
}

/// Issue 30, item 2: a small positive optimum is not discarded by the growth's gain tolerance
/// (relative to the length scale, 3e-7 here). One link with T just above 2w/a: the closed form
/// (aT - 2w)/(2k) is 5e-8, and every K >= 2 finds it; the growth returns it, not the idle gait.
#[test]
fn phase_growth_keeps_a_small_positive_optimum() {
    use crawlopt::optimal::{grow_phases, GrowOptions};
    let c = Crawler::new(vec![1.0], vec![1.0, 1.0], vec![2.0, 2.0]).unwrap();
    let p = GaitProblem::new(&c, 4.0000001, &[1.0], Cost::None, None).unwrap();
    let want = one_link_optimum(&c, &p).unwrap().value;
    assert!((want - 5e-8).abs() < 1e-15, "closed form {want}");
    let opts = GrowOptions {
        max_phases: 4,
        ..GrowOptions::default()
    };
    let g = grow_phases(&c, &p, &opts, &mut |_| {}).unwrap();
    let j = g.best.objective();
    assert!((j - want).abs() < 1e-12, "J = {j}, closed form {want}");
    assert!(g.best.phases >= 2);
}

/// Issue 30, item 15: a growth the time limit cuts short says so. Six blocks: K = 4 (and on a
/// fast machine even K = 3) cannot finish within 1 s, so some K stops at the time limit; the
/// result's status is then `time_limit` with that K and its bound, never "optimal" for the
/// smaller K proven before. Every word is the serde name of the status.
#[test]
fn a_growth_cut_short_by_the_time_limit_says_time_limit_with_its_k_and_bound() {
    use crawlopt::optimal::{grow_phases, GrowOptions, GrowthStop};
    let c = Crawler::new(vec![1.0; 5], vec![1.0; 6], vec![1.63; 6]).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0; 5], Cost::None, None).unwrap();
    let opts = GrowOptions {
        time_limit: Some(1.0),
        ..GrowOptions::default()
    };
    let g = grow_phases(&c, &p, &opts, &mut |_| {}).unwrap();
    assert_eq!(g.stop, GrowthStop::TimeLimit);
    let cert = &g.best.certificate;
    match g.table.last() {
        Some(last) if last.status == MilpStatus::TimeLimit => {
            assert_eq!(cert.status, MilpStatus::TimeLimit);
            assert_eq!(g.best.phases, last.phases);
            assert_eq!(cert.bound, last.bound);
            let j = g.best.objective();
            assert!(
                cert.bound >= j && (cert.gap - (cert.bound - j) / j.abs().max(1.0)).abs() < 1e-12
            );
        }
        // The limit struck between two K: the last K solved is proven, and only it.
        Some(last) => {
            assert_eq!(cert.status, MilpStatus::OptimalAmongKPhases);
            assert_eq!(g.best.phases, last.phases);
        }
        None => panic!("no K solved"),
    }
    for s in [
        MilpStatus::Optimal,
        MilpStatus::OptimalAmongKPhases,
        MilpStatus::TimeLimit,
        MilpStatus::ApproximationLimit,
        MilpStatus::Stationary,
        MilpStatus::Stalled,
    ] {
        assert_eq!(serde_json::to_value(s).unwrap(), s.as_str());
    }
}
