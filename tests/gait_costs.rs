//! Quadratic actuation cost, total-variation bounds, the growth of K and the convergence table,
//! against closed forms (theory §9 and the derivation in `optimal::one_link`).

use crawlopt::optimal::{
    discrete_convergence, grow_phases, one_link_optimum, solve_discrete_global, solve_phase_global,
    Cost, GaitProblem, GrowOptions, GrowthStop, MilpStatus,
};
use crawlopt::Crawler;

/// One link, k = 1, mu+ = 0.5, mu- = 1 on both blocks: C = [-0.5, 0.5], w = 1; a = 1, T = 10,
/// f2(u) = (c/2) u^2 with c = 0.8.
///
/// Closed form: a rise and fall of the link force by Delta, each half at rate 2 Delta / T,
/// moves the crawler Delta - w and costs 2 c Delta^2 / T, so
/// J(Delta) = (Delta - w)/k - 2 c Delta^2 / T is largest at Delta = T / (4 c k) = 3.125
/// (inside [w, a T / 2] = [1, 5]): J* = 2.125 - 1.5625 = 0.5625, at rate 0.625.
fn quadratic_one_link() -> (Crawler, GaitProblem) {
    let c = Crawler::uniform(2, 1.0, 0.5, 1.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::Quadratic { weight: 0.8 }, None).unwrap();
    (c, p)
}

#[test]
fn quadratic_cost_one_link_matches_the_closed_form_in_both_formulations() {
    let (c, p) = quadratic_one_link();
    let closed = one_link_optimum(&c, &p).unwrap();
    assert!((closed.value - 0.5625).abs() < 1e-12, "{}", closed.value);
    assert!((closed.rate - 0.625).abs() < 1e-12);

    let s = solve_phase_global(&c, &p, 4).unwrap();
    assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
    assert!(
        (s.objective() - 0.5625).abs() < 2e-6,
        "phase J = {} (cost {}, {} rounds)",
        s.objective(),
        s.actuation_cost,
        s.rounds
    );
    assert!(
        s.rounds > 1,
        "the optimal rate 0.625 is not among the first tangents"
    );
    assert!(s.certificate.gap <= 1e-6);
    // The optimal gait runs at the closed-form rate (to the square root of the objective's
    // tolerance: J is quadratic in the rate near its maximum).
    for u in &s.controls {
        assert!((u[0].abs() - 0.625).abs() < 1e-3, "rate {}", u[0]);
    }

    // P_m: catching-up is exact for one link and the optimal gait's halves lie on the grid, so
    // J_m = J* for every m >= 1.
    for m in 1..=3 {
        let s = solve_discrete_global(&c, &p, m).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::Optimal);
        assert!(
            (s.objective() - 0.5625).abs() < 2e-6,
            "m = {m}: J = {}",
            s.objective()
        );
    }
}

#[test]
fn growth_with_a_quadratic_cost_stops_within_the_approximation_tolerance() {
    // With f2 = (c/2) u^2 the values are exact only to the outer approximation's tolerance
    // (1e-6 relative), so a larger K must gain more than that to count: the one-link optimum
    // 0.5625 needs 2 slip phases, and K = 3 and 4 bring nothing.
    let (c, p) = quadratic_one_link();
    let g = grow_phases(&c, &p, &GrowOptions::default(), &mut |_| {}).unwrap();
    let ks: Vec<usize> = g.table.iter().map(|s| s.phases).collect();
    assert_eq!(ks, vec![1, 2, 3, 4], "{:?}", g.table);
    assert_eq!(g.stop, GrowthStop::NoGain);
    assert!(
        (g.best.objective() - 0.5625).abs() < 2e-6,
        "{}",
        g.best.objective()
    );
    assert!(g.best.certificate.bound >= g.best.objective() - 1e-9);
    assert!(g.best.certificate.gap <= 2e-6);
}

#[test]
fn a_heavy_cost_makes_idling_optimal() {
    // c = 1.4: Delta = T/(4c) = 1.79, J(Delta) = 0.79 - 0.89 < 0: stay idle, J* = 0.
    let c = Crawler::uniform(2, 1.0, 0.5, 1.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::Quadratic { weight: 1.4 }, None).unwrap();
    assert_eq!(one_link_optimum(&c, &p).unwrap().value, 0.0);
    let s = solve_phase_global(&c, &p, 4).unwrap();
    assert!(s.objective().abs() < 1e-6, "{}", s.objective());
    assert!(s.certificate.bound < 1e-6);
}

