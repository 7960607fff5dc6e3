//! Fuzz/property harness for sweep files (issue 30), on the machinery of
//! `tests/fuzz_readers.rs` (`tests/fuzz/harness.rs`): seed sweep files mutated structurally
//! (numbers replaced by extremes, keys deleted, arrays resized, types changed, text edits) and
//! by edits that target a sweep's own mistakes: one field named twice in two spellings, a whole
//! list beside one of its entries, spaces inside fields, zip and product sizes around the point
//! limit, and job settings out of range.
//!
//! The property: every case ends in a typed outcome (in-process `Ok`/`Err`, no panic, no hang;
//! the binary exits 0 or 2 with a message), and an accepted sweep is meaningful: no two axes
//! set the same number of the model (the column of one would not be the value the point ran
//! with), the columns are distinct, and a run that exits 0 has one row per point with no row
//! refused for a job setting (such a setting is refused before any work, exit 2).
//!
//! CI runs the property once with a fixed seed (a few seconds); `scripts/fuzz SECONDS` runs it
//! with fresh seeds alongside the readers' properties.

#[path = "fuzz/harness.rs"]
mod harness;

use crawlopt::study::{SweepSpec, MAX_POINTS};
use harness::*;
use proptest::prelude::*;
use std::path::Path;
use std::time::Duration;

/// Deadline of one `crawlopt sweep` run on a seed-sized grid (analyze and short simulations).
const QUICK: Duration = Duration::from_secs(20);

/// The base model of every seed (an inline [model]: one link, the gait problem of theory §10,
/// and a sine actuation for simulate).
const MODEL: &str = "[model.crawler]\nblocks = 2\nstiffness = 1.0\nmu_forward = 1.0\n\
    mu_backward = 2.0\n[model.gait]\nperiod = 10.0\nmax_actuator_speed = 1.0\n\
    [model.actuation]\nkind = \"sine\"\nperiod = 1.0\namplitude = 2.0\n";

fn seeds() -> Vec<Seed> {
    let seed = |name: &str, head: &str, axes: &str| {
        Seed::new(name, format!("{head}\n{MODEL}\n{axes}"), Syntax::Toml)
    };
    vec![
        seed(
            "analyze_product.toml",
            "job = \"analyze\"",
            "[[axis]]\nfield = \"gait.period\"\nvalues = [6.0, 8.0]\n\
             [[axis]]\nfield = \"crawler.mu_forward[1]\"\nvalues = [0.5, 1.0]\n",
        ),
        seed(
            "analyze_zip_range.toml",
            "job = \"analyze\"\ncombine = \"zip\"",
            "[[axis]]\nfield = \"crawler.mu_backward\"\n\
             range = { from = 1.5, to = 3.0, count = 3, scale = \"log\" }\n\
             [[axis]]\nfield = \"gait.period\"\nvalues = [5.0, 7.0, 9.0]\n",
        ),
        seed(
            "simulate.toml",
            "job = \"simulate\"\n[settings]\nsteps_per_period = 40\nmax_periods = 30\n\
             tol = 1e-9\nmethod = \"catching-up\"",
            "[[axis]]\nfield = \"actuation.amplitude\"\nvalues = [1.0, 3.0]\n",
        ),
        seed(
            "optimize.toml",
            "job = \"optimize\"\n[settings]\nphases = 2\ntime_limit = 2.0",
            "[[axis]]\nfield = \"gait.period\"\nvalues = [6.0, 10.0]\n",
        ),
        Seed::new(
            "general_optimize.toml",
            format!(
                "job = \"optimize\"\n[settings]\nm = 2\ntime_limit = 2.0\n{GENERAL}\n\
                 [[axis]]\nfield = \"problem.period\"\nvalues = [3.0, 10.0]\n\
                 [[axis]]\nfield = \"sweeping_process.offsets[2]\"\nvalues = [0.5, 2.0]\n"
            ),
            Syntax::Toml,
        ),
        Seed::new(
            "general_simulate.toml",
            format!(
                "job = \"simulate\"\n[settings]\nsteps_per_period = 40\nmax_periods = 30\n\
                 {GENERAL}\n[[axis]]\nfield = \"dynamics.B[1][1]\"\nvalues = [0.5, 2.0]\n"
            ),
            Syntax::Toml,
        ),
    ]
}

