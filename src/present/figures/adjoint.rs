//! Figure `adjoint`: the adjoint `p(t)`, `p(t) + omega` and the control `u(t)` of a certificate.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The adjoint state of the necessary conditions (theory §8) with the control it selects.
pub struct AdjointSeries<'a> {
    /// Sample times.
    pub t: &'a [f64],
    /// `p(t)`, one row per sample.
    pub p: &'a [Vec<f64>],
    /// `p(t) + omega`, one row per sample.
    pub p_plus_omega: &'a [Vec<f64>],
    /// `u(t)`, one row per sample.
    pub u: &'a [Vec<f64>],
}

impl Plot for AdjointSeries<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.p[0].len();
        let tr = (self.t[0], *self.t.last().unwrap_or(&1.0));
        let (top, bottom) = root.split_vertically(root.dim_in_pixel().1 / 2);
        let mut all: Vec<f64> = self.p.iter().flatten().copied().collect();
        all.extend(self.p_plus_omega.iter().flatten());
        all.push(0.0);
        let mut c = chart(
            &top,
            s,
            "Adjoint p(t) and switching function p(t) + ω",
            tr,
            range_of(&all, 0.1),
            "time t [time]",
            "adjoint [length/force]",
        )?;
        c.draw_series(std::iter::once(PathElement::new(
            vec![(tr.0, 0.0), (tr.1, 0.0)],
            s.line(RGBColor(150, 150, 150), 1.0),
        )))?;
        for l in 0..n {
            let col = link_colour(l);
            let p: Vec<(f64, f64)> = self.t.iter().zip(self.p).map(|(&t, r)| (t, r[l])).collect();
            c.draw_series(LineSeries::new(p, s.line(col, 2.0)))?
                .label(format!("p{}(t)", sub(l + 1)))
                .legend(legend_line(col, s.px(2.0)));
            let q: Vec<(f64, f64)> = self
                .t
                .iter()
                .zip(self.p_plus_omega)
                .map(|(&t, r)| (t, r[l]))
                .collect();
            c.draw_series(DashedLineSeries::new(
                q,
                s.px(7.0),
                s.px(4.0),
                s.line(col, 2.0),
            ))?
            .label(format!("p{0}(t) + ω{0}", sub(l + 1)))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 9, y)], col.stroke_width(2)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        let mut c = chart(
            &bottom,
            s,
            "Control u(t) (bang-bang: u = −a sign(p + ω))",
            tr,
            range_of(self.u.iter().flatten(), 0.15),
            "time t [time]",
            "rate u [force/time]",
        )?;
        for l in 0..n {
            let col = link_colour(l);
            let u: Vec<(f64, f64)> = self.t.iter().zip(self.u).map(|(&t, r)| (t, r[l])).collect();
            c.draw_series(LineSeries::new(u, s.line(col, 2.2)))?
                .label(format!("u{}(t)", sub(l + 1)))
                .legend(legend_line(col, s.px(2.2)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}

/// Figure `adjoint`: `p(t)`, `p(t) + omega` and `u(t)` of a certificate (plain arrays, one row
/// per sample; draw jumps as two samples at the same time).
pub fn adjoint_figure(
    t: &[f64],
    p: &[Vec<f64>],
    p_plus_omega: &[Vec<f64>],
    u: &[Vec<f64>],
) -> Result<Figure> {
    let n = p.first().map_or(0, Vec::len);
    let ok = t.len() >= 2
        && n > 0
        && [p.len(), p_plus_omega.len(), u.len()]
            .iter()
            .all(|&l| l == t.len())
        && p.iter()
            .chain(p_plus_omega)
            .chain(u)
            .all(|r| r.len() == n && r.iter().all(|v| v.is_finite()))
        && t.iter().all(|v| v.is_finite());
    if !ok {
        return Err(Error::invalid(
            "adjoint",
            format!("{} times", t.len()),
            "needs at least two samples and, per sample, one finite value per link in p, p + omega and u",
        ));
    }
    render(
        "adjoint",
        "The adjoint p(t) (solid) and p(t) + ω (dashed) of the necessary conditions, with the control u(t) they select."
            .into(),
        (FIGURE_SIZE.0, 640),
        &AdjointSeries {
            t,
            p,
            p_plus_omega,
            u,
        },
    )
}
