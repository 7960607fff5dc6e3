//! Wall time of the library's jobs called from Rust, for the Python package's overhead
//! (`scripts/bench-python` runs this and the same calls from Python and reports the ratio):
//! - `simulate`: examples/three_blocks_sine.toml, exact method, 1000 knots, to the periodic
//!   regime, one period recorded;
//! - `optimize`: examples/three_blocks_gait.toml, the default method (phase gaits, K grown),
//!   J* = 2.6.
//!
//! Both sides allocate with mimalloc, as the extension does.
//!
//! `cargo bench --bench api_timing` prints one JSON line: the median seconds per call of each
//! and the repetitions. The seconds are the CPU time of the thread that runs the job
//! (`CLOCK_THREAD_CPUTIME_ID`, as Python's `time.thread_time`; the extension runs a job on the
//! calling thread), so that neither another program's load on the machine (as in wall time)
//! nor the idle spinning of NumPy's OpenBLAS threads (as in the process's CPU time: 5 % of a
//! short simulation's samples in `perf`) counts. Run without `--bench` (as `cargo test --all-targets` does) it only
//! checks the values once.

use crawlopt::api::{self, Hooks, OptimizeSettings};

/// The Python extension's allocator (python/src/lib.rs), so that both sides do the same work:
/// under glibc's malloc the recorded trajectory's small vectors cost this side more than the
/// extension's whole call.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;
use crawlopt::integrate::{simulate, SimOptions};
use crawlopt::io::ModelFile;
use std::time::Instant;

/// The CPU time of this thread so far, in seconds.
fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes the timespec it is given.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// The median of `f`'s CPU time over repetitions filling about `seconds` of wall time (at
/// least 5).
fn median_seconds(seconds: f64, mut f: impl FnMut()) -> (f64, usize) {
    let began = Instant::now();
    let mut times = Vec::new();
    while times.len() < 5 || began.elapsed().as_secs_f64() < seconds {
        let t = cpu_seconds();
        f();
        times.push(cpu_seconds() - t);
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
        assert!((r.result.head.objective - 2.6).abs() < 1e-8);
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
