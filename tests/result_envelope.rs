//! One result envelope for both kinds of problem (`crawlopt::optimal::envelope`,
//! `crawlopt::io::ResultFile`): a general problem's result written by `optimize --json` carries
//! `format`, `version`, `kind`, `method`, `problem`, `objective`, `status`, `certificate` and
//! `solution`, reads back from itself alone, certifies (the same numbers as `optimize --certify`,
//! which certifies the answer in memory) and is refused, naming the field, when a number in it
//! was changed; crawler results carry the same envelope (the gait as `solution`), and files of
//! version 1 (the gait as `gait`, `kind` possibly absent) still read; `plot`, `report` and
//! `certify --plot` draw a general result read back as `optimize` drew it.

use std::process::Output;

mod common;
use common::{crawlopt, write};
use crawlopt::io::{GeneralAnswer, ResultFile};
use crawlopt::optimal::{GaitResult, ResultKind};
use serde_json::{json, Value};

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn json_of(out: &Output) -> Value {
    assert!(out.status.success(), "{}", stderr(out));
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

/// `crawlopt optimize FILE ARGS --json`, as text and as JSON.
fn optimize(file: &str, args: &[&str]) -> (String, Value) {
    let mut all = vec!["optimize", file];
    all.extend_from_slice(args);
    all.push("--json");
    let out = crawlopt(&all);
    let v = json_of(&out);
    (String::from_utf8(out.stdout).unwrap(), v)
}

const ONE_LINK: &str = "examples/general_one_link.toml";

/// The one-link problem of the paper's §4 (J* = (T - 2 (b - a)) / 2 = 3) by each method: the
/// envelope, the problem stored without `[input]`, and the result read back equal to itself.
#[test]
fn general_results_carry_the_envelope_and_read_back() {
    for (args, method, status, cert) in [
        (&["--m", "3"][..], "discrete", "optimal", "global"),
        (
            &["--method", "local", "--m", "4", "--shifts", "1"][..],
            "local",
            "stationary",
            "local",
        ),
        (
            &["--method", "phase"][..],
            "phase",
            "optimal_among_k_phases",
            "global_k_phases",
        ),
    ] {
        let (text, v) = optimize(ONE_LINK, args);
        assert_eq!(v["format"], "crawlopt-gait-result");
        assert_eq!(v["version"], 4);
        assert_eq!(v["kind"], "general");
        assert_eq!(v["method"], method);
        assert_eq!(v["status"], status);
        assert_eq!(v["certificate"]["kind"], cert);
        assert_eq!(
            v["problem"]["sweeping_process"]["normals"],
            json!([[1.0], [-1.0]])
        );
        assert_eq!(v["problem"]["problem"]["period"], 10.0);
        assert!(v["problem"].get("input").is_none(), "{}", v["problem"]);
        let j = v["objective"].as_f64().unwrap();
        // Each number once (version 3): the solution repeats neither J nor the MILP's
        // certificate, and the period is the problem's.
        for repeated in ["objective", "certificate"] {
            assert!(
                v["solution"].get(repeated).is_none(),
                "{method}: {repeated}"
            );
        }
        assert!(v.get("period").is_none(), "{method}");
        assert!((j - 3.0).abs() < 1e-7, "{method}: {j}");
        if cert == "local" {
            assert!(v["certificate"]["bound"].is_null() && v["certificate"]["gap"].is_null());
        } else {
            let milp = v["solver_objective"].as_f64().unwrap();
            assert!(
                milp <= v["certificate"]["bound"].as_f64().unwrap() + 1e-9,
                "{milp}"
            );
        }
        let r = ResultFile::from_json(&text, "r.json").unwrap();
        assert_eq!(r.head().kind, ResultKind::General);
        assert_eq!((r.head().method.as_str(), r.head().objective), (method, j));
        assert_eq!(r.head().status.as_str(), status);
        let ResultFile::General(answer) = r else {
            panic!("read as a crawler's")
        };
        // Written again, it reads back to the same answer.
        let again = crawlopt::io::json::to_string(&answer).unwrap();
        assert_eq!(GeneralAnswer::from_json(&again, "again").unwrap(), *answer);
        // The head as the variant has it: a record read directly (not through `ResultFile`)
        // whose kind or method is another's is refused naming the field.
        fn head(a: &mut GeneralAnswer) -> &mut crawlopt::optimal::envelope::ResultHead {
            &mut a.head
        }
        let mut other = (*answer).clone();
        head(&mut other).method = if method == "local" { "phase" } else { "local" }.into();
        let e = other.check_consistent("d.json").unwrap_err();
        assert!(e.to_string().starts_with("d.json: method"), "{e}");
        let mut other = (*answer).clone();
        head(&mut other).kind = ResultKind::Crawler;
        let e = other.check_consistent("d.json").unwrap_err();
        assert!(e.to_string().starts_with("d.json: kind"), "{e}");
        // Version 1 of a general result had the same shape: it reads to the same answer.
        let mut v1 = v.clone();
        v1["version"] = json!(1);
        let ResultFile::General(old) = ResultFile::from_json(&v1.to_string(), "v1.json").unwrap()
        else {
            panic!("read as a crawler's")
        };
        assert_eq!(old, answer);
        // Version 2 repeated J, the MILP's certificate and the period, and named a P_m
        // process's arrays x, u, lambda: it reads to the same answer, its repeated numbers
        // checked against the envelope's.
        let v2 = as_version_2(&v);
        let ResultFile::General(old) = ResultFile::from_json(&v2.to_string(), "v2.json").unwrap()
        else {
            panic!("read as a crawler's")
        };
        assert_eq!(old, answer);
        let mut w = v2.clone();
        w["solution"]["objective"] = json!(j - 0.1);
        let e = ResultFile::from_json(&w.to_string(), "v2.json").unwrap_err();
        assert!(
            e.to_string().starts_with("v2.json: solution.objective"),
            "{e}"
        );
        let mut w = v2.clone();
        w["period"] = json!(5.0);
        let e = ResultFile::from_json(&w.to_string(), "v2.json").unwrap_err();
        assert!(e.to_string().starts_with("v2.json: period"), "{e}");
        // A top-level solver_objective added to a version 2 file agrees with its MILP's.
        if let Some(milp) = v["solver_objective"].as_f64() {
            let mut w = v2.clone();
            w["solver_objective"] = json!(milp - 0.5);
            let e = ResultFile::from_json(&w.to_string(), "v2.json").unwrap_err();
            assert!(
                e.to_string().starts_with("v2.json: solver_objective"),
                "{e}"
            );
        }
        // The crawler's own reader names the kind.
        let e = GaitResult::from_json(&text, "r.json").unwrap_err();
        assert!(e.to_string().starts_with("r.json: kind"), "{e}");
    }
}

/// A general result of version 3 written as version 2 wrote it (module docs of
/// `crawlopt::optimal::envelope`'s `RESULT_VERSION`).
fn as_version_2(v: &Value) -> Value {
    let mut w = v.clone();
    let o = w.as_object_mut().unwrap();
    o.insert("version".into(), json!(2));
    o.insert("period".into(), v["problem"]["problem"]["period"].clone());
    let milp = o.remove("solver_objective");
    let s = o.get_mut("solution").unwrap().as_object_mut().unwrap();
    s.insert("objective".into(), v["objective"].clone());
    if let Some(milp) = milp {
        s.insert(
            "certificate".into(),
            json!({"status": v["status"], "milp_objective": milp,
                   "bound": v["certificate"]["bound"], "gap": v["certificate"]["gap"]}),
        );
    }
    if s.contains_key("m") {
        for (new, old) in [("states", "x"), ("controls", "u"), ("reactions", "lambda")] {
            let rows = s.remove(new).unwrap();
            s.insert(old.into(), rows);
        }
    }
    w
}

/// `crawlopt certify` on a general result: the conditions of the stored P_m optimum (read
/// back, the problem rebuilt from the file), the same as `optimize --certify` computes on the
/// answer in memory; the local method's process is certified too; a phase gait and a Cauchy
/// problem are refused with the reason.
#[test]
fn certify_reads_a_general_result_as_optimize_certify_does() {
    let dir = tempfile::tempdir().unwrap();
    for (example, m) in [(ONE_LINK, "3"), ("examples/general_drift.toml", "3")] {
        let (text, with) = optimize(example, &["--m", m, "--certify"]);
        let file = write(dir.path(), "r.json", &text);
        let file = file.to_str().unwrap();
        let c = json_of(&crawlopt(&["certify", file, "--json"]));
        let d = &with["necessary_conditions"];
        assert_eq!(c["format"], "crawlopt-general-necessary-conditions");
        assert_eq!(c["verdict"], "holds", "{example}: {}", c["reason"]);
        assert_eq!((&c["verdict"], &c["m"]), (&d["verdict"], &d["m"]));
        assert_eq!(c["objective"], d["objective"]);
        let j = with["objective"].as_f64().unwrap();
        assert!((c["objective"].as_f64().unwrap() - j).abs() < 1e-9 * j.abs().max(1.0));
        let (a, b) = (
            c["conditions"].as_array().unwrap(),
            d["conditions"].as_array().unwrap(),
        );
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            assert_eq!(x["name"], y["name"]);
            let (rx, ry) = (
                x["residual"].as_f64().unwrap(),
                y["residual"].as_f64().unwrap(),
            );
            assert!((rx - ry).abs() <= 1e-12, "{}: {rx} vs {ry}", x["name"]);
        }
        assert_eq!(c["multipliers"]["omega"], d["multipliers"]["omega"]);
        let out = crawlopt(&["certify", file]);
        assert!(out.status.success(), "{}", stderr(&out));
        let shown = String::from_utf8(out.stdout).unwrap();
        assert!(
            shown.contains(
                "necessary conditions (Theorem 2.2; discrete form Theorems 6.1-6.2): holds"
            ),
            "{shown}"
        );
        // --plot draws the result's figures and the adjoint of the conditions just computed.
        let figs = dir.path().join("certify-figures");
        let out = crawlopt(&["certify", file, "--plot", figs.to_str().unwrap()]);
        assert!(out.status.success(), "{}", stderr(&out));
        for name in ["polytope", "controls", "reactions", "integrand", "adjoint"] {
            assert!(
                figs.join(format!("{name}.svg")).is_file(),
                "{example}: {name}"
            );
        }
    }
    // §4's one-link optimum J* = 3 found by the local method from the square waves: a P_m
    // process, certified; its conditions hold.
    let (text, _) = optimize(
        ONE_LINK,
        &["--method", "local", "--m", "3", "--shifts", "1"],
    );
    let file = write(dir.path(), "local.json", &text);
    let c = json_of(&crawlopt(&["certify", file.to_str().unwrap(), "--json"]));
    assert_eq!(c["verdict"], "holds", "{}", c["reason"]);
    assert!((c["objective"].as_f64().unwrap() - 3.0).abs() < 1e-9);
    // A phase gait: certified on its own phases (§4's optimum, J* = 3; its conditions hold,
    // the stationarity in the durations included).
    let (text, _) = optimize(ONE_LINK, &["--method", "phase"]);
    let file = write(dir.path(), "phase.json", &text);
    let c = json_of(&crawlopt(&["certify", file.to_str().unwrap(), "--json"]));
    assert_eq!(
        (&c["verdict"], &c["method"]),
        (&"holds".into(), &"phase".into())
    );
    assert!((c["objective"].as_f64().unwrap() - 3.0).abs() < 1e-9);
    // A Cauchy problem: read back (x(0) is its initial state), refused by certify.
    let src = std::fs::read_to_string(ONE_LINK).unwrap().replace(
        "period = 10.0",
        "period = 10.0\nperiodic = false\ninitial_state = [0.0]",
    );
    let cauchy = write(dir.path(), "cauchy.toml", &src);
    let (text, v) = optimize(cauchy.to_str().unwrap(), &["--m", "2"]);
    assert_eq!(v["solution"]["states"][0], json!([0.0]));
    ResultFile::from_json(&text, "cauchy.json").unwrap();
    let file = write(dir.path(), "cauchy.json", &text);
    let out = crawlopt(&["certify", file.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).starts_with("error: problem.periodic"),
        "{}",
        stderr(&out)
    );
}

