//! P_m of the general problem (P) locally (the active-set method on its LPCC): the paper's §4
//! one-link problem against its closed form from starts that are not optimal, and random small
//! instances against the global MILP (never above it) and the simulator (a true process).

mod common;

use common::{one_link_problem, random_polygon_problem, Rng};
use crawlopt::integrate::{
    simulate_general, ControlInput, DriftStep, GeneralSimOptions, InputKind,
};
use crawlopt::model::general::{Boundary, GeneralCost};
use crawlopt::optimal::general::{
    analyze_polyhedron, check_problem, default_starts, solve_general_local, solve_general_pm,
    LocalRules,
};
use crawlopt::optimal::LocalStop;

/// The square wave `+v` then `-v` on `2^m` steps, rotated by `r` steps.
fn square(m: u32, v: f64, r: usize) -> Vec<Vec<f64>> {
    let mm = 1usize << m;
    let mut w: Vec<Vec<f64>> = (0..mm)
        .map(|i| vec![if i < mm / 2 { v } else { -v }])
        .collect();
    w.rotate_right(r);
    w
}

/// `sin(2 pi t / T)` at the middle of each of `2^m` steps.
fn sine(m: u32) -> Vec<Vec<f64>> {
    let mm = 1usize << m;
    (0..mm)
        .map(|i| vec![(std::f64::consts::TAU * (i as f64 + 0.5) / mm as f64).sin()])
        .collect()
}

#[test]
fn the_one_link_problem_reaches_its_closed_form_from_reasonable_starts() {
    // J* = (T - 2 (b - a)) / 2, attained on every grid whose half period is whole steps
    // (T = 10, C = [-1, 1]: J* = 3). A sine wave and a square wave of amplitude 0.8 travel
    // slower than they may (the square wave's J = (0.8 T - 4) / 2 = 2); the branch LP and the
    // pivots at degenerate pairs reach J*.
    let p = one_link_problem(-1.0, 1.0, 10.0);
    let g = check_problem(&p).unwrap();
    for m in 3..=5 {
        for (name, start) in [("sine", sine(m)), ("square 0.8", square(m, 0.8, 1))] {
            let s = solve_general_local(&p, &g, m, &start, LocalRules::default()).unwrap();
            assert_eq!(s.stop, LocalStop::Stationary);
            assert!(s.start_objective < 2.0 + 1e-9, "{}", s.start_objective);
            assert!(
                (s.objective - 3.0).abs() < 1e-7,
                "m = {m}, {name}: J = {} after {} LPs",
                s.objective,
                s.lp_solves
            );
        }
    }
    // The default starts (full-amplitude square waves at shifts) are optimal themselves here.
    for m in [2, 6] {
        for start in default_starts(&p, m, 4) {
            let s = solve_general_local(&p, &g, m, &start, LocalRules::default()).unwrap();
            assert!((s.objective - 3.0).abs() < 1e-7, "m = {m}: {}", s.objective);
        }
    }
    // Local, not global: from the square wave of amplitude 0.5 on 16 steps (J = 0.5) the
    // method stops at a stationary point of P_4 below J* (J = 1.75 on a plateau of J: the
    // gain needs two branches switched at once), never above it.
    let s = solve_general_local(&p, &g, 4, &square(4, 0.5, 0), LocalRules::default()).unwrap();
    assert!((s.start_objective - 0.5).abs() < 1e-9);
    assert_eq!(s.stop, LocalStop::Stationary);
    assert!(
        s.objective > 0.5 && s.objective < 3.0 - 1e-6,
        "{}",
        s.objective
    );
}

