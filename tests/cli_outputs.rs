//! Output files and resource limits of the command line (issue 18): `-o` and `--plot` targets
//! that are directories, symbolic links, FIFOs or standard output; no trajectory without a
//! periodic regime; inputs that would allocate or run without bound refused up front, naming
//! the flag or field and the limit. Every refusal here comes before any work, so each run is
//! quick (no timed assertions).

use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn crawlopt(args: &[&str]) -> Output {
    crawlopt_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

fn crawlopt_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_crawlopt"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A bundled example, by absolute path (some runs change directory).
fn example(name: &str) -> String {
    format!("{}/examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Asserts a refusal: exit 2, one line on stderr with every `want`, nothing on stdout.
fn assert_refused(out: &Output, want: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error: ") && err.lines().count() == 1,
        "one line: {err}"
    );
    for w in want {
        assert!(err.contains(w), "want {w:?} in {err}");
    }
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn mkfifo(p: &Path) {
    let st = Command::new("mkfifo").arg(p).status().unwrap();
    assert!(st.success());
}

const CSV_HEADER: &str = "t,x_1,X_1,X_2,y,slip_1,slip_2";

// ----- output files -----------------------------------------------------------------------

#[test]
fn simulate_into_a_directory_is_refused_before_the_work_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("d");
    std::fs::create_dir(&d).unwrap();
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", path(&d)]);
    assert_refused(&out, &[path(&d), "is a directory"]);
    assert_eq!(names(dir.path()), ["d"], "no temporary file beside it");
    assert!(names(&d).is_empty(), "nothing inside it");
}

#[test]
fn report_into_a_directory_is_refused_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("r.html");
    std::fs::create_dir(&d).unwrap();
    let model = example("one_link_gait.toml");
    let out = crawlopt(&["report", &model, "-o", path(&d)]);
    assert_refused(&out, &["r.html", "is a directory"]);
    // The default report.html, when that is a directory.
    std::fs::create_dir(dir.path().join("report.html")).unwrap();
    let out = crawlopt_in(dir.path(), &["report", &model]);
    assert_refused(&out, &["report.html", "is a directory"]);
    assert_eq!(names(dir.path()), ["r.html", "report.html"]);
    assert!(names(&d).is_empty() && names(&dir.path().join("report.html")).is_empty());
}

#[test]
fn a_symlink_to_a_file_is_written_through_and_stays_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("real.csv");
    std::fs::write(&real, "old\n").unwrap();
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).unwrap();
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink("real.csv", &link).unwrap();
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", path(&link)]);
    assert!(out.status.success(), "{}", stderr(&out));
    let meta = std::fs::symlink_metadata(&link).unwrap();
    assert!(meta.file_type().is_symlink(), "the link is not replaced");
    assert_eq!(
        std::fs::read_link(&link).unwrap(),
        PathBuf::from("real.csv")
    );
    let text = std::fs::read_to_string(&real).unwrap();
    assert!(
        text.starts_with(CSV_HEADER),
        "{}",
        &text[..40.min(text.len())]
    );
    let mode = std::fs::metadata(&real).unwrap().permissions().mode();
    assert_eq!(
        mode & 0o777,
        0o640,
        "the replaced file keeps its permissions"
    );
    assert_eq!(names(dir.path()), ["link.csv", "real.csv"]);
}

#[test]
fn a_symlink_to_nothing_or_to_a_directory_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let dangling = dir.path().join("dangling.csv");
    std::os::unix::fs::symlink("missing.csv", &dangling).unwrap();
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", path(&dangling)]);
    assert_refused(&out, &["dangling.csv", "symbolic link"]);
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    let to_dir = dir.path().join("to_dir.csv");
    std::os::unix::fs::symlink("sub", &to_dir).unwrap();
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", path(&to_dir)]);
    assert_refused(&out, &["to_dir.csv", "is a directory"]);
    assert_eq!(names(dir.path()), ["dangling.csv", "sub", "to_dir.csv"]);
    assert!(names(&dir.path().join("sub")).is_empty());
}

#[test]
fn a_fifo_is_written_into_and_stays_a_fifo() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("traj.csv");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", path(&fifo)]);
    if !out.status.success() {
        // Release the reader before failing.
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
        panic!("{}", stderr(&out));
    }
    let text = reader.join().unwrap();
    assert!(
        text.starts_with(CSV_HEADER),
        "{}",
        &text[..40.min(text.len())]
    );
    let meta = std::fs::symlink_metadata(&fifo).unwrap();
    assert!(meta.file_type().is_fifo(), "never renamed over");
    assert_eq!(names(dir.path()), ["traj.csv"], "no temporary file");
}

