//! The Newton-Krylov search of the periodic orbit (issue 15) against Anderson's: on the bench
//! gait (travelling sine, k = 1, mu+ = 1, mu- = 3.3, 1000 steps or knots) the orbit it finds is
//! a true fixed point of the period map, and its displacement per period is Anderson's, with
//! catching-up and with the exact method (whose Newton steps take catching-up's Jacobian).

#[path = "../examples/support/heterogeneous.rs"]
mod heterogeneous;

use crawlopt::integrate::{
    simulate, Actuation, CatchingUp, ExactPwl, Method, NewtonOptions, PeriodMap, Search,
    SimOptions, Waveform,
};
use crawlopt::Crawler;

/// The bench gait of `crawlopt bench` on `nb` blocks: `L_l = 2 sin(2 pi t - l pi / 2)`.
fn bench_gait(nb: usize) -> (Crawler, Actuation) {
    let c = Crawler::uniform(nb, 1.0, 1.0, 3.3).unwrap();
    let n = nb - 1;
    let phases = (0..n).map(|l| l as f64 * 90.0).collect();
    let a = Actuation::wave(Waveform::Sine, 1.0, vec![0.0; n], vec![2.0; n], phases).unwrap();
    (c, a)
}

fn search(
    c: &Crawler,
    a: &Actuation,
    method: Method,
    newton: bool,
) -> crawlopt::integrate::Simulation {
    let opts = SimOptions {
        method,
        record_periods: 0,
        newton: if newton {
            SimOptions::DEFAULT.newton
        } else {
            None
        },
        ..SimOptions::default()
    };
    simulate(c, a, &opts).unwrap()
}

#[test]
fn newton_orbit_is_a_fixed_point_of_one_plain_period() {
    for (nb, method) in [
        (30, Method::CatchingUp),
        (200, Method::CatchingUp),
        (200, Method::Exact),
    ] {
        let (c, a) = bench_gait(nb);
        let sim = search(&c, &a, method, true);
        assert_eq!(sim.search, Search::Newton, "N = {nb}");
        assert!(sim.newton_steps >= 1 && sim.tangent_products >= 1);
        // One plain period, integrated here, from the orbit state: it returns within the
        // search's tolerance, 1e-12 times the size of C.
        let mut map: Box<dyn PeriodMap> = match method {
            Method::CatchingUp => Box::new(CatchingUp::new(&c, &a, 1000).unwrap()),
            Method::Exact => Box::new(ExactPwl::new(&c, &a, 1000).unwrap()),
        };
        let mut x = sim.orbit_state.clone();
        let mut acc = vec![0.0; nb];
        map.run_period(&mut x, &mut acc, None).unwrap();
        let residual = x
            .iter()
            .zip(&sim.orbit_state)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        assert!(
            residual <= 1e-12 * c.state_scale(),
            "N = {nb}, {method}: residual {residual:e}"
        );
        let disp = acc.iter().sum::<f64>() / nb as f64;
        assert_eq!(Some(disp), sim.displacement_per_period, "N = {nb}");
    }
}

#[test]
fn newton_and_anderson_give_the_same_displacement() {
    for (nb, method) in [3, 5, 10, 30, 100, 200]
        .into_iter()
        .flat_map(|nb| [(nb, Method::CatchingUp), (nb, Method::Exact)])
    {
        let (c, a) = bench_gait(nb);
        let newton = search(&c, &a, method, true);
        let anderson = search(&c, &a, method, false);
        let (dn, da) = (
            newton.displacement_per_period.unwrap(),
            anderson.displacement_per_period.unwrap(),
        );
        assert!(
            (dn - da).abs() <= 1e-10,
            "N = {nb}, {method}: {dn} against {da}"
        );
        // From 10 blocks on, plain iteration is slow and Newton steps are taken; from 100 blocks
        // on Newton needs fewer period evaluations (plain and tangent) than Anderson.
        if nb >= 10 {
            assert_eq!(newton.search, Search::Newton, "N = {nb}, {method}");
        }
        if nb >= 100 {
            let evaluations = newton.periods_simulated + newton.tangent_products;
            assert!(
                evaluations < anderson.periods_simulated,
                "N = {nb}, {method}: {evaluations} against {}",
                anderson.periods_simulated
            );
        }
    }
}

