//! `crawlopt fit`: simulate-then-fit round trips (exact data recover every identifiable
//! parameter; noisy data lie inside the stated intervals), the prediction error of the fitted
//! model, bad inputs and contradictions.

use crawlopt::fit::{fit, record, FitData, FitResult, FitSettings, Param, PerParam, Recording};
use crawlopt::integrate::replay;
use crawlopt::integrate::Actuation;
use crawlopt::Crawler;
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// A two-phase travelling-wave gait of `n` links: each link stretches then contracts, link l
/// lagging by l/(n+1) of the period.
fn wave_gait(n: usize, amp: f64) -> Actuation {
    gait(n, amp, 1.0 / (n + 1) as f64)
}

/// A triangle wave on every link with the knots at eighths of the period, link l lagging by
/// `lag * l` periods (negative: a wave running backward; 0: every link together).
fn gait(n: usize, amp: f64, lag: f64) -> Actuation {
    let k = 8;
    let times: Vec<f64> = (0..k).map(|j| j as f64 / k as f64).collect();
    let lengths = times
        .iter()
        .map(|&t| {
            (0..n)
                .map(|l| {
                    let ph = (t - lag * l as f64).rem_euclid(1.0);
                    amp * (1.0 - (2.0 * ph - 1.0).abs())
                })
                .collect()
        })
        .collect();
    Actuation::piecewise_linear(1.0, times, lengths).unwrap()
}

fn film(c: &Crawler, act: &Actuation, frames: usize, periods: usize, noise: f64) -> FitData {
    let rec = Recording {
        frames_per_period: frames,
        periods,
        noise,
        seed: 7,
    };
    record(c, act, &rec).unwrap()
}

/// Whether `v` lies in `[lo, hi]` up to the LP tolerances (1e-9 relative).
fn inside(v: f64, iv: [Option<f64>; 2]) -> bool {
    let tol = 1e-9 * v.abs().max(1.0);
    iv[0].is_some_and(|lo| lo <= v + tol) && iv[1].is_none_or(|hi| v <= hi + tol)
}

fn assert_truth_inside(r: &FitResult, t: &PerParam<f64>) {
    let iv = flat(r.intervals.as_ref().expect("intervals"));
    for (j, (v, i)) in flat(t).iter().zip(&iv).enumerate() {
        assert!(
            inside(*v, *i),
            "parameter {j}: {v} outside {i:?}; {:?}",
            r.warnings
        );
    }
}

fn truth(c: &Crawler) -> PerParam<f64> {
    PerParam {
        stiffness: c.stiffness().to_vec(),
        mu_forward: c.mu_forward().to_vec(),
        mu_backward: c.mu_backward().to_vec(),
    }
}

fn fixed_k1(c: &Crawler) -> FitSettings {
    FitSettings {
        fixes: vec![("stiffness[1]".parse::<Param>().unwrap(), c.stiffness()[0])],
        ..FitSettings::default()
    }
}

fn flat<T: Clone>(p: &PerParam<T>) -> Vec<T> {
    p.stiffness
        .iter()
        .chain(&p.mu_forward)
        .chain(&p.mu_backward)
        .cloned()
        .collect()
}

