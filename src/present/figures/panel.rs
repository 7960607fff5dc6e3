//! The panels of a state in its set C, shared by the crawler's figure `polytope` and the general
//! problem's (P): a polygon (C, or its projection onto a pair of coordinates) with its labelled
//! edges and a path in it ([`PairPanel`]), and an interval of one coordinate with the path over
//! time ([`IntervalPanel`]). Both kinds of figure hand their projections here, so the drawing of
//! an orbit in C is one piece of code.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A projection of C onto a pair of coordinates `(x_i, x_j)`, `i < j` (0-based): the crawler's
/// ([`super::projection`]: link forces, faces labelled by block and sign) or the general
/// problem's (state components, faces labelled by number).
#[derive(Debug, Clone, PartialEq)]
pub struct Projection {
    /// Vertices of the polygon, counter-clockwise.
    pub vertices: Vec<(f64, f64)>,
    /// The labelled edges of positive length (a crawler's: among its six bounding lines;
    /// redundant faces have none).
    pub edges: Vec<Edge>,
    /// Sides `k` (from vertex `k` to the next) that are not faces of C but the window cutting
    /// an unbounded C (the general problem's; none for a crawler).
    pub open_sides: Vec<usize>,
}

/// An edge of a projection of C.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// The face: a crawler's `b+` (block `b` slides forward), `b−`, or a group `1–2+`; a general
    /// problem's number `j`.
    pub label: String,
    /// One end.
    pub from: (f64, f64),
    /// The other end.
    pub to: (f64, f64),
    /// Unit outer normal.
    pub normal: (f64, f64),
}

/// Colour of a side of a polygon that is not a face of C but the window that cuts an unbounded
/// C.
const OPEN_SIDE: RGBColor = RGBColor(170, 170, 170);

/// A polygon with a path in it.
pub(super) struct PairPanel<'a> {
    /// The polygon and its labelled edges.
    pub proj: &'a Projection,
    /// The title.
    pub title: String,
    /// The axis labels.
    pub axes: (String, String),
    /// The single panel of its figure (larger labels, a legend).
    pub big: bool,
    /// A path drawn thin and grey under the orbit (the crawler's approach from rest).
    pub transient: Option<Vec<(f64, f64)>>,
    /// The path, with a dot at its start and an arrow in its direction.
    pub orbit: Option<Vec<(f64, f64)>>,
    /// The legend's name of the path.
    pub orbit_label: &'a str,
    /// A cross at the origin.
    pub origin: bool,
    /// Equal scales on both axes (else each axis spans its own range).
    pub equal_scale: bool,
    /// Points marked with dots (C's vertices).
    pub dots: &'a [(f64, f64)],
}

