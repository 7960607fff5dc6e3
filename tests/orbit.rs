//! The Newton-Krylov search of the periodic orbit (issue 15) against Anderson's: on the bench
//! gait (travelling sine, k = 1, mu+ = 1, mu- = 3.3, catching-up on 1000 steps) the orbit it
//! finds is a true fixed point of the period map, and its displacement per period is Anderson's.

use crawlopt::integrate::{
    simulate, Actuation, CatchingUp, Method, PeriodMap, Search, SimOptions, Waveform,
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

fn search(c: &Crawler, a: &Actuation, newton: bool) -> crawlopt::integrate::Simulation {
    let opts = SimOptions {
        method: Method::CatchingUp,
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
    for nb in [30, 200] {
        let (c, a) = bench_gait(nb);
        let sim = search(&c, &a, true);
        assert_eq!(sim.search, Search::Newton, "N = {nb}");
        assert!(sim.newton_steps >= 1 && sim.tangent_products >= 1);
        // One plain period, integrated here, from the orbit state: it returns within the
        // search's tolerance, 1e-12 times the size of C.
        let mut map = CatchingUp::new(&c, &a, 1000).unwrap();
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
            "N = {nb}: residual {residual:e}"
        );
        let disp = acc.iter().sum::<f64>() / nb as f64;
        assert_eq!(Some(disp), sim.displacement_per_period, "N = {nb}");
    }
}

#[test]
fn newton_and_anderson_give_the_same_displacement() {
    for nb in [3, 5, 10, 30, 100, 200] {
        let (c, a) = bench_gait(nb);
        let newton = search(&c, &a, true);
        let anderson = search(&c, &a, false);
        let (dn, da) = (
            newton.displacement_per_period.unwrap(),
            anderson.displacement_per_period.unwrap(),
        );
        assert!((dn - da).abs() <= 1e-10, "N = {nb}: {dn} against {da}");
        // From 10 blocks on, plain iteration is slow and Newton steps are taken; from 100 blocks
        // on Newton needs fewer period evaluations (plain and tangent) than Anderson.
        if nb >= 10 {
            assert_eq!(newton.search, Search::Newton, "N = {nb}");
        }
        if nb >= 100 {
            let evaluations = newton.periods_simulated + newton.tangent_products;
            assert!(
                evaluations < anderson.periods_simulated,
                "N = {nb}: {evaluations} against {}",
                anderson.periods_simulated
            );
        }
    }
}

/// The exact method has no tangent map: the search there is Anderson's, unchanged.
#[test]
fn exact_method_keeps_anderson() {
    let (c, a) = bench_gait(30);
    let opts = SimOptions {
        record_periods: 0,
        ..SimOptions::default()
    };
    let sim = simulate(&c, &a, &opts).unwrap();
    assert_eq!(sim.search, Search::Anderson);
    assert_eq!(sim.tangent_products, 0);
}
