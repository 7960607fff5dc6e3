//! The table of P_1..P_m (paper §5: the optima of P_m converge to that of (P)) written once
//! (`optimal::refinement`) for the crawler's P_m and the general problem's: the general table
//! against the §4 closed form, against the crawler's table on a crawler instance, its first
//! row on a stiff drift, its events, and its consistency when a result file is read back.

use crawlopt::api::{optimize_general, Event, GeneralPmSettings, Hooks};
use crawlopt::io::{GeneralFile, ResultFile};
use crawlopt::model::general::GeneralCost;
use crawlopt::model::{crawler_as_general, Crawler};
use crawlopt::optimal::general::{check_problem, general_convergence};
use crawlopt::optimal::{discrete_convergence, Cost, GaitProblem, MilpStatus};
use crawlopt::Error;

fn one_link() -> GeneralFile {
    GeneralFile::parse(&std::fs::read_to_string("examples/general_one_link.toml").unwrap()).unwrap()
}

fn settings(m: u32) -> GeneralPmSettings {
    GeneralPmSettings {
        m,
        convergence: true,
        ..GeneralPmSettings::default()
    }
}

#[test]
fn the_one_link_table_is_the_closed_form_at_every_m() {
    // The optimal square wave (u = 1 for T/2, then -1) lies on every grid, so J_m = J* = 3.
    let r = optimize_general(&one_link(), &settings(4), Hooks::default()).unwrap();
    let table = r.records.convergence.as_ref().expect("a table was asked");
    assert_eq!(table.iter().map(|r| r.m).collect::<Vec<_>>(), [1, 2, 3, 4]);
    for row in table {
        assert_eq!(row.steps, 1 << row.m);
        assert!(
            (row.objective - 3.0).abs() < 1e-9,
            "m = {}: {}",
            row.m,
            row.objective
        );
        assert_eq!(row.status, MilpStatus::Optimal);
    }
    assert_eq!(r.solution.as_pm().unwrap().m, 4);
    assert!((r.head.objective - 3.0).abs() < 1e-9);
    // Without the flag, one MILP and no table.
    let one =
        optimize_general(&one_link(), &GeneralPmSettings::default(), Hooks::default()).unwrap();
    assert!(one.records.convergence.is_none());
}

/// On a crawler instance the general table is the crawler's, row by row: one loop over two
/// formulations of the same P_m.
#[test]
fn on_a_crawler_instance_the_two_tables_agree() {
    let crawler = Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap();
    let t = 6.0;
    let gp = GaitProblem::new(&crawler, t, &[1.0, 1.0], Cost::None, None).unwrap();
    let (chain, _) = discrete_convergence(&crawler, &gp, 3, &mut |_| {}).unwrap();
    let inst = crawler_as_general(&crawler, t, &gp.rate_bound, GeneralCost::None).unwrap();
    let g = check_problem(&inst.problem).unwrap();
    let (general, finest) = general_convergence(&inst.problem, &g, 3, true, &mut |_| {}).unwrap();
    assert_eq!(chain.len(), 3);
    assert_eq!(general.len(), 3);
    for (a, b) in chain.iter().zip(&general) {
        assert_eq!(a.m, b.m);
        assert!(
            (a.objective - b.objective).abs() < 1e-7,
            "m = {}: crawler {} vs general {}",
            a.m,
            a.objective,
            b.objective
        );
    }
    assert_eq!(finest.m, 3);
}

#[test]
fn a_stiff_drift_starts_the_table_at_its_first_stable_grid() {
    // A = -0.5 I with T = 10: P_1's step h = 5 is beyond the explicit limit (h |A| = 2.5 > 2),
    // P_2's is not (tests/cli_general.rs), so the table starts at m = 2.
    let f = GeneralFile::parse(&std::fs::read_to_string("examples/general_drift.toml").unwrap())
        .unwrap();
    let r = optimize_general(&f, &settings(3), Hooks::default()).unwrap();
    let ms: Vec<u32> = r.records.convergence.unwrap().iter().map(|r| r.m).collect();
    assert_eq!(ms, [2, 3]);
    match optimize_general(&f, &settings(1), Hooks::default()) {
        Err(Error::InvalidParameter { field, .. }) => assert_eq!(field, "m"),
        other => panic!("not refused: {other:?}"),
    }
}

#[test]
fn each_row_is_an_event() {
    let mut rows = Vec::new();
    let mut on = |e: &Event, _: f64| {
        if let Event::DiscreteSolved(row) = e {
            rows.push(row.m);
        }
    };
    let hooks = Hooks {
        events: Some(&mut on),
        cancel: None,
    };
    let r = optimize_general(&one_link(), &settings(3), hooks).unwrap();
    assert_eq!(rows, [1, 2, 3]);
    assert_eq!(r.records.convergence.unwrap().len(), 3);
}

#[test]
fn a_result_file_with_a_changed_table_is_refused() {
    let r = optimize_general(&one_link(), &settings(3), Hooks::default()).unwrap();
    let text = serde_json::to_string(&r).unwrap();
    assert!(ResultFile::from_json(&text, "r").is_ok());
    let edit = |f: &dyn Fn(&mut serde_json::Value)| {
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        f(&mut v);
        match ResultFile::from_json(&v.to_string(), "r") {
            Err(Error::InvalidParameter { field, .. }) => field,
            other => panic!("not refused: {other:?}"),
        }
    };
    let field = edit(&|v| v["convergence"][2]["objective"] = 2.5.into());
    assert!(field.ends_with("convergence"), "{field}");
    let field = edit(&|v| v["convergence"][1]["m"] = 1.into());
    assert!(field.contains("convergence[1]"), "{field}");
    let field = edit(&|v| v["convergence"][0]["bound"] = 1.0.into());
    assert!(field.contains("convergence[0]"), "{field}");
    let field = edit(&|v| {
        v["convergence"].as_array_mut().unwrap().pop();
    });
    assert!(field.ends_with("convergence"), "{field}");
}

/// The job's time limit is the API's to check (the solvers take none; they run within the
/// deadline the job sets): a limit that is not positive and finite is refused naming
/// `time_limit`, with and without the table, before any P_m is solved.
#[test]
fn a_bad_time_limit_is_refused_by_the_job() {
    for convergence in [true, false] {
        for t in [-1.0, 0.0, f64::NAN, f64::INFINITY] {
            let s = GeneralPmSettings {
                time_limit: Some(t),
                convergence,
                ..settings(3)
            };
            match optimize_general(&one_link(), &s, Hooks::default()) {
                Err(Error::InvalidParameter { field, .. }) => assert_eq!(field, "time_limit"),
                other => panic!("{t} not refused: {other:?}"),
            }
        }
    }
}
