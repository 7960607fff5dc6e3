//! The exact dynamic-programming projection onto C ([`ChainDp`]) against the active-set method
//! ([`ChainQp`]) on random chains (per-link stiffness, per-block friction) and random states:
//! the same minimiser and the same block displacements (multipliers, theory §4) to 1e-12 relative.

use crawlopt::sweep::{increment, Bound, ChainDp, ChainQp, ChainWarm};
use crawlopt::Crawler;
use proptest::prelude::*;

/// Random chains whose uniqueness condition holds with a margin of at least `1 / (8 N)`:
/// `mu^+` multiples of 1/4 and `mu^-` multiples of 1/4 plus `1 / (8 N)`, so that
/// `sum_J mu^+ - sum_{J^c} mu^-` is `|J^c| / (8 N)` modulo 1/4 (the block displacements at a
/// vertex of C are as well conditioned as that margin; with real-valued random thresholds the
/// margin of 40 blocks is ~1e-8 and D is determined only to ~1e-8 relative).
fn crawler_strategy() -> impl Strategy<Value = Crawler> {
    crawler_strategy_upto(40)
}

/// [`crawler_strategy`] with 2 to `max_blocks` blocks.
fn crawler_strategy_upto(max_blocks: usize) -> impl Strategy<Value = Crawler> {
    (2usize..=max_blocks)
        .prop_flat_map(|nb| {
            (
                prop::collection::vec(0.2f64..5.0, nb - 1),
                prop::collection::vec(1u32..=12, nb),
                prop::collection::vec(1u32..=12, nb),
            )
        })
        .prop_map(|(k, mp, mm)| {
            let nb = mp.len() as f64;
            let mp = mp.iter().map(|&i| i as f64 / 4.0).collect();
            let mm = mm
                .iter()
                .map(|&j| j as f64 / 4.0 + 1.0 / (8.0 * nb))
                .collect();
            Crawler::new(k, mp, mm).unwrap()
        })
}

/// Both solvers on `v`, the active-set one warm-started from `x_prev` (in C); returns the worst
/// difference of x and of D, relative to the scale of the data.
fn compare(c: &Crawler, qp: &mut ChainQp, x_prev: &mut [f64], v: &[f64]) -> (f64, f64) {
    let (n, nb) = (c.links(), c.blocks());
    let lo: Vec<f64> = c.mu_forward().iter().map(|m| -m).collect();
    let hi = c.mu_backward().to_vec();
    let mut dp = ChainDp::new(c.stiffness());
    let (mut x1, mut d1) = (vec![0.0; n], vec![0.0; nb]);
    dp.solve(&lo, &hi, v, &mut x1, &mut d1);
    let mut d2 = vec![0.0; nb];
    qp.solve(&lo, &hi, v, x_prev, &mut d2).unwrap();
    let scale = v
        .iter()
        .chain(x_prev.iter())
        .fold(c.state_scale(), |m, a| m.max(a.abs()));
    let kmin = c.stiffness().iter().copied().fold(f64::INFINITY, f64::min);
    let dx = x1
        .iter()
        .zip(x_prev.iter())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let dd = d1
        .iter()
        .zip(&d2)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    (dx / scale, dd * kmin / scale)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn dp_equals_active_set_from_rest_and_along_steps(
        (c, pts, far) in crawler_strategy().prop_flat_map(|c| {
            let n = c.links();
            (Just(c), prop::collection::vec(prop::collection::vec(-3.0f64..3.0, n), 1..30),
             prop::collection::vec(-1.0e3f64..1.0e3, n))
        })
    ) {
        let n = c.links();
        // Catching-up steps (warm active set) and a far point from rest (cold).
        let mut qp = ChainQp::new(c.stiffness());
        let mut x = vec![0.0; n];
        for delta in &pts {
            let v: Vec<f64> = x.iter().zip(delta).map(|(a, b)| a + b).collect();
            let (ex, ed) = compare(&c, &mut qp, &mut x, &v);
            prop_assert!(ex <= 1e-12 && ed <= 1e-12, "x: {ex:e}, D: {ed:e}");
        }
        let mut cold = ChainQp::new(c.stiffness());
        let mut x0 = vec![0.0; n];
        let (ex, ed) = compare(&c, &mut cold, &mut x0, &far);
        prop_assert!(ex <= 1e-12 && ed <= 1e-12, "far point: x: {ex:e}, D: {ed:e}");
    }
}