#[test]
fn random_instances_never_above_the_global_optimum_and_true_processes() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut improved = 0;
    let mut cases = 0;
    for (sigma, m) in [(3, 2), (4, 2), (5, 2), (6, 2), (3, 3)] {
        for _ in 0..2 {
            let p = random_polygon_problem(&mut rng, sigma);
            let g = analyze_polyhedron(&p.c).unwrap();
            let global = solve_general_pm(&p, &g, m).unwrap();
            for start in default_starts(&p, m, 2) {
                let s = solve_general_local(&p, &g, m, &start, LocalRules::default()).unwrap();
                cases += 1;
                let tol = 1e-7 * (1.0 + global.objective.abs());
                assert!(
                    s.objective <= global.objective + tol,
                    "sigma = {sigma}, m = {m}: local {} above global {}",
                    s.objective,
                    global.objective
                );
                assert!(s.objective >= s.start_objective - tol);
                improved += usize::from(s.objective > s.start_objective + 1e-6);
                // A true process: its controls, simulated from its x^0, give its states and J.
                let mm = 1usize << m;
                let h = p.period / mm as f64;
                let input = ControlInput::new(
                    InputKind::PiecewiseConstant,
                    p.period,
                    (0..mm).map(|i| i as f64 * h).collect(),
                    s.path.u.clone(),
                    &p.control,
                    "u",
                )
                .unwrap();
                let mut cauchy = p.clone();
                cauchy.boundary = Boundary::Initial(s.path.x[0].clone());
                // P_m's explicit step (the simulator's default steps a damping implicitly).
                let opts = GeneralSimOptions {
                    steps_per_period: mm,
                    drift: DriftStep::Explicit,
                    ..Default::default()
                };
                let sim = simulate_general(&cauchy, &input, &s.path.x[0], &opts).unwrap();
                let dx = sim
                    .x
                    .iter()
                    .flatten()
                    .zip(s.path.x.iter().flatten())
                    .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
                assert!(dx < 1e-9, "states differ by {dx}");
                assert!((sim.objective.unwrap() - s.objective).abs() < 1e-9);
                assert!((s.path.x[mm].iter().zip(&s.path.x[0])).all(|(a, b)| (a - b).abs() < 1e-7));
                let sum: f64 = s.path.u.iter().map(|u| u[0]).sum();
                assert!(sum.abs() < 1e-7, "mean {sum}");
            }
        }
    }
    // The method does move: most starts end above where they began.
    assert!(improved * 2 >= cases, "{improved} of {cases}");
}

#[test]
fn the_local_method_refuses_what_it_cannot_solve() {
    let mut p = one_link_problem(-1.0, 1.0, 10.0);
    let g = check_problem(&p).unwrap();
    let e = solve_general_local(&p, &g, 0, &square(1, 1.0, 0), LocalRules::default()).unwrap_err();
    assert!(e.to_string().starts_with("m:"), "{e}");
    let e = solve_general_local(&p, &g, 15, &square(1, 1.0, 0), LocalRules::default()).unwrap_err();
    assert!(e.to_string().starts_with("m:"), "{e}");
    let e = solve_general_local(&p, &g, 3, &square(2, 1.0, 0), LocalRules::default()).unwrap_err();
    assert!(e.to_string().starts_with("start:"), "{e}");
    let mut biased = square(3, 1.0, 0);
    biased[0][0] = 0.5;
    let e = solve_general_local(&p, &g, 3, &biased, LocalRules::default()).unwrap_err();
    assert!(e.to_string().starts_with("start[1]:"), "{e}");
    let mut outside = square(3, 1.0, 0);
    outside[0][0] = 2.0;
    outside[7][0] = -2.0;
    let e = solve_general_local(&p, &g, 3, &outside, LocalRules::default()).unwrap_err();
    assert!(e.to_string().starts_with("start.values[1]"), "{e}");
    // A bad time limit is the job's setting, refused by the API naming it.
    let file =
        crawlopt::io::GeneralFile::load_if_general("examples/general_one_link.toml".as_ref())
            .unwrap()
            .unwrap();
    let s = crawlopt::api::GeneralLocalSettings {
        m: 3,
        time_limit: Some(-1.0),
        ..crawlopt::api::GeneralLocalSettings::default()
    };
    let e = crawlopt::api::optimize_general_local(&file, &s, crawlopt::api::Hooks::default())
        .unwrap_err();
    assert!(e.to_string().starts_with("time_limit:"), "{e}");
    p.cost = GeneralCost::Quadratic { weight: 1.0 };
    let e = solve_general_local(&p, &g, 3, &square(3, 1.0, 0), LocalRules::default()).unwrap_err();
    assert!(e.to_string().starts_with("objective.cost:"), "{e}");
}