impl PairPanel<'_> {
    /// The panel in `area`: the polygon, its face labels, its dots, the origin, the transient
    /// and the path.
    pub(super) fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        s: Sty,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let (xr, yr, plot) = self.ranges(area, s);
        let mut c = chart(area, s, &self.title, xr, yr, &self.axes.0, &self.axes.1)?;
        self.draw_polygon(&mut c, s)?;
        self.draw_face_labels(&mut c, s, xr, yr)?;
        if !self.dots.is_empty() {
            c.draw_series(
                self.dots
                    .iter()
                    .map(|&d| Circle::new(d, s.px(3.0), BLACK.filled())),
            )?;
        }
        if self.origin {
            // The origin (unloaded crawler).
            c.draw_series(std::iter::once(Cross::new(
                (0.0, 0.0),
                s.px(4.0),
                s.line(RGBColor(120, 120, 120), 1.0),
            )))?;
        }
        if let Some(tr) = self.transient.as_ref().filter(|t| t.len() >= 2) {
            draw_thick(&mut c, tr, RGBColor(120, 120, 120), 1.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("transient from x = 0")
                .legend(legend_line(RGBColor(120, 120, 120), s.px(1.5)));
        }
        if let Some(o) = &self.orbit {
            self.draw_orbit(&mut c, s, o, xr, yr, plot)?;
        }
        Ok(())
    }

    /// The axis ranges around the polygon (with room for the face labels; widened to equal
    /// scales when asked) and the plotting area's size in pixels, which equal scales need.
    fn ranges<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        s: Sty,
    ) -> ((f64, f64), (f64, f64), (f64, f64)) {
        let p = self.proj;
        // Room around the polygon for the face labels (group labels such as 1–2+ are wide).
        let pad = if self.big { 0.18 } else { 0.3 };
        let xr = range_of(p.vertices.iter().map(|v| &v.0), pad);
        let yr = range_of(p.vertices.iter().map(|v| &v.1), pad);
        // The plotting area in pixels.
        let (w, h) = area.dim_in_pixel();
        let (pw, ph) = (
            w as f64 - s.px(70.0 + 28.0) as f64,
            h as f64 - s.px(46.0 + 20.0 + 30.0) as f64,
        );
        let (xr, yr) = if self.equal_scale {
            // Equal scales on both axes: widen the shorter range to the plot's aspect ratio.
            let (sx, sy) = ((xr.1 - xr.0) / pw.max(1.0), (yr.1 - yr.0) / ph.max(1.0));
            let k = sx.max(sy);
            let (cx, cy) = ((xr.0 + xr.1) / 2.0, (yr.0 + yr.1) / 2.0);
            (
                (cx - k * pw / 2.0, cx + k * pw / 2.0),
                (cy - k * ph / 2.0, cy + k * ph / 2.0),
            )
        } else {
            (xr, yr)
        };
        (xr, yr, (pw, ph))
    }

    /// The polygon, shaded, and its sides: black where they are faces of C, grey where they
    /// are the window's cut of an unbounded C.
    fn draw_polygon<'a, DB: DrawingBackend + 'a>(
        &self,
        c: &mut Chart2d<'a, DB>,
        s: Sty,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let p = self.proj;
        c.draw_series(std::iter::once(Polygon::new(
            p.vertices.clone(),
            RGBColor(0, 114, 178).mix(0.08).filled(),
        )))?;
        if p.open_sides.is_empty() {
            let mut closed = p.vertices.clone();
            closed.push(p.vertices[0]);
            c.draw_series(std::iter::once(PathElement::new(
                closed,
                s.line(BLACK, 1.6),
            )))?;
        } else {
            let nv = p.vertices.len();
            for k in 0..nv {
                let (a, b) = (p.vertices[k], p.vertices[(k + 1) % nv]);
                let style = if p.open_sides.contains(&k) {
                    s.line(OPEN_SIDE, 1.0)
                } else {
                    s.line(BLACK, 1.6)
                };
                c.draw_series(std::iter::once(PathElement::new(vec![a, b], style)))?;
            }
        }
        Ok(())
    }

    /// The labels of the faces, each beside the middle of its edge, off it along the outer
    /// normal (in the axis ranges `xr`, `yr`).
    fn draw_face_labels<'a, DB: DrawingBackend + 'a>(
        &self,
        c: &mut Chart2d<'a, DB>,
        s: Sty,
        xr: (f64, f64),
        yr: (f64, f64),
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let gap = 0.035 * (xr.1 - xr.0);
        for e in &self.proj.edges {
            let (label, a, b, (na, nbv)) = (&e.label, e.from, e.to, &e.normal);
            let m = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
            let h = if *na > 0.3 {
                HPos::Left
            } else if *na < -0.3 {
                HPos::Right
            } else {
                HPos::Center
            };
            let v = if *nbv > 0.3 {
                VPos::Bottom
            } else if *nbv < -0.3 {
                VPos::Top
            } else {
                VPos::Center
            };
            // The normal in pixels is not the normal in data units without equal scales: the
            // label is put off the edge by the same fraction of each axis.
            let off = if self.equal_scale {
                (gap * na, gap * nbv)
            } else {
                (0.035 * (xr.1 - xr.0) * na, 0.035 * (yr.1 - yr.0) * nbv)
            };
            c.draw_series(std::iter::once(Text::new(
                label.clone(),
                (m.0 + off.0, m.1 + off.1),
                s.text_c(if self.big { 15.0 } else { 14.0 }, RGBColor(60, 60, 60))
                    .pos(Pos::new(h, v)),
            )))?;
        }
        Ok(())
    }

    /// The path `o`: thick, a dot at its start, an arrow head in its direction, and the legend
    /// of a single panel (axis ranges `xr`, `yr`; plotting area `(pw, ph)` in pixels).
    fn draw_orbit<'a, DB: DrawingBackend + 'a>(
        &self,
        c: &mut Chart2d<'a, DB>,
        s: Sty,
        o: &[(f64, f64)],
        xr: (f64, f64),
        yr: (f64, f64),
        (pw, ph): (f64, f64),
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let pts: Vec<(f64, f64)> = dedup(o.to_vec());
        draw_thick(c, &pts, ORBIT, 2.8, s)?;
        c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label(self.orbit_label)
            .legend(legend_line(ORBIT, s.px(3.0)));
        c.draw_series(std::iter::once(Circle::new(
            pts[0],
            s.px(4.5),
            ORBIT.filled(),
        )))?
        .label("x(0)")
        .legend(|(x, y)| Circle::new((x + 11, y), 4, ORBIT.filled()));
        // Without equal scales the arrow is drawn where they are (y stretched by `fy`).
        let fy = if self.equal_scale {
            1.0
        } else {
            (xr.1 - xr.0) / (yr.1 - yr.0) * ph.max(1.0) / pw.max(1.0)
        };
        if let Some(head) = arrow_head(&pts, fy, 0.035 * (xr.1 - xr.0)) {
            c.draw_series(std::iter::once(Polygon::new(head, ORBIT.filled())))?;
        }
        if self.big {
            legend(c, s, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    }
}

/// Direction of travel of the path `pts`: the triangle of an arrow head of `size` in the middle
/// of its longest segment, measured and shaped with y stretched by `fy` (as on screen without
/// equal scales); none when the path does not move.
fn arrow_head(pts: &[(f64, f64)], fy: f64, size: f64) -> Option<Vec<(f64, f64)>> {
    let longest = pts.windows(2).map(|w| (w[0], w[1])).max_by(|a, b| {
        let la = (a.1 .0 - a.0 .0).hypot(a.1 .1 - a.0 .1);
        let lb = (b.1 .0 - b.0 .0).hypot(b.1 .1 - b.0 .1);
        la.total_cmp(&lb)
    });
    let (a, b) = longest?;
    let (a, b) = ((a.0, a.1 * fy), (b.0, b.1 * fy));
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len = dx.hypot(dy);
    // A path that does not move has no direction (nor a NaN one).
    (len > 0.0).then(|| {
        let (ux, uy) = (dx / len, dy / len);
        let tip = (
            (a.0 + b.0) / 2.0 + 0.5 * size * ux,
            (a.1 + b.1) / 2.0 + 0.5 * size * uy,
        );
        let l = (
            tip.0 - size * (ux - 0.5 * uy),
            tip.1 - size * (uy + 0.5 * ux),
        );
        let r = (
            tip.0 - size * (ux + 0.5 * uy),
            tip.1 - size * (uy - 0.5 * ux),
        );
        let back = |p: (f64, f64)| (p.0, p.1 / fy);
        vec![back(tip), back(l), back(r)]
    })
}

/// One end of an interval: its value, the text beside it, and whether it is a face of C (a
/// black line) or the window cutting an unbounded C (a grey one).
pub(super) struct IntervalEnd {
    pub value: f64,
    pub text: String,
    pub face: bool,
}

/// An interval of one coordinate (shaded) with a path over time in it.
pub(super) struct IntervalPanel<'a> {
    /// The title.
    pub title: &'a str,
    /// The label of the state's axis.
    pub ylabel: &'a str,
    /// The ends: lower, upper.
    pub ends: [IntervalEnd; 2],
    /// The time axis.
    pub times: (f64, f64),
    /// `(t, x(t))`.
    pub orbit: Option<Vec<(f64, f64)>>,
    /// The legend's name of the path.
    pub orbit_label: &'a str,
}

