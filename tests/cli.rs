//! The command-line contract: JSON fields, exit statuses, one-line errors naming the field,
//! no partial output files.

use std::process::Output;

mod common;
use common::{crawlopt, write};

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts that a run was refused (exit 2) with `want` in its message.
fn assert_refused(out: &Output, want: &str) {
    assert_eq!(out.status.code(), Some(2), "{}", stderr(out));
    assert!(
        stderr(out).contains(want),
        "want {want:?} in {}",
        stderr(out)
    );
}

const CRAWLER3: &str =
    "[crawler]\nblocks = 3\nstiffness = 1.0\nmu_forward = 1.0\nmu_backward = 3.0\n";

#[test]
fn analyze_json_has_the_contract_fields() {
    let out = crawlopt(&["analyze", "examples/three_blocks_sine.toml", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["uniqueness_ok"], true);
    assert!(v["violating_subset"].is_null());
    assert_eq!(v["vm_class"], "convex");
    assert_eq!(v["moves_forward"], true);
    assert_eq!(v["moves_backward"], false);
    assert_eq!(v["faces"].as_array().unwrap().len(), 6);
    assert_eq!(v["vertices"].as_array().unwrap().len(), 3);
    assert_eq!(v["link_force_ranges"][0], serde_json::json!([-1.0, 2.0]));
}

#[test]
fn analyze_reports_a_violated_uniqueness_condition_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    // N = 5, mu+ = 1, mu- = 1.5: 3 * 1 = 2 * 1.5.
    let f = write(
        dir.path(),
        "m.toml",
        "[crawler]\nblocks = 5\nstiffness = 1\nmu_forward = 1\nmu_backward = 1.5\n",
    );
    let out = crawlopt(&["analyze", f.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let v = json(&out);
    assert_eq!(v["uniqueness_ok"], false);
    assert_eq!(v["violating_subset"].as_array().unwrap().len(), 3);
    assert!(
        stderr(&out).contains("uniqueness condition"),
        "{}",
        stderr(&out)
    );
    // simulate refuses it, naming J.
    let f = write(
        dir.path(),
        "s.toml",
        "[crawler]\nblocks = 5\nstiffness = 1\nmu_forward = 1\nmu_backward = 1.5\n[actuation]\nkind = \"sine\"\nperiod = 1\namplitude = 1\n",
    );
    let out = crawlopt(&["simulate", f.to_str().unwrap()]);
    assert_refused(&out, "fails for blocks J = [");
    assert!(out.stdout.is_empty());
}

#[test]
fn simulate_json_has_the_contract_fields() {
    for method in ["exact", "catching-up"] {
        let out = crawlopt(&[
            "simulate",
            "examples/one_link.toml",
            "--json",
            "--method",
            method,
            "--steps-per-period",
            "400",
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let v = json(&out);
        let d = v["displacement_per_period"].as_f64().unwrap();
        assert!((d - 4.0).abs() < 1e-11, "{d}");
        assert_eq!(v["converged"], true);
        assert_eq!(v["method"], method);
        assert_eq!(v["steps_per_period"], 400);
        assert!(v["periods_to_converge"].as_u64().unwrap() >= 1);
        let tr = &v["trajectory"];
        assert_eq!(
            tr["t"].as_array().unwrap().len(),
            tr["x"].as_array().unwrap().len()
        );
    }
}

#[test]
fn simulate_writes_a_trajectory_csv() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("traj.csv");
    let out = crawlopt(&[
        "simulate",
        "examples/three_blocks_sine.toml",
        "--periods",
        "3",
        "-o",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,x_1,x_2,X_1,X_2,X_3,y,slip_1,slip_2,slip_3"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    let last = rows.last().unwrap();
    assert!((last[0] - 3.0).abs() < 1e-12);
    // Three periods of advance at the reported rate (1 + sqrt 2 / 2 ... measured by simulate).
    let v = json(&crawlopt(&[
        "simulate",
        "examples/three_blocks_sine.toml",
        "--json",
        "--periods",
        "0",
    ]));
    let d = v["displacement_per_period"].as_f64().unwrap();
    assert!((last[6] - rows[0][6] - 3.0 * d).abs() < 1e-9);
}

#[test]
fn piecewise_linear_and_csv_actuations_agree() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "gait.csv",
        "t,L1,L2\n0,0,0\n0.25,2,0\n0.5,2,2\n0.75,0,2\n",
    );
    let a = write(
        dir.path(),
        "a.toml",
        &format!("{CRAWLER3}[actuation]\nkind = \"csv\"\nperiod = 1.0\npath = \"gait.csv\"\n"),
    );
    let b = write(
        dir.path(),
        "b.toml",
        &format!("{CRAWLER3}[actuation]\nkind = \"piecewise_linear\"\nperiod = 1.0\ntimes = [0, 0.25, 0.5, 0.75]\nlengths = [[0, 0], [2, 0], [2, 2], [0, 2]]\n"),
    );
    let da = json(&crawlopt(&["simulate", a.to_str().unwrap(), "--json"]))
        ["displacement_per_period"]
        .as_f64()
        .unwrap();
    let db = json(&crawlopt(&["simulate", b.to_str().unwrap(), "--json"]))
        ["displacement_per_period"]
        .as_f64()
        .unwrap();
    assert_eq!(da, db);
    assert!(da > 0.0);
}

#[test]
fn bad_input_gives_one_line_naming_the_field_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let act = "[actuation]\nkind = \"sine\"\nperiod = 1.0\namplitude = 1.0\n";
    let cases: Vec<(String, &str)> = vec![
        ("[crawler]\nblocks = 1\nstiffness = 1\nmu_forward = 1\nmu_backward = 2\n".into(), "crawler.blocks"),
        ("[crawler]\nblocks = 3\nstiffness = 0\nmu_forward = 1\nmu_backward = 2\n".into(), "crawler.stiffness[1]"),
        ("[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = [1, -2, 1]\nmu_backward = 2\n".into(), "crawler.mu_forward[2]"),
        ("[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = 1\nmu_backward = inf\n".into(), "crawler.mu_backward[1]"),
        ("[crawler]\nblocks = 3\nstiffness = [1, 1, 1]\nmu_forward = 1\nmu_backward = 2\n".into(), "crawler.stiffness"),
        ("[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = 1\n".into(), "missing field `mu_backward`"),
        ("[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = 1\nmu_backward = 2\nspeed = 3\n".into(), "unknown field `speed`"),
        ("[crawler\nblocks = 3\n".into(), "invalid model file"),
        (format!("{CRAWLER3}[actuation]\nkind = \"sine\"\nperiod = -1.0\namplitude = 1.0\n"), "actuation.period"),
        (format!("{CRAWLER3}[actuation]\nkind = \"sine\"\nperiod = 1.0\namplitude = [1.0, 0.0]\n"), "actuation.amplitude[2]"),
        (format!("{CRAWLER3}[actuation]\nkind = \"sine\"\nperiod = 1.0\namplitude = [1.0, 1.0, 1.0]\n"), "actuation.amplitude"),
        (format!("{CRAWLER3}[actuation]\nkind = \"square\"\nperiod = 1.0\n"), "actuation.kind"),
        (format!("{CRAWLER3}[actuation]\nkind = \"csv\"\nperiod = 1.0\npath = \"missing.csv\"\n"), "missing.csv"),
        (format!("{CRAWLER3}[actuation]\nkind = \"piecewise_linear\"\nperiod = 1.0\ntimes = [0, 1.5]\nlengths = [[0, 0], [1, 1]]\n"), "actuation.times[2]"),
        (format!("{CRAWLER3}{act}[simulation]\ninitial_state = [5.0, 0.0]\n"), "simulation.initial_state: state is not admissible"),
        (format!("{CRAWLER3}{act}[simulation]\ninitial_state = [0.0]\n"), "simulation.initial_state"),
        (CRAWLER3.to_string(), "no [actuation] section"),
        (
            "[crawler]\nblocks = 3\nstiffness = 1e300\nmu_forward = 1\nmu_backward = 2.5\n[actuation]\nkind = \"piecewise_linear\"\nperiod = 1\ntimes = [0, 0.5]\nlengths = [[0, 0], [1e10, 2e10]]\n".into(),
            "overflow double precision",
        ),
        ("[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = 1e308\nmu_backward = 1.7e308\n".into(), "overflow"),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let f = write(dir.path(), &format!("bad{i}.toml"), text);
        let csv = dir.path().join(format!("out{i}.csv"));
        let out = crawlopt(&["simulate", f.to_str().unwrap(), "-o", csv.to_str().unwrap()]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "case {i}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(want),
            "case {i}: want {want:?} in {err:?}"
        );
        assert_eq!(err.trim_end().lines().count(), 1, "case {i}: {err}");
        assert!(!err.contains("panicked"));
        assert!(!csv.exists(), "case {i}: partial output left behind");
    }
    // Unreadable files.
    let out = crawlopt(&["analyze", dir.path().join("nope.toml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let f = write(
        dir.path(),
        "badcsv.toml",
        &format!("{CRAWLER3}[actuation]\nkind = \"csv\"\nperiod = 1.0\npath = \"bad.csv\"\n"),
    );
    write(dir.path(), "bad.csv", "0,0,0\n0.5,1,x\n");
    let out = crawlopt(&["simulate", f.to_str().unwrap()]);
    assert_refused(&out, "row 2, column 3");
}

#[test]
fn analyze_reports_the_one_link_optimum_of_a_gait_problem() {
    let out = crawlopt(&["analyze", "examples/one_link_gait.toml", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["gait"]["one_link_optimum"]["value"], 3.0);
    assert_eq!(v["gait"]["problem"]["rate_bound"], serde_json::json!([1.0]));
    let dir = tempfile::tempdir().unwrap();
    let crawler = "[crawler]\nblocks = 2\nstiffness = 1\nmu_forward = 1\nmu_backward = 2\n";
    for (gait, want) in [
        ("period = -1\nmax_actuator_speed = 1\n", "gait.period"),
        (
            "period = 10\nmax_actuator_speed = 0\n",
            "gait.max_actuator_speed[1]",
        ),
        (
            "period = 10\nmax_actuator_speed = [1, 1]\n",
            "gait.max_actuator_speed",
        ),
        (
            "period = 10\nmax_actuator_speed = 1\ncost = { kind = \"quadratic\" }\n",
            "gait.cost.weight",
        ),
        (
            "period = 10\nmax_actuator_speed = 1\ncost = { kind = \"quadratic\", weight = 0 }\n",
            "gait.cost.weight",
        ),
        (
            "period = 10\nmax_actuator_speed = 1\ncost = { kind = \"cubic\" }\n",
            "gait.cost.kind",
        ),
        (
            "period = 10\nmax_actuator_speed = 1\nmax_total_variation = -2\n",
            "gait.max_total_variation",
        ),
        ("period = 10\nspeed = 1\n", "unknown field `speed`"),
    ] {
        let f = write(dir.path(), "g.toml", &format!("{crawler}[gait]\n{gait}"));
        let out = crawlopt(&["analyze", f.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{gait}: {}", stderr(&out));
        assert!(
            stderr(&out).contains(want),
            "{gait}: want {want:?} in {}",
            stderr(&out)
        );
    }
}

#[test]
fn optimize_discrete_returns_a_verified_certified_gait() {
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "discrete",
        "--m",
        "3",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-8);
    assert_eq!(v["solution"]["displacement_per_period"], v["objective"]);
    assert!(v.get("verified_displacement").is_none(), "written once");
    assert_eq!(v["certificate"]["kind"], "global");
    assert!(v["certificate"]["gap"].as_f64().unwrap() < 1e-6);
    assert_eq!(v["solution"]["controls"].as_array().unwrap().len(), 8);
    assert_eq!(v["solution"]["times"].as_array().unwrap().len(), 9);
    // Bad input: no [gait] section, m out of range.
    // The phase method: exact continuous-time gait, certified among K-phase gaits.
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "phase",
        "--phases",
        "4",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-8);
    assert_eq!(v["certificate"]["kind"], "global_k_phases");
    assert_eq!(v["certificate"]["phases"], 4);
    // The default (auto): K grows until the value stops improving; the table is in the result.
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["format"], "crawlopt-gait-result");
    assert_eq!(v["method"], "phase");
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-8);
    assert_eq!(v["phase_growth"]["stop"], "no_gain");
    // The growth starts from the best structured gait (the triangle wave, J = 3, two slip
    // phases): K = 1 cannot beat it (its cutoff settles K = 1 with that gait), and K = 2 and 3
    // bring nothing more (patience 2). Without the start, K = 1 idled and the growth ran to 4.
    assert_eq!(v["phase_growth"]["table"].as_array().unwrap().len(), 3);
    // --convergence: J_m for m = 1..=3, all 3 (theory §10).
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "discrete",
        "--m",
        "3",
        "--convergence",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    let table = v["convergence"].as_array().unwrap();
    assert_eq!(table.len(), 3);
    for row in table {
        assert!((row["objective"].as_f64().unwrap() - 3.0).abs() < 1e-8);
    }
    assert_eq!(v["solution"]["m"], 3);
    // The local method from a result file, and its refusals.
    let dir = tempfile::tempdir().unwrap();
    let start = dir.path().join("start.json");
    std::fs::write(&start, &out.stdout).unwrap();
    let start = start.to_str().unwrap();
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "local",
        "--m",
        "6",
        "--start",
        start,
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["method"], "local");
    assert_eq!(v["certificate"]["kind"], "local");
    assert_eq!(v["certificate"]["gap"], serde_json::Value::Null);
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-8);
    assert_eq!(v["solution"]["controls"].as_array().unwrap().len(), 64);
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "local",
        "--start",
        start,
    ]);
    assert_refused(&out, "another crawler");
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--start", start]);
    assert_refused(&out, "--method local, sequence and discrete only");
    // The P_m MILP from a result file (sampled on its grid), recorded in the result; not with
    // --convergence, whose m start from m - 1.
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "discrete",
        "--m",
        "4",
        "--start",
        start,
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["certificate"]["kind"], "global");
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-8);
    assert!(
        (v["discrete_start"]["start_objective"].as_f64().unwrap() - 3.0).abs() < 1e-8,
        "{}",
        v["discrete_start"]
    );
    assert!(v["discrete_start"]["start"]
        .as_str()
        .unwrap()
        .contains("start.json"));
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "discrete",
        "--m",
        "3",
        "--convergence",
        "--start",
        start,
    ]);
    assert_refused(&out, "does not apply to --convergence");
    // Under a time limit the MILP starts from the local method's gait.
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "discrete",
        "--m",
        "3",
        "--time-limit",
        "60",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["status"], "optimal");
    assert!((v["objective"].as_f64().unwrap() - 2.0).abs() < 1e-8);
    let from = &v["discrete_start"];
    assert!(
        from["start"].as_str().unwrap().starts_with("local on P_3"),
        "{from}"
    );
    assert!(from["start_objective"].as_f64().unwrap() <= 2.0 + 1e-8);
    std::fs::write(
        dir.path().join("cut.json"),
        &std::fs::read(start).unwrap()[..100],
    )
    .unwrap();
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "local",
        "--start",
        dir.path().join("cut.json").to_str().unwrap(),
    ]);
    assert_refused(&out, "not a complete JSON");
    // --method sequence: from the best 3-slip-phase gait (13/6) to 2.6 with room for 4, an
    // exact continuous-time gait with a local certificate.
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--phases",
        "3",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let k3 = write(dir.path(), "k3.json", &String::from_utf8_lossy(&out.stdout));
    let k3 = k3.to_str().unwrap();
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "sequence",
        "--start",
        k3,
        "--phases",
        "4",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["method"], "sequence");
    assert_eq!(v["certificate"]["kind"], "local");
    assert_eq!(v["certificate"]["phases"], 4);
    assert_eq!(v["status"], "stationary");
    assert!((v["objective"].as_f64().unwrap() - 2.6).abs() < 1e-8);
    assert!(
        (v["solution"]["local"]["start_objective"].as_f64().unwrap() - 13.0 / 6.0).abs() < 1e-8
    );
    assert!(v["solution"]["local"]["switches"].as_u64().unwrap() >= 1);
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "sequence",
        "--m",
        "3",
    ]);
    assert_refused(&out, "--method sequence");
    // A time limit far too short: the best incumbent with its gap, never a claim of optimality;
    // or, with no gait found yet, a plain error.
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--phases",
        "12",
        "--time-limit",
        "0.02",
        "--json",
    ]);
    // A limit spent before the MILP has a gait returns the best structured gait (the floor of
    // every answer), with status time_limit and no gap: it proves nothing.
    if out.status.success() {
        let v = json(&out);
        assert_eq!(v["status"], "time_limit");
        if v["structured"].is_object() {
            assert!(v["certificate"]["gap"].is_null());
            assert!(v["structured"]["replaced"].is_string(), "{v}");
        } else {
            assert!(v["certificate"]["gap"].as_f64().unwrap() > 1e-3);
        }
    } else {
        assert_refused(&out, "time limit");
    }
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--convergence"]);
    assert_refused(&out, "--method discrete only");
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--m", "3"]);
    assert_refused(&out, "applies to --method discrete only");
    let out = crawlopt(&["optimize", "examples/one_link.toml"]);
    assert_refused(&out, "no [gait] section");
    for m in ["0", "17"] {
        let out = crawlopt(&[
            "optimize",
            "examples/one_link_gait.toml",
            "--method",
            "discrete",
            "--m",
            m,
        ]);
        assert_eq!(out.status.code(), Some(2), "m = {m}");
        assert!(stderr(&out).starts_with("error: --m:"), "{}", stderr(&out));
    }
    // Options of a part that does not run are refused, not silently ignored.
    for (args, flag) in [
        (&["--method", "local", "--patience", "1"][..], "patience"),
        (&["--phases", "3", "--patience", "1"], "patience"),
        (&["--phases", "3", "--max-phases", "4"], "max-phases"),
        (&["--method", "phase", "--shifts", "4"], "shifts"),
        (&["--method", "discrete", "--shifts", "4"], "shifts"),
        (&["--method", "discrete", "--max-phases", "4"], "max-phases"),
    ] {
        let mut all = vec!["optimize", "examples/one_link_gait.toml"];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&out).starts_with(&format!("error: --{flag}:"))
                && stderr(&out).contains("applies only to"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    // Bad values are refused before any solve (not turned into a note by a start policy), and
    // so is a quadratic cost for the local method; a quadratic cost makes discrete's default
    // start the phase gait, so --shifts does not apply there.
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string("examples/one_link_gait.toml").unwrap();
    let quadratic = write(
        dir.path(),
        "q.toml",
        &text.replace(
            "cost = { kind = \"none\" }",
            "cost = { kind = \"quadratic\", weight = 0.1 }",
        ),
    );
    let quadratic = quadratic.to_str().unwrap();
    assert!(std::fs::read_to_string(quadratic)
        .unwrap()
        .contains("quadratic"));
    for (args, want) in [
        (
            &["--method", "discrete", "--time-limit", "4", "--shifts", "0"][..],
            "error: --shifts:",
        ),
        (
            &[
                "--method",
                "discrete",
                "--time-limit",
                "4",
                "--max-phases",
                "0",
            ],
            "error: --max-phases:",
        ),
        (
            &["--method", "local", "--max-phases", "100"],
            "error: --max-phases:",
        ),
        (&["--patience", "0"], "error: --patience:"),
        (
            &["--method", "discrete", "--time-limit=-1"],
            "error: --time-limit:",
        ),
        (&["--method", "local", "--m", "15"], "error: --m:"),
    ] {
        let mut all = vec!["optimize", "examples/one_link_gait.toml"];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).starts_with(want), "{args:?}: {}", stderr(&out));
        assert!(!stderr(&out).contains("note:"), "{}", stderr(&out));
    }
    for (args, want) in [
        (&["--method", "local"][..], "error: gait.cost:"),
        (
            &["--method", "discrete", "--time-limit", "4", "--shifts", "2"],
            "error: --shifts:",
        ),
    ] {
        let mut all = vec!["optimize", quadratic];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).starts_with(want), "{args:?}: {}", stderr(&out));
    }
    // Where they apply, they are taken.
    for args in [
        &["--method", "sequence", "--phases", "4", "--max-phases", "5"][..],
        &[
            "--method",
            "discrete",
            "--time-limit",
            "20",
            "--shifts",
            "2",
            "--max-phases",
            "5",
        ],
        &[
            "--method",
            "local",
            "--m",
            "3",
            "--max-phases",
            "5",
            "--shifts",
            "2",
        ],
        &["--patience", "1", "--max-phases", "4"],
    ] {
        let mut all = vec!["optimize", "examples/one_link_gait.toml", "--json"];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        // The one-link optimum (theory §10): J = 3 on every method and grid here.
        let j = json(&out)["objective"].as_f64().unwrap();
        assert!((j - 3.0).abs() < 1e-8, "{args:?}: {j}");
    }
}