/// Pointer into a JSON document (`/solution/u/0/0`).
fn set(v: &mut Value, at: &str, to: Value) {
    *v.pointer_mut(at).unwrap_or_else(|| panic!("no {at}")) = to;
}

fn refused(v: &Value, want: &str) {
    let text = v.to_string();
    let e = ResultFile::from_json(&text, "r.json")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!("r.json: {want}")),
        "want {want}: {e}"
    );
}

/// A phase gait's record of its replay (`state_gap`, beyond the 1e-6 of C's scale that the
/// optimiser keeps) and of its MILP (`milp_objective` above the bound) are checked on reading
/// back, naming the field; they were printed as read.
#[test]
fn a_phase_gaits_replay_gap_and_milp_value_are_checked_on_reading() {
    let (_, v) = optimize(ONE_LINK, &["--method", "phase", "--phases", "4"]);
    ResultFile::from_json(&v.to_string(), "r.json").unwrap();
    let bound = v["certificate"]["bound"].as_f64().unwrap();
    for (at, to, want) in [
        ("/solution/state_gap", json!(0.5), "solution.state_gap"),
        ("/solution/state_gap", json!(-1e-9), "solution.state_gap"),
        ("/solver_objective", json!(bound + 0.5), "solver_objective"),
    ] {
        let mut w = v.clone();
        set(&mut w, at, to);
        refused(&w, want);
    }
}