/// The tangent map of a catching-up period (each step's projection differentiated on its active
/// faces) is the derivative of the period map: the period map is piecewise affine, so a small
/// perturbation of the state moves the end of the period by exactly `J` times it (up to
/// rounding) unless it crosses a change of pattern. The three projection methods give the same
/// `J w`.
#[test]
fn period_tangent_is_the_derivative_of_the_period_map() {
    use crawlopt::integrate::{Actuation, CatchingUp, PeriodMap, Waveform};
    use crawlopt::sweep::ProjectionMethod;
    let nb = 40;
    let c = Crawler::new(
        (0..nb - 1).map(|l| 0.5 + (l % 3) as f64 * 0.5).collect(),
        (0..nb).map(|b| 1.0 + (b % 2) as f64 * 0.25).collect(),
        (0..nb)
            .map(|b| 3.0 + (b % 3) as f64 * 0.25 + 1.0 / (8.0 * nb as f64))
            .collect(),
    )
    .unwrap();
    c.require_unique().unwrap();
    let n = c.links();
    let act = Actuation::wave(
        Waveform::Sine,
        1.0,
        vec![0.0; n],
        vec![2.0; n],
        (0..n).map(|l| 90.0 * l as f64).collect(),
    )
    .unwrap();
    let w: Vec<f64> = (0..n).map(|l| ((l * 7 % 11) as f64 - 5.0) / 5.0).collect();
    let mut tangents = Vec::new();
    for method in [
        ProjectionMethod::Dp,
        ProjectionMethod::ActiveSet,
        ProjectionMethod::Warm,
    ] {
        let mut cu = CatchingUp::new(&c, &act, 400).unwrap();
        cu.set_method(method);
        let mut x0 = vec![0.0; n];
        let mut acc = vec![0.0; nb];
        for _ in 0..20 {
            cu.run_period(&mut x0, &mut acc, None).unwrap();
        }
        let (mut xa, mut jw) = (x0.clone(), w.clone());
        assert!(cu.run_period_tangent(&mut xa, &mut jw).unwrap());
        let eps = 1e-7;
        let mut xb: Vec<f64> = x0.iter().zip(&w).map(|(a, b)| a + eps * b).collect();
        let mut xc = x0.clone();
        cu.run_period(&mut xb, &mut acc, None).unwrap();
        cu.run_period(&mut xc, &mut acc, None).unwrap();
        let err = (0..n)
            .map(|l| ((xb[l] - xc[l]) / eps - jw[l]).abs())
            .fold(0.0, f64::max);
        let size = jw.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
        assert!(size > 1e-3, "the tangent must not vanish: {size}");
        assert!(
            err <= 1e-6,
            "method {method:?}: J w off by {err:e} (|J w| = {size})"
        );
        tangents.push(jw);
    }
    for t in &tangents[1..] {
        let diff = (0..n)
            .map(|l| (tangents[0][l] - t[l]).abs())
            .fold(0.0, f64::max);
        assert!(diff <= 1e-9, "the methods' tangents differ by {diff:e}");
    }
}

/// On the bench gait with 1000 blocks, twenty periods from rest move every block the same with
/// the three projection methods, to 1e-10.
#[test]
fn long_chain_periods_agree_between_methods() {
    use crawlopt::integrate::{Actuation, CatchingUp, PeriodMap, Waveform};
    use crawlopt::sweep::ProjectionMethod;
    let nb = 1000;
    let c = Crawler::uniform(nb, 1.0, 1.0, 3.3).unwrap();
    let n = c.links();
    let act = Actuation::wave(
        Waveform::Sine,
        1.0,
        vec![0.0; n],
        vec![2.0; n],
        (0..n).map(|l| 90.0 * l as f64).collect(),
    )
    .unwrap();
    let mut out = Vec::new();
    for method in [
        ProjectionMethod::Dp,
        ProjectionMethod::ActiveSet,
        ProjectionMethod::Warm,
    ] {
        let mut cu = CatchingUp::new(&c, &act, 1000).unwrap();
        cu.set_method(method);
        let (mut x, mut acc) = (vec![0.0; n], vec![0.0; nb]);
        for _ in 0..20 {
            cu.run_period(&mut x, &mut acc, None).unwrap();
        }
        out.push((x, acc));
    }
    let y = out[1].1.iter().sum::<f64>() / nb as f64;
    assert!(y > 10.0, "the crawler moves: {y}");
    for o in &out[1..] {
        let dx = (0..n)
            .map(|l| (out[0].0[l] - o.0[l]).abs())
            .fold(0.0, f64::max);
        let dd = (0..nb)
            .map(|b| (out[0].1[b] - o.1[b]).abs())
            .fold(0.0, f64::max);
        assert!(dx <= 1e-10 * c.state_scale(), "states differ by {dx:e}");
        assert!(dd <= 1e-10 * y, "block displacements differ by {dd:e}");
    }
}

