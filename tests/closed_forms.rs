//! The one-link crawler against the closed forms of theory §9–10 (paper §4).

mod common;
use common::{disp, sine};
use crawlopt::integrate::{Actuation, Method};
use crawlopt::Crawler;

const TOL: f64 = 1e-11;

#[test]
fn sine_gait_moves_max_0_2a_minus_2() {
    // theory §10: N = 2, k = 1, mu+ = 1, mu- = 2, L = A sin(2 pi t): max(0, 2A - 2) per period.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    for a in [0.5, 1.0, 1.25, 2.0, 3.0, 7.5] {
        let want = f64::max(0.0, 2.0 * a - 2.0);
        let act = sine(1, 1.0, a, 0.0);
        for m in [4, 8, 100, 1000] {
            for method in [Method::CatchingUp, Method::Exact] {
                let got = disp(&c, &act, method, m);
                assert!(
                    (got - want).abs() < TOL,
                    "A = {a}, M = {m}, {method}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn rise_and_fall_moves_delta_l_minus_w_over_k() {
    // theory §9 with asymmetric friction and k != 1: C = [alpha, beta], w = beta - alpha,
    // any monotone rise by dL and fall back moves max(0, dL - w/k) per period.
    let (mp, mm) = (vec![1.0, 0.8], vec![2.5, 1.7]);
    let alpha = f64::max(-mp[0], -mm[1]);
    let beta = f64::min(mm[0], mp[1]);
    let w = beta - alpha;
    assert!((w - 1.8).abs() < 1e-15);
    for k in [0.5, 1.0, 3.0] {
        let c = Crawler::new(vec![k], mp.clone(), mm.clone()).unwrap();
        for dl in [0.3, 1.0, 2.0, 4.5] {
            let want = f64::max(0.0, dl - w / k);
            // Rise in two unequal pieces, hold, fall in three: shape and timing do not matter.
            let act = Actuation::piecewise_linear(
                5.0,
                vec![0.0, 0.4, 1.9, 2.5, 3.0, 4.1],
                vec![
                    vec![0.0],
                    vec![0.2 * dl],
                    vec![dl],
                    vec![dl],
                    vec![0.7 * dl],
                    vec![0.1 * dl],
                ],
            )
            .unwrap();
            let got = disp(&c, &act, Method::Exact, 0);
            assert!(
                (got - want).abs() < TOL,
                "k = {k}, dL = {dl}: {got} vs {want}"
            );
            // Catching-up is exact for N = 2: any grid that hits the extremes of L.
            let got = disp(&c, &act, Method::CatchingUp, 50);
            assert!(
                (got - want).abs() < TOL,
                "catching-up k = {k}, dL = {dl}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn catching_up_is_exact_for_one_link_at_any_m() {
    // On the grid's own piecewise-linear interpolant, catching-up equals the exact solution for
    // N = 2, even when the grid misses the peaks (M not a multiple of 4).
    let c = Crawler::new(vec![1.3], vec![1.0, 0.6], vec![2.0, 1.9]).unwrap();
    let act = sine(1, 2.0, 2.2, 0.0);
    for m in [5, 7, 13, 101] {
        let cu = disp(&c, &act, Method::CatchingUp, m);
        let ex = disp(&c, &act, Method::Exact, m);
        assert!((cu - ex).abs() < TOL, "M = {m}: {cu} vs {ex}");
        assert!(cu > 0.0);
    }
}

#[test]
fn one_sided_friction_cannot_move_periodically() {
    // theory §9: if only extension (or only contraction) moves forward, v_m is linear and every
    // periodic gait gives zero net displacement.
    for (mp, mm) in [
        (vec![1.0, 0.5], vec![2.0, 0.8]),
        (vec![0.5, 2.0], vec![0.8, 1.0]),
    ] {
        let c = Crawler::new(vec![1.0], mp, mm).unwrap();
        let o = c.analyze().one_link.unwrap();
        assert_ne!(o.extension_moves_forward, o.contraction_moves_forward);
        assert_eq!(c.analyze().vm_class, Some(crawlopt::model::VmClass::Linear));
        for a in [0.5, 3.0] {
            let act = sine(1, 1.0, a, 0.0);
            for method in [Method::CatchingUp, Method::Exact] {
                let got = disp(&c, &act, method, 64);
                assert!(got.abs() < TOL, "{got}");
            }
        }
    }
}

#[test]
fn minimum_at_for_locomotion_is_twice_the_width() {
    // theory §9: J* = max(0, (aT - 2w)/(2k)) for the bang-bang gait u = +a for T/2, -a for T/2;
    // the analysis reports the threshold 2w.
    let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
    let o = c.analyze().one_link.unwrap();
    assert_eq!(o.min_at_forward, Some(4.0));
    // Bang-bang gait with a = 1, T = 10: L rises at rate a/k for T/2 and falls back.
    let (a, t, k) = (1.0, 10.0, 1.0);
    let act = Actuation::piecewise_linear(
        t,
        vec![0.0, t / 2.0],
        vec![vec![0.0], vec![a * t / 2.0 / k]],
    )
    .unwrap();
    let got = disp(&c, &act, Method::Exact, 0);
    assert!(
        (got - 3.0).abs() < TOL,
        "theory §10 reference J* = 3, got {got}"
    );
}
