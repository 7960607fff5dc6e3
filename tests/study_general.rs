//! Parameter studies over a general problem (P) (`crawlopt::study` with a `[sweeping_process]`
//! base, theory §11): axes over the period, a face's offset, a matrix entry and the cost
//! against the closed form of the paper's §4 one-link problem in general form; every row
//! against a direct `crawlopt optimize` of the same point; bad axes and settings refused
//! naming them; resume, shards and figures through the binary.

use crawlopt::study::{self, Kind, Row, SweepSettings, SweepSpec};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

const BIN: &str = env!("CARGO_BIN_EXE_crawlopt");

/// The paper's §4 one-link problem in general form (examples/general_one_link.toml): C =
/// [-c_2, c_1] = [-1, 1], g = u, U = [-1, 1] with zero mean, f1 = |eta| / 2, T = 10; the
/// `[input]` is the optimal bang-bang control.
const ONE_LINK: &str = r#"
[sweeping_process]
normals = [[1.0], [-1.0]]
offsets = [1.0, 1.0]
[dynamics]
B = [[1.0]]
[control]
lower = [-1.0]
upper = [1.0]
[objective]
face_weights = [0.5, 0.5]
[problem]
period = 10.0
[input]
kind = "piecewise_constant"
times = [0.0, 5.0]
values = [[1.0], [-1.0]]
"#;

/// The one-link problem's optimum J* = max(0, (beta T - 2 w) / 2) for C of width w and
/// g = beta u, |u| <= 1 (theory §10: slide on each face for what is left of each half period
/// after crossing C at speed beta).
fn one_link_optimum(period: f64, width: f64, beta: f64) -> f64 {
    ((beta * period - 2.0 * width) / 2.0).max(0.0)
}

/// A sweep over the one-link base (inline) with `job`, `settings` and `axes` (TOML text).
fn sweep_text(job: &str, settings: &str, axes: &str) -> String {
    let model = ONE_LINK
        .replace("[sweeping_process]", "[model.sweeping_process]")
        .replace("[dynamics]", "[model.dynamics]")
        .replace("[control]", "[model.control]")
        .replace("[objective]", "[model.objective]")
        .replace("[problem]", "[model.problem]")
        .replace("[input]", "[model.input]");
    format!("job = \"{job}\"\n[settings]\n{settings}\n{model}\n{axes}")
}

