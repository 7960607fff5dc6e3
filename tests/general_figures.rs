//! The figures and the report of the general problem (P) (theory §11): drawn for n = 1, 2 and
//! 3, an unbounded C within its window, the orbit inside the polygon the figure draws, the
//! integrand's integral equal to the J of the record, and the report showing the optimiser's J.

use crawlopt::api::{self, GaitMethod, Hooks, Naming, OptimizeSettings};
use crawlopt::integrate::GeneralSimOptions;
use crawlopt::io::{GeneralAnswer, GeneralFile};
use crawlopt::model::general::GeneralProblem;
use crawlopt::present::{
    self, build_general_report, general_series, general_state_space, GeneralPath,
    GeneralReportInput,
};

fn load(path: &str) -> GeneralFile {
    GeneralFile::load_if_general(std::path::Path::new(path))
        .unwrap()
        .expect("a general problem file")
}

/// A box C = [-1, 1]^3 cut by x1 + x2 + x3 <= 1.5, g = u in the box U = [-1, 1]^3 with zero
/// mean, the reward on the cut face; the control pushes each component across C in turn.
const THREE: &str = "[sweeping_process]\n\
normals = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], \
[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 1.0, 1.0]]\n\
offsets = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.5]\n\
[dynamics]\nB = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n\
[control]\nlower = [-1.0, -1.0, -1.0]\nupper = [1.0, 1.0, 1.0]\n\
[objective]\nface_weights = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]\n\
[problem]\nperiod = 12.0\n\
[input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]\n\
values = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], \
[0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]\n";

/// `x` inside the counter-clockwise polygon `v` within `tol` (every edge's half-plane).
fn inside(v: &[(f64, f64)], x: (f64, f64), tol: f64) -> bool {
    (0..v.len()).all(|k| {
        let (a, b) = (v[k], v[(k + 1) % v.len()]);
        let cross = (b.0 - a.0) * (x.1 - a.1) - (b.1 - a.1) * (x.0 - a.0);
        cross >= -tol
    })
}

/// The integral of a piecewise-constant curve given as the pairs of points of its pieces.
fn integral(points: &[(f64, f64)]) -> f64 {
    points.chunks(2).map(|p| (p[1].0 - p[0].0) * p[0].1).sum()
}

fn integrand_integral(p: &GeneralProblem, path: &GeneralPath) -> f64 {
    let series = general_series(p, path);
    let s = series.iter().find(|s| s.name == "integrand").unwrap();
    integral(&s.lines[0].points)
}

fn answer(file: &GeneralFile, method: GaitMethod, m: Option<u32>) -> GeneralAnswer {
    let s = OptimizeSettings {
        method,
        m,
        naming: Naming::Keywords,
        ..OptimizeSettings::default()
    };
    let plan = s.plan_general(&[]).unwrap();
    api::optimize_general_plan(file, &plan, s.naming, Hooks::default()).unwrap()
}

#[test]
fn one_state_the_interval_and_every_method_s_integrand_gives_its_j() {
    let file = load("examples/general_one_link.toml");
    let (p, g) = api::general_problem(&file).unwrap();
    let sim = api::simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
    let path = GeneralPath::of_simulation(&sim).unwrap();
    let space = general_state_space(&p, &g, Some(&path)).unwrap();
    // C = [-1, 1]: face 2 (x >= -1) below, face 1 (x <= 1) above.
    let [lo, hi] = space.interval.unwrap();
    assert_eq!(
        (lo.value, lo.face, hi.value, hi.face),
        (-1.0, Some(2), 1.0, Some(1))
    );
    assert!(space.x.iter().all(|x| (-1.0..=1.0).contains(&x[0])));
    // J* = 3 (paper §4), the simulation's and the integrand's.
    assert!((integrand_integral(&p, &path) - 3.0).abs() < 1e-12);
    let figs = present::general_simulation_figures(&p, &sim).unwrap();
    let names: Vec<&str> = figs.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, ["polytope", "controls", "reactions", "integrand"]);
    assert!(figs[0].svg.contains("face 1:") && figs[0].svg.contains("x₁(t): periodic orbit"));
    // Every method's optimum: the integral of the integrand drawn is the J it states.
    for (method, m) in [
        (GaitMethod::Discrete, Some(2)),
        (GaitMethod::Local, Some(3)),
        (GaitMethod::Phase, None),
    ] {
        let a = answer(&file, method, m);
        let path = GeneralPath::of_answer(&a).unwrap();
        let j = integrand_integral(&p, &path);
        assert!(
            (j - path.objective).abs() <= 1e-9 * (1.0 + j.abs()),
            "{method:?}: {j} against {}",
            path.objective
        );
        assert!((path.objective - 3.0).abs() < 1e-6, "{method:?}");
        let figs = present::general_answer_figures(&p, &a).unwrap();
        assert!(figs.len() >= 4 && figs.iter().all(|f| f.png.len() > 1000));
    }
}

