//! Figures of a parameter study (`crawlopt sweep --plot`, `crawlopt plot TABLE.csv`): the
//! value against one axis with one line per value of a second axis, and a heat map over two
//! axes with the boundary of the no-locomotion region (value = 0).

use super::{
    chart, colour_bar, diverging, legend, legend_line, render, tick, Figure, Plot, Sty, PALETTE,
};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

/// A value counts as zero (no locomotion) at most this much above 0, relative to the largest.
pub const ZERO_TOL: f64 = 1e-9;

/// A grid of values over two axes (`x` fast, `y` slow), `None` where a point has no value (an
/// error row, or a point not computed).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepGrid {
    /// Name of the x axis (the sweep's field).
    pub x_name: String,
    /// Its values, increasing.
    pub x: Vec<f64>,
    /// Name of the y axis (empty for one axis).
    pub y_name: String,
    /// Its values, increasing (one value for one axis).
    pub y: Vec<f64>,
    /// What the values are (`objective`, `displacement_per_period`).
    pub value_name: String,
    /// `values[iy][ix]`.
    pub values: Vec<Vec<Option<f64>>>,
}

struct Lines<'a>(&'a SweepGrid);
struct Heat<'a>(&'a SweepGrid);

fn finite(g: &SweepGrid) -> impl Iterator<Item = f64> + '_ {
    g.values.iter().flatten().flatten().copied()
}

impl Plot for Lines<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> super::DrawResult
    where
        DB::ErrorType: 'static,
    {
        let g = self.0;
        let xr = super::range_of(&g.x, 0.03);
        let ys: Vec<f64> = finite(g).collect();
        let yr = super::range_of(&ys, 0.08);
        let mut c = chart(
            root,
            s,
            &format!("{} against {}", g.value_name, g.x_name),
            xr,
            yr,
            &g.x_name,
            &g.value_name,
        )?;
        let many = g.y.len() > PALETTE.len() * 2;
        for (iy, yv) in g.y.iter().enumerate() {
            // Beyond the palette, its colours darkened (so that no two lines look alike).
            let p = PALETTE[iy % PALETTE.len()];
            let dark = |v: u8, k: usize| (v as usize / (k + 1)) as u8;
            let k = iy / PALETTE.len();
            let colour = RGBColor(dark(p.0, k), dark(p.1, k), dark(p.2, k));
            // Gaps where a point has no value.
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for (ix, v) in g.values[iy].iter().enumerate() {
                match v {
                    Some(v) => runs.last_mut().expect("one run").push((g.x[ix], *v)),
                    None => runs.push(Vec::new()),
                }
            }
            let mut labelled = false;
            for run in runs.into_iter().filter(|r| !r.is_empty()) {
                let series = c.draw_series(LineSeries::new(run.clone(), s.line(colour, 2.0)))?;
                if !labelled && !g.y_name.is_empty() && (!many || iy % 2 == 0) {
                    series
                        .label(format!("{} = {}", g.y_name, tick(*yv, 1e-3 * yv.abs())))
                        .legend(legend_line(colour, s.px(2.0)));
                    labelled = true;
                }
                c.draw_series(
                    run.iter()
                        .map(|&p| Circle::new(p, s.px(3.0), colour.filled())),
                )?;
            }
        }
        if !g.y_name.is_empty() {
            legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    }
}

/// Cell edges of a grid of (possibly uneven) values: midpoints, the ends half a step out.
fn edges(v: &[f64]) -> Vec<f64> {
    if v.len() == 1 {
        let d = 0.5 * v[0].abs().max(1.0);
        return vec![v[0] - d, v[0] + d];
    }
    let mut e = vec![v[0] - 0.5 * (v[1] - v[0])];
    e.extend(v.windows(2).map(|w| 0.5 * (w[0] + w[1])));
    let n = v.len();
    e.push(v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]));
    e
}

