//! The long-chain study of `docs/guide/long-chains.md`: the best gait found against N on uniform
//! and heterogeneous chains, and the figures of the best gaits.
//!
//! `cargo run --release --example long_chain_study -- [DIR] [LIMIT] [N,N,...]` prints, per chain
//! and N, the best structured gait (J, which, seconds), the best travelling wave of one
//! wavelength along the body, and the chain method's answer under LIMIT seconds (default 20)
//! with how far its links' lags are from the alternating pattern, and the work bound over all
//! gaits (`certify::bound::work_bound`); and writes into DIR (default `docs/figures`) the
//! figure `long_chains_J_of_N.svg` (J against N, both chains, structured and chain method) and
//! the space-time figure (the library's `spacetime`) and a heat map of the actuator lengths
//! L_l(t) of the chain method's gait at N = 10, 30, 100 (both chains), as
//! `long_chains_{uniform,heterogeneous}_N{N}_{spacetime,lengths}.svg`.
//!
//! Chains as in `examples/bench_chains.rs`: uniform k = a = 1, T = 10, mu+ = 1, mu- = 1.3; the
//! heterogeneous chain: `k_l = 1 + 0.5 sin(1.7 l)`, block `b` with the friction pair `b mod 3`
//! of `(1, 1.3)`, `(1 + 0.1 sqrt 2, 1.3 + 0.2 sqrt 2)`, `(1 - 0.1 sqrt 3, 1.3 - 0.05 sqrt 3)`.

use crawlopt::api::{optimize, GaitMethod, Hooks, OptimizeSettings};
use crawlopt::certify::bound::work_bound;
use crawlopt::optimal::structured::{best_structured, StructuredOptions};
use crawlopt::optimal::{Cost, GaitProblem, GaitResult};
use crawlopt::present::gait_figures;
use crawlopt::Crawler;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use plotters::prelude::*;

/// One chain's values per N: (N, best structured J, chain method's J).
type Series = Vec<(usize, f64, f64)>;