/// A time limit spent before the first LP (1 ns) ends the local method with a time-limit error,
/// through the deadline the limit becomes; a cancelled job says cancelled even with its time
/// spent (cancellation wins over the time).
#[test]
fn a_spent_time_limit_ends_the_local_method_and_a_cancel_wins_over_it() {
    use crawlopt::api::{optimize_general_local, GeneralLocalSettings, Hooks};
    let p = one_link_problem(-1.0, 1.0, 10.0);
    let g = check_problem(&p).unwrap();
    let e = crawlopt::progress::within(Some(1e-9), || {
        solve_general_local(&p, &g, 3, &square(3, 1.0, 0), LocalRules::default())
    })
    .unwrap_err();
    assert!(matches!(e, crawlopt::Error::TimeLimit(_)), "{e}");
    let file =
        crawlopt::io::GeneralFile::load_if_general("examples/general_one_link.toml".as_ref())
            .unwrap()
            .unwrap();
    let s = GeneralLocalSettings {
        m: 3,
        time_limit: Some(1e-9),
        ..GeneralLocalSettings::default()
    };
    let e = optimize_general_local(&file, &s, Hooks::default()).unwrap_err();
    assert!(matches!(e, crawlopt::Error::TimeLimit(_)), "{e}");
    let cancel = crawlopt::progress::Cancel::new();
    cancel.cancel();
    let hooks = Hooks {
        events: None,
        cancel: Some(&cancel),
    };
    assert_eq!(
        optimize_general_local(&file, &s, hooks).unwrap_err(),
        crawlopt::Error::Cancelled
    );
}

#[test]
fn the_api_job_reports_its_starts_and_can_be_cancelled() {
    use crawlopt::api::{optimize_general_local, Event, GeneralLocalSettings, Hooks};
    use crawlopt::io::GeneralFile;
    use crawlopt::progress::Cancel;
    let file = GeneralFile::load_if_general("examples/general_one_link.toml".as_ref())
        .unwrap()
        .unwrap();
    let settings = GeneralLocalSettings {
        m: 3,
        shifts: 3,
        time_limit: None,
        start: None,
        max_phases: None,
        certify: false,
        bound: None,
    };
    let mut stages = 0;
    let mut count = |e: &Event, _: f64| stages += usize::from(matches!(e, Event::Stage(_)));
    let hooks = Hooks {
        events: Some(&mut count),
        cancel: None,
    };
    let r = optimize_general_local(&file, &settings, hooks).unwrap();
    assert_eq!(
        (
            r.starts.unwrap().start_from,
            r.starts.unwrap().starts_tried,
            stages
        ),
        ("input", 3, 3)
    );
    assert!((r.solution.objective() - 3.0).abs() < 1e-9);
    let cancel = Cancel::new();
    cancel.cancel();
    let hooks = Hooks {
        events: None,
        cancel: Some(&cancel),
    };
    let e = optimize_general_local(&file, &settings, hooks).unwrap_err();
    assert!(matches!(e, crawlopt::Error::Cancelled), "{e}");
}