/// The base of the general seeds: the paper's §4 one-link problem in general form (theory §11)
/// with its bang-bang `[input]`.
const GENERAL: &str = "[model.sweeping_process]\nnormals = [[1.0], [-1.0]]\noffsets = [1.0, 1.0]\n\
    [model.dynamics]\nB = [[1.0]]\n[model.control]\nlower = [-1.0]\nupper = [1.0]\n\
    [model.objective]\nface_weights = [0.5, 0.5]\n[model.problem]\nperiod = 10.0\n\
    [model.input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 5.0]\nvalues = [[1.0], [-1.0]]\n";

/// An edit aimed at a sweep's own mistakes, applied to the text after the mutation.
#[derive(Debug, Clone)]
enum SweepEdit {
    /// Nothing more.
    None,
    /// A further axis naming an axis's field in another spelling (`at` picks it).
    Duplicate { spelling: u8 },
    /// A whole list beside one of its entries.
    Overlap { indexed_first: bool },
    /// Spaces inside the first field.
    Spaces { spelling: u8 },
    /// `count` points on one axis, or zipped on two (around the point limit).
    Size { zip: bool, count: u8 },
    /// A setting with an extreme or out-of-range value.
    Setting { key: u8, value: u8 },
}

fn edit_strategy() -> impl Strategy<Value = SweepEdit> {
    prop_oneof![
        3 => Just(SweepEdit::None),
        2 => any::<u8>().prop_map(|spelling| SweepEdit::Duplicate { spelling }),
        1 => any::<bool>().prop_map(|indexed_first| SweepEdit::Overlap { indexed_first }),
        1 => any::<u8>().prop_map(|spelling| SweepEdit::Spaces { spelling }),
        1 => (any::<bool>(), any::<u8>()).prop_map(|(zip, count)| SweepEdit::Size { zip, count }),
        2 => (any::<u8>(), any::<u8>()).prop_map(|(key, value)| SweepEdit::Setting { key, value }),
    ]
}

/// Spellings of `gait.period`-like fields: the same field written otherwise.
fn respell(field: &str, k: u8) -> String {
    let (path, index) = match field.split_once('[') {
        Some((p, i)) => (p.to_string(), Some(i.trim_end_matches(']').to_string())),
        None => (field.to_string(), None),
    };
    let path = match k % 4 {
        0 => format!("{path} "),
        1 => format!(" {path}"),
        2 => path.replace('.', " . "),
        _ => format!("\t{path}\t"),
    };
    match index {
        Some(i) => match (k / 4) % 3 {
            0 => format!("{path}[ {i} ]"),
            1 => format!("{path}[+{i}]"),
            _ => format!("{path}[0{i}] "),
        },
        None => path,
    }
}

const SETTING_KEYS: &[&str] = &[
    "m",
    "phases",
    "max_phases",
    "patience",
    "shifts",
    "time_limit",
    "steps_per_period",
    "max_periods",
    "tol",
    "accelerate_after",
    "method",
];

const SETTING_VALUES: &[&str] = &[
    "0",
    "-1",
    "1",
    "4294967295",
    "18446744073709551615",
    "1e300",
    "-1e-300",
    "nan",
    "inf",
    "0.5",
    "65",
    "17",
    "\"discrete\"",
    "\"local\"",
    "\"\"",
];

