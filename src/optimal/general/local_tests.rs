//! Tests of [`super`]: the neighbours' test pruned to the switches that can gain (module
//! docs). With every degenerate pair tried, no switch the pruning would skip ever gains.

use super::super::branch_lp::{EVERY_NEIGHBOUR, PRUNED_TRIALS};
use super::*;
use crate::model::general::GeneralParts;
use crate::model::{crawler_as_general, Crawler};
use crate::optimal::general::analyze_polyhedron;
use proptest::prelude::*;

/// P_m locally from each square-wave start by `rules` with every neighbour tried: returns how
/// many of the switches the pruning would skip were tried, asserting that none gained; the
/// answers are asserted to be at least their start.
fn pruned_switches_never_gain(p: &GeneralProblem, m: u32, rules: LocalRules) -> usize {
    let g = analyze_polyhedron(&p.c).unwrap();
    EVERY_NEIGHBOUR.with(|e| e.set(true));
    PRUNED_TRIALS.with(|n| n.set((0, 0)));
    for start in default_starts(p, m, 2) {
        if let Ok(s) = solve_general_local(p, &g, m, &start, rules) {
            assert!(s.objective >= s.start_objective - 1e-9 * (1.0 + s.objective.abs()));
        }
    }
    EVERY_NEIGHBOUR.with(|e| e.set(false));
    let (tried, gains) = PRUNED_TRIALS.with(|n| n.get());
    assert_eq!(
        gains, 0,
        "{gains} of {tried} switches the pruning skips gained"
    );
    tried
}

/// A random polygon, no two faces opposite: every switch the pruning skips is of an unpaired
/// face, whose neighbour never gains where its rate does not pay.
fn polygon(sigma: usize, numbers: &[f64]) -> GeneralProblem {
    let r = |k: usize| numbers[k % numbers.len()];
    GeneralProblem::new(GeneralParts {
        normals: (0..sigma)
            .map(|k| {
                let th = std::f64::consts::TAU * (k as f64 + 0.4 * r(k)) / sigma as f64;
                vec![th.cos(), th.sin()]
            })
            .collect(),
        offsets: (0..sigma).map(|k| 0.5 + 2.0 * r(k + 7).abs()).collect(),
        a: Some(vec![vec![r(1), r(2)], vec![r(3), r(4)]]),
        b: vec![vec![1.0 + r(5), r(6)], vec![r(8), 1.0 + r(9)]],
        drift: Some(vec![0.2 * r(10), 0.2 * r(11)]),
        lower: Some(vec![-1.0, -1.0]),
        upper: Some(vec![1.0, 1.0]),
        zero_mean: true,
        face_weights: Some((0..sigma).map(|k| 0.4 + 1.2 * r(k + 12)).collect()),
        period: 4.0 + 8.0 * r(13).abs(),
        periodic: true,
        ..Default::default()
    })
    .unwrap()
}

/// A crawler's instance (every face paired, a block's friction bound), `None` where the
/// numbers break the uniqueness condition.
fn crawler_instance(blocks: usize, numbers: &[f64]) -> Option<GeneralProblem> {
    let r = |k: usize| numbers[k % numbers.len()];
    let crawler = Crawler::new(
        (0..blocks - 1).map(r).collect(),
        (0..blocks).map(|b| r(b + 3)).collect(),
        (0..blocks).map(|b| r(b + 7) + 0.6).collect(),
    )
    .ok()
    .filter(|c| c.require_unique().is_ok())?;
    let rates = vec![1.0; blocks - 1];
    let inst = crawler_as_general(&crawler, 10.0, &rates, GeneralCost::None).unwrap();
    Some(inst.problem)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn no_pruned_switch_gains_on_polygons(
        sigma in 3usize..=6,
        m in 2u32..=3,
        numbers in prop::collection::vec(-0.5f64..0.5, 19),
    ) {
        // The default rules (a crawler's, since both kinds share them) and (P)'s former ones.
        let former = LocalRules {
            pivoting: Pivoting::Neighbours,
            start: StartFaces::Reacting,
        };
        for rules in [LocalRules::default(), former] {
            pruned_switches_never_gain(&polygon(sigma, &numbers), m, rules);
        }
    }

    #[test]
    fn no_pruned_switch_gains_on_crawlers(
        blocks in 2usize..=4,
        m in 2u32..=5,
        numbers in prop::collection::vec(0.5f64..1.5, 12),
        touched in any::<bool>(),
    ) {
        if let Some(p) = crawler_instance(blocks, &numbers) {
            let start = if touched { StartFaces::Touched } else { StartFaces::Reacting };
            for pivoting in [Pivoting::Neighbours, Pivoting::Finish] {
                pruned_switches_never_gain(&p, m, LocalRules { pivoting, start });
            }
        }
    }
}

