//! Fuzz/property harness for every reader (issue 18): the model TOML, CSV actuations, gait-result
//! JSON and J_m tables. Each property mutates seed files (arbitrary bytes, syntax-token soup,
//! byte edits, and structural mutations of the value tree: numbers replaced by extremes, keys
//! deleted, arrays shortened, lengthened, emptied or with a row duplicated, types changed) and
//! runs every case through the reader and the commands that consume it, in-process (panics
//! caught) and through the binary (with a deadline and a memory limit). A case passes when every
//! run ends in success or a typed error: exit 0 or 2 (3 for `simulate` without a periodic
//! regime), `Ok` or `Err` in-process; a panic, an abort, a hang, or `--json` output that is not
//! JSON fails it.
//!
//! CI runs each property once with a fixed seed (well under a minute in release mode);
//! `scripts/fuzz SECONDS` runs them with fresh seeds for longer (see `tests/fuzz/harness.rs`).
//! Findings are recorded below as regression tests on the shrunk inputs of
//! `tests/fuzz/regressions/`.

#[path = "fuzz/harness.rs"]
mod harness;

use crawlopt::certify::certify_result;
use crawlopt::integrate::{simulate, Method, SimOptions};
use crawlopt::io::ModelFile;
use crawlopt::optimal::GaitResult;
use crawlopt::present::{self, report, PlotInput};
use harness::*;
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Duration;

/// Deadline of a run that should take a fraction of a second.
const QUICK: Duration = Duration::from_secs(20);
/// Deadline of an `optimize` or `report` run under `--time-limit 1`.
const SLOW: Duration = Duration::from_secs(30);

/// A fresh case directory under `target/tmp`.
fn case_dir(property: &str) -> tempfile::TempDir {
    let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz");
    std::fs::create_dir_all(&base).unwrap();
    tempfile::Builder::new()
        .prefix(&format!("{property}-"))
        .tempdir_in(base)
        .unwrap()
}

fn write_files(dir: &Path, files: &Files) {
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
}

fn first<T>(fs: impl IntoIterator<Item = Option<T>>) -> Option<T> {
    fs.into_iter().flatten().next()
}

// ---------------------------------------------------------------------------------------------
// Seeds.

/// A CSV actuation for two links (three blocks), with a header.
const CSV2: &str = "t, L_1, L_2\n0, 0, 0\n1, 3, 0\n2, 3, 3\n3, 0, 3\n";
/// A CSV actuation for one link, without a header, with a comment.
const CSV1: &str = "# one link\n0.0, 0.0\n0.5, 2.5\n";

fn csv_model(blocks: usize) -> String {
    format!(
        "[crawler]\nblocks = {blocks}\nstiffness = 1.0\nmu_forward = 1.0\nmu_backward = 3.0\n\n\
         [actuation]\nkind = \"csv\"\nperiod = 4.0\npath = \"gait.csv\"\n"
    )
}

/// The model seeds: the bundled examples and a few files using the optional fields.
fn model_seeds() -> &'static [Seed] {
    static SEEDS: OnceLock<Vec<Seed>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let mut names: Vec<PathBuf> = std::fs::read_dir(repo().join("examples"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        names.sort();
        let mut v: Vec<Seed> = names
            .iter()
            .map(|p| {
                Seed::new(
                    p.file_name().unwrap().to_string_lossy(),
                    std::fs::read_to_string(p).unwrap(),
                    Syntax::Toml,
                )
            })
            .collect();
        v.push(Seed::new("csv_model.toml", csv_model(3), Syntax::Toml));
        v.push(Seed::new(
            "triangle_lists.toml",
            "[crawler]\nblocks = 3\nstiffness = [1.0, 2.0]\nmu_forward = [1.0, 1.0, 1.5]\n\
             mu_backward = [3.0, 2.0, 3.0]\n\n[actuation]\nkind = \"triangle\"\nperiod = 2.0\n\
             amplitude = [2.0, 1.0]\nphase_deg = [0.0, 45.0]\nmean = [0.5, -0.5]\n\n\
             [simulation]\ninitial_state = [0.5, -0.5]\n",
            Syntax::Toml,
        ));
        v.push(Seed::new(
            "quadratic_tv_gait.toml",
            "[crawler]\nblocks = 2\nstiffness = 2.0\nmu_forward = [1.0, 0.5]\nmu_backward = 2.0\n\n\
             [gait]\nperiod = 6.0\nmax_actuator_speed = [1.5]\n\
             cost = { kind = \"quadratic\", weight = 0.5 }\nmax_total_variation = 8.0\n",
            Syntax::Toml,
        ));
        v
    })
}

/// Model seeds with a `[gait]` section (for `optimize` and `report`).
fn gait_model_seeds() -> Vec<Seed> {
    model_seeds()
        .iter()
        .filter(|s| s.tree.get("gait").is_some())
        .cloned()
        .collect()
}

/// A gait result seed and the model it was computed from.
#[derive(Clone)]
struct ResultSeed {
    seed: Seed,
    /// The model file's text.
    model: String,
}

/// The text of a model seed by name.
fn model_text(name: &str) -> String {
    model_seeds()
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no model seed {name}"))
        .text
        .clone()
}

