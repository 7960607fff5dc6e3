//! The figures of the general problem (P) (theory §11), from plain data: the set C with the
//! state's path in it ([`StateSpace`], figure `polytope`: an interval over time in 1-D, the
//! polygon in 2-D, projections onto pairs of coordinates beyond, drawn by the same panels as
//! the crawler's C), and curves over time ([`TimeSeries`]: the states, the controls, the
//! reactions, the objective's integrand).

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use super::panel::{IntervalEnd, IntervalPanel, PairPanel, Projection};
use super::polytope::projection_pairs;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One panel of [`StateSpace`]: C (or `C ∩ window`) projected onto `(x_i, x_j)`.
#[derive(Debug, Clone, PartialEq)]
pub struct StatePanel {
    /// `(i, j)`, 0-based, `i < j`.
    pub pair: (usize, usize),
    /// The polygon: vertices counter-clockwise, edges labelled with their face (in 2-D), the
    /// sides that are the window's.
    pub projection: Projection,
}

/// One end of C in 1-D: its value and the face there (1-based; `None` where a window cuts an
/// unbounded C).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntervalEndData {
    /// The value.
    pub value: f64,
    /// The face, 1-based.
    pub face: Option<usize>,
}

/// C of a general problem with a path of the state in it, as figure `polytope` draws it.
#[derive(Debug, Clone, PartialEq)]
pub struct StateSpace {
    /// The dimension `n`.
    pub dim: usize,
    /// Whether C is bounded (else it is drawn within a window, whose sides are grey).
    pub bounded: bool,
    /// `n = 1`: the ends of C (lower, upper).
    pub interval: Option<[IntervalEndData; 2]>,
    /// `n >= 2`: the pairs shown ([`projection_pairs`]).
    pub panels: Vec<StatePanel>,
    /// Points marked in the 2-D polygon (C's vertices).
    pub dots: Vec<(f64, f64)>,
    /// The path's times.
    pub t: Vec<f64>,
    /// The path's states, one per time (empty: C alone).
    pub x: Vec<Vec<f64>>,
    /// The legend's name of the path ("periodic orbit", ...).
    pub path_label: String,
}

struct StatePlot<'a>(&'a StateSpace);

impl StatePlot<'_> {
    fn path(&self, i: usize, j: usize) -> Option<Vec<(f64, f64)>> {
        let v = self.0;
        (v.x.len() >= 2).then(|| v.x.iter().map(|x| (x[i], x[j])).collect())
    }
}

impl Plot for StatePlot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let v = self.0;
        if let Some([lo, hi]) = v.interval {
            let end = |e: IntervalEndData, what: &str| IntervalEnd {
                value: e.value,
                text: match e.face {
                    Some(f) => format!("face {f}:  x₁ = {what} = {}", fmt_num(e.value)),
                    None => format!("C continues {what} (window)"),
                },
                face: e.face.is_some(),
            };
            let (t0, t1) = match (v.t.first(), v.t.last()) {
                (Some(&a), Some(&b)) if b > a => (a, b),
                _ => (0.0, 1.0),
            };
            let orbit = (v.x.len() >= 2).then(|| {
                v.t.iter()
                    .zip(&v.x)
                    .map(|(&t, x)| (t, x[0]))
                    .collect::<Vec<_>>()
            });
            let below = if lo.face.is_some() { "a" } else { "below" };
            let above = if hi.face.is_some() { "b" } else { "above" };
            return IntervalPanel {
                title: "The state x(t) in C (one state component)",
                ylabel: "state x₁",
                ends: [end(lo, below), end(hi, above)],
                times: (t0, t1),
                orbit,
                orbit_label: &format!("x₁(t): {}", v.path_label),
            }
            .draw(root, s);
        }
        let big = v.panels.len() == 1;
        let areas = if big {
            vec![root.clone()]
        } else {
            let cols = v.panels.len().min(3);
            root.split_evenly((v.panels.len().div_ceil(cols), cols))
        };
        for (area, p) in areas.iter().zip(&v.panels) {
            let (i, j) = p.pair;
            let title = if big {
                "The state x(t) in C (edges: face numbers)".to_string()
            } else {
                format!("C projected on (x{}, x{})", sub(i + 1), sub(j + 1))
            };
            PairPanel {
                proj: &p.projection,
                title,
                axes: (format!("x{}", sub(i + 1)), format!("x{}", sub(j + 1))),
                big,
                transient: None,
                orbit: self.path(i, j),
                orbit_label: &v.path_label,
                origin: false,
                equal_scale: comparable(&p.projection),
                dots: if big { &v.dots[..] } else { &[] },
            }
            .draw(area, s)?;
        }
        Ok(())
    }
}

