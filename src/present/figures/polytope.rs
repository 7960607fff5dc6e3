//! Figure `polytope`: the polytope C (an interval, a polygon with labelled faces, or pairwise
//! projections) with a periodic orbit in it.

use super::kit::*;
// The kit's alias, not the prelude's.
use super::kit::DrawResult;
use super::panel::{Edge, IntervalEnd, IntervalPanel, PairPanel, Projection};
use crate::error::{Error, Result};
use crate::integrate::Trajectory;
use crate::model::Crawler;
use plotters::coord::Shift;
use plotters::prelude::*;

pub(super) fn group_label(lo: usize, hi: usize, sign: char) -> String {
    if lo == hi {
        format!("{lo}{sign}")
    } else {
        format!("{lo}–{hi}{sign}")
    }
}

/// The projection of C onto `(x_i, x_j)` (0-based links, `i < j`), with face labels: `b+` is
/// block `b` sliding forward (`F_b = mu_b^+`), `b−` backward; a group `1–2+` slides together.
/// It is the hexagon `{ a in I_1, b - a in I_2, b in -I_3 }` where `I_1`, `I_2`, `I_3` are the
/// ranges of the summed increments `-F` of the blocks `1..=i+1`, `i+2..=j+1` and `j+2..=N`
/// (paths view of `model::polytope`: the three groups move independently).
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
        open_sides: Vec::new(),
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
    fn interval(&self) -> IntervalPanel<'static> {
        let (mp, mm) = (self.crawler.mu_forward(), self.crawler.mu_backward());
        let (lo, hi) = ((-mp[0]).max(-mm[1]), mm[0].min(mp[1]));
        let label_hi = if mm[0] < mp[1] { "1−" } else { "2+" };
        let label_lo = if -mp[0] > -mm[1] { "1+" } else { "2−" };
        let (t0, t1) = match self.orbit {
            Some(o) => (o.t[0], *o.t.last().unwrap_or(&1.0)),
            None => (0.0, 1.0),
        };
        let end = |v: f64, label: &str, what: &str| IntervalEnd {
            value: v,
            text: format!("face {label}:  x₁ = {what} = {}", fmt_num(v)),
            face: true,
        };
        IntervalPanel {
            title: "The state x(t) in C = [α, β] (one link)",
            ylabel: "link compression x₁ [force]",
            ends: [end(lo, label_lo, "α"), end(hi, label_hi, "β")],
            times: (t0, t1),
            orbit: self
                .orbit
                .map(|o| o.t.iter().zip(&o.x).map(|(&t, x)| (t, x[0])).collect()),
            orbit_label: "x₁(t) on the periodic orbit",
        }
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
        let title = if big {
            "The state x(t) in the polytope C (faces: block, sign)".to_string()
        } else {
            format!("C projected on (x{}, x{})", sub(i + 1), sub(j + 1))
        };
        PairPanel {
            proj: &p,
            title,
            axes: (
                format!("x{} [force]", sub(i + 1)),
                format!("x{} [force]", sub(j + 1)),
            ),
            big,
            transient: self
                .transient
                .map(|tr| tr.iter().map(|x| (x[i], x[j])).collect()),
            orbit: self
                .orbit
                .map(|o| o.x.iter().map(|x| (x[i], x[j])).collect()),
            orbit_label: "periodic orbit",
            origin: true,
            equal_scale: true,
            dots: &[],
        }
        .draw(area, s)
    }
}

impl Plot for InC<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.crawler.links();
        if n == 1 {
            return self.interval().draw(root, s);
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
