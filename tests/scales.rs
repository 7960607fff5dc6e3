//! The numeric range the optimisers support (README, "Supported range"): at its corners every
//! optimiser agrees with the one-link closed form (theory §9), just outside it they refuse with the
//! field named, and the inputs that once panicked inside HiGHS or gave a false certificate are
//! refused, never answered.

mod common;

use crawlopt::optimal::{
    one_link_optimum, solve_discrete_global, solve_discrete_local, solve_phase_global, Cost,
    GaitProblem, MAX_SWEEP,
};
use crawlopt::{Crawler, Error};

/// A one-link crawler with `mu^+ = mu`, `mu^- = 2 mu` on both blocks and its gait problem.
fn one_link(k: f64, mu: f64, period: f64, speed: f64, cost: Cost) -> (Crawler, GaitProblem) {
    let c = Crawler::new(vec![k], vec![mu; 2], vec![2.0 * mu; 2]).unwrap();
    let p = GaitProblem::new(&c, period, &[speed], cost, None).unwrap();
    (c, p)
}

/// Every optimiser's value against the closed form, relative to the length scale.
fn agrees_with_closed_form(c: &Crawler, p: &GaitProblem) {
    let exact = one_link_optimum(c, p).unwrap().value;
    let scale = p.length_scale(c).max(exact.abs());
    let phase = solve_phase_global(c, p, 2).unwrap();
    assert!(
        (phase.objective() - exact).abs() <= 1e-7 * scale,
        "phase {} against {exact} ({p:?})",
        phase.objective()
    );
    // The bound is valid and close: a gap of the length scale's order is no certificate.
    let b = phase.certificate.bound;
    assert!(
        b >= exact - 1e-7 * scale && b - exact <= 1e-7 * scale,
        "bound {b}"
    );
    if p.cost == Cost::None {
        // P_3's optimum with a sweep of the whole period is the continuous one (one rise, one
        // fall, on grid times) whenever the optimum moves; the local method from the idle start
        // may stop at 0, so only its validity is asserted: never above the optimum.
        let d = solve_discrete_global(c, p, 3).unwrap();
        assert!(
            d.objective() <= exact + 1e-7 * scale,
            "P_3 {}",
            d.objective()
        );
        assert!(d.certificate.bound >= d.objective() - 1e-7 * scale);
        let times = [0.0, p.period / 2.0, p.period];
        let rise = p.rate_bound[0] * p.period / 2.0 / c.stiffness()[0];
        let l = solve_discrete_local(c, p, 3, &times, &[vec![0.0], vec![rise], vec![0.0]]).unwrap();
        assert!(
            (l.verified_displacement - exact).abs() <= 1e-7 * scale,
            "local {} against {exact}",
            l.verified_displacement
        );
    }
}

#[test]
fn any_units_agree_with_the_closed_form() {
    // The optimisers solve in internal units (force: the friction scale, time: the period,
    // length: the smallest elongation crossing C), so the user's units are no limit. Each case
    // is the reference instance (sweep ratio a T / w = 10 / 3, J* = 3 in its length unit) in
    // other units; before the change of units, friction thresholds of 1e9 gave J = 0
    // "certified" and 1e-9 a HiGHS error.
    for (t, speed) in [(1e-12, 1e13), (1e12, 1e-11)] {
        let (c, p) = one_link(1.0, 1.0, t, speed, Cost::None);
        agrees_with_closed_form(&c, &p);
    }
    for mu in [1e-12, 1e-9, 1e9, 1e12] {
        let (c, p) = one_link(mu, mu, 10.0, 1.0, Cost::None);
        agrees_with_closed_form(&c, &p);
    }
    // Lengths: J* = 3e-9 (stiff springs) and 3e9 (soft ones); HiGHS's default absolute gap
    // (1e-6) once certified J = 3e-6 at a gap of a third of its value.
    for (k, speed) in [(1e9, 1e-9), (1e-9, 1e9)] {
        let (c, p) = one_link(k, 1.0, 10.0, speed, Cost::None);
        agrees_with_closed_form(&c, &p);
    }
    // All three at once, and a quadratic cost in the reference and in odd units.
    let (c, p) = one_link(1e7, 1e-5, 1e-4, 1e-7, Cost::None);
    agrees_with_closed_form(&c, &p);
    let (c, p) = one_link(1.0, 1.0, 10.0, 1.0, Cost::Quadratic { weight: 0.1 });
    agrees_with_closed_form(&c, &p);
    let (c, p) = one_link(1e3, 1e6, 1e-3, 1e3, Cost::Quadratic { weight: 1e-7 });
    agrees_with_closed_form(&c, &p);
    // Sweep ratio just below the limit: a T / w = 10 k / 3 = 3e5.
    let (c, p) = one_link(9e4, 1.0, 10.0, 1.0, Cost::None);
    agrees_with_closed_form(&c, &p);
}

