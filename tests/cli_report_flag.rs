//! `optimize --report FILE`: the report of the computed gait written beside the result, its
//! path checked before any work.

mod common;

use common::crawlopt;

#[test]
fn optimize_writes_the_report_of_its_gait() {
    let dir = tempfile::tempdir().unwrap();
    let html = dir.path().join("gait.html");
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--certify",
        "--report",
        html.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("objective J = 2.6 "), "{stdout}");
    assert!(stdout
        .trim_end()
        .ends_with(&format!("wrote {}", html.display())));
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.contains("2.6") && page.contains("<script"));
    // With --json, stdout is the one JSON document; the line goes to stderr.
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--json",
        "--report",
        html.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!((v["objective"].as_f64().unwrap() - 2.6).abs() < 1e-8);
    assert!(String::from_utf8_lossy(&out.stderr).contains("wrote"));
}

#[test]
fn a_directory_as_the_report_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let t = std::time::Instant::now();
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--report",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: "));
    assert!(out.stdout.is_empty());
    // The optimum takes seconds (4 s on the 2-core machine); the refusal comes before it.
    assert!(t.elapsed().as_secs_f64() < 2.0, "{:?}", t.elapsed());
}