#[test]
fn two_states_the_orbit_lies_in_the_polygon_drawn() {
    let file = load("examples/general_drift.toml");
    let (p, g) = api::general_problem(&file).unwrap();
    let a = answer(&file, GaitMethod::Discrete, Some(3));
    let path = GeneralPath::of_answer(&a).unwrap();
    let space = general_state_space(&p, &g, Some(&path)).unwrap();
    assert_eq!(space.panels.len(), 1);
    let poly = &space.panels[0].projection;
    // The square [-1, 1]^2, its four edges labelled with their faces, its vertices dotted.
    assert_eq!(poly.vertices.len(), 4);
    for v in &poly.vertices {
        assert!((v.0.abs() - 1.0).abs() < 1e-9 && (v.1.abs() - 1.0).abs() < 1e-9);
    }
    let mut labels: Vec<&str> = poly.edges.iter().map(|e| e.label.as_str()).collect();
    labels.sort();
    assert_eq!(labels, ["1", "2", "3", "4"]);
    for e in &poly.edges {
        let j: usize = e.label.parse().unwrap();
        let n = &p.c.normals[j - 1];
        assert_eq!(e.normal, (n[0], n[1]));
        for end in [e.from, e.to] {
            assert!((n[0] * end.0 + n[1] * end.1 - p.c.offsets[j - 1]).abs() < 1e-9);
        }
    }
    assert_eq!(space.dots.len(), 4);
    assert!(poly.open_sides.is_empty() && space.bounded);
    // Every state of the path drawn is in C and in the polygon.
    assert_eq!(space.x.len(), path.t.len());
    for x in &space.x {
        assert!(p.c.violation(x, 1e-9).is_none(), "{x:?}");
        assert!(inside(&poly.vertices, (x[0], x[1]), 1e-9), "{x:?}");
    }
    let j = integrand_integral(&p, &path);
    assert!((j - path.objective).abs() <= 1e-9 * (1.0 + j.abs()));
    let figs = present::general_answer_figures(&p, &a).unwrap();
    let names: Vec<&str> = figs.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(
        names,
        ["polytope", "states", "controls", "reactions", "integrand"]
    );
    // The controls' figure shows the bounds of U; the integrand's f1 and f2 apart (a cost).
    let series = general_series(&p, &path);
    assert_eq!(
        series[1].levels.iter().map(|l| l.0).collect::<Vec<_>>(),
        [-1.0, 1.0]
    );
    assert_eq!(series[3].lines.len(), 3);
}

#[test]
fn three_states_are_drawn_as_projections_written_to_a_directory() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("three.toml");
    std::fs::write(&path, THREE).unwrap();
    let file = load(path.to_str().unwrap());
    let (p, g) = api::general_problem(&file).unwrap();
    let sim = api::simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
    assert!(sim.simulation.converged);
    let gp = GeneralPath::of_simulation(&sim).unwrap();
    let space = general_state_space(&p, &g, Some(&gp)).unwrap();
    let pairs: Vec<(usize, usize)> = space.panels.iter().map(|q| q.pair).collect();
    assert_eq!(pairs, [(0, 1), (0, 2), (1, 2)]);
    for panel in &space.panels {
        // The projection of the cut cube on any pair is the square [-1, 1]^2: the cut
        // x_i + x_j <= 1.5 - x_k leaves (1, 1) in at x_k = -1.
        let v = &panel.projection.vertices;
        assert_eq!(v.len(), 4, "{v:?}");
        let (i, j) = panel.pair;
        for x in &space.x {
            assert!(inside(v, (x[i], x[j]), 1e-9));
        }
    }
    let j = integrand_integral(&p, &gp);
    assert!((j - gp.objective).abs() <= 1e-9 * (1.0 + j.abs()));
    assert!(
        gp.objective > 0.0,
        "the cut face is reached: {}",
        gp.objective
    );
    let figs = present::general_simulation_figures(&p, &sim).unwrap();
    let out = dir.path().join("figs");
    let written = present::write_figures(&out, &figs).unwrap();
    assert_eq!(written.len(), 2 * figs.len());
    for name in ["polytope", "states", "controls", "reactions", "integrand"] {
        for ext in ["svg", "png"] {
            assert!(out.join(format!("{name}.{ext}")).is_file(), "{name}.{ext}");
        }
    }
    assert!(figs[0].svg.contains("C projected on (x₁, x₃)"));
}

