//! Regression tests of issue 30's items on sweeps, simulate outputs and messages: fields
//! compared by meaning, the point limit on zip and on value lists, job settings refused before
//! any work, threads bounded by points and cores, `--resume` that never destroys a file that is
//! not this sweep's table, devices and FIFOs as sweep outputs, temporary files removed on
//! Ctrl-C and SIGTERM, `simulate --periods 0 -o`, and messages that say what is wrong.

use crawlopt::study::{SweepSettings, SweepSpec, MAX_POINTS, MAX_THREADS};
use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_crawlopt");

fn crawlopt(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().expect("runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The one-link gait problem of theory §10 (k = a = 1, mu+ = 1, mu- = 2: J* = (T - 4) / 2).
const MODEL: &str = r#"
[model.crawler]
blocks = 2
stiffness = 1.0
mu_forward = 1.0
mu_backward = 2.0
[model.gait]
period = 10.0
max_actuator_speed = 1.0
"#;

/// A sweep of `job` over the inline one-link model, with `rest` (settings, axes) appended.
fn sweep(job: &str, rest: &str) -> String {
    format!("job = \"{job}\"\n{MODEL}\n{rest}")
}

/// A sweep file `s.toml` in `dir` running `analyze` over `gait.period` at `periods`.
fn period_sweep(dir: &Path, periods: &str) -> std::path::PathBuf {
    let f = dir.join("s.toml");
    let axis = format!("[[axis]]\nfield = \"gait.period\"\nvalues = [{periods}]\n");
    std::fs::write(&f, sweep("analyze", &axis)).unwrap();
    f
}

fn parse(text: &str) -> crawlopt::Result<SweepSpec> {
    SweepSpec::parse(text, Path::new("."))
}

fn refused(text: &str) -> String {
    parse(text).expect_err("refused").to_string()
}

/// Item 1: one field in two spellings is one axis (the last would otherwise set the model of
/// every row: T = 6 and T = 8 rows both computed at T = 20).
#[test]
fn one_field_in_two_spellings_is_refused() {
    for (a, b) in [
        ("gait.period", "gait.period "),
        ("gait.period", " gait . period"),
        ("crawler.mu_forward[1]", "crawler.mu_forward[ 1 ]"),
        ("crawler.mu_forward[1]", "crawler.mu_forward [1] "),
        ("crawler.mu_forward[1]", "crawler.mu_forward[+1]"),
    ] {
        let text = sweep(
            "analyze",
            &format!(
                "[[axis]]\nfield = \"{a}\"\nvalues = [6, 8]\n[[axis]]\nfield = \"{b}\"\nvalues = [20]\n"
            ),
        );
        let e = refused(&text);
        assert!(
            e.starts_with("axis[2].field: is already axis[1]"),
            "{a:?} / {b:?}: {e}"
        );
    }
    // A whole list and one of its entries overlap (the row would show a value one entry does
    // not have), in either order.
    for (a, b) in [
        ("crawler.mu_forward", "crawler.mu_forward[1]"),
        ("crawler.mu_forward[ 2 ]", "crawler.mu_forward"),
    ] {
        let text = sweep(
            "analyze",
            &format!(
                "[[axis]]\nfield = \"{a}\"\nvalues = [1, 1.5]\n[[axis]]\nfield = \"{b}\"\nvalues = [0.5]\n"
            ),
        );
        let e = refused(&text);
        assert!(e.starts_with("axis[2].field: overlaps axis[1]"), "{e}");
    }
    // Different entries of one list are different fields; the column is the field as meant.
    let spec = parse(&sweep(
        "analyze",
        "[[axis]]\nfield = \" crawler.mu_forward[ 1 ]\"\nvalues = [1]\n\
         [[axis]]\nfield = \"crawler.mu_forward[2]\"\nvalues = [1.5]\n",
    ))
    .unwrap();
    let names: Vec<&str> = spec.axes.iter().map(|a| a.field.as_str()).collect();
    assert_eq!(names, ["crawler.mu_forward[1]", "crawler.mu_forward[2]"]);
    // And a spaced field sets its field: J* = (T - 4) / 2 at T = 6 and 8 (theory §10).
    let spec = parse(&sweep(
        "analyze",
        "[[axis]]\nfield = \"gait.period \"\nvalues = [6, 8]\n",
    ))
    .unwrap();
    let settings = SweepSettings::default();
    let rows = std::sync::Mutex::new(Vec::new());
    crawlopt::study::run(&spec, &settings, &|o, _| rows.lock().unwrap().push(o.row)).unwrap();
    let mut rows = rows.into_inner().unwrap();
    rows.sort_by_key(|r| r.point);
    let j: Vec<f64> = rows.iter().map(|r| r.objective.unwrap()).collect();
    assert_eq!(j, [1.0, 2.0]);
}

/// The same through the JSON form (Python's `co.sweep(dict)`).
#[test]
fn two_spellings_are_refused_from_json_too() {
    let json = r#"{"model": {"crawler": {"blocks": 2, "stiffness": 1.0, "mu_forward": 1.0,
        "mu_backward": 2.0}, "gait": {"period": 10.0, "max_actuator_speed": 1.0}},
        "job": "analyze", "axis": [{"field": "gait.period", "values": [6, 8]},
        {"field": "gait.period ", "values": [20]}]}"#;
    let e = SweepSpec::from_json(json, Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("axis[2].field: is already axis[1]"), "{e}");
}

