//! The library's job API (`crawlopt::api`): defaults and option applicability decided by the
//! library (not by a front end), messages in the caller's naming, events, notes and
//! cancellation, and the numbers of the paper's examples through it.

use crawlopt::api::{
    self, optimize, Event, GaitMethod, Hooks, Naming, OptimizeSettings, Start, DEFAULT_M_DISCRETE,
    DEFAULT_M_LOCAL, DEFAULT_SHIFTS,
};
use crawlopt::io::ModelFile;
use crawlopt::optimal::{Cost, GaitProblem};
use crawlopt::progress::Cancel;
use crawlopt::{Crawler, Error};

fn model(name: &str) -> (Crawler, GaitProblem) {
    let m = ModelFile::load(format!("examples/{name}.toml").as_ref()).unwrap();
    api::gait_problem(&m).unwrap()
}

fn with_tv(mut p: GaitProblem) -> GaitProblem {
    p.max_total_variation = Some(40.0);
    p
}

#[test]
fn defaults_are_the_library_s() {
    let (c, p) = model("one_link_gait");
    let plan = |s: OptimizeSettings, p: &GaitProblem| s.plan(&c, p).unwrap();
    let auto = plan(OptimizeSettings::default(), &p);
    assert_eq!(auto.method, GaitMethod::Phase);
    assert!(auto.certified_growth);
    assert_eq!((auto.growth.max_phases, auto.growth.patience), (8, 2));
    // A total-variation bound makes auto the discrete P_m (phase gaits cannot express it).
    let tv = plan(OptimizeSettings::default(), &with_tv(p.clone()));
    assert_eq!(
        (tv.method, tv.m),
        (GaitMethod::Discrete, DEFAULT_M_DISCRETE)
    );
    let local = OptimizeSettings {
        method: GaitMethod::Local,
        ..Default::default()
    };
    let local = plan(local, &p);
    assert_eq!((local.m, local.shifts), (DEFAULT_M_LOCAL, DEFAULT_SHIFTS));
    assert!(!local.certified_growth);
    let given = OptimizeSettings {
        method: GaitMethod::Phase,
        patience: Some(3),
        max_phases: Some(5),
        time_limit: Some(9.0),
        ..Default::default()
    };
    let given = plan(given, &p);
    assert_eq!(
        (
            given.growth.patience,
            given.growth.max_phases,
            given.growth.time_limit
        ),
        (3, 5, Some(9.0))
    );
}