/// Where `A = 0` and the file has no `[input]`, (P)'s local method starts from the phase
/// optimum (`start_from = "phase"`), as a crawler's local method does: on the three-block
/// crawler written as (P) its answer is the crawler's local answer (J = 2.595703125 at m = 10,
/// the same for both), where the square waves it started from before stopped at J = 2e-15.
/// With a drift (`A != 0`) no phase gait applies and the square waves start.
#[test]
fn the_local_method_starts_from_the_phase_optimum_where_a_is_zero() {
    use crawlopt::api::{optimize_general_local, GeneralLocalSettings, Hooks};
    use crawlopt::io::GeneralFile;
    use crawlopt::optimal::{solve_discrete_local_shifted, GaitProblem};
    let file = GeneralFile::load_if_general("examples/general_three_blocks.toml".as_ref())
        .unwrap()
        .unwrap();
    assert!(file.input.is_none());
    let r =
        optimize_general_local(&file, &GeneralLocalSettings::default(), Hooks::default()).unwrap();
    assert_eq!(r.starts.unwrap().start_from, "phase");
    // The crawler's local method from its phase start (the default policy of `optimize
    // --method local` on the crawler's file).
    let c = crawlopt::Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let pb = GaitProblem::new(&c, 10.0, &[1.0, 1.0], crawlopt::optimal::Cost::None, None).unwrap();
    let start = crawlopt::optimal::phase_start(
        &c,
        &pb,
        &crawlopt::optimal::GrowOptions::default(),
        &mut |_| {},
    )
    .unwrap();
    let (crawler, _) =
        solve_discrete_local_shifted(&c, &pb, 10, start.times(), start.lengths(), 8).unwrap();
    println!(
        "general J = {}, crawler J = {}",
        r.head.objective,
        crawler.objective()
    );
    assert!((r.head.objective - crawler.objective()).abs() < 1e-9);
    assert!(r.head.objective > 2.59, "{}", r.head.objective);
    // A period so short that the phase gait's mean, zero to its solver's tolerance, is 7e-9
    // of its controls: refused as a start before its grid was shifted to an exact zero mean
    // ("start[1]: the start control must have zero mean"). J* = 0 here (T < 2 (b - a)).
    let short = GeneralFile::parse(
        "[sweeping_process]\nnormals = [[1.0], [-1.0]]\noffsets = [1.0e-4, 1.0e-4]\n[dynamics]\n\
         B = [[1.0]]\n[control]\nlower = [-1.0]\nupper = [1.0]\nzero_mean = true\n\
         [objective]\nface_weights = [0.5, 0.5]\n[problem]\nperiod = 3.0e-5\n",
    )
    .unwrap();
    let s = GeneralLocalSettings {
        m: 6,
        ..GeneralLocalSettings::default()
    };
    let r = optimize_general_local(&short, &s, Hooks::default()).unwrap();
    assert_eq!(r.starts.unwrap().start_from, "phase");
    assert!(r.head.objective.abs() < 1e-12, "{}", r.head.objective);
    // A drift: the square waves.
    let drift = GeneralFile::parse(
        "[sweeping_process]\nnormals = [[1.0], [-1.0]]\noffsets = [1.0, 1.0]\n[dynamics]\n\
         A = [[-0.1]]\nB = [[1.0]]\n[control]\nlower = [-1.0]\nupper = [1.0]\nzero_mean = true\n\
         [objective]\nface_weights = [0.5, 0.5]\n[problem]\nperiod = 10.0\n",
    )
    .unwrap();
    let s = GeneralLocalSettings {
        m: 4,
        shifts: 2,
        time_limit: None,
        start: None,
        max_phases: None,
        certify: false,
        bound: None,
    };
    let r = optimize_general_local(&drift, &s, Hooks::default()).unwrap();
    assert_eq!(
        (r.starts.unwrap().start_from, r.starts.unwrap().starts_tried),
        ("square_waves", 2)
    );
}

