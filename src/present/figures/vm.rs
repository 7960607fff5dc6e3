//! Figure `vm`: the heat map of `v_m` over shape rates for a two-link crawler, with its zero set.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use crate::error::{Error, Result};
use crate::model::Crawler;
use plotters::coord::Shift;
use plotters::prelude::*;

/// `v_m` on a grid of shape rates for a two-link crawler.
pub struct VmMap<'a> {
    /// The crawler (two links).
    pub crawler: &'a Crawler,
}

/// Directions `theta` in `[0, 2 pi)` of the zero set of `v_m(cos theta, sin theta)` (v_m is
/// positively homogeneous, so its zero set is a union of rays), found by sign changes on a fine
/// grid refined by bisection.
pub fn vm_zero_directions(crawler: &Crawler) -> Vec<f64> {
    let f = |th: f64| crawler.vm(&[th.cos(), th.sin()]);
    let m = 3600;
    let scale = crawler.mu_forward().iter().fold(0.0f64, |a, b| a.max(*b));
    let tol = 1e-12 * scale.max(1.0);
    let mut out: Vec<f64> = Vec::new();
    let step = std::f64::consts::TAU / m as f64;
    for k in 0..m {
        let (a, b) = (k as f64 * step, (k + 1) as f64 * step);
        let (fa, fb) = (f(a), f(b));
        if fa.abs() <= tol {
            out.push(a);
        } else if fa * fb < 0.0 {
            let (mut lo, mut hi, mut flo) = (a, b, fa);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                let fm = f(mid);
                if (fm < 0.0) == (flo < 0.0) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            out.push(0.5 * (lo + hi));
        }
    }
    out
}

impl Plot for VmMap<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let (main, bar) = root.split_horizontally(root.dim_in_pixel().0 - s.px(120.0));
        let g = 120;
        let mut vmax = 0.0f64;
        let mut cells = Vec::with_capacity(g * g);
        for iy in 0..g {
            for ix in 0..g {
                let z = (
                    -1.0 + 2.0 * (ix as f64 + 0.5) / g as f64,
                    -1.0 + 2.0 * (iy as f64 + 0.5) / g as f64,
                );
                let v = self.crawler.vm(&[z.0, z.1]);
                vmax = vmax.max(v.abs());
                cells.push((ix, iy, v));
            }
        }
        let vmax = if vmax > 0.0 { vmax } else { 1.0 };
        let mut c = chart(
            &main,
            s,
            "Barycentre velocity vₘ(z′) over shape rates (two links)",
            (-1.0, 1.0),
            (-1.0, 1.0),
            "shape rate z′₁ [length/time]",
            "shape rate z′₂ [length/time]",
        )?;
        // Colours quantised to LEVELS steps, equal neighbours in a row merged into one rectangle
        // (keeps the SVG small; the colour bar shows the same steps).
        let h = 2.0 / g as f64;
        let q = |v: f64| ((v / vmax) * LEVELS as f64).round() as i32;
        let mut rects = Vec::new();
        for iy in 0..g {
            let row = &cells[iy * g..(iy + 1) * g];
            let mut start = 0;
            for ix in 1..=g {
                if ix == g || q(row[ix].2) != q(row[start].2) {
                    let level = q(row[start].2);
                    let (x0, x1) = (-1.0 + start as f64 * h, -1.0 + ix as f64 * h);
                    let y0 = -1.0 + iy as f64 * h;
                    rects.push(Rectangle::new(
                        [(x0, y0), (x1, y0 + h)],
                        diverging(level as f64 / LEVELS as f64).filled(),
                    ));
                    start = ix;
                }
            }
        }
        c.draw_series(rects)?;
        let zeros = vm_zero_directions(self.crawler);
        for (k, th) in zeros.iter().enumerate() {
            // A ray from 0 to the square's boundary.
            let (cx, cy) = (th.cos(), th.sin());
            let r = 1.0 / cx.abs().max(cy.abs());
            let series = c.draw_series(std::iter::once(PathElement::new(
                vec![(0.0, 0.0), (r * cx, r * cy)],
                s.line(BLACK, 2.0),
            )))?;
            if k == 0 {
                series
                    .label("zero set vₘ = 0")
                    .legend(legend_line(BLACK, s.px(2.0)));
            }
        }
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        let mut cb = colour_bar(&bar, s, vmax, "vₘ [length/time]")?;
        let steps = 2 * LEVELS + 1;
        cb.draw_series((0..steps).map(|k| {
            let level = k as f64 - LEVELS as f64;
            let a = vmax * (level - 0.5) / LEVELS as f64;
            let b = vmax * (level + 0.5) / LEVELS as f64;
            Rectangle::new(
                [(0.0, a.max(-vmax)), (1.0, b.min(vmax))],
                diverging(level / LEVELS as f64).filled(),
            )
        }))?;
        cb.draw_series(std::iter::once(Rectangle::new(
            [(0.0, -vmax), (1.0, vmax)],
            s.line(BLACK, 1.0),
        )))?;
        Ok(())
    }
}

/// Figure `vm`: the heat map of `v_m` over shape rates for a two-link crawler, with its zero
/// set (for mild anisotropy the six rays of Remark 3.3's monkey saddle).
pub fn vm_figure(crawler: &Crawler) -> Result<Figure> {
    if crawler.links() != 2 {
        return Err(Error::invalid(
            "crawler.blocks",
            crawler.blocks(),
            "the v_m heat map is drawn for two links (three blocks) only",
        ));
    }
    crawler.require_unique()?;
    let rays = vm_zero_directions(crawler).len();
    render(
        "vm",
        format!(
            "The displacement function vₘ(z′) for shape rates z′ = (z′₁, z′₂): blue moves the crawler forward, \
             vermillion backward. vₘ is positively homogeneous, so its zero set is {rays} ray(s) from the origin{}.",
            if rays >= 6 {
                " (a monkey saddle, paper Remark 3.3)"
            } else {
                ""
            }
        ),
        (762, 640),
        &VmMap { crawler },
    )
}

// ---------------------------------------------------------------------------------------------
// J_m against m
