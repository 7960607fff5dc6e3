//! P_m of the general problem (P) (theory §11), globally as a MILP: the paper's §4 one-link
//! problem in general form against its closed form, crawler instances against the dedicated
//! crawler P_m, and random small instances against the enumeration of every complementarity
//! branch (an LP each, no big-M): polygons for m = 1, 2, intervals for m = 3.

mod common;

use common::{one_link_problem, random_polygon_problem, Rng};
use crawlopt::model::general::{GeneralCost, GeneralParts, GeneralProblem, EXPLICIT_STEP_LIMIT};
use crawlopt::model::{crawler_as_general, Crawler};
use crawlopt::optimal::general::{
    analyze_polyhedron, check_problem, solve_general_branch, solve_general_pm,
};
use crawlopt::optimal::{solve_discrete_global, Cost, GaitProblem, MilpStatus};

#[test]
fn the_one_link_problem_of_section_4() {
    // J* = (T - 2 (b - a)) / 2 for T > 2 (b - a), 0 below; P_m attains it for every m >= 1
    // when the half period is a whole number of steps that reaches across C (theory §10).
    for (a, b, t, want) in [
        (-1.0, 1.0, 10.0, 3.0),
        (-0.5, 1.5, 12.0, 4.0),
        (-1.0, 1.0, 3.0, 0.0),
    ] {
        let p = one_link_problem(a, b, t);
        let g = check_problem(&p).unwrap();
        for m in 1..=3 {
            let s = solve_general_pm(&p, &g, m).unwrap();
            assert_eq!(s.certificate.status, MilpStatus::Optimal);
            assert!(
                (s.objective - want).abs() < 1e-7,
                "T = {t}, m = {m}: {}",
                s.objective
            );
            assert!(s.certificate.bound <= want + 1e-6);
        }
    }
}

#[test]
fn crawler_instances_give_the_crawler_p_m_optima() {
    let cases = [
        Crawler::new(vec![1.0], vec![1.0, 1.0], vec![2.0, 2.0]).unwrap(),
        Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap(),
    ];
    for crawler in cases {
        crawler.require_unique().unwrap();
        let speed = vec![1.0; crawler.links()];
        let gp = GaitProblem::new(&crawler, 6.0, &speed, Cost::None, None).unwrap();
        let inst = crawler_as_general(&crawler, 6.0, &gp.rate_bound, GeneralCost::None).unwrap();
        let g = check_problem(&inst.problem).unwrap();
        for m in 1..=2 {
            let want = solve_discrete_global(&crawler, &gp, m).unwrap();
            let got = solve_general_pm(&inst.problem, &g, m).unwrap();
            let j = want.verified_displacement - want.actuation_cost;
            assert!(
                (got.objective - j).abs() < 1e-7,
                "N = {}, m = {m}: {} vs {j}",
                crawler.blocks(),
                got.objective
            );
        }
    }
}

#[test]
fn random_instances_against_the_enumeration_of_branches() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let mut moving = 0;
    for (sigma, m, count) in [(3, 1, 4), (4, 1, 3), (3, 2, 2)] {
        for _ in 0..count {
            let mut p = random_polygon_problem(&mut rng, sigma);
            // A drift within P_m's explicit limit on this grid (beyond, m is refused).
            let h = p.period / (1u64 << m) as f64;
            let over = h * p.dynamics.split().stiff_rate / EXPLICIT_STEP_LIMIT;
            if over > 1.0 {
                p.dynamics
                    .a
                    .iter_mut()
                    .flatten()
                    .for_each(|v| *v /= 1.01 * over);
            }
            let g = analyze_polyhedron(&p.c).unwrap();
            assert!(g.bounded && g.degenerate_vertex.is_none());
            let steps = 1usize << m;
            let mut best = f64::NEG_INFINITY;
            for mask in 0u64..(1 << (steps * sigma)) {
                let active: Vec<Vec<bool>> = (0..steps)
                    .map(|i| {
                        (0..sigma)
                            .map(|j| mask >> (i * sigma + j) & 1 == 1)
                            .collect()
                    })
                    .collect();
                if let Some(v) = solve_general_branch(&p, m, &active).unwrap() {
                    best = best.max(v);
                }
            }
            let s = solve_general_pm(&p, &g, m).unwrap();
            assert!(
                (s.objective - best).abs() < 1e-7 * (1.0 + best.abs()),
                "sigma = {sigma}, m = {m}: MILP {} vs branches {best}",
                s.objective
            );
            moving += usize::from(best > 1e-3);
        }
    }
    // Most instances have a non-trivial optimum (the reactions pay).
    assert!(moving >= 7, "{moving} of 9");
}