/// A general job's notes reach its answer, as a crawler's do (`OptimizedFile::notes`, printed
/// by the command line after the job, `GeneralResult.notes` in Python): the three-block
/// crawler written as (P), by the crawler's sequence method at two slip phases, returns the
/// best structured gait and says why. Before, a note showed on the progress line only.
///
/// And the phase start on a short period: on a random 3-D polytope with `T = 1e-3`, the phase
/// gait's grid, shifted to a zero mean, lay outside U by `1.6e-9`, and the local method fell
/// back to square waves (with a note); its controls are now moved to a zero mean within U, and
/// it starts from the phase gait without a note.
#[test]
fn a_general_jobs_notes_reach_its_answer() {
    use crawlopt::api::{optimize_file, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::io::{GeneralFile, ProblemFile, ResultFile};
    let run = |file: GeneralFile, settings: &OptimizeSettings, seen: &mut Vec<String>| {
        let mut watch = |e: &crawlopt::api::Event, _: f64| {
            if let crawlopt::api::Event::Note(n) = e {
                seen.push(n.clone());
            }
        };
        let hooks = Hooks {
            events: Some(&mut watch),
            cancel: None,
        };
        optimize_file(&ProblemFile::General(Box::new(file)), settings, hooks).unwrap()
    };
    let three = GeneralFile::load_if_general("examples/general_three_blocks.toml".as_ref())
        .unwrap()
        .unwrap();
    let sequence = OptimizeSettings {
        method: GaitMethod::Sequence,
        phases: Some(2),
        ..Default::default()
    };
    let mut seen = Vec::new();
    let done = run(three, &sequence, &mut seen);
    assert_eq!(done.notes(), &seen[..], "the caller's events are passed on");
    assert_eq!(done.notes().len(), 1, "{:?}", done.notes());
    assert!(
        done.notes()[0].contains("is below the best structured gait"),
        "{}",
        done.notes()[0]
    );
    let short = GeneralFile::parse(
        "[sweeping_process]\n\
         normals = [[1.0575, -0.1534, -0.0317], [-1.1149, -0.0921, 0.1884], \
         [0.1214, 0.9217, 0.1539], [-0.1157, -1.0423, 0.1418], [0.0567, -0.1599, 1.1957], \
         [-0.1147, -0.0967, -0.8909], [0.9316, 0.9185, 0.8294], [-1.164, -0.9669, 0.8972]]\n\
         offsets = [1.101, 0.872, 0.953, 1.459, 0.984, 1.075, 1.367, 0.683]\n\
         [dynamics]\nB = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n\
         [control]\nlower = [-1.0, -1.0, -1.0]\nupper = [1.0, 1.0, 1.0]\nzero_mean = true\n\
         [objective]\nface_weights = [-0.692, 0.817, 0.636, -0.501, -0.62, 0.479, 0.881, -0.607]\n\
         [problem]\nperiod = 0.001\n",
    )
    .unwrap();
    let local = OptimizeSettings {
        method: GaitMethod::Local,
        m: Some(5),
        ..Default::default()
    };
    let mut seen = Vec::new();
    let done = run(short, &local, &mut seen);
    let ResultFile::General(answer) = &done.result else {
        panic!("a general answer")
    };
    let r = answer.as_ref();
    assert!(r.solution.as_local().is_some(), "the local method's answer");
    assert_eq!(r.starts.unwrap().start_from, "phase", "{:?}", done.notes());
    assert!(done.notes().is_empty() && seen.is_empty(), "{seen:?}");
}

/// (P)'s local method starts from a given general result (`--start`, `Start::File` or
/// `Start::Result`), as a crawler's does from a gait result: its control averaged on the grid
/// (`start_from = "start"`). A local optimum started from itself is stationary: the same `J`,
/// which is its start's. A phase optimum's result starts it too (never below its start's `J`
/// on the grid). A start of another shape, or a crawler's gait result, is refused naming
/// `start`.
#[test]
fn the_local_method_starts_from_a_given_result() {
    use crawlopt::api::{
        optimize_general_local, optimize_general_phase, GeneralLocalSettings, GeneralPhaseSettings,
        Hooks, Start,
    };
    use crawlopt::io::GeneralFile;
    let file = GeneralFile::load_if_general("examples/general_three_blocks.toml".as_ref())
        .unwrap()
        .unwrap();
    let s = GeneralLocalSettings {
        m: 6,
        shifts: 2,
        ..GeneralLocalSettings::default()
    };
    let first = optimize_general_local(&file, &s, Hooks::default()).unwrap();
    let again = GeneralLocalSettings {
        shifts: 1,
        start: Some(Start::Result {
            result: Box::new(first.clone().into()),
            name: "first".into(),
        }),
        ..s.clone()
    };
    let r = optimize_general_local(&file, &again, Hooks::default()).unwrap();
    assert_eq!(
        (r.starts.unwrap().start_from, r.starts.unwrap().starts_tried),
        ("start", 1)
    );
    assert!((r.solution.as_local().unwrap().start_objective - first.head.objective).abs() < 1e-9);
    assert!(
        (r.head.objective - first.head.objective).abs() < 1e-9,
        "{}",
        r.head.objective
    );
    // From a phase optimum's result file, as `--start` reads it.
    let phase = optimize_general_phase(
        &file,
        &GeneralPhaseSettings {
            phases: Some(3),
            ..GeneralPhaseSettings::default()
        },
        Hooks::default(),
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("phase.json");
    std::fs::write(&path, serde_json::to_string(&phase).unwrap()).unwrap();
    let from_file = GeneralLocalSettings {
        start: Some(Start::File(path)),
        ..s.clone()
    };
    let r = optimize_general_local(&file, &from_file, Hooks::default()).unwrap();
    assert_eq!(r.starts.unwrap().start_from, "start");
    assert!(r.head.objective >= r.solution.as_local().unwrap().start_objective - 1e-9);
    // The start is the phase gait averaged on 64 steps (J = 2.125 there for the phase's
    // 2.1667; the local answer 2.1875).
    assert!(
        (r.solution.as_local().unwrap().start_objective - phase.head.objective).abs()
            < 0.05 * phase.head.objective,
        "phase J = {}, its start on the grid {}",
        phase.head.objective,
        r.solution.as_local().unwrap().start_objective
    );
    // Another shape: the one-link problem's own answer on the three-block problem.
    let one = GeneralFile::load_if_general("examples/general_one_link.toml".as_ref())
        .unwrap()
        .unwrap();
    let wrong = GeneralLocalSettings {
        start: Some(Start::Result {
            result: Box::new(first.into()),
            name: "three.json".into(),
        }),
        ..s.clone()
    };
    let e = optimize_general_local(&one, &wrong, Hooks::default()).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("start: is a result of a problem with 2 states"),
        "{e}"
    );
    // A crawler's gait result.
    let c = crawlopt::Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let pb = crawlopt::optimal::GaitProblem::new(
        &c,
        10.0,
        &[1.0, 1.0],
        crawlopt::optimal::Cost::None,
        None,
    )
    .unwrap();
    let g = crawlopt::optimal::GaitResult::from_discrete(
        &c,
        &pb,
        &crawlopt::optimal::solve_discrete_global(&c, &pb, 2).unwrap(),
    );
    let crawler = GeneralLocalSettings {
        start: Some(Start::Result {
            result: Box::new(g.into()),
            name: "crawler.json".into(),
        }),
        ..s
    };
    let e = optimize_general_local(&file, &crawler, Hooks::default()).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("start: is a crawler's gait result"),
        "{e}"
    );
}

