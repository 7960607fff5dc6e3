//! The command line on general problem files (`[sweeping_process]`, theory §11): `analyze` and
//! `simulate` on the examples, and every refused input with exit 2 and its field named.

use std::process::Output;

mod common;
use common::{crawlopt, write};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

/// The one-link problem of the paper's §4 in general form, with `edit` applied to its text.
const ONE_LINK: &str = "[sweeping_process]\nnormals = [[1.0], [-1.0]]\noffsets = [1.0, 1.0]\n\
[dynamics]\nB = [[1.0]]\n[control]\nlower = [-1.0]\nupper = [1.0]\n\
[objective]\nface_weights = [0.5, 0.5]\n[problem]\nperiod = 10.0\n\
[input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 5.0]\nvalues = [[1.0], [-1.0]]\n";

#[test]
fn analyze_and_simulate_the_examples() {
    let out = crawlopt(&["analyze", "examples/general_drift.toml", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["kind"], "general");
    assert_eq!(v["geometry"]["vertices"].as_array().unwrap().len(), 4);
    assert_eq!(v["geometry"]["bounded"], true);
    assert_eq!(v["geometry"]["chebyshev_radius"], 1.0);
    let out = crawlopt(&["simulate", "examples/general_one_link.toml", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    // J* = (T - 2 (b - a)) / 2 = 3, on the bang-bang gait.
    let j = v["simulation"]["objective"].as_f64().unwrap();
    assert!((j - 3.0).abs() < 1e-12, "{j}");
    // A = 0 and a piecewise-constant input: the exact method unless catching-up is asked.
    assert_eq!(v["method"], "exact");
    let out = crawlopt(&[
        "simulate",
        "examples/general_one_link.toml",
        "--method",
        "catching-up",
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(v["method"], "catching-up");
    let j = v["simulation"]["objective"].as_f64().unwrap();
    assert!((j - 3.0).abs() < 1e-12, "{j}");
    assert_eq!(v["simulation"]["converged"], true);
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("drift.csv");
    let out = crawlopt(&[
        "simulate",
        "examples/general_drift.toml",
        "--steps-per-period",
        "100",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("J = "));
    // t, x_1, x_2, u_1, u_2, lambda_1..lambda_4; 101 rows after the header.
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(
        rows[0],
        "t,x_1,x_2,u_1,u_2,lambda_1,lambda_2,lambda_3,lambda_4"
    );
    assert_eq!(rows.len(), 102);
    assert_eq!(rows[1].split(',').count(), 9);
    // A directory as the output file is refused before any work.
    let out = crawlopt(&[
        "simulate",
        "examples/general_drift.toml",
        "-o",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn bad_problem_files_exit_2_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &str, &str, &str)] = &[
        // (command, replace, with, the message's start)
        (
            "analyze",
            "offsets = [1.0, 1.0]",
            "offsets = [1.0]",
            "sweeping_process.offsets",
        ),
        (
            "analyze",
            "offsets = [1.0, 1.0]",
            "offsets = [1.0, inf]",
            "sweeping_process.offsets[2]",
        ),
        (
            "analyze",
            "[[1.0], [-1.0]]",
            "[[1.0], [0.0]]",
            "sweeping_process.normals[2]",
        ),
        (
            "analyze",
            "B = [[1.0]]",
            "B = [[1.0, 2.0]]",
            "control.lower",
        ),
        (
            "analyze",
            "B = [[1.0]]",
            "B = [[1.0]]\nA = [[nan]]",
            "dynamics.A[1][1]",
        ),
        (
            "analyze",
            "lower = [-1.0]",
            "lower = [0.5]",
            "control.lower[1], control.upper[1]",
        ),
        (
            "analyze",
            "offsets = [1.0, 1.0]",
            "offsets = [-1.0, -1.0]",
            "sweeping_process: C is empty",
        ),
        // C = {0}: no interior (the paper's PLICQ).
        (
            "analyze",
            "offsets = [1.0, 1.0]",
            "offsets = [0.0, 0.0]",
            "sweeping_process",
        ),
        (
            "analyze",
            "face_weights = [0.5, 0.5]",
            "face_weights = [0.5]",
            "objective.face_weights",
        ),
        (
            "analyze",
            "period = 10.0",
            "period = -1.0",
            "problem.period",
        ),
        (
            "simulate",
            "values = [[1.0], [-1.0]]",
            "values = [[2.0], [-1.0]]",
            "input.values[1]",
        ),
        (
            "simulate",
            "times = [0.0, 5.0]",
            "times = [0.0, 12.0]",
            "input.times[2]",
        ),
        (
            "analyze",
            "[problem]",
            "[problem]\nperiodic = false",
            "problem.initial_state",
        ),
        (
            "analyze",
            "[objective]",
            "[objective]\nextra = 1",
            "invalid model file",
        ),
    ];
    for (i, (cmd, from, to, want)) in cases.iter().enumerate() {
        assert!(ONE_LINK.contains(from), "{from}");
        let f = write(
            dir.path(),
            &format!("p{i}.toml"),
            &ONE_LINK.replacen(from, to, 1),
        );
        let out = crawlopt(&[cmd, f.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{to}: {}", stderr(&out));
        let err = stderr(&out);
        // A parse error starts with the file's path.
        let named = err.starts_with(&format!("error: {want}"))
            || (want.starts_with("invalid") && err.contains(want));
        assert!(named, "{to}: want {want:?}, got {err}");
    }
    // Face weights at a vertex where three faces meet: the vertex is named, after the report.
    let square = "[sweeping_process]\n\
        normals = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 1.0]]\n\
        offsets = [1.0, 1.0, 1.0, 1.0, 2.0]\n[dynamics]\nB = [[1.0, 0.0], [0.0, 1.0]]\n\
        [control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\n\
        [objective]\nface_weights = [1.0, 0.0, 0.0, 0.0, 0.0]\n[problem]\nperiod = 1.0\n";
    let f = write(dir.path(), "square.toml", square);
    let out = crawlopt(&["analyze", f.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("objective.face_weights") && err.contains("vertex 1 = [1.0, 1.0]"),
        "{err}"
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("FAIL face weights well defined") && text.contains("(redundant)"));
    // With reaction weights the same polytope is fine.
    let f = write(
        dir.path(),
        "square_q.toml",
        &square.replace(
            "face_weights = [1.0, 0.0, 0.0, 0.0, 0.0]",
            "reaction_weights = [1.0, 0.0]",
        ),
    );
    let out = crawlopt(&["analyze", f.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
}

#[test]
fn optimize_solves_p_m_of_a_general_file() {
    let out = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--m",
        "2",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    let j = v["objective"].as_f64().unwrap();
    assert!((j - 3.0).abs() < 1e-7, "{j}");
    assert_eq!(v["status"], "optimal");
    assert_eq!(v["solution"]["controls"].as_array().unwrap().len(), 4);
    for (args, want) in [
        (&["--method", "phase", "--m", "2"][..], "error: --m"),
        (
            &["--method", "phase", "--max-phases", "0"][..],
            "error: --max-phases",
        ),
        // The crawler's upper bound: refused (it used to be dropped unsaid).
        (&["--bound"][..], "error: --bound"),
        (&["--m", "11"][..], "error: --m"),
        (&["--m", "0"][..], "error: --m: must be at least 1"),
    ] {
        let mut all = vec!["optimize", "examples/general_one_link.toml"];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).starts_with(want), "{}", stderr(&out));
    }
    // The drift example (A != 0, quadratic cost): P_1's step h = 5 is beyond the explicit
    // limit for A = -0.5 I (h |A| = 2.5 > 2: the factor 1 + h A = -1.5 reverses and grows
    // x), refused naming m and the m it needs; P_3 (h |A| = 0.625) is solved.
    let out = crawlopt(&["optimize", "examples/general_drift.toml", "--m", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with("error: --m:") && stderr(&out).contains("needs m >= 2"),
        "{}",
        stderr(&out)
    );
    let out = crawlopt(&[
        "optimize",
        "examples/general_drift.toml",
        "--m",
        "3",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert!(v["objective"].as_f64().unwrap().is_finite());
}

#[test]
fn optimize_convergence_tabulates_p_1_to_p_m_of_a_general_file() {
    let out = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--convergence",
        "--m",
        "3",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    let rows = v["convergence"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row["m"], i + 1);
        assert!((row["objective"].as_f64().unwrap() - 3.0).abs() < 1e-7);
    }
    let out = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--convergence",
        "--m",
        "2",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("convergence of the discrete problems P_m:")
    );
    for method in ["local", "phase"] {
        let out = crawlopt(&[
            "optimize",
            "examples/general_one_link.toml",
            "--method",
            method,
            "--convergence",
        ]);
        assert_eq!(out.status.code(), Some(2), "{method}");
        assert!(
            stderr(&out).starts_with("error: --convergence"),
            "{}",
            stderr(&out)
        );
    }
}

#[test]
fn optimize_method_phase_finds_the_exact_gait() {
    // The one-link problem: J* = (T - 2 (b - a)) / 2 = 3 with 4 phases (free rise, slide on
    // b, free fall, slide on a), two of them with a held face; in the general formulation
    // (K phases, no free transition), which needs K = 4 for it.
    let out = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--method",
        "phase",
        "--formulation",
        "general",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["method"], "phase");
    let j = v["objective"].as_f64().unwrap();
    assert!((j - 3.0).abs() < 1e-7, "{j}");
    assert_eq!(v["status"], "optimal_among_k_phases");
    let held = v["solution"]["held"].as_array().unwrap();
    assert_eq!(held.len(), 4);
    assert_eq!(
        held.iter()
            .filter(|h| !h.as_array().unwrap().is_empty())
            .count(),
        2
    );
    let out = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--method",
        "phase",
        "--formulation",
        "general",
        "--max-phases",
        "3",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("J = 0"));
    // K grown (the default): the table of the K solved, J_K = 0 below 4 phases; a fixed
    // --phases K is one MILP, with no table; --patience and --phases are checked.
    let table = &v["phase_growth"]["table"];
    let js: Vec<f64> = table
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["objective"].as_f64().unwrap())
        .collect();
    assert_eq!(js.len(), 4, "{js:?}");
    assert!(js[..3].iter().all(|j| j.abs() < 1e-9) && (js[3] - 3.0).abs() < 1e-7);
    assert_eq!(v["phase_growth"]["stop"], "max_phases");
    let out = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--method",
        "phase",
        "--formulation",
        "general",
        "--phases",
        "4",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let fixed = json(&out);
    assert!(fixed.get("phase_growth").is_none());
    assert!((fixed["objective"].as_f64().unwrap() - 3.0).abs() < 1e-7);
    for (args, want) in [
        (&["--patience", "0"][..], "error: --patience"),
        (&["--phases", "0"][..], "error: --phases"),
        (&["--phases", "25"][..], "error: --phases"),
    ] {
        let mut all = vec![
            "optimize",
            "examples/general_one_link.toml",
            "--method",
            "phase",
        ];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).starts_with(want), "{}", stderr(&out));
    }
    // A != 0 is refused naming the field.
    let out = crawlopt(&[
        "optimize",
        "examples/general_drift.toml",
        "--method",
        "phase",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with("error: dynamics.A"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn optimize_method_local_solves_p_m_locally() {
    // From the file's [input], a square wave of amplitude 0.8 (J = (0.8 T - 4) / 2 = 2): the
    // local method reaches the one-link optimum J* = (T - 2 (b - a)) / 2 = 3.
    let dir = tempfile::tempdir().unwrap();
    let slow = ONE_LINK.replace("values = [[1.0], [-1.0]]", "values = [[0.8], [-0.8]]");
    let f = write(dir.path(), "slow.toml", &slow);
    let f = f.to_str().unwrap();
    let out = crawlopt(&[
        "optimize", f, "--method", "local", "--m", "4", "--shifts", "2", "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["method"], "local");
    assert_eq!(v["start_from"], "input");
    assert_eq!(v["starts_tried"], 2);
    assert_eq!(v["solution"]["stop"], "stationary");
    let start = v["solution"]["start_objective"].as_f64().unwrap();
    assert!((start - 2.0).abs() < 1e-9, "{start}");
    let j = v["objective"].as_f64().unwrap();
    assert!((j - 3.0).abs() < 1e-7, "{j}");
    assert_eq!(v["solution"]["controls"].as_array().unwrap().len(), 16);
    let out = crawlopt(&["optimize", f, "--method", "local", "--m", "3"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("local LPCC method: stationary"));
    for (file, args, want) in [
        (f, &["--method", "sequence"][..], "error: --method"),
        (f, &["--shifts", "2"][..], "error: --shifts"),
        (
            f,
            &["--method", "local", "--shifts", "0"][..],
            "error: --shifts",
        ),
        (f, &["--method", "local", "--m", "15"][..], "error: --m"),
        (
            f,
            &["--method", "local", "--time-limit", "-1"][..],
            "error: --time-limit",
        ),
        (
            "examples/general_drift.toml",
            &["--method", "local"][..],
            "error: objective.cost",
        ),
    ] {
        let mut all = vec!["optimize", file];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).starts_with(want), "{}", stderr(&out));
    }
}

#[test]
fn plot_and_report_apply_to_general_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let file = "examples/general_drift.toml";
    // simulate --plot: C with the orbit, the states, controls, reactions and the integrand.
    let out = crawlopt(&[
        "simulate",
        file,
        "--steps-per-period",
        "200",
        "--plot",
        &d("sim"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    for name in ["polytope", "states", "controls", "reactions", "integrand"] {
        assert!(
            dir.path().join("sim").join(format!("{name}.png")).is_file(),
            "{name}"
        );
    }
    // analyze --plot: C alone.
    let out = crawlopt(&[
        "analyze",
        "examples/general_one_link.toml",
        "--plot",
        &d("c"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("c/polytope.svg").is_file());
    // optimize --plot --report: the report shows the J that --json prints.
    let report = d("r.html");
    let out = crawlopt(&[
        "optimize",
        file,
        "--m",
        "3",
        "--json",
        "--plot",
        &d("opt"),
        "--report",
        &report,
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let j = json(&out)["objective"].as_f64().unwrap();
    let html = std::fs::read_to_string(&report).unwrap();
    assert!(
        html.contains(&format!("id=\"objective\" data-value=\"{j}\"")),
        "{j}"
    );
    assert!(html.contains("crawlopt optimize general_drift.toml --report r.html"));
    assert!(dir.path().join("opt/integrand.svg").is_file());
    // crawlopt report on a general file: the optimum of optimize's default method.
    let out = crawlopt(&[
        "report",
        "examples/general_one_link.toml",
        "-o",
        &d("one.html"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout).contains("objective J = 3"));
    let html = std::fs::read_to_string(dir.path().join("one.html")).unwrap();
    assert!(html.contains("<h1>Optimum of a general problem (P)</h1>"));
    // Bad paths fail cleanly before the work, and leave nothing behind.
    let plain = write(dir.path(), "plain.txt", "not a directory");
    let out = crawlopt(&["simulate", file, "--plot", plain.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("exists and is not a directory"),
        "{}",
        stderr(&out)
    );
    let out = crawlopt(&[
        "optimize",
        file,
        "--m",
        "3",
        "--report",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let out = crawlopt(&["analyze", file, "--plot", &format!("{}/x", plain.display())]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&plain).unwrap(), "not a directory");
    // What does not apply is refused by the library, with its reason.
    for (args, want) in [
        (
            &["simulate", file, "--periods", "2"][..],
            "error: --periods: a general problem's simulation records one period",
        ),
        (
            &["simulate", file, "--no-newton"][..],
            "error: --no-newton: the general simulator iterates",
        ),
        (
            &["simulate", file, "--no-accelerate"][..],
            "error: --no-accelerate: the general simulator iterates the period map plainly",
        ),
        (
            &["simulate", file, "--accelerate-after", "7"][..],
            "error: --accelerate-after: the general simulator iterates the period map plainly",
        ),
        (
            &["simulate", file, "--increment-budget", "5"][..],
            "error: --increment-budget: the general simulator keeps no table",
        ),
        (&["report", file, "--phases", "2"][..], "error: --phases"),
    ] {
        let out = crawlopt(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).starts_with(want), "{}", stderr(&out));
    }
    // Without the periodic regime no figure is written (exit 3 says so).
    let out = crawlopt(&["simulate", file, "--max-periods", "1", "--plot", &d("none")]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("no figures written to"),
        "{}",
        stderr(&out)
    );
    assert!(!dir.path().join("none").exists());
}

/// `--formulation`: `transitions` reaches the §4 one-link optimum at `--phases 2` (4 phases)
/// where `general` gives 0; a name that is none, a crawler's file and a method other than phase
/// are refused with exit 2, naming `--formulation`.
#[test]
fn optimize_takes_the_phase_formulation() {
    let run = |extra: &[&str]| {
        let mut args = vec!["optimize", "examples/general_one_link.toml", "--json"];
        args.extend_from_slice(extra);
        crawlopt(&args)
    };
    let slots = run(&[
        "--method",
        "phase",
        "--phases",
        "2",
        "--formulation",
        "transitions",
    ]);
    assert!(slots.status.success(), "{}", stderr(&slots));
    let v = json(&slots);
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-7);
    assert_eq!(v["formulation"], "transitions");
    let plain = json(&run(&[
        "--method",
        "phase",
        "--phases",
        "2",
        "--formulation",
        "general",
    ]));
    assert!(plain["objective"].as_f64().unwrap().abs() < 1e-9);
    for out in [
        run(&["--method", "phase", "--formulation", "bogus"]),
        run(&["--method", "discrete", "--formulation", "general"]),
        crawlopt(&[
            "optimize",
            "examples/three_blocks_gait.toml",
            "--formulation",
            "chain",
        ]),
    ] {
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains("--formulation"), "{}", stderr(&out));
    }
}

/// A J that is solver noise prints as 0, as a crawler's does: P_1 of the three-block crawler's
/// general form is 0 up to about 1e-17 (its JSON keeps the number as simulated); the text and
/// the summary line snap it against the problem's floor of J, not against J itself.
#[test]
fn a_noise_j_prints_as_zero_for_a_general_problem_as_for_a_crawler() {
    for file in [
        "examples/general_three_blocks.toml",
        "examples/three_blocks_gait.toml",
    ] {
        let out = crawlopt(&["optimize", file, "--method", "discrete", "--m", "1"]);
        assert!(out.status.success(), "{}", stderr(&out));
        let text = String::from_utf8_lossy(&out.stdout);
        let j_line = text
            .lines()
            .find(|l| l.contains("J = "))
            .expect("a line of J");
        assert!(
            j_line.contains("J = 0 ") || j_line.trim_end().ends_with("J = 0"),
            "{file}:\n{text}"
        );
    }
}