/// Gait results computed by the binary once per test process (the current format of every
/// kind: phase, discrete, with a convergence table, local, with necessary conditions).
fn result_seeds() -> &'static [ResultSeed] {
    static SEEDS: OnceLock<Vec<ResultSeed>> = OnceLock::new();
    SEEDS.get_or_init(|| {
        let runs: &[(&str, &str, &[&str])] = &[
            ("one_link_phase", "one_link_gait.toml", &[]),
            (
                "one_link_discrete",
                "one_link_gait.toml",
                &["--method", "discrete", "--m", "3"],
            ),
            (
                "one_link_convergence",
                "one_link_gait.toml",
                &["--method", "discrete", "--m", "3", "--convergence"],
            ),
            (
                "three_blocks_local",
                "three_blocks_gait.toml",
                &["--method", "local", "--m", "5", "--time-limit", "2"],
            ),
            (
                "three_blocks_certified",
                "three_blocks_gait.toml",
                &["--phases", "3", "--certify"],
            ),
            (
                "four_blocks_phase",
                "four_blocks_varied_gait.toml",
                &["--phases", "2"],
            ),
            (
                "quadratic_tv_discrete",
                "quadratic_tv_gait.toml",
                &["--method", "discrete", "--m", "3"],
            ),
        ];
        let handles: Vec<_> = runs
            .iter()
            .map(|&(name, model, extra)| {
                let extra: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
                let text = model_text(model);
                std::thread::spawn(move || {
                    let dir = case_dir("seed");
                    std::fs::write(dir.path().join("model.toml"), &text).unwrap();
                    let mut args = vec!["optimize", "model.toml", "--json"];
                    args.extend(extra.iter().map(String::as_str));
                    let r = run_bin(dir.path(), &args, Duration::from_secs(120));
                    match r.outcome {
                        Outcome::Exit(0) => Some(ResultSeed {
                            seed: Seed::new(name, r.stdout, Syntax::Json),
                            model: text,
                        }),
                        _ => {
                            eprintln!(
                                "seed {name}: {} ended {:?}: {}",
                                r.command(),
                                r.outcome,
                                r.stderr
                            );
                            None
                        }
                    }
                })
            })
            .collect();
        let v: Vec<ResultSeed> = handles
            .into_iter()
            .filter_map(|h| h.join().unwrap())
            .collect();
        assert!(v.len() >= 3, "too few gait-result seeds could be computed");
        v
    })
}

fn jm_seeds() -> Vec<Seed> {
    vec![
        Seed::new(
            "jm_table.json",
            r#"{"format": "crawlopt-jm-table", "version": 1, "m": [1, 2, 3, 4, 5],
                "values": [2.0, 2.5, 2.8, 2.9, 2.95], "continuous": 3.0}"#,
            Syntax::Json,
        ),
        Seed::new(
            "jm_table_open.json",
            r#"{"format": "crawlopt-jm-table", "version": 1, "m": [2, 4],
                "values": [0.0, 1.25]}"#,
            Syntax::Json,
        ),
    ]
}

// ---------------------------------------------------------------------------------------------
// Consumers.

/// Small simulation options: enough to exercise the search without spending the CI budget.
fn small_sim(method: Method, initial_state: Option<Vec<f64>>) -> SimOptions {
    SimOptions {
        method,
        steps_per_period: 40,
        record_periods: 1,
        max_periods: 20,
        initial_state,
        ..SimOptions::default()
    }
}

/// Load + crawler + analysis + gait problem + actuation + simulation (both methods), in-process.
/// Crawlers of more than 1000 blocks are left to the binary (its memory is limited).
fn model_chain(path: PathBuf) -> impl FnOnce(&Steps) + Send + 'static {
    move |s: &Steps| {
        // A general problem file (`[sweeping_process]`): analysis, simulation, P_1.
        match s.step("GeneralFile::load_if_general", || {
            crawlopt::io::GeneralFile::load_if_general(&path)
        }) {
            Some(Some(general)) => return general_chain(s, &general),
            Some(None) => {}
            None => return,
        }
        let Some(model) = s.step("ModelFile::load", || ModelFile::load(&path)) else {
            return;
        };
        if (1001..=10_000_000).contains(&model.crawler.blocks) {
            return;
        }
        let Some(crawler) = s.step("ModelFile::crawler", || model.crawler()) else {
            return;
        };
        s.step("Crawler::analyze", || {
            Ok::<_, crawlopt::Error>(crawler.analyze())
        });
        s.step("ModelFile::gait", || model.gait(&crawler));
        let Some(act) = s.step("ModelFile::actuation", || model.actuation(crawler.links())) else {
            return;
        };
        if crawler.require_unique().is_err() {
            return;
        }
        let x0 = model.simulation.initial_state.clone();
        s.step("simulate (exact)", || {
            simulate(&crawler, &act, &small_sim(Method::Exact, x0.clone()))
        });
        s.step("simulate (catching-up)", || {
            simulate(&crawler, &act, &small_sim(Method::CatchingUp, x0.clone()))
        });
    }
}

