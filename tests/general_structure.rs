//! Structure recognised in a general problem (P): `GeneralProblem::as_chain` inverts
//! `crawler_as_general` exactly, whatever the order of the faces, the scale of their rows and
//! the scale of the objective, and recognises nothing that is not a crawler's gait problem.

mod common;

use common::Rng;
use crawlopt::model::general::{GeneralCost, GeneralParts, GeneralProblem};
use crawlopt::model::{crawler_as_general, Crawler};

/// The parts of a problem (unit rows), to edit.
fn parts_of(p: &GeneralProblem) -> GeneralParts {
    let (lower, upper) = match &p.control {
        crawlopt::model::general::ControlSet::Box { lower, upper } => {
            (lower.clone(), upper.clone())
        }
        _ => unreachable!("a crawler's U is a box"),
    };
    let weights = match &p.reward {
        crawlopt::model::general::Reward::FaceWeights(w) => w.clone(),
        _ => unreachable!("a crawler's f1 is by face weights"),
    };
    GeneralParts {
        normals: p.c.normals.clone(),
        offsets: p.c.offsets.clone(),
        b: p.dynamics.b.clone(),
        lower: Some(lower),
        upper: Some(upper),
        zero_mean: true,
        face_weights: Some(weights),
        cost: Some(p.cost.clone()),
        period: p.period,
        periodic: true,
        ..Default::default()
    }
}

/// An edit of a problem's parts.
type Edit = Box<dyn Fn(&mut GeneralParts)>;

fn random_crawler(rng: &mut Rng, blocks: usize) -> Crawler {
    loop {
        let k = (0..blocks - 1).map(|_| rng.range(0.3, 3.0)).collect();
        let fwd: Vec<f64> = (0..blocks).map(|_| rng.range(0.5, 1.5)).collect();
        let bwd = fwd.iter().map(|f| f * rng.range(1.2, 3.0)).collect();
        if let Ok(c) = Crawler::new(k, fwd, bwd) {
            if c.require_unique().is_ok() {
                return c;
            }
        }
    }
}

fn assert_same(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-12 * x.abs().max(1.0),
            "{what}: {a:?} vs {b:?}"
        );
    }
}

#[test]
fn a_crawlers_general_form_is_recognised_as_that_crawler() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for blocks in 2..=7 {
        for _ in 0..5 {
            let c = random_crawler(&mut rng, blocks);
            let rates: Vec<f64> = (0..blocks - 1).map(|_| rng.range(0.5, 2.0)).collect();
            let cost = if rng.range(0.0, 1.0) < 0.5 {
                GeneralCost::None
            } else {
                GeneralCost::Quadratic { weight: 0.3 }
            };
            let inst = crawler_as_general(&c, 7.0, &rates, cost.clone()).unwrap();
            let view = inst.problem.as_chain().expect("a crawler instance");
            assert_same(view.crawler.stiffness(), c.stiffness(), "stiffness");
            assert_same(view.crawler.mu_forward(), c.mu_forward(), "mu_forward");
            assert_same(view.crawler.mu_backward(), c.mu_backward(), "mu_backward");
            assert_same(&view.rate_bounds, &rates, "rate bounds");
            assert!((view.objective_scale - 1.0).abs() < 1e-12);
            let want = match cost {
                GeneralCost::Quadratic { weight } => Some(weight),
                _ => None,
            };
            match (view.cost_weight, want) {
                (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "{a} vs {b}"),
                (a, b) => assert_eq!(a, b),
            }
            for (b, pair) in view.faces.iter().enumerate() {
                assert_eq!(*pair, [2 * b, 2 * b + 1], "crawler_as_general's order");
            }
        }
    }
}

#[test]
fn order_row_scales_and_the_objectives_scale_do_not_hide_the_chain() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    for blocks in [2, 3, 5] {
        let c = random_crawler(&mut rng, blocks);
        let rates = vec![1.0; blocks - 1];
        let inst =
            crawler_as_general(&c, 5.0, &rates, GeneralCost::Quadratic { weight: 0.2 }).unwrap();
        let mut parts = parts_of(&inst.problem);
        // Reverse the faces, scale each row (and its offset) by its own factor, and the
        // objective (weights and cost) by 2.5.
        let sigma = parts.normals.len();
        let order: Vec<usize> = (0..sigma).rev().collect();
        let w = parts.face_weights.clone().unwrap();
        let scales: Vec<f64> = (0..sigma).map(|_| rng.range(0.2, 5.0)).collect();
        parts.normals = order
            .iter()
            .zip(&scales)
            .map(|(&f, s)| inst.problem.c.normals[f].iter().map(|v| v * s).collect())
            .collect();
        parts.offsets = order
            .iter()
            .zip(&scales)
            .map(|(&f, s)| inst.problem.c.offsets[f] * s)
            .collect();
        parts.face_weights = Some(order.iter().map(|&f| 2.5 * w[f]).collect());
        parts.cost = Some(GeneralCost::Quadratic { weight: 0.5 });
        let p = GeneralProblem::new(parts).unwrap();
        let view = p.as_chain().expect("still the crawler");
        assert_same(view.crawler.mu_forward(), c.mu_forward(), "mu_forward");
        assert_same(view.crawler.mu_backward(), c.mu_backward(), "mu_backward");
        assert!((view.objective_scale - 2.5).abs() < 1e-12);
        assert!((view.cost_weight.unwrap() - 0.2).abs() < 1e-12);
        assert_eq!(view.faces[0], [sigma - 1, sigma - 2]);
    }
}