/// Asserts that every optimiser refuses `(c, p)` naming `field`.
fn refused(c: &Crawler, p: &GaitProblem, field: &str) {
    let msgs = [
        solve_phase_global(c, p, 2).map(|_| ()),
        solve_discrete_global(c, p, 2).map(|_| ()),
        solve_discrete_local(c, p, 2, &[0.0, p.period], &vec![vec![0.0; c.links()]; 2]).map(|_| ()),
    ];
    for m in msgs {
        match m {
            Err(Error::InvalidParameter { field: f, .. }) if f.starts_with(field) => {}
            other => panic!("{field}: expected a refusal, got {other:?}"),
        }
    }
}

#[test]
fn outside_the_range_every_optimiser_refuses_naming_the_field() {
    // The one-link gait of the issue: k = 1e9 once gave J = 0 "certified" where J* = 5.
    let (c, p) = one_link(1e9, 0.5, 10.0, 1.0, Cost::None);
    assert!((one_link_optimum(&c, &p).unwrap().value - 5.0).abs() < 1e-8);
    refused(&c, &p, "gait.max_actuator_speed[1]");
    // Just above the sweep limit.
    let (c, p) = one_link(MAX_SWEEP * 0.31, 1.0, 10.0, 1.0, Cost::None);
    refused(&c, &p, "gait.max_actuator_speed[1]");
    // A period and a speed that once made the `highs` crate panic.
    let (c, p) = one_link(1.0, 1.0, 1e300, 1.0, Cost::None);
    refused(&c, &p, "gait.max_actuator_speed[1]");
    let (c, p) = one_link(1.0, 1.0, 10.0, 1e300, Cost::None);
    refused(&c, &p, "gait.max_actuator_speed[1]");
    let c = Crawler::new(vec![1e-200, 1e200], vec![1.0; 3], vec![1.5; 3]).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], Cost::None, None).unwrap();
    refused(&c, &p, "crawler.stiffness");
    // Rate bounds 1.6e-300 beside 1.6 (found by fuzzing: P_3 wrote a gait whose states its own
    // read-back refused, residual 1.8); at a ratio of 1e5 the same crawler is solved and read
    // back.
    let c = Crawler::new(vec![1.6, 1.86, 1.64], vec![1.0; 4], vec![2.0; 4]).unwrap();
    let p = GaitProblem::new(&c, 11.7, &[1e-300, 0.85, 1.48], Cost::None, None).unwrap();
    refused(&c, &p, "gait.max_actuator_speed");
    let p = GaitProblem::new(&c, 11.7, &[1e-5, 0.85, 1.48], Cost::None, None).unwrap();
    let r = solve_discrete_global(&c, &p, 2).unwrap();
    let g = crawlopt::optimal::GaitResult::from_discrete(&c, &p, &r);
    crawlopt::optimal::GaitResult::from_json(&serde_json::to_string(&g).unwrap(), "P_2").unwrap();
    // A cost that outweighs any motion by 1e300 (P_2 once answered J = -5.8e290).
    let (c, p) = one_link(1.0, 1.0, 10.0, 1.0, Cost::Quadratic { weight: 1e300 });
    let e = solve_discrete_global(&c, &p, 2).unwrap_err();
    assert!(e.to_string().starts_with("gait.cost.weight"), "{e}");
}