#[test]
fn exact_data_recover_every_identifiable_parameter() {
    let c = Crawler::new(vec![2.0, 0.5], vec![1.0, 1.5, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let data = record(
        &c,
        &wave_gait(2, 3.0),
        &Recording {
            frames_per_period: 60,
            periods: 2,
            noise: 0.0,
            seed: 1,
        },
    )
    .unwrap();
    let r = fit(&data, &fixed_k1(&c)).unwrap();
    let t = flat(&truth(&c));
    let est = flat(&r.crawler);
    let mut identified = 0;
    for (j, (e, v)) in est.iter().zip(&t).enumerate() {
        if let Some(e) = e {
            assert!((e - v).abs() <= 1e-9 * v, "parameter {j}: {e} against {v}");
            identified += 1;
        }
    }
    assert!(identified >= 4, "{identified}");
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 12,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(29),
        ..ProptestConfig::default()
    })]

    /// Noisy camera data of random crawlers (N = 2..10, per-link k, per-block mu, three
    /// gaits, 30 to 100 frames per period): the truth lies in every interval.
    #[test]
    fn noisy_data_lie_inside_the_intervals(
        nb in 2usize..=10,
        seed in 0u64..1000,
        which in 0usize..3,
        frames in 30usize..=100,
        noise in prop_oneof![Just(0.0), Just(1e-4), Just(1e-3)],
        given in any::<bool>(),
    ) {
        let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        let mut u = || { s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407); 0.5 + 1.5 * ((s >> 11) as f64 / (1u64 << 53) as f64) };
        let k: Vec<f64> = (1..nb).map(|_| u()).collect();
        let mf: Vec<f64> = (0..nb).map(|_| u()).collect();
        let mb: Vec<f64> = (0..nb).map(|_| u()).collect();
        let c = Crawler::new(k, mf, mb).unwrap();
        prop_assume!(c.require_unique().is_ok());
        let n = nb - 1;
        let lag = [1.0 / nb as f64, -1.0 / nb as f64, 0.0][which];
        // A stroke that makes blocks slide: beyond the sum of thresholds over the stiffness.
        let amp = 2.0 * (c.force_scale() * nb as f64) / c.stiffness().iter().fold(f64::INFINITY, |a, &b| a.min(b));
        let data = film(&c, &gait(n, amp, lag), frames, 2, noise * amp);
        let mut settings = fixed_k1(&c);
        if given {
            settings.noise = Some(noise * amp);
        }
        let r = fit(&data, &settings).unwrap();
        assert_truth_inside(&r, &truth(&c));
    }
}

#[test]
fn without_a_fix_the_fit_reports_ratios_to_stiffness_1() {
    let c = Crawler::new(vec![2.0, 0.5], vec![1.0, 1.5, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let r = fit(
        &film(&c, &wave_gait(2, 3.0), 50, 2, 0.0),
        &FitSettings::default(),
    )
    .unwrap();
    assert_eq!(r.scale.ratios_to.as_deref(), Some("stiffness[1]"));
    assert!(r.scale.fixed.is_empty());
    let k1 = c.stiffness()[0];
    for (e, v) in flat(&r.crawler).iter().zip(flat(&truth(&c))) {
        if let Some(e) = e {
            assert!(
                (e - v / k1).abs() <= 1e-9 * v / k1,
                "{e} against {}",
                v / k1
            );
        }
    }
}

/// A gait of period 2 that runs a wave forward, then backward: every block slides both ways.
fn there_and_back(n: usize, amp: f64) -> Actuation {
    let (f, b) = (
        gait(n, amp, 1.0 / (n + 1) as f64),
        gait(n, amp, -1.0 / (n + 1) as f64),
    );
    let (tf, lf) = f.knots(0);
    let (tb, lb) = b.knots(0);
    let times = tf
        .iter()
        .copied()
        .chain(tb.iter().map(|t| t + 1.0))
        .collect();
    let lengths = lf.into_iter().chain(lb).collect();
    Actuation::piecewise_linear(2.0, times, lengths).unwrap()
}

#[test]
fn the_fitted_model_predicts_the_data() {
    let c = Crawler::new(vec![1.5, 0.7], vec![1.0, 1.2, 0.9], vec![1.4, 1.1, 1.6]).unwrap();
    let data = film(&c, &there_and_back(2, 4.0), 64, 2, 0.0);
    let r = fit(&data, &fixed_k1(&c)).unwrap();
    // The front block never slides backward: its mu- is bounded only below (the model file
    // takes twice that bound); every other parameter is identified.
    let known = flat(&r.crawler).iter().filter(|e| e.is_some()).count();
    assert_eq!(known, 7, "{:?}", r.crawler);
    // The true crawler replayed from the first frame reproduces the frames (knots at frames).
    let k = c.stiffness();
    let x0: Vec<f64> = (0..2).map(|l| k[l] * data.compression(0, l)).collect();
    let truth_replay = replay(&c, &data.t, &data.lengths, &x0, &data.positions[0]).unwrap();
    let err = truth_replay
        .iter()
        .zip(&data.positions)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(u, v)| (u - v).abs()))
        .fold(0.0_f64, f64::max);
    assert!(err < 1e-9, "{err}");
    let p = r.prediction.expect("prediction");
    assert!(p.max < 1e-7 && p.rms <= p.max, "{p:?}");
    // A wrong model predicts worse: the fitted stiffness of link 2 doubled.
    let wrong = Crawler::new(vec![1.5, 1.4], vec![1.0, 1.2, 0.9], vec![1.4, 1.1, 1.6]).unwrap();
    let x0: Vec<f64> = (0..2)
        .map(|l| wrong.stiffness()[l] * data.compression(0, l))
        .collect();
    let w = replay(&wrong, &data.t, &data.lengths, &x0, &data.positions[0]).unwrap();
    let werr = w
        .iter()
        .zip(&data.positions)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(u, v)| (u - v).abs()))
        .fold(0.0_f64, f64::max);
    assert!(werr > 1e-3, "{werr}");
}

