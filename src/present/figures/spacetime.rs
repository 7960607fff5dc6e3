//! Figure `spacetime`: the blocks' positions `X_b(t)` over the recorded periods, slipping
//! intervals coloured by direction, the barycentre overlaid.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use crate::error::Result;
use crate::integrate::Trajectory;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Drawing offset between consecutive blocks (a rest length for display only: the model's shape
/// `z` is measured from an arbitrary rest length), large enough that blocks never overlap in a
/// picture of `traj`.
pub fn display_spacing(traj: &Trajectory) -> f64 {
    let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &traj.positions {
        for w in p.windows(2) {
            let z = w[1] - w[0];
            zmin = zmin.min(z);
            zmax = zmax.max(z);
        }
    }
    if !(zmin.is_finite() && zmax.is_finite()) {
        return 1.0;
    }
    let span = (zmax - zmin).max(1e-9 * zmax.abs().max(1.0));
    nice_ceil((-zmin).max(0.0) + 1.5 * span.max(0.25 * zmax.abs()))
}

/// The smallest of 1, 2, 2.5, 5 times a power of ten at or above `v > 0`.
pub(super) fn nice_ceil(v: f64) -> f64 {
    if !(v > 0.0 && v.is_finite()) {
        return 1.0;
    }
    let p = 10f64.powf(v.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * p >= v * (1.0 - 1e-12) {
            return m * p;
        }
    }
    10.0 * p
}

/// The blocks' positions over several periods with their slip states and the barycentre.
pub struct SpaceTime<'a> {
    /// The recorded motion (`t`, `positions`, `barycentre`, `slip`).
    pub trajectory: &'a Trajectory,
    /// The period `T` (period boundaries are marked).
    pub period: f64,
}

impl Plot for SpaceTime<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let tr = self.trajectory;
        let nb = tr.positions[0].len();
        let d = display_spacing(tr);
        let off = |b: usize| b as f64 * d;
        let t_end = *tr.t.last().unwrap_or(&1.0);
        let t0 = tr.t[0];
        let ys: Vec<f64> = tr
            .positions
            .iter()
            .flat_map(|p| p.iter().enumerate().map(|(b, x)| x + off(b)))
            .collect();
        let yr = range_of(&ys, 0.06);
        let title = format!(
            "Space-time diagram: block b drawn at X_b + (b−1)ℓ₀, ℓ₀ = {} (a display rest length)",
            fmt_num(d)
        );
        let mut c = chart(
            root,
            s,
            &title,
            (t0, t_end),
            yr,
            "time t [time]",
            "position [length]",
        )?;
        // Period boundaries.
        let periods = ((t_end - t0) / self.period).round() as usize;
        for k in 1..periods {
            let t = t0 + k as f64 * self.period;
            c.draw_series(DashedLineSeries::new(
                vec![(t, yr.0), (t, yr.1)],
                s.px(3.0),
                s.px(4.0),
                s.line(RGBColor(170, 170, 170), 1.0),
            ))?;
        }
        for b in 0..nb {
            self.draw_block(&mut c, s, b, d, (t0, t_end), yr)?;
        }
        c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label("slides forward")
            .legend(legend_line(FORWARD, s.px(3.5)));
        c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label("slides backward")
            .legend(legend_line(BACKWARD, s.px(3.5)));
        let mid = off(nb - 1) / 2.0;
        let bary: Vec<(f64, f64)> =
            tr.t.iter()
                .zip(&tr.barycentre)
                .map(|(&t, y)| (t, y + mid))
                .collect();
        c.draw_series(DashedLineSeries::new(
            bary,
            s.px(7.0),
            s.px(4.0),
            s.line(BLACK, 2.0),
        ))?
        .label("barycentre y(t) + (N−1)ℓ₀/2")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], BLACK.stroke_width(2)));
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}

impl SpaceTime<'_> {
    /// Block `b` drawn `b d` up: grey where it sticks, coloured where it slips, and its label
    /// (of about 20 blocks at most); `(t0, t_end)` and `yr` are the axes' ranges.
    fn draw_block<'a, DB: DrawingBackend + 'a>(
        &self,
        c: &mut Chart2d<'a, DB>,
        s: Sty,
        b: usize,
        d: f64,
        (t0, t_end): (f64, f64),
        yr: (f64, f64),
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let tr = self.trajectory;
        let nb = tr.positions[0].len();
        let pts: Vec<(f64, f64)> =
            tr.t.iter()
                .zip(&tr.positions)
                .map(|(&t, p)| (t, p[b] + b as f64 * d))
                .collect();
        draw_thick(c, &pts, STICK, 1.2, s)?;
        if b == 0 {
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("block sticks")
                .legend(legend_line(STICK, s.px(1.5)));
        }
        for (sign, colour) in [(1i8, FORWARD), (-1i8, BACKWARD)] {
            for r in slip_runs(&tr.slip, b, &pts, sign) {
                draw_thick(c, &r, colour, 3.2, s)?;
            }
        }
        // At most about 20 block labels (long chains: every k-th block and the front one).
        let every = nb.div_ceil(20);
        if b % every == 0 || b == nb - 1 {
            c.draw_series(std::iter::once(Text::new(
                format!("block {}", b + 1),
                (t0 + 0.005 * (t_end - t0), pts[0].1 - 0.012 * (yr.1 - yr.0)),
                s.text(12.0).pos(Pos::new(HPos::Left, VPos::Top)),
            )))?;
        }
        Ok(())
    }
}

/// The slipping intervals of block `b` in the slip state `sign`, as the maximal runs of
/// consecutive intervals in it, one polyline of `pts` each (`slip[i]` is the state over
/// `(t[i-1], t[i])`).
fn slip_runs(
    slip: &[Vec<crate::integrate::Slip>],
    b: usize,
    pts: &[(f64, f64)],
    sign: crate::integrate::Slip,
) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut open = false;
    for i in 1..pts.len() {
        if slip[i][b] == sign {
            if !open {
                runs.push(vec![pts[i - 1]]);
                open = true;
            }
            if let Some(r) = runs.last_mut() {
                r.push(pts[i]);
            }
        } else {
            open = false;
        }
    }
    runs
}

/// Figure `spacetime`: `X_b(t)` over the recorded periods, slipping intervals coloured by
/// direction, barycentre overlaid.
pub fn spacetime_figure(traj: &Trajectory, period: f64) -> Result<Figure> {
    check_trajectory(traj)?;
    let periods = ((traj.t.last().unwrap_or(&0.0) - traj.t[0]) / period).round();
    render(
        "spacetime",
        format!(
            "Block positions X_b(t) over {periods} periods on the periodic orbit: blue where the block slides forward, \
             vermillion where it slides backward, grey where it sticks; dashed: the barycentre y(t)."
        ),
        FIGURE_SIZE,
        &SpaceTime {
            trajectory: traj,
            period,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// The trajectory in C
