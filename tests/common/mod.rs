//! Helpers shared by the integration tests.
#![allow(dead_code)]

use crawlopt::integrate::{simulate, Actuation, Method, SimOptions, Simulation, Waveform};
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
