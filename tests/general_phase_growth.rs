//! `K` grown until the value stops improving, written once (`optimal::growth`) for the
//! crawler's phase gaits and the general problem's: the general growth against the §4
//! closed form, against the crawler's growth on crawler instances, its patience, its events
//! and cancellation, and its refusals naming the field.

use crawlopt::api::{optimize_general_phase, Event, GeneralPhaseSettings, Hooks};
use crawlopt::io::GeneralFile;
use crawlopt::model::general::GeneralCost;
use crawlopt::model::{crawler_as_general, Crawler};
use crawlopt::optimal::general::{check_problem, grow_general_phases};
use crawlopt::optimal::growth::{GrowthRange, GrowthStop};
use crawlopt::optimal::{grow_phases, Cost, GaitProblem, GrowOptions, MilpStatus};
use crawlopt::progress::Cancel;
use crawlopt::Error;

/// The paper's §4 one-link problem with `C = [-1, 1]`, `U = [-1, 1]`, `f1 = |eta| / 2`:
/// `J* = (T - 4) / 2`, reached with 4 phases and no fewer (tests/general_phase.rs).
fn one_link(period: f64) -> GeneralFile {
    GeneralFile::parse(&format!(
        "[sweeping_process]\nnormals = [[1.0], [-1.0]]\noffsets = [1.0, 1.0]\n\
         [dynamics]\nB = [[1.0]]\n\
         [control]\nlower = [-1.0]\nupper = [1.0]\nzero_mean = true\n\
         [objective]\nface_weights = [0.5, 0.5]\n\
         [problem]\nperiod = {period}\n"
    ))
    .unwrap()
}

/// The library's defaults but the general formulation (`K` phases, no free transition), whose
/// values at each `K` these tests assert; on a problem that is not a chain the default is the
/// free-transition one ([`free_transitions_reach_the_one_link_optimum_at_two_slots`]).
fn settings(edit: impl FnOnce(&mut GeneralPhaseSettings)) -> GeneralPhaseSettings {
    let mut s = GeneralPhaseSettings {
        formulation: Some(crawlopt::api::PhaseFormulation::General),
        ..GeneralPhaseSettings::default()
    };
    edit(&mut s);
    s
}

#[test]
fn the_growth_reaches_the_one_link_closed_form_at_four_phases() {
    let t = 10.0;
    let want = (t - 4.0) / 2.0;
    let r = optimize_general_phase(&one_link(t), &settings(|_| {}), Hooks::default()).unwrap();
    assert!(
        (r.head.objective - want).abs() < 1e-9,
        "{}",
        r.head.objective
    );
    let g = r.records.phase_growth.as_ref().expect("K was grown");
    let js: Vec<f64> = g.table.iter().map(|s| s.objective).collect();
    assert_eq!(g.table.len(), 4, "{js:?}");
    for (k, j) in js.iter().enumerate() {
        let closed = if k + 1 < 4 { 0.0 } else { want };
        assert!((j - closed).abs() < 1e-9, "K = {}: {j}", k + 1);
    }
    assert_eq!(g.stop, GrowthStop::MaxPhases);
    assert_eq!(r.head.certificate.phases, Some(4));
    assert_eq!(r.head.status, MilpStatus::OptimalAmongKPhases);
    // A fixed K is one MILP, with no table: the same optimum at K = 4, none below.
    let four = optimize_general_phase(
        &one_link(t),
        &settings(|s| s.phases = Some(4)),
        Hooks::default(),
    )
    .unwrap();
    assert!((four.head.objective - want).abs() < 1e-9);
    assert!(four.records.phase_growth.is_none());
    let three = optimize_general_phase(
        &one_link(t),
        &settings(|s| s.phases = Some(3)),
        Hooks::default(),
    )
    .unwrap();
    assert!(
        three.head.objective.abs() < 1e-9,
        "{}",
        three.head.objective
    );
    assert_eq!(three.head.certificate.phases, Some(3));
}

