//! The orbit search on heterogeneous chains: the default search (a Newton-Krylov step, then
//! Anderson mixing the preconditioned residual) against Anderson alone, side by side.
//!
//! `cargo run --release --example heterogeneous_chains -- [N:SEED,N:SEED,...]` (default the
//! chains of `tests/orbit.rs` and two longer ones: 120:11, 100:100, 200:101, 300:102, 500:103,
//! 1000:104) prints a CSV table: N, seed, method, periods and Jacobian-vector products of the
//! default search, periods of Anderson alone, both times in seconds and the difference of the
//! displacements per period. The chain (the generator of `tests/orbit.rs`): per-link stiffness
//! in [0.5, 2], mu+ in {0.75, 1} and mu- in {2.5, 3.5} + 1/(8 N) per block, a sine wave of
//! amplitude 1.5 and 60 degrees per link, catching-up on 1000 steps per period.

#[path = "support/heterogeneous.rs"]
mod heterogeneous;

use crawlopt::integrate::{simulate, Actuation, Method, SimOptions, Simulation};
use crawlopt::Crawler;
use std::time::Instant;

fn timed(c: &Crawler, a: &Actuation, newton: bool) -> Result<(Simulation, f64), crawlopt::Error> {
    let opts = SimOptions {
        method: Method::CatchingUp,
        record_periods: 0,
        newton: SimOptions::DEFAULT.newton.filter(|_| newton),
        ..SimOptions::default()
    };
    let t0 = Instant::now();
    let sim = simulate(c, a, &opts)?;
    Ok((sim, t0.elapsed().as_secs_f64()))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let cases: Vec<(usize, u64)> = match std::env::args().nth(1) {
        Some(list) => list
            .split(',')
            .map(|p| {
                let (n, s) = p.split_once(':').ok_or("expected N:SEED")?;
                Ok::<_, Box<dyn std::error::Error>>((n.trim().parse()?, s.trim().parse()?))
            })
            .collect::<Result<_, _>>()?,
        None => vec![
            (120, 11),
            (100, 100),
            (200, 101),
            (300, 102),
            (500, 103),
            (1000, 104),
        ],
    };
    println!(
        "N,seed,periods,products,seconds,anderson_periods,anderson_seconds,displacement_difference"
    );
    for (nb, seed) in cases {
        let (c, a) = heterogeneous::heterogeneous_chain(nb, seed)?;
        let (s, t) = timed(&c, &a, true)?;
        let (sa, ta) = timed(&c, &a, false)?;
        let diff = match (s.displacement_per_period, sa.displacement_per_period) {
            (Some(d), Some(da)) => format!("{:.2e}", (d - da).abs()),
            _ => "not converged".into(),
        };
        println!(
            "{nb},{seed},{},{},{t:.3},{},{ta:.3},{diff}",
            s.periods_simulated, s.tangent_products, sa.periods_simulated
        );
    }
    Ok(())
}