/// A Newton step starved of products (one: the preconditioner's alpha, no Krylov step) leaves
/// the state where it was: every step fails, and after `max_failures` of them Anderson (mixing
/// the preconditioned residual) finds the orbit, with the displacement of Anderson alone.
#[test]
fn failed_newton_steps_leave_the_search_to_anderson() {
    let (c, a) = bench_gait(100);
    let starved = NewtonOptions {
        max_products: 1,
        ..NewtonOptions::DEFAULT
    };
    let opts = SimOptions {
        method: Method::CatchingUp,
        record_periods: 0,
        newton: Some(starved),
        ..SimOptions::default()
    };
    let sim = simulate(&c, &a, &opts).unwrap();
    let anderson = search(&c, &a, Method::CatchingUp, false);
    assert_eq!(sim.newton_steps, starved.max_failures);
    let (d, da) = (
        sim.displacement_per_period.unwrap(),
        anderson.displacement_per_period.unwrap(),
    );
    assert!((d - da).abs() <= 1e-10, "{d} against {da}");
}

/// The findings behind the Newton-Krylov search (`src/integrate/newton.rs`), on the Jacobian of
/// the period map at the orbit built densely from N tangent products: a nonnegative matrix with
/// row sums at most 1, whose slowest mode contracts by `1 - lambda_1 ~ 30 / N^2`, the next by
/// four times less (a diffusion: `1 - lambda_j ~ j^2`), with a leading eigenvector of one sign
/// (the lowest sine mode of the chain, pinned at its ends).
#[test]
fn period_jacobian_is_a_pinned_diffusion() {
    use nalgebra::{DMatrix, DVector};
    for nb in [50, 100] {
        let (c, a) = bench_gait(nb);
        let n = nb - 1;
        let sim = search(&c, &a, Method::CatchingUp, true);
        let mut map = CatchingUp::new(&c, &a, 1000).unwrap();
        let mut j = DMatrix::zeros(n, n);
        for col in 0..n {
            let (mut x, mut dx) = (sim.orbit_state.clone(), vec![0.0; n]);
            dx[col] = 1.0;
            assert!(map.run_period_tangent(&mut x, &mut dx).unwrap());
            j.set_column(col, &DVector::from_vec(dx));
        }
        assert!(j.iter().all(|&v| v >= -1e-15), "N = {nb}");
        assert!((0..n).all(|r| j.row(r).sum() <= 1.0 + 1e-12), "N = {nb}");
        let mut ev: Vec<_> = j.complex_eigenvalues().iter().copied().collect();
        ev.sort_by(|p, q| q.norm().total_cmp(&p.norm()));
        let (l1, l2) = (ev[0], ev[1]);
        assert!(
            l1.im.abs() < 1e-9 && l2.im.abs() < 1e-9,
            "N = {nb}: {l1}, {l2}"
        );
        let gap = (1.0 - l1.re) * (nb * nb) as f64;
        assert!(
            (25.0..35.0).contains(&gap),
            "N = {nb}: (1 - lambda_1) N^2 = {gap}"
        );
        let ratio = (1.0 - l2.re) / (1.0 - l1.re);
        assert!((3.5..4.5).contains(&ratio), "N = {nb}: ratio {ratio}");
        // Leading eigenvector by inverse iteration: one sign along the chain.
        let lu = (&j - DMatrix::identity(n, n) * (l1.re * (1.0 + 1e-9))).lu();
        let mut v = DVector::from_element(n, 1.0);
        for _ in 0..4 {
            v = lu.solve(&v).unwrap();
            v /= v.norm();
        }
        let s = v.sum().signum();
        assert!(v.iter().all(|&e| e * s >= -1e-12), "N = {nb}: {v}");
    }
}

/// A heterogeneous chain of `nb` blocks (see `examples/support/heterogeneous.rs`).
fn heterogeneous_chain(nb: usize, seed: u64) -> (Crawler, Actuation) {
    heterogeneous::heterogeneous_chain(nb, seed).unwrap()
}