#[test]
fn the_report_into_a_fifo_is_written_into_it() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("r.html");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let model = example("one_link_gait.toml");
    let out = crawlopt(&["report", &model, "-o", path(&fifo)]);
    if !out.status.success() {
        // Release the reader before failing.
        drop(std::fs::OpenOptions::new().write(true).open(&fifo));
        panic!("{}", stderr(&out));
    }
    let html = reader.join().unwrap();
    assert!(html.contains("</html>"), "a whole page");
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    assert_eq!(names(dir.path()), ["r.html"]);
}

#[test]
fn standard_output_is_written_through_in_order() {
    // The test captures stdout through a pipe: /dev/stdout is that pipe.
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", "/dev/stdout"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with(CSV_HEADER),
        "{}",
        &text[..40.min(text.len())]
    );
    // The whole CSV, then the summary (one descriptor, one offset).
    let lines: Vec<&str> = text.lines().collect();
    let summary = lines
        .iter()
        .position(|l| l.starts_with("method"))
        .expect("a summary");
    assert!(lines[1..summary]
        .iter()
        .all(|l| l.split(',').count() == CSV_HEADER.split(',').count()));
    assert!(lines[summary..]
        .iter()
        .any(|l| l.contains("trajectory written to /dev/stdout")));
}

#[test]
fn without_a_periodic_regime_no_trajectory_and_no_figures_are_written() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.toml");
    std::fs::write(
        &model,
        "[crawler]\nblocks = 10\nstiffness = 1\nmu_forward = 1\nmu_backward = 3.3\n[actuation]\nkind = \"sine\"\nperiod = 1\namplitude = 2\nphase_deg = [0, 90, 180, 270, 360, 450, 540, 630, 720]\n",
    )
    .unwrap();
    let csv = dir.path().join("traj.csv");
    let figs = dir.path().join("figs");
    let out = crawlopt(&[
        "simulate",
        path(&model),
        "--max-periods",
        "2",
        "--no-accelerate",
        "-o",
        path(&csv),
        "--plot",
        path(&figs),
    ]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("not reached"), "{err}");
    assert!(err.contains("no trajectory written to"), "{err}");
    assert!(err.contains("no figures written to"), "{err}");
    assert!(
        !String::from_utf8_lossy(&out.stdout).contains("trajectory written"),
        "the summary does not claim it"
    );
    assert_eq!(names(dir.path()), ["m.toml"]);
}

#[test]
fn plot_into_a_regular_file_is_refused_and_the_file_kept() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("figs");
    std::fs::write(&file, "keep").unwrap();
    let out = crawlopt(&["simulate", "examples/one_link.toml", "--plot", path(&file)]);
    assert_refused(&out, &["figs", "not a directory"]);
    let out = crawlopt(&[
        "simulate",
        "examples/one_link.toml",
        "--plot",
        &format!("{}/sub", path(&file)),
    ]);
    assert_refused(&out, &["cannot create the directory"]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep");
    assert_eq!(names(dir.path()), ["figs"]);
}

#[test]
fn a_file_in_a_missing_directory_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("no/such/t.csv");
    let out = crawlopt(&["simulate", "examples/one_link.toml", "-o", path(&target)]);
    assert_refused(&out, &["t.csv", "cannot write"]);
    assert!(names(dir.path()).is_empty());
}

// ----- resource limits ----------------------------------------------------------------------

#[test]
fn optimize_refuses_a_million_blocks_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("big.toml");
    std::fs::write(
        &model,
        "[crawler]\nblocks = 1000000\nstiffness = 1.0\nmu_forward = 1.0\nmu_backward = 3.3\n\
         [gait]\nperiod = 10.0\nmax_actuator_speed = 1.0\n",
    )
    .unwrap();
    for method in ["auto", "phase", "discrete", "local", "sequence"] {
        let out = crawlopt(&["optimize", path(&model), "--method", method]);
        assert_refused(&out, &["crawler.blocks", "at most 1000 blocks", "1000000"]);
    }
}