/// A start computed for a problem whose controls reach further (a wider U, faster actuators)
/// is no gait of this problem: refused naming `start` and the start's own field, for (P) and
/// for a crawler alike. The crawler's local method had answered "an LP of fixed branches has
/// no feasible point", and (P)'s `start.values[1]: lies outside U`. A start from a narrower
/// problem is a gait of this one and is taken: (P)'s local method from the one-link optimum
/// of `U = [-1, 1]` reaches the optimum of `U = [-2, 2]` (J = 8 at `T = 10`, `m = 5`).
#[test]
fn a_start_outside_this_problems_controls_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let examples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let read = |name: &str| std::fs::read_to_string(examples.join(name)).unwrap();
    let narrow = examples.join("general_one_link.toml");
    let wide = common::write(
        dir.path(),
        "wide.toml",
        &read("general_one_link.toml")
            .replace("lower = [-1.0]", "lower = [-2.0]")
            .replace("upper = [1.0]", "upper = [2.0]"),
    );
    let crawler = examples.join("three_blocks_gait.toml");
    let fast = common::write(
        dir.path(),
        "fast.toml",
        &read("three_blocks_gait.toml")
            .replace("max_actuator_speed = 1.0", "max_actuator_speed = 2.0"),
    );
    let phase = |file: &std::path::Path, name: &str| {
        let v = common::crawlopt_json(&[
            "optimize",
            file.to_str().unwrap(),
            "--method",
            "phase",
            "--json",
        ]);
        common::write(dir.path(), name, &v.to_string())
    };
    let (wide_start, fast_start) = (phase(&wide, "wide.json"), phase(&fast, "fast.json"));
    for (file, start, method, want) in [
        (
            &narrow,
            &wide_start,
            "local",
            "error: start: its control solution.controls[",
        ),
        (
            &crawler,
            &fast_start,
            "local",
            "error: start: its rate solution.controls[",
        ),
        (
            &crawler,
            &fast_start,
            "sequence",
            "error: start: its rate solution.controls[",
        ),
    ] {
        let out = common::crawlopt(&[
            "optimize",
            file.to_str().unwrap(),
            "--method",
            method,
            "--start",
            start.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.starts_with(want), "{err}");
    }
    let narrow_start = phase(&narrow, "narrow.json");
    let v = common::crawlopt_json(&[
        "optimize",
        wide.to_str().unwrap(),
        "--method",
        "local",
        "--m",
        "5",
        "--start",
        narrow_start.to_str().unwrap(),
        "--json",
    ]);
    assert!((v["objective"].as_f64().unwrap() - 8.0).abs() < 1e-9, "{v}");
    assert_eq!(v["start_from"], "start");
}

