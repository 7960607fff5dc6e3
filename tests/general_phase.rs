//! Exact continuous-time gaits of the general problem (P) where `A = 0` (theory §7 generalised,
//! §11): the phase MILP against the paper's §4 one-link closed form, against the dedicated
//! crawler phase method on crawler instances, re-verified by an independent replay in the
//! exact simulator, non-decreasing in K, and its refusals.

mod common;

use common::{one_link_problem, random_polygon_problem, Rng};
use crawlopt::integrate::{simulate_general_exact, ControlInput, InputKind};
use crawlopt::model::general::{Boundary, GeneralCost, GeneralParts, GeneralProblem};
use crawlopt::model::{crawler_as_general, Crawler};
use crawlopt::optimal::general::{
    check_problem, solve_general_phase, solve_general_transitions, GeneralPhaseGait,
};
use crawlopt::optimal::{solve_phase_global, Cost, GaitProblem, MilpStatus};
use crawlopt::Error;

/// Replays the gait's controls and durations in the exact simulator from its `x_0` and
/// returns `(int f1, the largest state difference at the phase boundaries, x(T) - x(0))`.
fn replay(p: &GeneralProblem, s: &GeneralPhaseGait) -> (f64, f64, f64) {
    let mut times = vec![0.0];
    for d in &s.durations[..s.durations.len() - 1] {
        times.push(times.last().unwrap() + d);
    }
    let total: f64 = s.durations.iter().sum();
    let input = ControlInput::new(
        InputKind::PiecewiseConstant,
        total,
        times.clone(),
        s.controls.clone(),
        &p.control,
        "input",
    )
    .unwrap();
    let mut cauchy = p.clone();
    cauchy.period = total;
    cauchy.boundary = Boundary::Initial(s.states[0].clone());
    let sim = simulate_general_exact(&cauchy, &input, &s.states[0], 1, 1e-12).unwrap();
    let mut gap = 0.0_f64;
    for (j, &t) in times.iter().enumerate().skip(1) {
        let i = sim.t.iter().position(|&v| v == t).unwrap();
        for (a, b) in sim.x[i].iter().zip(&s.states[j]) {
            gap = gap.max((a - b).abs());
        }
    }
    let end = sim.x.last().unwrap();
    for (a, b) in end.iter().zip(s.states.last().unwrap()) {
        gap = gap.max((a - b).abs());
    }
    let periodic = end
        .iter()
        .zip(&s.states[0])
        .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
    (sim.reward, gap, periodic)
}

#[test]
fn the_one_link_problem_of_section_4() {
    // J* = (T - 2 (b - a)) / 2 for T > 2 (b - a), 0 below. The optimum needs 4 phases: a free
    // rise across C, a slide held on b (u = 1, lambda = 1), a free fall, a slide held on a.
    // With 3 phases no periodic gait slides with u != 0 (the slide's U must cancel the two
    // crossings' +-(b - a)), so J = 0 below K = 4.
    for (a, b, t, want) in [
        (-1.0, 1.0, 10.0, 3.0),
        (-0.5, 1.5, 12.0, 4.0),
        (-1.0, 1.0, 3.0, 0.0),
    ] {
        let p = one_link_problem(a, b, t);
        let g = check_problem(&p).unwrap();
        let mut last = f64::NEG_INFINITY;
        for k in 1..=5 {
            let s = solve_general_phase(&p, &g, k).unwrap();
            assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
            let expect = if k >= 4 { want } else { 0.0 };
            assert!(
                (s.objective - expect).abs() < 1e-7,
                "T = {t}, K = {k}: {} vs {expect}",
                s.objective
            );
            assert!(s.certificate.bound <= expect + 1e-6);
            assert!(
                s.objective >= last - 1e-9,
                "K = {k}: {} < {last}",
                s.objective
            );
            last = s.objective;
            let total: f64 = s.durations.iter().sum();
            assert!((total - t).abs() < 1e-9 * t);
            let (reward, gap, periodic) = replay(&p, &s);
            assert!(
                (reward - s.objective).abs() < 1e-9,
                "{reward} vs {}",
                s.objective
            );
            assert!(gap < 1e-9 && periodic < 1e-9, "{gap:e} {periodic:e}");
        }
    }
}