#[test]
fn an_actuation_offset_that_would_drown_the_stroke_is_refused() {
    use crawlopt::integrate::{simulate, Actuation, Method, SimOptions, Waveform};
    let c = Crawler::uniform(3, 1.0, 1.0, 3.0).unwrap();
    let wave = |mean: f64| {
        Actuation::wave(
            Waveform::Sine,
            1.0,
            vec![mean; 2],
            vec![2.0; 2],
            vec![0.0, 90.0],
        )
    };
    let disp = |a: &Actuation| {
        let o = SimOptions {
            method: Method::Exact,
            ..SimOptions::default()
        };
        simulate(&c, a, &o)
            .unwrap()
            .displacement_per_period
            .unwrap()
    };
    // The offset does not move the crawler: up to 1e6 times the stroke it changes nothing
    // beyond rounding (the three-block sine of the examples moves 1.914 per period)...
    let (d0, d5) = (disp(&wave(0.0).unwrap()), disp(&wave(2e5).unwrap()));
    assert!(
        (d0 - 1.914).abs() < 1e-3 && (d5 - d0).abs() < 1e-6,
        "{d0} {d5}"
    );
    // ...beyond it, the stroke is lost to the offset's rounding (1e300 once moved 0): refused.
    let e = wave(1e300).unwrap_err();
    assert!(e.to_string().starts_with("actuation.mean[1]"), "{e}");
    let e = Actuation::piecewise_linear(1.0, vec![0.0, 0.5], vec![vec![1e12], vec![1e12 + 1.0]])
        .unwrap_err();
    assert!(e.to_string().starts_with("actuation.lengths[*][1]"), "{e}");
}

/// A crawler of tiny lengths is its twin in units of one: the three-block crawler with
/// stiffness `k` and speed `1 / k` (lengths `1 / k` times those of `k = 1`) picks the same
/// structured start, and the phase MILP (`K = 3`) with a quadratic cost states its gap relative
/// to `J`. With the
/// floor of `J` at 1 in every unit, at `k = 1e12` every structured gait tied (their values,
/// about `1.5e-12`, differ by less than `1e-12`), and the first, the lag 3/16 with `J = 1.375`
/// in units of one, became the start, where the twin's is the lag 4/16 with `J = 1.5`; the
/// outer approximation's gap came out absolute (`1e-12` times the twin's).
#[test]
fn exact_twins_of_tiny_lengths_pick_the_same_start_and_state_the_same_gaps() {
    use crawlopt::optimal::structured::{best_structured, StructuredOptions};
    let twin = |k: f64, cost: Cost| {
        let c = Crawler::uniform(3, k, 1.0, 1.5).unwrap();
        let p = GaitProblem::new(&c, 10.0, &[1.0 / k; 2], cost, None).unwrap();
        (c, p)
    };
    let (c, p) = twin(1.0, Cost::None);
    let want = best_structured(&c, &p, &StructuredOptions::default())
        .unwrap()
        .unwrap();
    assert!((want.objective - 1.5).abs() < 1e-9, "{}", want.objective);
    for k in [1e6, 1e12] {
        let (c, p) = twin(k, Cost::None);
        let s = best_structured(&c, &p, &StructuredOptions::default())
            .unwrap()
            .unwrap();
        assert_eq!(s.best.origin, want.best.origin, "k = {k}");
        assert!(
            (s.objective * k - want.objective).abs() <= 1e-9 * want.objective,
            "k = {k}: J k = {}",
            s.objective * k
        );
    }
    let gap = |k: f64| {
        let (c, p) = twin(k, Cost::Quadratic { weight: 0.05 / k });
        let s = solve_phase_global(&c, &p, 3).unwrap();
        assert!(
            s.objective() * k > 1.8,
            "k = {k}: J k = {}",
            s.objective() * k
        );
        s.certificate.gap
    };
    let at_one = gap(1.0);
    assert!(
        at_one > 1e-9,
        "the outer approximation's gap at k = 1: {at_one}"
    );
    for k in [1e6, 1e12] {
        // Up to the floor's cap at 1 (the length unit is 2.5 at k = 1): a factor of 2.5.
        let g = gap(k);
        assert!(
            g >= 0.1 * at_one && g <= 10.0 * at_one,
            "k = {k}: gap {g} against {at_one} at k = 1"
        );
    }
}

