//! `crawlopt sweep` through the binary: a run killed with SIGKILL and resumed gives the table
//! of an uninterrupted run; shards merged give the unsharded table; a missing shard is named.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_crawlopt");

/// A one-link grid of 60 optimisations (k = a = 1, mu- = 2; mu+ and T vary, mu+ = 2 violates
/// the uniqueness condition).
const SWEEP: &str = r#"
job = "optimize"
[model.crawler]
blocks = 2
stiffness = 1.0
mu_forward = 1.0
mu_backward = 2.0
[model.gait]
period = 10.0
max_actuator_speed = 1.0
[[axis]]
field = "crawler.mu_forward"
values = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
[[axis]]
field = "gait.period"
range = { from = 1.0, to = 19.0, count = 10 }
"#;

fn sweep_file(dir: &Path) -> PathBuf {
    let p = dir.join("grid.toml");
    std::fs::write(&p, SWEEP).unwrap();
    p
}

fn crawlopt(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).output().expect("runs")
}

/// The data lines of a CSV table sorted by point, without the `seconds` column (wall time).
fn table(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let sec = header.iter().position(|c| *c == "seconds").unwrap();
    let mut rows: Vec<(usize, String)> = lines
        .map(|l| {
            let mut c: Vec<String> = csv::ReaderBuilder::new()
                .has_headers(false)
                .from_reader(l.as_bytes())
                .records()
                .next()
                .unwrap()
                .unwrap()
                .iter()
                .map(str::to_string)
                .collect();
            c.remove(sec);
            (c[0].parse().unwrap(), c.join("|"))
        })
        .collect();
    rows.sort();
    rows.into_iter().map(|(_, l)| l).collect()
}

fn rows_in(path: &Path) -> usize {
    std::fs::read_to_string(path)
        .map(|t| t.lines().count().saturating_sub(1))
        .unwrap_or(0)
}

#[test]
fn killed_and_resumed_equals_uninterrupted() {
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(dir.path());
    let f = file.to_str().unwrap();
    let whole = dir.path().join("whole.csv");
    let out = crawlopt(&["sweep", f, "-j", "2", "-o", whole.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let full = table(&whole);
    assert_eq!(full.len(), 60);
    assert_eq!(full.iter().filter(|l| l.contains("uniqueness")).count(), 10);

    let part = dir.path().join("part.csv");
    let mut child = Command::new(BIN)
        .args(["sweep", f, "-j", "1", "-o", part.to_str().unwrap()])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let began = Instant::now();
    while rows_in(&part) < 3 {
        assert!(
            began.elapsed() < Duration::from_secs(120),
            "no rows written"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let before = rows_in(&part);
    assert!(before < 60, "the run finished before it was killed");
    let out = crawlopt(&[
        "sweep",
        f,
        "-j",
        "2",
        "-o",
        part.to_str().unwrap(),
        "--resume",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains(&format!("{before} already done")), "{said}");
    assert_eq!(table(&part), full);
    // Run again without --resume: refused, the table kept.
    let out = crawlopt(&["sweep", f, "-o", part.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--resume"));
    assert_eq!(table(&part), full);
}

#[test]
fn shards_merged_equal_the_whole_and_a_missing_shard_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(dir.path());
    let f = file.to_str().unwrap();
    let whole = dir.path().join("whole.csv");
    assert!(crawlopt(&["sweep", f, "-o", whole.to_str().unwrap()])
        .status
        .success());
    let shards: Vec<String> = (1..=3)
        .map(|i| {
            let p = dir.path().join(format!("shard-{i}-of-3.csv"));
            let s = format!("{i}/3");
            let out = crawlopt(&["sweep", f, "--shard", &s, "-o", p.to_str().unwrap()]);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            assert_eq!(rows_in(&p), 20);
            p.to_str().unwrap().to_string()
        })
        .collect();
    let merged = dir.path().join("merged.csv");
    let m = merged.to_str().unwrap();
    let mut args = vec!["sweep", "merge", f, "--shards", "3", "-o", m];
    args.extend(shards.iter().map(String::as_str));
    let out = crawlopt(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(table(&merged), table(&whole));
    // The merged table is sorted by point.
    let text = std::fs::read_to_string(&merged).unwrap();
    let ids: Vec<usize> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(ids, (0..60).collect::<Vec<_>>());

    std::fs::remove_file(&merged).unwrap();
    let out = crawlopt(&[
        "sweep", "merge", f, "--shards", "3", "-o", m, &shards[0], &shards[2],
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("shard 2/3: 20 point(s) missing: 1, 4, 7"),
        "{err}"
    );
    assert!(!merged.exists());
}

#[test]
fn bad_sweep_files_and_flags_exit_2_naming_the_field() {
    let dir = tempfile::tempdir().unwrap();
    let file = sweep_file(dir.path());
    let f = file.to_str().unwrap();
    let out = crawlopt(&["sweep", f, "--shard", "4/3"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("error: shard: "));
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, SWEEP.replace("gait.period", "gait.periods")).unwrap();
    let out = crawlopt(&["sweep", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: axis[2].field: "), "{err}");
    // JSON Lines on standard output: one object per point.
    std::fs::write(
        &bad,
        SWEEP
            .replace("job = \"optimize\"", "job = \"analyze\"")
            .replace("count = 10", "count = 2"),
    )
    .unwrap();
    let out = crawlopt(&["sweep", bad.to_str().unwrap(), "--json"]);
    assert!(out.status.success());
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 12);
    assert!(lines.iter().all(|l| l["crawler.mu_forward"].is_number()));
}

/// A sweep runs the chain method (issue 27) over the length of a uniform chain: every point
/// says `method = chain` and is at least the alternating triangle wave, `4 - 1/(N - 1)` (the
/// structured floor of the method).
#[test]
fn a_sweep_runs_the_chain_method_over_the_chain_length() {
    let dir = tempfile::tempdir().unwrap();
    let spec = r#"
job = "optimize"
[model.crawler]
blocks = 8
stiffness = 1.0
mu_forward = 1.0
mu_backward = 1.3
[model.gait]
period = 10.0
max_actuator_speed = 1.0
[settings]
method = "chain"
time_limit = 30.0
[[axis]]
field = "crawler.blocks"
values = [8, 10]
"#;
    let file = dir.path().join("chain.toml");
    std::fs::write(&file, spec).unwrap();
    let out_csv = dir.path().join("chain.csv");
    let out = crawlopt(&[
        "sweep",
        file.to_str().unwrap(),
        "-j",
        "1",
        "-o",
        out_csv.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut rd = csv::Reader::from_path(&out_csv).unwrap();
    let header = rd.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    let (blocks, method, objective) = (col("crawler.blocks"), col("method"), col("objective"));
    let mut seen = 0;
    for row in rd.records() {
        let row = row.unwrap();
        let n: f64 = row[blocks].parse().unwrap();
        let j: f64 = row[objective].parse().unwrap();
        assert_eq!(&row[method], "chain");
        let wave = 4.0 - 1.0 / (n - 1.0);
        assert!(j >= wave - 1e-7, "N = {n}: J = {j} below the wave {wave}");
        seen += 1;
    }
    assert_eq!(seen, 2);
}