/// A general result changed in one number (the objective, a control, a reaction, the bound,
/// the status, the problem) is refused by `ResultFile::from_json`, and so by `certify`, naming
/// the field.
#[test]
fn tampered_general_results_are_refused_naming_the_field() {
    let (_, v) = optimize(ONE_LINK, &["--m", "3"]);
    let j = v["objective"].as_f64().unwrap();
    let u = |i: usize| v["solution"]["controls"][i][0].as_f64().unwrap();
    // The P_3 optimum: up for half the period, down for the other half (in some rotation);
    // swapping a step of each keeps the mean but not the process.
    let up = (0..8).find(|&i| u(i) > 0.5).unwrap();
    let down = (0..8).find(|&i| u(i) < -0.5).unwrap();
    let cases: Vec<(&str, Value, &str)> = vec![
        ("/objective", json!(j + 0.1), "objective"),
        (
            "/solution/controls/0/0",
            json!(u(0) / 2.0),
            "solution.controls",
        ),
        ("/solution/controls/0/0", json!(3.0), "solution.controls[0]"),
        // A bound above J that the gap does not state: the pair is refused.
        ("/certificate/bound", json!(j + 1.0), "certificate.gap"),
        ("/certificate/bound", json!(j - 1.0), "certificate.bound"),
        ("/certificate/gap", json!(0.5), "certificate.gap"),
        // A local method's status on the global method's answer. (A status lowered to
        // time_limit, with the gap it states, is a weaker claim that holds: version 2 refused
        // it only because the MILP's repeated status disagreed.)
        ("/status", json!("stationary"), "status"),
        ("/certificate/kind", json!("local"), "certificate.kind"),
        ("/problem/problem/period", json!(5.0), "solution.states["),
        // Not a general result's method ("sequence" is one since it runs on a chain).
        ("/method", json!("simplex"), "method"),
        ("/kind", json!("robot"), "kind"),
        ("/version", json!(5), "version"),
        ("/solution/m", json!(11), "solution.m"),
        // The MILP's incumbent above its own bound.
        ("/solver_objective", json!(j + 1.0), "solver_objective"),
        (
            "/problem/objective/face_weights",
            json!([0.5, 0.25]),
            "objective",
        ),
        (
            "/problem/sweeping_process/offsets",
            json!([1.0]),
            "problem.sweeping_process.offsets",
        ),
    ];
    for (at, to, want) in cases {
        let mut w = v.clone();
        set(&mut w, at, to);
        refused(&w, want);
    }
    let mut w = v.clone();
    let (a, b) = (
        v["solution"]["controls"][up].clone(),
        v["solution"]["controls"][down].clone(),
    );
    set(&mut w, &format!("/solution/controls/{up}"), b);
    set(&mut w, &format!("/solution/controls/{down}"), a);
    refused(&w, "solution.states[");
    let mut w = v.clone();
    let lam = v["solution"]["reactions"].as_array().unwrap();
    let i = lam
        .iter()
        .position(|l| l[0].as_f64().unwrap() > 0.0)
        .unwrap();
    set(
        &mut w,
        &format!("/solution/reactions/{i}/0"),
        json!(lam[i][0].as_f64().unwrap() * 2.0),
    );
    refused(&w, "solution.states[");
    // The phase gait: a duration, a reaction, the cost, a held face.
    let (_, v) = optimize(ONE_LINK, &["--method", "phase"]);
    for (at, to, want) in [
        ("/solution/durations/0", json!(1.0), "solution.durations"),
        (
            "/solution/actuation_cost",
            json!(1.0),
            "solution.actuation_cost",
        ),
        ("/solution/held/0", json!([7]), "solution.held[0]"),
        ("/objective", json!(2.0), "objective"),
        ("/certificate/phases", json!(2), "certificate.phases"),
    ] {
        let mut w = v.clone();
        set(&mut w, at, to);
        refused(&w, want);
    }
    let mut w = v.clone();
    let held = v["solution"]["held"].as_array().unwrap();
    let j = held
        .iter()
        .position(|h| !h.as_array().unwrap().is_empty())
        .unwrap();
    let f = held[j][0].as_u64().unwrap() as usize - 1;
    let r = v["solution"]["reactions"][j][f].as_f64().unwrap();
    set(
        &mut w,
        &format!("/solution/reactions/{j}/{f}"),
        json!(r * 1.5),
    );
    // A reaction changed breaks its phase's step, named at the state it should reach (as P_m's
    // above), with the rows it should follow from.
    refused(
        &w,
        &format!(
            "solution.states[{}]: does not follow from solution.states[{j}], \
             solution.controls[{j}] and solution.reactions[{j}]",
            j + 1
        ),
    );
    // (P)'s other conditions on the phase gait's own rows: a negative reaction, a reaction on a
    // face the phase does not hold, a control outside U.
    let mut w = v.clone();
    set(&mut w, &format!("/solution/reactions/{j}/{f}"), json!(-r));
    refused(&w, &format!("solution.reactions[{j}][{f}]: negative"));
    let mut w = v.clone();
    set(
        &mut w,
        &format!("/solution/reactions/{j}/{}", 1 - f),
        json!(r),
    );
    refused(
        &w,
        &format!(
            "solution.reactions[{j}][{}]: a reaction on face {}",
            1 - f,
            2 - f
        ),
    );
    let mut w = v.clone();
    set(&mut w, "/solution/controls/0/0", json!(5.0));
    refused(&w, "solution.controls[0]: outside U");
    // The local answer: its status follows its stop.
    let (_, v) = optimize(
        ONE_LINK,
        &["--method", "local", "--m", "3", "--shifts", "1"],
    );
    let mut w = v.clone();
    set(&mut w, "/status", json!("optimal"));
    refused(&w, "status");
    let mut w = v.clone();
    set(&mut w, "/best_start", json!(4));
    refused(&w, "best_start");
    // One answer type for every method: a local answer without its starts, or with a MILP's
    // objective, and a global answer with starts, are refused naming the field; a solution of
    // another method's shape is refused naming what it lacks.
    let mut w = v.clone();
    w.as_object_mut().unwrap().remove("best_start");
    refused(&w, "start_from: a local answer records its starts");
    let mut w = v.clone();
    w["solver_objective"] = json!(1.0);
    refused(&w, "solver_objective: the local method solves no MILP");
    let mut w = v.clone();
    set(&mut w, "/method", json!("phase"));
    refused(&w, "malformed general result: missing field `max_phases`");
    let (_, mut w) = optimize(ONE_LINK, &["--m", "2"]);
    w["start_from"] = json!("input");
    w["starts_tried"] = json!(1);
    w["best_start"] = json!(0);
    refused(&w, "start_from: only the local method records its starts");
    // Through the command line: exit 2, the field named.
    let dir = tempfile::tempdir().unwrap();
    let (_, mut v) = optimize(ONE_LINK, &["--m", "2"]);
    set(&mut v, "/objective", json!(4.0));
    let f = write(dir.path(), "bad.json", &v.to_string());
    let out = crawlopt(&["certify", f.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("bad.json: objective"),
        "{}",
        stderr(&out)
    );
}

/// Crawler results: the envelope of version 4 (`kind`, the gait under `solution`; version 2
/// had the same shape and reads to the same result), and a file of version 1 (the gait under `gait`, `kind` possibly absent, as the files the docs shipped)
/// still reads, to the same result; a version 2 file without `kind`, or with its gait under
/// `gait`, is refused naming the field, and one claiming to be a general result is refused.
/// Version 4 has (P)'s places: the crawler and its gait problem under `problem`, the gait's own
/// numbers in `solution`, the displacement once; versions 1 to 3 read to the same result.
#[test]
fn crawler_results_read_in_version_2_and_in_version_1() {
    let (text, v) = optimize("examples/one_link_gait.toml", &["--phases", "4"]);
    assert_eq!(v["kind"], "crawler");
    assert_eq!(v["format"], "crawlopt-gait-result");
    assert_eq!(v["version"], 4);
    assert!(
        v["solution"]["durations"].is_array() && v.get("gait").is_none(),
        "{v}"
    );
    assert_eq!(v["problem"]["crawler"]["blocks"], 2);
    assert_eq!(v["problem"]["gait"]["period"], 10.0);
    assert_eq!(v["solution"]["displacement_per_period"], v["objective"]);
    for old_place in [
        "crawler",
        "m",
        "displacement_per_period",
        "verified_displacement",
    ] {
        assert!(v.get(old_place).is_none(), "{old_place}: {v}");
    }
    let v3 = as_version_3(&v);
    assert_eq!(
        GaitResult::from_json(&v3.to_string(), "v3.json").unwrap(),
        GaitResult::from_json(&text, "r.json").unwrap()
    );
    // Its two displacements must agree.
    let mut twice = v3.clone();
    twice["verified_displacement"] = json!(2.5);
    let e = GaitResult::from_json(&twice.to_string(), "v3.json").unwrap_err();
    assert!(
        e.to_string().starts_with("v3.json: verified_displacement"),
        "{e}"
    );
    let mut v2 = v3.clone();
    v2["version"] = json!(2);
    assert_eq!(
        GaitResult::from_json(&v2.to_string(), "v2.json").unwrap(),
        GaitResult::from_json(&text, "r.json").unwrap()
    );
    let r = ResultFile::from_json(&text, "r.json").unwrap();
    assert_eq!(r.head().kind, ResultKind::Crawler);
    assert!((r.head().objective - v["objective"].as_f64().unwrap()).abs() == 0.0);
    assert_eq!(r.head().certificate.kind, "global_k_phases");
    // Version 1: the gait under `gait`, no `kind`.
    let mut old = v3.clone();
    let o = old.as_object_mut().unwrap();
    o.remove("kind");
    let gait = o.remove("solution").unwrap();
    o.insert("gait".into(), gait);
    o.insert("version".into(), json!(1));
    let r = ResultFile::from_json(&old.to_string(), "old.json").unwrap();
    assert_eq!(r.head().kind, ResultKind::Crawler);
    assert_eq!(
        GaitResult::from_json(&old.to_string(), "old.json").unwrap(),
        GaitResult::from_json(&text, "r.json").unwrap()
    );
    // A reader's errors on a version 1 file say that its gait was read as the solution.
    let mut short = old.clone();
    short["gait"]["states"].as_array_mut().unwrap().pop();
    let e = ResultFile::from_json(&short.to_string(), "old.json").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("old.json (version 1, its gait read as solution): solution.states"),
        "{e}"
    );
    // The envelope names the method that ran: the sequence and chain methods' exact phase
    // gaits read back under their own names (version 1 wrote "phase" for them).
    for method in ["sequence", "chain"] {
        let (text, v) = optimize(
            "examples/three_blocks_gait.toml",
            &["--method", method, "--time-limit", "20"],
        );
        assert_eq!(v["method"], method);
        let r = ResultFile::from_json(&text, "r.json").unwrap();
        assert_eq!(r.head().method, method);
        let mut as_v1 = v.clone();
        as_v1["method"] = json!("phase");
        let ResultFile::Crawler(old) = ResultFile::from_json(&as_v1.to_string(), "o").unwrap()
        else {
            panic!("read as a general result")
        };
        assert_eq!(old.result.head.objective, v["objective"].as_f64().unwrap());
    }
    // Version 2 needs its kind and its solution.
    let mut no_kind = v3.clone();
    no_kind["version"] = json!(2);
    no_kind.as_object_mut().unwrap().remove("kind");
    let e = ResultFile::from_json(&no_kind.to_string(), "r.json").unwrap_err();
    assert!(e.to_string().starts_with("r.json: kind"), "{e}");
    let mut old_key = old.clone();
    old_key["version"] = json!(2);
    old_key["kind"] = json!("crawler");
    let e = ResultFile::from_json(&old_key.to_string(), "r.json").unwrap_err();
    assert!(e.to_string().contains("solution"), "{e}");
    let mut general = v;
    general["kind"] = json!("general");
    let e = ResultFile::from_json(&general.to_string(), "g.json").unwrap_err();
    assert!(e.to_string().contains("malformed general result"), "{e}");
    // certify of a crawler result as before.
    let dir = tempfile::tempdir().unwrap();
    let f = write(dir.path(), "old.json", &old.to_string());
    let c = json_of(&crawlopt(&["certify", f.to_str().unwrap(), "--json"]));
    assert_eq!(c["format"], "crawlopt-necessary-conditions");
    assert_eq!(c["verdict"], "holds");
}