/// A random interval C = [a, b] (n = 1) with random `A`, `B`, `b` and face weights.
fn random_interval(rng: &mut Rng) -> GeneralProblem {
    let mut r = || rng.range(-0.5, 0.5);
    let (lo, hi) = (0.3 + r().abs(), 0.3 + r().abs());
    GeneralProblem::new(GeneralParts {
        normals: vec![vec![1.0], vec![-1.0]],
        offsets: vec![hi, lo],
        a: Some(vec![vec![r()]]),
        b: vec![vec![1.0 + r()]],
        drift: Some(vec![r() * 0.2]),
        lower: Some(vec![-1.0]),
        upper: Some(vec![1.0]),
        zero_mean: true,
        face_weights: Some(vec![0.4 + 1.2 * r(), 0.4 + 1.2 * r()]),
        period: 4.0 + 6.0 * r().abs(),
        periodic: true,
        ..Default::default()
    })
    .unwrap()
}

#[test]
fn random_intervals_against_the_enumeration_of_branches_for_m_3() {
    // m = 3: 8 steps. In one dimension at most one of the two faces is active at a point
    // (b > a), so each step has three branches (off both, on the upper, on the lower face):
    // 3^8 = 6561 LPs per instance, the subsets with both faces held skipped as infeasible.
    let mut rng = Rng(0x5851_f42d_4c95_7f2d);
    let m = 3;
    let steps = 1usize << m;
    let mut moving = 0;
    for _ in 0..3 {
        let p = random_interval(&mut rng);
        let g = analyze_polyhedron(&p.c).unwrap();
        let mut best = f64::NEG_INFINITY;
        for code in 0..3usize.pow(steps as u32) {
            let mut c = code;
            let active: Vec<Vec<bool>> = (0..steps)
                .map(|_| {
                    let k = c % 3;
                    c /= 3;
                    vec![k == 1, k == 2]
                })
                .collect();
            if let Some(v) = solve_general_branch(&p, m, &active).unwrap() {
                best = best.max(v);
            }
        }
        let s = solve_general_pm(&p, &g, m).unwrap();
        assert!(
            (s.objective - best).abs() < 1e-7 * (1.0 + best.abs()),
            "m = {m}: MILP {} vs branches {best}",
            s.objective
        );
        moving += usize::from(best > 1e-3);
    }
    assert!(moving >= 2, "{moving} of 3");
}

#[test]
fn p_m_refuses_what_it_cannot_solve() {
    // An unbounded C, m beyond the limit, a branch LP with a quadratic cost: errors naming
    // the field.
    let mut p = one_link_problem(-1.0, 1.0, 10.0);
    let g = check_problem(&p).unwrap();
    let e = solve_general_pm(&p, &g, 11).unwrap_err().to_string();
    assert!(e.starts_with("m:"), "{e}");
    p.cost = GeneralCost::Quadratic { weight: 1.0 };
    let e = solve_general_branch(&p, 1, &vec![vec![false; 2]; 2])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("objective.cost"), "{e}");
    let half = GeneralProblem::new(GeneralParts {
        normals: vec![vec![1.0]],
        offsets: vec![1.0],
        b: vec![vec![1.0]],
        lower: Some(vec![-1.0]),
        upper: Some(vec![1.0]),
        zero_mean: true,
        face_weights: Some(vec![1.0]),
        period: 1.0,
        periodic: true,
        ..Default::default()
    })
    .unwrap();
    let g = check_problem(&half).unwrap();
    let e = solve_general_pm(&half, &g, 1).unwrap_err().to_string();
    assert!(e.starts_with("sweeping_process"), "{e}");
}

