//! Figures of a fit (`crawlopt fit --plot`): the measured positions against those of the fitted
//! model re-simulated under the measured actuation, and per block the spring force against the
//! velocity with the fitted thresholds (the flow rule: the points of a sliding block sit on a
//! threshold, those of a still one between the two).

use super::{
    chart, legend, legend_line, link_colour, range_of, render, sub, Figure, Plot, Sty, BACKWARD,
    FIGURE_SIZE, FORWARD, STICK,
};
use crate::error::{Error, Result};
use crate::fit::{FitData, FitResult};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The figures of `r`, a fit of `data`: `fit_trajectories` (when the fitted model was
/// re-simulated) and `fit_force_block_<b>` for every block (when a crawler was fitted).
pub fn fit_figures(data: &FitData, r: &FitResult) -> Result<Vec<Figure>> {
    let Some(model) = &r.model else {
        return Err(Error::invalid(
            "--plot",
            "no fitted crawler",
            format!("nothing to draw: {}", r.warnings.join("; ")),
        ));
    };
    let mut figs = Vec::new();
    if let Some(p) = &r.prediction {
        figs.push(render(
            "fit_trajectories",
            "Block positions: measured (dots) and predicted by the fitted model re-simulated \
             under the measured actuation (lines)."
                .into(),
            FIGURE_SIZE,
            &Trajectories {
                data,
                predicted: &p.positions,
            },
        )?);
    }
    let nb = data.blocks();
    let m = data.samples();
    for b in 0..nb {
        let mut pts = Vec::with_capacity(m);
        for i in 0..m {
            let (i0, i1) = (i.saturating_sub(1), (i + 1).min(m - 1));
            let v = (data.positions[i1][b] - data.positions[i0][b]) / (data.t[i1] - data.t[i0]);
            let mut f = 0.0;
            if b > 0 {
                f += model.stiffness[b - 1] * data.compression(i, b - 1);
            }
            if b + 1 < nb {
                f -= model.stiffness[b] * data.compression(i, b);
            }
            pts.push((v, f, r.sliding[i][b]));
        }
        figs.push(render(
            &format!("fit_force_block_{}", b + 1),
            format!(
                "Block {}: spring force (fitted stiffnesses) against velocity, with the fitted \
                 thresholds mu+ and -mu-.",
                b + 1
            ),
            FIGURE_SIZE,
            &Forces {
                block: b,
                pts,
                mu_forward: model.mu_forward[b],
                mu_backward: model.mu_backward[b],
                known: [
                    r.crawler.mu_forward[b].is_some(),
                    r.crawler.mu_backward[b].is_some(),
                ],
            },
        )?);
    }
    Ok(figs)
}

struct Trajectories<'a> {
    data: &'a FitData,
    predicted: &'a [Vec<f64>],
}

impl Plot for Trajectories<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> super::DrawResult
    where
        DB::ErrorType: 'static,
    {
        let d = self.data;
        let xr = range_of(&d.t, 0.02);
        let all: Vec<f64> = d
            .positions
            .iter()
            .chain(self.predicted)
            .flatten()
            .copied()
            .collect();
        let yr = range_of(&all, 0.05);
        let mut c = chart(
            root,
            s,
            "measured and fitted trajectories",
            xr,
            yr,
            "t [time]",
            "X [length]",
        )?;
        for b in 0..d.blocks() {
            let col = link_colour(b);
            c.draw_series(
                d.t.iter()
                    .zip(&d.positions)
                    .map(|(&t, x)| Circle::new((t, x[b]), s.px(2.0), col.filled())),
            )?;
            c.draw_series(LineSeries::new(
                d.t.iter().zip(self.predicted).map(|(&t, x)| (t, x[b])),
                s.line(col, 1.5),
            ))?
            .label(format!("X{}", sub(b + 1)))
            .legend(legend_line(col, s.px(2.0)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}

struct Forces {
    block: usize,
    pts: Vec<(f64, f64, i8)>,
    mu_forward: f64,
    mu_backward: f64,
    known: [bool; 2],
}

impl Plot for Forces {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> super::DrawResult
    where
        DB::ErrorType: 'static,
    {
        let vs: Vec<f64> = self.pts.iter().map(|p| p.0).collect();
        let fs: Vec<f64> = self
            .pts
            .iter()
            .map(|p| p.1)
            .chain([self.mu_forward, -self.mu_backward])
            .collect();
        let xr = range_of(&vs, 0.05);
        let yr = range_of(&fs, 0.1);
        let b = self.block + 1;
        let mut c = chart(
            root,
            s,
            &format!("block {b}: force against velocity"),
            xr,
            yr,
            &format!("X{}' [length/time]", sub(b)),
            &format!("F{} [force]", sub(b)),
        )?;
        for (dir, col, name) in [
            (1i8, FORWARD, "sliding forward"),
            (-1, BACKWARD, "sliding backward"),
            (0, STICK, "other samples"),
        ] {
            c.draw_series(
                self.pts
                    .iter()
                    .filter(|p| p.2 == dir)
                    .map(|p| Circle::new((p.0, p.1), s.px(2.5), col.filled())),
            )?
            .label(name)
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, col.filled()));
        }
        for (v, col, name, known) in [
            (self.mu_forward, FORWARD, "mu+", self.known[0]),
            (-self.mu_backward, BACKWARD, "-mu-", self.known[1]),
        ] {
            let label = if known {
                format!("fitted {name}")
            } else {
                format!("{name} (not bounded above by the data: model value)")
            };
            c.draw_series(DashedLineSeries::new(
                [(xr.0, v), (xr.1, v)],
                s.px(6.0),
                s.px(4.0),
                s.line(col, 1.5),
            ))?
            .label(label)
            .legend(legend_line(col, s.px(2.0)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}
