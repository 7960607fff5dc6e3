//! The local LPCC method for P_m (theory §6): never worse than its start, never better than the
//! global optimum, exact on the one-link closed form, re-verified by the simulator.

use crawlopt::optimal::{
    gait_knots, sample_increments, shift_knots, solve_discrete_global, solve_discrete_local,
    solve_discrete_local_shifted, solve_phase_global, Cost, GaitProblem, LocalStop,
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
    // theory §10: J_m = 3 for every m. Start: a small rise and fall (sweep 2.5, J = 0.5).
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let times = [0.0, 2.5, 5.0, 10.0];
    let lengths = [vec![0.0], vec![2.5], vec![0.0], vec![0.0]];
    for m in [2, 4, 6] {
        let s = solve_discrete_local(&c, &p, m, &times, &lengths).unwrap();
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
        let s = solve_discrete_local(&c, &p, m, &times, &lengths).unwrap();
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
    let phase = solve_phase_global(&c, &p, 4).unwrap();
    let (times, lengths) = knots_of(&phase, c.stiffness());
    for m in [2, 3] {
        let global = solve_discrete_global(&c, &p, m).unwrap();
        let s = solve_discrete_local(&c, &p, m, &times, &lengths).unwrap();
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
    let s = solve_discrete_local(&c, &p, 10, &times, &lengths).unwrap();
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
    let e = solve_discrete_local(&c, &p, 3, &times, &lengths).unwrap_err();
    assert!(e.to_string().starts_with("gait.cost"), "{e}");
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let e = solve_discrete_local(&c, &p, 15, &times, &lengths).unwrap_err();
    assert!(e.to_string().starts_with("m:"), "{e}");
}

#[test]
fn a_start_shifted_by_whole_steps_samples_to_the_rotated_grid_gait() {
    // shift_knots gives the gait L(s + d): for d = j h its grid increments are those of the
    // original rotated by j steps.
    let (t, m) = (10.0, 4u32);
    let steps = 1usize << m;
    let times = [0.0, 1.7, 4.0, 6.3, 10.0];
    let lengths = [
        vec![0.0, 0.0],
        vec![1.5, -0.4],
        vec![0.7, 1.1],
        vec![-0.3, 0.2],
        vec![0.0, 0.0],
    ];
    let (k, a) = ([1.0, 2.0], [3.0, 3.0]);
    let base = sample_increments(&times, &lengths, &k, &a, t, steps);
    for j in [0, 1, 5, 11] {
        let d = t * j as f64 / steps as f64;
        let (st, sl) = shift_knots(&times, &lengths, d, t);
        assert_eq!(st.first(), Some(&0.0));
        assert_eq!(st.last(), Some(&t));
        assert_eq!(sl.first(), sl.last());
        let shifted = sample_increments(&st, &sl, &k, &a, t, steps);
        for i in 0..steps {
            for l in 0..2 {
                let want = base[(i + j) % steps][l];
                assert!((shifted[i][l] - want).abs() < 1e-12, "j {j} i {i} l {l}");
            }
        }
    }
}

#[test]
fn shifted_starts_keep_the_best_local_answer() {
    // Three blocks on 64 steps from the phase optimum: the unshifted start is the first of the
    // shifts, so the best of 8 is at least its answer, and one shift is that answer.
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let phase = solve_phase_global(&c, &p, 4).unwrap();
    let (times, lengths) = knots_of(&phase, c.stiffness());
    let plain = solve_discrete_local(&c, &p, 6, &times, &lengths).unwrap();
    let (one, d) = solve_discrete_local_shifted(&c, &p, 6, &times, &lengths, 1).unwrap();
    assert_eq!(d, 0.0);
    assert_eq!(one.objective(), plain.objective());
    let (best, d) = solve_discrete_local_shifted(&c, &p, 6, &times, &lengths, 8).unwrap();
    println!(
        "64 steps: unshifted {}, best of 8 shifts {} (shift {d})",
        plain.objective(),
        best.objective()
    );
    assert!(best.objective() >= plain.objective() - 1e-12);
    assert!(best.objective() <= 2.6 + 1e-9);
    let e = solve_discrete_local_shifted(&c, &p, 6, &times, &lengths, 0).unwrap_err();
    assert!(e.to_string().starts_with("shifts"), "{e}");
}