#[test]
fn patience_ends_the_growth_on_a_plateau_and_the_claim_is_the_last_k() {
    // J_4 = J_5 = J_6 = 3: with patience 2 the growth stops at K = 6, and the best gait (found
    // at K = 4) is claimed for K = 6, the largest K proven.
    let s = settings(|s| {
        s.max_phases = Some(10);
        s.patience = 2;
    });
    let r = optimize_general_phase(&one_link(10.0), &s, Hooks::default()).unwrap();
    let g = r.records.phase_growth.as_ref().unwrap();
    assert_eq!(g.stop, GrowthStop::NoGain);
    assert_eq!(g.table.len(), 6);
    assert_eq!(r.head.certificate.phases, Some(6));
    assert_eq!(r.solution.as_phase().unwrap().max_phases, 6);
    assert!((r.head.objective - 3.0).abs() < 1e-9);
    assert!(r.solution.as_phase().unwrap().certificate.bound >= r.head.objective - 1e-9);
}

#[test]
fn each_k_is_an_event_and_a_cancelled_job_stops() {
    let mut solved = Vec::new();
    let mut stages = 0;
    let mut on = |e: &Event, _: f64| match e {
        Event::PhaseSolved { step, start } => {
            assert!(!start);
            solved.push(step.phases)
        }
        Event::Stage(_) => stages += 1,
        _ => {}
    };
    let hooks = Hooks {
        events: Some(&mut on),
        cancel: None,
    };
    let r = optimize_general_phase(&one_link(10.0), &settings(|_| {}), hooks).unwrap();
    assert_eq!(solved, vec![1, 2, 3, 4]);
    assert_eq!(stages, 1);
    assert_eq!(r.records.phase_growth.unwrap().table.len(), solved.len());
    let cancel = Cancel::new();
    cancel.cancel();
    let hooks = Hooks {
        events: None,
        cancel: Some(&cancel),
    };
    match optimize_general_phase(&one_link(10.0), &settings(|_| {}), hooks) {
        Err(Error::Cancelled) => {}
        other => panic!("not cancelled: {other:?}"),
    }
}

#[test]
fn bad_settings_are_refused_naming_the_field() {
    let cases: Vec<(GeneralPhaseSettings, &str)> = vec![
        (settings(|s| s.phases = Some(0)), "phases"),
        (settings(|s| s.phases = Some(1000)), "phases"),
        (settings(|s| s.max_phases = Some(0)), "max_phases"),
        (settings(|s| s.max_phases = Some(1000)), "max_phases"),
        (settings(|s| s.patience = 0), "patience"),
        (settings(|s| s.time_limit = Some(-1.0)), "time_limit"),
    ];
    for (s, want) in cases {
        match optimize_general_phase(&one_link(10.0), &s, Hooks::default()) {
            Err(Error::InvalidParameter { field, .. }) => assert_eq!(field, want, "{s:?}"),
            other => panic!("{s:?} not refused: {other:?}"),
        }
    }
}

/// On crawler instances the general growth (K phases) and the crawler's (K slip phases, a
/// transition free before each) run the same loop over their own MILPs: crawler(K) =
/// general(2K) on these instances (tests/general_phase.rs), the general table never
/// decreases, and both stop for the same reason at the matching K.
#[test]
fn on_crawler_instances_both_growths_agree() {
    let cases = [
        Crawler::new(vec![1.0], vec![1.0, 1.0], vec![2.0, 2.0]).unwrap(),
        Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap(),
    ];
    for crawler in cases {
        let t = 6.0;
        let speed = vec![1.0; crawler.links()];
        let gp = GaitProblem::new(&crawler, t, &speed, Cost::None, None).unwrap();
        let chain = grow_phases(
            &crawler,
            &gp,
            &GrowOptions {
                max_phases: 3,
                patience: 3,
                ..GrowOptions::default()
            },
            &mut |_| {},
        )
        .unwrap();
        let inst = crawler_as_general(&crawler, t, &gp.rate_bound, GeneralCost::None).unwrap();
        let g = check_problem(&inst.problem).unwrap();
        let range = GrowthRange {
            min_phases: 1,
            max_phases: 6,
            patience: 6,
        };
        let general = grow_general_phases(&inst.problem, &g, range, &mut |_| {}).unwrap();
        assert_eq!(chain.table.len(), 3);
        assert_eq!(general.table.len(), 6);
        for w in general.table.windows(2) {
            assert!(
                w[1].objective >= w[0].objective - 1e-9,
                "{:?}",
                general.table
            );
        }
        for (k, step) in chain.table.iter().enumerate() {
            let twice = &general.table[2 * k + 1];
            assert_eq!(twice.phases, 2 * (k + 1));
            assert!(
                (twice.objective - step.objective).abs() < 1e-7,
                "N = {}, K = {}: general {} vs crawler {}",
                crawler.blocks(),
                k + 1,
                twice.objective,
                step.objective
            );
        }
        assert_eq!(chain.stop, general.stop);
        assert!((general.best.objective - chain.best.objective()).abs() < 1e-7);
    }
}