#[test]
fn optimize_refuses_grids_too_large_for_the_blocks() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("five.toml");
    std::fs::write(
        &model,
        "[crawler]\nblocks = 5\nstiffness = 1.0\nmu_forward = 1.0\nmu_backward = 1.6\n\
         [gait]\nperiod = 10.0\nmax_actuator_speed = 1.0\n",
    )
    .unwrap();
    let out = crawlopt(&[
        "optimize",
        path(&model),
        "--method",
        "discrete",
        "--m",
        "16",
    ]);
    assert_refused(&out, &["--m: ", "262144 block-steps"]);
}

#[test]
fn optimize_local_refuses_a_million_shifts() {
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "local",
        "--m",
        "4",
        "--shifts",
        "1000000",
    ]);
    assert_refused(&out, &["shifts", "1..=256", "1000000"]);
}

#[test]
fn simulate_refuses_recordings_and_grids_beyond_memory() {
    let out = crawlopt(&[
        "simulate",
        "examples/three_blocks_sine.toml",
        "--periods",
        "100000000",
    ]);
    assert_refused(&out, &["--periods", "5e7 values"]);
    for method in ["exact", "catching-up"] {
        let out = crawlopt(&[
            "simulate",
            "examples/three_blocks_sine.toml",
            "--periods",
            "0",
            "--method",
            method,
            "--steps-per-period",
            "100000000",
        ]);
        assert_refused(&out, &["--steps-per-period", "10000000"]);
    }
    // Within the step limit, but not times the links (2.5e7).
    let dir = tempfile::tempdir().unwrap();
    let five = dir.path().join("five.toml");
    std::fs::write(
        &five,
        "[crawler]\nblocks = 5\nstiffness = 1\nmu_forward = 1\nmu_backward = 3.3\n\
         [actuation]\nkind = \"sine\"\nperiod = 1\namplitude = 2\nphase_deg = [0, 90, 180, 270]\n",
    )
    .unwrap();
    let out = crawlopt(&[
        "simulate",
        path(&five),
        "--periods",
        "0",
        "--steps-per-period",
        "9000000",
    ]);
    assert_refused(&out, &["--steps-per-period", "2.5e7"]);
}

#[test]
fn bench_refuses_every_flag_that_would_hang_or_mean_nothing_by_its_name() {
    let cases: &[(&[&str], &[&str])] = &[
        (&["--min-time", "nan"], &["--min-time", "NaN"]),
        (&["--min-time", "inf"], &["--min-time", "inf"]),
        (&["--min-time", "0"], &["--min-time"]),
        (&["--min-time", "-1"], &["--min-time"]),
        (&["--min-time", "1e6"], &["--min-time", "600"]),
        (&["--periods", "1000000000"], &["--periods", "1e9"]),
        (&["--periods", "0"], &["--periods", "at least 1"]),
        (
            &["--blocks", "1000000", "--steps", "10", "--periods", "1"],
            &["--blocks", "2..=100000"],
        ),
        (&["--blocks", "1"], &["--blocks", "2..=100000"]),
        (
            &["--blocks", "2000", "--no-newton"],
            &["--blocks", "1000 without --periods with --no-newton"],
        ),
        (&["--blocks", "3", "--steps", "0"], &["--steps"]),
        (
            &["--blocks", "100000", "--steps", "2000", "--periods", "1"],
            &["--steps", "25000000"],
        ),
        (&["--mu-forward", "-1"], &["--mu-forward"]),
        (&["--mu-backward", "nan"], &["--mu-backward"]),
        (&["--mu-forward", "1e300"], &["--mu-forward"]),
        (&["--amplitude", "1e308"], &["--amplitude"]),
        (&["--amplitude", "0"], &["--amplitude"]),
        (&["--phase-deg", "inf"], &["--phase-deg"]),
        // mu- = 3 violates the uniqueness condition for 4 blocks: the flags are named.
        (
            &["--blocks", "4", "--mu-backward", "3"],
            &["--mu-forward, --mu-backward", "--blocks 4", "uniqueness"],
        ),
    ];
    for (args, want) in cases {
        let mut all = vec!["bench"];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_refused(&out, want);
        assert!(
            !stderr(&out).contains("crawler."),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn bench_runs_with_valid_flags() {
    let out = crawlopt(&[
        "bench",
        "--blocks",
        "3",
        "--steps",
        "50",
        "--periods",
        "2",
        "--min-time",
        "0.001",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.lines().count(), 2, "{text}");
    for line in text.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["periods"], 2);
        assert!(v["us_per_step"].as_f64().unwrap().is_finite());
    }
}
