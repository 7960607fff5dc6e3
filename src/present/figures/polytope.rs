//! Figure `polytope`: the polytope C (an interval, a polygon with labelled faces, or pairwise
//! projections) with a periodic orbit in it.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use crate::error::{Error, Result};
use crate::integrate::Trajectory;
use crate::model::Crawler;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Projection of C onto the link forces `(x_i, x_j)`, `i < j` (0-based): the hexagon
/// `{ a in I_1, b - a in I_2, b in -I_3 }` where `I_1`, `I_2`, `I_3` are the ranges of the summed
/// increments `-F` of the blocks `1..=i+1`, `i+2..=j+1` and `j+2..=N` (paths view of
/// `model::polytope`: the three groups move independently).
#[derive(Debug, Clone, PartialEq)]
pub struct Projection {
    /// Vertices of the polygon, counter-clockwise.
    pub vertices: Vec<(f64, f64)>,
    /// The edges of positive length among the six bounding lines (redundant faces have none).
    pub edges: Vec<Edge>,
}

/// An edge of a projection of C.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// The face: `b+` (block `b` slides forward), `b−`, or a group `1–2+`.
    pub label: String,
    /// One end.
    pub from: (f64, f64),
    /// The other end.
    pub to: (f64, f64),
    /// Unit outer normal.
    pub normal: (f64, f64),
}

pub(super) fn group_label(lo: usize, hi: usize, sign: char) -> String {
    if lo == hi {
        format!("{lo}{sign}")
    } else {
        format!("{lo}–{hi}{sign}")
    }
}

/// The projection of C onto `(x_i, x_j)` (0-based links, `i < j`), with face labels: `b+` is
/// block `b` sliding forward (`F_b = mu_b^+`), `b−` backward; a group `1–2+` slides together.
pub fn projection(crawler: &Crawler, i: usize, j: usize) -> Projection {
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    let nb = crawler.blocks();
    let sum = |r: std::ops::Range<usize>| -> (f64, f64) {
        (
            -r.clone().map(|b| mp[b]).sum::<f64>(),
            r.map(|b| mm[b]).sum::<f64>(),
        )
    };
    let (lo1, hi1) = sum(0..i + 1);
    let (lo2, hi2) = sum(i + 1..j + 1);
    let (lo3, hi3) = sum(j + 1..nb);
    // Lines as (normal, offset, label): normal . (a, b) <= offset.
    let lines = [
        ((1.0, 0.0), hi1, group_label(1, i + 1, '−')),
        ((-1.0, 0.0), -lo1, group_label(1, i + 1, '+')),
        ((-1.0, 1.0), hi2, group_label(i + 2, j + 1, '−')),
        ((1.0, -1.0), -lo2, group_label(i + 2, j + 1, '+')),
        ((0.0, 1.0), -lo3, group_label(j + 2, nb, '+')),
        ((0.0, -1.0), hi3, group_label(j + 2, nb, '−')),
    ];
    let mut poly = vec![(lo1, -hi3), (hi1, -hi3), (hi1, -lo3), (lo1, -lo3)];
    for &((na, nbv), off, _) in &lines[2..4] {
        poly = clip(&poly, na, nbv, off);
    }
    let scale = hi1 - lo1 + hi3 - lo3;
    let mut edges = Vec::new();
    for ((na, nbv), off, label) in lines {
        let on: Vec<(f64, f64)> = poly
            .iter()
            .copied()
            .filter(|&(a, b)| (na * a + nbv * b - off).abs() <= 1e-9 * scale)
            .collect();
        if on.len() >= 2 {
            let (p, q) = (on[0], on[on.len() - 1]);
            if (p.0 - q.0).hypot(p.1 - q.1) > 1e-9 * scale {
                let norm = na.hypot(nbv);
                edges.push(Edge {
                    label,
                    from: p,
                    to: q,
                    normal: (na / norm, nbv / norm),
                });
            }
        }
    }
    Projection {
        vertices: poly,
        edges,
    }
}

/// Sutherland–Hodgman: the part of a convex polygon with `na a + nb b <= off`.
pub(super) fn clip(poly: &[(f64, f64)], na: f64, nb: f64, off: f64) -> Vec<(f64, f64)> {
    let f = |p: (f64, f64)| na * p.0 + nb * p.1 - off;
    let mut out = Vec::new();
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            let t = fp / (fp - fq);
            out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    out
}

/// Which pairs of links a figure of C shows: the polygon for two links, every pair up to four
/// links, consecutive pairs (at most six) beyond.
pub fn projection_pairs(links: usize) -> Vec<(usize, usize)> {
    if links <= 4 {
        let mut v = Vec::new();
        for i in 0..links {
            for j in i + 1..links {
                v.push((i, j));
            }
        }
        v
    } else {
        (0..links.min(7) - 1).map(|i| (i, i + 1)).collect()
    }
}