/// Figure `long_chains_J_of_N.svg`: J against N (log scale) for both chains, the best
/// structured gait dashed and the chain method's answer solid.
fn j_of_n_svg(path: &Path, series: &[(&str, Series)]) -> Result<(), Box<dyn std::error::Error>> {
    // The text is measured with the font the library's figures embed.
    let font = include_bytes!("../assets/fonts/DejaVuSans.ttf");
    plotters::style::register_font("sans-serif", FontStyle::Normal, font)
        .map_err(|_| "the font cannot be registered")?;
    let root = SVGBackend::new(path, (760, 460)).into_drawing_area();
    root.fill(&WHITE)?;
    let nmax = series
        .iter()
        .flat_map(|(_, s)| s.iter().map(|r| r.0))
        .max()
        .unwrap_or(100) as f64;
    let jmax = series
        .iter()
        .flat_map(|(_, s)| s.iter().map(|r| r.1.max(r.2)))
        .fold(0.0, f64::max);
    let mut chart = ChartBuilder::on(&root)
        .caption("J against N (k = a = 1, T = 10)", ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d((2.0..nmax * 1.05).log_scale(), 0.0..jmax * 1.08)?;
    chart
        .configure_mesh()
        .x_desc("N (blocks)")
        .y_desc("J (displacement per period)")
        .draw()?;
    let colours = [RGBColor(0, 114, 178), RGBColor(213, 94, 0)];
    for ((name, s), colour) in series.iter().zip(colours) {
        let chain: Vec<(f64, f64)> = s.iter().map(|r| (r.0 as f64, r.2)).collect();
        let structured: Vec<(f64, f64)> = s.iter().map(|r| (r.0 as f64, r.1)).collect();
        chart
            .draw_series(LineSeries::new(chain.clone(), colour.stroke_width(2)))?
            .label(format!("{name}: chain method"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart.draw_series(chain.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
        chart
            .draw_series(DashedLineSeries::new(
                structured,
                6,
                4,
                colour.stroke_width(1),
            ))?
            .label(format!("{name}: best structured gait"))
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(1))
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

#[path = "support/cycling_chain.rs"]
mod cycling_chain;

/// The heterogeneous chain of `nb` blocks (module docs): three friction pairs.
fn heterogeneous(nb: usize) -> Crawler {
    cycling_chain::cycling_chain(nb, 3)
}

/// The lag of every link's length profile: the time of its minimum, as a fraction of T.
fn lags(r: &GaitResult) -> Vec<f64> {
    let g = &r.gait;
    let t = r.problem.period;
    let n = g.lengths[0].len();
    (0..n)
        .map(|l| {
            let j = (0..g.lengths.len())
                .min_by(|&a, &b| g.lengths[a][l].total_cmp(&g.lengths[b][l]))
                .unwrap_or(0);
            g.times[j] / t
        })
        .collect()
}

/// Largest distance of neighbouring links' lag differences from 1/2 (0: exactly alternating).
fn off_alternating(r: &GaitResult) -> f64 {
    let v = lags(r);
    v.windows(2)
        .map(|w| {
            let d = (w[1] - w[0]).rem_euclid(1.0);
            (d - 0.5).abs()
        })
        .fold(0.0, f64::max)
}

/// A heat map of L_l(t) (links down, one period across), normalised per link.
fn lengths_svg(r: &GaitResult, title: &str) -> String {
    let g = &r.gait;
    let t = r.problem.period;
    let n = g.lengths[0].len();
    let (w, h, left, top) = (640.0, 360.0, 60.0, 40.0);
    let cols = 160;
    let cell_w = w / cols as f64;
    let cell_h = h / n as f64;
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" \
         font-family=\"sans-serif\" font-size=\"12\">",
        w + left + 20.0,
        h + top + 40.0
    );
    let _ = write!(s, "<text x=\"{left}\" y=\"20\">{title}</text>");
    let span: Vec<(f64, f64)> = (0..n)
        .map(|l| {
            g.lengths
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), row| {
                    (a.min(row[l]), b.max(row[l]))
                })
        })
        .collect();
    // Colours quantised to 24 levels, equal neighbours along a row merged into one rectangle.
    let level = |l: usize, c: usize| -> usize {
        let tc = (c as f64 + 0.5) / cols as f64 * t;
        let j = g
            .times
            .iter()
            .rposition(|&x| x <= tc)
            .unwrap_or(0)
            .min(g.times.len() - 2);
        let a = (tc - g.times[j]) / (g.times[j + 1] - g.times[j]);
        let v = g.lengths[j][l] + a * (g.lengths[j + 1][l] - g.lengths[j][l]);
        let (lo, hi) = span[l];
        let z = if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        (z * 23.0).round() as usize
    };
    for l in 0..n {
        let mut c0 = 0;
        while c0 < cols {
            let q = level(l, c0);
            let mut c1 = c0 + 1;
            while c1 < cols && level(l, c1) == q {
                c1 += 1;
            }
            let z = q as f64 / 23.0;
            let (rr, gg, bb) = (
                (255.0 * z) as u8,
                (80.0 + 100.0 * (1.0 - (2.0 * z - 1.0).abs())) as u8,
                (255.0 * (1.0 - z)) as u8,
            );
            let _ = write!(
                s,
                "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{:.1}\" height=\"{:.1}\" \
                 fill=\"rgb({rr},{gg},{bb})\"/>",
                left + c0 as f64 * cell_w,
                top + l as f64 * cell_h,
                (c1 - c0) as f64 * cell_w + 0.1,
                cell_h + 0.1
            );
            c0 = c1;
        }
    }
    let _ = write!(
        s,
        "<text x=\"{left}\" y=\"{}\">t = 0</text><text x=\"{}\" y=\"{}\" \
         text-anchor=\"end\">t = T</text>",
        top + h + 16.0,
        left + w,
        top + h + 16.0
    );
    let _ = write!(
        s,
        "<text x=\"{}\" y=\"{}\" transform=\"rotate(-90 {} {})\" \
         text-anchor=\"middle\">link 1 (top) to {n}</text>",
        left - 12.0,
        top + h / 2.0,
        left - 12.0,
        top + h / 2.0
    );
    let _ = write!(
        s,
        "<text x=\"{left}\" y=\"{}\">blue: shortest, red: longest (per link)</text></svg>",
        top + h + 32.0
    );
    s
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = Path::new(args.first().map_or("docs/figures", |s| s.as_str())).to_path_buf();
    let limit: f64 = args.get(1).map_or(Ok(20.0), |s| s.parse())?;
    let ns: Vec<usize> = match args.get(2) {
        Some(list) => list
            .split(',')
            .map(|s| s.trim().parse())
            .collect::<Result<_, _>>()?,
        None => vec![2, 3, 4, 5, 6, 8, 10, 15, 20, 30, 50, 70, 100],
    };
    std::fs::create_dir_all(&dir)?;
    println!(
        "| chain | N | best structured J | which | s | 1-wavelength travelling triangle J | \
         chain J | status | s | max lag offset from alternating | work bound |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut series: Vec<(&str, Series)> = Vec::new();
    for kind in ["uniform", "heterogeneous"] {
        let mut values: Series = Vec::new();
        for &nb in &ns {
            let c = if kind == "uniform" {
                Crawler::uniform(nb, 1.0, 1.0, 1.3)?
            } else {
                heterogeneous(nb)
            };
            if c.require_unique().is_err() {
                println!("| {kind} | {nb} | (uniqueness condition fails) |||||||");
                continue;
            }
            let p = GaitProblem::new(&c, 10.0, &vec![1.0; nb - 1], Cost::None, None)?;
            let s = best_structured(&c, &p, &StructuredOptions::default())?
                .ok_or("no structured gait")?;
            let one_wave = s
                .rows
                .iter()
                .filter(|r| {
                    r.description
                        .starts_with("structured: travelling triangle wave, 1 wavelength")
                })
                .filter_map(|r| r.objective)
                .fold(f64::NAN, f64::max);
            let t0 = Instant::now();
            let r = optimize(
                &c,
                &p,
                &OptimizeSettings {
                    method: GaitMethod::Chain,
                    time_limit: Some(limit),
                    ..Default::default()
                },
                Hooks::default(),
            )?
            .result;
            let wall = t0.elapsed().as_secs_f64();
            println!(
                "| {kind} | {nb} | {:.6} | {} | {:.2} | {one_wave:.6} | {:.6} | {} | {wall:.1} | \
                 {:.3} | {:.3} |",
                s.objective,
                s.best.origin.trim_start_matches("structured: "),
                s.seconds,
                r.head.objective,
                r.head.status.as_str(),
                off_alternating(&r),
                work_bound(&c, &p)
            );
            values.push((nb, s.objective, r.head.objective));
            let figure = [10, 30, 100].contains(&nb);
            if figure {
                let stem = format!("long_chains_{kind}_N{nb}");
                for f in gait_figures(&r)? {
                    if f.name == "spacetime" {
                        std::fs::write(dir.join(format!("{stem}_spacetime.svg")), &f.svg)?;
                    }
                }
                let title = format!(
                    "{kind} chain, N = {nb}: L_l(t), J = {:.4}",
                    r.head.objective
                );
                std::fs::write(
                    dir.join(format!("{stem}_lengths.svg")),
                    lengths_svg(&r, &title),
                )?;
            }
        }
        series.push((kind, values));
    }
    if ns.len() > 1 {
        j_of_n_svg(&dir.join("long_chains_J_of_N.svg"), &series)?;
    }
    Ok(())
}