#[test]
fn options_that_do_not_apply_are_refused_in_the_caller_s_naming() {
    let (c, p) = model("one_link_gait");
    let refused = |s: OptimizeSettings, p: &GaitProblem| match s.plan(&c, p) {
        Err(Error::InvalidParameter { field, reason, .. }) => (field, reason),
        other => panic!("{other:?}"),
    };
    let s = OptimizeSettings {
        method: GaitMethod::Phase,
        start: Some(Start::File("x.json".into())),
        ..Default::default()
    };
    let (field, reason) = refused(s.clone(), &p);
    assert_eq!(field, "start");
    assert_eq!(
        reason,
        "applies to method=\"local\", \"sequence\" and \"discrete\" only"
    );
    let flags = OptimizeSettings {
        naming: Naming::Flags,
        ..s
    };
    assert_eq!(
        refused(flags, &p).1,
        "applies to --method local, sequence and discrete only"
    );
    // max_phases applies to a growth of K; with `phases` fixed nothing grows.
    let s = OptimizeSettings {
        phases: Some(3),
        max_phases: Some(5),
        ..Default::default()
    };
    let (field, reason) = refused(s.clone(), &p);
    assert_eq!(field, "max_phases");
    assert!(
        reason.starts_with("applies only to a growth of K"),
        "{reason}"
    );
    assert!(reason.contains("without phases"), "{reason}");
    let flags = OptimizeSettings {
        naming: Naming::Flags,
        ..s
    };
    let (field, reason) = refused(flags, &p);
    assert_eq!(field, "--max-phases");
    assert!(reason.contains("without --phases"), "{reason}");
    // shifts: the local method only; with a quadratic cost discrete's start is no local one.
    let quadratic = GaitProblem {
        cost: Cost::Quadratic { weight: 0.5 },
        ..p.clone()
    };
    let s = OptimizeSettings {
        method: GaitMethod::Discrete,
        time_limit: Some(5.0),
        shifts: Some(2),
        ..Default::default()
    };
    assert!(s.plan(&c, &p).is_ok());
    assert_eq!(refused(s, &quadratic).0, "shifts");
    // Method-specific options.
    let s = OptimizeSettings {
        method: GaitMethod::Discrete,
        phases: Some(2),
        ..Default::default()
    };
    assert_eq!(
        refused(s, &p),
        ("phases".into(), "applies to method=\"phase\" only".into())
    );
    let s = OptimizeSettings {
        m: Some(3),
        ..Default::default()
    };
    assert_eq!(refused(s, &p).0, "m");
    let s = OptimizeSettings {
        method: GaitMethod::Discrete,
        m: Some(0),
        ..Default::default()
    };
    assert!(refused(s, &p).1.contains("at least 1"));
    // Values are checked before any solve.
    let s = OptimizeSettings {
        time_limit: Some(-1.0),
        ..Default::default()
    };
    assert_eq!(refused(s, &p).0, "time_limit");
    assert_eq!(
        GaitMethod::from_name("sequence").unwrap(),
        GaitMethod::Sequence
    );
    assert!(GaitMethod::from_name("fast").is_err());
    // Every method is read back from its name, and a refusal lists every name in the order
    // front ends list them (the command line's `--method` values are these names).
    for m in GaitMethod::ALL {
        assert_eq!(GaitMethod::from_name(m.name()).unwrap(), m);
        assert!(!m.summary().is_empty(), "{}", m.name());
    }
    // One reader of an integration method's name for every front end (Python's spelling
    // `catching_up` too), refusing another naming `method`.
    use crawlopt::integrate::Method;
    for m in Method::ALL {
        assert_eq!(Method::from_name(m.name()).unwrap(), m);
        assert_eq!(m.to_string(), m.name());
    }
    assert_eq!(
        Method::from_name("catching_up").unwrap(),
        Method::CatchingUp
    );
    match Method::from_name("rk4").unwrap_err() {
        Error::InvalidParameter { field, reason, .. } => {
            assert_eq!(field, "method");
            assert_eq!(reason, "must be \"exact\" or \"catching-up\"");
        }
        other => panic!("{other:?}"),
    }
    let names: Vec<&str> = GaitMethod::ALL.iter().map(|m| m.name()).collect();
    let refusal = GaitMethod::from_name("fast").unwrap_err().to_string();
    assert!(
        refusal.contains(&format!("must be one of {}", names.join(", "))),
        "{refusal}"
    );
}

#[test]
fn the_three_block_optimum_with_its_events() {
    // The peers' instance (examples/three_blocks_gait.toml): J* = 2.6 among phase gaits, K
    // grown until two K bring no gain.
    let (c, p) = model("three_blocks_gait");
    let mut events = Vec::new();
    let mut on = |e: &Event, t: f64| events.push((e.clone(), t));
    let best = optimize(
        &c,
        &p,
        &OptimizeSettings {
            certify: true,
            ..Default::default()
        },
        Hooks {
            events: Some(&mut on),
            cancel: None,
        },
    )
    .unwrap();
    assert!((best.result.head.objective - 2.6).abs() < 1e-8);
    assert_eq!(best.result.head.method, "phase");
    assert!(best.necessary_conditions.is_some());
    let solved: Vec<usize> = events
        .iter()
        .filter_map(|(e, _)| match e {
            Event::PhaseSolved { step, start: false } => Some(step.phases),
            _ => None,
        })
        .collect();
    let growth = best.result.records.phase_growth.as_ref().unwrap();
    assert_eq!(solved.len(), growth.table.len());
    assert_eq!(solved, (1..=solved.len()).collect::<Vec<_>>());
    // Events come in time order, each stamped with the seconds since the job began.
    assert!(events.windows(2).all(|w| w[0].1 <= w[1].1));
    assert!(matches!(events[0].0, Event::Stage(_)));
}

/// The sequence method with K below the slip phases of its default start (the phase optimum,
/// 4 slip phases here) starts from a gait grown to at most K phases, where it was refused; the
/// structured gait (6 slip phases) is not its start. Here the growth reaches K = 3, so the
/// answer is at least the 3-phase MILP's optimum 13/6, with at most 3 slip phases.
#[test]
fn the_sequence_method_below_its_default_start_s_phases_starts_at_k() {
    let (c, p) = model("three_blocks_gait");
    let run = |method, phases| {
        let s = OptimizeSettings {
            method,
            phases: Some(phases),
            ..Default::default()
        };
        optimize(&c, &p, &s, Hooks::default()).unwrap().result
    };
    let milp = run(GaitMethod::Phase, 3);
    assert!(
        (milp.head.objective - 13.0 / 6.0).abs() < 1e-8,
        "{}",
        milp.head.objective
    );
    let seq = run(GaitMethod::Sequence, 3);
    assert_eq!(seq.head.method, "sequence");
    assert!(
        seq.head.objective >= milp.head.objective - 1e-9,
        "{}",
        seq.head.objective
    );
    assert!(crawlopt::optimal::slip_sequence(&seq.gait.slip).len() <= 3);
}