#[test]
fn crawler_instances_give_the_crawler_phase_optima() {
    // A crawler step (a transition and a slip phase) is two general phases, and a general
    // phase is a transition or a slip phase, so crawler(K) <= general(2K) <= crawler(2K) steps.
    // The two need not be equal: the crawler of stiffness (1, 2, 1.5), mu+ = (1, 1.2, 0.9, 1.1),
    // mu- = (2.5, 3.1, 2.7, 2), unit rate bounds, T = 8 has crawler(3) = 3.0667 < general(6) =
    // 3.0818 = crawler(4), its general gait two slip phases in a row, twice (measured, 20 s:
    // not run here). On these instances they are equal (measured).
    let cases = [
        (
            Crawler::new(vec![1.0], vec![1.0, 1.0], vec![2.0, 2.0]).unwrap(),
            vec![1, 2],
        ),
        (
            Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap(),
            vec![1, 2, 3],
        ),
    ];
    for (crawler, steps) in cases {
        crawler.require_unique().unwrap();
        let speed = vec![1.0; crawler.links()];
        let t = 6.0;
        let gp = GaitProblem::new(&crawler, t, &speed, Cost::None, None).unwrap();
        let inst = crawler_as_general(&crawler, t, &gp.rate_bound, GeneralCost::None).unwrap();
        let g = check_problem(&inst.problem).unwrap();
        for k in steps {
            let want = solve_phase_global(&crawler, &gp, k).unwrap();
            assert_eq!(want.certificate.status, MilpStatus::OptimalAmongKPhases);
            let got = solve_general_phase(&inst.problem, &g, 2 * k).unwrap();
            assert_eq!(got.certificate.status, MilpStatus::OptimalAmongKPhases);
            assert!(
                (got.objective - want.objective()).abs() < 1e-7,
                "N = {}, K = {k}: {} vs {}",
                crawler.blocks(),
                got.objective,
                want.objective()
            );
            let above = solve_phase_global(&crawler, &gp, 2 * k).unwrap();
            assert!(got.objective <= above.objective() + 1e-7);
            let (reward, gap, periodic) = replay(&inst.problem, &got);
            assert!((reward - got.objective).abs() < 1e-9);
            assert!(gap < 1e-9 && periodic < 1e-9, "{gap:e} {periodic:e}");
        }
    }
}