/// Item 8: zip and value lists obey the point limit, as a product does.
#[test]
fn zip_and_value_lists_obey_the_point_limit() {
    let n = MAX_POINTS + 1;
    let text = format!(
        "combine = \"zip\"\n{}",
        sweep(
            "analyze",
            &format!(
                "[[axis]]\nfield = \"gait.period\"\nvalues = [{}]\n\
                 [[axis]]\nfield = \"crawler.stiffness\"\nvalues = [{}]\n",
                vec!["5"; n].join(","),
                vec!["1"; n].join(",")
            ),
        )
    );
    let e = refused(&text);
    assert!(
        e.starts_with("axis[1].values:") && e.contains(&MAX_POINTS.to_string()),
        "{e}"
    );
    // At the limit, a zip is accepted and has that many points.
    let text = format!(
        "combine = \"zip\"\n{}",
        sweep(
            "analyze",
            &format!(
                "[[axis]]\nfield = \"gait.period\"\nrange = {{ from = 5, to = 9, count = {MAX_POINTS} }}\n\
                 [[axis]]\nfield = \"crawler.stiffness\"\nrange = {{ from = 1, to = 2, count = {MAX_POINTS} }}\n"
            ),
        )
    );
    assert_eq!(parse(&text).unwrap().len().unwrap(), MAX_POINTS);
}

/// Item 8: a list far beyond the limit is refused by a scan of the text, before the TOML
/// parser holds its numbers (3 million values held over a gigabyte for 18 s before). Only the
/// scan says "more than"; the parsed list's refusal gives the count.
#[test]
fn huge_value_lists_are_refused_before_parsing() {
    let n = 3 * MAX_POINTS;
    let list = vec!["6"; n].join(",");
    for (at, layout) in [
        (2, format!("values = [{list}]")),
        (
            2,
            format!("\"values\"=[\n{}\n]", list.replace(",6,6,", ",\n6,6,")),
        ),
    ] {
        let text = format!(
            "combine = \"zip\"\n{}",
            sweep(
                "analyze",
                &format!(
                    "[[axis]]\nfield = \"gait.period\"\nvalues = [1, 2]\n\
                     [[axis]]\nfield = \"crawler.stiffness\"\n{layout}\n"
                ),
            )
        );
        let e = refused(&text);
        assert!(
            e.starts_with(&format!("axis[{at}].values: at most 1000000"))
                && e.contains("more than 1000000 values"),
            "{e}"
        );
    }
}