/// A phase claim is written as it is read: the MILPs prove their answers over the length unit
/// (they are solved in internal units), so the gap is stated over it too. Capped at 1, a crawler
/// of length unit `2500` (stiffness `1e-3`) with a quadratic cost stated a gap of `2.2e-4` for
/// its `optimal_among_k_phases` claim, above what a reader accepts (`1e-5`), and `certify`
/// refused the file `optimize` had written.
#[test]
fn a_phase_claim_at_a_large_length_unit_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let text = "[crawler]\nblocks = 3\nstiffness = 0.001\nmu_forward = 1.0\n\
                mu_backward = 1.5\n[gait]\nperiod = 10.0\nmax_actuator_speed = 1000.0\n\
                cost = { kind = \"quadratic\", weight = 370.0 }\n";
    let file = common::write(dir.path(), "large.toml", text);
    let v = common::optimize_json(&file, &["--method", "phase", "--phases", "3"]);
    assert_eq!(v["status"], "optimal_among_k_phases");
    let gap = v["certificate"]["gap"].as_f64().unwrap();
    assert!(gap <= 1e-6, "gap {gap}");
    common::certify_written(dir.path(), &v);
}

/// Exact twins of the three-block phase optimum (forces times `f`, time times `t`, lengths times
/// `l`) get one certificate: the same verdict, the phase LP stationary in the durations to
/// rounding, and all 8 branch LPs through its biactive pairs at `J`. With the Hamiltonian
/// counted in units of one, the twin in forces 1e6, time 1e-6 and lengths 1e6 `failed` its
/// duration stationarity at `1.2e-4` (the rounding of Hamiltonians of size `1e12`), and at
/// periods of `1e-5` no branch LP was solved (HiGHS's absolute tolerances against durations of
/// `1e-7`); the crawler in units of one is `degenerate` with all 8.
#[test]
fn exact_twins_of_the_three_block_optimum_get_one_certificate() {
    use crawlopt::api::{self, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::certify::{certify_result, Verdict};
    let certified = |f: f64, t: f64, l: f64| {
        let c = Crawler::uniform(3, f / l, f, 1.5 * f).unwrap();
        let p = GaitProblem::new(&c, 10.0 * t, &[l / t; 2], Cost::None, None).unwrap();
        let settings = OptimizeSettings {
            method: GaitMethod::Phase,
            phases: Some(6),
            ..Default::default()
        };
        let r = api::optimize(&c, &p, &settings, Hooks::default())
            .unwrap()
            .result;
        assert!(
            (r.head.objective / l - 2.6).abs() < 1e-9,
            "{f} {t} {l}: J = {}",
            r.head.objective
        );
        certify_result(&r, "twin").unwrap()
    };
    for (f, t, l) in [
        (1.0, 1.0, 1.0),
        (1e6, 1e-6, 1e6),
        (1.0, 1e-6, 1.0),
        (1e6, 1.0, 1.0),
        (1.0, 1.0, 1e6),
    ] {
        let nc = certified(f, t, l);
        let at = format!("forces x{f}, time x{t}, lengths x{l}");
        assert_eq!(nc.verdict, Verdict::Degenerate, "{at}: {}", nc.reason);
        let d = nc
            .conditions
            .iter()
            .find(|c| c.name == "duration_stationarity")
            .expect("a phase gait's duration condition");
        assert!(d.holds && d.residual < 1e-12, "{at}: {}", d.residual);
        let b = nc
            .branch_lp
            .as_ref()
            .unwrap_or_else(|| panic!("{at}: no branch LP"));
        assert_eq!(b.branches, 8, "{at}");
        assert!(b.improvement.abs() <= 1e-9 * l, "{at}: {}", b.improvement);
    }
}

/// The three-block P_2 answer of a quadratic cost, unpolished (its rates off their bounds only
/// as accurate as the MILP's outer approximation), is no KKT point: in forces of order one its
/// slip stationarity fails by `2e-4`. Its exact twins in the unit of force (the same controls
/// times the unit, simulated on their periodic orbit) get that one certificate (the
/// certificate counts forces in units of the stiffest spring): the same verdict and residuals,
/// the margin and the multipliers `p` in lengths per force (times the force unit, the same
/// numbers). Before, the twin in forces times `1e6` (its `p` of order `1e-7`, every residual
/// under `tol max(1, ||p||)`) was certified `holds`, and the twin in forces times `1e-6`
/// failed by `2e2`.
#[test]
fn exact_twins_in_force_of_an_unpolished_answer_get_one_verdict() {
    use crawlopt::api::{self, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::certify::{certify, CertifyOptions, NecessaryConditions, Process, Verdict};
    let twin = |f: f64| {
        let c = Crawler::uniform(3, f, f, 1.5 * f).unwrap();
        let cost = Cost::Quadratic {
            weight: 0.2 / (f * f),
        };
        let p = GaitProblem::new(&c, 10.0, &[1.0; 2], cost, None).unwrap();
        (c, p)
    };
    let (c, p) = twin(1.0);
    let settings = OptimizeSettings {
        method: GaitMethod::Discrete,
        m: Some(2),
        polish: Some(false),
        ..Default::default()
    };
    let r = api::optimize(&c, &p, &settings, Hooks::default())
        .unwrap()
        .result;
    let certified = |f: f64| -> NecessaryConditions {
        let (c, p) = twin(f);
        let u: Vec<Vec<f64>> = r
            .gait
            .controls
            .iter()
            .map(|u| u.iter().map(|v| v * f).collect())
            .collect();
        let pr = Process::discrete_from_controls(&c, &p, 2, &u).unwrap();
        certify(&pr, &CertifyOptions::default()).unwrap()
    };
    let one = certified(1.0);
    assert_eq!(one.verdict, Verdict::Fails, "{}", one.reason);
    let slip = one
        .conditions
        .iter()
        .find(|c| c.name == "slip_stationarity")
        .unwrap();
    assert!(!slip.holds && slip.residual > 1e-5, "{}", slip.residual);
    for f in [1e6, 1e-6] {
        let nc = certified(f);
        assert!(close(nc.objective, one.objective), "forces x{f}");
        assert_eq!(nc.verdict, one.verdict, "forces x{f}: {}", nc.reason);
        assert_eq!(nc.conditions.len(), one.conditions.len());
        for (a, b) in nc.conditions.iter().zip(&one.conditions) {
            assert_eq!((&a.name, a.holds), (&b.name, b.holds), "forces x{f}");
            assert!(
                close(a.residual, b.residual),
                "forces x{f}: {} {} vs {}",
                a.name,
                a.residual,
                b.residual
            );
        }
        assert!(
            close(nc.nondegeneracy_margin * f, one.nondegeneracy_margin),
            "forces x{f}: margin {} vs {}",
            nc.nondegeneracy_margin,
            one.nondegeneracy_margin
        );
        assert!(
            close(sup(&nc) * f, sup(&one)),
            "forces x{f}: sup |p| {} vs {}",
            sup(&nc),
            sup(&one)
        );
    }
}

/// Exact twins in units of force, time and length get one certificate: the unpolished P_2
/// answer of a quadratic cost and the phase optimum at `K = 4` (no cost) of the three-block
/// crawler, rebuilt by simulation with forces times `F`, times times `T` and lengths times `L`
/// (`k F / L`, `mu F`, `T`, rate bounds `F / T`, the cost's weight `c L T / F^2`, controls `F /
/// T`), get the verdict and residuals of the crawler in units of one, its `J` times `L`, its
/// margin and `sup |p|` times `L / F`, its knot times and Theorem 2.2's weak maximality (an
/// integral over time) times `T`. Before, the certificate was
/// computed with forces in units of the stiffest spring but times and lengths as given: at
/// `(1e6, 1e-6, 1e6)` (rates of `1e12`) the phase optimum's multiplier LP ended in HiGHS's status
/// unknown.
#[test]
fn exact_twins_in_force_time_and_length_get_one_certificate() {
    use crawlopt::api::{self, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::certify::{
        certify, CertifyOptions, ConditionCheck, NecessaryConditions, Process,
    };
    let twin = |(f, t, l): (f64, f64, f64), cost: bool| {
        let c = Crawler::uniform(3, f / l, f, 1.5 * f).unwrap();
        let cost = if cost {
            Cost::Quadratic {
                weight: 0.2 * l * t / (f * f),
            }
        } else {
            Cost::None
        };
        let p = GaitProblem::new(&c, 10.0 * t, &[l / t; 2], cost, None).unwrap();
        (c, p)
    };
    let one = (1.0, 1.0, 1.0);
    let optimum = |method: GaitMethod, cost: bool| {
        let (c, p) = twin(one, cost);
        let settings = OptimizeSettings {
            method,
            m: (method == GaitMethod::Discrete).then_some(2),
            phases: (method == GaitMethod::Phase).then_some(4),
            polish: (method == GaitMethod::Discrete).then_some(false),
            ..Default::default()
        };
        api::optimize(&c, &p, &settings, Hooks::default())
            .unwrap()
            .result
    };
    for (method, cost) in [(GaitMethod::Discrete, true), (GaitMethod::Phase, false)] {
        let r = optimum(method, cost);
        let certified = |(f, t, l): (f64, f64, f64)| -> NecessaryConditions {
            let (c, p) = twin((f, t, l), cost);
            let u: Vec<Vec<f64>> = r
                .gait
                .controls
                .iter()
                .map(|u| u.iter().map(|v| v * f / t).collect())
                .collect();
            let pr = match method {
                GaitMethod::Discrete => Process::discrete_from_controls(&c, &p, 2, &u),
                _ => {
                    let d: Vec<f64> = r.gait.durations.iter().map(|d| d * t).collect();
                    Process::phase_from_controls(&c, &p, &d, &u)
                }
            }
            .unwrap();
            certify(&pr, &CertifyOptions::default())
                .unwrap_or_else(|e| panic!("{method:?} at {:?}: {e}", (f, t, l)))
        };
        let base = certified(one);
        for units in [
            (1e6, 1e-6, 1e6),
            (1.0, 1e-6, 1.0),
            (1.0, 1.0, 1e6),
            (1e-6, 1e6, 1e-6),
            (3.0, 0.5, 7.0),
        ] {
            let (f, t, l) = units;
            let nc = certified(units);
            let what = format!("{method:?} at {units:?}");
            assert!(close(nc.objective, base.objective * l), "{what}");
            assert_eq!(nc.verdict, base.verdict, "{what}: {}", nc.reason);
            assert_eq!(nc.conditions.len(), base.conditions.len(), "{what}");
            for (a, b) in nc.conditions.iter().zip(&base.conditions) {
                assert_eq!((&a.name, a.holds), (&b.name, b.holds), "{what}");
                // Theorem 2.2's weak maximality is an integral over time, in the user's time.
                let per_time =
                    if (a.name.as_str(), a.theorem.as_str()) == ("weak_maximality", "2.2") {
                        t
                    } else {
                        1.0
                    };
                let a = ConditionCheck {
                    residual: a.residual / per_time,
                    ..a.clone()
                };
                assert!(
                    close(a.residual, b.residual) || a.residual.max(b.residual) < 1e-9,
                    "{what}: {} {} vs {}",
                    a.name,
                    a.residual,
                    b.residual
                );
            }
            let per_force = l / f;
            assert!(
                close(
                    nc.nondegeneracy_margin,
                    base.nondegeneracy_margin * per_force
                ),
                "{what}: margin"
            );
            assert!(close(sup(&nc), sup(&base) * per_force), "{what}: sup |p|");
            let (a, b) = (&nc.multipliers.times, &base.multipliers.times);
            assert_eq!(a.len(), b.len(), "{what}");
            assert!(
                a.iter().zip(b).all(|(x, y)| close(*x, y * t)),
                "{what}: times"
            );
        }
    }
}

/// `a` and `b` equal to `1e-6` relative (`1e-12` absolute): twins' numbers, rounding apart.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * a.abs().max(b.abs()) + 1e-12
}

/// `sup |p|` of a certificate's multipliers.
fn sup(c: &crawlopt::certify::NecessaryConditions) -> f64 {
    c.multipliers
        .p
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
}

/// A crawler certified in periods states its numbers in its own time: the time a degenerate
/// reason quotes is its piece's knot time (the P_2 optimum of the four-block crawler, `mu^- =
/// 1.6`, `T = 10`, its steps rotated so that the place the reason names is not at `t = 0`), and
/// the paper's norm's `sum_k tau_k |psi_k|` is in its time: twins in time by `s` have the norm
/// `A + s B`, affine in `s` (in periods it was the same for every `s`).
#[test]
fn a_certificate_in_periods_states_its_times_in_the_crawlers_time() {
    use crawlopt::api::{self, GaitMethod, Hooks, OptimizeSettings};
    use crawlopt::certify::{certify, CertifyOptions, NecessaryConditions, Process, Verdict};
    let certified = |s: f64, u: &[Vec<f64>]| -> NecessaryConditions {
        let c = Crawler::uniform(4, 1.0, 1.0, 1.6).unwrap();
        let p = GaitProblem::new(&c, 10.0 * s, &[1.0 / s; 3], Cost::None, None).unwrap();
        let u: Vec<Vec<f64>> = u
            .iter()
            .map(|r| r.iter().map(|v| v / s).collect())
            .collect();
        let pr = Process::discrete_from_controls(&c, &p, 2, &u).unwrap();
        certify(&pr, &CertifyOptions::default()).unwrap()
    };
    let c = Crawler::uniform(4, 1.0, 1.0, 1.6).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0; 3], Cost::None, None).unwrap();
    let settings = OptimizeSettings {
        method: GaitMethod::Discrete,
        m: Some(2),
        ..Default::default()
    };
    let r = api::optimize(&c, &p, &settings, Hooks::default())
        .unwrap()
        .result;
    let steps = r.gait.controls.len();
    let mut later = None;
    for rotate in 0..steps {
        let u: Vec<Vec<f64>> = (0..steps)
            .map(|i| r.gait.controls[(i + rotate) % steps].clone())
            .collect();
        let nc = certified(1.0, &u);
        assert_eq!(nc.verdict, Verdict::Degenerate, "{}", nc.reason);
        // "... on piece j (t = X), link l ..."
        let after = |key: &str| -> &str {
            let at = nc.reason.find(key).unwrap() + key.len();
            let rest = &nc.reason[at..];
            &rest[..rest.find([' ', ')', ',']).unwrap()]
        };
        let j: usize = after("on piece ").parse().unwrap();
        let t: f64 = after("(t = ").parse().unwrap();
        let knot = nc.multipliers.times[j];
        assert!(
            (t - knot).abs() < 1e-6,
            "{}: t = {t}, knot {knot}",
            nc.reason
        );
        if knot > 0.0 {
            later = Some(u);
        }
    }
    let u = later.expect("a rotation puts the degenerate place after t = 0");
    // Twins in time: the paper's norm is affine in the time unit.
    let norms: Vec<f64> = [1.0, 2.0, 4.0]
        .iter()
        .map(|&s| certified(s, &u).normalisation.paper_norm)
        .collect();
    let (a, b, c4) = (norms[0], norms[1], norms[2]);
    assert!(b > a * (1.0 + 1e-9), "{norms:?}");
    assert!(close(c4 - b, 2.0 * (b - a)), "{norms:?}");
}
