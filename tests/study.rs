//! Parameter studies (`crawlopt::study`): the sweep file, its points, the runs against the
//! one-link closed form of theory §9, shards, and the table read back.

use crawlopt::study::{
    self, header, merge, read_table, Format, Job, Row, Shard, SweepSettings, SweepSpec, TableWriter,
};
use std::path::Path;
use std::sync::Mutex;

fn spec(text: &str) -> SweepSpec {
    SweepSpec::parse(text, Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn err(text: &str) -> String {
    SweepSpec::parse(text, Path::new("."))
        .expect_err("an error")
        .to_string()
}

/// One link, k = a = 1, mu- = 2 on both blocks; axes mu+ (both blocks) and T.
const ONE_LINK: &str = r#"
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
values = [0.5, 1.0, 1.5, 2.0, 2.5]
[[axis]]
field = "gait.period"
range = { from = 2.0, to = 12.0, count = 6 }
"#;

/// theory §9 by hand for mu+ = p on both blocks, mu- = 2, k = a = 1: C = [max(-p, -2),
/// min(2, p)]; locomotion needs mu+ < mu- (both directions), then J* = max(0, (T - 2w)/2).
fn closed_form(p: f64, t: f64) -> f64 {
    if p < 2.0 {
        let w = p.min(2.0) - (-p).max(-2.0);
        ((t - 2.0 * w) / 2.0).max(0.0)
    } else {
        0.0
    }
}

fn run_all(spec: &SweepSpec, settings: &SweepSettings) -> Vec<Row> {
    let rows = Mutex::new(Vec::new());
    crawlopt::study::run(spec, settings, &|o, _| rows.lock().unwrap().push(o.row)).expect("runs");
    let mut rows = rows.into_inner().unwrap();
    rows.sort_by_key(|r| r.point);
    rows
}

#[test]
fn one_link_grid_matches_the_closed_form_and_ill_posed_points_are_error_rows() {
    let s = spec(ONE_LINK);
    assert_eq!(s.len().unwrap(), 30);
    let rows = run_all(
        &s,
        &SweepSettings {
            threads: 2,
            ..Default::default()
        },
    );
    assert_eq!(rows.len(), 30);
    let (mut zero, mut moving) = (0, 0);
    for (id, r) in rows.iter().enumerate() {
        assert_eq!(r.point, id);
        let (p, t) = (r.values[0], r.values[1]);
        // The product: the first axis varies slowest.
        assert_eq!(p, [0.5, 1.0, 1.5, 2.0, 2.5][id / 6]);
        assert_eq!(t, 2.0 + 2.0 * (id % 6) as f64);
        if p == 2.0 {
            // mu_1^+ = mu_2^- (J = {1}): the uniqueness condition fails on this line.
            let e = r.error.as_deref().expect("an error row");
            assert!(e.contains("uniqueness condition"), "{e}");
            assert_eq!(r.status, "error");
            assert_eq!(r.objective, None);
            continue;
        }
        assert_eq!(r.error, None, "point {id}");
        let j = r.objective.expect("J");
        let want = closed_form(p, t);
        assert!(
            (j - want).abs() <= 1e-9,
            "p = {p}, T = {t}: J = {j}, J* = {want}"
        );
        assert!((r.displacement_per_period.unwrap() - want).abs() <= 1e-9);
        assert_eq!(r.status, "optimal_among_k_phases");
        assert!(r.gap.unwrap() <= 1e-9);
        if want == 0.0 {
            zero += 1;
        } else {
            moving += 1;
        }
    }
    // Both sides of a T = 2w and the no-locomotion column mu+ > mu- are in the grid.
    assert!(zero >= 8 && moving >= 8, "{zero} {moving}");
}

#[test]
fn analyze_job_reports_the_closed_form_and_the_class_of_vm() {
    let s = spec(&ONE_LINK.replace("job = \"optimize\"", "job = \"analyze\""));
    let rows = run_all(&s, &SweepSettings::default());
    for r in &rows {
        let (p, t) = (r.values[0], r.values[1]);
        if p == 2.0 {
            // Analysed (not refused), with no closed form.
            assert_eq!(r.status, "not_unique");
            assert_eq!(r.objective, None);
            continue;
        }
        assert_eq!(r.certificate.as_deref(), Some("closed_form"));
        assert!((r.objective.unwrap() - closed_form(p, t)).abs() <= 1e-12);
        // mu+ > mu- on both blocks: both strokes move it backward (theory §9).
        let class = if p < 2.0 { "convex" } else { "concave" };
        assert_eq!(r.status, class, "p = {p}");
    }
}

#[test]
fn shards_partition_the_points_and_merge_to_the_whole_run() {
    let s = spec(&ONE_LINK.replace("job = \"optimize\"", "job = \"analyze\""));
    let whole = run_all(&s, &SweepSettings::default());
    let dir = tempfile::tempdir().unwrap();
    let mut files = Vec::new();
    for i in 1..=4 {
        let shard = Shard { index: i, count: 4 };
        let rows = run_all(
            &s,
            &SweepSettings {
                shard: Some(shard),
                ..Default::default()
            },
        );
        assert!(rows.iter().all(|r| shard.holds(r.point)));
        let path = dir.path().join(format!("shard-{i}.csv"));
        let (mut w, done) = TableWriter::open(&s, Some(&path), Format::Csv, false).unwrap();
        assert!(done.is_empty());
        for r in &rows {
            w.write(r).unwrap();
        }
        files.push(path);
    }
    let merged = merge(&s, &files, 4).unwrap().expect("complete");
    let strip = |rows: &[Row]| -> Vec<Row> {
        rows.iter()
            .map(|r| Row {
                seconds: 0.0,
                ..r.clone()
            })
            .collect()
    };
    assert_eq!(strip(&merged), strip(&whole));
    // Without shard 3: its points are named, by shard.
    let partial = [files[0].clone(), files[1].clone(), files[3].clone()];
    let problems = merge(&s, &partial, 4).unwrap().expect_err("incomplete");
    let lines = problems.lines(4);
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!(
        lines[0].starts_with("shard 3/4: 7 point(s) missing: 2, 6, 10"),
        "{lines:?}"
    );
    // A shard given twice: its points are duplicates, with the file named.
    let twice = [files.clone(), vec![files[1].clone()]].concat();
    let problems = merge(&s, &twice, 4).unwrap().expect_err("duplicates");
    assert_eq!(problems.duplicates.len(), 8);
    assert!(problems.lines(4)[0].contains("shard-2.csv"));
}

#[test]
fn tables_read_back_exactly_and_a_torn_last_line_is_dropped() {
    let s = spec(&ONE_LINK.replace("job = \"optimize\"", "job = \"analyze\""));
    let rows = run_all(&s, &SweepSettings::default());
    let dir = tempfile::tempdir().unwrap();
    for name in ["t.csv", "t.jsonl"] {
        let path = dir.path().join(name);
        let (mut w, _) = TableWriter::open(&s, Some(&path), Format::Csv, false).unwrap();
        for r in &rows[..10] {
            w.write(r).unwrap();
        }
        drop(w);
        let (back, _) = read_table(&path, &header(&s)).unwrap();
        assert_eq!(back, rows[..10].to_vec(), "{name}");
        // Without --resume an existing table is not overwritten.
        let e = TableWriter::open(&s, Some(&path), Format::Csv, false)
            .err()
            .unwrap();
        assert!(e.to_string().contains("--resume"), "{e}");
        // A run killed in the middle of a line: the torn line is cut off on resume.
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str(&study::line(&rows[10], &header(&s), Format::of(&path))[..7]);
        std::fs::write(&path, text).unwrap();
        let (mut w, done) = TableWriter::open(&s, Some(&path), Format::Csv, true).unwrap();
        assert_eq!(done, (0..10).collect());
        for r in &rows[10..] {
            w.write(r).unwrap();
        }
        drop(w);
        let (back, _) = read_table(&path, &header(&s)).unwrap();
        assert_eq!(back, rows, "{name}");
    }
    // A table of another sweep is refused on resume, naming the point.
    let other = spec(
        &ONE_LINK
            .replace("0.5, 1.0", "0.6, 1.0")
            .replace("optimize", "analyze"),
    );
    let path = dir.path().join("t.csv");
    let e = TableWriter::open(&other, Some(&path), Format::Csv, true)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("point 0") && e.contains("another sweep"), "{e}");
}

#[test]
fn axes_ranges_indices_and_zip() {
    let s = spec(
        r#"
job = "analyze"
combine = "zip"
[model.crawler]
blocks = 3
stiffness = 1.0
mu_forward = 1.0
mu_backward = 1.5
[[axis]]
field = "crawler.mu_backward[3]"
range = { from = 1.0, to = 100.0, count = 3, scale = "log" }
[[axis]]
field = "crawler.stiffness[2]"
values = [2.0, 3.0, 4.0]
"#,
    );
    assert_eq!(s.job, Job::Analyze);
    let pts = s.points();
    assert_eq!(pts.len(), 3);
    assert_eq!(pts[0].values, vec![1.0, 2.0]);
    assert!((pts[1].values[0] - 10.0).abs() < 1e-12);
    assert_eq!(pts[2].values, vec![100.0, 4.0]);
    let c = s.model_at(&pts[2]).unwrap().crawler().unwrap();
    // The scalar of the base model was expanded to one per block / link.
    assert_eq!(c.mu_backward(), &[1.5, 1.5, 100.0]);
    assert_eq!(c.stiffness(), &[1.0, 4.0]);
    // Blocks as an axis, with an index into a per-block list: N comes first.
    let s = spec(
        r#"
job = "analyze"
[model.crawler]
blocks = 3
stiffness = 1.0
mu_forward = 1.0
mu_backward = 1.5
[[axis]]
field = "crawler.mu_forward[2]"
values = [0.9]
[[axis]]
field = "crawler.blocks"
values = [2, 4]
"#,
    );
    let c = s.model_at(&s.point(1)).unwrap().crawler().unwrap();
    assert_eq!(c.mu_forward(), &[1.0, 0.9, 1.0, 1.0]);
    // An index beyond N is an error of that point naming the field.
    let s = spec(&ONE_LINK.replace("\"gait.period\"", "\"crawler.mu_backward[3]\""));
    let e = s.model_at(&s.point(0)).unwrap_err().to_string();
    assert!(
        e.starts_with("crawler.mu_backward[3]:") && e.contains("2 entries"),
        "{e}"
    );
}

#[test]
fn errors_name_the_field() {
    let cases = [
        (
            ONE_LINK.replace("crawler.mu_forward", "crawler.mu_fwd"),
            "axis[1].field",
        ),
        (
            ONE_LINK.replace("gait.period\"", "gait.period[2]\""),
            "axis[2].field",
        ),
        (
            ONE_LINK.replace("job = \"optimize\"", "job = \"solve\""),
            "job",
        ),
        (
            ONE_LINK.replace("count = 6", "count = 0"),
            "axis[2].range.count",
        ),
        (
            ONE_LINK.replace("count = 6 }", "count = 6, scale = \"cubic\" }"),
            "axis[2].range.scale",
        ),
        (
            ONE_LINK
                .replace("from = 2.0", "from = -2.0")
                .replace("count = 6 }", "count = 6, scale = \"log\" }"),
            "axis[2].range.from",
        ),
        (
            ONE_LINK.replace(
                "job = \"optimize\"",
                "job = \"optimize\"\ncombine = \"zip\"",
            ),
            "axis[2]",
        ),
        (
            ONE_LINK.replace(
                "job = \"optimize\"",
                "job = \"optimize\"\n[settings]\nmethod = \"best\"",
            ),
            "settings.method",
        ),
        (
            ONE_LINK.replace(
                "job = \"optimize\"",
                "job = \"optimize\"\n[settings]\ntime_limit = -1",
            ),
            "settings.time_limit",
        ),
        (
            ONE_LINK.replace("job = \"optimize\"", "job = \"analyze\"\n[settings]\nm = 3"),
            "settings.m",
        ),
        (
            ONE_LINK.replace(
                "job = \"optimize\"",
                "job = \"optimize\"\n[settings]\nmm = 3",
            ),
            "settings",
        ),
        (
            ONE_LINK.replace("values = [0.5", "values = [nan, 0.5"),
            "axis[1].values",
        ),
        (
            ONE_LINK.replace("field = \"gait.period\"", "field = \"crawler.mu_forward\""),
            "axis[2].field",
        ),
        (
            "job = \"analyze\"\n[[axis]]\nfield = \"gait.period\"\nvalues = [1]".into(),
            "base",
        ),
    ];
    for (text, field) in cases {
        let e = err(&text);
        assert!(e.starts_with(&format!("{field}: ")), "{field}: {e}");
    }
    // Settings that do not apply to the method are refused before any point runs (issue 30:
    // every row was an error row, exit 0), named as settings.
    let e = err(&ONE_LINK.replace(
        "job = \"optimize\"",
        "job = \"optimize\"\n[settings]\nmethod = \"phase\"\nm = 3",
    ));
    assert!(e.starts_with("settings.m: applies to"), "{e}");
}

#[test]
fn figures_of_a_table_have_the_axes_and_the_no_locomotion_boundary() {
    let s = spec(&ONE_LINK.replace("job = \"optimize\"", "job = \"analyze\""));
    let rows = run_all(&s, &SweepSettings::default());
    let axes: Vec<String> = s.axes.iter().map(|a| a.field.clone()).collect();
    let figs = study::figures(&axes, &rows).unwrap();
    let names: Vec<&str> = figs.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["sweep_lines", "sweep_map"]);
    for f in &figs {
        assert!(
            f.svg.starts_with("<svg") && f.svg.contains("gait.period"),
            "{}",
            f.name
        );
        assert!(f.png.starts_with(b"\x89PNG"));
    }
    // One line per value of mu+, labelled; the map has the boundary and the error cells.
    assert!(figs[0].svg.contains("crawler.mu_forward = 0.5"));
    assert!(figs[1].svg.contains("boundary of no locomotion"));
    assert!(figs[1].svg.contains("no value (error)"));
    // The table read back without its sweep file gives the same figures.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("t.jsonl");
    let (mut w, _) = TableWriter::open(&s, Some(&path), Format::Csv, false).unwrap();
    for r in &rows {
        w.write(r).unwrap();
    }
    let (axes_back, rows_back) = study::read_any_table(&path).unwrap();
    assert_eq!(axes_back, axes);
    assert_eq!(rows_back, rows);
    // Not a sweep table: refused naming the file.
    std::fs::write(&path, "{\"a\": 1}\n").unwrap();
    let e = study::read_any_table(&path).unwrap_err().to_string();
    assert!(e.contains("not a sweep table"), "{e}");
}