#[test]
fn a_quadratic_cost_by_outer_approximation() {
    // f2 = (c/2) u^2 on the one-link problem: a control of constant magnitude v up then down
    // gives J(v) = (v T - 2 w)/2 - c v^2 T/2 (the reaction pays half the travel beyond the
    // width w = b - a; for a given int |u|, int u^2 is least at constant |u|, Jensen), so
    // v* = min(1, 1/(2c)) and, for c = 1, J* = T/8 - w when T > 8 w. P_m attains it on every
    // grid whose half period is whole steps. T = 40, w = 2: J* = 3.
    let mut p = one_link_problem(-1.0, 1.0, 40.0);
    p.cost = GeneralCost::Quadratic { weight: 1.0 };
    let g = check_problem(&p).unwrap();
    for m in 1..=2 {
        let s = solve_general_pm(&p, &g, m).unwrap();
        assert_eq!(s.certificate.status, MilpStatus::Optimal);
        assert!((s.objective - 3.0).abs() < 1e-5, "m = {m}: {}", s.objective);
        assert!(s.certificate.bound >= s.objective - 1e-9);
        assert!(
            s.path.u.iter().all(|u| (u[0].abs() - 0.5).abs() < 1e-3),
            "{:?}",
            s.path.u
        );
    }
    // A crawler instance with a quadratic cost against the crawler's P_m.
    let crawler = Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap();
    let speed = vec![1.0; 2];
    let gp =
        GaitProblem::new(&crawler, 6.0, &speed, Cost::Quadratic { weight: 0.3 }, None).unwrap();
    let inst = crawler_as_general(
        &crawler,
        6.0,
        &gp.rate_bound,
        GeneralCost::Quadratic { weight: 0.3 },
    )
    .unwrap();
    let g = check_problem(&inst.problem).unwrap();
    let want = solve_discrete_global(&crawler, &gp, 2).unwrap();
    let got = solve_general_pm(&inst.problem, &g, 2).unwrap();
    let j = want.verified_displacement - want.actuation_cost;
    assert!((got.objective - j).abs() < 1e-5, "{} vs {j}", got.objective);
}

/// (P)'s global P_m starts from a given general result (`GeneralPmSettings::start`, `--start`),
/// as a crawler's P_m starts from a gait: its process on the grid is the MILP's first
/// incumbent, recorded as `discrete_start` with its `J`. From the local optimum of the
/// three-block crawler written as (P) the MILP still reaches the global optimum of P_3 (the
/// crawler's own, 2); the answer is never below its start's `J`, reads back as `certify` reads
/// it, and records where it started. Refused naming `start`: with the phase method, with the
/// convergence table, a crawler's gait result, and a result of another problem.
#[test]
fn the_global_p_m_starts_from_a_given_result() {
    use crawlopt::api::{
        optimize_general, optimize_general_local, GaitMethod, GeneralLocalSettings,
        GeneralPmSettings, Hooks, OptimizeSettings, Start,
    };
    use crawlopt::io::{GeneralFile, ResultFile};
    let load = |path: &str| {
        GeneralFile::load_if_general(path.as_ref())
            .unwrap()
            .unwrap()
    };
    let file = load("examples/general_three_blocks.toml");
    let local = GeneralLocalSettings {
        m: 3,
        ..GeneralLocalSettings::default()
    };
    let start = optimize_general_local(&file, &local, Hooks::default()).unwrap();
    let from = |start: Start| GeneralPmSettings {
        m: 3,
        start: Some(start),
        ..GeneralPmSettings::default()
    };
    let given = Start::Result {
        result: Box::new(start.clone().into()),
        name: "local.json".into(),
    };
    let r = optimize_general(&file, &from(given.clone()), Hooks::default()).unwrap();
    let st = r.discrete_start.as_ref().expect("the start is recorded");
    assert_eq!(st.start, "local (local.json)");
    assert!(
        (st.start_objective - start.head.objective).abs() < 1e-9,
        "the start's J on its own grid: {} against {}",
        st.start_objective,
        start.head.objective
    );
    assert!(r.head.objective >= st.start_objective - 1e-9);
    assert_eq!(r.head.status, MilpStatus::Optimal);
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let pb = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let crawler = solve_discrete_global(&c, &pb, 3).unwrap();
    assert!(
        (r.head.objective - crawler.objective()).abs() < 1e-7,
        "(P) from a start {} against the crawler's P_3 {}",
        r.head.objective,
        crawler.objective()
    );
    let text = serde_json::to_string(&r).unwrap();
    let ResultFile::General(back) = ResultFile::from_json(&text, "r.json").unwrap() else {
        panic!("a general result")
    };
    assert_eq!(back.discrete_start, r.discrete_start);
    // What does not take a start, named.
    let refused = |s: OptimizeSettings| match s.plan_general(&[]) {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    let with_start = OptimizeSettings {
        start: Some(given.clone()),
        ..Default::default()
    };
    let phase = OptimizeSettings {
        method: GaitMethod::Phase,
        ..with_start.clone()
    };
    assert_eq!(refused(phase), "start");
    let table = OptimizeSettings {
        convergence: true,
        ..with_start.clone()
    };
    assert_eq!(refused(table), "start");
    // A crawler's gait result, and a result of another problem.
    let g = crawlopt::optimal::GaitResult::from_discrete(&c, &pb, &crawler);
    let e = optimize_general(
        &file,
        &from(Start::Result {
            result: Box::new(g.into()),
            name: "crawler.json".into(),
        }),
        Hooks::default(),
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("start: "), "{e}");
    let one = load("examples/general_one_link.toml");
    let e = optimize_general(&one, &from(given), Hooks::default()).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("start: is a result of a problem with 2 states"),
        "{e}"
    );
}