/// Item 9: settings no point can run with are refused when the file is read, named
/// `settings.KEY`, by the library's own checks of those settings.
#[test]
fn job_settings_are_refused_up_front() {
    let axis = "[[axis]]\nfield = \"gait.period\"\nvalues = [6, 8]\n";
    for (job, setting, field) in [
        ("optimize", "m = 4294967295", "settings.m"),
        ("optimize", "m = 0", "settings.m"),
        ("optimize", "method = \"discrete\"\nm = 17", "settings.m"),
        ("optimize", "method = \"local\"\nm = 15", "settings.m"),
        ("optimize", "phases = 0", "settings.phases"),
        ("optimize", "phases = 65", "settings.phases"),
        ("optimize", "max_phases = 0", "settings.max_phases"),
        ("optimize", "max_phases = 1000", "settings.max_phases"),
        ("optimize", "patience = 0", "settings.patience"),
        ("optimize", "shifts = 0", "settings.shifts"),
        (
            "optimize",
            "method = \"local\"\nshifts = 100000",
            "settings.shifts",
        ),
        ("optimize", "time_limit = -1", "settings.time_limit"),
        ("optimize", "time_limit = 0", "settings.time_limit"),
        ("optimize", "time-limit = inf", "settings.time_limit"),
        ("optimize", "time_limit = nan", "settings.time_limit"),
        ("optimize", "method = \"nope\"", "settings.method"),
        ("optimize", "m = \"a\"", "settings.m"),
        ("optimize", "formulation = \"nope\"", "settings.formulation"),
        ("optimize", "start = 3", "settings.start"),
        ("optimize", "bound = true", "settings.bound"),
        // Options that do not apply to the method the settings decide.
        ("optimize", "m = 3", "settings.m"),
        ("optimize", "shifts = 3", "settings.shifts"),
        ("optimize", "convergence = true", "settings.convergence"),
        (
            "optimize",
            "method = \"local\"\nphases = 3",
            "settings.phases",
        ),
        (
            "optimize",
            "method = \"discrete\"\nphases = 3",
            "settings.phases",
        ),
        ("optimize", "phases = 3\npatience = 2", "settings.patience"),
        ("optimize", "start = \"x.json\"", "settings.start"),
        (
            "optimize",
            "method = \"local\"\nstart = \"missing.json\"",
            "settings.start",
        ),
        (
            "simulate",
            "steps_per_period = 0",
            "settings.steps_per_period",
        ),
        (
            "simulate",
            "steps_per_period = 100000000",
            "settings.steps_per_period",
        ),
        ("simulate", "max_periods = 0", "settings.max_periods"),
        ("simulate", "tol = -1", "settings.tol"),
        ("simulate", "tol = 0", "settings.tol"),
        ("simulate", "tol = nan", "settings.tol"),
        ("simulate", "tol = inf", "settings.tol"),
        ("simulate", "method = \"euler\"", "settings.method"),
        ("analyze", "tol = 1", "settings.tol"),
    ] {
        let text = format!("job = \"{job}\"\n[settings]\n{setting}\n{MODEL}\n{axis}");
        let e = refused(&text);
        assert!(e.starts_with(&format!("{field}:")), "{setting}: {e}");
    }
    // The same settings within range are taken.
    for (job, setting) in [
        ("optimize", "method = \"discrete\"\nm = 3"),
        ("optimize", "phases = 2"),
        ("optimize", "time_limit = 5"),
        (
            "simulate",
            "steps_per_period = 10\ntol = 1e-9\nmax_periods = 10",
        ),
    ] {
        let text = format!("job = \"{job}\"\n[settings]\n{setting}\n{MODEL}\n{axis}");
        parse(&text).unwrap_or_else(|e| panic!("{setting}: {e}"));
    }
}

/// Item 9 through the binary: exit 2 before any work, nothing written.
#[test]
fn the_binary_refuses_bad_settings_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for setting in [
        "job = \"optimize\"\n[settings]\nm = 4294967295",
        "job = \"simulate\"\n[settings]\nsteps_per_period = 0",
        "job = \"simulate\"\n[settings]\ntol = -1",
    ] {
        let f = dir.path().join("s.toml");
        std::fs::write(
            &f,
            format!("{setting}\n{MODEL}\n[[axis]]\nfield = \"gait.period\"\nvalues = [6]\n"),
        )
        .unwrap();
        let out_csv = dir.path().join("out.csv");
        let o = crawlopt(&[
            "sweep",
            f.to_str().unwrap(),
            "-o",
            out_csv.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2), "{setting}: {}", stderr(&o));
        assert!(stderr(&o).starts_with("error: settings."), "{}", stderr(&o));
        assert!(!out_csv.exists());
    }
}