/// The text of a sweep after `edit`.
fn apply(text: &str, edit: &SweepEdit) -> String {
    let first_field = text
        .lines()
        .find_map(|l| l.strip_prefix("field = \""))
        .and_then(|l| l.strip_suffix('"'))
        .unwrap_or("gait.period")
        .to_string();
    match edit {
        SweepEdit::None => text.to_string(),
        SweepEdit::Duplicate { spelling } => format!(
            "{text}\n[[axis]]\nfield = {:?}\nvalues = [20.0]\n",
            respell(&first_field, *spelling)
        ),
        SweepEdit::Overlap { indexed_first } => {
            let (a, b) = if *indexed_first {
                ("crawler.mu_backward[2]", "crawler.mu_backward")
            } else {
                ("crawler.mu_backward", "crawler.mu_backward[ 1 ]")
            };
            format!(
                "{text}\n[[axis]]\nfield = \"{a}\"\nvalues = [2.5]\n\
                 [[axis]]\nfield = \"{b}\"\nvalues = [3.0]\n"
            )
        }
        SweepEdit::Spaces { spelling } => text.replacen(
            &format!("field = \"{first_field}\""),
            &format!("field = {:?}", respell(&first_field, *spelling)),
            1,
        ),
        SweepEdit::Size { zip, count } => {
            // Around the limit (refused before any point runs) or small.
            let n = match count % 4 {
                0 => MAX_POINTS + 1,
                1 => MAX_POINTS * 3,
                2 => usize::MAX / 2,
                _ => 3,
            };
            let combine = if *zip { "combine = \"zip\"\n" } else { "" };
            let axes = if *zip {
                format!(
                    "[[axis]]\nfield = \"gait.period\"\nrange = {{ from = 5, to = 9, count = {n} }}\n\
                     [[axis]]\nfield = \"crawler.stiffness\"\nrange = {{ from = 1, to = 2, count = {n} }}\n"
                )
            } else {
                format!(
                    "[[axis]]\nfield = \"gait.period\"\nrange = {{ from = 5, to = 9, count = {n} }}\n\
                     [[axis]]\nfield = \"crawler.stiffness\"\nvalues = [1.0, 2.0]\n"
                )
            };
            format!("{combine}job = \"analyze\"\n{MODEL}\n{axes}")
        }
        SweepEdit::Setting { key, value } => {
            let key = SETTING_KEYS[*key as usize % SETTING_KEYS.len()];
            let value = SETTING_VALUES[*value as usize % SETTING_VALUES.len()];
            let line = format!("{key} = {value}");
            if text.contains("[settings]") {
                // Replace the key if the seed has it, else add it.
                let mut out: Vec<String> = Vec::new();
                let mut done = false;
                for l in text.lines() {
                    if l.starts_with(&format!("{key} =")) && !done {
                        out.push(line.clone());
                        done = true;
                    } else {
                        out.push(l.to_string());
                    }
                }
                let mut t = out.join("\n");
                if !done {
                    t = t.replacen("[settings]", &format!("[settings]\n{line}"), 1);
                }
                t
            } else {
                format!("{text}\n[settings]\n{line}\n")
            }
        }
    }
}

/// An accepted sweep's axes, checked for meaning: each column names the number it sets, and
/// no two set the same number (a field twice, or a whole list and one of its entries).
fn meaningless(spec: &SweepSpec) -> Option<String> {
    let parsed: Vec<(String, Option<String>)> = spec
        .axes
        .iter()
        .map(|a| match a.field.split_once('[') {
            Some((p, i)) => (p.to_string(), Some(i.to_string())),
            None => (a.field.clone(), None),
        })
        .collect();
    for (i, a) in parsed.iter().enumerate() {
        if a.0.contains(char::is_whitespace) || a.1.as_deref().is_some_and(|s| s.contains(' ')) {
            return Some(format!(
                "column {:?} is not the field as meant",
                spec.axes[i].field
            ));
        }
        for b in &parsed[..i] {
            if a.0 == b.0 && (a.1 == b.1 || a.1.is_none() || b.1.is_none()) {
                return Some(format!("two axes set one number: {:?} and {:?}", b, a));
            }
        }
    }
    None
}