/// Slots of a free transition and a phase (`solve_general_transitions`) are as strong as the
/// chain's formulation where measured: the crawler's `J_K` at `K` slots on the three-block
/// example (2.1667, 2.6) and on the four-block crawler whose optimum has two slip phases in a
/// row (3.0667 at `K` = 2 and 3, where the general formulation needs 4 and 6 phases); the §4
/// one-link optimum at `K = 2` (the general formulation needs 4); on random polygons, at least
/// the general formulation at `K` and at most it at `2K`. Every gait replayed, of at most `2K`
/// phases.
#[test]
fn free_transitions_are_as_strong_as_the_chains_formulation() {
    let check = |p: &GeneralProblem, s: &GeneralPhaseGait, k: usize| {
        assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
        assert!(s.durations.len() <= 2 * k, "{} phases", s.durations.len());
        let (reward, gap, periodic) = replay(p, s);
        assert!(
            (reward - s.objective).abs() < 1e-9,
            "{reward} vs {}",
            s.objective
        );
        assert!(gap < 1e-9 && periodic < 1e-9, "{gap:e} {periodic:e}");
    };
    for (a, b, t, want) in [(-1.0, 1.0, 10.0, 3.0), (-0.5, 1.5, 12.0, 4.0)] {
        let p = one_link_problem(a, b, t);
        let g = check_problem(&p).unwrap();
        for k in 1..=3 {
            let s = solve_general_transitions(&p, &g, k).unwrap();
            let expect = if k >= 2 { want } else { 0.0 };
            assert!(
                (s.objective - expect).abs() < 1e-7,
                "K = {k}: {}",
                s.objective
            );
            check(&p, &s, k);
        }
    }
    let crawlers = [
        (
            Crawler::new(vec![1.0; 2], vec![1.0; 3], vec![1.5; 3]).unwrap(),
            10.0,
            [3, 4],
        ),
        (
            Crawler::new(
                vec![1.0, 2.0, 1.5],
                vec![1.0, 1.2, 0.9, 1.1],
                vec![2.5, 3.1, 2.7, 2.0],
            )
            .unwrap(),
            8.0,
            [2, 3],
        ),
    ];
    for (crawler, t, ks) in crawlers {
        let speed = vec![1.0; crawler.links()];
        let gp = GaitProblem::new(&crawler, t, &speed, Cost::None, None).unwrap();
        let inst = crawler_as_general(&crawler, t, &gp.rate_bound, GeneralCost::None).unwrap();
        let g = check_problem(&inst.problem).unwrap();
        for k in ks {
            let want = solve_phase_global(&crawler, &gp, k).unwrap().objective();
            let s = solve_general_transitions(&inst.problem, &g, k).unwrap();
            assert!(
                (s.objective - want).abs() < 1e-7,
                "N = {}, K = {k}: {} vs the crawler's {want}",
                crawler.blocks(),
                s.objective
            );
            check(&inst.problem, &s, k);
        }
    }
    let mut rng = Rng(0x5851_f42d_4c95_7f2d);
    for sigma in [3, 4, 5] {
        let mut p = random_polygon_problem(&mut rng, sigma);
        p.dynamics.a = vec![vec![0.0; 2]; 2];
        let g = check_problem(&p).unwrap();
        for k in 1..=2 {
            let s = solve_general_transitions(&p, &g, k).unwrap();
            let below = solve_general_phase(&p, &g, k).unwrap().objective;
            let above = solve_general_phase(&p, &g, 2 * k).unwrap().objective;
            let tol = 1e-7 * below.abs().max(1.0);
            assert!(
                below <= s.objective + tol && s.objective <= above + tol,
                "sigma = {sigma}, K = {k}: {below} <= {} <= {above}",
                s.objective
            );
            check(&p, &s, k);
        }
    }
}

#[test]
fn random_polygons_no_exact_gait_of_k_segments_beats_the_phase_optimum() {
    // Independent lower bounds: a zero-mean two-level control played by the exact simulator to
    // its periodic regime is an exact gait whose segments (between events) are phases (the
    // faces with a reaction are active along a segment), so the phase optimum with K = the
    // number of segments is at least its J. Random polygons (3..5 faces) with A = 0, random B,
    // b and face weights.
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut compared = 0;
    let mut strict = 0;
    for sigma in [3, 4, 5, 3, 4, 5, 3, 4] {
        let mut p = random_polygon_problem(&mut rng, sigma);
        p.dynamics.a = vec![vec![0.0; 2]; 2];
        let g = check_problem(&p).unwrap();
        let t = p.period;
        let t1 = t * rng.range(0.2, 0.8);
        let u1 = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
        // u2 = -t1 u1 / (T - t1), scaled into the box with u1.
        let mut u2: Vec<f64> = u1.iter().map(|v| -t1 * v / (t - t1)).collect();
        let over = u2.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        let u1: Vec<f64> = u1.iter().map(|v| v / over).collect();
        u2.iter_mut().for_each(|v| *v /= over);
        let input = ControlInput::new(
            InputKind::PiecewiseConstant,
            t,
            vec![0.0, t1],
            vec![u1, u2],
            &p.control,
            "input",
        )
        .unwrap();
        let sim = simulate_general_exact(&p, &input, &g.chebyshev_centre, 500, 1e-13).unwrap();
        let k = sim.u.len();
        if !sim.converged || k > 8 {
            continue;
        }
        let lower = sim.objective.unwrap();
        let s = solve_general_phase(&p, &g, k).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
        assert!(
            s.objective >= lower - 1e-7,
            "sigma = {sigma}, K = {k}: {} < {lower}",
            s.objective
        );
        let (reward, gap, periodic) = replay(&p, &s);
        assert!((reward - s.objective).abs() < 1e-9);
        assert!(gap < 1e-9 && periodic < 1e-9, "{gap:e} {periodic:e}");
        compared += 1;
        if s.objective > lower + 1e-6 {
            strict += 1;
        }
    }
    assert!(compared >= 4, "only {compared} instances compared");
    eprintln!("{compared} compared, {strict} improved on the two-level control");
}