/// The crawler's local method is (P)'s on the crawler's instance, under one set of rules for
/// both kinds (`LocalRules`' default for one start, `MultiStart::for_starts` for several): the
/// three-block crawler and its general form (`general_three_blocks.toml`) reach the same
/// local optimum from the same phase start at the same shifts, and the same status. While
/// (P) had rules of its own, the general form ended at 2.46875 at m = 6 where the crawler
/// reached 2.5625.
#[test]
fn a_crawler_and_its_general_form_reach_the_same_local_optimum() {
    use crawlopt::api::{
        gait_problem, optimize, optimize_general_local, GaitMethod, GeneralLocalSettings, Hooks,
        OptimizeSettings,
    };
    use crawlopt::io::{GeneralFile, ModelFile};
    let model = ModelFile::load("examples/three_blocks_gait.toml".as_ref()).unwrap();
    let (c, pb) = gait_problem(&model).unwrap();
    let file = GeneralFile::load_if_general("examples/general_three_blocks.toml".as_ref())
        .unwrap()
        .unwrap();
    for m in [4, 6, 8] {
        let s = OptimizeSettings {
            method: GaitMethod::Local,
            m: Some(m),
            ..OptimizeSettings::default()
        };
        let crawler = optimize(&c, &pb, &s, Hooks::default()).unwrap().result;
        let s = GeneralLocalSettings {
            m,
            ..GeneralLocalSettings::default()
        };
        let general = optimize_general_local(&file, &s, Hooks::default()).unwrap();
        assert!(
            (crawler.head.objective - general.head.objective).abs() < 1e-9,
            "m = {m}: the crawler's {} against (P)'s {}",
            crawler.head.objective,
            general.head.objective
        );
        assert_eq!(crawler.head.status, general.head.status, "m = {m}");
    }
}

/// A file's `[input]` that cannot start the local method (here a mean of 0.25 under
/// `zero_mean = true`) is refused naming `input.values`, the field to mend, not the grid's
/// `start[1]` it was averaged into.
#[test]
fn an_input_that_cannot_start_the_local_method_is_named() {
    use crawlopt::api::{optimize_general_local, GeneralLocalSettings, Hooks};
    let text = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let start = text.rfind("[input]").expect("the example has an input");
    let text = format!(
        "{}[input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 5.0]\nvalues = [[1.0], [-0.5]]\n",
        &text[..start]
    );
    let file = crawlopt::io::GeneralFile::parse(&text).unwrap();
    let s = GeneralLocalSettings {
        m: 3,
        ..GeneralLocalSettings::default()
    };
    match optimize_general_local(&file, &s, Hooks::default()) {
        Err(crawlopt::Error::InvalidParameter { field, reason, .. }) => {
            assert_eq!(field, "input.values", "{reason}");
            assert!(reason.contains("zero mean"), "{reason}");
        }
        other => panic!("expected a refusal naming input.values, got {other:?}"),
    }
}

