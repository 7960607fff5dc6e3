//! `optimize` on a general problem file is decided by the library
//! (`OptimizeSettings::plan_general`), not by the front ends: which method runs, with which
//! defaults, and which settings are refused, each named as the caller spelled it.

use crawlopt::api::{
    GaitMethod, GeneralLocalSettings, GeneralPhaseSettings, GeneralPlan, GeneralPmSettings, Naming,
    OptimizeSettings, Start,
};

fn field(s: &OptimizeSettings, front_end: &[(&str, bool)]) -> String {
    match s.plan_general(front_end) {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => field,
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn the_plan_fills_in_each_methods_defaults() {
    let auto = OptimizeSettings::default();
    assert_eq!(
        auto.plan_general(&[]).unwrap(),
        GeneralPlan::Discrete(GeneralPmSettings::default())
    );
    let local = OptimizeSettings {
        method: GaitMethod::Local,
        m: Some(4),
        time_limit: Some(5.0),
        ..Default::default()
    };
    assert_eq!(
        local.plan_general(&[]).unwrap(),
        GeneralPlan::Local(GeneralLocalSettings {
            m: 4,
            time_limit: Some(5.0),
            ..Default::default()
        })
    );
    let phase = OptimizeSettings {
        method: GaitMethod::Phase,
        max_phases: Some(3),
        ..Default::default()
    };
    assert_eq!(
        phase.plan_general(&[]).unwrap(),
        GeneralPlan::Phase(GeneralPhaseSettings {
            max_phases: Some(3),
            ..Default::default()
        })
    );
    let discrete = OptimizeSettings {
        method: GaitMethod::Discrete,
        certify: true,
        polish: Some(false),
        ..Default::default()
    };
    assert_eq!(
        discrete.plan_general(&[]).unwrap(),
        GeneralPlan::Discrete(GeneralPmSettings {
            certify: true,
            polish: false,
            ..Default::default()
        })
    );
}

/// Each setting that does not apply is refused naming it: as a flag for the command line, as
/// a keyword for Python; a bound (the crawler's upper bound) with the local method too (with
/// a global method it applies where the problem is a crawler's: tests/general_structure.rs).
#[test]
fn settings_that_do_not_apply_are_refused_naming_them() {
    let with = |method, naming, edit: &dyn Fn(&mut OptimizeSettings)| {
        let mut s = OptimizeSettings {
            method,
            naming,
            ..Default::default()
        };
        edit(&mut s);
        s
    };
    let (f, k) = (Naming::Flags, Naming::Keywords);
    use GaitMethod::{Auto, Chain, Discrete, Local, Phase, Sequence};
    let cases: Vec<(OptimizeSettings, &str)> = vec![
        // The crawler's sequence and chain methods apply where the problem is a chain (checked
        // when they run: tests/general_on_chain.rs); their refusals are their settings'.
        (with(Sequence, f, &|s| s.m = Some(2)), "--m"),
        (with(Chain, k, &|s| s.polish = Some(true)), "polish"),
        (with(Auto, f, &|s| s.phases = Some(2)), "--phases"),
        (with(Auto, f, &|s| s.patience = Some(2)), "--patience"),
        (with(Auto, f, &|s| s.max_phases = Some(2)), "--max-phases"),
        (with(Local, f, &|s| s.convergence = true), "--convergence"),
        (with(Phase, k, &|s| s.convergence = true), "convergence"),
        // A start applies to the local method and to P_m globally (auto), not to the phase's.
        (
            with(Phase, f, &|s| s.start = Some(Start::File("a.json".into()))),
            "--start",
        ),
        (with(Discrete, f, &|s| s.shifts = Some(2)), "--shifts"),
        (with(Local, f, &|s| s.polish = Some(false)), "--no-polish"),
        (with(Phase, f, &|s| s.m = Some(2)), "--m"),
        // One MILP at a fixed K takes no growth settings (as for a crawler's problem).
        (
            with(Phase, f, &|s| {
                s.phases = Some(3);
                s.max_phases = Some(4)
            }),
            "--max-phases",
        ),
        (
            with(Phase, k, &|s| {
                s.phases = Some(3);
                s.patience = Some(1)
            }),
            "patience",
        ),
        (with(Phase, f, &|s| s.shifts = Some(2)), "--shifts"),
        (with(Local, k, &|s| s.polish = Some(true)), "polish"),
        (with(Discrete, k, &|s| s.max_phases = Some(2)), "max_phases"),
        (with(Discrete, k, &|s| s.shifts = Some(2)), "shifts"),
        (with(Phase, k, &|s| s.m = Some(2)), "m"),
    ];
    for (s, want) in &cases {
        assert_eq!(field(s, &[]), *want, "{s:?}");
    }
    // The growth's flags say which method takes them, as the keywords do.
    let edits: [&dyn Fn(&mut OptimizeSettings); 3] =
        [&|s| s.phases = Some(2), &|s| s.patience = Some(2), &|s| {
            s.max_phases = Some(2)
        }];
    for edit in edits {
        let e = with(Discrete, f, edit).plan_general(&[]).unwrap_err();
        assert!(
            e.to_string().contains("applies to --method phase only"),
            "{e}"
        );
    }
    // A front end's own options for crawler results only (named as the front end names them;
    // the command line's --plot and --report now apply to both kinds and are not listed).
    let s = with(Auto, f, &|_| {});
    assert_eq!(field(&s, &[("plot", true)]), "--plot");
    assert!(s.plan_general(&[("plot", false)]).is_ok());
}

/// `shifts` sets the rotations of the default start of P_m (under a time limit, without a
/// start or a convergence table), as it sets a crawler's default start's time shifts; where no
/// default start runs it is refused naming it, and its range is checked as the local method's.
#[test]
fn shifts_apply_to_the_default_start_of_p_m() {
    let with = |edit: &dyn Fn(&mut OptimizeSettings)| {
        let mut s = OptimizeSettings {
            method: GaitMethod::Discrete,
            naming: Naming::Flags,
            shifts: Some(2),
            time_limit: Some(5.0),
            ..Default::default()
        };
        edit(&mut s);
        s
    };
    assert_eq!(
        with(&|_| {}).plan_general(&[]).unwrap(),
        GeneralPlan::Discrete(GeneralPmSettings {
            shifts: 2,
            time_limit: Some(5.0),
            ..Default::default()
        })
    );
    let refused = [
        with(&|s| s.time_limit = None),
        with(&|s| s.convergence = true),
        with(&|s| s.start = Some(Start::File("a.json".into()))),
    ];
    for s in &refused {
        assert_eq!(field(s, &[]), "--shifts", "{s:?}");
        let e = s.plan_general(&[]).unwrap_err().to_string();
        assert!(e.contains("the default start of --method discrete"), "{e}");
    }
    let file =
        crawlopt::io::GeneralFile::load_if_general("examples/general_three_blocks.toml".as_ref())
            .unwrap()
            .unwrap();
    let s = GeneralPmSettings {
        m: 2,
        shifts: 0,
        time_limit: Some(5.0),
        ..Default::default()
    };
    match crawlopt::api::optimize_general(&file, &s, crawlopt::api::Hooks::default()) {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => assert_eq!(field, "shifts"),
        other => panic!("expected a refusal naming shifts, got {other:?}"),
    }
}

/// `max_phases` bounds the phase gait that starts the local method and P_m's default start on
/// a general problem, as it bounds a crawler's phase start; where no phase gait is grown (a
/// start given, no default start, the file's `[input]` or `A != 0`) it is refused naming it,
/// and its range is the phase method's.
#[test]
fn max_phases_bounds_the_phase_start_of_a_general_problem() {
    use crawlopt::api::{optimize_general_local, GeneralLocalSettings, Hooks};
    let with = |method: GaitMethod, edit: &dyn Fn(&mut OptimizeSettings)| {
        let mut s = OptimizeSettings {
            method,
            naming: Naming::Flags,
            max_phases: Some(2),
            ..Default::default()
        };
        edit(&mut s);
        s
    };
    assert_eq!(
        with(GaitMethod::Local, &|_| {}).plan_general(&[]).unwrap(),
        GeneralPlan::Local(GeneralLocalSettings {
            max_phases: Some(2),
            ..Default::default()
        })
    );
    assert_eq!(
        with(GaitMethod::Discrete, &|s| s.time_limit = Some(5.0))
            .plan_general(&[])
            .unwrap(),
        GeneralPlan::Discrete(GeneralPmSettings {
            max_phases: Some(2),
            time_limit: Some(5.0),
            ..Default::default()
        })
    );
    let refused = [
        with(GaitMethod::Local, &|s| {
            s.start = Some(Start::File("a.json".into()))
        }),
        with(GaitMethod::Discrete, &|_| {}),
        with(GaitMethod::Discrete, &|s| {
            s.time_limit = Some(5.0);
            s.convergence = true
        }),
    ];
    for s in &refused {
        assert_eq!(field(s, &[]), "--max-phases", "{s:?}");
    }
    let load = |path: &str| {
        crawlopt::io::GeneralFile::load_if_general(path.as_ref())
            .unwrap()
            .unwrap()
    };
    for (path, k) in [
        ("examples/general_one_link.toml", 2),
        ("examples/general_three_blocks.toml", 0),
        ("examples/general_three_blocks.toml", 25),
    ] {
        let s = GeneralLocalSettings {
            max_phases: Some(k),
            ..Default::default()
        };
        match optimize_general_local(&load(path), &s, Hooks::default()) {
            Err(crawlopt::Error::InvalidParameter { field, .. }) => {
                assert_eq!(field, "max_phases", "{path}, {k}")
            }
            other => panic!("{path}, {k}: expected a refusal naming max_phases, got {other:?}"),
        }
    }
}