/// The pruning has work to do: on the three-block crawler, and on a polygon, the neighbours'
/// test meets switches it skips (and none of them gains).
#[test]
fn the_pruning_skips_switches_on_three_blocks_and_a_polygon() {
    let numbers = [0.5, 0.7, 0.9, 1.1, 1.3, 1.0, 0.8, 1.2, 0.6, 1.4, 1.0, 0.9];
    let three = crawler_instance(3, &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.9, 0.9, 0.9]);
    let skipped = pruned_switches_never_gain(&three.unwrap(), 4, LocalRules::default());
    assert!(skipped > 0, "no switch skipped on three blocks");
    let shape: Vec<f64> = numbers.iter().map(|v| v - 1.0).collect();
    let skipped = pruned_switches_never_gain(&polygon(5, &shape), 3, LocalRules::default());
    assert!(skipped > 0, "no switch skipped on a polygon");
}

/// A search from several starts keeps the best of them, each solved as it is alone, and its
/// finish (from the basis the best start ended on) ends `stationary` at least as high; a search
/// without a start is refused naming `start`, not a panic.
#[test]
fn a_search_keeps_the_best_start_and_its_finish_does_not_lose() {
    let p = crawler_instance(3, &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.9, 0.9, 0.9]).unwrap();
    let g = analyze_polyhedron(&p.c).unwrap();
    let m = 4;
    let starts = default_starts(&p, m, 4);
    let screen = LocalRules {
        pivoting: Pivoting::ReducedCosts,
        start: StartFaces::Touched,
    };
    let alone: Vec<f64> = starts
        .iter()
        .map(|s| solve_general_local(&p, &g, m, s, screen).unwrap().objective)
        .collect();
    let mut told = Vec::new();
    let plan = MultiStart {
        rules: screen,
        finish: None,
    };
    let best = solve_general_local_best(&p, &g, m, &starts, plan, &mut |k| told.push(k)).unwrap();
    assert_eq!(told, (0..starts.len()).collect::<Vec<_>>());
    assert_eq!(best.tried, starts.len());
    let top = alone.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(best.solution.objective, alone[best.best_start]);
    assert!(best.solution.objective >= top - 1e-9 * (1.0 + top.abs()));
    // The first of equals: no start before the kept one was better.
    let kept = best.solution.objective;
    assert!(alone[..best.best_start]
        .iter()
        .all(|&j| j <= kept + 1e-9 * (1.0 + kept.abs())));
    let plan = MultiStart {
        rules: screen,
        finish: Some(Pivoting::Finish),
    };
    let finished = solve_general_local_best(&p, &g, m, &starts, plan, &mut |_| {}).unwrap();
    assert_eq!(finished.best_start, best.best_start);
    assert_eq!(finished.solution.stop, LocalStop::Stationary);
    let j = finished.solution.objective;
    assert!(
        j >= top - 1e-9 * (1.0 + top.abs()),
        "{j} below the screen's {top}"
    );
    assert!(finished.solution.lp_solves >= best.solution.lp_solves);
    let none = solve_general_local_best(&p, &g, m, &[], plan, &mut |_| {});
    assert!(matches!(none, Err(Error::InvalidParameter { field, .. }) if field == "start"));
}

/// A rotation is a crawler's time shift: the `j`-th rotation of a grid's control is the same
/// gait advanced by its [`rotation_shift`] as the crawler advances one
/// ([`crate::optimal::shift_knots`]: the actuator lengths integrated from the control, shifted,
/// and sampled back on the grid by [`crate::optimal::sample_increments`]); where `shifts`
/// divides the grid, that shift is the crawler's `j`-th, `j T / shifts`. Also for shifts that
/// do not divide it, and for more shifts than steps (equal rotations tried once).
#[test]
fn a_rotation_is_the_crawlers_time_shift_of_the_same_gait() {
    use crate::optimal::{sample_increments, shift_knots};
    let (steps, period) = (8, 2.0);
    let h = period / steps as f64;
    let u: Vec<Vec<f64>> = [3.0, -1.0, 2.0, 0.5, -2.5, 1.0, -1.5, -1.5]
        .iter()
        .map(|&v| vec![v])
        .collect();
    // The gait's knots: L at the grid's times, L' = u (one link of unit stiffness).
    let times: Vec<f64> = (0..=steps).map(|k| k as f64 * h).collect();
    let mut lengths = vec![vec![0.0]];
    for v in &u {
        let last = lengths.last().unwrap()[0];
        lengths.push(vec![last + v[0] * h]);
    }
    for shifts in [1, 3, 8, 16] {
        let grids = rotated(&u, shifts);
        for (j, grid) in grids.iter().enumerate() {
            let shift = rotation_shift(steps, shifts, j, period);
            if steps % shifts == 0 {
                assert_eq!(shift, period * j as f64 / shifts as f64);
            }
            let (t, l) = shift_knots(&times, &lengths, shift, period);
            let sampled = sample_increments(&t, &l, &[1.0], &[10.0], period, steps);
            for (k, (a, b)) in grid.iter().zip(&sampled).enumerate() {
                assert!(
                    (a[0] * h - b[0]).abs() < 1e-12,
                    "shifts {shifts}, rotation {j}, step {k}: {} against {}",
                    a[0] * h,
                    b[0]
                );
            }
        }
    }
}