#[test]
fn an_unbounded_c_is_drawn_within_a_window() {
    // The half-strip -1 <= x1 <= 1, x2 <= 1 (unbounded below).
    let text = "[sweeping_process]\nnormals = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]]\n\
offsets = [1.0, 1.0, 1.0]\n[dynamics]\nB = [[1.0, 0.0], [0.0, 1.0]]\n\
[control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\n\
[objective]\nreaction_weights = [1.0, 0.0]\n[problem]\nperiod = 4.0\n";
    let file = GeneralFile::parse(text).unwrap();
    let a = api::analyze_general(&file).unwrap();
    assert!(!a.geometry.bounded);
    let space = general_state_space(&a.problem, &a.geometry, None).unwrap();
    let poly = &space.panels[0].projection;
    assert!(!space.bounded && !poly.open_sides.is_empty());
    // The three faces are edges; the window closes the polygon below.
    let mut labels: Vec<&str> = poly.edges.iter().map(|e| e.label.as_str()).collect();
    labels.sort();
    assert_eq!(labels, ["1", "2", "3"]);
    for v in &a.geometry.vertices.clone().unwrap() {
        assert!(inside(&poly.vertices, (v.point[0], v.point[1]), 1e-9));
    }
    // The window closes it below C's vertices (at x2 = 1) with one grey side.
    assert_eq!(poly.open_sides.len(), 1);
    let k = poly.open_sides[0];
    let (p0, p1) = (
        poly.vertices[k],
        poly.vertices[(k + 1) % poly.vertices.len()],
    );
    assert!(p0.1 == p1.1 && p0.1 < 1.0, "{:?}", poly.vertices);
    let figs = present::general_analysis_figures(&a).unwrap();
    assert_eq!(figs.len(), 1);
    assert!(figs[0].caption.contains("unbounded"));
}

#[test]
fn the_report_shows_the_optimiser_s_objective_and_the_problem() {
    let file = load("examples/general_drift.toml");
    let p = file.problem().unwrap();
    let settings = OptimizeSettings {
        method: GaitMethod::Discrete,
        m: Some(3),
        certify: true,
        naming: Naming::Keywords,
        ..OptimizeSettings::default()
    };
    let plan = settings.plan_general(&[]).unwrap();
    let a = api::optimize_general_plan(&file, &plan, settings.naming, Hooks::default()).unwrap();
    let r = a.solution.as_pm().expect("discrete");
    let html = build_general_report(
        &p,
        GeneralReportInput::Answer(&a),
        "general_drift.toml",
        "crawlopt optimize general_drift.toml --report r.html",
    )
    .unwrap();
    let want = format!("id=\"objective\" data-value=\"{}\"", r.objective);
    assert!(html.contains(&want), "{want}");
    for part in [
        "<table id=\"faces\">",
        "id=\"fig-polytope\"",
        "id=\"fig-integrand\"",
        "id=\"fig-adjoint\"",
        "<table id=\"conditions\">",
        "n = 2, m = 2, σ = 4",
        "crawlopt optimize general_drift.toml --report r.html",
    ] {
        assert!(html.contains(part), "{part}");
    }
    // No animation (nor any script) for a general problem.
    assert!(!html.contains("<script"));
    // A simulation's report, and none without the periodic regime.
    let sim = api::simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
    let html = build_general_report(&p, GeneralReportInput::Simulation(&sim), "s", "c").unwrap();
    assert!(html.contains(&format!(
        "data-value=\"{}\"",
        sim.simulation.objective.unwrap()
    )));
    let short = GeneralSimOptions {
        max_periods: 1,
        ..GeneralSimOptions::DEFAULT
    };
    let sim = api::simulate_general(&file, &short).unwrap();
    assert!(!sim.simulation.converged);
    assert!(build_general_report(&p, GeneralReportInput::Simulation(&sim), "s", "c").is_err());
    assert!(present::general_simulation_figures(&p, &sim).is_err());
}

#[test]
fn a_regular_polygon_of_thirty_faces_is_drawn_exactly_without_labels() {
    // Faces at angles 2 pi k / 30, offsets 1: the vertices lie at radius 1 / cos(pi / 30).
    let n = 30;
    let normals: Vec<String> = (0..n)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            format!("[{:?}, {:?}]", a.cos(), a.sin())
        })
        .collect();
    let text = format!(
        "[sweeping_process]\nnormals = [{}]\noffsets = [{}]\n[dynamics]\n\
B = [[1.0, 0.0], [0.0, 1.0]]\n[control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\n\
[objective]\nreaction_weights = [1.0, 0.0]\n[problem]\nperiod = 4.0\n",
        normals.join(", "),
        vec!["1.0"; n].join(", ")
    );
    let a = api::analyze_general(&GeneralFile::parse(&text).unwrap()).unwrap();
    let space = general_state_space(&a.problem, &a.geometry, None).unwrap();
    let poly = &space.panels[0].projection;
    assert_eq!(poly.vertices.len(), n);
    let r = 1.0 / (std::f64::consts::PI / n as f64).cos();
    for v in &poly.vertices {
        assert!((v.0.hypot(v.1) - r).abs() < 1e-9, "{v:?}");
    }
    // More edges than present::general::MAX_LABELLED_EDGES: none labelled.
    assert!(poly.edges.is_empty());
    assert_eq!(space.dots.len(), n);
}
