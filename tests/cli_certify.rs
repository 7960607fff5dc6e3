//! The `certify` command-line contract: the JSON certificate, `optimize --certify`, and one-line
//! errors (exit status 2) for bad or inconsistent result files.

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::crawlopt;

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stdout)))
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn write(dir: &Path, name: &str, v: &serde_json::Value) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, serde_json::to_string(v).unwrap()).unwrap();
    p
}

/// `optimize --json` of the one-link example on P_3.
fn one_link_result() -> serde_json::Value {
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
    json(&out)
}

#[test]
fn certify_json_has_the_contract_fields() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(dir.path(), "r.json", &one_link_result());
    let out = crawlopt(&["certify", f.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["format"], "crawlopt-necessary-conditions");
    assert_eq!(v["verdict"], "holds");
    assert_eq!(v["lambda"], 1.0);
    let conds = v["conditions"].as_array().unwrap();
    assert!(conds.len() >= 12);
    for c in conds {
        for key in [
            "name",
            "theorem",
            "statement",
            "residual",
            "tolerance",
            "holds",
        ] {
            assert!(!c[key].is_null(), "{key} missing in {c}");
        }
    }
    let m = &v["multipliers"];
    assert_eq!(m["times"].as_array().unwrap().len(), 9);
    for key in ["p", "p_plus_omega", "psi", "u"] {
        assert_eq!(m[key].as_array().unwrap().len(), 8, "{key}");
    }
    assert_eq!(m["xi"].as_array().unwrap().len(), 2);
    assert_eq!(v["one_link"]["bang_bang"], true);
    // The human form prints the verdict and every condition.
    let out = crawlopt(&["certify", f.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains(": holds"), "{text}");
    assert!(text.contains("weak_maximality"), "{text}");
}

#[test]
fn optimize_certify_adds_the_certificate() {
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--phases",
        "4",
        "--certify",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["format"], "crawlopt-gait-result");
    assert_eq!(v["necessary_conditions"]["verdict"], "holds");
    assert!(v["necessary_conditions"]["conditions"]
        .as_array()
        .unwrap()
        .iter()
        .all(|c| c["holds"] == true));
}

/// An edit of a result file.
type Edit = Box<dyn Fn(&mut serde_json::Value)>;

#[test]
fn inconsistent_result_files_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = one_link_result();
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "grid",
            Box::new(|v| v["solution"]["m"] = serde_json::json!(4)),
            "dyadic grid",
        ),
        (
            "outside",
            Box::new(|v| {
                v["solution"]["states"][3][0] = serde_json::json!(5.0);
            }),
            "outside C",
        ),
        (
            "periodic",
            Box::new(|v| {
                let last = v["solution"]["states"].as_array().unwrap().len() - 1;
                let x = v["solution"]["states"][last][0].as_f64().unwrap();
                // Towards the inside of C = [-1, 1], so that only periodicity breaks.
                v["solution"]["states"][last][0] = serde_json::json!(x - 0.5 * x.signum());
            }),
            "not periodic",
        ),
        (
            "mean",
            Box::new(|v| v["solution"]["controls"][0][0] = serde_json::json!(0.5)),
            "zero mean",
        ),
        (
            "rate",
            Box::new(|v| v["solution"]["controls"][0][0] = serde_json::json!(1.5)),
            "rate bound",
        ),
        (
            "dynamics",
            Box::new(|v| {
                let d = v["solution"]["block_displacements"][1][1].as_f64().unwrap();
                v["solution"]["block_displacements"][1][1] = serde_json::json!(d + 0.25);
            }),
            "does not follow",
        ),
        (
            "steps",
            Box::new(|v| {
                v["solution"]["durations"][0] = serde_json::json!(1.0);
                v["solution"]["durations"][1] = serde_json::json!(1.5);
                v["solution"]["times"][1] = serde_json::json!(1.0);
            }),
            "h = T / 2^3",
        ),
    ];
    for (name, edit, want) in cases {
        let mut v = good.clone();
        edit(&mut v);
        let f = write(dir.path(), &format!("{name}.json"), &v);
        let out = crawlopt(&["certify", f.to_str().unwrap()]);
        let e = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {e}");
        assert!(out.stdout.is_empty(), "{name}");
        assert_eq!(e.lines().count(), 1, "{name}: {e}");
        assert!(e.starts_with("error: "), "{name}: {e}");
        assert!(e.contains(want), "{name}: {e}");
    }
    let out = crawlopt(&["certify", "no/such/file.json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("no/such/file.json"));
}

/// A phase answer with a piece of about 1e-12 of the period (four blocks of unequal stiffness
/// and friction, K = 3): HiGHS meets the rate bound only to its feasibility tolerance, and that
/// excess divided by so short a duration gave a rate 7 % beyond the bound, which `certify` then
/// refused. The decoder clips each increment to the bound the MILP imposes, so the answer keeps
/// every rate within it and reads back.
#[test]
fn a_phase_answer_with_a_very_short_piece_keeps_its_rates_within_the_bound() {
    let dir = tempfile::tempdir().unwrap();
    let model = common::write(
        dir.path(),
        "four.toml",
        "[crawler]\nblocks = 4\nstiffness = [1.0, 2.0, 1.5]\n\
         mu_forward = [1.0, 1.2, 0.9, 1.1]\nmu_backward = [2.5, 3.1, 2.7, 2.0]\n\n\
         [gait]\nperiod = 8.0\nmax_actuator_speed = 1.0\ncost = { kind = \"none\" }\n",
    );
    let v = common::optimize_json(&model, &["--phases", "3"]);
    // J_3 of this crawler, as tests/general_phase.rs finds it with the chain's formulation.
    assert!((v["objective"].as_f64().unwrap() - 3.0666666667).abs() < 1e-7);
    let bound: Vec<f64> = v["problem"]["gait"]["rate_bound"]
        .as_array()
        .unwrap()
        .iter()
        .map(|a| a.as_f64().unwrap())
        .collect();
    for (j, u) in v["solution"]["controls"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
    {
        for (l, ul) in u.as_array().unwrap().iter().enumerate() {
            let ul = ul.as_f64().unwrap();
            assert!(
                ul.abs() <= bound[l] * (1.0 + 1e-12),
                "controls[{j}][{l}] = {ul}"
            );
        }
    }
    assert_eq!(common::certify_written(dir.path(), &v)["verdict"], "holds");
}
