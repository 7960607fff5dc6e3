//! Wall time of the library's jobs called from Rust, for the Python package's overhead
//! (`scripts/bench-python` runs this and the same calls from Python and reports the ratio):
//! - `simulate`: examples/three_blocks_sine.toml, exact method, 1000 knots, to the periodic
//!   regime, one period recorded;
//! - `optimize`: examples/three_blocks_gait.toml, the default method (phase gaits, K grown),
//!   J* = 2.6.
//!
//! `cargo bench --bench api_timing` prints one JSON line: the median seconds per call of each
//! and the repetitions. Run without `--bench` (as `cargo test --all-targets` does) it only
//! checks the values once.

use crawlopt::api::{self, Hooks, OptimizeSettings};
use crawlopt::integrate::{simulate, SimOptions};
use crawlopt::io::ModelFile;
use std::time::Instant;

/// The median of `f`'s wall time over repetitions filling about `seconds` (at least 5).
fn median_seconds(seconds: f64, mut f: impl FnMut()) -> (f64, usize) {
    let began = Instant::now();
    let mut times = Vec::new();
    while times.len() < 5 || began.elapsed().as_secs_f64() < seconds {
        let t = Instant::now();
        f();
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], times.len())
}

fn main() {
    let timing = std::env::args().any(|a| a == "--bench");
    let sine = ModelFile::load("examples/three_blocks_sine.toml".as_ref()).unwrap();
    let crawler = sine.crawler().unwrap();
    let act = sine.actuation(crawler.links()).unwrap();
    let opts = SimOptions {
        record_periods: 1,
        ..SimOptions::default()
    };
    let run_sim = || {
        let s = simulate(&crawler, &act, &opts).unwrap();
        assert!((s.displacement_per_period.unwrap() - 1.914213562).abs() < 1e-8);
    };
    let gait = ModelFile::load("examples/three_blocks_gait.toml".as_ref()).unwrap();
    let (c, p) = api::gait_problem(&gait).unwrap();
    let run_opt = || {
        let r = api::optimize(&c, &p, &OptimizeSettings::default(), Hooks::default()).unwrap();
        assert!((r.result.objective - 2.6).abs() < 1e-8);
    };
    if !timing {
        run_sim();
        run_opt();
        return;
    }
    let (sim, sim_reps) = median_seconds(3.0, run_sim);
    let (opt, opt_reps) = median_seconds(10.0, run_opt);
    println!(
        "{}",
        serde_json::json!({
            "simulate_s": sim, "simulate_reps": sim_reps,
            "optimize_s": opt, "optimize_reps": opt_reps,
        })
    );
}
