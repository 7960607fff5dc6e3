//! The crawler's local methods (`sequence`, `chain`) on a general problem that is a crawler's
//! gait problem (`crawlopt::api::optimize_general_on_chain`): the same gait as on the crawler,
//! written back in the problem's terms and re-verified by the general exact simulator (`J`
//! times the objective's scale), with a local claim; read back checked, certified, refused
//! where the problem is not a chain or a setting does not apply.

mod common;

use common::crawlopt;
use crawlopt::api::{
    gait_problem, optimize, optimize_general_plan, Event, GaitMethod, GeneralAnswer,
    GeneralSolution, Hooks, Naming, OptimizeSettings,
};
use crawlopt::certify::bound::{upper_bound, BoundSettings};
use crawlopt::io::{GeneralFile, ModelFile, ResultFile};
use crawlopt::optimal::MilpStatus;

const GENERAL: &str = "examples/general_three_blocks.toml";
const CRAWLER: &str = "examples/three_blocks_gait.toml";

/// The three-block problem in general form with its objective scaled by `lambda`.
fn general_file(lambda: f64) -> GeneralFile {
    let text = std::fs::read_to_string(GENERAL).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("face_weights"))
        .unwrap()
        .to_string();
    let inner = line.split('[').nth(1).unwrap().trim_end_matches(']');
    let scaled: Vec<String> = inner
        .split(',')
        .map(|v| format!("{:e}", lambda * v.trim().parse::<f64>().unwrap()))
        .collect();
    let text = text.replace(&line, &format!("face_weights = [{}]", scaled.join(", ")));
    GeneralFile::parse(&text).unwrap()
}

fn run(file: &GeneralFile, s: &OptimizeSettings) -> crawlopt::Result<GeneralAnswer> {
    let plan = s.plan_general(&[])?;
    optimize_general_plan(file, &plan, s.naming, Hooks::default())
}

/// Both methods give the crawler's gait: `J` is the crawler's times the objective's scale (1
/// and 2.5), the status the crawler's stop, the certificate `local`, the solution's bound
/// absent; the gait has as many phases as it says.
#[test]
fn the_crawlers_local_methods_run_on_its_general_form() {
    let model = ModelFile::load(CRAWLER.as_ref()).unwrap();
    let (crawler, gp) = gait_problem(&model).unwrap();
    for method in [GaitMethod::Sequence, GaitMethod::Chain] {
        let s = OptimizeSettings {
            method,
            ..Default::default()
        };
        let want = optimize(&crawler, &gp, &s, Hooks::default())
            .unwrap()
            .result;
        for lambda in [1.0, 2.5] {
            let r = run(&general_file(lambda), &s).unwrap();
            let GeneralSolution::Phase(g) = &r.solution else {
                panic!("not a phase answer");
            };
            let j = lambda * want.head.objective;
            assert!(
                (r.head.objective - j).abs() < 1e-9 * j,
                "{method:?}: {} vs {j}",
                r.head.objective
            );
            assert_eq!(r.head.method, method.name());
            assert_eq!(r.head.status, want.head.status);
            assert!(matches!(
                r.head.status,
                MilpStatus::Stationary | MilpStatus::Stalled
            ));
            assert_eq!(r.head.certificate.kind, "local");
            assert!(r.head.certificate.bound.is_none() && r.head.certificate.gap.is_none());
            assert!(g.certificate.bound.is_nan());
            assert_eq!(g.max_phases, g.durations.len());
            assert_eq!(g.durations, want.gait.durations);
            assert_eq!(r.formulation.as_deref(), Some("chain"));
        }
    }
}

/// Written and read back, the answer is checked as any general result: the same answer, and a
/// tampered claim refused naming its field.
#[test]
fn a_local_answer_reads_back_and_tampering_is_refused() {
    let s = OptimizeSettings {
        method: GaitMethod::Sequence,
        ..Default::default()
    };
    let r = run(&general_file(1.0), &s).unwrap();
    let text = serde_json::to_string(&r).unwrap();
    let ResultFile::General(back) = ResultFile::from_json(&text, "r.json").unwrap() else {
        panic!("not a general result");
    };
    assert_eq!(serde_json::to_string(&back).unwrap(), text);
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(Edit, &str)> = vec![
        (
            Box::new(|v| v["status"] = "optimal".into()),
            "r.json: status",
        ),
        (
            Box::new(|v| v["certificate"]["kind"] = "global_k_phases".into()),
            "r.json: certificate",
        ),
        (
            Box::new(|v| v["certificate"]["bound"] = 9.0.into()),
            "r.json: certificate",
        ),
        (
            Box::new(|v| {
                v.as_object_mut()
                    .unwrap()
                    .remove("formulation")
                    .map(|_| ())
                    .unwrap()
            }),
            "r.json: formulation",
        ),
        (
            Box::new(|v| v["solution"]["max_phases"] = 3.into()),
            "r.json: solution.max_phases",
        ),
        (
            Box::new(|v| v["objective"] = 3.0.into()),
            "r.json: objective",
        ),
        // A face held on a transition, which the segment does not touch.
        (
            Box::new(|v| v["solution"]["held"][0] = serde_json::json!([1])),
            "r.json: solution.held[0]",
        ),
        (
            Box::new(|v| v["method"] = "simplex".into()),
            "r.json: method",
        ),
    ];
    for (edit, field) in cases {
        let mut w = v.clone();
        edit(&mut w);
        let e = ResultFile::from_json(&w.to_string(), "r.json")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(field), "{field}: {e}");
    }
}

