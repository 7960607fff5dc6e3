//! The phase MILP on long uniform chains, its formulations side by side (issue: optimal gaits
//! for chains of 10 to 100 blocks).
//!
//! `cargo run --release --example phase_long_chain -- N K SECONDS [VARIANT,...] [MU_MINUS]`
//! solves the phase MILP of `K` slip phases on the uniform chain of `N` blocks (k = a = 1,
//! T = 10, mu+ = 1, mu- = MU_MINUS, default 1.3, no cost) under a time limit, once per variant,
//! in one run of one binary:
//! `plain` (the default formulation, no start), `dissipation` (the dissipation row),
//! `wave` (the alternating triangle wave as the start: the MILP's incumbent when it fits `K`,
//! else a cutoff), `wave+dissipation`; `grow` and `grow+wave` raise `K` from 1 to `K` within
//! the time limit instead (`grow_phases`, without and with the wave as `GrowOptions::start`;
//! `+dissipation` adds the row there too),
//! printing the largest `K` solved. It prints one CSV row per variant: the variant, N, K,
//! status, J of the answer, the MILP's bound, the gap and the seconds.

use crawlopt::optimal::{
    grow_phases, phase_gait_of, solve_phase_with, Cost, Formulation, GaitProblem, GrowOptions,
    PhaseOptions,
};
use crawlopt::Crawler;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let nb: usize = args.first().map_or(Ok(10), |s| s.parse())?;
    let k: usize = args.get(1).map_or(Ok(2), |s| s.parse())?;
    let limit: f64 = args.get(2).map_or(Ok(60.0), |s| s.parse())?;
    let variants: Vec<String> = args
        .get(3)
        .map_or("plain,dissipation,wave,wave+dissipation", |s| s.as_str())
        .split(',')
        .map(str::to_owned)
        .collect();
    let mm: f64 = args.get(4).map_or(Ok(1.3), |s| s.parse())?;
    let crawler = Crawler::uniform(nb, 1.0, 1.0, mm)?;
    let n = nb - 1;
    let problem = GaitProblem::new(&crawler, 10.0, &vec![1.0; n], Cost::None, None)?;
    // The alternating triangle wave: odd links against even links at the full rate a = 1,
    // amplitude aT/4 (four pieces of T/4 so that every knot is a turning point or a midpoint).
    let q = 2.5;
    let durations = vec![q; 4];
    let sign = |l: usize| if l % 2 == 0 { 1.0 } else { -1.0 };
    let increments: Vec<Vec<f64>> = [1.0, -1.0, -1.0, 1.0]
        .iter()
        .map(|s| (0..n).map(|l| s * sign(l) * q).collect())
        .collect();
    let wave = phase_gait_of(&crawler, &problem, &durations, &increments)?;
    eprintln!(
        "triangle wave: J = {:.6}, {} slip phases",
        wave.objective(),
        wave.phases
    );
    println!("variant,N,K,status,J,bound,gap,seconds");
    for v in &variants {
        let opts = PhaseOptions {
            start: v.contains("wave").then(|| wave.clone()),
            cutoff: None,
            formulation: Formulation {
                dissipation_row: Some(v.contains("dissipation")),
            },
        };
        let t0 = Instant::now();
        if v.starts_with("grow") {
            let opts = GrowOptions {
                max_phases: k,
                time_limit: Some(limit),
                start: opts.start,
                formulation: opts.formulation,
                ..GrowOptions::default()
            };
            match grow_phases(&crawler, &problem, &opts, &mut |st| {
                eprintln!(
                    "{v}: K = {} {:?} J = {:.6} bound {:.6} ({:.1} s)",
                    st.phases, st.status, st.objective, st.bound, st.seconds
                )
            }) {
                Ok(g) => println!(
                    "{v},{nb},{},{},{:.6},{:.6},{:.4},{:.1}",
                    g.best.phases,
                    g.best.certificate.status.as_str(),
                    g.best.objective(),
                    g.best.certificate.bound,
                    g.best.certificate.gap,
                    t0.elapsed().as_secs_f64()
                ),
                Err(e) => println!(
                    "{v},{nb},{k},error: {e},,,,{:.1}",
                    t0.elapsed().as_secs_f64()
                ),
            }
            continue;
        }
        match crawlopt::progress::within(Some(limit), || {
            solve_phase_with(&crawler, &problem, k, &opts)
        }) {
            Ok(s) => println!(
                "{v},{nb},{k},{},{:.6},{:.6},{:.4},{:.1}",
                s.certificate.status.as_str(),
                s.objective(),
                s.certificate.bound,
                s.certificate.gap,
                t0.elapsed().as_secs_f64()
            ),
            Err(e) => println!(
                "{v},{nb},{k},error: {e},,,,{:.1}",
                t0.elapsed().as_secs_f64()
            ),
        }
    }
    Ok(())
}