fn spec(text: &str) -> SweepSpec {
    SweepSpec::parse(text, Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn refused(text: &str) -> String {
    SweepSpec::parse(text, Path::new("."))
        .expect_err("refused")
        .to_string()
}

fn run_all(spec: &SweepSpec) -> Vec<Row> {
    let rows = Mutex::new(Vec::new());
    let settings = SweepSettings {
        threads: 2,
        ..Default::default()
    };
    study::run(spec, &settings, &|o, _| rows.lock().unwrap().push(o.row)).expect("runs");
    let mut rows = rows.into_inner().unwrap();
    rows.sort_by_key(|r| r.point);
    rows
}

fn ok(row: &Row) -> &Row {
    assert!(row.error.is_none(), "point {}: {:?}", row.point, row.error);
    row
}

#[test]
fn a_period_axis_gives_the_closed_form_with_what_is_proven() {
    let s = spec(&sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"problem.period\"\nvalues = [2.0, 3.0, 4.0, 6.0, 8.0, 10.0, 12.0]\n",
    ));
    assert_eq!(s.kind, Kind::General);
    assert_eq!(study::header(&s)[1], "problem.period");
    let rows = run_all(&s);
    assert_eq!(rows.len(), 7);
    for r in &rows {
        let t = r.values[0];
        let want = one_link_optimum(t, 2.0, 1.0);
        let j = ok(r).objective.expect("an objective");
        assert!((j - want).abs() < 1e-7, "T = {t}: J = {j}, J* = {want}");
        // P_m globally (the default method of a general problem): a proven optimum.
        assert_eq!(r.method.as_deref(), Some("discrete"));
        assert_eq!(r.certificate.as_deref(), Some("global"));
        assert_eq!(r.status, "optimal");
        let bound = r.bound.expect("a bound");
        assert!(
            bound >= j - 1e-9 && bound <= want + 1e-6,
            "T = {t}: {bound}"
        );
        assert!(r.displacement_per_period.is_none() && r.verdict.is_none());
    }
}

#[test]
fn offset_matrix_and_cost_axes_give_the_closed_form() {
    // c_2 moves the face x >= -c_2: width 1 + c_2; the whole list sets both offsets: 2 c.
    let s = spec(&sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"sweeping_process.offsets[2]\"\nvalues = [0.5, 1.0, 2.0, 3.0]\n",
    ));
    for r in run_all(&s) {
        let want = one_link_optimum(10.0, 1.0 + r.values[0], 1.0);
        let j = ok(&r).objective.unwrap();
        assert!(
            (j - want).abs() < 1e-7,
            "c_2 = {}: {j} vs {want}",
            r.values[0]
        );
    }
    let s = spec(&sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"sweeping_process.offsets\"\nvalues = [0.5, 1.0, 2.0]\n",
    ));
    for r in run_all(&s) {
        let want = one_link_optimum(10.0, 2.0 * r.values[0], 1.0);
        assert!((ok(&r).objective.unwrap() - want).abs() < 1e-7, "{r:?}");
    }
    // g = beta u: B's entry is the speed.
    let s = spec(&sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"dynamics.B[1][1]\"\nvalues = [0.5, 1.0, 2.0]\n",
    ));
    for r in run_all(&s) {
        let want = one_link_optimum(10.0, 2.0, r.values[0]);
        assert!((ok(&r).objective.unwrap() - want).abs() < 1e-7, "{r:?}");
    }
    // U = [-1, beta] with zero mean: up at beta for T/(1 + beta), down at 1 for the rest, so
    // the travel is 2 beta T/(1 + beta) and J* = beta T/(1 + beta) - w (both switches on
    // P_3's grid for these beta).
    let s = spec(&sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"control.upper[1]\"\nvalues = [0.3333333333333333, 1.0, 3.0]\n",
    ));
    for r in run_all(&s) {
        let b = r.values[0];
        let want = b * 10.0 / (1.0 + b) - 2.0;
        assert!((ok(&r).objective.unwrap() - want).abs() < 1e-7, "{r:?}");
    }
    // f1 = q eta_1 + eta_2 / 2: the reaction on each face is T/2 - w at best (zero mean
    // balances the travel both ways), so J* = (q + 1/2)(T/2 - w).
    let s = spec(&sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"objective.face_weights[1]\"\nvalues = [0.0, 0.5, 2.0]\n",
    ));
    for r in run_all(&s) {
        let want = (r.values[0] + 0.5) * 3.0;
        assert!((ok(&r).objective.unwrap() - want).abs() < 1e-7, "{r:?}");
    }
    // f2 = (c/2) u^2, T = 40: the speed v* = min(1, 1/(2c)) and J* = v T/2 - w - c v^2 T/2
    // (tests/general_pm.rs: J* = 3 for c = 1).
    let text = sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"objective.cost.weight\"\nvalues = [0.25, 0.5, 1.0, 2.0]\n",
    )
    .replace("period = 10.0", "period = 40.0")
    .replace(
        "face_weights = [0.5, 0.5]",
        "face_weights = [0.5, 0.5]\ncost = { kind = \"quadratic\", weight = 1.0 }",
    );
    for r in run_all(&spec(&text)) {
        let c = r.values[0];
        let v = (1.0 / (2.0 * c)).min(1.0);
        let want = v * 20.0 - 2.0 - c * v * v * 20.0;
        let j = ok(&r).objective.unwrap();
        assert!((j - want).abs() < 1e-5, "c = {c}: {j} vs {want}");
    }
}