/// C with an optional trajectory in it.
pub struct InC<'a> {
    /// The crawler.
    pub crawler: &'a Crawler,
    /// The periodic orbit (recorded periods), if any.
    pub orbit: Option<&'a Trajectory>,
    /// The approach to the orbit from rest (states), drawn thin and grey under it.
    pub transient: Option<&'a [Vec<f64>]>,
}

impl InC<'_> {
    fn draw_interval<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let (mp, mm) = (self.crawler.mu_forward(), self.crawler.mu_backward());
        let (lo, hi) = ((-mp[0]).max(-mm[1]), mm[0].min(mp[1]));
        let label_hi = if mm[0] < mp[1] { "1−" } else { "2+" };
        let label_lo = if -mp[0] > -mm[1] { "1+" } else { "2−" };
        let (t0, t1) = match self.orbit {
            Some(o) => (o.t[0], *o.t.last().unwrap_or(&1.0)),
            None => (0.0, 1.0),
        };
        let w = hi - lo;
        let mut c = chart(
            root,
            s,
            "The state x(t) in C = [α, β] (one link)",
            (t0, t1),
            (lo - 0.25 * w, hi + 0.25 * w),
            "time t [time]",
            "link compression x₁ [force]",
        )?;
        c.draw_series(std::iter::once(Rectangle::new(
            [(t0, lo), (t1, hi)],
            RGBColor(0, 114, 178).mix(0.08).filled(),
        )))?;
        for (v, label, what) in [(hi, label_hi, "β"), (lo, label_lo, "α")] {
            c.draw_series(std::iter::once(PathElement::new(
                vec![(t0, v), (t1, v)],
                s.line(BLACK, 1.6),
            )))?;
            let dy = if v == hi { 0.09 * w } else { -0.09 * w };
            c.draw_series(std::iter::once(Text::new(
                format!("face {label}:  x₁ = {what} = {}", fmt_num(v)),
                (t0 + 0.01 * (t1 - t0), v + dy),
                s.text(13.0).pos(Pos::new(HPos::Left, VPos::Center)),
            )))?;
        }
        if let Some(o) = self.orbit {
            let pts: Vec<(f64, f64)> = o.t.iter().zip(&o.x).map(|(&t, x)| (t, x[0])).collect();
            draw_thick(&mut c, &pts, ORBIT, 2.6, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("x₁(t) on the periodic orbit")
                .legend(legend_line(ORBIT, s.px(3.0)));
            legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    }

    fn draw_pair<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        s: Sty,
        (i, j): (usize, usize),
        big: bool,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let p = projection(self.crawler, i, j);
        // Room around the polygon for the face labels (group labels such as 1–2+ are wide).
        let pad = if big { 0.18 } else { 0.3 };
        let xr = range_of(p.vertices.iter().map(|v| &v.0), pad);
        let yr = range_of(p.vertices.iter().map(|v| &v.1), pad);
        // Equal scales on both axes: widen the shorter range to the plot's aspect ratio.
        let (w, h) = area.dim_in_pixel();
        let (pw, ph) = (
            w as f64 - s.px(70.0 + 28.0) as f64,
            h as f64 - s.px(46.0 + 20.0 + 30.0) as f64,
        );
        let (sx, sy) = ((xr.1 - xr.0) / pw.max(1.0), (yr.1 - yr.0) / ph.max(1.0));
        let k = sx.max(sy);
        let (cx, cy) = ((xr.0 + xr.1) / 2.0, (yr.0 + yr.1) / 2.0);
        let xr = (cx - k * pw / 2.0, cx + k * pw / 2.0);
        let yr = (cy - k * ph / 2.0, cy + k * ph / 2.0);
        let title = if big {
            "The state x(t) in the polytope C (faces: block, sign)".to_string()
        } else {
            format!("C projected on (x{}, x{})", sub(i + 1), sub(j + 1))
        };
        let mut c = chart(
            area,
            s,
            &title,
            xr,
            yr,
            &format!("x{} [force]", sub(i + 1)),
            &format!("x{} [force]", sub(j + 1)),
        )?;
        let mut closed = p.vertices.clone();
        closed.push(p.vertices[0]);
        c.draw_series(std::iter::once(Polygon::new(
            p.vertices.clone(),
            RGBColor(0, 114, 178).mix(0.08).filled(),
        )))?;
        c.draw_series(std::iter::once(PathElement::new(
            closed,
            s.line(BLACK, 1.6),
        )))?;
        let gap = 0.035 * (xr.1 - xr.0);
        for e in &p.edges {
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
            c.draw_series(std::iter::once(Text::new(
                label.clone(),
                (m.0 + gap * na, m.1 + gap * nbv),
                s.text_c(if big { 15.0 } else { 14.0 }, RGBColor(60, 60, 60))
                    .pos(Pos::new(h, v)),
            )))?;
        }
        // The origin (unloaded crawler).
        c.draw_series(std::iter::once(Cross::new(
            (0.0, 0.0),
            s.px(4.0),
            s.line(RGBColor(120, 120, 120), 1.0),
        )))?;
        if let Some(tr) = self.transient.filter(|t| t.len() >= 2) {
            let pts: Vec<(f64, f64)> = tr.iter().map(|x| (x[i], x[j])).collect();
            draw_thick(&mut c, &pts, RGBColor(120, 120, 120), 1.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("transient from x = 0")
                .legend(legend_line(RGBColor(120, 120, 120), s.px(1.5)));
        }
        if let Some(o) = self.orbit {
            let pts: Vec<(f64, f64)> = dedup(o.x.iter().map(|x| (x[i], x[j])).collect());
            draw_thick(&mut c, &pts, ORBIT, 2.8, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("periodic orbit")
                .legend(legend_line(ORBIT, s.px(3.0)));
            c.draw_series(std::iter::once(Circle::new(
                pts[0],
                s.px(4.5),
                ORBIT.filled(),
            )))?
            .label("x(0)")
            .legend(|(x, y)| Circle::new((x + 11, y), 4, ORBIT.filled()));
            // Direction of travel: an arrow head in the middle of the longest segment.
            let longest = pts.windows(2).map(|w| (w[0], w[1])).max_by(|a, b| {
                let la = (a.1 .0 - a.0 .0).hypot(a.1 .1 - a.0 .1);
                let lb = (b.1 .0 - b.0 .0).hypot(b.1 .1 - b.0 .1);
                la.total_cmp(&lb)
            });
            if let Some((a, b)) = longest {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len = dx.hypot(dy);
                if len > 0.0 {
                    let size = 0.035 * (xr.1 - xr.0);
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
                    c.draw_series(std::iter::once(Polygon::new(
                        vec![tip, l, r],
                        ORBIT.filled(),
                    )))?;
                }
            }
            if big {
                legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
            }
        }
        Ok(())
    }
}

impl Plot for InC<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.crawler.links();
        if n == 1 {
            return self.draw_interval(root, s);
        }
        let pairs = projection_pairs(n);
        if pairs.len() == 1 {
            return self.draw_pair(root, s, pairs[0], true);
        }
        let cols = pairs.len().min(3);
        let rows = pairs.len().div_ceil(cols);
        let areas = root.split_evenly((rows, cols));
        for (area, &pair) in areas.iter().zip(&pairs) {
            self.draw_pair(area, s, pair, false)?;
        }
        Ok(())
    }
}

