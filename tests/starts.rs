//! The start policies of the local methods and of the P_m MILP (`crawlopt::optimal::start`).

use crawlopt::optimal::{
    discrete_start, phase_start, shifted_origin, Cost, GaitProblem, GrowOptions, StartEvent,
    StartGait,
};
use crawlopt::{Crawler, Error};

fn three_blocks(cost: Cost, tv: Option<f64>) -> (Crawler, GaitProblem) {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], cost, tv).unwrap();
    (c, p)
}

/// The events of a policy, as text.
fn record(events: &mut Vec<String>) -> impl FnMut(StartEvent) + '_ {
    |e| {
        events.push(match e {
            StartEvent::Stage(s) => format!("stage {s}"),
            StartEvent::Phase(st) => format!("phase {} {}", st.phases, st.objective),
            StartEvent::Note(s) => format!("note {s}"),
        })
    }
}

#[test]
fn the_phase_start_stops_at_the_first_k_without_a_gain() {
    // Three blocks: J_K = 0, 0, 13/6, 2.6, 2.6 for K = 1..5. A start need not be certified, so
    // the growth stops at K = 5, the first without a gain; the gait is certified among gaits of
    // at most 5 slip phases, which its origin names.
    let (c, p) = three_blocks(Cost::None, None);
    let mut events = Vec::new();
    let s = phase_start(&c, &p, &GrowOptions::default(), &mut record(&mut events)).unwrap();
    assert!(
        (s.result.head.objective - 2.6).abs() < 1e-8,
        "{}",
        s.result.head.objective
    );
    assert_eq!(s.origin, "phase (K = 5)");
    assert_eq!(s.result.head.method, "phase");
    assert_eq!(events[0], "stage start: phase gait, K = 1");
    let ks: Vec<&str> = events[1..]
        .iter()
        .map(|e| e.split(' ').nth(1).unwrap())
        .collect();
    assert_eq!(ks, ["1", "2", "3", "4", "5"], "{events:?}");
    assert_eq!(s.times().len(), s.lengths().len());
}

#[test]
fn the_discrete_start_is_the_local_optimum_under_a_time_limit() {
    let (c, p) = three_blocks(Cost::None, None);
    let limited = GrowOptions {
        time_limit: Some(60.0),
        ..GrowOptions::default()
    };
    let mut events = Vec::new();
    let s = discrete_start(&c, &p, 3, 8, &limited, &mut record(&mut events))
        .unwrap()
        .expect("a start under a time limit");
    assert!(
        s.origin.starts_with("local on P_3, from phase (K = 5)"),
        "{}",
        s.origin
    );
    assert_eq!(s.result.head.method, "local");
    // The local method reaches P_3's global optimum, 2 (tests/discrete.rs), from the phase gait.
    assert!(
        (s.result.head.objective - 2.0).abs() < 1e-8,
        "{}",
        s.result.head.objective
    );
    assert!(
        events
            .iter()
            .any(|e| e == "stage start: local LPCC method on P_3"),
        "{events:?}"
    );
    assert!(!events.iter().any(|e| e.starts_with("note")), "{events:?}");

    // Without a time limit, or with a TV bound phase gaits cannot express: no start.
    let none = discrete_start(&c, &p, 3, 8, &GrowOptions::default(), &mut |_| {}).unwrap();
    assert_eq!(none, None);
    let (c_tv, p_tv) = three_blocks(Cost::None, Some(4.0));
    let none = discrete_start(&c_tv, &p_tv, 3, 8, &limited, &mut |_| {}).unwrap();
    assert_eq!(none, None);

    // A quadratic cost: the local method has none, so the phase gait is the start.
    let (c_q, p_q) = three_blocks(Cost::Quadratic { weight: 0.1 }, None);
    let s = discrete_start(&c_q, &p_q, 3, 8, &limited, &mut |_| {})
        .unwrap()
        .expect("a start");
    assert_eq!(s.result.head.method, "phase");
    assert!(s.origin.starts_with("phase (K = "), "{}", s.origin);
}

#[test]
fn a_start_that_cannot_be_had_is_a_note_not_an_error() {
    // A limit too short for any phase gait: the MILP goes on without a start, and says so.
    let (c, p) = three_blocks(Cost::None, None);
    let short = GrowOptions {
        time_limit: Some(1e-6),
        ..GrowOptions::default()
    };
    let mut events = Vec::new();
    let s = discrete_start(&c, &p, 3, 8, &short, &mut record(&mut events)).unwrap();
    assert_eq!(s, None);
    assert!(
        events.iter().any(|e| e.starts_with("note no start gait")),
        "{events:?}"
    );
    // The local methods cannot go on without one: there it is a time-limit error.
    let e = phase_start(&c, &p, &short, &mut |_| {}).unwrap_err();
    assert!(matches!(e, Error::TimeLimit(_)), "{e}");
    // Bad options are errors, not notes.
    let limited = GrowOptions {
        time_limit: Some(60.0),
        ..GrowOptions::default()
    };
    let e = discrete_start(&c, &p, 3, 0, &limited, &mut |_| {}).unwrap_err();
    assert!(e.to_string().starts_with("shifts"), "{e}");
    for bad in [
        GrowOptions {
            max_phases: 0,
            ..limited.clone()
        },
        GrowOptions {
            patience: 0,
            ..limited.clone()
        },
        GrowOptions {
            time_limit: Some(-1.0),
            ..limited.clone()
        },
    ] {
        let mut events = Vec::new();
        assert!(discrete_start(&c, &p, 3, 8, &bad, &mut record(&mut events)).is_err());
        assert!(events.is_empty(), "{events:?}");
    }
}

#[test]
fn a_stored_start_must_be_of_this_crawler_and_period() {
    let (c, p) = three_blocks(Cost::None, None);
    let s = phase_start(&c, &p, &GrowOptions::default(), &mut |_| {}).unwrap();
    let again = StartGait::from_result(&c, &p, s.result.clone(), "a.json").unwrap();
    assert_eq!(again.origin, "phase (a.json)");
    let c4 = Crawler::uniform(4, 1.0, 1.0, 1.5).unwrap();
    let p4 = GaitProblem::new(&c4, 10.0, &[1.0; 3], Cost::None, None).unwrap();
    let e = StartGait::from_result(&c4, &p4, s.result.clone(), "a.json").unwrap_err();
    assert!(e.to_string().starts_with("start"), "{e}");
    let p_long = GaitProblem::new(&c, 20.0, &[1.0, 1.0], Cost::None, None).unwrap();
    assert!(StartGait::from_result(&c, &p_long, s.result, "a.json").is_err());
    assert_eq!(shifted_origin("phase (K = 5)", 0.0), "phase (K = 5)");
    assert_eq!(
        shifted_origin("phase (K = 5)", 1.25),
        "phase (K = 5) shifted by 1.25"
    );
}