#[test]
fn what_is_not_a_crawlers_problem_is_not_recognised() {
    let c = Crawler::new(vec![1.0, 2.0], vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap();
    let inst = crawler_as_general(&c, 6.0, &[1.0, 1.0], GeneralCost::None).unwrap();
    let base = parts_of(&inst.problem);
    assert!(GeneralProblem::new(base.clone())
        .unwrap()
        .as_chain()
        .is_some());
    let edits: Vec<(&str, Edit)> = vec![
        (
            "a normal off the chain",
            Box::new(|p| p.normals[2][0] += 1e-6),
        ),
        ("a drift", Box::new(|p| p.drift = Some(vec![0.1, 0.0]))),
        (
            "a state-dependent drift",
            Box::new(|p| p.a = Some(vec![vec![-0.1, 0.0], vec![0.0, 0.0]])),
        ),
        ("B not diagonal", Box::new(|p| p.b[0][1] = 0.1)),
        (
            "U not symmetric",
            Box::new(|p| p.lower = Some(vec![-1.0, -0.5])),
        ),
        (
            "a weight off the pattern",
            Box::new(|p| p.face_weights.as_mut().unwrap()[3] *= 1.01),
        ),
        (
            "the objective reversed",
            Box::new(|p| {
                for w in p.face_weights.as_mut().unwrap() {
                    *w = -*w;
                }
            }),
        ),
        (
            "a matrix cost",
            Box::new(|p| {
                p.cost = Some(GeneralCost::Matrix {
                    matrix: vec![vec![1.0, 0.0], vec![0.0, 2.0]],
                })
            }),
        ),
        ("no zero mean", Box::new(|p| p.zero_mean = false)),
        (
            "a Cauchy problem",
            Box::new(|p| {
                p.periodic = false;
                p.initial_state = Some(vec![0.0, 0.0]);
            }),
        ),
        (
            "a face more",
            Box::new(|p| {
                p.normals.push(vec![1.0, 1.0]);
                p.offsets.push(10.0);
                p.face_weights.as_mut().unwrap().push(0.0);
            }),
        ),
    ];
    for (what, edit) in edits {
        let mut parts = base.clone();
        edit(&mut parts);
        let p = GeneralProblem::new(parts).unwrap();
        assert!(p.as_chain().is_none(), "{what}");
    }
    // The paper's §4 one-link problem in general form is not a crawler's: a crawler of one
    // link has four faces (two per block), this C two.
    let text = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let file = crawlopt::io::GeneralFile::parse(&text).unwrap();
    assert!(file.problem().unwrap().as_chain().is_none());
}

/// The chain's upper bound on a general problem that is a crawler's gait problem is the
/// crawler's (times the objective's scale), above the verified optimum; it is refused naming
/// `bound` where the problem is not a chain; read back, a bound below J is refused.
#[test]
fn the_chain_bound_of_a_general_problem_is_the_crawlers() {
    use crawlopt::api::{optimize_general, GeneralPmSettings};
    use crawlopt::certify::bound::{upper_bound, BoundSettings};
    use crawlopt::optimal::{Cost, GaitProblem};
    let b = BoundSettings {
        resolution: Some(4),
        box_resolution: Some(4),
        ..BoundSettings::default()
    };
    let crawler = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let gp = GaitProblem::new(&crawler, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    let want = upper_bound(&crawler, &gp, &b).unwrap().value;
    let text = std::fs::read_to_string("examples/general_three_blocks.toml").unwrap();
    let s = GeneralPmSettings {
        m: 2,
        bound: Some(b),
        ..GeneralPmSettings::default()
    };
    for scale in [1.0, 2.5] {
        let mut file = crawlopt::io::GeneralFile::parse(&text).unwrap();
        if let Some(w) = file.objective.face_weights.as_mut() {
            for v in w.iter_mut() {
                *v *= scale;
            }
        }
        let r = optimize_general(&file, &s, crawlopt::api::Hooks::default()).unwrap();
        let ub = r
            .head
            .certificate
            .upper_bound
            .as_ref()
            .expect("a chain: bound proven");
        assert!(
            (ub.value - scale * want).abs() < 1e-9 * want,
            "{} vs {}",
            ub.value,
            want
        );
        assert!(ub.value >= r.head.objective);
        // Read back: consistent; a bound below J is refused naming it.
        let json = serde_json::to_string(&r).unwrap();
        assert!(crawlopt::io::ResultFile::from_json(&json, "r").is_ok());
        let mut v: serde_json::Value = serde_json::from_str(&json).unwrap();
        v["certificate"]["upper_bound"]["value"] = (0.5 * r.head.objective).into();
        match crawlopt::io::ResultFile::from_json(&v.to_string(), "r") {
            Err(crawlopt::Error::InvalidParameter { field, .. }) => {
                assert_eq!(field, "r: certificate.upper_bound.value")
            }
            other => panic!("not refused: {other:?}"),
        }
    }
    let one_link = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let file = crawlopt::io::GeneralFile::parse(&one_link).unwrap();
    match optimize_general(&file, &s, crawlopt::api::Hooks::default()) {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => assert_eq!(field, "bound"),
        other => panic!("not refused: {other:?}"),
    }
}

/// On a crawler's gait problem the phase method takes the chain's formulation (K slip phases,
/// transitions free): the three-block optimum 2.6 at K = 4, where the general formulation
/// needs 8 phases (0 at K = 4); its bound at K bounds the general K-phase gaits; the answer
/// reads back consistent, and "chain" on a problem that is not one is refused.
#[test]
fn a_chain_takes_the_chains_phase_formulation() {
    use crawlopt::api::{optimize_general_phase, GeneralPhaseSettings, Hooks, PhaseFormulation};
    let text = std::fs::read_to_string("examples/general_three_blocks.toml").unwrap();
    let file = crawlopt::io::GeneralFile::parse(&text).unwrap();
    let settings = |formulation| GeneralPhaseSettings {
        phases: Some(4),
        formulation,
        ..GeneralPhaseSettings::default()
    };
    let chain = optimize_general_phase(&file, &settings(None), Hooks::default()).unwrap();
    assert_eq!(chain.formulation.as_deref(), Some("chain"));
    assert!(
        (chain.head.objective - 2.6).abs() < 1e-9,
        "{}",
        chain.head.objective
    );
    assert!(chain.solution.as_phase().unwrap().durations.len() <= 8);
    let general = optimize_general_phase(
        &file,
        &settings(Some(PhaseFormulation::General)),
        Hooks::default(),
    )
    .unwrap();
    assert!(general.formulation.is_none());
    assert!(
        general.head.objective.abs() < 1e-9,
        "{}",
        general.head.objective
    );
    assert!(chain.solution.as_phase().unwrap().certificate.bound >= general.head.objective);
    // The general formulation reaches it with 8 phases.
    let eight = optimize_general_phase(
        &file,
        &GeneralPhaseSettings {
            phases: Some(8),
            formulation: Some(PhaseFormulation::General),
            ..GeneralPhaseSettings::default()
        },
        Hooks::default(),
    )
    .unwrap();
    assert!(
        (eight.head.objective - 2.6).abs() < 1e-7,
        "{}",
        eight.head.objective
    );
    // The held faces carry the reactions, and the rewards add up to J.
    let w = [
        1.0 / 3.0,
        -1.0 / 3.0,
        0.5_f64.sqrt() / 3.0,
        -(0.5_f64.sqrt()) / 3.0,
        1.0 / 3.0,
        -1.0 / 3.0,
    ];
    let s = chain.solution.as_phase().unwrap();
    let mut reward = 0.0;
    for (j, tau) in s.durations.iter().enumerate() {
        for (f, r) in s.reactions[j].iter().enumerate() {
            if *r != 0.0 {
                assert!(
                    s.held[j].contains(&(f + 1)),
                    "phase {j}: face {} not held",
                    f + 1
                );
            }
            reward += w[f] * r * tau;
        }
    }
    assert!(
        (reward - chain.head.objective).abs() < 1e-9,
        "{reward} vs {}",
        chain.head.objective
    );
    let json = serde_json::to_string(&chain).unwrap();
    assert!(crawlopt::io::ResultFile::from_json(&json, "r").is_ok());
    // "chain" on the one-link problem (not a crawler's) is refused naming the field.
    let one = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let one = crawlopt::io::GeneralFile::parse(&one).unwrap();
    let r = optimize_general_phase(
        &one,
        &settings(Some(PhaseFormulation::General)),
        Hooks::default(),
    )
    .unwrap();
    assert!(r.formulation.is_none());
    let r = optimize_general_phase(&one, &settings(None), Hooks::default()).unwrap();
    assert_eq!(r.formulation.as_deref(), Some("transitions"));
    match optimize_general_phase(
        &one,
        &settings(Some(PhaseFormulation::Chain)),
        Hooks::default(),
    ) {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => assert_eq!(field, "formulation"),
        other => panic!("not refused: {other:?}"),
    }
    let mut v: serde_json::Value = serde_json::to_value(&r).unwrap();
    v["formulation"] = "chain".into();
    match crawlopt::io::ResultFile::from_json(&v.to_string(), "r") {
        Err(crawlopt::Error::InvalidParameter { field, .. }) => assert_eq!(field, "r: formulation"),
        other => panic!("not refused: {other:?}"),
    }
}

/// A problem file of a general problem (its unit rows, as the library stores them).
fn file_of(p: &GeneralProblem) -> crawlopt::io::GeneralFile {
    let parts = parts_of(p);
    let cost = match p.cost {
        GeneralCost::Quadratic { weight } => {
            format!("cost = {{ kind = \"quadratic\", weight = {weight:?} }}\n")
        }
        _ => String::new(),
    };
    let text = format!(
        "[sweeping_process]\nnormals = {:?}\noffsets = {:?}\n[dynamics]\nB = {:?}\n\
         [control]\nlower = {:?}\nupper = {:?}\nzero_mean = true\n\
         [objective]\nface_weights = {:?}\n{cost}[problem]\nperiod = {:?}\n",
        parts.normals,
        parts.offsets,
        parts.b,
        parts.lower.unwrap(),
        parts.upper.unwrap(),
        parts.face_weights.unwrap(),
        p.period
    );
    crawlopt::io::GeneralFile::parse(&text).unwrap()
}

/// With stiffness other than 1 the chain's problem is the crawler's (its rate bounds are the
/// crawler's k_l times the actuator speeds): the chain phase answer equals the crawler's phase
/// optimum, its bound at K bounds the general formulation at K, and the chain's upper bound
/// is the crawler's.
#[test]
fn with_any_stiffness_the_chain_is_the_crawlers_problem() {
    use crawlopt::api::{
        optimize_general, optimize_general_phase, GeneralPhaseSettings, GeneralPmSettings, Hooks,
        PhaseFormulation,
    };
    use crawlopt::certify::bound::{upper_bound, BoundSettings};
    use crawlopt::optimal::{solve_phase_global, Cost, GaitProblem};
    for k in [[0.5, 2.0], [0.25, 4.0]] {
        let c = Crawler::new(k.to_vec(), vec![1.0, 1.2, 0.9], vec![2.5, 3.1, 2.7]).unwrap();
        c.require_unique().unwrap();
        let gp = GaitProblem::new(&c, 8.0, &[1.0, 1.0], Cost::None, None).unwrap();
        let inst = crawler_as_general(&c, 8.0, &gp.rate_bound, GeneralCost::None).unwrap();
        let file = file_of(&inst.problem);
        let phases = |k, formulation| GeneralPhaseSettings {
            phases: Some(k),
            formulation,
            ..GeneralPhaseSettings::default()
        };
        let want = solve_phase_global(&c, &gp, 2).unwrap();
        let chain = optimize_general_phase(&file, &phases(2, None), Hooks::default()).unwrap();
        assert_eq!(chain.formulation.as_deref(), Some("chain"));
        assert!(
            (chain.head.objective - want.objective()).abs() < 1e-7,
            "k = {k:?}: chain {} vs crawler {}",
            chain.head.objective,
            want.objective()
        );
        let general = optimize_general_phase(
            &file,
            &phases(2, Some(PhaseFormulation::General)),
            Hooks::default(),
        )
        .unwrap();
        assert!(
            general.head.objective <= chain.solution.as_phase().unwrap().certificate.bound + 1e-7
        );
        let b = BoundSettings {
            resolution: Some(4),
            box_resolution: Some(4),
            ..BoundSettings::default()
        };
        let s = GeneralPmSettings {
            m: 2,
            bound: Some(b),
            ..GeneralPmSettings::default()
        };
        let r = optimize_general(&file, &s, Hooks::default()).unwrap();
        let got = r.head.certificate.upper_bound.unwrap().value;
        let crawler = upper_bound(&c, &gp, &b).unwrap().value;
        // The same LP up to the last bit of its data (a_l / k_l * k_l): equal to its tolerance.
        assert!(
            (got - crawler).abs() < 1e-7 * crawler,
            "k = {k:?}: {got} vs {crawler}"
        );
    }
}
