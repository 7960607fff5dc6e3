//! The displacement per period of a long chain against N, approaching its continuum value.
//!
//! `cargo run --release --example long_chain -- [DIR] [N,N,...]` searches the periodic orbit of
//! the bench gait (travelling sine `L_l = 2 sin(2 pi t - l pi/2)`, k = 1, mu+ = 1, mu- = 3.3,
//! catching-up on 1000 steps per period; the Newton-Krylov search) for every N (default 10 to
//! 10^4), prints a CSV table (N, 1/N, displacement per period, periods, tangent products,
//! seconds), the least-squares fit `d(N) = d_inf - c / N` on the three largest N, and writes
//! the figure of the displacement against 1/N (`long_chain.svg` and `.png` in DIR, default
//! the current directory): a straight line to the continuum value at 1/N = 0.

use crawlopt::integrate::{simulate, Actuation, Method, SimOptions, Waveform};
use crawlopt::present::figures::sweep::{sweep_lines_figure, SweepGrid};
use crawlopt::Crawler;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = std::path::PathBuf::from(args.first().map_or(".", |s| s.as_str()));
    let ns: Vec<usize> = match args.get(1) {
        Some(list) => list
            .split(',')
            .map(|s| s.trim().parse())
            .collect::<Result<_, _>>()?,
        None => vec![10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10_000],
    };
    println!("N,inv_N,displacement_per_period,periods,tangent_products,seconds");
    let mut points = Vec::new();
    for &nb in &ns {
        let crawler = Crawler::uniform(nb, 1.0, 1.0, 3.3)?;
        let n = nb - 1;
        let phases = (0..n).map(|l| l as f64 * 90.0).collect();
        let act = Actuation::wave(Waveform::Sine, 1.0, vec![0.0; n], vec![2.0; n], phases)?;
        let opts = SimOptions {
            method: Method::CatchingUp,
            record_periods: 0,
            ..SimOptions::default()
        };
        let t0 = Instant::now();
        let sim = simulate(&crawler, &act, &opts)?;
        let d = sim
            .displacement_per_period
            .ok_or(format!("N = {nb}: the periodic regime was not reached"))?;
        println!(
            "{nb},{:.6e},{d:.15},{},{},{:.3}",
            1.0 / nb as f64,
            sim.periods_simulated,
            sim.tangent_products,
            t0.elapsed().as_secs_f64()
        );
        points.push((1.0 / nb as f64, d));
    }
    // d = d_inf - c x, x = 1/N, by least squares on the three largest N.
    let mut tail = points.clone();
    tail.sort_by(|a, b| a.0.total_cmp(&b.0));
    tail.truncate(3);
    if tail.len() >= 2 {
        let m = tail.len() as f64;
        let (sx, sy) = tail
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
        let (mx, my) = (sx / m, sy / m);
        let sxx: f64 = tail.iter().map(|(x, _)| (x - mx).powi(2)).sum();
        let sxy: f64 = tail.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
        let slope = sxy / sxx;
        println!(
            "# fit on the three largest N: d(N) = {:.9} - {:.4} / N",
            my - slope * mx,
            -slope
        );
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let grid = SweepGrid {
        x_name: "1/N".into(),
        x: points.iter().map(|p| p.0).collect(),
        y_name: String::new(),
        y: vec![0.0],
        value_name: "displacement per period".into(),
        values: vec![points.iter().map(|p| Some(p.1)).collect()],
    };
    let fig = sweep_lines_figure(&grid)?;
    std::fs::create_dir_all(&dir)?;
    std::fs::write(dir.join("long_chain.svg"), &fig.svg)?;
    std::fs::write(dir.join("long_chain.png"), &fig.png)?;
    Ok(())
}