/// `analyze` and `simulate` of a model file through the binary; `variant` picks flags.
fn model_commands(dir: &Path, variant: u8, stats: &mut Stats) -> Option<Failure> {
    let plot = variant % 8 == 0;
    let mut analyze = vec!["analyze", "model.toml"];
    if variant & 1 == 1 {
        analyze.push("--json");
    }
    if plot {
        analyze.extend(["--plot", "plots-analyze"]);
    }
    let a = run_bin(dir, &analyze, QUICK);
    let mut sim = vec![
        "simulate",
        "model.toml",
        "--max-periods",
        "30",
        "--steps-per-period",
        "40",
    ];
    if variant & 2 == 2 {
        sim.push("--json");
    }
    if variant & 4 == 4 {
        sim.extend(["--method", "catching-up"]);
    }
    if plot {
        sim.extend(["--plot", "plots-simulate"]);
    }
    let s = run_bin(dir, &sim, QUICK);
    first([
        judge_bin("analyze", &a, &[], stats),
        judge_bin("simulate", &s, &[3], stats),
    ])
}

/// Reading a gait result and everything that consumes one, in-process.
fn result_chain(text: String) -> impl FnOnce(&Steps) + Send + 'static {
    move |s: &Steps| {
        let input = s.step("PlotInput::from_json", || {
            PlotInput::from_json(&text, "result.json")
        });
        if let Some(input) = input {
            s.step("PlotInput::figures", || input.figures());
        }
        let Some(r) = s.step("GaitResult::from_json", || {
            GaitResult::from_json(&text, "result.json")
        }) else {
            return;
        };
        s.step("certify_result", || certify_result(&r, "result.json"));
        s.step("gait_figures", || present::gait_figures(&r));
        s.step("build_report", || report::build_report(&r, "result.json"));
    }
}

fn result_commands(dir: &Path, variant: u8, stats: &mut Stats) -> Option<Failure> {
    let (consumer, args): (&str, Vec<&str>) = match variant % 6 {
        0 => ("certify", vec!["certify", "result.json", "--json"]),
        1 => ("certify", vec!["certify", "result.json", "--plot", "plots"]),
        2 => ("plot", vec!["plot", "result.json", "-o", "plots"]),
        3 => ("report", vec!["report", "result.json", "-o", "r.html"]),
        _ => return None,
    };
    judge_bin(consumer, &run_bin(dir, &args, QUICK), &[], stats)
}

// ---------------------------------------------------------------------------------------------
// The properties.

fn outcome_of(
    steps: &[(String, Outcome, String)],
    stats: &mut Stats,
    consumer: &str,
) -> Option<Failure> {
    judge_steps(consumer, steps, stats)
}

/// The library's jobs on a general problem file, with small budgets.
fn general_chain(s: &Steps, file: &crawlopt::io::GeneralFile) {
    use crawlopt::api;
    s.step("api::analyze_general", || api::analyze_general(file));
    let opts = crawlopt::integrate::GeneralSimOptions {
        steps_per_period: 50,
        max_periods: 50,
        ..Default::default()
    };
    s.step("api::simulate_general", || {
        api::simulate_general(file, &opts)
    });
    let pm = api::GeneralPmSettings {
        m: 1,
        time_limit: Some(1.0),
        certify: true,
    };
    s.step("api::optimize_general", || api::optimize_general(file, &pm));
}

/// Model files: every mutation through the in-process chain and `analyze` + `simulate`.
#[test]
fn fuzz_model_files() {
    let seeds = model_seeds();
    let dir = case_dir("model");
    std::fs::write(dir.path().join("gait.csv"), CSV2).unwrap();
    drive(
        "model",
        600,
        (0..seeds.len(), mutation_strategy(), any::<u8>()),
        |(i, m, variant), stats| {
            let files: Files = vec![("model.toml".into(), seeds[*i].render(m))];
            let d = dir.path();
            for p in ["plots-analyze", "plots-simulate"] {
                let _ = std::fs::remove_dir_all(d.join(p));
            }
            write_files(d, &files);
            let steps = in_process(QUICK, model_chain(d.join("model.toml")));
            let mut failure = outcome_of(&steps, stats, "in-process");
            // The binary on one case in two: spawning costs more than the library calls.
            if failure.is_none() && variant % 2 == 0 {
                failure = model_commands(d, variant / 2, stats);
            }
            let mut files = files;
            files.push(("gait.csv".into(), CSV2.into()));
            (files, failure)
        },
    );
}

/// Where a CSV model points: the file, or a path that is not one.
const CSV_PATHS: &[&str] = &[
    "",
    ".",
    "..",
    "missing.csv",
    "/dev/null",
    "/dev/zero",
    "sub",
    "gait.csv/",
    "GAIT.CSV",
];