#[test]
fn a_quadratic_cost_by_outer_approximation() {
    // f2 = (c/2) u^2 on the one-link problem: a control of constant magnitude v up then down
    // gives J(v) = (v T - 2 w)/2 - c v^2 T/2 (the reaction pays half the travel beyond the
    // width w = b - a; for a given int |u|, int u^2 is least at constant |u|, Jensen), so
    // v* = min(1, 1/(2c)) and, for c = 1, J* = T/8 - w when T > 8 w. T = 40, w = 2: J* = 3,
    // with 4 phases at |u| = 1/2.
    let mut p = one_link_problem(-1.0, 1.0, 40.0);
    p.cost = GeneralCost::Quadratic { weight: 1.0 };
    let g = check_problem(&p).unwrap();
    let s = solve_general_phase(&p, &g, 4).unwrap();
    assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
    assert!((s.objective - 3.0).abs() < 1e-5, "{}", s.objective);
    assert!(s.certificate.bound >= s.objective - 1e-9);
    assert!(s.certificate.bound <= 3.0 + 1e-5);
    assert!(
        s.controls.iter().all(|u| (u[0].abs() - 0.5).abs() < 1e-3),
        "{:?}",
        s.controls
    );
    let (reward, gap, periodic) = replay(&p, &s);
    assert!((reward - s.actuation_cost - s.objective).abs() < 1e-9);
    assert!(gap < 1e-9 && periodic < 1e-9, "{gap:e} {periodic:e}");
    // A crawler instance with a quadratic cost against the crawler's phase method (K steps,
    // 2K general phases).
    let crawler = Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap();
    let gp = GaitProblem::new(
        &crawler,
        6.0,
        &[1.0, 1.0],
        Cost::Quadratic { weight: 0.3 },
        None,
    )
    .unwrap();
    let inst = crawler_as_general(
        &crawler,
        6.0,
        &gp.rate_bound,
        GeneralCost::Quadratic { weight: 0.3 },
    )
    .unwrap();
    let g = check_problem(&inst.problem).unwrap();
    for k in [1, 2] {
        let want = solve_phase_global(&crawler, &gp, k).unwrap();
        let got = solve_general_phase(&inst.problem, &g, 2 * k).unwrap();
        assert_eq!(got.certificate.status, MilpStatus::OptimalAmongKPhases);
        assert!(
            (got.objective - want.objective()).abs() < 1e-5,
            "K = {k}: {} vs {}",
            got.objective,
            want.objective()
        );
    }
}

#[test]
fn a_polytope_u_gives_the_box_optimum() {
    // U = {u <= 1, -u <= 1} is the box [-1, 1]: the same J* = 3 with 4 phases, 0 with 3.
    let mut q = parts();
    q.lower = None;
    q.upper = None;
    q.g = Some(vec![vec![1.0], vec![-1.0]]);
    q.h = Some(vec![1.0, 1.0]);
    let p = GeneralProblem::new(q).unwrap();
    let g = check_problem(&p).unwrap();
    for (k, want) in [(3, 0.0), (4, 3.0)] {
        let s = solve_general_phase(&p, &g, k).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
        assert!(
            (s.objective - want).abs() < 1e-7,
            "K = {k}: {}",
            s.objective
        );
        let (reward, gap, periodic) = replay(&p, &s);
        assert!((reward - s.objective).abs() < 1e-9);
        assert!(gap < 1e-9 && periodic < 1e-9, "{gap:e} {periodic:e}");
    }
}

