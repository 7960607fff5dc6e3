//! Every reader of a gait result (certify, plot, report, --start) runs one consistency check
//! (`GaitResult::check_consistent`, through `GaitResult::from_json`): the results the optimisers
//! write pass it, and every mutation the robustness issue found accepted (or drawn) is refused
//! naming its field.

mod common;

use crawlopt::optimal::{
    grow_phases, solve_discrete_global, solve_discrete_local, Cost, GaitProblem, GaitResult,
    GrowOptions,
};
use crawlopt::{Crawler, Error};
use serde_json::{json, Value};

fn three_blocks() -> (Crawler, GaitProblem) {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    (c, p)
}

/// The results of the three formulations, as JSON values.
fn results() -> Vec<(&'static str, Value)> {
    let (c, p) = three_blocks();
    let growth = grow_phases(
        &c,
        &p,
        &GrowOptions {
            max_phases: 4,
            ..GrowOptions::default()
        },
        &mut |_| {},
    )
    .unwrap();
    let phase = GaitResult::from_growth(&c, &p, &growth);
    let disc = GaitResult::from_discrete(&c, &p, &solve_discrete_global(&c, &p, 2).unwrap());
    let (t, l) = (&phase.gait.times, &phase.gait.lengths);
    let local = GaitResult::from_local(
        &c,
        &p,
        &solve_discrete_local(&c, &p, 4, t, l).unwrap(),
        "phase",
    );
    [("phase", phase), ("discrete", disc), ("local", local)]
        .into_iter()
        .map(|(k, r)| (k, serde_json::to_value(&r).unwrap()))
        .collect()
}

fn read(v: &Value) -> crawlopt::Result<GaitResult> {
    GaitResult::from_json(&v.to_string(), "r.json")
}

/// Applies `edit` to a copy of `v` and asserts the reader refuses it naming `field`.
fn refused(v: &Value, field: &str, edit: impl FnOnce(&mut Value)) {
    let mut w = v.clone();
    edit(&mut w);
    match read(&w) {
        Err(Error::InvalidParameter { field: f, .. }) if f.contains(field) => {}
        Err(Error::Inadmissible { what, .. }) if what.contains(field) => {}
        other => panic!("{field}: expected a refusal naming it, got {other:?}"),
    }
}

#[test]
fn optimiser_results_pass_and_mutations_are_refused_by_field() {
    for (kind, v) in results() {
        let r = read(&v).unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert_eq!(serde_json::to_value(&r).unwrap(), v);
        let g = "solution";
        // Redundant fields: lengths, slip modes, the objective and its parts.
        refused(&v, "solution.lengths[1]", |w| {
            w[g]["lengths"][1][0] = json!(3.5)
        });
        refused(&v, "solution.lengths[1]", |w| {
            w[g]["lengths"][1][0] = json!(1e300)
        });
        let moving = r
            .gait
            .block_displacements
            .iter()
            .enumerate()
            .find_map(|(j, d)| d.iter().position(|x| x.abs() > 1e-3).map(|b| (j, b)))
            .unwrap();
        refused(&v, "solution.slip", |w| {
            let s = &mut w[g]["slip"][moving.0][moving.1];
            *s = json!(-s.as_i64().unwrap());
        });
        let still = r
            .gait
            .slip
            .iter()
            .enumerate()
            .find_map(|(j, s)| s.iter().position(|&x| x == 0).map(|b| (j, b)));
        if let Some((j, b)) = still {
            let f = r
                .crawler
                .crawler()
                .unwrap()
                .block_forces(&r.gait.states[j + 1])[b];
            if (f + 1.5).abs() > 1e-3 {
                refused(&v, "solution.slip", |w| w[g]["slip"][j][b] = json!(-1));
            }
        }
        refused(&v, "objective", |w| w["objective"] = json!(7.5));
        refused(&v, "solution.displacement_per_period", |w| {
            w[g]["displacement_per_period"] = json!(7.5)
        });
        refused(&v, "solution.actuation_cost", |w| {
            w[g]["actuation_cost"] = json!(1.0)
        });
        // The gait itself: a displacement, a state outside C, a control beyond a = 1, a
        // non-zero mean, a negative duration, another crawler's friction.
        refused(&v, "solution.", |w| {
            w[g]["block_displacements"][0][0] = json!(0.7)
        });
        refused(&v, "solution.states[1]", |w| {
            w[g]["states"][1][0] = json!(9.0)
        });
        refused(&v, "solution.controls", |w| {
            w[g]["controls"][0][0] = json!(-5.0)
        });
        refused(&v, "solution.", |w| {
            let u = w[g]["controls"][0][1].as_f64().unwrap();
            w[g]["controls"][0][1] = json!(u + 0.01);
        });
        refused(&v, "solution.durations", |w| {
            w[g]["durations"][0] = json!(-1.0)
        });
        refused(&v, "solution.", |w| {
            w["problem"]["crawler"]["mu_forward"] = json!([0.5, 0.5, 0.5])
        });
        // Method, grid, certificate.
        refused(&v, "method", |w| w["method"] = json!("bogus"));
        refused(&v, "solution.m", |w| w[g]["m"] = json!(40));
        refused(&v, "certificate", |w| {
            w["certificate"]["kind"] = json!("global_everything")
        });
        if r.head.certificate.bound.is_some() {
            refused(&v, "certificate.bound", |w| {
                w["certificate"]["bound"] = json!(r.head.objective - 0.5)
            });
            refused(&v, "certificate.gap", |w| {
                w["certificate"]["gap"] = json!(0.5)
            });
        }
        if kind == "discrete" {
            // An uneven grid: two steps of 2 and 3 where P_2 has 2.5 each.
            refused(&v, "solution.durations[0]", |w| {
                w[g]["durations"][0] = json!(2.0);
                w[g]["durations"][1] = json!(3.0);
            });
        }
        if kind == "phase" {
            refused(&v, "phase_growth.table", |w| {
                w["phase_growth"]["table"][0]["objective"] = json!(99.0)
            });
            refused(&v, "objective", |w| {
                let rows = w["phase_growth"]["table"].as_array_mut().unwrap();
                for row in rows {
                    row["objective"] = json!(1.0);
                    row["bound"] = json!(1.0);
                }
            });
        }
    }
}