/// A version 4 crawler's document in the shape versions 1 to 3 wrote (the inverse of the
/// reader's upgrade): the crawler at the top level, the gait problem as `problem`, the
/// solution's numbers and records at the top level, the displacement twice.
fn as_version_3(v: &Value) -> Value {
    let mut old = v.clone();
    let o = old.as_object_mut().unwrap();
    let problem = o.remove("problem").unwrap();
    o.insert("crawler".into(), problem["crawler"].clone());
    o.insert("problem".into(), problem["gait"].clone());
    let s = o["solution"].as_object_mut().unwrap();
    let moved: Vec<(String, Value)> = [
        "m",
        "displacement_per_period",
        "actuation_cost",
        "local",
        "polish",
    ]
    .iter()
    .filter_map(|k| s.remove(*k).map(|x| (k.to_string(), x)))
    .collect();
    o.extend(moved);
    let d = o["displacement_per_period"].clone();
    o.insert("verified_displacement".into(), d);
    o.insert("version".into(), json!(3));
    old
}

/// A crawler's field at the place of another version is refused naming it, not dropped: the
/// old top-level names in a version 4 file, a moved field inside a version 3 file's solution,
/// a misspelt record in the solution; the displacement written twice by version 3 must be a
/// number, equal to the other within the reader's tolerance (`3` and `3.0` are one number);
/// an error of the crawler or the gait problem names its place under `problem`.
#[test]
fn a_crawlers_field_at_another_versions_place_is_refused() {
    let (_, v) = optimize(
        "examples/one_link_gait.toml",
        &["--method", "local", "--m", "3"],
    );
    let read = |w: &Value| GaitResult::from_json(&w.to_string(), "r.json");
    let refused = |w: &Value, want: &str| {
        let e = read(w).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!("r.json: {want}")),
            "want {want}: {e}"
        );
    };
    for (old, value) in [
        ("verified_displacement", json!(99.0)),
        ("crawler", json!(7)),
        ("m", json!(3)),
        ("polish", json!({})),
        ("local", v["solution"]["local"].clone()),
    ] {
        let mut w = v.clone();
        w[old] = value;
        refused(&w, old);
    }
    let mut misspelt = v.clone();
    misspelt["solution"]["polsh"] = json!({"applied": true});
    let e = read(&misspelt).unwrap_err().to_string();
    assert!(e.contains("unknown field `polsh`"), "{e}");
    let v3 = as_version_3(&v);
    let mut inside = v3.clone();
    inside["solution"]["m"] = json!(3);
    refused(&inside, "solution.m");
    let mut null = v3.clone();
    null["verified_displacement"] = Value::Null;
    refused(&null, "verified_displacement");
    let mut integer = v3.clone();
    assert_eq!(v3["displacement_per_period"], 3.0);
    integer["verified_displacement"] = json!(3);
    assert_eq!(read(&integer).unwrap(), read(&v).unwrap());
    let mut period = v.clone();
    period["problem"]["gait"]["period"] = json!(-1.0);
    refused(&period, "problem.gait.period");
    let mut friction = v.clone();
    friction["problem"]["crawler"]["mu_forward"] = json!([1.0, -1.0]);
    refused(&friction, "problem.crawler.mu_forward");
}

