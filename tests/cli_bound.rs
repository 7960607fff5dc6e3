//! `optimize --bound`: the upper bound over all periodic gaits beside the K-phase certificate,
//! in the text, in the JSON result, and read back by `certify`.

mod common;

use common::{crawlopt, crawlopt_json};

#[test]
fn optimize_reports_the_upper_bound_and_the_file_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--bound",
        "--bound-resolution",
        "16",
        "--bound-box-resolution",
        "16",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    // J* = 3; the bound on the 16 x 16 grid is 3.25 (gap 2h, h = w / 16).
    assert!(
        stdout.contains("upper bound over all periodic gaits: 3.25")
            && stdout.contains("pl-storage, grid 16 x 16")
            && stdout.contains("optimal within 7.7 %"),
        "{stdout}"
    );
    let out = crawlopt(&[
        "optimize",
        "examples/one_link_gait.toml",
        "--bound",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let ub = &v["certificate"]["upper_bound"];
    assert_eq!(ub["method"], "pl-storage");
    assert_eq!(ub["resolution"], 8);
    assert!((ub["value"].as_f64().unwrap() - 3.5).abs() < 1e-6, "{ub}");
    // The file is readable, and a bound below the objective is refused by name.
    let file = dir.path().join("g.json");
    std::fs::write(&file, &out.stdout).unwrap();
    let ok = crawlopt(&["certify", file.to_str().unwrap()]);
    assert_eq!(
        ok.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let mut bad = v.clone();
    bad["certificate"]["upper_bound"]["value"] = serde_json::json!(2.5);
    std::fs::write(&file, serde_json::to_vec(&bad).unwrap()).unwrap();
    let err = crawlopt(&["certify", file.to_str().unwrap()]);
    assert_eq!(err.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&err.stderr).contains("certificate.upper_bound.value"),
        "{}",
        String::from_utf8_lossy(&err.stderr)
    );
    // Every --bound-* flag needs --bound, and the message names the flag given.
    for flag in [
        "--bound-resolution",
        "--bound-box-resolution",
        "--bound-time-limit",
        "--bound-cost-tangents",
    ] {
        let out = crawlopt(&["optimize", "examples/one_link_gait.toml", flag, "4"]);
        assert_eq!(out.status.code(), Some(2), "{flag}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("error: {flag}: ")), "{err}");
    }
}

/// `--bound-time-limit` is the bound's own: it shared an argument id with `optimize`'s
/// `--time-limit`, so `--bound-time-limit 0.5` alone stopped the three-block MILP at 0.5 s
/// (status `time_limit`, exit 0). With `--bound` and that limit (the bound's LP on a 2 x 2 grid
/// takes about 0.04 s), the MILP still proves its optimum.
#[test]
fn the_bounds_time_limit_is_not_the_optimisers() {
    let v = common::crawlopt_json(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--bound",
        "--bound-resolution",
        "2",
        "--bound-box-resolution",
        "2",
        "--bound-time-limit",
        "0.5",
        "--json",
    ]);
    assert_eq!(v["status"], "optimal_among_k_phases", "{}", v["status"]);
    assert!((v["objective"].as_f64().unwrap() - 2.6).abs() < 1e-9);
    assert!(v["certificate"]["upper_bound"]["value"].as_f64().unwrap() >= 2.6 - 1e-9);
}

#[test]
fn the_quadratic_cost_enters_the_bound_by_its_tangents() {
    // c = 0.2: J* = 2 at the rate bound; on 16 x 16 with 4 tangents the bound is
    // J* + 2h + T c a^2 / (2 M^2) = 2 + 0.25 + 0.0625 (tests/upper_bound.rs).
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("q.toml");
    let text = std::fs::read_to_string("examples/one_link_gait.toml").unwrap();
    let text = text.replace(
        r#"cost = { kind = "none" }"#,
        r#"cost = { kind = "quadratic", weight = 0.2 }"#,
    );
    std::fs::write(&file, text).unwrap();
    let v = crawlopt_json(&[
        "optimize",
        file.to_str().unwrap(),
        "--bound",
        "--bound-resolution",
        "16",
        "--bound-box-resolution",
        "16",
        "--bound-cost-tangents",
        "4",
        "--json",
    ]);
    let ub = &v["certificate"]["upper_bound"];
    assert_eq!(ub["cost_tangents"], 4);
    assert!(
        (ub["value"].as_f64().unwrap() - 2.3125).abs() < 1e-6,
        "{ub}"
    );
    assert!((v["objective"].as_f64().unwrap() - 2.0).abs() < 1e-6, "{v}");
    // The text names the tangents with the grid.
    let out = crawlopt(&[
        "optimize",
        file.to_str().unwrap(),
        "--bound",
        "--bound-resolution",
        "16",
        "--bound-box-resolution",
        "16",
        "--bound-cost-tangents",
        "4",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("(pl-storage, grid 16 x 16, 4 cost tangents)"),
        "{text}"
    );
}

/// The default grid fits the crawler: a four-block crawler's 8 x 8 grid has 1e8 simplices and
/// was refused ("--bound-resolution: the grid has 106168320 simplices"), so `--bound` without
/// grid flags failed on every four-block crawler. It now takes the 2 x 1 grid, whose LP
/// finishes (docs/guide/bound.md: 6.667 in 15 s); the bound is above the certified J and below
/// the trivial one, aT(N-1)/N = 7.5 (V = 0). A grid given is refused when its LP is too large,
/// naming the flag given.
#[test]
fn the_default_grid_fits_a_four_block_crawler() {
    let dir = tempfile::tempdir().unwrap();
    let file = common::write(
        dir.path(),
        "four.toml",
        "[crawler]\nblocks = 4\nstiffness = 1\nmu_forward = 1\nmu_backward = 1.6\n\n\
         [gait]\nperiod = 10\nmax_actuator_speed = 1\ncost = { kind = \"none\" }\n",
    );
    let f = file.to_str().unwrap();
    let v = crawlopt_json(&[
        "optimize",
        f,
        "--phases",
        "2",
        "--bound",
        "--bound-time-limit",
        "3",
        "--json",
    ]);
    let ub = &v["certificate"]["upper_bound"];
    assert_eq!(
        (ub["resolution"].as_u64(), ub["box_resolution"].as_u64()),
        (Some(2), Some(1))
    );
    let j = v["objective"].as_f64().unwrap();
    assert!((j - 3.6).abs() < 1e-6, "{j}");
    let value = ub["value"].as_f64().unwrap();
    assert!(value >= j && value <= 7.5 + 1e-9, "{ub}");
    // A grid given that is too large is refused (exit 2) naming the flag given, and why.
    let refused = |grid: &[&str], flag: &str, why: &str| {
        let mut args = vec!["optimize", f, "--phases", "2", "--bound"];
        args.extend_from_slice(grid);
        let err = crawlopt(&args);
        assert_eq!(err.status.code(), Some(2));
        let stderr = String::from_utf8_lossy(&err.stderr);
        assert!(stderr.contains(flag) && stderr.contains(why), "{stderr}");
    };
    refused(
        &["--bound-resolution", "8", "--bound-box-resolution", "8"],
        "--bound-resolution",
        "simplices",
    );
    // Only the box given, too fine for four blocks: refused by its row count, naming it.
    refused(
        &["--bound-box-resolution", "8"],
        "--bound-box-resolution",
        "rows",
    );
}
