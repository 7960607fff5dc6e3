//! Long chains (issue 27), benchmark rows: today's default method (the phase MILPs with K grown,
//! `optimize` without options before the structured floor) and the chain method, side by side
//! in one run, on uniform and heterogeneous chains.
//!
//! `cargo run --release --example bench_chains -- [LIMIT] [N,N,...] [chain]` (default 40 s,
//! N = 10, 20, 50, 100; `chain`: the chain method only, for its time targets) prints one Markdown table: per chain and method, the time to the first gait at least
//! as good as the best structured gait, the time to the final gait (the last improvement: the
//! growth's last better K, the chain method's last sweep that raised J), the run's wall time,
//! the final J, the K among which it is certified and the bound of that class (the chain method
//! certifies nothing), and the work bound over all gaits (`certify::bound::work_bound`).
//!
//! Chains: k = a = 1, T = 10, mu+ = 1, mu- = 1.3 (uniform), and per-link
//! `k_l = 1 + 0.5 sin(1.7 l)`, per-block friction pairs cycling over `(1, 1.3)`,
//! `(1 + 0.1 sqrt 2, 1.3 + 0.2 sqrt 2)`, `(1 - 0.1 sqrt 3, 1.3 - 0.05 sqrt 3)` (block `b` takes
//! pair `b mod 3`; heterogeneous; `l`, `b` from 0), a = k, T = 10.

use crawlopt::api::{optimize, Event, GaitMethod, Hooks, OptimizeSettings};
use crawlopt::certify::bound::work_bound;
use crawlopt::optimal::structured::{best_structured, StructuredOptions};
use crawlopt::optimal::{grow_phases, Cost, GaitProblem, GrowOptions, MilpStatus};
use crawlopt::Crawler;
use std::time::Instant;

#[path = "support/cycling_chain.rs"]
mod cycling_chain;

/// The heterogeneous chain of `nb` blocks (module docs): three friction pairs.
fn heterogeneous(nb: usize) -> Crawler {
    cycling_chain::cycling_chain(nb, 3)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let limit: f64 = args.first().map_or(Ok(40.0), |s| s.parse())?;
    let ns: Vec<usize> = match args.get(1) {
        Some(list) => list
            .split(',')
            .map(|s| s.trim().parse())
            .collect::<Result<_, _>>()?,
        None => vec![10, 20, 50, 100],
    };
    let only_chain = args.get(2).is_some_and(|s| s == "chain");
    println!("time limit {limit} s per method and chain\n");
    println!(
        "| chain | N | best structured J (s) | method | time to >= structured (s) | \
         time to final (s) | wall (s) | final J | certified K | bound of that class | work bound |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for kind in ["uniform", "heterogeneous"] {
        for &nb in &ns {
            let c = if kind == "uniform" {
                Crawler::uniform(nb, 1.0, 1.0, 1.3)?
            } else {
                heterogeneous(nb)
            };
            let p = GaitProblem::new(&c, 10.0, &vec![1.0; nb - 1], Cost::None, None)?;
            let s = best_structured(&c, &p, &StructuredOptions::default())?
                .ok_or("no structured gait")?;
            let js = s.objective;
            let head = format!("| {kind} | {nb} | {js:.6} ({:.2})", s.seconds);
            let work = format!("{:.3}", work_bound(&c, &p));

            // Today's default: the phase MILPs with K grown (patience 2) under the limit.
            if !only_chain {
                phase_growth_row(&c, &p, limit, js, &head, &work);
            }

            // The chain method.
            let t0 = Instant::now();
            let mut first: Option<f64> = None;
            let (mut last, mut last_j) = (None::<f64>, f64::NEG_INFINITY);
            let mut on = |e: &Event, t: f64| match e {
                Event::Stage(s) if first.is_none() && s.starts_with("best structured gait") => {
                    (first, last, last_j) = (Some(t), Some(t), js);
                }
                Event::ChainSweep(st) if st.objective > last_j + 1e-12 * last_j.abs().max(1.0) => {
                    (last, last_j) = (Some(t), st.objective);
                }
                _ => {}
            };
            let r = optimize(
                &c,
                &p,
                &OptimizeSettings {
                    method: GaitMethod::Chain,
                    time_limit: Some(limit),
                    ..Default::default()
                },
                Hooks {
                    events: Some(&mut on),
                    cancel: None,
                },
            );
            let wall = t0.elapsed().as_secs_f64();
            match r {
                Ok(r) => println!(
                    "{head} | chain | {} | {} | {wall:.1} | {:.6} ({}) | - | - | {work} |",
                    first.map_or("never".into(), |t| format!("{t:.2}")),
                    last.map_or("-".into(), |t| format!("{t:.2}")),
                    r.result.head.objective,
                    r.result.head.status.as_str()
                ),
                Err(e) => {
                    println!("{head} | chain | - | - | {wall:.1} | error: {e} | - | - | {work} |")
                }
            }
        }
    }
    Ok(())
}

/// The row of today's default method: the phase MILPs with K grown (patience 2) under `limit`
/// seconds, `js` the best structured gait's J, `head` and `work` the row's first and last cells.
fn phase_growth_row(c: &Crawler, p: &GaitProblem, limit: f64, js: f64, head: &str, work: &str) {
    let t0 = Instant::now();
    let mut first: Option<f64> = None;
    let (mut last, mut last_j) = (None::<f64>, f64::NEG_INFINITY);
    let g = grow_phases(
        c,
        p,
        &GrowOptions {
            time_limit: Some(limit),
            ..GrowOptions::default()
        },
        &mut |st| {
            let t = t0.elapsed().as_secs_f64();
            if first.is_none() && st.objective >= js - 1e-9 {
                first = Some(t);
            }
            if st.objective > last_j + 1e-9 {
                (last, last_j) = (Some(t), st.objective);
            }
        },
    );
    let wall = t0.elapsed().as_secs_f64();
    match g {
        Ok(g) => {
            let certified = g
                .table
                .iter()
                .filter(|r| r.status == MilpStatus::OptimalAmongKPhases)
                .map(|r| r.phases)
                .max();
            let bound = g.table.last().map(|r| (r.phases, r.bound));
            println!(
                "{head} | phase growth (today's default) | {} | {} | {wall:.1} | {:.6} | {} | {} | {work} |",
                first.map_or("never".into(), |t| format!("{t:.1}")),
                last.map_or("-".into(), |t| format!("{t:.1}")),
                g.best.objective(),
                certified.map_or("-".into(), |k| k.to_string()),
                bound.map_or("-".into(), |(k, b)| format!("{b:.3} (K <= {k})")),
            );
        }
        Err(e) => println!(
            "{head} | phase growth (today's default) | never | - | {wall:.1} | error: {e} | - | - | {work} |"
        ),
    }
}
