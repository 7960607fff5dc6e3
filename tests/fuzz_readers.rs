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
        ..Default::default()
    };
    s.step("api::optimize_general", || {
        api::optimize_general(file, &pm, crawlopt::api::Hooks::default())
    });
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
// General-problem files (issue 30): the property `general_files::fuzz_general_files`.

#[path = "fuzz/general.rs"]
mod general_files;