/// On a problem that is not a crawler's (the §4 one-link problem: two faces, not four) the
/// methods are refused naming `method`; a setting they do not take is refused naming it as the
/// caller spelled it.
#[test]
fn what_does_not_apply_is_refused() {
    let text = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let one_link = GeneralFile::parse(&text).unwrap();
    for method in [GaitMethod::Sequence, GaitMethod::Chain] {
        let s = OptimizeSettings {
            method,
            ..Default::default()
        };
        let e = run(&one_link, &s).unwrap_err().to_string();
        assert!(
            e.starts_with("method:") && e.contains("crawler's gait problem"),
            "{e}"
        );
        for (naming, edit, want) in [
            (
                Naming::Flags,
                OptimizeSettings {
                    m: Some(3),
                    ..s.clone()
                },
                "--m",
            ),
            (
                Naming::Flags,
                OptimizeSettings {
                    polish: Some(false),
                    ..s.clone()
                },
                "--no-polish",
            ),
            (
                Naming::Keywords,
                OptimizeSettings {
                    shifts: Some(2),
                    ..s.clone()
                },
                "shifts",
            ),
            (
                Naming::Keywords,
                OptimizeSettings {
                    convergence: true,
                    ..s.clone()
                },
                "convergence",
            ),
        ] {
            let s = OptimizeSettings { naming, ..edit };
            let e = s.plan_general(&[]).unwrap_err().to_string();
            assert!(e.starts_with(&format!("{want}:")), "{want}: {e}");
        }
    }
}

/// `crawlopt optimize GENERAL.toml --method sequence --certify --json`: the general certificate
/// of the gait on its phases gives the crawler certificate's verdict on the crawler's gait
/// (`degenerate` for the three-block optimum J = 2.6), and `crawlopt certify` of the written
/// answer the same certificate.
#[test]
fn the_command_line_certifies_the_gait_as_the_crawlers() {
    let v = common::crawlopt_json(&[
        "optimize",
        GENERAL,
        "--method",
        "sequence",
        "--certify",
        "--json",
    ]);
    assert_eq!(v["method"], "sequence");
    assert!((v["objective"].as_f64().unwrap() - 2.6).abs() < 1e-9);
    let c = common::crawlopt_json(&[
        "optimize",
        CRAWLER,
        "--method",
        "sequence",
        "--certify",
        "--json",
    ]);
    assert_eq!(
        v["necessary_conditions"]["verdict"],
        c["necessary_conditions"]["verdict"]
    );
    let dir = tempfile::tempdir().unwrap();
    let back = common::certify_written(dir.path(), &v);
    assert_eq!(back, v["necessary_conditions"]);
    let text =
        String::from_utf8(crawlopt(&["optimize", GENERAL, "--method", "chain"]).stdout).unwrap();
    assert!(
        text.contains("by the crawler's chain method on the problem's chain"),
        "{text}"
    );
}