#[test]
fn the_one_link_closed_form_through_analyze_and_optimize() {
    // theory §10: J* = (a T - 2 w) / (2 k) = 3.
    let m = ModelFile::load("examples/one_link_gait.toml".as_ref()).unwrap();
    let a = api::analyze(&m).unwrap();
    let closed = a.gait.unwrap().one_link_optimum.unwrap().value;
    assert!((closed - 3.0).abs() < 1e-12);
    let (c, p) = api::gait_problem(&m).unwrap();
    let best = optimize(&c, &p, &OptimizeSettings::default(), Hooks::default()).unwrap();
    assert!((best.result.head.objective - closed).abs() < 1e-8);
}

#[test]
fn a_cancelled_job_stops_with_cancelled() {
    let (c, p) = model("three_blocks_gait");
    let cancel = Cancel::new();
    cancel.cancel();
    let r = optimize(
        &c,
        &p,
        &OptimizeSettings::default(),
        Hooks {
            events: None,
            cancel: Some(&cancel),
        },
    );
    assert_eq!(r, Err(Error::Cancelled));
}

#[test]
fn a_start_in_memory_is_checked_and_recorded() {
    let (c, p) = model("three_blocks_gait");
    let phase = optimize(
        &c,
        &p,
        &OptimizeSettings {
            method: GaitMethod::Phase,
            phases: Some(3),
            ..Default::default()
        },
        Hooks::default(),
    )
    .unwrap()
    .result;
    let s = OptimizeSettings {
        method: GaitMethod::Sequence,
        start: Some(Start::Result {
            result: Box::new(phase.clone().into()),
            name: "k3".into(),
        }),
        phases: Some(4),
        ..Default::default()
    };
    let seq = optimize(&c, &p, &s, Hooks::default()).unwrap().result;
    assert!(
        (seq.head.objective - 2.6).abs() < 1e-8,
        "{}",
        seq.head.objective
    );
    // A start of another crawler is refused, naming the start.
    let (c2, p2) = model("one_link_gait");
    match optimize(&c2, &p2, &s, Hooks::default()) {
        Err(Error::InvalidParameter { field, value, .. }) => {
            assert_eq!((field.as_str(), value.as_str()), ("start", "k3"))
        }
        other => panic!("{other:?}"),
    }
}

/// Issue 30, item 5: the periodicity tolerance is bounded above (`MAX_TOL`), for the crawler's
/// and the general simulators alike; `tol = 0.5` took the first period of a transient for the
/// orbit (J = 1.833 against 1.914 on `three_blocks_sine.toml`).
#[test]
fn a_tolerance_beyond_max_tol_is_refused_naming_tol() {
    use crawlopt::integrate::{GeneralSimOptions, SimOptions, MAX_TOL};
    let m = ModelFile::load("examples/three_blocks_sine.toml".as_ref()).unwrap();
    let crawler = m.crawler().unwrap();
    let act = m.actuation(crawler.links()).unwrap();
    for tol in [
        0.5,
        1e300,
        2.0 * MAX_TOL,
        0.0,
        -1.0,
        f64::NAN,
        f64::INFINITY,
    ] {
        let opts = SimOptions {
            tol,
            ..SimOptions::DEFAULT
        };
        let e = opts.check().unwrap_err().to_string();
        assert!(e.starts_with("tol: must be in (0, 1e-3]"), "{tol}: {e}");
        let e = crawlopt::integrate::simulate(&crawler, &act, &opts).unwrap_err();
        assert!(e.to_string().starts_with("tol: "), "{tol}: {e}");
        let g = GeneralSimOptions {
            tol,
            ..GeneralSimOptions::default()
        };
        assert!(g.check(1).unwrap_err().to_string().starts_with("tol: "));
    }
    let opts = SimOptions {
        tol: MAX_TOL,
        ..SimOptions::DEFAULT
    };
    let s = crawlopt::integrate::simulate(&crawler, &act, &opts).unwrap();
    let j = s.displacement_per_period.unwrap();
    assert!((j - 1.914213562).abs() < 1e-8, "J = {j}");
}