/// A start is the MILP's first incumbent: under a time limit far too short for the MILP alone
/// (P_4 of the three-block crawler as (P) in 0.05 s, where alone it returns J = 0.125, and
/// 0.042 as a Cauchy problem from 0), the answer is at least the start's `J`, on the periodic
/// problem and on the Cauchy problem (whose last state has a column of its own, filled from the
/// start's last state). An `m` beyond P_m's range is refused naming `m` before
/// the start is averaged on its grid.
#[test]
fn a_start_is_the_first_incumbent_under_a_time_limit() {
    use crawlopt::api::{
        optimize_general, optimize_general_local, GeneralLocalSettings, GeneralPmSettings, Hooks,
        Start,
    };
    use crawlopt::io::GeneralFile;
    use crawlopt::model::general::Boundary;
    use crawlopt::optimal::general::solve_general_pm_from;
    let file = GeneralFile::load_if_general("examples/general_three_blocks.toml".as_ref())
        .unwrap()
        .unwrap();
    let local = GeneralLocalSettings {
        m: 4,
        ..GeneralLocalSettings::default()
    };
    let start = optimize_general_local(&file, &local, Hooks::default()).unwrap();
    let given = Start::Result {
        result: Box::new(start.clone().into()),
        name: "local".into(),
    };
    let s = GeneralPmSettings {
        m: 4,
        time_limit: Some(0.05),
        start: Some(given.clone()),
        ..GeneralPmSettings::default()
    };
    let r = optimize_general(&file, &s, Hooks::default()).unwrap();
    let st = r.discrete_start.as_ref().unwrap();
    assert!(
        r.head.objective >= st.start_objective - 1e-9 && st.start_objective > 2.5,
        "J = {} from a start of J = {}",
        r.head.objective,
        st.start_objective
    );
    // The same start on the problem as a Cauchy problem from x(0) = 0.
    let mut p = file.problem().unwrap();
    p.boundary = Boundary::Initial(vec![0.0; p.states()]);
    let g = check_problem(&p).unwrap();
    let u = start.solution.as_local().unwrap().path.u.clone();
    let (sol, j) =
        crawlopt::progress::within(Some(0.05), || solve_general_pm_from(&p, &g, 4, true, &u))
            .unwrap();
    assert!(
        sol.objective >= j - 1e-9 && j > 0.0,
        "Cauchy: J = {} from a start of J = {j}",
        sol.objective
    );
    let beyond = GeneralPmSettings {
        m: 40,
        start: Some(given),
        ..GeneralPmSettings::default()
    };
    match optimize_general(&file, &beyond, Hooks::default()) {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => assert_eq!(field, "m"),
        other => panic!("{other:?}"),
    }
}