/// `bound` with the crawler's local methods on its general form, as with every method on (P):
/// the crawler's own upper bound times the objective's scale (1 and 2.5), at least `J`,
/// recorded beside the `local` certificate; read back and certified; a bound below `J`
/// refused naming `certificate.upper_bound.value`; the report shows it as recorded.
#[test]
fn the_crawlers_local_methods_take_the_chains_upper_bound() {
    let model = ModelFile::load(CRAWLER.as_ref()).unwrap();
    let (crawler, gp) = gait_problem(&model).unwrap();
    let b = BoundSettings {
        resolution: Some(2),
        box_resolution: Some(2),
        ..Default::default()
    };
    let want = upper_bound(&crawler, &gp, &b).unwrap().value;
    let dir = tempfile::tempdir().unwrap();
    for method in [GaitMethod::Sequence, GaitMethod::Chain] {
        let s = OptimizeSettings {
            method,
            bound: Some(b),
            ..Default::default()
        };
        for lambda in [1.0, 2.5] {
            let r = run(&general_file(lambda), &s).unwrap();
            let ub = r.head.certificate.upper_bound.as_ref().unwrap();
            assert!(
                (ub.value - lambda * want).abs() <= 1e-9 * lambda * want,
                "{method:?}: {} vs {}",
                ub.value,
                lambda * want
            );
            assert!(ub.value >= r.head.objective, "{method:?}");
            assert_eq!(r.head.certificate.kind, "local");
            assert!(r.head.certificate.bound.is_none());
        }
        let r = run(&general_file(1.0), &s).unwrap();
        let text = serde_json::to_string(&r).unwrap();
        ResultFile::from_json(&text, "r.json").unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let certified = common::certify_written(dir.path(), &v);
        assert!(certified["verdict"].is_string(), "{certified}");
        let file = common::write(dir.path(), "r.json", &text);
        let html = dir.path().join("r.html");
        let out = crawlopt(&[
            "report",
            file.to_str().unwrap(),
            "-o",
            html.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{out:?}");
        let page = std::fs::read_to_string(&html).unwrap();
        let shown = page
            .split("<b id=\"upper-bound\">")
            .nth(1)
            .and_then(|t| t.split("</b>").next())
            .unwrap_or_else(|| panic!("{method:?}: no upper bound in the report"));
        let shown: f64 = shown.parse().unwrap();
        assert!((shown - want).abs() <= 1e-5 * want, "{shown} vs {want}");
        assert!(page.contains("as recorded in the file, not re-proven here"));
        v["certificate"]["upper_bound"]["value"] = (0.5 * r.head.objective).into();
        let e = ResultFile::from_json(&v.to_string(), "r.json")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("r.json: certificate.upper_bound.value"),
            "{e}"
        );
    }
}

/// The crawler's job reports its progress in the problem's units of `J`: with the objective
/// scaled by 2.5, every value of `J` in its events (each K solved of the sequence method's
/// start, each sweep of the chain method) is 2.5 times the one at scale 1 (they were the
/// crawler's, the same at both scales).
#[test]
fn the_crawlers_progress_is_in_the_problems_units() {
    for method in [GaitMethod::Sequence, GaitMethod::Chain] {
        let s = OptimizeSettings {
            method,
            ..Default::default()
        };
        let values = |lambda: f64| {
            let mut js = Vec::new();
            let mut on = |e: &Event, _: f64| match e {
                Event::PhaseSolved { step, .. } => js.push(step.objective),
                Event::ChainSweep(c) => js.push(c.objective),
                _ => {}
            };
            let plan = s.plan_general(&[]).unwrap();
            let hooks = Hooks {
                events: Some(&mut on),
                cancel: None,
            };
            let r = optimize_general_plan(&general_file(lambda), &plan, s.naming, hooks).unwrap();
            (js, r.head.objective)
        };
        let (one, j1) = values(1.0);
        let (scaled, j) = values(2.5);
        assert!(!one.is_empty(), "{method:?}: no event with a J");
        assert_eq!(one.len(), scaled.len(), "{method:?}");
        for (a, b) in one.iter().zip(&scaled) {
            assert!(
                (b - 2.5 * a).abs() <= 1e-9 * b.abs().max(1.0),
                "{method:?}: {b} vs {a}"
            );
        }
        assert!((j - 2.5 * j1).abs() <= 1e-9 * j, "{method:?}");
    }
}

/// A sweep over the chain's period with the chain method: each row says what the answer
/// claims, `local` without bound or gap, with the method's stop as its status (it said
/// `global_k_phases` with NaN for bound and gap).
#[test]
fn a_sweep_row_claims_what_the_answer_claims() {
    let dir = tempfile::tempdir().unwrap();
    let spec = dir.path().join("sweep.toml");
    let base = std::fs::canonicalize(GENERAL).unwrap();
    std::fs::write(
        &spec,
        format!(
            "base = {:?}\njob = \"optimize\"\n[settings]\nmethod = \"chain\"\n\n[[axis]]\nfield = \
             \"problem.period\"\nvalues = [6.0, 10.0]\n",
            base.to_str().unwrap()
        ),
    )
    .unwrap();
    let table = dir.path().join("table.csv");
    let out = crawlopt(&[
        "sweep",
        spec.to_str().unwrap(),
        "-j",
        "1",
        "--output",
        table.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&table).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2, "{text}");
    for r in rows {
        assert_eq!(r[col("method")], "chain", "{text}");
        assert_eq!(r[col("certificate")], "local", "{text}");
        assert_eq!((r[col("bound")], r[col("gap")]), ("", ""), "{text}");
        assert!(
            matches!(r[col("status")], "stalled" | "stationary"),
            "{text}"
        );
    }
}

/// The certificate's verdict does not depend on the objective's scale: the sequence method's
/// optimum (J = 2.6) is `degenerate` at scale 1 and at 1e-7, where the switching function's
/// zeros are below the LP's resolution (it said `holds` there: a margin of 1e-12 passed
/// against 1e-6 of multipliers of size 1e-7).
#[test]
fn the_verdict_does_not_depend_on_the_objectives_scale() {
    for lambda in [1.0, 1e-7] {
        let s = OptimizeSettings {
            method: GaitMethod::Sequence,
            certify: true,
            ..Default::default()
        };
        let r = run(&general_file(lambda), &s).unwrap();
        assert!(r.solution.as_phase().is_some(), "not a phase answer");
        let c = r.necessary_conditions.as_ref().unwrap();
        assert_eq!(
            c.verdict,
            crawlopt::certify::Verdict::Degenerate,
            "{lambda}: {}",
            c.reason
        );
    }
}

/// The chain's phase MILP on a general problem with a quadratic cost: the answer's
/// `milp_objective` is the MILP's J, at most its bound, so the file reads back and certifies
/// (it held the MILP's displacement, 2.1667 above the bound 1.5503 with a weight of 0.1, and
/// `certify` refused the file `optimize` had just written).
#[test]
fn a_phase_answer_with_a_cost_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(GENERAL).unwrap().replace(
        "[problem]",
        "cost = { kind = \"quadratic\", weight = 0.1 }\n\n[problem]",
    );
    assert!(
        text.contains("weight = 0.1"),
        "the example's layout changed"
    );
    let file = common::write(dir.path(), "q.toml", &text);
    let v = common::optimize_json(&file, &["--method", "phase", "--phases", "3"]);
    let (milp, bound) = (
        v["solver_objective"].as_f64().unwrap(),
        v["certificate"]["bound"].as_f64().unwrap(),
    );
    let j = v["objective"].as_f64().unwrap();
    assert!(
        milp <= bound + 1e-9 * bound.abs().max(1.0),
        "{milp} above {bound}"
    );
    assert!(
        (milp - j).abs() <= 1e-6,
        "the MILP's J {milp} against the replayed {j}"
    );
    common::certify_written(dir.path(), &v);
}