#[test]
fn an_unwritable_output_leaves_nothing_and_exits_2() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("no/such/dir/t.csv");
    let out = crawlopt(&[
        "simulate",
        "examples/one_link.toml",
        "-o",
        target.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("t.csv"));
}

#[test]
fn non_convergence_is_not_reported_as_periodic() {
    // Ten blocks need about 50 periods of plain iteration: one period is not enough.
    let dir = tempfile::tempdir().unwrap();
    let f = write(
        dir.path(),
        "m.toml",
        "[crawler]\nblocks = 10\nstiffness = 1\nmu_forward = 1\nmu_backward = 3.3\n[actuation]\nkind = \"sine\"\nperiod = 1\namplitude = 2\nphase_deg = [0, 90, 180, 270, 360, 450, 540, 630, 720]\n",
    );
    let out = crawlopt(&[
        "simulate",
        f.to_str().unwrap(),
        "--json",
        "--max-periods",
        "3",
        "--no-accelerate",
    ]);
    assert_eq!(out.status.code(), Some(3));
    let v = json(&out);
    assert_eq!(v["converged"], false);
    assert!(v["displacement_per_period"].is_null());
    assert!(v["last_period_displacement"].is_f64());
    assert!(stderr(&out).contains("not reached"));
}

#[test]
fn plot_report_and_plot_flags_write_their_files() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    // optimize --json, then plot and report from the result file.
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--json",
        "--plot",
        &d("opt"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let result = write(dir.path(), "r.json", &String::from_utf8_lossy(&out.stdout));
    for name in ["actuation", "spacetime", "polytope"] {
        for ext in ["svg", "png"] {
            assert!(
                dir.path().join(format!("opt/{name}.{ext}")).is_file(),
                "{name}.{ext}"
            );
        }
    }
    let out = crawlopt(&["plot", result.to_str().unwrap(), "-o", &d("figs")]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(std::fs::read_dir(d("figs")).unwrap().count(), 6);
    // certify --plot adds the adjoint; optimize --convergence --plot the J_m figure.
    let out = crawlopt(&["certify", result.to_str().unwrap(), "--plot", &d("cert")]);
    assert!(out.status.success(), "{}", stderr(&out));
    let adj = std::fs::read_to_string(dir.path().join("cert/adjoint.svg")).unwrap();
    assert!(
        adj.contains("p + ω") || adj.contains("p(t) + ω"),
        "adjoint labels"
    );
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--method",
        "discrete",
        "--m",
        "2",
        "--convergence",
        "--plot",
        &d("conv"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let jm = std::fs::read_to_string(dir.path().join("conv/jm.svg")).unwrap();
    assert!(jm.contains("Convergence of the discrete optima"));
    let out = crawlopt(&["report", result.to_str().unwrap(), "-o", &d("r.html")]);
    assert!(out.status.success(), "{}", stderr(&out));
    let html = std::fs::read_to_string(d("r.html")).unwrap();
    assert!(html.contains("id=\"crawler-data\"") && html.contains(">r.json"));
    // From the model file directly (phase method, K = 6).
    let out = crawlopt(&[
        "report",
        "examples/three_blocks_gait.toml",
        "-o",
        &d("m.html"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(std::fs::read_to_string(d("m.html"))
        .unwrap()
        .contains("fig-vm"));
    // --plot on analyze and simulate.
    let out = crawlopt(&[
        "analyze",
        "examples/three_blocks_gait.toml",
        "--plot",
        &d("an"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("an/vm.svg").is_file() && dir.path().join("an/polytope.png").is_file());
    let out = crawlopt(&[
        "simulate",
        "examples/piecewise_linear.toml",
        "--plot",
        &d("sim"),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let st = std::fs::read_to_string(dir.path().join("sim/spacetime.svg")).unwrap();
    assert!(st.contains("position [length]"));
}

#[test]
fn plot_and_report_refuse_bad_input_with_nothing_written() {
    let dir = tempfile::tempdir().unwrap();
    let d = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--json"]);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let truncated = write(dir.path(), "t.json", &text[..text.len() / 2]);
    let other = write(
        dir.path(),
        "v.json",
        &text.replace("\"version\":4", "\"version\":9"),
    );
    let good = write(dir.path(), "r.json", &text);
    // Absurd but finite rate bounds: refused by the reader (the sweep ratio a T / w is beyond
    // what any optimiser resolves), not drawn and not a hang.
    let mut huge: serde_json::Value = serde_json::from_str(&text).unwrap();
    huge["problem"]["gait"]["rate_bound"] = serde_json::json!([1e308]);
    let huge = write(dir.path(), "h.json", &huge.to_string());
    let blocker = write(dir.path(), "file", "x");
    let cases: [(&[&str], &str); 6] = [
        (
            &["plot", huge.to_str().unwrap(), "-o", &d("f3")],
            "more than 1e308 times per period",
        ),
        (
            &["plot", truncated.to_str().unwrap(), "-o", &d("f1")],
            "not a complete JSON document",
        ),
        (
            &["report", truncated.to_str().unwrap(), "-o", &d("r1.html")],
            "not a complete JSON document",
        ),
        (
            &["plot", other.to_str().unwrap(), "-o", &d("f2")],
            "version",
        ),
        (
            &[
                "plot",
                good.to_str().unwrap(),
                "-o",
                &format!("{}/sub", blocker.display()),
            ],
            "cannot create the directory",
        ),
        (
            &["report", "examples/one_link.toml", "-o", &d("r2.html")],
            "no [gait] section",
        ),
    ];
    for (args, msg) in cases {
        let out = crawlopt(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = stderr(&out);
        assert!(
            err.starts_with("error: ") && err.lines().count() == 1,
            "{err}"
        );
        assert!(err.contains(msg), "{args:?}: {err}");
    }
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["file", "h.json", "r.json", "t.json", "v.json"],
        "nothing half-written"
    );
}

#[test]
fn optimize_and_simulate_list_the_librarys_methods_and_refuse_another() {
    use crawlopt::api::GaitMethod;
    use crawlopt::integrate::Method;
    // `--method` takes the library's names, each with the library's summary in `--help`, and
    // clap refuses another name listing them.
    let optimize: Vec<_> = GaitMethod::ALL.map(|m| (m.name(), m.summary())).into();
    let simulate: Vec<_> = Method::ALL.map(|m| (m.name(), m.summary())).into();
    for (command, methods, other) in [
        ("optimize", optimize, "fast"),
        ("simulate", simulate, "rk4"),
    ] {
        let help = crawlopt(&[command, "--help"]);
        assert!(help.status.success(), "{}", stderr(&help));
        let help = String::from_utf8_lossy(&help.stdout);
        for (name, summary) in &methods {
            assert!(help.contains(&format!("{name}:")), "{name} in {help}");
            assert!(help.contains(summary), "{summary} in {help}");
        }
        let out = crawlopt(&[
            command,
            "examples/three_blocks_gait.toml",
            "--method",
            other,
        ]);
        assert_refused(
            &out,
            &format!("invalid value '{other}' for '--method <METHOD>'"),
        );
        let names: Vec<&str> = methods.iter().map(|(name, _)| *name).collect();
        assert!(stderr(&out).contains(&format!("[possible values: {}]", names.join(", "))));
    }
}