/// Files the build before version 4 wrote (`tests/data/v3_*.json`: a local P_m answer of one
/// link at m = 3, a polished P_m answer of a quadratic cost, a sequence search's gait of three
/// blocks) read to what this build writes for the same command: the same result, the local
/// record and the polishing record now in the solution; the sequence search's, cut by a time
/// limit, read with its numbers where they were.
#[test]
fn version_3_files_of_the_build_before_read_as_this_build_writes_them() {
    let dir = tempfile::tempdir().unwrap();
    let quadratic = write(
        dir.path(),
        "quadratic.toml",
        "[crawler]\nblocks = 2\nstiffness = 1.0\nmu_forward = 1.0\nmu_backward = 2.0\n\n\
         [gait]\nperiod = 10.0\nmax_actuator_speed = 1.0\n\
         cost = { kind = \"quadratic\", weight = 0.6 }\n",
    );
    let quadratic = quadratic.to_str().unwrap();
    let read = |name: &str| {
        let text = std::fs::read_to_string(format!("tests/data/{name}")).unwrap();
        let v: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["version"], 3, "{name}");
        (GaitResult::from_json(&text, name).unwrap(), v)
    };
    for (name, model, args) in [
        (
            "v3_local.json",
            "examples/one_link_gait.toml",
            &["--method", "local", "--m", "3"][..],
        ),
        (
            "v3_polished.json",
            quadratic,
            &["--method", "discrete", "--m", "3"][..],
        ),
    ] {
        let (old, v3) = read(name);
        let (text, v4) = optimize(model, args);
        assert_eq!(
            old,
            GaitResult::from_json(&text, "r.json").unwrap(),
            "{name}"
        );
        assert_eq!(v4["solution"]["m"], v3["m"]);
        for record in ["local", "polish"] {
            assert_eq!(
                v4["solution"].get(record),
                v3.get(record),
                "{name}: {record}"
            );
        }
        assert_eq!(serde_json::to_value(&old).unwrap(), v4, "{name}");
    }
    let (seq, v3) = read("v3_sequence.json");
    assert_eq!(seq.head.method, "sequence");
    assert_eq!(seq.displacement_per_period, v3["verified_displacement"]);
    assert_eq!(seq.crawler.blocks, 3);
    assert_eq!(seq.problem.period, v3["problem"]["period"]);
    let v4 = serde_json::to_value(&seq).unwrap();
    assert_eq!(v4["solution"]["local"], v3["local"]);
    assert_eq!(
        GaitResult::from_json(&v4.to_string(), "v4.json").unwrap(),
        seq
    );
}