/// Figure `polytope`: C (interval, polygon with labelled faces, or pairwise projections) with
/// the periodic orbit of `orbit` highlighted over the `transient` that leads to it from rest
/// (states; not drawn for one link, whose figure has time on its axis).
pub fn polytope_figure(
    crawler: &Crawler,
    orbit: Option<&Trajectory>,
    transient: Option<&[Vec<f64>]>,
) -> Result<Figure> {
    if transient.is_some_and(|t| t.iter().any(|x| x.len() != crawler.links())) {
        return Err(Error::invalid(
            "transient",
            "a state of the wrong size",
            format!("one force per link ({})", crawler.links()),
        ));
    }
    if let Some(o) = orbit {
        check_trajectory(o)?;
        if o.x[0].len() != crawler.links() {
            return Err(Error::invalid(
                "trajectory",
                format!("{} link forces", o.x[0].len()),
                format!("the crawler has {} links", crawler.links()),
            ));
        }
    }
    let n = crawler.links();
    let pairs = projection_pairs(n);
    let size = match n {
        1 | 2 => (760, 640),
        _ => {
            let cols = pairs.len().min(3) as u32;
            let rows = pairs.len().div_ceil(3) as u32;
            (cols * 380, rows * 370)
        }
    };
    let what = match n {
        1 => "the interval C = [α, β] of the link force".to_string(),
        2 => "the polygon C in the plane of the link forces (x₁, x₂)".to_string(),
        _ if n <= 4 => "the projections of C on every pair of link forces".to_string(),
        _ => format!(
            "the projections of C on consecutive pairs of link forces (the first {})",
            pairs.len()
        ),
    };
    render(
        "polytope",
        format!(
            "The admissible spring forces: {what}. A face labelled b+ (b−) is where block b slides forward \
             (backward); a range such as 1–2+ is a group of blocks sliding together.{}",
            match (orbit.is_some(), transient.is_some() && crawler.links() > 1) {
                (true, true) => {
                    " Green: the periodic orbit x(t), dot at t = 0, arrow in the direction of travel; \
                     grey: the approach to it from rest (x = 0)."
                }
                (true, false) => {
                    " Green: the periodic orbit x(t), dot at t = 0, arrow in the direction of travel."
                }
                _ => "",
            }
        ),
        size,
        &InC {
            crawler,
            orbit,
            transient,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// v_m over directions (two links)