/// The settings as a table of keys (a sweep file's `[settings]`, Python's keywords) are the
/// struct's own fields: every key read into its field, the flags' dashed spellings of
/// `max_phases` and `time_limit` too; a refused value names its key and shows it; a key of no
/// setting (and `start`, `naming`, which the caller sets) names `settings`; `bound` is `true`,
/// `false` or a table of the bound's settings, each named by its path.
#[test]
fn settings_from_keys_are_the_fields() {
    use crawlopt::api::PhaseFormulation;
    let keys = |text: &str| -> toml::Table { toml::from_str(text).unwrap() };
    let all = keys(
        "method = \"phase\"\nphases = 3\npatience = 2\nmax-phases = 7\nm = 4\nconvergence = true\n\
         shifts = 5\ntime-limit = 2.5\ncertify = true\npolish = false\nformulation = \"general\"",
    );
    let by_hand = OptimizeSettings {
        method: GaitMethod::Phase,
        phases: Some(3),
        patience: Some(2),
        max_phases: Some(7),
        m: Some(4),
        convergence: true,
        shifts: Some(5),
        time_limit: Some(2.5),
        certify: true,
        polish: Some(false),
        formulation: Some(PhaseFormulation::General),
        ..Default::default()
    };
    assert_eq!(OptimizeSettings::from_keys(&all).unwrap(), by_hand);
    assert_eq!(
        OptimizeSettings::from_keys(&toml::Table::new()).unwrap(),
        OptimizeSettings::default()
    );
    // The bound: true (its defaults), false (none), or a table of its settings.
    use crawlopt::certify::bound::BoundSettings;
    for (text, bound) in [
        ("bound = true", Some(BoundSettings::default())),
        ("bound = false", None),
        (
            "bound = { resolution = 16, time_limit = 5 }",
            Some(BoundSettings {
                resolution: Some(16),
                time_limit: Some(5.0),
                ..Default::default()
            }),
        ),
    ] {
        assert_eq!(
            OptimizeSettings::from_keys(&keys(text)).unwrap().bound,
            bound,
            "{text}"
        );
    }
    // A value of the wrong type is an `Error::WrongType` (Python's TypeError), as serde found
    // it; any other refusal an `InvalidParameter`. Both name the key and show its value.
    for (text, field, value, wrong_type) in [
        ("m = -3", "m", "-3", false),
        ("m = \"a\"", "m", "\"a\"", true),
        ("method = \"fast\"", "method", "\"fast\"", false),
        ("method = 3", "method", "3", true),
        ("formulation = \"best\"", "formulation", "\"best\"", false),
        ("certify = 1", "certify", "1", true),
        ("time_limit = \"1s\"", "time_limit", "\"1s\"", true),
        ("mm = 3", "settings", "the table given", false),
        ("start = \"r.json\"", "settings", "the table given", false),
        ("bound = 3", "bound", "3", true),
        ("bound = { grid = 4 }", "bound.grid", "4", false),
        (
            "bound = { resolution = -1 }",
            "bound.resolution",
            "-1",
            false,
        ),
        (
            "bound = { resolution = \"fine\" }",
            "bound.resolution",
            "\"fine\"",
            true,
        ),
    ] {
        let e = OptimizeSettings::from_keys(&keys(text)).unwrap_err();
        match (&e, wrong_type) {
            (
                Error::WrongType {
                    field: f,
                    value: v,
                    reason,
                },
                true,
            ) => {
                assert_eq!((f.as_str(), v.as_str()), (field, value), "{text}");
                assert!(reason.starts_with("invalid type: "), "{text}: {reason}");
                assert!(e
                    .to_string()
                    .starts_with(&format!("{field}: invalid type: ")));
            }
            (
                Error::InvalidParameter {
                    field: f, value: v, ..
                },
                false,
            ) => {
                assert_eq!((f.as_str(), v.as_str()), (field, value), "{text}")
            }
            other => panic!("{text}: {other:?}"),
        }
    }
    // One reader of the names: a table refuses an unknown method or formulation in the words
    // of `from_name`, which the command line's `--formulation` uses.
    let reason = |e: Error| match e {
        Error::InvalidParameter { reason, .. } => reason,
        other => panic!("{other:?}"),
    };
    for (text, by_name) in [
        (
            "method = \"fast\"",
            GaitMethod::from_name("fast").unwrap_err(),
        ),
        (
            "formulation = \"best\"",
            PhaseFormulation::from_name("best").unwrap_err(),
        ),
    ] {
        let e = OptimizeSettings::from_keys(&keys(text)).unwrap_err();
        assert_eq!(reason(e), reason(by_name), "{text}");
    }
    // A key of no setting is named in the refusal, which lists the settings.
    let e = reason(OptimizeSettings::from_keys(&keys("mm = 3")).unwrap_err());
    assert!(e.contains("`mm` is not a setting"), "{e}");
    assert!(e.contains("max_phases") && !e.contains("max-phases"), "{e}");
}
