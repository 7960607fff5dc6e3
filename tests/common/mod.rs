//! Helpers shared by the integration tests.
#![allow(dead_code)]

use crawlopt::integrate::{simulate, Actuation, Method, SimOptions, Simulation, Waveform};
use crawlopt::model::general::{GeneralParts, GeneralProblem};
use crawlopt::Crawler;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn sine(n: usize, period: f64, amp: f64, phase_step_deg: f64) -> Actuation {
    Actuation::wave(
        Waveform::Sine,
        period,
        vec![0.0; n],
        vec![amp; n],
        (0..n).map(|l| l as f64 * phase_step_deg).collect(),
    )
    .unwrap()
}

pub fn run(c: &Crawler, a: &Actuation, method: Method, m: usize) -> Simulation {
    let s = simulate(
        c,
        a,
        &SimOptions {
            method,
            steps_per_period: m,
            record_periods: 1,
            max_periods: 5000,
            ..SimOptions::default()
        },
    )
    .unwrap();
    assert!(
        s.converged,
        "no periodic regime: {:?}",
        &s.residual_history[s.residual_history.len().saturating_sub(5)..]
    );
    s
}

pub fn disp(c: &Crawler, a: &Actuation, method: Method, m: usize) -> f64 {
    run(c, a, method, m).displacement_per_period.unwrap()
}

/// Runs the `crawlopt` binary with `args` (from the crate's directory).
pub fn crawlopt(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crawlopt"))
        .args(args)
        .output()
        .unwrap()
}

/// Runs `crawlopt` with `args`, asserts that it succeeded (showing its stderr if not) and
/// parses its standard output as JSON.
pub fn crawlopt_json(args: &[&str]) -> serde_json::Value {
    let out = crawlopt(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// `crawlopt optimize FILE ARGS --json`, which must succeed: the answer it prints.
pub fn optimize_json(file: &Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["optimize", file.to_str().unwrap()];
    all.extend_from_slice(args);
    all.push("--json");
    crawlopt_json(&all)
}

/// Writes an answer (a result file's JSON) into `dir` and certifies it back with
/// `crawlopt certify FILE --json`, which must succeed: the certificate it prints.
pub fn certify_written(dir: &Path, answer: &serde_json::Value) -> serde_json::Value {
    let file = write(dir, "answer.json", &answer.to_string());
    crawlopt_json(&["certify", file.to_str().unwrap(), "--json"])
}

/// Writes `text` to `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A small deterministic generator (xorshift64*), uniform in [0, 1): random instances that are
/// the same on every run.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// A general problem on a random bounded polygon of `sigma` faces (at spread angles), with
/// random `A`, `B`, `b` and face weights, box U with zero mean, periodic (tests/general_pm.rs,
/// tests/general_local.rs).
pub fn random_polygon_problem(rng: &mut Rng, sigma: usize) -> GeneralProblem {
    let normals = (0..sigma)
        .map(|k| {
            let th = std::f64::consts::TAU * (k as f64 + rng.range(-0.2, 0.2)) / sigma as f64;
            vec![th.cos(), th.sin()]
        })
        .collect();
    let mut r = || rng.range(-0.5, 0.5);
    GeneralProblem::new(GeneralParts {
        normals,
        offsets: (0..sigma).map(|_| 0.5 + r().abs() * 2.0).collect(),
        a: Some(vec![vec![r(), r()], vec![r(), r()]]),
        b: vec![vec![1.0 + r(), r()], vec![r(), 1.0 + r()]],
        drift: Some(vec![r() * 0.2, r() * 0.2]),
        lower: Some(vec![-1.0, -1.0]),
        upper: Some(vec![1.0, 1.0]),
        zero_mean: true,
        face_weights: Some((0..sigma).map(|_| 0.4 + 1.2 * r()).collect()),
        period: 4.0 + 8.0 * r().abs(),
        periodic: true,
        ..Default::default()
    })
    .unwrap()
}

/// The paper's §4 one-link problem in general form: C = [a, b], g = u, U = [-1, 1] with zero
/// mean, f1 = |eta| / 2 (face weights 1/2, 1/2), periodic.
pub fn one_link_problem(a: f64, b: f64, period: f64) -> GeneralProblem {
    GeneralProblem::new(GeneralParts {
        normals: vec![vec![1.0], vec![-1.0]],
        offsets: vec![b, -a],
        b: vec![vec![1.0]],
        lower: Some(vec![-1.0]),
        upper: Some(vec![1.0]),
        zero_mean: true,
        face_weights: Some(vec![0.5, 0.5]),
        period,
        periodic: true,
        ..Default::default()
    })
    .unwrap()
}

/// Controls of another global optimum of the three-block P_3 (J = 2, as the MILP's): the one
/// the general formulation of the same problem returns (`examples/general_three_blocks.toml`),
/// with strong stationarity failing at its biactive pairs.
pub const OTHER_P3_OPTIMUM: [[f64; 2]; 8] = [
    [0.6, 0.6],
    [-1.0, 1.0],
    [0.4, 1.0],
    [0.0, 1.0],
    [-1.0, -1.0],
    [-1.0, -1.0],
    [1.0, -0.6],
    [1.0, -1.0],
];

/// A certificate (its verdict, branch LPs and reason) of a process at which strong
/// stationarity fails but which no branch LP through it beats, every one solved: `fails`, with
/// the reason saying the failure does not show it suboptimal.
pub fn assert_fails_but_locally_optimal(
    verdict: crawlopt::certify::Verdict,
    branch: Option<&crawlopt::certify::BranchLp>,
    reason: &str,
) {
    assert_eq!(verdict, crawlopt::certify::Verdict::Fails, "{reason}");
    let b = branch.expect("f2 = 0: the branch LPs");
    assert!(b.improvement.abs() < 1e-9, "{b:?}");
    assert!(b.biactive > 0 && b.branches == 1 << b.biactive, "{b:?}");
    assert!(
        reason.contains("this failure does not show it suboptimal"),
        "{reason}"
    );
}