#[test]
fn an_idle_gait_of_one_piece_is_read_drawn_and_reported() {
    // K = 1 on the one-link problem: the optimum is to stay idle, one piece with u = 0. Its
    // replay and its figures once failed ("actuation.times: needs at least 2 knots").
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
    let s = crawlopt::optimal::solve_phase_global(&c, &p, 1).unwrap();
    let r = GaitResult::from_phase(&c, &p, &s);
    assert_eq!((r.gait.durations.len(), r.head.objective), (1, 0.0));
    let back = read(&serde_json::to_value(&r).unwrap()).unwrap();
    assert!(!crawlopt::present::gait_figures(&back).unwrap().is_empty());
    let html = crawlopt::present::report::build_report(&back, "r.json").unwrap();
    assert!(html.contains("<svg"));
}

/// P_m's optimal values need not rise with `m`: one catching-up step is not two half steps (on
/// the three-block crawler, from a state on the boundary of C, the projection of `x + delta`
/// is not in general that of the projection of `x + delta/2` plus `delta/2`, nor are the block
/// displacements), so P_m's processes are not P_(m+1)'s. A crawler's convergence table whose
/// `J` falls with `m` is therefore read, as a general one is (the drift problem's does fall,
/// tests/general_convergence.rs); its other invariants still hold.
#[test]
fn a_convergence_table_may_fall_with_m() {
    let (c, p) = three_blocks();
    let mut proj = crawlopt::sweep::Projector::new(&c).unwrap();
    let mut rng = common::Rng(12345);
    let mut uniform = || rng.range(-3.0, 3.0);
    let mut gap = 0.0_f64;
    for _ in 0..200 {
        let mut x = vec![0.0; 2];
        let (pre, delta) = ([uniform(), uniform()], [uniform(), uniform()]);
        let half = [delta[0] / 2.0, delta[1] / 2.0];
        let mut d = [vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]];
        proj.step(&mut x, &pre, &mut d[0]).unwrap();
        let (mut one, mut two) = (x.clone(), x);
        proj.step(&mut one, &delta, &mut d[0]).unwrap();
        let moved_one: f64 = d[0].iter().sum();
        proj.step(&mut two, &half, &mut d[1]).unwrap();
        proj.step(&mut two, &half, &mut d[2]).unwrap();
        let moved_two: f64 = d[1].iter().chain(&d[2]).sum();
        gap = gap
            .max((one[0] - two[0]).abs())
            .max((one[1] - two[1]).abs())
            .max((moved_one - moved_two).abs());
    }
    println!("largest gap between one step and two half steps: {gap:.3e}");
    assert!(gap > 1e-2, "one step equals two half steps here: {gap}");
    let (rows, s) = crawlopt::optimal::discrete_convergence(&c, &p, 2, &mut |_| {}).unwrap();
    // Both rows optimal: the rule this test replaces (optimal values rising with m) applied.
    assert!(rows
        .iter()
        .all(|r| r.status == crawlopt::optimal::MilpStatus::Optimal));
    let mut r = GaitResult::from_discrete(&c, &p, &s);
    r.records.convergence = Some(rows);
    let mut v = serde_json::to_value(&r).unwrap();
    read(&v).unwrap();
    let last = v["convergence"][1]["objective"].as_f64().unwrap();
    v["convergence"][0]["objective"] = json!(last + 0.5);
    v["convergence"][0]["bound"] = json!(last + 0.5);
    read(&v).unwrap();
    refused(&v, "convergence[0]", |w| {
        w["convergence"][0]["bound"] = json!(last)
    });
}

