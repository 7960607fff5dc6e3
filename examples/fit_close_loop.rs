//! Close the loop of `crawlopt fit` (docs/guide/fit.md): fit a crawler to the recorded
//! trajectory `examples/fit_recorded.csv`, optimise a gait on the fitted model, and re-simulate
//! that gait at every corner of the box of fitted intervals.
//!
//! `cargo run --release --example fit_close_loop` prints the fitted parameters, the optimal
//! displacement on the fitted model, and its smallest and largest value over the corners.
//! `cargo run --release --example fit_close_loop -- --record` first writes the recording
//! again: the crawler below, filmed at 100 frames per period for 2 periods (of 2 time units: a
//! travelling wave run forward then backward), with Gaussian noise of standard deviation 1e-3
//! on every position (seed 29).

use crawlopt::api::{optimize, GaitMethod, Hooks, OptimizeSettings};
use crawlopt::fit::{column_names, fit, record, FitData, FitSettings, Param, Recording};
use crawlopt::integrate::{simulate, Actuation, SimOptions};
use crawlopt::optimal::{Cost, GaitProblem};
use crawlopt::Crawler;

const CSV: &str = "examples/fit_recorded.csv";

/// The crawler that was "filmed" (unknown to the fit but for stiffness[1]).
fn truth() -> Crawler {
    Crawler::new(vec![1.0, 1.6], vec![0.9, 1.2, 0.8], vec![1.1, 1.0, 0.7]).expect("crawler")
}

/// A triangle wave on both links, link 2 lagging by `lag` periods, knots at eighths.
fn wave(amp: f64, lag: f64, t0: f64) -> (Vec<f64>, Vec<Vec<f64>>) {
    let times: Vec<f64> = (0..8).map(|j| j as f64 / 8.0).collect();
    let lengths = times
        .iter()
        .map(|&t| {
            (0..2)
                .map(|l| amp * (1.0 - (2.0 * (t - lag * l as f64).rem_euclid(1.0) - 1.0).abs()))
                .collect()
        })
        .collect();
    (times.iter().map(|t| t + t0).collect(), lengths)
}

fn recorded_gait() -> Actuation {
    let (mut t, mut l) = wave(4.0, 1.0 / 3.0, 0.0);
    let (t2, l2) = wave(4.0, -1.0 / 3.0, 1.0);
    t.extend(t2);
    l.extend(l2);
    Actuation::piecewise_linear(2.0, t, l).expect("gait")
}

fn write_csv(data: &FitData) {
    let mut s = format!(
        "# A 3-block crawler filmed at 100 frames per period (2 periods of period 2), noise 1e-3:\n\
         # written by `cargo run --release --example fit_close_loop -- --record`.\n{}\n",
        column_names(3).join(",")
    );
    for i in 0..data.samples() {
        let row: Vec<String> = std::iter::once(data.t[i])
            .chain(data.lengths[i].iter().copied())
            .chain(data.positions[i].iter().copied())
            .map(|v| format!("{v:.6}"))
            .collect();
        s += &(row.join(",") + "\n");
    }
    std::fs::write(CSV, s).expect("write the recording");
}

fn main() -> Result<(), crawlopt::Error> {
    if std::env::args().any(|a| a == "--record") {
        let rec = Recording {
            frames_per_period: 100,
            periods: 2,
            noise: 1e-3,
            seed: 29,
        };
        write_csv(&record(&truth(), &recorded_gait(), &rec)?);
        println!("wrote {CSV}");
    }
    let text = std::fs::read_to_string(CSV).map_err(|e| crawlopt::Error::Io {
        path: CSV.into(),
        reason: e.to_string(),
    })?;
    let data = FitData::from_csv(&text, CSV, 3)?;
    let settings = FitSettings {
        fixes: vec![("stiffness[1]".parse::<Param>()?, 1.0)],
        ..FitSettings::default()
    };
    let r = fit(&data, &settings)?;
    let iv = r.intervals.clone().expect("intervals");
    println!(
        "noise: sigma = {:.3e} (estimated: {})",
        r.noise.sigma, r.noise.estimated
    );
    for w in &r.warnings {
        println!("warning: {w}");
    }
    let names = ["stiffness", "mu_forward", "mu_backward"];
    let est = [
        &r.crawler.stiffness,
        &r.crawler.mu_forward,
        &r.crawler.mu_backward,
    ];
    let ivs = [&iv.stiffness, &iv.mu_forward, &iv.mu_backward];
    let t = truth();
    let tv = [t.stiffness(), t.mu_forward(), t.mu_backward()];
    for f in 0..3 {
        for j in 0..est[f].len() {
            println!(
                "{}[{}]: estimate {:?}, interval [{:.4}, {}], truth {}",
                names[f],
                j + 1,
                est[f][j].map(|v| (v * 1e4).round() / 1e4),
                ivs[f][j][0].unwrap_or(f64::NAN),
                ivs[f][j][1].map_or("unbounded".into(), |v| format!("{v:.4}")),
                tv[f][j]
            );
        }
    }
    let fitted = r.fitted.clone().expect("fitted crawler");
    // The gait problem of docs/guide/fit.md: T = 10, |L'| <= 1.
    let problem = GaitProblem::new(&fitted, 10.0, &[1.0, 1.0], Cost::None, None)?;
    let settings = OptimizeSettings {
        method: GaitMethod::Phase,
        phases: Some(4),
        ..OptimizeSettings::default()
    };
    let best = optimize(&fitted, &problem, &settings, Hooks::default())?;
    let act = crawlopt::present::gait_actuation(&best.result)?;
    println!(
        "optimal displacement on the fitted model: {:.6}",
        best.result.displacement_per_period
    );
    // Corners of the interval box (the fixed stiffness[1] stays 1; an unbounded parameter
    // takes its lower end and the model value).
    let flat: Vec<[f64; 2]> = ivs
        .iter()
        .enumerate()
        .flat_map(|(f, v)| {
            let model = r.model.clone().expect("model");
            let mv = [model.stiffness, model.mu_forward, model.mu_backward];
            v.iter()
                .enumerate()
                .map(move |(j, i)| [i[0].unwrap_or(0.0), i[1].unwrap_or(mv[f][j])])
                .collect::<Vec<_>>()
        })
        .collect();
    let free: Vec<usize> = (0..flat.len())
        .filter(|&j| flat[j][1] > flat[j][0])
        .collect();
    let (mut lo, mut hi, mut skipped) = (f64::INFINITY, f64::NEG_INFINITY, 0);
    for mask in 0u32..(1 << free.len()) {
        let mut p: Vec<f64> = flat.iter().map(|v| v[0]).collect();
        for (bit, &j) in free.iter().enumerate() {
            p[j] = flat[j][((mask >> bit) & 1) as usize];
        }
        let c = Crawler::new(p[..2].to_vec(), p[2..5].to_vec(), p[5..].to_vec())?;
        if c.require_unique().is_err() {
            skipped += 1;
            continue;
        }
        let sim = simulate(&c, &act, &SimOptions::default())?;
        let d = sim.displacement_per_period.expect("periodic regime");
        lo = lo.min(d);
        hi = hi.max(d);
    }
    println!(
        "over the {} corners of the interval box: displacement from {lo:.6} to {hi:.6} \
         ({skipped} corners skipped: uniqueness fails there)",
        1u32 << free.len()
    );
    let sim = simulate(&t, &act, &SimOptions::default())?;
    println!(
        "on the true crawler: {:.6}",
        sim.displacement_per_period.expect("periodic regime")
    );
    Ok(())
}
