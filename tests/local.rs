//! The local LPCC method for P_m (SPEC §6): never worse than its start, never better than the
//! global optimum, exact on the one-link closed form, re-verified by the simulator.

use crawlopt::optimal::{
    gait_knots, sample_increments, solve_discrete_global, solve_discrete_local, solve_phase_global,
    Cost, GaitProblem, LocalStop,
};
use crawlopt::Crawler;

fn knots_of(s: &crawlopt::optimal::PhaseSolution, k: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
    let incs: Vec<Vec<f64>> = s
        .controls
        .iter()
        .zip(&s.durations)
        .map(|(u, d)| u.iter().map(|v| v * d).collect())
        .collect();
    gait_knots(&s.durations, &incs, k)
}

#[test]
fn sampled_increments_are_admissible() {
    // A triangle L rising by 3 over [0, 3] and falling over [3, 10], k = 2: U = k dL.
    let times = [0.0, 3.0, 10.0];
    let lengths = [vec![0.0], vec![3.0], vec![0.0]];
    let incs = sample_increments(&times, &lengths, &[2.0], &[2.0], 10.0, 16);
    assert_eq!(incs.len(), 16);
    let h = 10.0 / 16.0;
    assert!(incs.iter().all(|u| u[0].abs() <= 2.0 * h + 1e-15));
    assert!(incs.iter().map(|u| u[0]).sum::<f64>().abs() < 1e-12);
    // The first step lies in the rise: U = k h.
    assert!((incs[0][0] - 2.0 * h).abs() < 1e-12);
}

#[test]
fn one_link_local_improves_a_poor_start_and_keeps_the_optimum() {
    // SPEC §10: J_m = 3 for every m. Start: a small rise and fall (sweep 2.5, J = 0.5).
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let times = [0.0, 2.5, 5.0, 10.0];
    let lengths = [vec![0.0], vec![2.5], vec![0.0], vec![0.0]];
    for m in [2, 4, 6] {
        let s = solve_discrete_local(&c, &p, m, &times, &lengths, Some(60.0)).unwrap();
        assert!(
            (s.start_objective - 0.5).abs() < 1e-9,
            "{}",
            s.start_objective
        );
        // A local method: better than its start, never above the optimum (m = 2 reaches it;
        // finer grids stop at stationary points of their own, e.g. 1.125 at m = 4).
        assert!(s.objective() > 0.5 + 1e-3, "m = {m}: {}", s.objective());
        assert!(s.objective() <= 3.0 + 1e-9, "m = {m}: {}", s.objective());
        assert_eq!(s.stop, LocalStop::Stationary);
        if m == 2 {
            assert!((s.objective() - 3.0).abs() < 1e-9, "{}", s.objective());
        }
    }
    // From the optimal gait (the closed form: rise by 5 over half the period), it stays there.
    let times = [0.0, 5.0, 10.0];
    let lengths = [vec![0.0], vec![5.0], vec![0.0]];
    for m in [4, 8] {
        let s = solve_discrete_local(&c, &p, m, &times, &lengths, Some(60.0)).unwrap();
        assert!(
            (s.objective() - 3.0).abs() < 1e-9,
            "m = {m}: {}",
            s.objective()
        );
    }
}

#[test]
fn three_block_local_lies_between_its_start_and_the_global_optimum() {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let phase = solve_phase_global(&c, &p, 4, Some(120.0)).unwrap();
    let (times, lengths) = knots_of(&phase, c.stiffness());
    for m in [2, 3] {
        let global = solve_discrete_global(&c, &p, m, Some(120.0)).unwrap();
        let s = solve_discrete_local(&c, &p, m, &times, &lengths, Some(60.0)).unwrap();
        eprintln!(
            "N = 3, m = {m}: start {} -> local {} ({:?}, {} LPs, {} switches); global {}",
            s.start_objective,
            s.objective(),
            s.stop,
            s.lp_solves,
            s.switches,
            global.objective()
        );
        assert!(s.objective() >= s.start_objective - 1e-9);
        assert!(s.objective() <= global.objective() + 1e-9);
        // The returned gait is a P_m process: zero-mean, within the rate bounds.
        for l in 0..2 {
            assert!(s.controls.iter().map(|u| u[l]).sum::<f64>().abs() < 1e-9);
        }
        assert!(s.controls.iter().flatten().all(|u| u.abs() <= 1.0 + 1e-9));
    }
    // On a fine grid the local optimum approaches the continuous-time value 2.6 from below.
    let s = solve_discrete_local(&c, &p, 10, &times, &lengths, Some(60.0)).unwrap();
    assert!(
        s.objective() <= 2.6 + 1e-9 && s.objective() > 2.59,
        "{}",
        s.objective()
    );
}

#[test]
fn local_refuses_what_it_does_not_handle() {
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::Quadratic { weight: 1.0 }, None).unwrap();
    let times = [0.0, 5.0, 10.0];
    let lengths = [vec![0.0], vec![2.0], vec![0.0]];
    let e = solve_discrete_local(&c, &p, 3, &times, &lengths, None).unwrap_err();
    assert!(e.to_string().starts_with("gait.cost"), "{e}");
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let e = solve_discrete_local(&c, &p, 15, &times, &lengths, None).unwrap_err();
    assert!(e.to_string().starts_with("m:"), "{e}");
}
