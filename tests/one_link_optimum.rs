//! The closed-form optimum of the one-link gait problem (theory §9), checked against simulations
//! of the gaits it returns and of competing gaits.

mod common;
use crawlopt::integrate::{Actuation, Method};
use crawlopt::optimal::{one_link_optimum, Cost, GaitProblem};
use crawlopt::Crawler;

fn problem(c: &Crawler, t: f64, speed: f64, cost: Cost, tv: Option<f64>) -> GaitProblem {
    GaitProblem::new(c, t, &[speed], cost, tv).unwrap()
}

/// Displacement minus cost of the gait that rises by `sweep` (force units) in time `t1` and falls
/// back in `t - t1`, by simulation (exact method) and exact integration of the cost.
fn simulated_value(c: &Crawler, t: f64, t1: f64, sweep: f64, cost: Cost) -> f64 {
    let k = c.stiffness()[0];
    let act =
        Actuation::piecewise_linear(t, vec![0.0, t1], vec![vec![0.0], vec![sweep / k]]).unwrap();
    let d = common::disp(c, &act, Method::Exact, 0);
    d - (cost.eval(&[sweep / t1]) * t1 + cost.eval(&[sweep / (t - t1)]) * (t - t1))
}

#[test]
fn spec_reference_value_and_its_gait() {
    // theory §10: N = 2, k = 1, a = 1, T = 10, mu+ = 1, mu- = 2: w = 2, J* = 3.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let p = problem(&c, 10.0, 1.0, Cost::None, None);
    let o = one_link_optimum(&c, &p).unwrap();
    assert_eq!(o.value, 3.0);
    let d = common::disp(&c, &o.gait(&c, 10.0).unwrap(), Method::Exact, 0);
    assert!((d - 3.0).abs() < 1e-12, "{d}");
}

#[test]
fn no_cost_matches_spec_formula_across_parameters() {
    // J* = max(0, (a T - 2 w) / (2 k)), including the no-locomotion side of a T = 2 w.
    for (mp, mm) in [
        (vec![1.0, 1.0], vec![2.0, 2.0]),
        (vec![1.0, 0.8], vec![2.5, 1.7]),
    ] {
        for k in [0.5, 1.0, 4.0] {
            let c = Crawler::new(vec![k], mp.clone(), mm.clone()).unwrap();
            let w = c.analyze().one_link.unwrap().width;
            for speed in [0.3, 1.0] {
                let a = k * speed;
                for t in [
                    0.5 * w / a,
                    2.0 * w / a,
                    2.0 * w / a + 1e-3,
                    3.0 * w / a,
                    17.0,
                ] {
                    let o = one_link_optimum(&c, &problem(&c, t, speed, Cost::None, None)).unwrap();
                    let want = f64::max(0.0, (a * t - 2.0 * w) / (2.0 * k));
                    assert!(
                        (o.value - want).abs() < 1e-12,
                        "k {k} a {a} T {t}: {} vs {want}",
                        o.value
                    );
                    if let Some(g) = o.gait(&c, t) {
                        let d = common::disp(&c, &g, Method::Exact, 0);
                        assert!(
                            (d - o.displacement).abs() < 1e-11,
                            "{d} vs {}",
                            o.displacement
                        );
                    } else {
                        assert_eq!(o.value, 0.0);
                    }
                }
            }
        }
    }
}

#[test]
fn quadratic_cost_closed_form_beats_every_two_phase_gait() {
    // Closed form (src/optimal/one_link.rs): J(D) = (D - w)/k - 2 c D^2 / T, maximised at
    // D = clamp(T / (4 c k), w, a T / 2). Compare with a scan over rise times t1 and sweeps D,
    // every candidate simulated.
    let c = Crawler::new(vec![2.0], vec![1.0, 0.8], vec![2.5, 1.7]).unwrap();
    let (t, speed) = (10.0, 1.0);
    let w = c.analyze().one_link.unwrap().width;
    for weight in [0.01, 0.05, 0.2] {
        let cost = Cost::Quadratic { weight };
        let o = one_link_optimum(&c, &problem(&c, t, speed, cost, None)).unwrap();
        let k = 2.0;
        let d_star = (t / (4.0 * weight * k)).clamp(w, k * speed * t / 2.0);
        let want = f64::max(0.0, (d_star - w) / k - 2.0 * weight * d_star * d_star / t);
        assert!(
            (o.value - want).abs() < 1e-12,
            "c {weight}: {} vs {want}",
            o.value
        );
        if o.value > 0.0 {
            let sim = simulated_value(&c, t, t / 2.0, o.sweep, cost);
            assert!(
                (sim - o.value).abs() < 1e-11,
                "c {weight}: simulated {sim} vs {}",
                o.value
            );
        }
        let mut best = f64::NEG_INFINITY;
        for i in 1..20 {
            let t1 = t * i as f64 / 20.0;
            let dmax = k * speed * t1.min(t - t1);
            for j in 1..=20 {
                let sweep = dmax * j as f64 / 20.0;
                best = best.max(simulated_value(&c, t, t1, sweep, cost));
            }
        }
        assert!(
            best <= o.value + 1e-11,
            "c {weight}: a scanned gait gives {best} > J* = {}",
            o.value
        );
        assert!(
            best >= o.value - 0.05 * o.value.abs() - 1e-9,
            "c {weight}: scan best {best}, J* {}",
            o.value
        );
    }
}

#[test]
fn total_variation_bound_and_one_sided_friction() {
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    // TV(u) <= 3 allows rates 3/4 (u = +3/4 then -3/4 has TV 3): a sweep of (10/2)(3/4)
    // = 3.75 and J* = 3.75 - 2 = 1.75.
    let o = one_link_optimum(&c, &problem(&c, 10.0, 1.0, Cost::None, Some(3.0))).unwrap();
    assert_eq!((o.value, o.sweep, o.rate), (1.75, 3.75, 0.75));
    // TV(u) <= 4 a is no constraint: J* = 3 as without it.
    let o = one_link_optimum(&c, &problem(&c, 10.0, 1.0, Cost::None, Some(4.0))).unwrap();
    assert_eq!(o.value, 3.0);
    // Only extension moves forward: no periodic gait moves it, J* = 0.
    let c = Crawler::new(vec![1.0], vec![1.0, 0.5], vec![2.0, 0.8]).unwrap();
    let o = one_link_optimum(&c, &problem(&c, 100.0, 1.0, Cost::None, None)).unwrap();
    assert_eq!(o.value, 0.0);
    assert!(o.reason.contains("stay idle"));
}