/// CSV actuations: the CSV mutated (as a table of cells), sometimes the path of the model, and
/// both through the loader and `simulate`.
#[test]
fn fuzz_csv_actuations() {
    let seeds = [
        (3usize, Seed::new("gait.csv", CSV2, Syntax::Csv)),
        (2, Seed::new("gait.csv", CSV1, Syntax::Csv)),
    ];
    let dir = case_dir("csv");
    std::fs::create_dir_all(dir.path().join("sub")).unwrap();
    drive(
        "csv",
        400,
        (0..seeds.len(), mutation_strategy(), any::<u8>()),
        |(i, m, variant), stats| {
            let (blocks, seed) = &seeds[*i];
            let mut model = csv_model(*blocks);
            if variant % 8 == 7 {
                let p = CSV_PATHS[(*variant as usize / 8) % CSV_PATHS.len()];
                model = model.replace("\"gait.csv\"", &format!("{p:?}"));
            }
            let files: Files = vec![
                ("model.toml".into(), model.into_bytes()),
                ("gait.csv".into(), seed.render(m)),
            ];
            let d = dir.path();
            write_files(d, &files);
            let steps = in_process(QUICK, model_chain(d.join("model.toml")));
            let mut failure = outcome_of(&steps, stats, "in-process");
            if failure.is_none() && variant % 2 == 0 {
                let mut args = vec!["simulate", "model.toml", "--max-periods", "30"];
                if variant & 2 == 2 {
                    args.push("--json");
                }
                failure = judge_bin("simulate", &run_bin(d, &args, QUICK), &[3], stats);
            }
            (files, failure)
        },
    );
}

/// Gait results: every mutation through the reader, certify, the figures and the report
/// in-process, and one in three through `certify`, `plot` or `report`.
#[test]
fn fuzz_gait_results() {
    let seeds = result_seeds();
    let dir = case_dir("result");
    drive(
        "result",
        400,
        (0..seeds.len(), mutation_strategy(), any::<u8>()),
        |(i, m, variant), stats| {
            let bytes = seeds[*i].seed.render(m);
            let files: Files = vec![("result.json".into(), bytes.clone())];
            let d = dir.path();
            let _ = std::fs::remove_dir_all(d.join("plots"));
            write_files(d, &files);
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let steps = in_process(QUICK, result_chain(text));
            let mut failure = outcome_of(&steps, stats, "in-process");
            if failure.is_none() {
                failure = result_commands(d, *variant, stats);
            }
            (files, failure)
        },
    );
}

/// J_m tables through `PlotInput` and `plot`.
#[test]
fn fuzz_jm_tables() {
    let seeds = jm_seeds();
    let dir = case_dir("jm");
    drive(
        "jm",
        400,
        (0..seeds.len(), mutation_strategy(), any::<u8>()),
        |(i, m, variant), stats| {
            let bytes = seeds[*i].render(m);
            let files: Files = vec![("table.json".into(), bytes.clone())];
            let d = dir.path();
            let _ = std::fs::remove_dir_all(d.join("plots"));
            write_files(d, &files);
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let steps = in_process(QUICK, move |s: &Steps| {
                if let Some(input) = s.step("PlotInput::from_json", || {
                    PlotInput::from_json(&text, "table.json")
                }) {
                    s.step("PlotInput::figures", || input.figures());
                }
            });
            let mut failure = outcome_of(&steps, stats, "in-process");
            if failure.is_none() && variant % 4 == 0 {
                let r = run_bin(d, &["plot", "table.json", "-o", "plots"], QUICK);
                failure = judge_bin("plot", &r, &[], stats);
            }
            (files, failure)
        },
    );
}

/// `optimize` (and `report`) of mutated gait problems under `--time-limit 1`, and `optimize
/// --start` of mutated gait results.
#[test]
fn fuzz_optimize() {
    let models = gait_model_seeds();
    let dir = case_dir("optimize");
    drive(
        "optimize",
        60,
        (0..models.len(), gentle_mutation_strategy(), any::<u8>()),
        |(i, m, variant), stats| {
            let d = dir.path();
            let _ = std::fs::remove_dir_all(d.join("plots"));
            let start = variant % 4 == 3;
            let (files, consumer, args): (Files, &str, Vec<&str>) = if start {
                // A mutated result as the start of the local methods, on its own model.
                let seeds = result_seeds();
                let r = &seeds[*i % seeds.len()];
                // Its own model, or one case in eight another (a start for another crawler).
                let model = match *variant / 4 % 8 {
                    7 => &seeds[(*i + 1) % seeds.len()].model,
                    _ => &r.model,
                };
                let method = ["local", "sequence", "discrete"][(*variant as usize / 4) % 3];
                (
                    vec![
                        ("model.toml".into(), model.clone().into_bytes()),
                        ("start.json".into(), r.seed.render(m)),
                    ],
                    "optimize --start",
                    vec![
                        "optimize",
                        "model.toml",
                        "--method",
                        method,
                        "--start",
                        "start.json",
                        "--time-limit",
                        "1",
                    ],
                )
            } else {
                let files: Files = vec![("model.toml".into(), models[*i].render(m))];
                let mut args = vec!["optimize", "model.toml", "--time-limit", "1"];
                let consumer = match (variant / 4) % 8 {
                    0 => {
                        args = vec!["report", "model.toml", "-o", "r.html", "--time-limit", "1"];
                        "report"
                    }
                    1 => {
                        args.extend(["--method", "discrete", "--m", "3"]);
                        "optimize"
                    }
                    2 => {
                        args.extend(["--method", "local", "--m", "4"]);
                        "optimize"
                    }
                    3 => {
                        args.extend(["--phases", "2", "--certify", "--json"]);
                        "optimize"
                    }
                    4 => {
                        args.extend(["--method", "sequence"]);
                        "optimize"
                    }
                    5 => {
                        args.extend(["--json", "--plot", "plots"]);
                        "optimize"
                    }
                    _ => "optimize",
                };
                (files, consumer, args)
            };
            write_files(d, &files);
            let failure = judge_bin(consumer, &run_bin(d, &args, SLOW), &[], stats);
            (files, failure)
        },
    );
}

