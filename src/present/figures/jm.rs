//! Figure `jm`: `J_m` against `m`, with the continuous-time value as a line.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use crate::error::{Error, Result};
use crate::optimal::ConvergenceRow;
use plotters::coord::Shift;
use plotters::prelude::*;

/// Optimal values of the discrete problems P_m against m, with the continuous-time value.
pub struct JmSeries<'a> {
    /// The `m` values.
    pub m: &'a [u32],
    /// `J_m`.
    pub values: &'a [f64],
    /// The continuous-time optimum (or the best phase gait), drawn as a line.
    pub continuous: Option<f64>,
}

impl Plot for JmSeries<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let ms: Vec<f64> = self.m.iter().map(|&m| m as f64).collect();
        let lo = ms.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ms.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let xr = (lo - 0.5, hi + 0.5);
        let mut ys = self.values.to_vec();
        ys.extend(self.continuous);
        let yr = range_of(&ys, 0.15);
        let mut c = chart_x(
            root,
            s,
            "Convergence of the discrete optima Jₘ",
            xr,
            yr,
            "m  (Pₘ has 2^m steps per period)",
            "optimal value J [length]",
            true,
        )?;
        if let Some(v) = self.continuous {
            c.draw_series(DashedLineSeries::new(
                vec![(xr.0, v), (xr.1, v)],
                s.px(8.0),
                s.px(5.0),
                s.line(BLACK, 1.6),
            ))?
            .label("continuous time")
            .legend(legend_line(BLACK, s.px(1.6)));
        }
        let pts: Vec<(f64, f64)> = ms
            .iter()
            .copied()
            .zip(self.values.iter().copied())
            .collect();
        c.draw_series(LineSeries::new(pts.clone(), s.line(FORWARD, 2.0)))?
            .label("Jₘ (global optimum of Pₘ)")
            .legend(legend_line(FORWARD, s.px(2.0)));
        c.draw_series(
            pts.iter()
                .map(|&p| Circle::new(p, s.px(5.0), FORWARD.filled())),
        )?;
        legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
        Ok(())
    }
}

/// Figure `jm`: `J_m` against `m` with the continuous-time value as a line.
pub fn jm_figure(m: &[u32], values: &[f64], continuous: Option<f64>) -> Result<Figure> {
    if m.is_empty() || m.len() != values.len() {
        return Err(Error::invalid(
            "J_m table",
            format!("{} m values, {} J values", m.len(), values.len()),
            "needs one J value per m, at least one",
        ));
    }
    if values.iter().chain(&continuous).any(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "J_m table",
            "a non-finite value",
            "needs finite values",
        ));
    }
    render(
        "jm",
        "Optimal values Jₘ of the discrete problems Pₘ (2^m steps) against m; dashed: the continuous-time value."
            .into(),
        (780, 520),
        &JmSeries {
            m,
            values,
            continuous,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Adjoint of a certificate

/// Figure `jm` of a result's convergence table (`optimize --convergence`, a crawler's or (P)'s
/// alike), without a continuous-time line: the table knows none.
pub fn convergence_figure(table: &[ConvergenceRow]) -> Result<Figure> {
    let m: Vec<u32> = table.iter().map(|r| r.m).collect();
    let values: Vec<f64> = table.iter().map(|r| r.objective).collect();
    jm_figure(&m, &values, None)
}