#[test]
fn a_simulate_job_plays_the_input_on_each_point() {
    // The bang-bang input on C of width 1 + c_2: J = (T - 2 w) / 2, exactly (A = 0).
    let s = spec(&sweep_text(
        "simulate",
        "",
        "[[axis]]\nfield = \"sweeping_process.offsets[2]\"\nvalues = [0.5, 1.0, 2.0, 3.0]\n",
    ));
    for r in run_all(&s) {
        let want = one_link_optimum(10.0, 1.0 + r.values[0], 1.0);
        let j = ok(&r).objective.unwrap();
        assert!(
            (j - want).abs() < 1e-9,
            "c_2 = {}: {j} vs {want}",
            r.values[0]
        );
        assert_eq!(r.method.as_deref(), Some("exact"));
        assert_eq!(r.status, "converged");
    }
    // Analyze: a point whose C is empty (c_1 + c_2 < 0) is its row's error, naming the field.
    let s = spec(&sweep_text(
        "analyze",
        "",
        "[[axis]]\nfield = \"sweeping_process.offsets[1]\"\nvalues = [1.0, -2.0]\n",
    ));
    let rows = run_all(&s);
    assert_eq!(ok(&rows[0]).status, "well_posed");
    assert_eq!(rows[1].status, "error");
    let e = rows[1].error.as_deref().unwrap();
    assert!(e.starts_with("sweeping_process"), "{e}");
}

#[test]
fn bad_axes_and_settings_are_refused_naming_them() {
    let axis = |field: &str, values: &str| {
        sweep_text(
            "optimize",
            "",
            &format!("[[axis]]\nfield = \"{field}\"\nvalues = {values}\n"),
        )
    };
    for (text, field, says) in [
        (
            axis("problem.periods", "[1.0]"),
            "axis[1].field",
            "problem.period",
        ),
        (
            axis("gait.period", "[1.0]"),
            "axis[1].field",
            "general problem",
        ),
        (
            axis("sweeping_process.offsets[3]", "[1.0]"),
            "axis[1].field",
            "entry 3 does not exist",
        ),
        (
            axis("dynamics.A[1]", "[1.0]"),
            "axis[1].field",
            "is a matrix",
        ),
        (axis("dynamics.B[2][1]", "[1.0]"), "axis[1].field", "row 2"),
        (
            axis("problem.period[1]", "[1.0]"),
            "axis[1].field",
            "no index",
        ),
        (
            axis("control.lower[1][1]", "[1.0]"),
            "axis[1].field",
            "one index",
        ),
        (
            axis("objective.reaction_weights[1]", "[1.0]"),
            "axis[1].field",
            "no objective.reaction_weights",
        ),
        (
            axis("objective.cost.weight", "[1.0]"),
            "axis[1].field",
            "no table cost",
        ),
        (
            axis("problem.period", "[10.0, 0.0]"),
            "axis[1].values",
            "positive",
        ),
        (
            axis("problem.period", "[10.0, nan]"),
            "axis[1].values",
            "finite",
        ),
        (
            sweep_text(
                "optimize",
                "phases = 3",
                "[[axis]]\nfield = \"problem.period\"\nvalues = [10.0]\n",
            ),
            "settings.phases",
            "general problem",
        ),
        (
            sweep_text(
                "optimize",
                "m = 11",
                "[[axis]]\nfield = \"problem.period\"\nvalues = [10.0]\n",
            ),
            "settings.m",
            "1..=10",
        ),
        (
            sweep_text(
                "simulate",
                "accelerate_after = 3",
                "[[axis]]\nfield = \"problem.period\"\nvalues = [10.0]\n",
            ),
            "settings.accelerate_after",
            "general problem",
        ),
    ] {
        let e = refused(&text);
        assert!(e.starts_with(&format!("{field}: ")), "{field}: {e}");
        assert!(e.contains(says), "{says}: {e}");
    }
    // One entry in two spellings; a whole list and one of its entries.
    let two = |a: &str, b: &str| {
        sweep_text(
            "optimize",
            "",
            &format!(
                "[[axis]]\nfield = \"{a}\"\nvalues = [1.0]\n[[axis]]\nfield = \"{b}\"\nvalues = [2.0]\n"
            ),
        )
    };
    let e = refused(&two("dynamics.B[1][1]", " dynamics.B[ 1 ][ 1 ]"));
    assert!(
        e.starts_with("axis[2].field: ") && e.contains("is already axis[1]"),
        "{e}"
    );
    let e = refused(&two(
        "sweeping_process.offsets",
        "sweeping_process.offsets[1]",
    ));
    assert!(
        e.starts_with("axis[2].field: ") && e.contains("overlaps"),
        "{e}"
    );
    // Simulate plays the base's [input]: a base without one is refused.
    let text = sweep_text(
        "simulate",
        "",
        "[[axis]]\nfield = \"problem.period\"\nvalues = [10.0]\n",
    );
    let cut = text.find("[model.input]").unwrap();
    let e = refused(&format!("{}{}", &text[..cut], &text[cut..].replacen("[model.input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 5.0]\nvalues = [[1.0], [-1.0]]\n", "", 1)));
    assert!(e.starts_with("base: ") && e.contains("[input]"), "{e}");
}