/// The free-transition formulation through the API (`formulation = Transitions`): the growth
/// reaches the §4 one-link optimum at `K = 2` slots (4 phases; the general formulation needs
/// `K = 4`), says `formulation = "transitions"`, reads back and certifies (`holds`); the same
/// file without its formulation is refused (4 phases for `K = 2`), naming the field. On this
/// problem, which is not a chain, it is the default: the library's default settings give the
/// same growth.
#[test]
fn free_transitions_reach_the_one_link_optimum_at_two_slots() {
    use crawlopt::api::PhaseFormulation;
    use crawlopt::io::ResultFile;
    let t = 10.0;
    let want = (t - 4.0) / 2.0;
    let s = settings(|s| s.formulation = Some(PhaseFormulation::Transitions));
    let r = optimize_general_phase(&one_link(t), &s, Hooks::default()).unwrap();
    assert!(
        (r.head.objective - want).abs() < 1e-9,
        "{}",
        r.head.objective
    );
    assert_eq!(r.formulation.as_deref(), Some("transitions"));
    let g = r.records.phase_growth.as_ref().expect("K was grown");
    let js: Vec<f64> = g.table.iter().map(|s| s.objective).collect();
    assert!(js[0].abs() < 1e-9 && (js[1] - want).abs() < 1e-9, "{js:?}");
    let default = optimize_general_phase(
        &one_link(t),
        &GeneralPhaseSettings::default(),
        Hooks::default(),
    )
    .unwrap();
    assert_eq!(default.formulation.as_deref(), Some("transitions"));
    let default_js: Vec<f64> = default
        .records
        .phase_growth
        .as_ref()
        .unwrap()
        .table
        .iter()
        .map(|s| s.objective)
        .collect();
    assert_eq!(default_js, js);
    let fixed = settings(|s| {
        s.formulation = Some(PhaseFormulation::Transitions);
        s.phases = Some(2);
        s.certify = true;
    });
    let two = optimize_general_phase(&one_link(t), &fixed, Hooks::default()).unwrap();
    assert!((two.head.objective - want).abs() < 1e-9);
    assert_eq!(two.solution.as_phase().unwrap().durations.len(), 4);
    let verdict = two.necessary_conditions.as_ref().map(|c| c.verdict);
    assert_eq!(verdict, Some(crawlopt::certify::Verdict::Holds));
    let text = serde_json::to_string(&two).unwrap();
    let back = ResultFile::from_json(&text, "two.json").unwrap();
    assert!((back.head().objective - want).abs() < 1e-9);
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v.as_object_mut().unwrap().remove("formulation");
    let e = ResultFile::from_json(&v.to_string(), "two.json").unwrap_err();
    assert!(e.to_string().contains("solution.durations"), "{e}");
}

/// In a growth every row's bound is at least the `J` of every earlier row (the classes of gaits
/// of at most `K` phases are nested: an earlier gait is one of the later class), so a general
/// result whose table says otherwise is refused naming the row, as a crawler's is (one table
/// check for both, `optimal::consistency::check_table`). The edited table keeps its best value
/// the answer's and every value under its own bound: only the order is wrong.
#[test]
fn a_growth_whose_optimum_falls_with_k_is_refused() {
    let r = optimize_general_phase(&one_link(10.0), &settings(|_| {}), Hooks::default()).unwrap();
    let text = serde_json::to_string(&r).unwrap();
    assert!(crawlopt::io::ResultFile::from_json(&text, "r").is_ok());
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let bound = v["phase_growth"]["table"][2]["bound"].as_f64().unwrap();
    assert!(bound < 0.5, "{bound}");
    let row = &mut v["phase_growth"]["table"][1];
    row["objective"] = 0.5.into();
    row["bound"] = 0.5.into();
    match crawlopt::io::ResultFile::from_json(&v.to_string(), "r") {
        Err(Error::InvalidParameter { field, reason, .. }) => {
            assert!(field.ends_with("phase_growth.table[2]"), "{field}");
            assert!(reason.contains("smaller class"), "{reason}");
        }
        other => panic!("not refused: {other:?}"),
    }
}