/// Each link's rate is held to its own bound: on a crawler whose rate bounds are 10 apart
/// (`a = [1, 0.1]`, `T = 100`: `J = 4.5`, the slow link at its bound throughout), a control of
/// the slow link beyond its bound by `5e-7` of it is refused naming it, while the same change
/// inwards reads back. Since the crawler's own check became (P)'s, every component was held to
/// `1e-7` of the largest bound, and this control (`5e-8` over) was refused only through the
/// step it breaks (`solution.states[1]`, a residual of `2.5e-7` over its piece of 5).
#[test]
fn each_links_rate_is_held_to_its_own_bound() {
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 100.0, &[1.0, 0.1], Cost::None, None).unwrap();
    let growth = grow_phases(
        &c,
        &p,
        &GrowOptions {
            max_phases: 3,
            ..GrowOptions::default()
        },
        &mut |_| {},
    )
    .unwrap();
    let v = serde_json::to_value(GaitResult::from_growth(&c, &p, &growth)).unwrap();
    read(&v).unwrap();
    assert!(v["objective"].as_f64().unwrap() > 4.0, "{}", v["objective"]);
    let controls = v["solution"]["controls"].as_array().unwrap();
    let j = controls
        .iter()
        .position(|u| (u[1].as_f64().unwrap().abs() - 0.1).abs() < 1e-12)
        .expect("the slow link at its bound on some phase");
    let u = controls[j][1].as_f64().unwrap();
    refused(&v, &format!("solution.controls[{j}][1]"), |w| {
        w["solution"]["controls"][j][1] = json!(u * (1.0 + 5e-7))
    });
    let mut w = v.clone();
    w["solution"]["controls"][j][1] = json!(u * (1.0 - 1e-9));
    read(&w).unwrap();
}

/// A P_m gait's slip modes are written at a threshold that is a length, as the reader's (it was
/// `1e-9` times the time step): at a period of `1e7` a block moving by `1.25e-6` was written as sticking,
/// and at a period of `1e-5` one moving by `3e-16` as slipping off its face; `optimize` exited
/// 0 with files that `certify` refused.
#[test]
fn slip_modes_are_written_at_a_threshold_of_length() {
    let dir = tempfile::tempdir().unwrap();
    let crawler = |mu: f64, period: f64, speed: f64| {
        format!(
            "[crawler]\nblocks = 3\nstiffness = 1.0\nmu_forward = {mu:?}\n\
             mu_backward = {:?}\n[gait]\nperiod = {period:?}\nmax_actuator_speed = {speed:?}\n\
             cost = {{ kind = \"none\" }}\n",
            1.5 * mu
        )
    };
    for (text, args) in [
        (
            crawler(1e-6, 1e7, 1e-12),
            &["--method", "discrete", "--m", "3"][..],
        ),
        (crawler(1.0, 1e-5, 1e6), &["--method", "local"][..]),
    ] {
        let file = common::write(dir.path(), "c.toml", &text);
        let v = common::optimize_json(&file, args);
        let slips = v["solution"]["slip"].as_array().unwrap();
        assert!(
            slips
                .iter()
                .flat_map(|r| r.as_array().unwrap())
                .any(|s| s != 0),
            "{args:?}: a gait with J = {} slips",
            v["objective"]
        );
        common::certify_written(dir.path(), &v);
    }
}