impl Plot for IntervalPanel<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let [lo, hi] = &self.ends;
        let (t0, t1) = self.times;
        let w = hi.value - lo.value;
        let mut c = chart(
            root,
            s,
            self.title,
            (t0, t1),
            (lo.value - 0.25 * w, hi.value + 0.25 * w),
            "time t [time]",
            self.ylabel,
        )?;
        c.draw_series(std::iter::once(Rectangle::new(
            [(t0, lo.value), (t1, hi.value)],
            RGBColor(0, 114, 178).mix(0.08).filled(),
        )))?;
        for (end, up) in [(hi, true), (lo, false)] {
            let style = if end.face {
                s.line(BLACK, 1.6)
            } else {
                s.line(OPEN_SIDE, 1.0)
            };
            c.draw_series(std::iter::once(PathElement::new(
                vec![(t0, end.value), (t1, end.value)],
                style,
            )))?;
            let dy = if up { 0.09 * w } else { -0.09 * w };
            c.draw_series(std::iter::once(Text::new(
                end.text.clone(),
                (t0 + 0.01 * (t1 - t0), end.value + dy),
                s.text(13.0).pos(Pos::new(HPos::Left, VPos::Center)),
            )))?;
        }
        if let Some(pts) = &self.orbit {
            draw_thick(&mut c, pts, ORBIT, 2.6, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label(self.orbit_label)
                .legend(legend_line(ORBIT, s.px(3.0)));
            legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    }
}