/// A table printed by a sweep that exited 0: one row per point, none refused for a setting.
fn table_meaningless(stdout: &str, points: usize) -> Option<String> {
    let mut r = csv::ReaderBuilder::new().from_reader(stdout.as_bytes());
    let header: Vec<String> = r.headers().ok()?.iter().map(str::to_string).collect();
    let error = header.iter().position(|c| c == "error")?;
    let mut rows = 0;
    for rec in r.records() {
        let rec = rec.ok()?;
        rows += 1;
        if rec.get(error).is_some_and(|e| e.starts_with("settings.")) {
            return Some(format!("a row refused for a setting: {}", &rec[error]));
        }
    }
    (rows != points).then(|| format!("{rows} rows for {points} points"))
}

/// Sweep files: every mutation and edit through the parser (and the first points' models)
/// in-process, and one case in two through `crawlopt sweep`.
#[test]
fn fuzz_sweep_files() {
    let seeds = seeds();
    let base = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz");
    std::fs::create_dir_all(&base).unwrap();
    let dir = tempfile::Builder::new()
        .prefix("sweep-")
        .tempdir_in(base)
        .unwrap();
    drive(
        "sweep",
        200,
        (
            0..seeds.len(),
            gentle_mutation_strategy(),
            edit_strategy(),
            any::<u8>(),
        ),
        |(i, m, edit, variant), stats| {
            let seed = &seeds[*i];
            // One case in four unmutated but for the sweep edit (to reach the runs).
            let text = if variant % 4 == 0 {
                seed.text.clone()
            } else {
                String::from_utf8_lossy(&seed.render(m)).into_owned()
            };
            let text = apply(&text, edit);
            let files: Files = vec![("sweep.toml".into(), text.clone().into_bytes())];
            let d = dir.path();
            std::fs::write(d.join("sweep.toml"), &text).unwrap();
            let parsed = text.clone();
            let steps = in_process(QUICK, move |s: &Steps| {
                let Some(spec) = s.step("SweepSpec::parse", || {
                    SweepSpec::parse(&parsed, Path::new("."))
                }) else {
                    return;
                };
                s.step("meaning", || match meaningless(&spec) {
                    Some(why) => panic!("accepted a meaningless sweep: {why}"),
                    None => Ok::<_, String>(()),
                });
                for id in 0..spec.len().unwrap_or(0).min(3) {
                    s.step("SweepSpec::problem_at", || spec.problem_at(&spec.point(id)));
                }
            });
            let mut failure = judge_steps("in-process", &steps, stats);
            if failure.is_none() && variant % 2 == 0 {
                let r = run_bin(d, &["sweep", "sweep.toml", "-j", "2"], QUICK);
                failure = judge_bin("sweep", &r, &[], stats);
                if failure.is_none() && r.outcome == Outcome::Exit(0) {
                    let points = SweepSpec::parse(&text, Path::new("."))
                        .ok()
                        .and_then(|s| s.len().ok());
                    let why = match points {
                        Some(n) => table_meaningless(&r.stdout, n),
                        None => Some("exit 0 on a file the library refuses".into()),
                    };
                    failure = why.map(|why| Failure {
                        signature: format!("sweep: exit 0 but {why}"),
                        detail: format!("command: {}\nstderr:\n{}", r.command(), r.stderr),
                    });
                }
            }
            (files, failure)
        },
    );
}

/// The edits do what they say: a duplicate in another spelling, and a setting out of range,
/// are refused by the parser.
#[test]
fn sweep_edits_render_what_they_say() {
    let seeds = seeds();
    for s in &seeds {
        assert!(
            SweepSpec::parse(&s.text, Path::new(".")).is_ok(),
            "{}",
            s.name
        );
    }
    for k in 0..12u8 {
        let t = apply(&seeds[0].text, &SweepEdit::Duplicate { spelling: k });
        let e = SweepSpec::parse(&t, Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(e.contains("is already axis[1]"), "{k}: {e}");
    }
    let t = apply(&seeds[2].text, &SweepEdit::Setting { key: 6, value: 0 });
    assert!(t.contains("steps_per_period = 0"), "{t}");
    let e = SweepSpec::parse(&t, Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("settings.steps_per_period"), "{e}");
    assert_eq!(
        respell("crawler.mu_forward[1]", 4),
        "crawler.mu_forward [+1]"
    );
}
