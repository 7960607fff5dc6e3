//! The general problem (P) (theory §11): the exact projection onto a polyhedron against an
//! independent enumeration of active sets and the variational inequality, the catching-up
//! simulation against closed forms (the paper's §4 one-link problem in general form, a box with
//! linear drift), and the crawler as an instance (same steps as the dedicated crawler path).

mod common;

use common::Rng;
use crawlopt::integrate::{
    simulate, simulate_general, simulate_general_exact, Actuation, ControlInput, GeneralSimOptions,
    InputKind, Method, SimOptions,
};
use crawlopt::model::general::{GeneralCost, GeneralParts, GeneralProblem, Polyhedron};
use crawlopt::model::{crawler_as_general, Crawler, CrawlerInstance};
use crawlopt::sweep::{PolyProjector, Projector};

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The projection by enumeration: every set S of at most n faces with independent normals, the
/// point `z = v - N_S^T mu` on those faces; the one that is feasible with `mu >= 0` satisfies
/// the KKT conditions, which determine the projection uniquely.
fn project_by_enumeration(c: &Polyhedron, v: &[f64]) -> Vec<f64> {
    let (sigma, n) = (c.faces(), c.dim());
    let mut best: Option<Vec<f64>> = None;
    for mask in 0u32..(1 << sigma) {
        let s: Vec<usize> = (0..sigma).filter(|j| mask & (1 << j) != 0).collect();
        if s.len() > n {
            continue;
        }
        let k = s.len();
        let gram = nalgebra::DMatrix::from_fn(k, k, |a, b| dot(&c.normals[s[a]], &c.normals[s[b]]));
        if k > 0 && gram.determinant().abs() < 1e-8 {
            continue;
        }
        let rhs = nalgebra::DVector::from_iterator(
            k,
            s.iter().map(|&j| dot(&c.normals[j], v) - c.offsets[j]),
        );
        let mu = if k == 0 {
            rhs.clone()
        } else {
            gram.lu().solve(&rhs).unwrap()
        };
        let mut z = v.to_vec();
        for (a, &j) in s.iter().enumerate() {
            for i in 0..n {
                z[i] -= mu[a] * c.normals[j][i];
            }
        }
        let feasible = (0..sigma).all(|j| c.slack(j, &z) <= 1e-10);
        if feasible && mu.iter().all(|m| *m >= -1e-10) {
            best = Some(z);
            break;
        }
    }
    best.expect("a KKT point exists")
}

fn random_polytope(rng: &mut Rng, n: usize, sigma: usize) -> Polyhedron {
    let normals = (0..sigma)
        .map(|_| (0..n).map(|_| rng.range(-1.0, 1.0)).collect())
        .collect();
    let offsets = (0..sigma).map(|_| rng.range(0.3, 2.0)).collect();
    Polyhedron::new(normals, offsets, "C").unwrap()
}

#[test]
fn the_projection_is_exact_on_random_polytopes() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut cases = 0;
    for n in 2..=3 {
        for sigma in 3..=8 {
            for _ in 0..25 {
                let c = random_polytope(&mut rng, n, sigma);
                let mut proj = PolyProjector::new(c.clone());
                // A chain of projections, each warm-started from the previous answer (the
                // catching-up scheme's use), from the interior point 0.
                let mut x = vec![0.0; n];
                for _ in 0..6 {
                    let v: Vec<f64> = (0..n).map(|_| rng.range(-4.0, 4.0)).collect();
                    let a = proj.project(&x, &v).unwrap();
                    let scale = v.iter().fold(2.0_f64, |m, t| m.max(t.abs()));
                    assert!(a.residual <= 1e-12 * scale, "KKT residual {}", a.residual);
                    let z = project_by_enumeration(&c, &v);
                    for i in 0..n {
                        assert!((a.x[i] - z[i]).abs() <= 1e-11 * scale, "{:?} vs {z:?}", a.x);
                    }
                    // The variational inequality <v - x, y - x> <= 0 at random points y of C.
                    for _ in 0..20 {
                        let y: Vec<f64> = (0..n).map(|_| rng.range(-3.0, 3.0)).collect();
                        if c.violation(&y, 0.0).is_some() {
                            continue;
                        }
                        let vi: f64 = (0..n).map(|i| (v[i] - a.x[i]) * (y[i] - a.x[i])).sum();
                        assert!(vi <= 1e-11 * scale * scale, "{vi}");
                    }
                    x = a.x;
                    cases += 1;
                }
            }
        }
    }
    assert_eq!(cases, 2 * 6 * 25 * 6);
}