/// Whether a polygon's two spans are within a factor 4 of each other (then it is drawn with
/// equal scales, so that angles between faces are true; else each axis spans its own range).
fn comparable(p: &Projection) -> bool {
    let span = |f: fn(&(f64, f64)) -> f64| {
        let (lo, hi) = p
            .vertices
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        hi - lo
    };
    let (a, b) = (span(|v| v.0), span(|v| v.1));
    a > 0.0 && b > 0.0 && a.max(b) <= 4.0 * a.min(b)
}

/// Figure `polytope` of a general problem: C with the path of the state (see [`StateSpace`]).
pub fn general_polytope_figure(v: &StateSpace) -> Result<Figure> {
    let bad = |why: String| Err(Error::invalid("state space", format!("n = {}", v.dim), why));
    if v.x.iter().any(|x| x.len() != v.dim) || (!v.x.is_empty() && v.x.len() != v.t.len()) {
        return bad("one state of n components per time".into());
    }
    match (v.dim, &v.interval) {
        (0, _) => return bad("a state needs a component".into()),
        (1, None) => return bad("one component needs the interval C".into()),
        (1, Some([lo, hi]))
            if lo.value.partial_cmp(&hi.value) != Some(std::cmp::Ordering::Less) =>
        {
            return bad(format!(
                "the interval [{}, {}] is empty",
                lo.value, hi.value
            ))
        }
        (1, _) => {}
        (_, _) => {
            if v.panels.is_empty()
                || v.panels.iter().any(|p| {
                    p.projection.vertices.len() < 3 || p.pair.0 >= v.dim || p.pair.1 >= v.dim
                })
            {
                return bad("every pair needs a polygon of at least three vertices".into());
            }
        }
    }
    let n = v.dim;
    let size = match n {
        1 => (760, 560),
        2 => (760, 640),
        _ => {
            let cols = v.panels.len().min(3) as u32;
            let rows = v.panels.len().div_ceil(3) as u32;
            (cols * 380, rows * 370)
        }
    };
    let what = match n {
        1 => "the interval C of the state and the state x(t) over time".to_string(),
        2 => "the polygon C in the plane of the state (x₁, x₂), its vertices as dots".to_string(),
        _ if v.panels.len() == projection_pairs(n).len() && n <= 4 => {
            "the projections of C on every pair of state components".to_string()
        }
        _ => format!(
            "the projections of C on consecutive pairs of state components (the first {})",
            v.panels.len()
        ),
    };
    let path = if v.x.len() >= 2 {
        if n == 1 {
            format!(" Green: {}.", v.path_label)
        } else {
            format!(
                " Green: {}, dot at t = 0, arrow in the direction of travel.",
                v.path_label
            )
        }
    } else {
        String::new()
    };
    let window = if v.bounded {
        ""
    } else {
        " C is unbounded: it is drawn within a window around its vertices and the path, whose \
         sides are grey."
    };
    let faces = if n == 2 {
        " An edge is labelled with its face j (1-based; up to 24 edges)."
    } else {
        ""
    };
    render(
        "polytope",
        format!("The set C of the sweeping process: {what}.{faces}{window}{path}"),
        size,
        &StatePlot(v),
    )
}