/// `certify` applies to (P)'s local method as to its global ones and to a crawler's local
/// method: the conditions it attaches are those `crawlopt certify` computes on the same answer
/// read back without them (`api::certify_result_file`), on the one-link problem (P_10, where
/// the local answer is the optimum J = 3, and the conditions hold) and on the three-block
/// crawler written as (P). Before, the setting was refused for the local method.
#[test]
fn the_local_methods_certify_is_the_one_certify_of_its_result() {
    use crawlopt::api::{certify_result_file, optimize_file, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::certify::Verdict;
    use crawlopt::io::{GeneralFile, ProblemFile, ResultFile};
    for (path, holds) in [
        ("examples/general_one_link.toml", true),
        ("examples/general_three_blocks.toml", false),
    ] {
        let file = GeneralFile::load_if_general(path.as_ref())
            .unwrap()
            .unwrap();
        let file = ProblemFile::General(Box::new(file));
        let settings = OptimizeSettings {
            method: GaitMethod::Local,
            certify: true,
            ..Default::default()
        };
        let done = optimize_file(&file, &settings, Hooks::default()).unwrap();
        let ResultFile::General(answer) = done.result.clone() else {
            panic!("a general answer")
        };
        let attached = answer.necessary_conditions.clone().expect("certified");
        if holds {
            assert_eq!(
                attached.verdict,
                Verdict::Holds,
                "{path}: {}",
                attached.reason
            );
            assert!((answer.head.objective - 3.0).abs() < 1e-9, "{path}");
        }
        let mut bare = answer.clone();
        bare.necessary_conditions = None;
        let text = crawlopt::io::json::to_string(&ResultFile::General(bare)).unwrap();
        let read = ResultFile::from_json(&text, path).unwrap();
        let again = certify_result_file(read, path).unwrap();
        assert_eq!(
            crawlopt::io::json::to_string(&again).unwrap(),
            crawlopt::io::json::to_string(&attached).unwrap(),
            "{path}"
        );
    }
}

/// `bound` applies to (P)'s local method where the problem is a crawler's (a chain), as to its
/// global methods and to a crawler's local method: the same upper bound as the global P_m's
/// under the same settings (the bound is over all periodic gaits, whatever the method), at
/// least the local J, kept when the result is read back, and a recorded bound below J refused
/// naming its field. Before, the setting was refused for the local method.
#[test]
fn the_local_method_proves_the_chains_upper_bound() {
    use crawlopt::api::{optimize_file, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::certify::bound::BoundSettings;
    use crawlopt::io::{GeneralFile, ProblemFile, ResultFile};
    let path = "examples/general_three_blocks.toml";
    let file = GeneralFile::load_if_general(path.as_ref())
        .unwrap()
        .unwrap();
    let file = ProblemFile::General(Box::new(file));
    let bound = BoundSettings {
        resolution: Some(2),
        box_resolution: Some(2),
        ..Default::default()
    };
    let with = |method| OptimizeSettings {
        method,
        bound: Some(bound),
        ..Default::default()
    };
    let answer = |method| {
        let done = optimize_file(&file, &with(method), Hooks::default()).unwrap();
        let ResultFile::General(a) = done.result else {
            panic!("a general answer")
        };
        a
    };
    let (local, global) = (answer(GaitMethod::Local), answer(GaitMethod::Discrete));
    let ub = local.head.certificate.upper_bound.clone().expect("a bound");
    let want = global
        .head
        .certificate
        .upper_bound
        .clone()
        .expect("a bound");
    assert_eq!(ub.value, want.value);
    assert!(
        ub.value >= local.head.objective,
        "{} < {}",
        ub.value,
        local.head.objective
    );
    let text = crawlopt::io::json::to_string(&ResultFile::General(local.clone())).unwrap();
    let read = ResultFile::from_json(&text, path).unwrap();
    assert_eq!(read, ResultFile::General(local.clone()));
    // A recorded answer is refused naming the field it gets wrong: a bound below J; a gap (a
    // local answer proves no bound of its own); the chain's bound on a problem that is not a
    // chain (the one-link problem's local answer, with the three-block one's bound).
    let refused = |a: &crawlopt::io::GeneralAnswer, field: &str| {
        let text =
            crawlopt::io::json::to_string(&ResultFile::General(Box::new(a.clone()))).unwrap();
        let e = ResultFile::from_json(&text, path).unwrap_err();
        assert!(
            matches!(&e, crawlopt::Error::InvalidParameter { field: f, .. } if f.ends_with(field)),
            "{field}: {e}"
        );
    };
    let mut low = local.clone();
    low.head.certificate.upper_bound.as_mut().unwrap().value = 1.0;
    refused(&low, "certificate.upper_bound.value");
    let mut gap = local;
    gap.head.certificate.gap = Some(0.0);
    refused(&gap, "certificate.gap");
    let one_link = GeneralFile::load_if_general("examples/general_one_link.toml".as_ref())
        .unwrap()
        .unwrap();
    let one_link = ProblemFile::General(Box::new(one_link));
    let e = optimize_file(&one_link, &with(GaitMethod::Local), Hooks::default()).unwrap_err();
    assert!(
        matches!(&e, crawlopt::Error::InvalidParameter { field, .. } if field == "bound"),
        "{e}"
    );
    let plain = OptimizeSettings {
        method: GaitMethod::Local,
        ..Default::default()
    };
    let done = optimize_file(&one_link, &plain, Hooks::default()).unwrap();
    let ResultFile::General(mut foreign) = done.result else {
        panic!("a general answer")
    };
    foreign.head.certificate.upper_bound = Some(ub);
    refused(&foreign, "certificate.upper_bound");
}