#[test]
fn total_variation_bound_in_p_m_matches_the_closed_form() {
    // theory §10 crawler with TV(u) <= 3: rates 3/4, sweep 3.75, J* = 1.75 (optimal::one_link).
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, Some(3.0)).unwrap();
    assert_eq!(one_link_optimum(&c, &p).unwrap().value, 1.75);
    for m in 1..=3 {
        let s = solve_discrete_global(&c, &p, m).unwrap();
        assert!(
            (s.objective() - 1.75).abs() < 1e-7,
            "m = {m}: {}",
            s.objective()
        );
        let tv: f64 = (0..s.controls.len())
            .map(|i| (s.controls[(i + 1) % s.controls.len()][0] - s.controls[i][0]).abs())
            .sum();
        assert!(tv <= 3.0 + 1e-7, "TV(u) = {tv}");
    }
    // The phase formulation cannot express it and says so.
    let e = solve_phase_global(&c, &p, 4).unwrap_err().to_string();
    assert!(e.contains("gait.max_total_variation"), "{e}");
}

#[test]
fn growing_k_stops_where_the_value_stops_improving() {
    // One link: nothing moves with one slip phase, then J = 3 for every K >= 2 (extension and
    // contraction, each after its transition across C).
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let g = grow_phases(&c, &p, &GrowOptions::default(), &mut |_| {}).unwrap();
    assert_eq!(g.stop, GrowthStop::NoGain);
    let ks: Vec<usize> = g.table.iter().map(|s| s.phases).collect();
    assert_eq!(ks, vec![1, 2, 3, 4]);
    assert!(g.table[0].objective.abs() < 1e-9);
    assert!((g.best.objective() - 3.0).abs() < 1e-8);
    assert_eq!(g.best.phases, 4, "certified for the largest K solved");

    // N = 3, mu+ = 1, mu- = 1.5 (the peers' instance): J_K = 0 up to K = 2 slip phases, 13/6
    // at K = 3, then 2.6 from K = 4 on (4 slip phases and 4 transitions); non-decreasing in K.
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let g = grow_phases(&c, &p, &GrowOptions::default(), &mut |_| {}).unwrap();
    for w in g.table.windows(2) {
        assert!(w[1].objective >= w[0].objective - 1e-7, "{:?}", g.table);
    }
    assert!(g.table[..2].iter().all(|s| s.objective.abs() < 1e-9));
    assert!((g.table[2].objective - 13.0 / 6.0).abs() < 1e-7);
    assert!(
        (g.best.objective() - 2.6).abs() < 1e-7,
        "{}",
        g.best.objective()
    );
    assert_eq!(g.stop, GrowthStop::NoGain);
    assert_eq!(g.best.phases, 6);
    assert_eq!(g.table.len(), 6);

    // a T < 2 w (theory §9): nothing moves for any K; idling is certified for every K tried.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 3.0, &[1.0], Cost::None, None).unwrap();
    let opts = GrowOptions {
        max_phases: 3,
        ..GrowOptions::default()
    };
    let g = grow_phases(&c, &p, &opts, &mut |_| {}).unwrap();
    assert_eq!(g.stop, GrowthStop::MaxPhases);
    assert_eq!(g.table.len(), 3);
    assert_eq!(
        g.best.phases, 3,
        "the idle gait is certified for the last K"
    );
    assert!(g.best.objective().abs() < 1e-9 && g.best.certificate.bound < 1e-9);

    // Backward-only crawler (mu+ > 2 mu-, Remark 3.3): idle is globally optimal at once.
    let c = Crawler::uniform(3, 1.0, 2.5, 1.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let g = grow_phases(&c, &p, &GrowOptions::default(), &mut |_| {}).unwrap();
    assert_eq!(g.stop, GrowthStop::NoForwardMotion);
    assert_eq!(g.table.len(), 1);
    assert_eq!(g.best.objective(), 0.0);
}

#[test]
fn convergence_table_of_p_m() {
    // theory §10: J_m = 3 for every m.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let mut seen = 0;
    let (table, finest) = discrete_convergence(&c, &p, 3, &mut |_| seen += 1).unwrap();
    assert_eq!(seen, 3);
    assert_eq!(table.iter().map(|r| r.m).collect::<Vec<_>>(), vec![1, 2, 3]);
    assert!(table.iter().all(|r| (r.objective - 3.0).abs() < 1e-8));
    assert_eq!(finest.m, 3);
}