/// Random chains of 1 to 300 links with the margin of [`crawler_strategy`].
fn long_crawler_strategy() -> impl Strategy<Value = Crawler> {
    crawler_strategy_upto(301)
}

/// [`ChainWarm`] (guess from its last working set, certify, repair) against [`ChainDp`] and the
/// warm [`ChainQp`] on `v`: the worst differences of x and D relative to the scale, and whether
/// the faces agree on every block that is not degenerate (a multiplier clearly nonzero, or an
/// increment clearly inside its bounds).
fn compare_warm(
    c: &Crawler,
    warm: &mut ChainWarm,
    qp: &mut ChainQp,
    x_qp: &mut [f64],
    v: &[f64],
) -> (f64, f64, bool) {
    let (n, nb) = (c.links(), c.blocks());
    let lo: Vec<f64> = c.mu_forward().iter().map(|m| -m).collect();
    let hi = c.mu_backward().to_vec();
    let mut dp = ChainDp::new(c.stiffness());
    let (mut x1, mut d1) = (vec![0.0; n], vec![0.0; nb]);
    dp.solve(&lo, &hi, v, &mut x1, &mut d1);
    // The same step as a catching-up step from x_qp (`solve_increment`, v formed in the pass)
    // by a twin of the warm solver with the same guess.
    let mut twin = warm.clone();
    let mut x4 = x_qp.to_vec();
    let delta: Vec<f64> = v.iter().zip(&x4).map(|(a, b)| a - b).collect();
    let mut d4 = vec![f64::NAN; nb];
    twin.solve_increment(&mut x4, &delta, &mut d4);
    let mut d2 = vec![0.0; nb];
    qp.solve(&lo, &hi, v, x_qp, &mut d2).unwrap();
    let (mut x3, mut d3) = (vec![f64::NAN; n], vec![f64::NAN; nb]);
    warm.solve(v, &mut x3, &mut d3);
    let scale = v.iter().fold(c.state_scale(), |m, a| m.max(a.abs()));
    let kmin = c.stiffness().iter().copied().fold(f64::INFINITY, f64::min);
    let mut ex: f64 = 0.0;
    for l in 0..n {
        ex = ex
            .max((x3[l] - x1[l]).abs())
            .max((x3[l] - x_qp[l]).abs())
            .max((x4[l] - x1[l]).abs());
    }
    let mut ed: f64 = 0.0;
    for b in 0..nb {
        ed = ed
            .max((d3[b] - d1[b]).abs())
            .max((d3[b] - d2[b]).abs())
            .max((d4[b] - d1[b]).abs());
    }
    let tol = 1e-9 * scale;
    let faces_agree = (0..nb).all(|b| {
        let w = warm.working_set()[b];
        let inc = increment(&x1, b);
        let clearly_free = inc - lo[b] > tol && hi[b] - inc > tol;
        let clearly_active = d1[b].abs() * kmin > tol;
        let others = [
            dp.working_set()[b],
            qp.working_set()[b],
            twin.working_set()[b],
        ];
        if clearly_free {
            w == Bound::Free && others.iter().all(|&o| o == Bound::Free)
        } else if clearly_active {
            w != Bound::Free && others.iter().all(|&o| o == w)
        } else {
            true
        }
    });
    (ex / scale, ed * kmin / scale, faces_agree)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 192, failure_persistence: None, ..ProptestConfig::default() })]

    /// The warm projection equals the DP and the active-set method to 1e-12 along sequences of
    /// catching-up steps of random sizes (from orbit-like steps that keep the faces to jumps that
    /// change most of them), from rest (an empty guess) and from a random wrong guess.
    #[test]
    fn warm_equals_dp_and_active_set(
        (c, steps, far, guess) in long_crawler_strategy().prop_flat_map(|c| {
            let (n, nb) = (c.links(), c.blocks());
            (Just(c),
             prop::collection::vec(
                 (prop::collection::vec(-3.0f64..3.0, n), -4i32..=0), 1..25),
             prop::collection::vec(-1.0e3f64..1.0e3, n),
             prop::collection::vec(0u8..3, nb))
        })
    ) {
        let (n, nb) = (c.links(), c.blocks());
        let lo: Vec<f64> = c.mu_forward().iter().map(|m| -m).collect();
        let mut warm = ChainWarm::new(c.stiffness(), &lo, c.mu_backward());
        let mut qp = ChainQp::new(c.stiffness());
        let mut x = vec![0.0; n];
        for (delta, e) in &steps {
            let h = 10f64.powi(*e);
            let v: Vec<f64> = x.iter().zip(delta).map(|(a, b)| a + h * b).collect();
            let (ex, ed, faces) = compare_warm(&c, &mut warm, &mut qp, &mut x, &v);
            prop_assert!(ex <= 1e-12 && ed <= 1e-12, "step: x: {ex:e}, D: {ed:e}");
            prop_assert!(faces, "step: the faces differ");
        }
        // Cold: an empty guess, and a random one (faces that need not be anywhere near).
        let mut cold = ChainWarm::new(c.stiffness(), &lo, c.mu_backward());
        let (mut qp0, mut x0) = (ChainQp::new(c.stiffness()), vec![0.0; n]);
        let (ex, ed, faces) = compare_warm(&c, &mut cold, &mut qp0, &mut x0, &far);
        prop_assert!(ex <= 1e-12 && ed <= 1e-12 && faces, "far point: x: {ex:e}, D: {ed:e}");
        let ws: Vec<Bound> = guess
            .iter()
            .map(|g| [Bound::Free, Bound::Lower, Bound::Upper][*g as usize])
            .collect();
        let mut wrong = ChainWarm::new(c.stiffness(), &lo, c.mu_backward());
        wrong.set_working_set(&ws);
        let (mut qp1, mut x1) = (ChainQp::new(c.stiffness()), vec![0.0; n]);
        let (ex, ed, faces) = compare_warm(&c, &mut wrong, &mut qp1, &mut x1, &far);
        prop_assert!(ex <= 1e-12 && ed <= 1e-12 && faces, "wrong guess: x: {ex:e}, D: {ed:e}");
        prop_assert_eq!(wrong.working_set().len(), nb);
    }
}