// ---------------------------------------------------------------------------------------------
// The harness itself: it must see what it is looking for.

#[test]
fn harness_tells_panics_and_hangs_from_errors() {
    let steps = in_process(Duration::from_secs(5), |s: &Steps| {
        s.step("fine", || Ok::<_, String>(()));
        s.step("refused", || Err::<(), _>("typed error"));
        s.step("boom", || -> Result<(), String> { panic!("deliberate") });
    });
    let outcomes: Vec<String> = steps.iter().map(|(_, o, _)| o.class()).collect();
    assert_eq!(outcomes, ["ok", "error", "other (panic)"]);
    let failure = judge_steps("self-test", &steps, &mut Stats::default()).unwrap();
    assert!(
        failure.signature.contains("boom: panic"),
        "{}",
        failure.signature
    );
    let steps = in_process(Duration::from_millis(50), |s: &Steps| {
        s.step("sleeps", || -> Result<(), String> {
            std::thread::sleep(Duration::from_secs(2));
            Ok(())
        });
    });
    assert_eq!(steps[0].1, Outcome::Hang);
    // A process past its deadline is killed and reported as a hang.
    let dir = case_dir("self-test");
    let model = repo().join("examples/three_blocks_gait.toml");
    let r = run_bin(
        dir.path(),
        &["optimize", model.to_str().unwrap()],
        Duration::from_millis(1),
    );
    assert_eq!(r.outcome, Outcome::Hang);
    assert!(judge_bin("optimize", &r, &[], &mut Stats::default()).is_some());
}

#[test]
fn mutations_render_what_they_say() {
    let seed = Seed::new("m.toml", "[a]\nx = 1.5\ny = [1, 2, 3]\n", Syntax::Toml);
    let text = |ops: Vec<Op>| String::from_utf8(seed.render(&Mutation::Tree(ops))).unwrap();
    // Extremes the format cannot hold as values are written raw.
    let nan = EXTREMES
        .iter()
        .position(|e| matches!(e, Extreme::Raw("nan")))
        .unwrap();
    let t = text(vec![Op::Number {
        sel: 0,
        field: true,
        with: nan,
    }]);
    assert!(t.contains("x = nan"), "{t}");
    let t = text(vec![Op::Resize {
        sel: 0,
        mode: 3,
        at: 1,
    }]);
    assert!(t.contains("y = [1, 2, 2, 3]"), "{t}");
    let t = text(vec![Op::Delete { sel: 1 }]);
    assert!(!t.contains("x ="), "{t}");
    let csv = Seed::new("g.csv", CSV2, Syntax::Csv);
    let t = String::from_utf8(csv.render(&Mutation::Tree(vec![Op::Resize {
        sel: 0,
        mode: 0,
        at: 0,
    }])))
    .unwrap();
    assert_eq!(t, "t, L_1, L_2\n0, 0, 0\n1, 3, 0\n2, 3, 3\n");
}

// ---------------------------------------------------------------------------------------------
// Regressions: the findings, each on its shrunk input in `tests/fuzz/regressions/` (or, where
// the input is not a file that git can hold, made by the test), run as the finding ran it.

