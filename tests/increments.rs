//! Catching-up's increments streamed step by step (memory `O(N)`, issue 15) against the stored
//! table: bitwise the same periods, tangents, searches and recorded trajectories, on smooth
//! waves (sine and triangle, uniform and heterogeneous chains) and a piecewise-linear gait.

#[path = "../examples/support/heterogeneous.rs"]
mod heterogeneous;

use crawlopt::integrate::{
    simulate, Actuation, CatchingUp, IncrementStorage, Method, PeriodMap, SimOptions, Waveform,
};
use crawlopt::Crawler;

/// The cases: (crawler, actuation, steps per period).
fn cases() -> Vec<(Crawler, Actuation, usize)> {
    let sine = {
        let c = Crawler::uniform(50, 1.0, 1.0, 3.3).unwrap();
        let phases = (0..49).map(|l| l as f64 * 90.0).collect();
        let a = Actuation::wave(Waveform::Sine, 1.0, vec![0.0; 49], vec![2.0; 49], phases);
        (c, a.unwrap(), 400)
    };
    let triangle = {
        let c = Crawler::uniform(12, 2.0, 1.0, 3.3).unwrap();
        let phases = (0..11).map(|l| l as f64 * 37.0).collect();
        let a = Actuation::wave(
            Waveform::Triangle,
            2.5,
            vec![0.3; 11],
            vec![1.5; 11],
            phases,
        );
        (c, a.unwrap(), 333)
    };
    let (hc, ha) = heterogeneous::heterogeneous_chain(80, 7).unwrap();
    let gait = {
        let c = Crawler::uniform(3, 1.0, 1.0, 2.5).unwrap();
        let a = Actuation::piecewise_linear(
            1.0,
            vec![0.1, 0.4, 0.7],
            vec![vec![1.0, -1.0], vec![-1.0, 1.0], vec![0.5, 0.5]],
        );
        (c, a.unwrap(), 250)
    };
    vec![sine, triangle, (hc, ha, 500), gait]
}

#[test]
fn streamed_periods_and_tangents_are_bitwise_the_stored_ones() {
    let mut tangents = 0;
    for (c, a, m) in cases() {
        let (n, nb) = (c.links(), c.blocks());
        let mut maps = [IncrementStorage::Stored, IncrementStorage::Streamed]
            .map(|s| CatchingUp::with_storage(&c, &a, m, s).unwrap());
        assert_eq!(maps[0].increment_storage(), IncrementStorage::Stored);
        assert_eq!(maps[1].increment_storage(), IncrementStorage::Streamed);
        assert_eq!(maps[0].increment_bytes(), 8 * n * m);
        assert_eq!(maps[1].increment_bytes(), 40 * n);
        let runs: Vec<_> = maps
            .iter_mut()
            .map(|map| {
                map.record_tangent(true);
                let (mut x, mut acc) = (vec![0.0; n], vec![0.0; nb]);
                let mut periods = Vec::new();
                for _ in 0..3 {
                    map.run_period(&mut x, &mut acc, None).unwrap();
                    periods.push((x.clone(), acc.clone()));
                }
                // The recorded tangent and a tangent period from the last state.
                let mut dx: Vec<f64> = (0..n).map(|l| ((l * 7 % 5) as f64 - 2.0) / 3.0).collect();
                map.apply_tangent(&mut dx);
                let mut dy = dx.clone();
                assert!(map.run_period_tangent(&mut x, &mut dy).unwrap());
                (periods, dx, dy, x)
            })
            .collect();
        assert_eq!(runs[0], runs[1], "N = {nb}, m = {m}");
        // Not vacuous: the crawler moved and the tangent is not zero.
        assert!(runs[0].0[2].1.iter().any(|d| d.abs() > 1e-3), "N = {nb}");
        tangents += runs[0].1.iter().any(|d| d.abs() > 1e-6) as usize;
    }
    assert!(tangents >= 3, "{tangents} non-zero tangents");
}

#[test]
fn a_search_with_streamed_increments_is_the_stored_search() {
    for (c, a, m) in cases() {
        let opts = |budget| SimOptions {
            method: Method::CatchingUp,
            steps_per_period: m,
            record_periods: 2,
            increment_budget: budget,
            ..SimOptions::default()
        };
        let stored = simulate(&c, &a, &opts(SimOptions::DEFAULT.increment_budget)).unwrap();
        let streamed = simulate(&c, &a, &opts(0)).unwrap();
        assert!(stored.converged && stored.trajectory.is_some());
        assert_eq!(stored, streamed, "N = {}", c.blocks());
        // The exact method's Newton steps take catching-up's Jacobian: streamed there too.
        let exact = |budget| SimOptions {
            method: Method::Exact,
            ..opts(budget)
        };
        let (e0, e1) = (
            simulate(&c, &a, &exact(SimOptions::DEFAULT.increment_budget)).unwrap(),
            simulate(&c, &a, &exact(0)).unwrap(),
        );
        assert_eq!(e0, e1, "exact, N = {}", c.blocks());
    }
}

#[test]
fn the_budget_chooses_the_storage_and_a_table_beyond_the_sample_limit_is_refused() {
    let within = IncrementStorage::within;
    assert_eq!(within(8000, 1000, 1), IncrementStorage::Stored);
    assert_eq!(within(7999, 1000, 1), IncrementStorage::Streamed);
    assert_eq!(within(0, 1, 1), IncrementStorage::Streamed);
    assert_eq!(
        within(usize::MAX, usize::MAX, usize::MAX),
        IncrementStorage::Streamed
    );
    // The default keeps 1000 x 1000 (8 MB) and streams 10^4 x 1000 (80 MB).
    let d = IncrementStorage::DEFAULT_BUDGET;
    assert_eq!(within(d, 1000, 1000), IncrementStorage::Stored);
    assert_eq!(within(d, 10_000, 1000), IncrementStorage::Streamed);
    let c = Crawler::uniform(5, 1.0, 1.0, 3.3).unwrap();
    let a = Actuation::wave(
        Waveform::Sine,
        1.0,
        vec![0.0; 4],
        vec![2.0; 4],
        vec![0.0; 4],
    );
    let opts = SimOptions {
        method: Method::CatchingUp,
        steps_per_period: 9_000_000,
        max_periods: 1,
        record_periods: 0,
        increment_budget: usize::MAX,
        ..SimOptions::default()
    };
    let e = simulate(&c, &a.unwrap(), &opts).unwrap_err().to_string();
    assert!(e.contains("increment_budget") && e.contains("2.5e7"), "{e}");
}