fn crawlopt(args: &[&str]) -> std::process::Output {
    Command::new(BIN).args(args).output().expect("runs")
}

/// A sweep file over a base problem file beside it: the period and the offset c_2.
fn sweep_files(dir: &Path, settings: &str) -> PathBuf {
    std::fs::write(dir.join("one_link.toml"), ONE_LINK).unwrap();
    let sweep = dir.join("grid.toml");
    std::fs::write(
        &sweep,
        format!(
            "base = \"one_link.toml\"\njob = \"optimize\"\n[settings]\n{settings}\n\
             [[axis]]\nfield = \"problem.period\"\nvalues = [3.0, 6.0, 10.0]\n\
             [[axis]]\nfield = \"sweeping_process.offsets[2]\"\nvalues = [0.5, 1.0, 2.0, 3.0]\n"
        ),
    )
    .unwrap();
    sweep
}

/// The data lines of a CSV table sorted by point, without the `seconds` column (wall time).
fn table(path: &Path) -> Vec<String> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let sec = r
        .headers()
        .unwrap()
        .iter()
        .position(|c| c == "seconds")
        .unwrap();
    let mut rows: Vec<(usize, String)> = r
        .records()
        .map(|rec| {
            let mut c: Vec<String> = rec.unwrap().iter().map(str::to_string).collect();
            c.remove(sec);
            (c[0].parse().unwrap(), c.join("|"))
        })
        .collect();
    rows.sort();
    rows.into_iter().map(|(_, l)| l).collect()
}

