//! The presentation layer: figure sets, all-or-nothing writing, the self-contained report, and
//! refusal of bad result files.

use crawlopt::optimal::{solve_phase_global, Cost, GaitProblem, GaitResult};
use crawlopt::present::{self, report, write_figures, PlotInput};
use crawlopt::Crawler;

fn one_link() -> GaitResult {
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    GaitResult::from_phase(&c, &p, &solve_phase_global(&c, &p, 4).unwrap())
}

fn three_blocks() -> GaitResult {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    GaitResult::from_phase(&c, &p, &solve_phase_global(&c, &p, 3).unwrap())
}

#[test]
fn a_gait_result_gives_its_figures_and_they_are_written_together() {
    let r = three_blocks();
    let figs = present::gait_figures(&r).unwrap();
    let names: Vec<&str> = figs.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["actuation", "spacetime", "polytope", "vm"]);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a/b");
    let written = write_figures(&out, &figs).unwrap();
    assert_eq!(written.len(), 8);
    for p in &written {
        let bytes = std::fs::read(p).unwrap();
        match p.extension().unwrap().to_str().unwrap() {
            "png" => assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n"),
            _ => assert!(bytes.starts_with(b"<svg")),
        }
    }
    // Only the figures: no temporary files left.
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 8);
}

#[test]
fn an_unwritable_directory_fails_cleanly_with_nothing_left() {
    let figs = present::gait_figures(&one_link()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("file");
    std::fs::write(&file, "x").unwrap();
    let e = write_figures(&file.join("figs"), &figs).unwrap_err();
    assert!(e.to_string().contains("cannot create the directory"), "{e}");
    let e = write_figures(&file, &figs).unwrap_err();
    assert!(e.to_string().contains("not a directory"), "{e}");
    // A destination that cannot be replaced: nothing else is written either.
    let out = dir.path().join("out");
    std::fs::create_dir_all(out.join("polytope.png")).unwrap();
    let e = write_figures(&out, &figs).unwrap_err();
    assert!(e.to_string().contains("is a directory"), "{e}");
    let left: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
    assert_eq!(left.len(), 1, "only the pre-existing directory");
}

#[test]
fn the_report_is_self_contained_and_shows_the_numbers() {
    let r = one_link();
    let html = report::build_report(&r, "one_link_gait.toml").unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    // Nothing is fetched: the only URL is the SVG namespace (an identifier, never loaded).
    let stripped = html.replace("http://www.w3.org/2000/svg", "");
    assert!(!stripped.contains("http://") && !stripped.contains("https://"));
    for external in ["<link", " src=", "@import", "url("] {
        assert!(!html.contains(external), "external reference {external:?}");
    }
    assert!(html.contains("id=\"crawler-data\""));
    assert!(html.contains("id=\"anim-state\""));
    assert!(html.contains(&format!("data-value=\"{}\"", r.displacement_per_period)));
    assert!((r.displacement_per_period - 3.0).abs() < 1e-9);
    for fig in ["fig-actuation", "fig-spacetime", "fig-polytope"] {
        assert!(html.contains(fig), "{fig}");
    }
    assert!(html.contains("<svg viewBox=\"0 0 900 640\""));
    assert!(html.contains("one_link_gait.toml"));
    // Three blocks: the v_m heat map as well.
    let html = report::build_report(&three_blocks(), "r.json").unwrap();
    assert!(html.contains("fig-vm"));
    let out = tempfile::tempdir().unwrap();
    let p = out.path().join("r.html");
    report::write_report(&p, &html).unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), html);
}

#[test]
fn bad_result_files_are_refused() {
    let r = one_link();
    let text = serde_json::to_string(&r).unwrap();
    let e = PlotInput::from_json(&text[..text.len() - 20], "r.json").unwrap_err();
    assert!(
        e.to_string().contains("not a complete JSON document"),
        "{e}"
    );
    let e = PlotInput::from_json(&text.replace("\"version\":4", "\"version\":7"), "r.json")
        .unwrap_err();
    assert!(e.to_string().contains("version"), "{e}");
    assert!(PlotInput::from_json("{}", "r.json").is_err());
    // A result whose gait does not do what it claims is not pictured.
    let mut edited = r;
    edited.displacement_per_period = 5.0;
    let e = present::gait_figures(&edited).unwrap_err();
    assert!(e.to_string().contains("when replayed"), "{e}");
    assert!(report::build_report(&edited, "r.json").is_err());
}

#[test]
fn a_jm_table_gives_the_convergence_figure() {
    let t = r#"{"format": "crawlopt-jm-table", "version": 1, "m": [1, 2, 3], "values": [3, 3, 3], "continuous": 3}"#;
    let figs = PlotInput::from_json(t, "jm.json")
        .unwrap()
        .figures()
        .unwrap();
    assert_eq!(figs.len(), 1);
    assert_eq!(figs[0].name, "jm");
    let e = PlotInput::from_json(&t.replace("\"version\": 1", "\"version\": 2"), "jm.json")
        .unwrap_err();
    assert!(e.to_string().contains("version 1 only"), "{e}");
    let e = PlotInput::from_json(&t.replace("[3, 3, 3]", "[3, 3]"), "jm.json")
        .unwrap()
        .figures()
        .unwrap_err();
    assert!(e.to_string().contains("one J value per m"), "{e}");
}

#[test]
fn the_transient_starts_at_rest_and_ends_on_the_orbit() {
    let r = three_blocks();
    let (crawler, sim) = present::replay_gait(&r, 1).unwrap();
    let act = present::gait_actuation(&r).unwrap();
    let states = present::transient_states(
        &crawler,
        &act,
        crawlopt::integrate::Method::Exact,
        r.gait.durations.len(),
    )
    .unwrap();
    assert_eq!(states[0], vec![0.0, 0.0]);
    // The orbit's states at the phase boundaries include where the transient ends.
    let end = states.last().unwrap();
    let traj = sim.trajectory.unwrap();
    let near = traj
        .x
        .iter()
        .map(|x| (x[0] - end[0]).abs().max((x[1] - end[1]).abs()))
        .fold(f64::INFINITY, f64::min);
    assert!(near < 1e-9, "the transient ends {near} away from the orbit");
}