/// Under a time limit (and no start given) (P)'s global P_m starts from the local method's
/// answer on the same grid, as a crawler's P_m does: the local method from its own start (the
/// phase optimum where `A = 0`, the file's `[input]` where there is one), recorded as
/// `discrete_start` and named as a crawler's (the three-block crawler's and its general form's
/// are the same), the MILP still proving its optimum. Not without a time limit; with a
/// quadratic cost (which the local method takes not) from the local method's start itself.
#[test]
fn under_a_time_limit_p_m_starts_from_the_local_answer() {
    use crawlopt::api::{optimize_general, GeneralPmSettings, Hooks};
    use crawlopt::io::GeneralFile;
    let run = |path: &str, time_limit: Option<f64>| {
        let file = GeneralFile::load_if_general(path.as_ref())
            .unwrap()
            .unwrap();
        let s = GeneralPmSettings {
            m: 3,
            time_limit,
            ..GeneralPmSettings::default()
        };
        optimize_general(&file, &s, Hooks::default()).unwrap()
    };
    for (path, from, j) in [
        (
            "examples/general_three_blocks.toml",
            "local on P_3, from phase (K = 5)",
            2.0,
        ),
        (
            "examples/general_one_link.toml",
            "local on P_3, from input",
            3.0,
        ),
    ] {
        let r = run(path, Some(120.0));
        let st = r.discrete_start.as_ref().expect("a default start");
        assert_eq!(st.start, from);
        assert!(st.start_objective <= r.head.objective + 1e-9);
        assert_eq!(r.head.status, MilpStatus::Optimal);
        assert!(
            (r.head.objective - j).abs() < 1e-6,
            "{path}: {}",
            r.head.objective
        );
        assert!(run(path, None).discrete_start.is_none());
    }
    // The crawler whose general form `general_three_blocks` is records the same start, by
    // the same name (one policy, `pm_start`), with the same `J` on the grid.
    let (c, pb) = crawlopt::api::gait_problem(
        &crawlopt::io::ModelFile::load("examples/three_blocks_gait.toml".as_ref()).unwrap(),
    )
    .unwrap();
    let settings = crawlopt::api::OptimizeSettings {
        method: crawlopt::api::GaitMethod::Discrete,
        m: Some(3),
        time_limit: Some(120.0),
        ..Default::default()
    };
    let crawler = crawlopt::api::optimize(&c, &pb, &settings, Hooks::default()).unwrap();
    let twin = crawler.result.discrete_start.expect("the crawler's start");
    let general = run("examples/general_three_blocks.toml", Some(120.0));
    let st = general.discrete_start.expect("(P)'s start");
    assert_eq!(st.start, twin.start);
    assert!((st.start_objective - twin.start_objective).abs() < 1e-9);
    // With a quadratic cost (which the local method takes not) the start is the file's
    // `[input]` itself, unsolved, as a crawler's P_m starts from its phase gait there.
    let quadratic = run("examples/general_drift.toml", Some(120.0));
    let st = quadratic.discrete_start.as_ref().expect("the input starts");
    assert_eq!(st.start, "input");
    assert!(st.start_objective <= quadratic.head.objective + 1e-9);
    assert_eq!(quadratic.head.status, MilpStatus::Optimal);
}