fn one_link(a: f64, b: f64, period: f64, cost: GeneralCost) -> GeneralProblem {
    GeneralProblem::new(GeneralParts {
        normals: vec![vec![1.0], vec![-1.0]],
        offsets: vec![b, -a],
        b: vec![vec![1.0]],
        lower: Some(vec![-1.0]),
        upper: Some(vec![1.0]),
        zero_mean: true,
        face_weights: Some(vec![0.5, 0.5]),
        cost: Some(cost),
        period,
        periodic: true,
        ..Default::default()
    })
    .unwrap()
}

fn bang_bang(p: &GeneralProblem) -> ControlInput {
    ControlInput::new(
        InputKind::PiecewiseConstant,
        p.period,
        vec![0.0, p.period / 2.0],
        vec![vec![1.0], vec![-1.0]],
        &p.control,
        "input",
    )
    .unwrap()
}

#[test]
fn the_one_link_problem_of_section_4_in_general_form() {
    // C = [a, b], g = u, f1 = |eta|/2: the bang-bang gait u = +1 then -1 gives
    // J = (T - 2 (b - a)) / 2 for T > 2 (b - a) (the paper's J*), and 0 below; with
    // f2 = (c/2) u^2 the cost c T / 2 is subtracted (|u| = 1 throughout).
    for (a, b, t) in [(-1.0, 1.0, 10.0), (-0.5, 2.0, 7.0), (0.25, 1.0, 1.0)] {
        let want = f64::max(0.0, (t - 2.0 * (b - a)) / 2.0);
        for c in [0.0, 0.5] {
            let p = one_link(a, b, t, GeneralCost::Quadratic { weight: c });
            let start = [0.5 * (a + b)];
            let sim =
                simulate_general(&p, &bang_bang(&p), &start, &GeneralSimOptions::DEFAULT).unwrap();
            assert!(sim.converged);
            let j = sim.objective.unwrap();
            assert!(
                (j - (want - c * t / 2.0)).abs() < 1e-12,
                "{a} {b} {t} {c}: {j}"
            );
            assert!(sim.max_kkt_residual < 1e-12);
            assert!(sim.mean_control[0].abs() < 1e-15);
        }
    }
}

