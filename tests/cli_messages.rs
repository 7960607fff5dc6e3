//! What the command line says: messages that name the flag or field and say why (negative flag
//! values, extreme friction in the uniqueness condition, a result file's version of the wrong
//! type, no note before an error, what every method says when its time limit is spent at once),
//! and text output at a readable precision while `--json` keeps every digit.

use crawlopt::optimal::GaitResult;
use crawlopt::present::text::num;
use std::path::Path;
use std::process::Output;

mod common;
use common::{crawlopt, write};

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts exit 2, a first line `error: ...` containing every one of `want`, and no note.
fn assert_refused(out: &Output, want: &[&str]) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    let first = err.lines().next().unwrap_or_default();
    assert!(first.starts_with("error: "), "{err}");
    for w in want {
        assert!(first.contains(w), "want {w:?} in {first:?}");
    }
    assert!(!err.contains("note:"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// The numbers in `text` (maximal runs of digits and dots; an exponent's digits are a number of
/// their own) with more than `max` significant digits.
fn long_numbers(text: &str, max: usize) -> Vec<String> {
    let mut found = Vec::new();
    let mut run = String::new();
    for c in text.chars().chain(std::iter::once(' ')) {
        if c.is_ascii_digit() || c == '.' {
            run.push(c);
            continue;
        }
        let digits: String = run.chars().filter(char::is_ascii_digit).collect();
        let significant = digits.trim_start_matches('0').len();
        if significant > max {
            found.push(run.clone());
        }
        run.clear();
    }
    found
}

#[test]
fn the_number_scanner_finds_long_numbers() {
    let text = "u = [1.0000000000005613, -1] e = 0.0000000000001443115198287173 ok 1.914213562 \
                1e-300 t = [0, 2.5]";
    assert_eq!(
        long_numbers(text, 12),
        ["1.0000000000005613", "0.0000000000001443115198287173"]
    );
}

#[test]
fn negative_flag_values_name_the_flag() {
    let gait = "examples/one_link_gait.toml";
    for (args, want) in [
        (
            &["optimize", gait, "--m", "-1"][..],
            &["invalid value '-1' for '--m <M>'", "must not be negative"][..],
        ),
        (
            &["optimize", gait, "--phases", "-1"],
            &[
                "invalid value '-1' for '--phases <PHASES>'",
                "must not be negative",
            ],
        ),
        (
            &["optimize", gait, "--method", "local", "--shifts", "-3"],
            &["'--shifts <SHIFTS>'", "must not be negative"],
        ),
        (
            &["optimize", gait, "--max-phases", "-2"],
            &["'--max-phases <MAX_PHASES>'"],
        ),
        (
            &["optimize", gait, "--m", "1.5"],
            &["'--m <M>'", "not a whole number"],
        ),
        (
            &["optimize", gait, "--time-limit", "-1"],
            &["--time-limit: must be positive and finite (got -1)"],
        ),
        (
            &[
                "optimize",
                gait,
                "--method",
                "discrete",
                "--time-limit",
                "-1e-3",
            ],
            &["--time-limit: must be positive and finite (got -0.001)"],
        ),
        (
            &["optimize", gait, "--time-limit", "-inf"],
            &["--time-limit: must be positive and finite (got -inf)"],
        ),
        (
            &["report", gait, "--time-limit", "-1", "-o", "never.html"],
            &["--time-limit: must be positive and finite"],
        ),
        (
            &["report", gait, "--phases", "-1", "-o", "never.html"],
            &["'--phases <PHASES>'", "must not be negative"],
        ),
        (
            &[
                "simulate",
                "examples/three_blocks_sine.toml",
                "--periods",
                "-1",
            ],
            &["'--periods <PERIODS>'", "must not be negative"],
        ),
        (
            &["simulate", "examples/three_blocks_sine.toml", "--tol", "-1"],
            &["tol: must be in (0, 1e-3]", "(got -1)"],
        ),
        // Issue 30, item 5: a tolerance that takes the first period of a transient for the
        // orbit (J = 1.833 against 1.914) is refused, not answered.
        (
            &[
                "simulate",
                "examples/three_blocks_sine.toml",
                "--tol",
                "0.5",
            ],
            &["tol: must be in (0, 1e-3]", "(got 0.5)"],
        ),
        (
            &[
                "simulate",
                "examples/three_blocks_sine.toml",
                "--tol",
                "1e300",
            ],
            &["tol: must be in (0, 1e-3]"],
        ),
        (
            &["bench", "--blocks", "3,-4", "--steps", "10"],
            &["invalid value '-4' for '--blocks <BLOCKS>'"],
        ),
        (
            &["bench", "--steps", "-10"],
            &["'--steps <STEPS>'", "must not be negative"],
        ),
    ] {
        let out = crawlopt(args);
        assert_refused(&out, want);
        assert!(
            !stderr(&out).contains("unexpected argument"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
    assert!(!Path::new("never.html").exists());
}

#[test]
fn negative_values_of_signed_flags_are_values() {
    let out = crawlopt(&[
        "bench",
        "--blocks",
        "3",
        "--steps",
        "20",
        "--min-time",
        "0.001",
        "--phase-deg",
        "-90",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).contains("sin(2 pi t - l -90 deg)"));
}

/// A three-block model file with these friction thresholds and a sine actuation.
fn crawler(mu_forward: &str, mu_backward: &str) -> String {
    format!(
        "[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = {mu_forward}\nmu_backward = {mu_backward}\n\
         [actuation]\nkind = \"sine\"\nperiod = 1\namplitude = 1\n"
    )
}

#[test]
fn the_uniqueness_message_is_consistent_at_extreme_friction() {
    let dir = tempfile::tempdir().unwrap();
    // A true violation at an extreme scale: J = {1, 2}, 1e300 + 1e300 = 2e300.
    let f = write(
        dir.path(),
        "v.toml",
        &crawler("[1e300, 1e300, 5e300]", "[9e300, 9e300, 2e300]"),
    );
    let out = crawlopt(&["analyze", f.to_str().unwrap()]);
    assert_refused(
        &out,
        &[
            "uniqueness condition (paper eq. 3.6) fails for blocks J = [1, 2]",
            "sum of mu_forward over J = 2e300 equals sum of mu_backward over the other blocks = 2e300",
        ],
    );
    assert!(stdout(&out).contains("FAILS for J = [1, 2]"));
    // ... and at a tiny one: J = {1, 2, 3} of five blocks, 3e-300 = 2 * 1.5e-300.
    let f = write(
        dir.path(),
        "t.toml",
        "[crawler]\nblocks = 5\nstiffness = 1\nmu_forward = 1e-300\nmu_backward = 1.5e-300\n",
    );
    let out = crawlopt(&["analyze", f.to_str().unwrap()]);
    assert_refused(
        &out,
        &[
            "J = [1, 2, 3]",
            "over J = 3e-300 equals",
            "other blocks = 3e-300 ",
        ],
    );
    // mu+ = 1e300 against mu- = 3 is no violation: J = {} compares 0 with 9. It is either
    // analysed or refused for its range, but never called non-unique, and no number is written
    // out in hundreds of digits.
    for (name, text) in [
        ("f.toml", crawler("1e300", "3")),
        ("b.toml", crawler("1", "1e-300")),
    ] {
        let f = write(dir.path(), name, &text);
        for cmd in ["analyze", "simulate"] {
            let out = crawlopt(&[cmd, f.to_str().unwrap()]);
            let all = format!("{}{}", stdout(&out), stderr(&out));
            assert!(!all.contains("FAILS"), "{name} {cmd}: {all}");
            assert!(!all.contains("-0 "), "{name} {cmd}: {all}");
            assert!(!all.contains("fails for blocks"), "{name} {cmd}: {all}");
            assert!(long_numbers(&all, 17).is_empty(), "{name} {cmd}: {all}");
            assert_ne!(out.status.code(), Some(101), "{name} {cmd}: {all}");
        }
    }
    // A subnormal threshold leaves the condition undecidable, and says why.
    let f = write(dir.path(), "s.toml", &crawler("[1, 1e-310, 1]", "2"));
    let out = crawlopt(&["analyze", f.to_str().unwrap()]);
    assert_refused(
        &out,
        &[
            "cannot be decided",
            "crawler.mu_forward[2] = 1e-310",
            "smallest normal double",
        ],
    );
}

#[test]
fn a_version_of_the_wrong_type_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mut v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for (version, want) in [
        (serde_json::json!("1"), r#"(got "1" (a string))"#),
        (serde_json::json!(5), "(got 5)"),
        (serde_json::json!(1.5), "(got 1.5)"),
        (serde_json::json!(null), "(got null)"),
        (serde_json::json!([1]), "(got [1] (an array))"),
        (serde_json::json!("x".repeat(100)), "xxx... (a string))"),
    ] {
        v["version"] = version;
        let f = write(dir.path(), "r.json", &v.to_string());
        let target = dir.path().join("out");
        let file = f.to_str().unwrap();
        for args in [
            vec!["certify", file],
            vec!["plot", file, "-o", target.to_str().unwrap()],
            vec!["report", file, "-o", target.to_str().unwrap()],
        ] {
            let out = crawlopt(&args);
            assert_refused(
                &out,
                &[
                    "r.json: version: this build reads versions 1, 2, 3 and 4 only",
                    want,
                ],
            );
            assert!(!target.exists());
        }
    }
    v.as_object_mut().unwrap().remove("version");
    let f = write(dir.path(), "r.json", &v.to_string());
    assert_refused(
        &crawlopt(&["certify", f.to_str().unwrap()]),
        &["version", "(got nothing)"],
    );
}

#[test]
fn no_note_precedes_an_error() {
    // A time limit too short for anything: the start gait cannot be had (which a note would
    // say, adding that the MILP goes on without it) and then the MILP finds nothing either.
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "discrete",
        "--time-limit",
        "1e-9",
    ]);
    assert_refused(&out, &["time limit"]);
    assert_eq!(stderr(&out).lines().count(), 1, "{}", stderr(&out));
    assert!(out.stdout.is_empty());
    // The other methods evaluate the structured gaits first: the limit spent, their best is the
    // answer (status time_limit, no gap), with neither an error nor a note.
    for method in ["local", "sequence", "phase"] {
        let out = crawlopt(&[
            "optimize",
            "examples/three_blocks_gait.toml",
            "--method",
            method,
            "--time-limit",
            "1e-9",
            "--json",
        ]);
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(stderr(&out).is_empty(), "{}", stderr(&out));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["status"], "time_limit");
        assert!(v["certificate"]["gap"].is_null());
        assert_eq!(
            v["structured"]["replaced"],
            "the time limit was spent on the structured gaits"
        );
    }
    // Bad options are refused before any solve, with no note either.
    for args in [
        &["--method", "discrete", "--time-limit", "0"][..],
        &["--method", "local", "--shifts", "0"],
        &["--method", "local", "--time-limit", "nan"],
        &["--method", "discrete", "--m", "0", "--time-limit", "5"],
    ] {
        let mut all = vec!["optimize", "examples/three_blocks_gait.toml"];
        all.extend_from_slice(args);
        let out = crawlopt(&all);
        assert_refused(&out, &[]);
        assert_eq!(
            stderr(&out).lines().count(),
            1,
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

#[test]
fn text_output_is_rounded_and_json_keeps_every_digit() {
    // optimize: J = 3 up to solver noise, shown as 3.
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--certify"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        long_numbers(&text, 12).is_empty(),
        "{:?}",
        long_numbers(&text, 12)
    );
    assert!(
        text.contains("objective J = 3 (displacement per period 3, actuation cost 0)"),
        "{text}"
    );
    assert!(
        text.contains("u = [-1]") && text.contains("u = [1]"),
        "{text}"
    );
    assert!(text.contains("0: t = [0, "), "{text}");
    assert!(!text.contains("-0,") && !text.contains("[-0]"), "{text}");
    // simulate: 1/2 + sqrt(2) rounded to 10 significant digits.
    let out = crawlopt(&["simulate", "examples/three_blocks_sine.toml"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        long_numbers(&text, 12).is_empty(),
        "{:?}",
        long_numbers(&text, 12)
    );
    assert!(
        text.contains("displacement per period: 1.914213562\n"),
        "{text}"
    );
    assert!(
        text.contains("state at the start of the periodic period: [-0.5, -1.5]"),
        "{text}"
    );
    // analyze and the discrete P_3 gait (controls with noise of 1e-16 in the solver's answer).
    for args in [
        &["analyze", "examples/three_blocks_gait.toml"][..],
        &[
            "optimize",
            "examples/three_blocks_gait.toml",
            "--method",
            "discrete",
        ],
    ] {
        let out = crawlopt(args);
        assert!(out.status.success(), "{}", stderr(&out));
        let text = stdout(&out);
        assert!(long_numbers(&text, 12).is_empty(), "{args:?}: {text}");
    }

    // --json: every digit, and a result that reads back as it was written.
    let out = crawlopt(&["simulate", "examples/three_blocks_sine.toml", "--json"]);
    let raw = stdout(&out);
    let v: serde_json::Value = serde_json::from_str(&raw).unwrap();
    let d = v["displacement_per_period"].as_f64().unwrap();
    assert!((d - (0.5 + 2f64.sqrt())).abs() < 1e-9);
    assert!(
        raw.contains(&format!("\"displacement_per_period\":{d}")),
        "the JSON number is the shortest exact form of the value"
    );
    assert!(!long_numbers(&raw, 15).is_empty(), "full precision in JSON");
    assert_eq!(num(d, 1.0), "1.914213562");

    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--json"]);
    let raw = stdout(&out);
    let v: serde_json::Value = serde_json::from_str(&raw).unwrap();
    let r = GaitResult::from_json(&raw, "r.json").unwrap();
    assert_eq!(serde_json::to_value(&r).unwrap(), v, "bit-exact round trip");
    assert_eq!(r.head.objective, v["objective"].as_f64().unwrap());
    let dir = tempfile::tempdir().unwrap();
    let f = write(dir.path(), "r.json", &raw);
    let out = crawlopt(&["certify", f.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = crawlopt(&[
        "report",
        f.to_str().unwrap(),
        "-o",
        dir.path().join("r.html").to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let line = stdout(&out);
    assert!(long_numbers(&line, 12).is_empty(), "{line}");
    assert!(
        line.contains(&format!("(objective J = {}, ", num(r.head.objective, 10.0))),
        "{line}"
    );
}

/// Issue 30, item 17: no negative zero in JSON output. P_1 of three blocks is idle and HiGHS
/// bounds it by zero up to its rounding (`-0.0` once, which the writer turns into `0.0`;
/// `1.8e-15` with (P)'s MILP on the crawler's instance, whose rows are scaled by
/// `sqrt(k_(b-1) + k_b)`; the writer itself is tested in `io::json`): the text has no `-0.0`
/// and the table's bound is zero to rounding.
#[test]
fn json_output_has_no_negative_zero() {
    let out = crawlopt(&[
        "optimize",
        "examples/three_blocks_gait.toml",
        "--method",
        "discrete",
        "--convergence",
        "--m",
        "2",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(!text.contains("-0.0,") && !text.contains("-0.0}"), "{text}");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let bound = v["convergence"][0]["bound"].as_f64().unwrap();
    assert!(bound.abs() <= 1e-12, "{bound}");
}

/// A limit spent before any method has a gait (1 ns: less than the structured gaits take),
/// through the job's deadline: every method but discrete returns the best structured gait with
/// status time_limit; the discrete P_m and its convergence table (no structured floor) end with
/// a time-limit error, never a panic.
#[test]
fn a_time_limit_spent_at_once_says_time_limit_for_every_method() {
    for method in [
        &["auto"][..],
        &["phase", "--phases", "4"],
        &["local"],
        &["sequence"],
        &["chain"],
    ] {
        let mut args = vec!["optimize", "examples/three_blocks_gait.toml", "--method"];
        args.extend(method);
        args.extend(["--time-limit", "1e-9", "--json"]);
        let out = crawlopt(&args);
        assert!(out.status.success(), "{method:?}: {}", stderr(&out));
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["status"], "time_limit", "{method:?}");
        assert!(v["structured"]["replaced"].is_string(), "{method:?}: {v}");
    }
    for extra in [&[][..], &["--convergence"]] {
        let mut args = vec![
            "optimize",
            "examples/three_blocks_gait.toml",
            "--method",
            "discrete",
        ];
        args.extend(extra);
        args.extend(["--time-limit", "1e-9"]);
        assert_refused(&crawlopt(&args), &["time limit was reached"]);
    }
}

/// Every refusal names the flag the user gave, or would give: the bound's own settings, a
/// given start of more slip phases than the sequence method's K, a fixed K of a general phase
/// MILP with a growth setting, and the computation's flags of `report` on a result file, whose
/// gait is computed already (nothing written).
#[test]
fn refusals_name_the_flag_to_change() {
    let dir = tempfile::tempdir().unwrap();
    let three = "examples/three_blocks_gait.toml";
    let general = "examples/general_three_blocks.toml";
    for (args, want) in [
        (
            &["optimize", three, "--bound", "--bound-time-limit", "-1"][..],
            "error: --bound-time-limit:",
        ),
        (
            &["optimize", general, "--bound", "--bound-resolution", "0"],
            "error: --bound-resolution:",
        ),
        (
            &[
                "optimize",
                "examples/general_one_link.toml",
                "--method",
                "phase",
                "--phases",
                "3",
                "--max-phases",
                "0",
            ],
            "error: --max-phases: applies only to a growth of K, without --phases",
        ),
    ] {
        assert_refused(&crawlopt(args), &[want]);
    }
    let four = common::optimize_json(three.as_ref(), &["--method", "phase", "--phases", "4"]);
    let start = write(dir.path(), "four.json", &four.to_string());
    let out = crawlopt(&[
        "optimize",
        three,
        "--method",
        "sequence",
        "--phases",
        "3",
        "--start",
        start.to_str().unwrap(),
    ]);
    assert_refused(
        &out,
        &["error: --start: has more slip phases than --phases = 3 (got 4 slip phases)"],
    );
    let html = dir.path().join("r.html");
    let out = crawlopt(&[
        "report",
        "examples/general_one_link.toml",
        "--phases",
        "3",
        "-o",
        html.to_str().unwrap(),
    ]);
    assert_refused(
        &out,
        &["error: --phases: applies to a crawler's model file only"],
    );
    assert!(!html.exists());
    let out = crawlopt(&["optimize", "examples/one_link_gait.toml", "--json"]);
    assert!(out.status.success());
    let result = write(dir.path(), "r.json", &String::from_utf8_lossy(&out.stdout));
    for flag in ["--phases", "--time-limit"] {
        let out = crawlopt(&[
            "report",
            result.to_str().unwrap(),
            flag,
            "3",
            "-o",
            html.to_str().unwrap(),
        ]);
        assert_refused(
            &out,
            &[&format!("error: {flag}: applies to a problem file only")],
        );
        assert!(!html.exists());
    }
}