/// Heterogeneous chains, where the Newton step fails (the active pattern holds only within
/// about 1e-3 of the orbit, see `NewtonOptions::max_failures`) and the search goes on with
/// Anderson mixing the preconditioned residual: the displacement is Anderson's (alone, the
/// search without Newton) to 1e-10 and the search needs fewer period evaluations (periods +
/// products) than Anderson alone with catching-up, on the chain of 120 blocks and on random
/// chains of 100 to 300 blocks. Measured counts (newton.rs docs): 27 + 27 against 62
/// (N = 120), 28 + 26 / 35 + 40 / 32 + 31 against 89 / 219 / 285. The exact method, whose
/// failed Newton step costs as much (26 + 29 against 53 at N = 120), is checked for its
/// displacement only.
#[test]
fn heterogeneous_chains_need_fewer_evaluations_than_anderson() {
    let cases = [
        (120, 11, Method::CatchingUp),
        (120, 11, Method::Exact),
        (100, 100, Method::CatchingUp),
        (200, 101, Method::CatchingUp),
        (300, 102, Method::CatchingUp),
    ];
    for (nb, seed, method) in cases {
        let (c, a) = heterogeneous_chain(nb, seed);
        let newton = search(&c, &a, method, true);
        let anderson = search(&c, &a, method, false);
        let (dn, da) = (
            newton.displacement_per_period.unwrap(),
            anderson.displacement_per_period.unwrap(),
        );
        assert!(
            (dn - da).abs() <= 1e-10,
            "N = {nb}, {method}: {dn} against {da}"
        );
        let evaluations = newton.periods_simulated + newton.tangent_products;
        println!(
            "N = {nb} (seed {seed}), {method}: {} periods + {} products against {}",
            newton.periods_simulated, newton.tangent_products, anderson.periods_simulated
        );
        assert!(
            method == Method::Exact || evaluations < anderson.periods_simulated,
            "N = {nb}, {method}: {evaluations} against {}",
            anderson.periods_simulated
        );
    }
}

/// N = 1000 on the bench gait (catching-up): the Newton-Krylov search's displacement is
/// Anderson's to 1e-10, Anderson's searched to a tolerance ten times tighter (1e-13 times the
/// size of C: at the default 1e-12 the state that repeats lies up to `tol / (1 - lambda_1)`
/// from the orbit, `1 - lambda_1 ~ 30 / N^2`, and the two answers differ by 1.04e-10). The
/// slowest test of this file: Anderson alone takes 873 periods, about 17 s on the loaded
/// 2-core machine. The exact method at N = 1000 (Anderson alone: about 30 s) is compared by
/// `crawlopt bench --blocks 1000 --min-time 0.01` with and without `--no-newton`.
#[test]
fn newton_and_anderson_agree_at_1000_blocks() {
    let (c, a) = bench_gait(1000);
    let newton = search(&c, &a, Method::CatchingUp, true);
    let opts = SimOptions {
        method: Method::CatchingUp,
        record_periods: 0,
        newton: None,
        tol: 1e-13,
        ..SimOptions::default()
    };
    let anderson = simulate(&c, &a, &opts).unwrap();
    let (dn, da) = (
        newton.displacement_per_period.unwrap(),
        anderson.displacement_per_period.unwrap(),
    );
    assert!((dn - da).abs() <= 1e-10, "{dn} against {da}");
    assert_eq!(newton.search, Search::Newton);
    let evaluations = newton.periods_simulated + newton.tangent_products;
    assert!(
        evaluations < anderson.periods_simulated,
        "{evaluations} against {}",
        anderson.periods_simulated
    );
}

/// The tangent map replayed from the recorded pattern (`PeriodMap::apply_tangent`, the pattern
/// kept as the blocks that change state, only the touched segments re-averaged) is the tangent
/// applied step by step during the period (`run_period_tangent`), from rest (the transient,
/// where many blocks change per step) and after some periods, on heterogeneous chains (per-link
/// stiffness, per-block friction) and the bench gait, on random vectors.
#[test]
fn recorded_tangent_replays_the_period_tangent() {
    let mut chains = vec![heterogeneous_chain(40, 5), heterogeneous_chain(120, 11)];
    chains.push(bench_gait(60));
    for (c, a) in &chains {
        let (n, nb) = (c.links(), c.blocks());
        let mut map = CatchingUp::new(c, a, 400).unwrap();
        assert!(map.record_tangent(true));
        let mut x = vec![0.0; n];
        for period in 0..12 {
            let x0 = x.clone();
            let mut acc = vec![0.0; nb];
            map.run_period(&mut x, &mut acc, None).unwrap();
            if ![0, 1, 11].contains(&period) {
                continue;
            }
            for trial in 0..3 {
                let v: Vec<f64> = (0..n)
                    .map(|l| ((l * (7 + trial) + 3 * period) as f64 * 0.61).sin())
                    .collect();
                let mut replayed = v.clone();
                map.apply_tangent(&mut replayed);
                let (mut xs, mut direct) = (x0.clone(), v.clone());
                assert!(map.run_period_tangent(&mut xs, &mut direct).unwrap());
                let err = replayed
                    .iter()
                    .zip(&direct)
                    .map(|(p, q)| (p - q).abs())
                    .fold(0.0, f64::max);
                assert!(err <= 1e-13, "N = {nb}, period {period}: {err:e}");
                assert!(direct.iter().any(|d| *d != 0.0), "N = {nb}: J v vanished");
            }
        }
    }
}