#[test]
fn a_box_with_linear_drift_converges_at_order_one_to_the_closed_form() {
    // C = [-1, 1]^2, g = -alpha x + u, u = (u1, 0) constant, x(0) = 0, f1 = the reaction on
    // the face x_1 <= 1. x_1 = (u1/alpha)(1 - e^(-alpha t)) reaches 1 at
    // t* = -ln(1 - alpha/u1)/alpha and is then held with reaction u1 - alpha, so
    // J = (T - t*)(u1 - alpha). Catching-up is first order in h (explicit in g).
    let (alpha, u1, t) = (0.5, 1.0, 2.0);
    let p = GeneralProblem::new(GeneralParts {
        normals: vec![
            vec![1.0, 0.0],
            vec![0.0, 1.0],
            vec![-1.0, 0.0],
            vec![0.0, -1.0],
        ],
        offsets: vec![1.0; 4],
        a: Some(vec![vec![-alpha, 0.0], vec![0.0, -alpha]]),
        b: vec![vec![1.0, 0.0], vec![0.0, 1.0]],
        lower: Some(vec![-1.0, -1.0]),
        upper: Some(vec![1.0, 1.0]),
        zero_mean: false,
        face_weights: Some(vec![1.0, 0.0, 0.0, 0.0]),
        period: t,
        periodic: false,
        initial_state: Some(vec![0.0, 0.0]),
        ..Default::default()
    })
    .unwrap();
    let input = ControlInput::new(
        InputKind::PiecewiseConstant,
        t,
        vec![0.0],
        vec![vec![u1, 0.0]],
        &p.control,
        "input",
    )
    .unwrap();
    let t_star = -(1.0 - alpha / u1).ln() / alpha;
    let exact = (t - t_star) * (u1 - alpha);
    let mut errors = vec![];
    for m in [1000, 2000, 4000] {
        let opts = GeneralSimOptions {
            steps_per_period: m,
            ..GeneralSimOptions::DEFAULT
        };
        let sim = simulate_general(&p, &input, &[0.0, 0.0], &opts).unwrap();
        let err = (sim.objective.unwrap() - exact).abs();
        assert!(err <= 2.0 * t / m as f64, "M = {m}: {err}");
        // The state stays in C and x_2 stays 0.
        assert!(sim.x.iter().all(|x| x[0] <= 1.0 + 1e-15 && x[1] == 0.0));
        errors.push(err);
    }
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((order - 1.0).abs() < 0.2, "order {order} from {errors:?}");
    }
}

/// Crawlers with per-link stiffness and per-block friction, N = 2..5.
fn crawlers() -> Vec<Crawler> {
    let k = [1.0, 2.5, 0.7, 1.3];
    let mp = [1.0, 1.2, 0.8, 1.1, 0.9];
    let mm = [2.1, 2.7, 3.1, 2.3, 2.9];
    (2..=5)
        .map(|nb| {
            let c =
                Crawler::new(k[..nb - 1].to_vec(), mp[..nb].to_vec(), mm[..nb].to_vec()).unwrap();
            c.require_unique().unwrap();
            c
        })
        .collect()
}

/// A gait of `crawler` over T = 4 (each link extends then contracts, shifted from link to
/// link): its piecewise-linear actuation, the crawler's general form with rate bounds above its
/// controls, and those controls u = K L' (the last piece back to the first row at T) as the
/// general form's piecewise-constant input.
fn shifted_gait(crawler: &Crawler) -> (f64, Actuation, CrawlerInstance, ControlInput) {
    let n = crawler.links();
    let t = 4.0;
    let times = vec![0.0, 1.0, 2.0, 3.0];
    let lengths: Vec<Vec<f64>> = (0..4)
        .map(|k| {
            (0..n)
                .map(|l| [0.0, 3.0, 1.0, 2.5][(k + l) % 4] * (1.0 + 0.2 * l as f64))
                .collect()
        })
        .collect();
    let act = Actuation::piecewise_linear(t, times.clone(), lengths.clone()).unwrap();
    let ks = crawler.stiffness();
    let u: Vec<Vec<f64>> = (0..4)
        .map(|k| {
            let (t1, next) = if k == 3 {
                (t, &lengths[0])
            } else {
                (times[k + 1], &lengths[k + 1])
            };
            (0..n)
                .map(|l| ks[l] * (next[l] - lengths[k][l]) / (t1 - times[k]))
                .collect()
        })
        .collect();
    let a_max: Vec<f64> = (0..n)
        .map(|l| u.iter().fold(0.0_f64, |m, r| m.max(r[l].abs())) + 1.0)
        .collect();
    let inst = crawler_as_general(crawler, t, &a_max, GeneralCost::None).unwrap();
    let input = ControlInput::new(
        InputKind::PiecewiseConstant,
        t,
        times,
        u,
        &inst.problem.control,
        "input",
    )
    .unwrap();
    (t, act, inst, input)
}