impl Plot for Heat<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> super::DrawResult
    where
        DB::ErrorType: 'static,
    {
        let g = self.0;
        let (main, bar) = root.split_horizontally(root.dim_in_pixel().0 - s.px(120.0));
        let (ex, ey) = (edges(&g.x), edges(&g.y));
        let vmax = finite(g).fold(0.0f64, |a, v| a.max(v.abs()));
        let vmax = if vmax > 0.0 { vmax } else { 1.0 };
        let zero = |v: f64| v.abs() <= ZERO_TOL * vmax;
        let mut c = chart(
            &main,
            s,
            &format!("{} over {} and {}", g.value_name, g.x_name, g.y_name),
            (ex[0], ex[ex.len() - 1]),
            (ey[0], ey[ey.len() - 1]),
            &g.x_name,
            &g.y_name,
        )?;
        let grey = RGBColor(200, 200, 200);
        let mut rects = Vec::new();
        for iy in 0..g.y.len() {
            for ix in 0..g.x.len() {
                let fill = match g.values[iy][ix] {
                    Some(v) => diverging(v / vmax),
                    None => grey,
                };
                rects.push(Rectangle::new(
                    [(ex[ix], ey[iy]), (ex[ix + 1], ey[iy + 1])],
                    fill.filled(),
                ));
            }
        }
        c.draw_series(rects)?;
        // The boundary of the no-locomotion region: the cell edges between a zero and a
        // non-zero value.
        let is_zero = |iy: usize, ix: usize| g.values[iy][ix].map(zero);
        let mut segs = Vec::new();
        for iy in 0..g.y.len() {
            for ix in 0..g.x.len() {
                let Some(z) = is_zero(iy, ix) else { continue };
                if ix + 1 < g.x.len() && is_zero(iy, ix + 1).is_some_and(|n| n != z) {
                    segs.push(vec![(ex[ix + 1], ey[iy]), (ex[ix + 1], ey[iy + 1])]);
                }
                if iy + 1 < g.y.len() && is_zero(iy + 1, ix).is_some_and(|n| n != z) {
                    segs.push(vec![(ex[ix], ey[iy + 1]), (ex[ix + 1], ey[iy + 1])]);
                }
            }
        }
        for (k, seg) in segs.into_iter().enumerate() {
            let series =
                c.draw_series(std::iter::once(PathElement::new(seg, s.line(BLACK, 2.5))))?;
            if k == 0 {
                series
                    .label("boundary of no locomotion (value 0)")
                    .legend(legend_line(BLACK, s.px(2.5)));
            }
        }
        if g.values.iter().flatten().any(Option::is_none) {
            c.draw_series(std::iter::once(Rectangle::new(
                [(ex[0], ey[0]), (ex[0], ey[0])],
                grey.filled(),
            )))?
            .label("no value (error)")
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], grey.filled()));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        let mut cb = colour_bar(&bar, s, vmax, &g.value_name)?;
        let (span, steps) = (2.0 * vmax, 100);
        cb.draw_series((0..steps).map(|k| {
            let a = -vmax + span * k as f64 / steps as f64;
            let b = -vmax + span * (k + 1) as f64 / steps as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                diverging(0.5 * (a + b) / vmax).filled(),
            )
        }))?;
        Ok(())
    }
}

fn check(g: &SweepGrid) -> Result<()> {
    let sorted = |v: &[f64]| !v.is_empty() && v.windows(2).all(|w| w[0] < w[1]);
    let shape = g.values.len() == g.y.len() && g.values.iter().all(|r| r.len() == g.x.len());
    if !sorted(&g.x) || !sorted(&g.y) || !shape || g.x.iter().chain(&g.y).any(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "sweep table",
            format!("{} x {} values", g.x.len(), g.y.len()),
            "the figures need increasing finite axis values and one value per grid point",
        ));
    }
    Ok(())
}

/// Figure `sweep_lines`: the value against the x axis, one line per value of the y axis.
pub fn sweep_lines_figure(g: &SweepGrid) -> Result<Figure> {
    check(g)?;
    let per = if g.y_name.is_empty() {
        String::new()
    } else {
        format!(", one line per value of {}", g.y_name)
    };
    render(
        "sweep_lines",
        format!(
            "{} against {}{per}; gaps where a point has no value.",
            g.value_name, g.x_name
        ),
        (900, 560),
        &Lines(g),
    )
}

/// Figure `sweep_map`: the value over the two axes (blue positive, vermillion negative, grey
/// without a value) with the boundary of the region where it is 0 (no locomotion).
pub fn sweep_map_figure(g: &SweepGrid) -> Result<Figure> {
    check(g)?;
    render(
        "sweep_map",
        format!(
            "{} over {} and {}: blue forward, white 0, vermillion backward, grey no value; black: \
             the boundary of the no-locomotion region (value 0).",
            g.value_name, g.x_name, g.y_name
        ),
        (900, 640),
        &Heat(g),
    )
}
