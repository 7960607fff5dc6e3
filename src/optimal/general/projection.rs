//! The projection of a polyhedron `C = {x : <x*_j, x> <= c_j}` (within an optional window, a
//! box that cuts an unbounded C) onto a pair of coordinates `(x_a, x_b)`: a convex polygon,
//! computed exactly by support linear programs (the figures of the general problem (P) draw
//! it; theory §11).
//!
//! The polygon is found by the recursive support method: the maximisers of the four axis
//! directions are vertices; for two consecutive vertices `p`, `q` (counter-clockwise) the LP in
//! the direction of the outer normal of `pq` either finds a point beyond the line `pq` (a new
//! vertex between them) or proves `pq` an edge. So `2 V` LPs (of `sigma` rows and `n` columns)
//! find the `V` vertices, with no sampling of directions. The LPs are posed in units of C's
//! scale, as [`super::geometry`]'s are.

use crate::error::{Error, Result};
use crate::model::general::Polyhedron;
use crate::optimal::solver::{Highs, SolveStatus};
use highs::{RowProblem, Sense};

/// Most vertices of a projected polygon (the LPs stop there; a polygon of more vertices is
/// drawn with these, a sub-polygon of it).
pub const MAX_PROJECTED_VERTICES: usize = 256;

/// A vertex of a projected polygon: the point of the plane and a point of C (within the
/// window) that projects onto it.
#[derive(Debug, Clone, PartialEq)]
pub struct ProjectedVertex {
    /// `(x_a, x_b)`.
    pub point: (f64, f64),
    /// The point of C it comes from (`n` components).
    pub lifted: Vec<f64>,
}

/// The checks of [`project_polyhedron`]'s arguments: two different coordinates of the `n`, and
/// a window of one finite interval `lo < hi` per coordinate.
fn check_projection(n: usize, window: Option<&[(f64, f64)]>, a: usize, b: usize) -> Result<()> {
    if a >= n || b >= n || a == b {
        return Err(Error::invalid(
            "projection",
            format!("({}, {})", a + 1, b + 1),
            format!("needs two different coordinates of the {n}"),
        ));
    }
    if let Some(w) = window {
        if w.len() != n
            || w.iter()
                .any(|(lo, hi)| !(lo.is_finite() && hi.is_finite() && lo < hi))
        {
            return Err(Error::invalid(
                "window",
                format!("{} intervals", w.len()),
                format!("needs one finite interval lo < hi per coordinate ({n})"),
            ));
        }
    }
    Ok(())
}

/// The support LPs of the projection of `C ∩ window` onto `(x_a, x_b)`, posed in units of
/// the scale `s` (C's, widened by the window's ends).
struct Support<'a> {
    c: &'a Polyhedron,
    window: Option<&'a [(f64, f64)]>,
    s: f64,
    a: usize,
    b: usize,
}

impl Support<'_> {
    /// The maximiser over `C ∩ window` of `d.0 x_a + d.1 x_b`, a vertex of the polygon with
    /// its point of C; an error when the LP has no optimum (C within the window empty, or
    /// unbounded without a window).
    fn at(&self, d: (f64, f64)) -> Result<ProjectedVertex> {
        let (c, window, s, a, b) = (self.c, self.window, self.s, self.a, self.b);
        let n = c.dim();
        let mut pb = RowProblem::default();
        let cols: Vec<_> = (0..n)
            .map(|k| {
                let cost = if k == a {
                    d.0
                } else if k == b {
                    d.1
                } else {
                    0.0
                };
                match window {
                    Some(w) => pb.add_column(cost, w[k].0 / s..=w[k].1 / s),
                    None => pb.add_column(cost, f64::NEG_INFINITY..f64::INFINITY),
                }
            })
            .collect();
        for j in 0..c.faces() {
            let row: Vec<_> = cols
                .iter()
                .zip(&c.normals[j])
                .map(|(&x, &v)| (x, v))
                .collect();
            pb.add_row(..=c.offsets[j] / s, row);
        }
        let ans = Highs::new(pb, Sense::Maximise, "projection of C")?.solve()?;
        match ans.status {
            SolveStatus::Optimal => {
                let lifted: Vec<f64> = ans.columns.iter().map(|v| v * s).collect();
                Ok(ProjectedVertex {
                    point: (lifted[a], lifted[b]),
                    lifted,
                })
            }
            _ => Err(Error::Infeasible(
                "projection of C: C within the window is empty".into(),
            )),
        }
    }
}

/// Whether `p` and `q` are the same point of the plane, to `tol` in each coordinate.
fn same(p: &ProjectedVertex, q: &ProjectedVertex, tol: f64) -> bool {
    (p.point.0 - q.point.0).abs() <= tol && (p.point.1 - q.point.1).abs() <= tol
}

/// Refines each side of `ring` until every side is an edge (module docs): the LP in the
/// direction of the side's outer normal either finds a vertex beyond it, inserted, or proves
/// it an edge; at most [`MAX_PROJECTED_VERTICES`] vertices.
fn refine_sides(ring: &mut Vec<ProjectedVertex>, support: &Support<'_>, tol: f64) -> Result<()> {
    let mut k = 0;
    while k < ring.len() && ring.len() > 1 {
        let (p, q) = (&ring[k], &ring[(k + 1) % ring.len()]);
        let (dx, dy) = (q.point.0 - p.point.0, q.point.1 - p.point.1);
        let len = dx.hypot(dy);
        if len <= tol || ring.len() >= MAX_PROJECTED_VERTICES {
            k += 1;
            continue;
        }
        let d = (dy / len, -dx / len);
        let v = support.at(d)?;
        let beyond = d.0 * (v.point.0 - p.point.0) + d.1 * (v.point.1 - p.point.1);
        if beyond > tol && !same(&v, p, tol) && !same(&v, q, tol) {
            ring.insert(k + 1, v);
        } else {
            k += 1;
        }
    }
    Ok(())
}