/// A curve of a [`TimeSeries`].
#[derive(Debug, Clone, PartialEq)]
pub struct SeriesLine {
    /// The legend's name.
    pub label: String,
    /// The points `(t, value)` (a piecewise-constant curve repeats its times at the jumps).
    pub points: Vec<(f64, f64)>,
    /// Drawn thick (the main curve) or thin (its parts).
    pub thick: bool,
}

/// Curves over time with horizontal reference levels, as a figure draws them.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSeries {
    /// The file stem.
    pub name: String,
    /// The caption.
    pub caption: String,
    /// The title.
    pub title: String,
    /// The label of the value axis.
    pub ylabel: String,
    /// The curves.
    pub lines: Vec<SeriesLine>,
    /// Dashed levels `(value, legend name)` (bounds of U, ...).
    pub levels: Vec<(f64, String)>,
}

/// At most this many curves have a legend entry (the others are drawn without one).
pub const MAX_LEGEND: usize = 12;

impl Plot for TimeSeries {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let ts = self
            .lines
            .iter()
            .flat_map(|l| l.points.iter().map(|p| &p.0));
        let (t0, t1) = range_of(ts, 0.0);
        let vals: Vec<f64> = self
            .lines
            .iter()
            .flat_map(|l| l.points.iter().map(|p| p.1))
            .chain(self.levels.iter().map(|l| l.0))
            .collect();
        let entries = self.lines.len().min(MAX_LEGEND) + usize::from(!self.levels.is_empty());
        let yr = headroom(range_of(&vals, 0.08), entries.min(6));
        let mut c = chart(
            root,
            s,
            &self.title,
            (t0, t1),
            yr,
            "time t [time]",
            &self.ylabel,
        )?;
        if !self.levels.is_empty() {
            for (k, (v, _)) in self.levels.iter().enumerate() {
                let pts = dashes(t0, t1, *v, 60);
                let series = c.draw_series(
                    pts.into_iter()
                        .map(|seg| PathElement::new(seg, s.line(RGBColor(120, 120, 120), 1.2))),
                )?;
                if k == 0 {
                    let names: Vec<&str> = self.levels.iter().map(|l| l.1.as_str()).collect();
                    let mut names = names;
                    names.dedup();
                    series
                        .label(names.join(", "))
                        .legend(legend_line(RGBColor(120, 120, 120), s.px(1.2)));
                }
            }
        }
        for (k, l) in self.lines.iter().enumerate() {
            let colour = link_colour(k);
            draw_thick(
                &mut c,
                &l.points,
                colour,
                if l.thick { 2.4 } else { 1.3 },
                s,
            )?;
            if k < MAX_LEGEND {
                c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                    .label(l.label.clone())
                    .legend(legend_line(colour, s.px(if l.thick { 3.0 } else { 1.5 })));
            }
        }
        if entries > 0 {
            legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    }
}

/// A dashed horizontal line at `v` from `t0` to `t1` in `n` dashes.
fn dashes(t0: f64, t1: f64, v: f64, n: usize) -> Vec<Vec<(f64, f64)>> {
    let dt = (t1 - t0) / n as f64;
    (0..n)
        .map(|k| {
            let a = t0 + k as f64 * dt;
            vec![(a, v), (a + 0.55 * dt, v)]
        })
        .collect()
}

/// The figure of a [`TimeSeries`].
pub fn time_series_figure(ts: &TimeSeries) -> Result<Figure> {
    if ts.lines.is_empty() || ts.lines.iter().any(|l| l.points.len() < 2) {
        return Err(Error::invalid(
            format!("figure {}", ts.name),
            format!("{} curves", ts.lines.len()),
            "needs at least one curve of at least two points",
        ));
    }
    if ts
        .lines
        .iter()
        .flat_map(|l| &l.points)
        .any(|p| !(p.0.is_finite() && p.1.is_finite()))
    {
        return Err(Error::invalid(
            format!("figure {}", ts.name),
            "a non-finite point",
            "every point of a curve must be finite",
        ));
    }
    render(&ts.name, ts.caption.clone(), FIGURE_SIZE, ts)
}