#[test]
fn a_cauchy_problem_from_a_face() {
    // The one-link problem from x(0) = a = -1 with x(T) free, T = 10: with eta = lambda_b -
    // lambda_a, J = (L_a + L_b)/2 (L the integrated reactions), and int |u| = L_a + L_b + the
    // free travel <= T. Reactions on both faces need a travel of at least b - a = 2, so
    // J <= (T - 2)/2 = 4, attained by 3 phases: slide on a (u = -1, 5 s), rise (u = 1, 2 s),
    // slide on b (u = 1, 3 s), zero mean. (On one face only, its reaction is paid back by as
    // much free travel: J <= T/4 = 2.5.)
    let mut q = parts();
    q.periodic = false;
    q.initial_state = Some(vec![-1.0]);
    let p = GeneralProblem::new(q).unwrap();
    let g = check_problem(&p).unwrap();
    for k in [3, 4] {
        let s = solve_general_phase(&p, &g, k).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::OptimalAmongKPhases);
        assert!((s.objective - 4.0).abs() < 1e-7, "K = {k}: {}", s.objective);
        assert!((s.states[0][0] + 1.0).abs() < 1e-12);
        let (reward, gap, _) = replay(&p, &s);
        assert!((reward - s.objective).abs() < 1e-9);
        assert!(gap < 1e-9, "{gap:e}");
    }
}

fn parts() -> GeneralParts {
    GeneralParts {
        normals: vec![vec![1.0], vec![-1.0]],
        offsets: vec![1.0, 1.0],
        b: vec![vec![1.0]],
        lower: Some(vec![-1.0]),
        upper: Some(vec![1.0]),
        zero_mean: true,
        face_weights: Some(vec![0.5, 0.5]),
        period: 10.0,
        periodic: true,
        ..Default::default()
    }
}

fn refused_field(p: GeneralParts, k: usize) -> String {
    let p = GeneralProblem::new(p).unwrap();
    let g = check_problem(&p).unwrap();
    match solve_general_phase(&p, &g, k) {
        Err(Error::InvalidParameter { field, .. }) => field,
        other => panic!("not refused: {other:?}"),
    }
}

#[test]
fn bad_input_is_refused_naming_the_field() {
    let mut a = parts();
    a.a = Some(vec![vec![-0.5]]);
    assert_eq!(refused_field(a, 4), "dynamics.A");
    assert_eq!(refused_field(parts(), 0), "max_phases");
    assert_eq!(refused_field(parts(), 1000), "max_phases");
    // A bad time limit is the job's setting, refused by the API (tests/general_phase_growth.rs).
}

/// Reactions only on held faces and never negative, exactly: a random quadrilateral whose
/// `K = 3` optimum (general formulation) ends with a phase of `1.1e-12 T`, where the MILP's
/// integrated reactions on faces it does not hold (zero to HiGHS's feasibility tolerance),
/// divided by that duration, were stored as reactions of 0.83 and 1.64. Every answer of the
/// formulations and `K` tried here holds the invariant, and its `int f1` is the replay's.
#[test]
fn reactions_sit_on_held_faces_only_even_on_a_vanishing_phase() {
    let text = "[sweeping_process]\n\
        normals = [[0.9985, 0.0548], [-0.9927, 0.1209], [-0.6066, -0.795], [-0.0777, -0.997]]\n\
        offsets = [1.226, 0.869, 1.112, 1.375]\n\
        [dynamics]\nB = [[0.731, 0.146], [-0.096, -0.37]]\n\
        [control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\nzero_mean = true\n\
        [objective]\nface_weights = [0.759, 0.322, 0.057, 0.555]\n\
        [problem]\nperiod = 7.18\n";
    let p = crawlopt::io::GeneralFile::parse(text)
        .unwrap()
        .problem()
        .unwrap();
    let g = check_problem(&p).unwrap();
    for k in 1..=4 {
        for s in [
            solve_general_phase(&p, &g, k).unwrap(),
            solve_general_transitions(&p, &g, k).unwrap(),
        ] {
            for (j, (held, r)) in s.held.iter().zip(&s.reactions).enumerate() {
                for (f, &rf) in r.iter().enumerate() {
                    assert!(rf >= 0.0, "K = {k}, phase {j}, face {}: {rf}", f + 1);
                    assert!(
                        rf == 0.0 || held.contains(&(f + 1)),
                        "K = {k}, phase {j}: {rf} on face {} not held ({held:?})",
                        f + 1
                    );
                }
            }
            let (reward, gap, periodic) = replay(&p, &s);
            assert!((reward - s.objective).abs() < 1e-9, "K = {k}");
            assert!(
                gap < 1e-9 && periodic < 1e-9,
                "K = {k}: {gap:e} {periodic:e}"
            );
        }
    }
}