/// With a quadratic cost, under a time limit, a crawler's P_m starts from its phase gait
/// (`optimal::discrete_start`), and so does its general form (where `A = 0` and there is no
/// `[input]`): both record the same phase gait as their start, with the same `J` on the grid,
/// and prove the same optimum of P_2.
/// `max_phases` bounds that phase gait for both kinds (each `K` of the start's growth is an
/// event), and is refused, naming it, where no phase gait starts.
#[test]
fn a_quadratic_cost_starts_p_m_from_the_phase_gait_for_both_kinds() {
    use crawlopt::api::{
        gait_problem, optimize, optimize_general, GaitMethod, GeneralPlan, Hooks, OptimizeSettings,
    };
    use crawlopt::io::{GeneralFile, ModelFile};
    let text = std::fs::read_to_string("examples/three_blocks_gait.toml").unwrap();
    let text = text.replace(
        "cost = { kind = \"none\" }",
        "cost = { kind = \"quadratic\", weight = 0.3 }",
    );
    let (c, pb) = gait_problem(&ModelFile::parse(&text).unwrap()).unwrap();
    let text = std::fs::read_to_string("examples/general_three_blocks.toml").unwrap();
    let text = text.replace(
        "[objective]\n",
        "[objective]\ncost = { kind = \"quadratic\", weight = 0.3 }\n",
    );
    let file = GeneralFile::parse(&text).unwrap();
    let s = OptimizeSettings {
        method: GaitMethod::Discrete,
        m: Some(2),
        max_phases: Some(2),
        time_limit: Some(120.0),
        ..OptimizeSettings::default()
    };
    let (crawler, ks, crawler_notes) =
        with_start_phases(|hooks| optimize(&c, &pb, &s, hooks).unwrap().result);
    assert!(!ks.is_empty() && ks.iter().all(|&k| k <= 2), "{ks:?}");
    let from = crawler
        .discrete_start
        .as_ref()
        .expect("the crawler's start");
    assert!(from.start.starts_with("phase (K = "), "{}", from.start);
    let GeneralPlan::Discrete(pm) = s.plan_general(&[]).unwrap() else {
        panic!("not P_m's plan")
    };
    let (general, ks, notes) =
        with_start_phases(|hooks| optimize_general(&file, &pm, hooks).unwrap());
    // One policy for both kinds: the same start, and the same note saying why it is unsolved.
    assert_eq!(notes, crawler_notes);
    assert_eq!(
        notes,
        ["P_2 starts from the phase gait itself (the local method takes no cost f2)"]
    );
    assert!(!ks.is_empty() && ks.iter().all(|&k| k <= 2), "{ks:?}");
    let st = general.discrete_start.as_ref().expect("(P)'s start");
    assert_eq!(st.start, from.start);
    assert!((st.start_objective - from.start_objective).abs() < 1e-9);
    assert!(st.start_objective <= general.head.objective + 1e-9);
    assert_eq!(general.head.status, MilpStatus::Optimal);
    assert_eq!(crawler.head.status, MilpStatus::Optimal);
    assert!(
        (crawler.head.objective - general.head.objective).abs() < 1e-5,
        "the crawler's {} against (P)'s {}",
        crawler.head.objective,
        general.head.objective
    );
    // No phase gait where the file's `[input]` starts, or where `A != 0`.
    for path in [
        "examples/general_one_link.toml",
        "examples/general_drift.toml",
    ] {
        let file = GeneralFile::load_if_general(path.as_ref())
            .unwrap()
            .unwrap();
        match optimize_general(&file, &pm, Hooks::default()) {
            Err(crawlopt::Error::InvalidParameter { field, .. }) => {
                assert_eq!(field, "max_phases", "{path}")
            }
            other => panic!("{path}: expected a refusal naming max_phases, got {other:?}"),
        }
    }
}

/// What `run` returns with the hooks it is given, the `K` of each phase MILP its start gait
/// solved (its `PhaseSolved` events with `start`), and its notes.
fn with_start_phases<T>(
    run: impl FnOnce(crawlopt::api::Hooks<'_>) -> T,
) -> (T, Vec<usize>, Vec<String>) {
    use crawlopt::api::{Event, Hooks};
    let mut ks = Vec::new();
    let mut notes = Vec::new();
    let mut on = |e: &Event, _: f64| match e {
        Event::PhaseSolved { step, start: true } => ks.push(step.phases),
        Event::Note(n) => notes.push(n.clone()),
        _ => {}
    };
    let hooks = Hooks {
        events: Some(&mut on),
        cancel: None,
    };
    let out = run(hooks);
    (out, ks, notes)
}
