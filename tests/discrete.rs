//! The global solver of P_m (theory §6) against the one-link closed form and the simulator.

use crawlopt::optimal::{
    one_link_optimum, solve_discrete_global, solve_discrete_global_from, solve_discrete_local,
    solve_phase_global, Cost, GaitProblem, GaitResult, MilpStatus,
};
use crawlopt::Crawler;

#[test]
fn one_link_p_m_equals_the_closed_form_for_every_m() {
    // theory §10: N = 2, k = 1, a = 1, T = 10, mu+ = 1, mu- = 2: the P_m optimum is 3 for m >= 1.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    for m in 1..=4 {
        let s = solve_discrete_global(&c, &p, m).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::Optimal);
        assert!(
            (s.verified_displacement - 3.0).abs() < 1e-8,
            "m = {m}: {}",
            s.verified_displacement
        );
        assert!(
            s.certificate.gap < 1e-6,
            "m = {m}: gap {}",
            s.certificate.gap
        );
        assert_eq!(s.controls.len(), 1 << m);
        // Zero-mean control within the rate bound.
        let mean: f64 = s.controls.iter().map(|u| u[0]).sum::<f64>();
        assert!(mean.abs() < 1e-9);
        assert!(s.controls.iter().all(|u| u[0].abs() <= 1.0 + 1e-9));
    }
}

#[test]
fn discrete_optimum_never_exceeds_the_continuous_one_for_one_link() {
    // Asymmetric friction, several stiffnesses and periods, including no locomotion (a T < 2 w).
    for (k, t) in [(1.0, 3.0), (2.0, 7.0), (0.5, 4.0)] {
        let c = Crawler::new(vec![k], vec![1.0, 0.8], vec![2.5, 1.7]).unwrap();
        let p = GaitProblem::new(&c, t, &[1.0], Cost::None, None).unwrap();
        let cont = one_link_optimum(&c, &p).unwrap().value;
        for m in 1..=3 {
            let s = solve_discrete_global(&c, &p, m).unwrap();
            assert!(
                s.verified_displacement <= cont + 1e-8,
                "k {k} T {t} m {m}: {} > {cont}",
                s.verified_displacement
            );
            // Catching-up is exact for one link and bang-bang is optimal: P_m reaches J* too.
            assert!(
                (s.verified_displacement - cont).abs() < 1e-8,
                "k {k} T {t} m {m}: {} vs {cont}",
                s.verified_displacement
            );
        }
    }
}

#[test]
fn three_block_p_m_matches_the_peer_milp() {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let mut values = Vec::new();
    for m in 1..=3 {
        let s = solve_discrete_global(&c, &p, m).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::Optimal);
        assert!(s.verified_displacement >= -1e-12, "m {m}");
        println!(
            "N = 3, mu+ = 1, mu- = 1.5: J_{m} = {} (gap {:.1e})",
            s.verified_displacement, s.certificate.gap
        );
        values.push(s.verified_displacement);
    }
    // The plain big-M MILP of shared/peers (milp_highs.py, README) finds 2.0 at M = 8.
    assert!((values[2] - 2.0).abs() < 1e-8, "J_3 = {}", values[2]);
}

#[test]
fn a_start_is_the_first_incumbent_of_p_m() {
    // Four blocks on 16 steps: the MILP alone holds 2.25 after 120 s (the plain MILP of
    // shared/peers 2.75), far from the local method's 3.5. Started from that gait, a solve cut
    // short after a second returns at least it, so the start was taken.
    let c = Crawler::uniform(4, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0; 3], Cost::None, None).unwrap();
    let phase = solve_phase_global(&c, &p, 3).unwrap();
    let g = GaitResult::from_phase(&c, &p, &phase).gait;
    let local = solve_discrete_local(&c, &p, 4, &g.times, &g.lengths).unwrap();
    assert!(local.objective() > 3.5 - 1e-9, "{}", local.objective());
    let g = GaitResult::from_local(&c, &p, &local, "phase").gait;
    let (times, lengths) = (g.times, g.lengths);
    // Within a deadline of 1 s (the job's, as the API sets it from `time_limit`).
    let s = crawlopt::progress::within(Some(1.0), || {
        solve_discrete_global_from(&c, &p, 4, Some((&times, &lengths)))
    })
    .unwrap();
    let start = s.start_objective.expect("a start");
    assert!((start - local.objective()).abs() < 1e-9, "{start}");
    assert!(s.objective() >= start - 1e-9, "{} < {start}", s.objective());
    assert!(s.certificate.bound >= s.objective() - 1e-9);
}

#[test]
fn a_start_changes_no_optimum() {
    // The optimum of P_3 started from itself is the optimum found without a start, and the
    // start's own value is reported. (That a start with a quadratic cost or a TV bound sets
    // every column feasibly is checked by the unit tests of the module.)
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let plain = solve_discrete_global(&c, &p, 3).unwrap();
    assert_eq!(plain.start_objective, None);
    let (times, lengths) = plain.knots(c.stiffness());
    let s = solve_discrete_global_from(&c, &p, 3, Some((&times, &lengths))).unwrap();
    let start = s.start_objective.expect("a start");
    assert!((start - plain.objective()).abs() < 1e-9, "{start}");
    assert_eq!(s.certificate.status, MilpStatus::Optimal);
    assert!((s.objective() - plain.objective()).abs() < 1e-8);
}

#[test]
fn a_start_breaking_the_tv_bound_is_refused() {
    // HiGHS would drop such a start without a word; the solver names it instead.
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, Some(1.0)).unwrap();
    let times = [0.0, 2.5, 5.0, 7.5, 10.0];
    let lengths = [
        vec![0.0, 0.0],
        vec![2.0, 0.0],
        vec![2.0, 2.0],
        vec![0.0, 2.0],
        vec![0.0, 0.0],
    ];
    let e = solve_discrete_global_from(&c, &p, 3, Some((&times, &lengths))).unwrap_err();
    assert!(
        e.to_string().starts_with("start") && e.to_string().contains("max_total_variation"),
        "{e}"
    );
}