/// An exact tie: a step whose start and end lie on vertices of C (an optimal gait's orbit; found
/// by fuzzing on a six-block P_4 answer). Blocks 1 and 2 slide together by 7.358 while the
/// minimiser of the chain's first link falls on block 2's face to within rounding; the dynamic
/// programme and the warm method took block 2 as free and reported D = 0 for both (the state
/// right), so a replay of the gait moved the crawler 41.48 a period instead of 43.94. Every
/// method must give the active-set method's displacements, from the exact state and from one
/// moved by 1e-12.
#[test]
fn a_step_between_vertices_of_c_keeps_its_block_displacements() {
    use crawlopt::sweep::{ProjectionMethod, Projector};
    let c = Crawler::new(
        vec![9.931; 5],
        vec![2.542, 1.974, 1.244, 2.727, 1.465, 2.81],
        vec![2.739, 1.484, 1.338, 1.807, 1.02, 0.533],
    )
    .unwrap();
    // The answer's own numbers, to the last digit (the tie is in their rounding).
    let start = [
        0.8369999999999999,
        2.3209999999999997,
        3.659,
        0.9320000000000002,
        -0.533,
    ];
    let h = 1.8545;
    let u = [
        -1.8220544621191692,
        -43.09060900000001,
        -3.784847667834997,
        -1.3399838231329197,
        3.923632846849055e-16,
    ];
    let delta: Vec<f64> = u.iter().map(|u| u * h).collect();
    for moved in [0.0, -1e-12, 1e-12] {
        let x0: Vec<f64> = start.iter().map(|v| v + moved).collect();
        let step = |method| {
            let mut p = Projector::new(&c).unwrap();
            p.set_method(method);
            let (mut x, mut d) = (vec![0.0; 5], vec![0.0; 6]);
            p.project_from_origin(&x0, &mut x, &mut d).unwrap();
            p.step(&mut x, &delta, &mut d).unwrap();
            (x, d)
        };
        let (x_ref, d_ref) = step(ProjectionMethod::ActiveSet);
        assert!(
            (d_ref[0] - 7.358).abs() < 1e-3 && (d_ref[1] - 7.358).abs() < 1e-3,
            "{d_ref:?}"
        );
        for method in [ProjectionMethod::Warm, ProjectionMethod::Dp] {
            let (x, d) = step(method);
            for (a, b) in x.iter().zip(&x_ref).chain(d.iter().zip(&d_ref)) {
                assert!(
                    (a - b).abs() <= 1e-9,
                    "{method:?}, moved {moved}: {d:?} vs {d_ref:?}"
                );
            }
        }
    }
}