/// A general simulation's objective at the top level, beside the nested one.
#[test]
fn a_general_simulation_has_its_objective_at_the_top() {
    let v = json_of(&crawlopt(&["simulate", ONE_LINK, "--json"]));
    assert_eq!(v["objective"], v["simulation"]["objective"]);
    assert!((v["objective"].as_f64().unwrap() - 3.0).abs() < 1e-12);
}

/// A simulation of either kind has one envelope in front of its own fields: `format`,
/// `version`, `kind` and `objective` (a crawler's: its displacement per period, `f2 = 0`;
/// `max(0, 2A - 2) = 4` for one link under a sine of amplitude 3, theory §10).
#[test]
fn a_simulation_of_either_kind_has_one_envelope() {
    let dir = tempfile::tempdir().unwrap();
    let crawler = common::write(
        dir.path(),
        "one_link_sine.toml",
        "[crawler]\nblocks = 2\nstiffness = 1.0\nmu_forward = 1.0\nmu_backward = 2.0\n\n\
         [actuation]\nkind = \"sine\"\nperiod = 1.0\namplitude = 3.0\n",
    );
    let c = json_of(&crawlopt(&[
        "simulate",
        crawler.to_str().unwrap(),
        "--json",
    ]));
    let g = json_of(&crawlopt(&["simulate", ONE_LINK, "--json"]));
    for (v, kind) in [(&c, "crawler"), (&g, "general")] {
        assert_eq!(v["format"], "crawlopt-simulation");
        assert_eq!(v["version"], 1);
        assert_eq!(v["kind"], kind);
    }
    assert_eq!(c["objective"], c["displacement_per_period"]);
    assert!(
        (c["objective"].as_f64().unwrap() - 4.0).abs() < 1e-9,
        "{}",
        c["objective"]
    );
    assert!((g["objective"].as_f64().unwrap() - 3.0).abs() < 1e-12);
}