#[test]
fn an_outlier_is_left_out_and_named() {
    let c = Crawler::new(vec![2.0, 0.5], vec![1.0, 1.5, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let mut data = film(&c, &wave_gait(2, 3.0), 60, 3, 1e-4);
    data.positions[40][1] += 0.5;
    let r = fit(
        &data,
        &FitSettings {
            noise: Some(1e-4),
            ..fixed_k1(&c)
        },
    )
    .unwrap();
    assert_eq!(r.outlier_rows, vec![41], "{:?}", r.warnings);
    assert!(
        r.warnings.iter().any(|w| w.contains("rows 41")),
        "{:?}",
        r.warnings
    );
    assert_truth_inside(&r, &truth(&c));
}

#[test]
fn a_block_sliding_forward_at_two_forces_is_a_contradiction() {
    // Two recordings of one gait, the second with block 2's mu+ raised by half: together they
    // show block 2 sliding forward at two forces.
    let a = Crawler::new(vec![2.0, 0.5], vec![1.0, 1.5, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let b = Crawler::new(vec![2.0, 0.5], vec![1.0, 2.25, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let (da, db) = (
        film(&a, &wave_gait(2, 3.0), 60, 2, 0.0),
        film(&b, &wave_gait(2, 3.0), 60, 2, 0.0),
    );
    let shift = da.t[da.t.len() - 1] + 1.0 / 60.0;
    let data = FitData::new(
        3,
        da.t.iter()
            .copied()
            .chain(db.t.iter().map(|t| t + shift))
            .collect(),
        da.lengths.iter().chain(&db.lengths).cloned().collect(),
        da.positions.iter().chain(&db.positions).cloned().collect(),
    )
    .unwrap();
    let r = fit(&data, &fixed_k1(&a)).unwrap();
    assert!(r.intervals.is_none());
    let w = r.warnings.join("\n");
    assert!(w.contains("contradict the model"), "{w}");
    assert!(w.contains("block 2 slides forward at forces from"), "{w}");
    // Each recording alone is consistent.
    assert!(fit(&da, &fixed_k1(&a)).unwrap().intervals.is_some());
}

fn csv_of(data: &FitData) -> String {
    let nb = data.blocks();
    let mut s = crawlopt::fit::column_names(nb).join(",") + "\n";
    for i in 0..data.samples() {
        let row: Vec<String> = std::iter::once(data.t[i])
            .chain(data.lengths[i].iter().copied())
            .chain(data.positions[i].iter().copied())
            .map(|v| v.to_string())
            .collect();
        s += &(row.join(",") + "\n");
    }
    s
}

fn csv_error(text: &str) -> String {
    FitData::from_csv(text, "data.csv", 3)
        .unwrap_err()
        .to_string()
}

#[test]
fn bad_inputs_are_refused_naming_the_column_or_row() {
    let c = Crawler::new(vec![2.0, 0.5], vec![1.0, 1.5, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let good = csv_of(&film(&c, &wave_gait(2, 3.0), 30, 1, 0.0));
    let back = FitData::from_csv(&good, "data.csv", 3).unwrap();
    assert_eq!(back.samples(), 31);
    let lines: Vec<&str> = good.lines().collect();
    // Unsorted times: rows 3 and 4 swapped.
    let mut swapped = lines.clone();
    swapped.swap(3, 4);
    let e = csv_error(&(swapped.join("\n")));
    assert!(
        e.contains("row 4, column t") && e.contains("strictly increase"),
        "{e}"
    );
    // A missing column.
    let e = csv_error(&good.replacen("X_2", "X_9", 1));
    assert!(e.contains("column 5") && e.contains("X_9"), "{e}");
    let dropped: Vec<String> = lines
        .iter()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string())
        .collect();
    let e = csv_error(&dropped.join("\n"));
    assert!(e.contains("column X_3") && e.contains("missing"), "{e}");
    // Too few samples.
    let e = csv_error(&lines[..4].join("\n"));
    assert!(e.contains("samples") && e.contains("at least 5"), "{e}");
    // NaN and text.
    let mut nan = lines.clone();
    let l7 = nan[7].replacen(',', ",NaN,", 1);
    let l7: Vec<&str> = l7.split(',').collect();
    let l7 = [l7[0], l7[1]]
        .iter()
        .chain(&l7[3..])
        .copied()
        .collect::<Vec<_>>()
        .join(",");
    nan[7] = &l7;
    let e = csv_error(&nan.join("\n"));
    assert!(
        e.contains("row 7, column L_1") && e.contains("finite"),
        "{e}"
    );
    let mut text = lines.clone();
    let bad = text[2].replacen(',', ",abc,", 1);
    let bad: Vec<&str> = bad.split(',').collect();
    let bad = [bad[0], bad[1]]
        .iter()
        .chain(&bad[3..])
        .copied()
        .collect::<Vec<_>>()
        .join(",");
    text[2] = &bad;
    let e = csv_error(&text.join("\n"));
    assert!(
        e.contains("row 2, column L_1") && e.contains("not a number"),
        "{e}"
    );
    // A header of numbers, and a file with nothing.
    let e = csv_error(&lines[1..].join("\n"));
    assert!(e.contains("header"), "{e}");
    assert!(csv_error("").contains("empty"));
    // Arrays of the wrong shape, and settings no fit runs with.
    let e = FitData::new(
        3,
        vec![0.0; 6],
        vec![vec![0.0; 2]; 6],
        vec![vec![0.0; 2]; 6],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("X, row 1") && e.contains("needs 3 values"),
        "{e}"
    );
    let e = fit(
        &back,
        &FitSettings {
            noise: Some(-1.0),
            ..FitSettings::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("noise:"), "{e}");
    let e = fit(
        &back,
        &FitSettings {
            fixes: vec![("mu_forward[4]".parse().unwrap(), 1.0)],
            ..FitSettings::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("fix mu_forward[4]"), "{e}");
    assert!("stiffness[0]".parse::<Param>().is_err());
    assert!("k[1]".parse::<Param>().is_err());
    assert_eq!(
        "mu_backward[3]".parse::<Param>().unwrap().to_string(),
        "mu_backward[3]"
    );
}

#[test]
fn the_command_writes_a_model_file_and_the_json_of_the_issue() {
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("fitted.toml");
    let figs = dir.path().join("figs");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_crawlopt"))
        .args([
            "fit",
            "examples/fit_recorded.csv",
            "--blocks",
            "3",
            "--fix",
            "stiffness[1]=1",
            "--json",
            "-o",
        ])
        .arg(&model)
        .arg("--plot")
        .arg(&figs)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for f in ["stiffness", "mu_forward", "mu_backward"] {
        assert!(v["crawler"][f].is_array(), "{v}");
        assert!(v["intervals"][f][0].is_array(), "{v}");
    }
    assert_eq!(v["crawler"]["stiffness"][0], 1.0);
    // The model file is one that simulate and optimize read.
    let c = crawlopt::io::ModelFile::load(&model)
        .unwrap()
        .crawler()
        .unwrap();
    assert_eq!(
        c.stiffness()[1],
        v["crawler"]["stiffness"][1].as_f64().unwrap()
    );
    assert!(figs.join("fit_trajectories.svg").is_file());
    assert!(figs.join("fit_force_block_3.png").is_file());
    // Bad input: exit 2 and a message naming the column.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_crawlopt"))
        .args(["fit", "examples/fit_recorded.csv", "--blocks", "4"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("column L_3"));
}

#[test]
fn a_cancelled_fit_stops_with_cancelled() {
    use crawlopt::api::{self, Event, Hooks};
    let c = Crawler::new(vec![2.0, 0.5], vec![1.0, 1.5, 0.8], vec![2.0, 2.5, 1.7]).unwrap();
    let data = film(&c, &wave_gait(2, 3.0), 40, 1, 0.0);
    let cancel = crawlopt::progress::Cancel::new();
    cancel.cancel();
    let r = api::fit(
        &data,
        &fixed_k1(&c),
        Hooks {
            events: None,
            cancel: Some(&cancel),
        },
    );
    assert_eq!(r.unwrap_err(), crawlopt::Error::Cancelled);
    // Not cancelled: the stage and the warnings arrive as events.
    let mut seen = Vec::new();
    let mut obs = |e: &Event, _: f64| seen.push(e.clone());
    let r = api::fit(
        &data,
        &fixed_k1(&c),
        Hooks {
            events: Some(&mut obs),
            cancel: None,
        },
    )
    .unwrap();
    assert!(matches!(&seen[0], Event::Stage(s) if s.contains("fitting 3 blocks")));
    assert_eq!(seen.len(), 1 + r.warnings.len());
}

/// The estimate's error and the cost on a 10-block chain (docs/guide/fit.md, "Limits"):
/// `cargo test --release --test fit -- --ignored --nocapture estimate_error_and_cost`.
#[test]
#[ignore = "a measurement for the documentation (about 15 s)"]
fn estimate_error_and_cost() {
    let nb = 10;
    let c = Crawler::new(
        (1..nb).map(|i| 0.5 + 0.1 * i as f64).collect(),
        (0..nb).map(|i| 0.6 + 0.07 * i as f64).collect(),
        (0..nb).map(|i| 1.3 - 0.05 * i as f64).collect(),
    )
    .unwrap();
    let amp = 2.0 * c.force_scale() * nb as f64 / 0.5;
    for (periods, noise) in [(4, 1e-4), (4, 1e-3), (10, 1e-3)] {
        let data = film(&c, &gait(nb - 1, amp, 0.1), 100, periods, noise * amp);
        let began = std::time::Instant::now();
        let r = fit(&data, &fixed_k1(&c)).unwrap();
        let seconds = began.elapsed().as_secs_f64();
        assert_truth_inside(&r, &truth(&c));
        let err = flat(&r.crawler)
            .iter()
            .zip(flat(&truth(&c)))
            .filter_map(|(e, v)| e.map(|e| (e - v).abs() / v))
            .fold(0.0_f64, f64::max);
        println!(
            "{} samples, noise {noise} of the stroke: largest relative error {err:.4}, {seconds:.1} s",
            data.samples()
        );
    }
}

#[test]
fn still_data_give_no_crawler_and_say_why() {
    let data = FitData::new(
        2,
        (0..6).map(f64::from).collect(),
        vec![vec![1.0]; 6],
        vec![vec![0.0, 1.0]; 6],
    )
    .unwrap();
    let r = fit(&data, &FitSettings::default()).unwrap();
    assert!(r.fitted.is_none() && r.model.is_none() && r.prediction.is_none());
    assert!(r.crawler.mu_forward.iter().all(Option::is_none));
    assert!(
        r.warnings
            .iter()
            .any(|w| w.contains("mu_forward[1]: the data do not bound it")),
        "{:?}",
        r.warnings
    );
    assert!(
        r.warnings.iter().any(|w| w.contains("no fitted crawler")),
        "{:?}",
        r.warnings
    );
}