/// The chain's phase growth on a general problem starts from the chain's best structured gait,
/// as the crawler's does: at `K = 2` the answer is the crawler's (the travelling wave, J = 1.5,
/// `dominates_k_phases`), where the 2-phase MILP alone finds only the idle gait (J = 0). The
/// file reads back and certifies; the same gait claimed optimal among 2 phases is refused.
#[test]
fn a_general_chain_keeps_the_structured_gait_where_k_is_too_small() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["--method", "phase", "--phases", "2"];
    let general = common::optimize_json(std::path::Path::new(GENERAL), &args);
    let crawler = common::optimize_json(std::path::Path::new(CRAWLER), &args);
    for v in [&general, &crawler] {
        assert_eq!(v["status"], "dominates_k_phases", "{}", v["kind"]);
    }
    let (jg, jc) = (
        general["objective"].as_f64().unwrap(),
        crawler["objective"].as_f64().unwrap(),
    );
    assert!(
        (jg - 1.5).abs() < 1e-9 && (jc - 1.5).abs() < 1e-9,
        "{jg} {jc}"
    );
    assert_eq!(
        general["structured"]["origin"],
        crawler["structured"]["origin"]
    );
    let phases = general["solution"]["durations"].as_array().unwrap().len();
    assert!(
        phases > 4,
        "{phases} phases: the structured gait is not of the class K = 2"
    );
    common::certify_written(dir.path(), &general);
    let mut claimed = general.clone();
    claimed["status"] = "optimal_among_k_phases".into();
    let path = common::write(dir.path(), "claimed.json", &claimed.to_string());
    let out = common::crawlopt(&["certify", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("solution.durations"), "{err}");
    // The claim is the chain's, for its structured start: without either it is refused.
    for field in ["structured", "formulation"] {
        let mut v = general.clone();
        v.as_object_mut().unwrap().remove(field);
        let path = common::write(dir.path(), "tampered.json", &v.to_string());
        let out = common::crawlopt(&["certify", path.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains("status"),
            "{field}: {err}"
        );
    }
}