fn regression(name: &str) -> String {
    repo()
        .join("tests/fuzz/regressions")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// Runs the binary in a fresh directory; fails unless it ends with exit 0, 2 with a message, or
/// one of `also`.
fn typed_run(dir: &Path, args: &[&str], also: &[i32], deadline: Duration) -> BinRun {
    let r = run_bin(dir, args, deadline);
    if let Some(f) = judge_bin(args[0], &r, also, &mut Stats::default()) {
        panic!("{}\n{}", f.signature, f.detail);
    }
    r
}

fn assert_refused(r: &BinRun, want: &str) {
    assert_eq!(r.outcome, Outcome::Exit(2), "{}", r.stderr);
    assert!(r.stderr.contains(want), "want {want:?} in {}", r.stderr);
}

/// A CSV actuation `path = ""` named the file as "" and said it could not be read; it says the
/// path is empty.
#[test]
fn regression_csv_path_empty() {
    let dir = case_dir("regression");
    let r = typed_run(
        dir.path(),
        &["simulate", &regression("csv_path_empty.toml")],
        &[],
        QUICK,
    );
    assert_refused(&r, "actuation.path: is empty: name the CSV file");
}

/// A CSV actuation, or a model file, that is a device or a FIFO: `/dev/zero` was read without
/// end (memory without bound: one endless CSV record), a FIFO blocked forever. Refused before
/// being opened.
#[test]
fn regression_inputs_that_are_not_regular_files() {
    let dir = case_dir("regression");
    let d = dir.path();
    let fifo = d.join("fifo");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    let mut paths = vec!["/dev/zero", "sub"];
    std::fs::create_dir_all(d.join("sub")).unwrap();
    if made {
        paths.push("fifo");
    }
    let deadline = Duration::from_secs(5);
    for p in paths {
        std::fs::write(d.join("model.toml"), csv_model(2).replace("gait.csv", p)).unwrap();
        let r = typed_run(d, &["simulate", "model.toml"], &[], deadline);
        assert_refused(&r, "cannot read actuation CSV: is ");
        let r = typed_run(d, &["analyze", p], &[], deadline);
        assert_refused(&r, ": is ");
    }
}

/// Result files are read by the CLI with `read_to_string`: a FIFO blocks `certify`, `plot`,
/// `report` and `--start` forever, and `/dev/zero` is read until memory runs out (exit 2 "out of
/// memory" only because the harness limits the address space). Found by probing the readers'
/// paths alongside the fuzzing; for the owner of `src/main.rs` (`read_text`): read through the
/// bounded reader of the model files.
#[test]
fn regression_result_files_that_are_not_regular_files() {
    let dir = case_dir("regression");
    let d = dir.path();
    let fifo = d.join("fifo.json");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    // `report` reads a result when the name ends in .json.
    std::os::unix::fs::symlink("/dev/zero", d.join("zero.json")).unwrap();
    std::fs::write(d.join("model.toml"), model_text("one_link_gait.toml")).unwrap();
    let deadline = Duration::from_secs(5);
    for input in ["fifo.json", "zero.json"] {
        for args in [
            vec!["certify", input],
            vec!["plot", input, "-o", "plots"],
            vec!["report", input, "-o", "r.html"],
            vec![
                "optimize",
                "model.toml",
                "--method",
                "local",
                "--start",
                input,
            ],
        ] {
            let r = typed_run(d, &args, &[], deadline);
            // Refused before reading, not after an allocation failure.
            assert_eq!(r.outcome, Outcome::Exit(2), "{}", r.command());
            assert!(
                !r.stderr.contains("out of memory") && r.seconds < 2.0,
                "{}: {} after {:.1} s",
                r.command(),
                r.stderr,
                r.seconds
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// General-problem files (issue 30): structured edits of a problem (P), then the generic
// mutations one case in four.

/// A general problem file as data, rendered to TOML by [`GeneralDoc::render`].
#[derive(Debug, Clone)]
struct GeneralDoc {
    normals: Vec<Vec<f64>>,
    offsets: Vec<f64>,
    a: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    /// Face weights (else reaction weights `[1, 0, ...]`).
    face_weights: Option<Vec<f64>>,
    cost: f64,
    period: f64,
    times: Vec<f64>,
    values: Vec<Vec<f64>>,
}

/// The seeds: the one-link problem of §4, the drift example's box with a stiff-capable `A`,
/// and a hexagon with reaction weights.
fn general_docs() -> Vec<GeneralDoc> {
    let one_link = GeneralDoc {
        normals: vec![vec![1.0], vec![-1.0]],
        offsets: vec![1.0, 1.0],
        a: vec![vec![0.0]],
        b: vec![vec![1.0]],
        lower: vec![-1.0],
        upper: vec![1.0],
        face_weights: Some(vec![0.5, 0.5]),
        cost: 0.0,
        period: 10.0,
        times: vec![0.0, 5.0],
        values: vec![vec![1.0], vec![-1.0]],
    };
    let square = GeneralDoc {
        normals: vec![
            vec![1.0, 0.0],
            vec![0.0, 1.0],
            vec![-1.0, 0.0],
            vec![0.0, -1.0],
        ],
        offsets: vec![1.0; 4],
        a: vec![vec![-0.5, 0.0], vec![0.0, -0.5]],
        b: vec![vec![1.0, 0.0], vec![0.0, 1.0]],
        lower: vec![-1.0, -1.0],
        upper: vec![1.0, 1.0],
        face_weights: Some(vec![1.0, 0.0, 0.0, 0.0]),
        cost: 0.1,
        period: 10.0,
        times: vec![0.0, 2.5, 5.0, 7.5],
        values: vec![
            vec![1.0, 0.5],
            vec![1.0, -0.5],
            vec![-1.0, -0.5],
            vec![-1.0, 0.5],
        ],
    };
    let mut hexagon = square.clone();
    hexagon.normals = polygon_normals(6);
    hexagon.offsets = vec![1.0; 6];
    hexagon.face_weights = None;
    vec![one_link, square, hexagon]
}

fn polygon_normals(k: usize) -> Vec<Vec<f64>> {
    (0..k)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / k as f64;
            vec![t.cos(), t.sin()]
        })
        .collect()
}

/// A structured edit of a [`GeneralDoc`].
#[derive(Debug, Clone)]
enum GeneralEdit {
    /// One entry of a field (0 normals, 1 offsets, 2 A, 3 B, 4 weights, 5 bounds, 6 period,
    /// 7 cost, 8 input values) set to an extreme.
    Extreme { field: u8, at: u16, with: u8 },
    /// Face `face` (mod sigma) repeated `times` more times.
    Duplicate { face: u8, times: u8 },
    /// C as a regular polygon of `GENERAL_FACES[k]` faces (2-d seeds).
    Faces { k: u8 },
    /// `A = diag(-10^e, s 10^e, ...)` (`s` the sign of the second entry).
    Stiff { exp: u16, unstable: bool },
    /// Every weight times `10^e`.
    ScaleWeights { exp: i16 },
}

/// Extremes of a general file's numbers.
const GENERAL_EXTREMES: &[f64] = &[
    1e308, -1e308, 1e-300, -1e-300, 1.7e308, 5e-324, 0.0, -0.0, 1e20, 1e-20, 1e12, -1e12,
];
/// Face counts of [`GeneralEdit::Faces`] (one beyond the limit).
const GENERAL_FACES: &[usize] = &[3, 5, 64, 300, crawlopt::model::general::MAX_FACES + 1];

fn general_edit_strategy() -> impl Strategy<Value = GeneralEdit> {
    prop_oneof![
        6 => (0u8..9, any::<u16>(), 0..GENERAL_EXTREMES.len() as u8)
            .prop_map(|(field, at, with)| GeneralEdit::Extreme { field, at, with }),
        2 => (any::<u8>(), 1u8..4).prop_map(|(face, times)| GeneralEdit::Duplicate { face, times }),
        1 => (0..GENERAL_FACES.len() as u8).prop_map(|k| GeneralEdit::Faces { k }),
        3 => (0u16..309, any::<bool>()).prop_map(|(exp, unstable)| GeneralEdit::Stiff { exp, unstable }),
        1 => (-320i16..320).prop_map(|exp| GeneralEdit::ScaleWeights { exp }),
    ]
}

impl GeneralDoc {
    fn apply(&mut self, e: &GeneralEdit) {
        let n = self.normals[0].len();
        let pick = |len: usize, at: u16| at as usize % len.max(1);
        match *e {
            GeneralEdit::Extreme { field, at, with } => {
                let v = GENERAL_EXTREMES[with as usize];
                let flat = |m: &mut Vec<Vec<f64>>, at: u16| {
                    let cols = m[0].len();
                    let k = pick(m.len() * cols, at);
                    m[k / cols][k % cols] = v;
                };
                match field {
                    0 => flat(&mut self.normals, at),
                    1 => {
                        let k = pick(self.offsets.len(), at);
                        self.offsets[k] = v;
                    }
                    2 => flat(&mut self.a, at),
                    3 => flat(&mut self.b, at),
                    4 => {
                        if let Some(w) = &mut self.face_weights {
                            let k = pick(w.len(), at);
                            w[k] = v;
                        }
                    }
                    5 => {
                        let k = pick(self.lower.len(), at);
                        if at % 2 == 0 {
                            self.lower[k] = -v.abs();
                        } else {
                            self.upper[k] = v.abs();
                        }
                    }
                    6 => self.period = v,
                    7 => self.cost = v,
                    _ => flat(&mut self.values, at),
                }
            }
            GeneralEdit::Duplicate { face, times } => {
                let j = face as usize % self.normals.len();
                for _ in 0..times {
                    self.normals.push(self.normals[j].clone());
                    self.offsets.push(self.offsets[j]);
                    if let Some(w) = &mut self.face_weights {
                        w.push(w[j]);
                    }
                }
            }
            GeneralEdit::Faces { k } => {
                if n == 2 {
                    let k = GENERAL_FACES[k as usize];
                    self.normals = polygon_normals(k);
                    self.offsets = vec![1.0; k];
                    if let Some(w) = &mut self.face_weights {
                        *w = (0..k).map(|j| if j == 0 { 1.0 } else { 0.0 }).collect();
                    }
                }
            }
            GeneralEdit::Stiff { exp, unstable } => {
                let r = 10f64.powi(i32::from(exp));
                for (i, row) in self.a.iter_mut().enumerate() {
                    row.iter_mut().for_each(|v| *v = 0.0);
                    row[i] = if i == 1 && unstable { r } else { -r };
                }
            }
            GeneralEdit::ScaleWeights { exp } => {
                let s = 10f64.powi(i32::from(exp));
                if let Some(w) = &mut self.face_weights {
                    w.iter_mut().for_each(|v| *v *= s);
                }
            }
        }
    }

    /// TOML, with `ws` choosing the layout (compact, spread over lines with comments, tabs).
    fn render(&self, ws: u8) -> String {
        let (sep, open, close) = match ws % 4 {
            0 => (", ", "[", "]"),
            1 => (",\n  ", "[\n  ", ",\n]"),
            2 => (" ,\t", "[ \t", " ]"),
            _ => (", # a comment\n", "[ # open\n", "\n]"),
        };
        let num = |v: &f64| format!("{v:?}");
        let row = |r: &[f64]| format!("[{}]", r.iter().map(num).collect::<Vec<_>>().join(", "));
        let vec = |r: &[f64]| {
            format!(
                "{open}{}{close}",
                r.iter().map(num).collect::<Vec<_>>().join(sep)
            )
        };
        let mat = |m: &[Vec<f64>]| {
            format!(
                "{open}{}{close}",
                m.iter().map(|r| row(r)).collect::<Vec<_>>().join(sep)
            )
        };
        let n = self.normals[0].len();
        let reward = match &self.face_weights {
            Some(w) => format!("face_weights = {}", vec(w)),
            None => format!(
                "reaction_weights = {}",
                vec(&(0..n)
                    .map(|i| if i == 0 { 1.0 } else { 0.0 })
                    .collect::<Vec<_>>())
            ),
        };
        let pad = if ws % 2 == 1 { "\n\n" } else { "\n" };
        format!(
            "[sweeping_process]\nnormals = {}\noffsets = {}{pad}[dynamics]\nA = {}\nB = {}{pad}\
             [control]\nlower = {}\nupper = {}\nzero_mean = true{pad}[objective]\n{reward}\n\
             cost = {{ kind = \"quadratic\", weight = {} }}{pad}[problem]\nperiod = {}{pad}\
             [input]\nkind = \"piecewise_constant\"\ntimes = {}\nvalues = {}\n",
            mat(&self.normals),
            vec(&self.offsets),
            mat(&self.a),
            mat(&self.b),
            vec(&self.lower),
            vec(&self.upper),
            num(&self.cost),
            num(&self.period),
            vec(&self.times),
            mat(&self.values),
        )
    }
}

/// The invariant of every answer on a general file: no non-finite number reported (issue 30,
/// item 3), no periodic regime without its `J`. A violation panics inside the step (a failure).
fn general_answers(s: &Steps, file: &crawlopt::io::GeneralFile) {
    use crawlopt::api;
    s.step("api::analyze_general", || api::analyze_general(file));
    let opts = crawlopt::integrate::GeneralSimOptions {
        steps_per_period: 64,
        max_periods: 50,
        ..Default::default()
    };
    s.step("api::simulate_general (finite answer)", || {
        let r = api::simulate_general(file, &opts)?;
        let sim = &r.simulation;
        if sim.converged {
            let j = sim.objective.expect("a periodic regime without J");
            assert!(
                j.is_finite() && sim.reward.is_finite() && sim.cost.is_finite(),
                "J = {j}"
            );
        }
        assert!(
            sim.x.iter().flatten().all(|v| v.is_finite()),
            "a state is not finite"
        );
        assert!(
            sim.lambda.iter().flatten().all(|v| v.is_finite()),
            "a reaction is not finite"
        );
        Ok::<_, crawlopt::Error>(())
    });
    let pm = api::GeneralPmSettings {
        m: 2,
        time_limit: Some(1.0),
        certify: false,
    };
    s.step("api::optimize_general (finite answer)", || {
        let r = api::optimize_general(file, &pm)?;
        let o = r.solution.objective;
        assert!(o.is_finite(), "P_m's J = {o}");
        Ok::<_, crawlopt::Error>(())
    });
}

/// General-problem files: structured edits (extremes such as 1e308, 1e-300 and a huge `A`,
/// duplicated faces, many faces up to one beyond the limit, weights scaled, the layout's
/// whitespace and comments), and one case in four a generic mutation of the result, through the
/// library's jobs with the finite-answer invariant and, one case in four, `simulate --json`.
#[test]
fn fuzz_general_files() {
    let docs = general_docs();
    let dir = case_dir("general");
    drive(
        "general",
        120,
        (
            0..docs.len(),
            proptest::collection::vec(general_edit_strategy(), 0..4),
            any::<u8>(),
            mutation_strategy(),
        ),
        |(i, edits, variant, m), stats| {
            let mut doc = docs[*i].clone();
            edits.iter().for_each(|e| doc.apply(e));
            let text = doc.render(*variant);
            let bytes = if variant % 4 == 3 {
                Seed::new("general.toml", text, Syntax::Toml).render(m)
            } else {
                text.into_bytes()
            };
            let files: Files = vec![("general.toml".into(), bytes)];
            let d = dir.path();
            write_files(d, &files);
            let path = d.join("general.toml");
            let steps = in_process(QUICK, move |s: &Steps| {
                if let Some(Some(file)) = s.step("GeneralFile::load_if_general", || {
                    crawlopt::io::GeneralFile::load_if_general(&path)
                }) {
                    general_answers(s, &file);
                }
            });
            let mut failure = outcome_of(&steps, stats, "in-process");
            if failure.is_none() && (variant / 4) % 4 == 0 {
                let run = run_bin(d, &["simulate", "general.toml", "--json"], QUICK);
                failure = judge_bin("simulate", &run, &[3], stats);
                if failure.is_none() && run.outcome == Outcome::Exit(0) {
                    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
                    let sim = &v["simulation"];
                    if sim["converged"] == true && !sim["objective"].is_f64() {
                        failure = Some(Failure {
                            signature: "simulate: converged without a finite J".into(),
                            detail: run.stdout.chars().take(400).collect(),
                        });
                    }
                }
            }
            (files, failure)
        },
    );
}