/// Item 14: a block count out of range is said to be out of range, with the range; a
/// fraction is not a whole number. Both when the file is read.
#[test]
fn block_counts_out_of_range_are_named_with_the_range() {
    for (v, want) in [
        ("1e16", "must be in 2..=10000000"),
        ("1", "must be in 2..=10000000"),
        ("-3", "must be in 2..=10000000"),
        ("2.5", "must be a whole number of blocks"),
    ] {
        let e = refused(&sweep(
            "analyze",
            &format!("[[axis]]\nfield = \"crawler.blocks\"\nvalues = [3, {v}]\n"),
        ));
        assert!(e.starts_with("axis[1].values: "), "{e}");
        assert!(e.contains(want), "{v}: {e}");
        assert!(!e.contains("must be an integer"), "{e}");
    }
}

/// Item 14: the matrix message says "dimension" once.
#[test]
fn a_matrix_of_the_wrong_width_says_dimension_once() {
    let text = "[sweeping_process]\nnormals = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]]\n\
        offsets = [1.0, 1.0, 1.0, 1.0]\n[dynamics]\nA = [[-0.5, 0.0], [0.0]]\n\
        B = [[1.0, 0.0], [0.0, 1.0]]\n[control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\n\
        [objective]\nface_weights = [1.0, 0.0, 0.0, 0.0]\n[problem]\nperiod = 10.0\n";
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("g.toml");
    std::fs::write(&f, text).unwrap();
    let o = crawlopt(&["analyze", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("dynamics.A[2]"), "{e}");
    assert!(
        e.contains("the state's dimension") && !e.contains("dimension dimension"),
        "{e}"
    );
}

/// Item 6: threads are bounded by the points and the cores; absurd numbers are refused,
/// naming the flag, before the output is touched.
#[test]
fn threads_are_bounded_and_absurd_numbers_refused() {
    let s = |threads| SweepSettings {
        threads,
        ..Default::default()
    };
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    assert_eq!(s(5000).threads_for(4), 4.min(cores));
    assert_eq!(s(0).threads_for(3), 3.min(cores));
    assert_eq!(s(1).threads_for(100), 1);
    assert_eq!(s(MAX_THREADS).threads_for(0), 1);
    assert!(s(MAX_THREADS).check().is_ok());
    let e = s(MAX_THREADS + 1).check().unwrap_err().to_string();
    assert!(e.starts_with("threads: must be at most 4096"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    let f = period_sweep(dir.path(), "6, 8, 10, 12");
    let out = dir.path().join("t.csv");
    std::fs::write(&out, "keep").unwrap();
    for j in ["18446744073709551615", "100000"] {
        let o = crawlopt(&[
            "sweep",
            f.to_str().unwrap(),
            "-j",
            j,
            "-o",
            out.to_str().unwrap(),
            "--resume",
        ]);
        assert_eq!(o.status.code(), Some(2));
        assert!(
            stderr(&o).starts_with("error: --jobs: must be at most"),
            "{}",
            stderr(&o)
        );
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep");
    }
    // -j 5000 on four points runs (four threads at most, not 5000).
    let o = crawlopt(&["sweep", f.to_str().unwrap(), "-j", "4096"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 5);
}

/// Item 10: `--resume` never truncates a file that is not a table of this sweep, also when it
/// has no newline at all; a torn header or row of this sweep is still continued.
#[test]
fn resume_never_destroys_a_file_that_is_not_this_table() {
    let dir = tempfile::tempdir().unwrap();
    let f = period_sweep(dir.path(), "6, 8, 10");
    let f = f.to_str().unwrap();
    let junk = "x".repeat(200_000);
    for (name, text) in [
        ("big.csv", junk.clone()),
        ("big.jsonl", junk.clone()),
        ("other.csv", "point,gait.mu\n0,1\n2".to_string()),
        ("rows.csv", format!("{}\n0,6,1", "point,gait.period,objective,displacement_per_period,method,certificate,gap,bound,status,verdict,seconds,error")),
        ("tail.csv", "point,gait.period,objective,displacement_per_period,method,certificate,gap,bound,status,verdict,seconds,error\nnot a row".to_string()),
        ("tail.jsonl", "{\"point\":0,\"gait.period\":6,\"objective\":1,\"displacement_per_period\":1,\"method\":null,\"certificate\":\"closed_form\",\"gap\":0,\"bound\":1,\"status\":\"convex\",\"verdict\":null,\"seconds\":0,\"error\":null}\n{\"x\":".to_string()),
    ] {
        let p = dir.path().join(name);
        std::fs::write(&p, &text).unwrap();
        let o = crawlopt(&["sweep", f, "-o", p.to_str().unwrap(), "--resume"]);
        if name == "rows.csv" {
            // This sweep's header and a torn row: continued (the torn row cut off).
            assert!(o.status.success(), "{}", stderr(&o));
            let t = std::fs::read_to_string(&p).unwrap();
            assert_eq!(t.lines().count(), 4, "{t}");
            continue;
        }
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        assert!(stderr(&o).contains(name), "{}", stderr(&o));
        assert_eq!(std::fs::read_to_string(&p).unwrap(), text, "{name} was changed");
    }
    // A torn header (a run killed while writing it) is started over.
    let p = dir.path().join("torn.csv");
    std::fs::write(&p, "point,gait.per").unwrap();
    let o = crawlopt(&["sweep", f, "-o", p.to_str().unwrap(), "--resume"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&p).unwrap().lines().count(), 4);
}

/// Item 13: a device or a FIFO is written straight into, as every other output; `--resume`
/// on one is refused clearly.
#[cfg(unix)]
#[test]
fn sweep_writes_into_devices_and_fifos() {
    let dir = tempfile::tempdir().unwrap();
    let f = period_sweep(dir.path(), "6, 8, 10");
    let f = f.to_str().unwrap();
    let o = crawlopt(&["sweep", f, "-o", "/dev/null"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = crawlopt(&["sweep", f, "-o", "/dev/null", "--resume"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("/dev/null: is not a regular file: --resume"),
        "{}",
        stderr(&o)
    );
    let fifo = dir.path().join("pipe");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let o = crawlopt(&["sweep", f, "-o", fifo.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = reader.join().unwrap();
    assert!(text.starts_with("point,gait.period,objective"), "{text}");
    assert_eq!(text.lines().count(), 4);
}

/// Item 12: `--periods 0` with `-o` is refused naming --periods, before any work.
#[test]
fn periods_zero_with_an_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p0.csv");
    let o = crawlopt(&[
        "simulate",
        "examples/three_blocks_sine.toml",
        "--periods",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).starts_with("error: --periods: "),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists());
    // Without -o, 0 periods is still a simulation without a recorded trajectory.
    let o = crawlopt(&[
        "simulate",
        "examples/three_blocks_sine.toml",
        "--periods",
        "0",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Item 11: Ctrl-C or SIGTERM while a long trajectory is being written leaves no temporary
/// file: the process removes it and ends with status 130.
#[cfg(unix)]
#[test]
fn signals_leave_no_temporary_file() {
    for signal in [libc::SIGINT, libc::SIGTERM] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("traj.csv");
        let mut child = Command::new(BIN)
            .args([
                "simulate",
                "examples/three_blocks_sine.toml",
                "--periods",
                "2000",
                "-o",
                out.to_str().unwrap(),
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Wait until the temporary file is being written (not a timing assertion: a bounded
        // wait for a precondition).
        let temporary = || {
            std::fs::read_dir(dir.path())
                .unwrap()
                .filter_map(|e| e.ok())
                .any(|e| e.file_name().to_string_lossy().starts_with(".traj.csv.tmp"))
        };
        let began = std::time::Instant::now();
        while !temporary() {
            assert!(began.elapsed().as_secs() < 60, "no temporary file appeared");
            assert!(
                child.try_wait().unwrap().is_none(),
                "ended before the signal"
            );
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        unsafe { libc::kill(child.id() as i32, signal) };
        let status = child.wait().unwrap();
        assert_eq!(status.code(), Some(130), "signal {signal}: {status:?}");
        let left: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(left.is_empty(), "signal {signal}: left {left:?}");
    }
}
