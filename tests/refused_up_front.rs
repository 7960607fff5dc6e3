//! What a job cannot add to its answer is refused before the job runs, not after it: the
//! upper bound over all periodic gaits where it cannot be proven (more than four blocks, its
//! settings out of range) and the necessary conditions of a Cauchy problem (stated for
//! periodic problems only). Each refusal names the setting as the caller spells it, and the
//! job sends no event before it (no stage, no start gait, no MILP).

use crawlopt::api::{
    optimize, optimize_general_plan, Event, GaitMethod, Hooks, Naming, OptimizeSettings,
};
use crawlopt::certify::bound::BoundSettings;
use crawlopt::io::GeneralFile;
use crawlopt::model::Crawler;
use crawlopt::optimal::{Cost, GaitProblem};

/// Every method on a general problem file.
const GENERAL_METHODS: [GaitMethod; 5] = [
    GaitMethod::Discrete,
    GaitMethod::Local,
    GaitMethod::Phase,
    GaitMethod::Sequence,
    GaitMethod::Chain,
];

/// A general job's refusal under `s`, with the events it sent first.
fn general_refusal(file: &GeneralFile, s: &OptimizeSettings) -> (String, Vec<Event>) {
    let mut events = Vec::new();
    let mut on = |e: &Event, _: f64| events.push(e.clone());
    let plan = s.plan_general(&[]).unwrap();
    let hooks = Hooks {
        events: Some(&mut on),
        cancel: None,
    };
    let e = optimize_general_plan(file, &plan, s.naming, hooks)
        .unwrap_err()
        .to_string();
    (e, events)
}

/// A crawler's job's refusal of `bound` (named as a flag), with the events it sent first.
fn crawler_refusal(blocks: usize, mu_backward: f64, b: BoundSettings) -> (String, Vec<Event>) {
    let crawler = Crawler::uniform(blocks, 1.0, 1.0, mu_backward).unwrap();
    let speeds = vec![1.0; blocks - 1];
    let problem = GaitProblem::new(&crawler, 10.0, &speeds, Cost::None, None).unwrap();
    let mut events = Vec::new();
    let mut on = |e: &Event, _: f64| events.push(e.clone());
    let s = OptimizeSettings {
        bound: Some(b),
        naming: Naming::Flags,
        ..Default::default()
    };
    let hooks = Hooks {
        events: Some(&mut on),
        cancel: None,
    };
    let e = optimize(&crawler, &problem, &s, hooks)
        .unwrap_err()
        .to_string();
    (e, events)
}

/// A crawler of five blocks: the bound's grid would have 8 dimensions (at most 6), refused
/// naming the crawler's blocks before the phase growth runs; a setting out of range likewise.
#[test]
fn a_crawlers_bound_that_cannot_be_proven_is_refused_first() {
    let cases = [
        (BoundSettings::default(), "crawler.blocks"),
        (
            BoundSettings {
                resolution: Some(0),
                ..Default::default()
            },
            "--bound-resolution",
        ),
    ];
    for (b, want) in cases {
        let (e, events) = crawler_refusal(5, 1.6, b);
        assert!(e.starts_with(want), "{want}: {e}");
        assert!(events.is_empty(), "{want}: {events:?}");
    }
}

/// A grid of more than 4e6 simplices (60 x 60 on three blocks: 3.1e8) is refused naming the
/// resolution given before any method runs, for the crawler and for its general form (each
/// ran its search first, then was refused).
#[test]
fn a_bound_grid_too_large_is_refused_first() {
    let b = BoundSettings {
        resolution: Some(60),
        box_resolution: Some(60),
        ..Default::default()
    };
    let (e, events) = crawler_refusal(3, 1.5, b);
    assert!(
        e.starts_with("--bound-resolution:") && e.contains("simplices"),
        "{e}"
    );
    assert!(events.is_empty(), "{events:?}");
    let s = OptimizeSettings {
        bound: Some(b),
        naming: Naming::Flags,
        ..Default::default()
    };
    let text = std::fs::read_to_string("examples/general_three_blocks.toml").unwrap();
    let file = GeneralFile::parse(&text).unwrap();
    for method in GENERAL_METHODS {
        let s = OptimizeSettings {
            method,
            ..s.clone()
        };
        let (e, events) = general_refusal(&file, &s);
        assert!(e.starts_with("--bound-resolution:"), "{method:?}: {e}");
        assert!(events.is_empty(), "{method:?}: {events:?}");
    }
    // `analyze` says where the bound applies, as `--bound` decides it.
    for (file, applies) in [
        ("examples/general_three_blocks.toml", true),
        ("examples/general_chain20.toml", false),
    ] {
        let text = std::fs::read_to_string(file).unwrap();
        let a = crawlopt::api::analyze_general(&GeneralFile::parse(&text).unwrap()).unwrap();
        let detail = &a
            .checks
            .iter()
            .find(|c| c.name == "structure")
            .unwrap()
            .detail;
        let says = detail.contains("the chain's upper bound applies");
        assert_eq!(says, applies, "{file}: {detail}");
    }
}

/// The 20-block chain in general form: every method refuses `bound` (the problem's chain is
/// named, with its blocks) before it runs; with keywords, as Python names it.
#[test]
fn a_chains_bound_beyond_four_blocks_is_refused_by_every_method_first() {
    let text = std::fs::read_to_string("examples/general_chain20.toml").unwrap();
    let file = GeneralFile::parse(&text).unwrap();
    for method in GENERAL_METHODS {
        for (naming, want) in [(Naming::Flags, "--bound:"), (Naming::Keywords, "bound:")] {
            let s = OptimizeSettings {
                method,
                naming,
                bound: Some(BoundSettings::default()),
                ..Default::default()
            };
            let (e, events) = general_refusal(&file, &s);
            assert!(e.starts_with(want), "{method:?}: {e}");
            assert!(e.contains("crawler.blocks is 20"), "{method:?}: {e}");
            assert!(events.is_empty(), "{method:?}: {events:?}");
        }
    }
}

/// The §4 one-link problem as a Cauchy problem from x(0) = 0: `certify` is refused by each
/// method that runs on it, naming it, before the method runs (each ran, then was refused naming
/// `problem.periodic`); without `certify` each method answers.
#[test]
fn certify_on_a_cauchy_problem_is_refused_first() {
    let text = std::fs::read_to_string("examples/general_one_link.toml")
        .unwrap()
        .replace(
            "period = 10.0",
            "period = 10.0\nperiodic = false\ninitial_state = [0.0]",
        );
    let file = GeneralFile::parse(&text).unwrap();
    for method in [GaitMethod::Discrete, GaitMethod::Local, GaitMethod::Phase] {
        let s = OptimizeSettings {
            method,
            m: (method != GaitMethod::Phase).then_some(2),
            naming: Naming::Flags,
            certify: true,
            ..Default::default()
        };
        let (e, events) = general_refusal(&file, &s);
        assert!(
            e.starts_with("--certify:") && e.contains("periodic problems only"),
            "{method:?}: {e}"
        );
        assert!(events.is_empty(), "{method:?}: {events:?}");
        let s = OptimizeSettings {
            certify: false,
            ..s
        };
        let plan = s.plan_general(&[]).unwrap();
        let r = optimize_general_plan(&file, &plan, s.naming, Hooks::default()).unwrap();
        assert!(r.head.objective > 0.0, "{method:?}");
    }
}