/// `plot` and `report` read a general result back (the problem from its envelope) and draw
/// what `optimize --plot --report` drew from the answer in memory: the same figures, byte for
/// byte (the numbers round-trip exactly), and a report showing the same objective.
#[test]
fn plot_and_report_read_a_general_result_back() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for (example, args) in [
        ("examples/general_drift.toml", vec!["--m", "3"]),
        (ONE_LINK, vec!["--method", "phase"]),
    ] {
        let live = d.join("live");
        let html = d.join("live.html");
        let mut all = args.clone();
        all.extend(["--plot", live.to_str().unwrap()]);
        all.extend(["--report", html.to_str().unwrap()]);
        let (text, v) = optimize(example, &all);
        let file = write(d, "r.json", &text);
        let again = d.join("again");
        let out = crawlopt(&[
            "plot",
            file.to_str().unwrap(),
            "-o",
            again.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let mut names: Vec<_> = std::fs::read_dir(&live)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().ends_with(".svg"))
            .collect();
        names.sort();
        assert!(names.len() >= 4, "{example}: {names:?}");
        for n in &names {
            let (a, b) = (
                std::fs::read(live.join(n)).unwrap(),
                std::fs::read(again.join(n)).unwrap(),
            );
            assert!(a == b, "{example}: {n:?} differs when read back");
        }
        let page = d.join("again.html");
        let out = crawlopt(&[
            "report",
            file.to_str().unwrap(),
            "-o",
            page.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        let value = |p: &std::path::Path| {
            let h = std::fs::read_to_string(p).unwrap();
            let key = "id=\"objective\" data-value=\"";
            let at = h.find(key).unwrap() + key.len();
            h[at..at + h[at..].find('"').unwrap()]
                .parse::<f64>()
                .unwrap()
        };
        let j = v["objective"].as_f64().unwrap();
        assert!(
            (value(&page) - j).abs() <= 1e-12 * j.abs().max(1.0),
            "{example}"
        );
        assert!(
            (value(&html) - j).abs() <= 1e-12 * j.abs().max(1.0),
            "{example}"
        );
        std::fs::remove_dir_all(&live).unwrap();
        std::fs::remove_dir_all(&again).unwrap();
    }
}

/// A gait that barely moves reads back: the three-block problem with one face weight off the
/// crawler's pattern by 1e-10 (not a chain), whose K = 4 and K = 5 optima in the general
/// formulation have J near 0, stored to the solver's tolerance of U and of J's scale (their
/// zero mean, 6e-12, and their reward, 2.5e-10, were refused relative to their own tiny size).
/// The default there, free transitions, reads back too.
#[test]
fn a_gait_that_barely_moves_reads_back() {
    let text = std::fs::read_to_string("examples/general_three_blocks.toml")
        .unwrap()
        .replace(
            "face_weights = [0.3333333333333333,",
            "face_weights = [0.3333333334333333,",
        );
    let file = crawlopt::io::GeneralFile::parse(&text).unwrap();
    use crawlopt::api::PhaseFormulation;
    for (k, formulation) in [4, 5]
        .into_iter()
        .flat_map(|k| [(k, Some(PhaseFormulation::General)), (k, None)])
    {
        let s = crawlopt::api::GeneralPhaseSettings {
            phases: Some(k),
            formulation,
            ..Default::default()
        };
        let r = crawlopt::api::optimize_general_phase(&file, &s, crawlopt::api::Hooks::default())
            .unwrap();
        match formulation {
            Some(_) => assert!(r.formulation.is_none()),
            None => assert_eq!(r.formulation.as_deref(), Some("transitions")),
        }
        let json = serde_json::to_string(&r).unwrap();
        if let Err(e) = ResultFile::from_json(&json, "r.json") {
            panic!("K = {k} (J = {}): {e}", r.head.objective);
        }
    }
}

/// One table of methods for the result files of both kinds: every method the API runs but
/// `auto` (which answers as the method it chose) is a result's method, with the kind of
/// solution its answer has; the refusal of any other word lists them all, the same for a
/// crawler's file and for (P)'s.
#[test]
fn one_table_of_result_methods() {
    use crawlopt::api::GaitMethod;
    use crawlopt::optimal::envelope::{SolutionKind, RESULT_METHODS};
    let run: Vec<&str> = GaitMethod::ALL
        .iter()
        .filter(|m| **m != GaitMethod::Auto)
        .map(|m| m.name())
        .collect();
    let written: Vec<&str> = RESULT_METHODS.iter().map(|(m, _)| *m).collect();
    assert_eq!(run, written);
    assert_eq!(SolutionKind::Discrete.methods(), ["discrete"]);
    assert_eq!(SolutionKind::Local.methods(), ["local"]);
    assert_eq!(
        SolutionKind::Phase.methods(),
        ["phase", "sequence", "chain"]
    );
    assert_eq!(SolutionKind::of_method("auto"), None);
    let want = "r.json: method: must be \"discrete\", \"local\", \"phase\", \"sequence\" or \
                \"chain\" (got simplex)";
    let e = SolutionKind::of_result(Some("simplex"), "r.json").unwrap_err();
    assert_eq!(e.to_string(), want);
    // A crawler's file and (P)'s refuse an unknown method alike.
    let crawler = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--phases",
        "2",
        "--json",
    ]);
    let general = crawlopt(&[
        "optimize",
        "examples/general_one_link.toml",
        "--method",
        "phase",
        "--phases",
        "2",
        "--json",
    ]);
    for out in [crawler, general] {
        assert!(out.status.success(), "{}", stderr(&out));
        let mut v: Value = serde_json::from_slice(&out.stdout).unwrap();
        v["method"] = json!("simplex");
        let e = ResultFile::from_json(&v.to_string(), "r.json").unwrap_err();
        assert_eq!(e.to_string(), want);
    }
}