#[test]
fn the_crawler_as_an_instance_gives_the_crawler_path_to_1e_12() {
    for crawler in crawlers() {
        let n = crawler.links();
        let (t, act, inst, input) = shifted_gait(&crawler);
        let p = &inst.problem;
        let m = 400;
        let h = t / m as f64;
        // One period step by step from x = 0: the crawler's projector in the K^-1 metric and the
        // general projector in x~ = K^(-1/2) x.
        let mut cauchy = p.clone();
        cauchy.boundary = crawlopt::model::general::Boundary::Initial(vec![0.0; n]);
        let opts = GeneralSimOptions {
            steps_per_period: m,
            ..GeneralSimOptions::DEFAULT
        };
        let g = simulate_general(&cauchy, &input, &vec![0.0; n], &opts).unwrap();
        let mut proj = Projector::new(&crawler).unwrap();
        let mut x = vec![0.0; n];
        let mut d = vec![0.0; crawler.blocks()];
        let mut disp = 0.0;
        let scale = crawler.force_scale();
        for i in 0..m {
            let mut ui = vec![0.0; n];
            input.mean(i as f64 * h, (i + 1) as f64 * h, &mut ui);
            let delta: Vec<f64> = ui.iter().map(|v| h * v).collect();
            proj.step(&mut x, &delta, &mut d).unwrap();
            disp += d.iter().sum::<f64>() / crawler.blocks() as f64;
            let xg = inst.to_crawler(&g.x[i + 1]);
            for l in 0..n {
                assert!(
                    (xg[l] - x[l]).abs() <= 1e-12 * scale,
                    "N = {}, step {i}: {xg:?} vs {x:?}",
                    crawler.blocks()
                );
            }
        }
        let j = g.objective.unwrap();
        assert!(disp.abs() > 0.1, "the actuation moves the crawler");
        assert!((j - disp).abs() <= 1e-12 * disp.abs(), "{j} vs {disp}");
        // The periodic regime: the crawler's simulator (plain iteration from 0, no
        // acceleration) and the general one agree on the displacement per period.
        let sim = simulate(
            &crawler,
            &act,
            &SimOptions {
                method: Method::CatchingUp,
                steps_per_period: m,
                accelerate_after: None,
                ..SimOptions::default()
            },
        )
        .unwrap();
        let gp = simulate_general(p, &input, &vec![0.0; n], &opts).unwrap();
        let (a, b) = (sim.displacement_per_period.unwrap(), gp.objective.unwrap());
        assert!(
            (a - b).abs() <= 1e-11 * a.abs(),
            "N = {}: {a} vs {b}",
            crawler.blocks()
        );
    }
}

#[test]
fn the_exact_method_where_a_is_zero_matches_the_crawler_exact_method() {
    // The crawler's exact event-driven method (K^-1 metric) and the general exact method on
    // the crawler's general form (Euclidean in x~), on the same piecewise-linear actuation:
    // the same displacement per period (1e-12), and the general catching-up converging to it.
    for crawler in crawlers() {
        let n = crawler.links();
        let (_, act, inst, input) = shifted_gait(&crawler);
        let p = &inst.problem;
        let sim = simulate(
            &crawler,
            &act,
            &SimOptions {
                method: Method::Exact,
                accelerate_after: None,
                ..SimOptions::default()
            },
        )
        .unwrap();
        let want = sim.displacement_per_period.unwrap();
        let ex = simulate_general_exact(p, &input, &vec![0.0; n], 5000, 1e-12).unwrap();
        let got = ex.objective.unwrap();
        assert!(
            (got - want).abs() <= 1e-12 * want.abs().max(1.0),
            "N = {}: {got} vs {want}",
            crawler.blocks()
        );
        assert!(ex.max_kkt_residual <= 1e-12);
        // Catching-up approaches it as the step shrinks.
        let cu = simulate_general(
            p,
            &input,
            &vec![0.0; n],
            &GeneralSimOptions {
                steps_per_period: 4000,
                ..GeneralSimOptions::DEFAULT
            },
        )
        .unwrap();
        assert!(
            (cu.objective.unwrap() - want).abs() < 1e-2 * want.abs().max(1.0),
            "{} vs {want}",
            cu.objective.unwrap()
        );
    }
}