#[test]
fn every_row_equals_a_direct_optimize_of_its_point() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_files(dir.path(), "certify = true");
    let s = SweepSpec::load(&sweep).unwrap();
    let rows = run_all(&s);
    assert_eq!(rows.len(), 12);
    for r in &rows {
        let (t, c2) = (r.values[0], r.values[1]);
        // The point's file written by hand (not by the sweep's setter), optimised by the
        // command.
        let text = ONE_LINK
            .replace("period = 10.0", &format!("period = {t:?}"))
            .replace("offsets = [1.0, 1.0]", &format!("offsets = [1.0, {c2:?}]"));
        let file = dir.path().join(format!("point-{}.toml", r.point));
        std::fs::write(&file, text).unwrap();
        let out = crawlopt(&["optimize", file.to_str().unwrap(), "--certify", "--json"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(
            ok(r).objective,
            v["objective"].as_f64(),
            "point {}",
            r.point
        );
        assert_eq!(Some(r.status.as_str()), v["status"].as_str());
        assert_eq!(r.bound, v["certificate"]["bound"].as_f64());
        assert_eq!(r.method.as_deref(), v["method"].as_str());
        assert_eq!(
            r.verdict.as_deref(),
            v["necessary_conditions"]["verdict"].as_str(),
            "point {}",
            r.point
        );
        assert!(r.verdict.is_some());
        let want = one_link_optimum(t, 1.0 + c2, 1.0);
        assert!((r.objective.unwrap() - want).abs() < 1e-7, "{r:?}");
    }
}

#[test]
fn resumed_and_sharded_runs_give_the_table_of_one_run_and_it_plots() {
    let dir = tempfile::tempdir().unwrap();
    let sweep = sweep_files(dir.path(), "");
    let f = sweep.to_str().unwrap();
    let whole = dir.path().join("whole.csv");
    let out = crawlopt(&["sweep", f, "-j", "2", "-o", whole.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let full = table(&whole);
    assert_eq!(full.len(), 12);
    assert!(
        full.iter().all(|l| l.contains("|discrete|global|")),
        "{full:?}"
    );

    // A run interrupted after 5 rows, in the middle of writing the sixth.
    let text = std::fs::read_to_string(&whole).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let part = dir.path().join("part.csv");
    std::fs::write(
        &part,
        format!("{}\n{}", lines[..6].join("\n"), &lines[6][..4]),
    )
    .unwrap();
    let out = crawlopt(&["sweep", f, "-o", part.to_str().unwrap(), "--resume"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("7 computed (0 with an error), 5 already done"),
        "{said}"
    );
    assert_eq!(table(&part), full);

    // Shards joined.
    let shards: Vec<String> = (1..=2)
        .map(|i| {
            let p = dir.path().join(format!("shard-{i}.csv"));
            let out = crawlopt(&[
                "sweep",
                f,
                "--shard",
                &format!("{i}/2"),
                "-o",
                p.to_str().unwrap(),
            ]);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            p.to_str().unwrap().to_string()
        })
        .collect();
    let merged = dir.path().join("merged.csv");
    let out = crawlopt(&[
        "sweep",
        "merge",
        f,
        "--shards",
        "2",
        "-o",
        merged.to_str().unwrap(),
        &shards[0],
        &shards[1],
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(table(&merged), full);

    // The figures of the table: J against c_2 (a line per period) and the heat map.
    let figs = dir.path().join("figs");
    let out = crawlopt(&[
        "plot",
        whole.to_str().unwrap(),
        "-o",
        figs.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let svgs = std::fs::read_dir(&figs)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "svg")
        })
        .count();
    assert_eq!(svgs, 2);
    let (axes, rows) = study::read_any_table(&whole).unwrap();
    assert_eq!(axes, ["problem.period", "sweeping_process.offsets[2]"]);
    let figures = study::figures(&axes, &rows).unwrap();
    assert_eq!(figures.len(), 2);
}

#[test]
fn a_matrix_entry_sets_its_place_and_r_stays_symmetric() {
    // Two controls, f2 = (1/2) u^T R u: an entry of R sets its mirror too (R is symmetric);
    // an omitted A is 0 with the entry set.
    let text = sweep_text(
        "optimize",
        "",
        "[[axis]]\nfield = \"objective.cost.matrix[1][2]\"\nvalues = [0.25]\n\
         [[axis]]\nfield = \"dynamics.A[1][1]\"\nvalues = [-0.5]\n",
    )
    .replace("B = [[1.0]]", "B = [[1.0, 0.5]]")
    .replace("lower = [-1.0]", "lower = [-1.0, -1.0]")
    .replace("upper = [1.0]", "upper = [1.0, 1.0]")
    .replace(
        "face_weights = [0.5, 0.5]",
        "face_weights = [0.5, 0.5]\ncost = { kind = \"matrix\", matrix = [[1.0, 0.0], [0.0, 1.0]] }",
    )
    .replace("values = [[1.0], [-1.0]]", "values = [[1.0, 0.0], [-1.0, 0.0]]");
    let s = spec(&text);
    let f = s.general_at(&s.point(0)).unwrap();
    let cost = f.objective.cost.as_ref().unwrap();
    assert_eq!(
        cost.matrix.as_deref(),
        Some(&[vec![1.0, 0.25], vec![0.25, 1.0]][..])
    );
    assert_eq!(f.dynamics.a, Some(vec![vec![-0.5]]));
    f.problem().expect("a well-posed problem");
    let e = refused(&text.replace("dynamics.A[1][1]", "objective.cost.matrix[2][1]"));
    assert!(
        e.starts_with("axis[2].field: ") && e.contains("is already axis[1]"),
        "{e}"
    );
}