/// Removes the points of `ring` where the polygon does not turn (to `tol`): an axis direction
/// along an edge has the whole edge as maximisers, and the LP may return a point inside it.
fn drop_straight(ring: &mut Vec<ProjectedVertex>, tol: f64) {
    let mut k = 0;
    while ring.len() > 3 && k < ring.len() {
        let nv = ring.len();
        let (p, q, r) = (
            ring[(k + nv - 1) % nv].point,
            ring[k].point,
            ring[(k + 1) % nv].point,
        );
        let (u, v) = ((q.0 - p.0, q.1 - p.1), (r.0 - q.0, r.1 - q.1));
        let turn = u.0 * v.1 - u.1 * v.0;
        if turn <= tol * (u.0.hypot(u.1) + v.0.hypot(v.1)) {
            ring.remove(k);
        } else {
            k += 1;
        }
    }
}

/// The projection of `C ∩ window` onto `(x_a, x_b)` (`a != b`, 0-based): the polygon's
/// vertices counter-clockwise, each with a point of C above it. `window` is a box
/// `[lo_k, hi_k]` per coordinate (finite), needed when C is unbounded; `None` for a bounded C.
/// Errors: an empty `C ∩ window`, an unbounded LP (C unbounded and no window).
pub fn project_polyhedron(
    c: &Polyhedron,
    window: Option<&[(f64, f64)]>,
    a: usize,
    b: usize,
) -> Result<Vec<ProjectedVertex>> {
    check_projection(c.dim(), window, a, b)?;
    let s = window
        .map(|w| {
            w.iter()
                .fold(c.scale(), |m, (lo, hi)| m.max(lo.abs()).max(hi.abs()))
        })
        .unwrap_or_else(|| c.scale());
    let support = Support { c, window, s, a, b };
    let tol = 1e-9 * s;
    // The maximisers of +x_a, +x_b, -x_a, -x_b: counter-clockwise.
    let mut ring: Vec<ProjectedVertex> = Vec::new();
    for d in [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)] {
        let v = support.at(d)?;
        if !ring.iter().any(|p| same(p, &v, tol)) {
            ring.push(v);
        }
    }
    refine_sides(&mut ring, &support, tol)?;
    drop_straight(&mut ring, tol);
    Ok(ring)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cube_projects_to_a_square_and_an_octahedron_to_a_diamond() {
        let mut normals = Vec::new();
        for k in 0..3 {
            for sgn in [1.0, -1.0] {
                let mut r = vec![0.0; 3];
                r[k] = sgn;
                normals.push(r);
            }
        }
        let cube = Polyhedron::new(normals, vec![1.0; 6], "c").unwrap();
        let sq = project_polyhedron(&cube, None, 0, 2).unwrap();
        assert_eq!(sq.len(), 4);
        for v in &sq {
            assert!((v.point.0.abs() - 1.0).abs() < 1e-9 && (v.point.1.abs() - 1.0).abs() < 1e-9);
        }
        // Counter-clockwise: positive signed area 4.
        let area: f64 = (0..4)
            .map(|k| {
                let (p, q) = (sq[k].point, sq[(k + 1) % 4].point);
                p.0 * q.1 - p.1 * q.0
            })
            .sum::<f64>()
            / 2.0;
        assert!((area - 4.0).abs() < 1e-9, "{area}");
        // |x1| + |x2| + |x3| <= 1 onto (x1, x2): the diamond |x1| + |x2| <= 1.
        let mut normals = Vec::new();
        for s1 in [1.0, -1.0] {
            for s2 in [1.0, -1.0] {
                for s3 in [1.0, -1.0] {
                    normals.push(vec![s1, s2, s3]);
                }
            }
        }
        let oct = Polyhedron::new(normals, vec![1.0; 8], "c").unwrap();
        let d = project_polyhedron(&oct, None, 0, 1).unwrap();
        assert_eq!(d.len(), 4);
        for v in &d {
            assert!((v.point.0.abs() + v.point.1.abs() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn an_unbounded_set_needs_a_window_and_is_cut_by_it() {
        // The half-plane x1 <= 1 in the plane.
        let c = Polyhedron::new(vec![vec![1.0, 0.0]], vec![1.0], "c").unwrap();
        assert!(project_polyhedron(&c, None, 0, 1).is_err());
        let w = [(-2.0, 3.0), (-1.0, 1.0)];
        let p = project_polyhedron(&c, Some(&w), 0, 1).unwrap();
        let mut xs: Vec<(f64, f64)> = p.iter().map(|v| v.point).collect();
        xs.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let want = [(-2.0, -1.0), (-2.0, 1.0), (1.0, -1.0), (1.0, 1.0)];
        for (g, w) in xs.iter().zip(want) {
            assert!(
                (g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9,
                "{xs:?}"
            );
        }
        assert!(project_polyhedron(&c, Some(&w[..1]), 0, 1).is_err());
        assert!(project_polyhedron(&c, None, 0, 0).is_err());
    }
}
