//! Figure `actuation`: the actuators' lengths `L_l(t)` and rates `u_l(t)` over a period.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A piecewise-linear actuation over one period: `L` at the knots and `u = K L'` on the pieces.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuationSeries {
    /// Knot times from 0 to the period `T` inclusive.
    pub times: Vec<f64>,
    /// `L(t_j)` at every knot, one row per knot (`times.len()` rows).
    pub lengths: Vec<Vec<f64>>,
    /// `u_j = K (L_{j+1} - L_j) / (t_{j+1} - t_j)` on every piece (`times.len() - 1` rows).
    pub controls: Vec<Vec<f64>>,
    /// Rate bounds `a_l` of the gait problem, drawn as the bang-bang levels `±a_l`.
    pub rate_bound: Option<Vec<f64>>,
}

impl ActuationSeries {
    /// From knots over one period (`times` from 0 to `T` inclusive, one row of lengths per knot)
    /// and the stiffnesses: the controls are the slopes times `k_l`. Zero-length pieces are
    /// dropped.
    pub fn from_knots(
        times: &[f64],
        lengths: &[Vec<f64>],
        stiffness: &[f64],
        rate_bound: Option<Vec<f64>>,
    ) -> Result<Self> {
        if times.len() < 2 || times.len() != lengths.len() {
            return Err(Error::invalid(
                "actuation knots",
                format!("{} times, {} rows", times.len(), lengths.len()),
                "need at least two knots and one row of lengths per knot",
            ));
        }
        let (mut t, mut l, mut u) = (vec![times[0]], vec![lengths[0].clone()], Vec::new());
        for j in 1..times.len() {
            let dt = times[j] - times[j - 1];
            if dt.is_nan() || dt <= 0.0 {
                continue;
            }
            u.push(
                (0..stiffness.len())
                    .map(|i| stiffness[i] * (lengths[j][i] - lengths[j - 1][i]) / dt)
                    .collect(),
            );
            t.push(times[j]);
            l.push(lengths[j].clone());
        }
        if u.is_empty() {
            return Err(Error::invalid(
                "actuation knots",
                "no piece of positive duration",
                "need increasing times",
            ));
        }
        Ok(ActuationSeries {
            times: t,
            lengths: l,
            controls: u,
            rate_bound,
        })
    }
}

impl Plot for ActuationSeries {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.lengths[0].len();
        let period = *self.times.last().unwrap_or(&1.0);
        let (top, bottom) = root.split_vertically(root.dim_in_pixel().1 / 2);
        let lr = headroom(range_of(self.lengths.iter().flatten(), 0.08), n);
        let mut c = chart(
            &top,
            s,
            "Actuation over one period",
            (0.0, period),
            lr,
            "time t [time]",
            "actuator length L [length]",
        )?;
        for l in 0..n {
            let pts: Vec<(f64, f64)> = self
                .times
                .iter()
                .zip(&self.lengths)
                .map(|(&t, row)| (t, row[l]))
                .collect();
            draw_thick(&mut c, &pts, link_colour(l), 2.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label(format!("L{}(t)", sub(l + 1)))
                .legend(legend_line(link_colour(l), s.px(2.5)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        let mut urange: Vec<f64> = self.controls.iter().flatten().copied().collect();
        if let Some(a) = &self.rate_bound {
            urange.extend(a.iter().flat_map(|a| [*a, -*a]));
        }
        let ur = headroom(range_of(&urange, 0.12), n);
        let mut c = chart(
            &bottom,
            s,
            if self.rate_bound.is_some() {
                "Rate u = k L′ (bang-bang arcs sit on the dashed bounds ±a)"
            } else {
                "Rate u = k L′"
            },
            (0.0, period),
            ur,
            "time t [time]",
            "rate u [force/time]",
        )?;
        if let Some(a) = &self.rate_bound {
            for (l, &a) in a.iter().enumerate() {
                for v in [a, -a] {
                    c.draw_series(DashedLineSeries::new(
                        vec![(0.0, v), (period, v)],
                        s.px(6.0),
                        s.px(4.0),
                        s.line(RGBColor(150, 150, 150), 1.0),
                    ))?;
                }
                if l == 0 {
                    c.draw_series(std::iter::once(Text::new(
                        "±a",
                        (period * 0.005, a),
                        s.text_c(12.0, RGBColor(110, 110, 110))
                            .pos(Pos::new(HPos::Left, VPos::Bottom)),
                    )))?;
                }
            }
        }
        for l in 0..n {
            let mut pts = Vec::with_capacity(2 * self.controls.len());
            for (j, u) in self.controls.iter().enumerate() {
                pts.push((self.times[j], u[l]));
                pts.push((self.times[j + 1], u[l]));
            }
            draw_thick(&mut c, &pts, link_colour(l), 2.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label(format!("u{}(t)", sub(l + 1)))
                .legend(legend_line(link_colour(l), s.px(2.5)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}

/// Figure `actuation`: `L_l(t)` and `u_l(t)` over a period.
pub fn actuation_figure(a: &ActuationSeries) -> Result<Figure> {
    render(
        "actuation",
        format!(
            "Actuator lengths L(t) and rates u(t) = k L′(t) over one period{}.",
            if a.rate_bound.is_some() {
                "; dashed: the rate bounds ±a"
            } else {
                ""
            }
        ),
        (FIGURE_SIZE.0, 640),
        a,
    )
}

// ---------------------------------------------------------------------------------------------
// Space-time diagram
