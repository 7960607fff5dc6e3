//! `crawlopt simulate --no-newton`: the search with Anderson alone against the default
//! Newton-Krylov search on a chain of 30 blocks (the bench gait), in the JSON and text output.

use std::process::Output;

mod common;
use common::{crawlopt, write};

/// The bench gait on 30 blocks: `L_l = 2 sin(2 pi t - l pi / 2)`.
fn model() -> String {
    let phases: Vec<String> = (0..29).map(|l| format!("{}", 90 * l)).collect();
    format!(
        "[crawler]\nblocks = 30\nstiffness = 1\nmu_forward = 1\nmu_backward = 3.3\n\
         [actuation]\nkind = \"sine\"\nperiod = 1\namplitude = 2\nphase_deg = [{}]\n",
        phases.join(", ")
    )
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn no_newton_searches_with_anderson_alone_and_finds_the_same_displacement() {
    let dir = tempfile::tempdir().unwrap();
    let f = write(dir.path(), "chain.toml", &model());
    let base = ["simulate", f.to_str().unwrap(), "--method", "catching-up"];
    let newton = json(&crawlopt(&[&base[..], &["--json"]].concat()));
    let anderson = json(&crawlopt(&[&base[..], &["--json", "--no-newton"]].concat()));
    assert_eq!(newton["search"], "newton");
    assert!(newton["newton_steps"].as_u64().unwrap() >= 1);
    assert!(newton["tangent_products"].as_u64().unwrap() >= 1);
    assert_eq!(anderson["search"], "anderson");
    assert_eq!(anderson["newton_steps"], 0);
    assert_eq!(anderson["tangent_products"], 0);
    let (dn, da) = (
        newton["displacement_per_period"].as_f64().unwrap(),
        anderson["displacement_per_period"].as_f64().unwrap(),
    );
    assert!((dn - da).abs() <= 1e-10, "{dn} against {da}");
    // The text output names the search and its cost.
    let text = crawlopt(&[&base[..], &["--no-newton"]].concat());
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("Anderson-accelerated search"), "{text}");
    assert!(
        text.contains("0 Newton step(s), 0 Jacobian-vector product(s)"),
        "{text}"
    );
}
