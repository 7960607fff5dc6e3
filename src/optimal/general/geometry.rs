//! The geometry of a polyhedron `C = {x : <x*_j, x> <= c_j}` (unit normals) by linear programs
//! and exact enumeration: the Chebyshev centre (the paper's PLICQ is a non-empty interior),
//! boundedness, redundant faces, vertices with their active faces, and whether face weights
//! define `f1` uniquely (theory §11).
//!
//! The linear programs go through `crate::optimal::solver` and are posed in units of C's
//! scale `s = max_j |c_j|` (the state divided by `s`), so that HiGHS's absolute tolerances
//! (1e-9) are relative to C; every decision below uses the relative tolerance [`REL_TOL`].
//!
//! Cost in the number of faces `sigma` (at most [`crate::model::general::MAX_FACES`]): the
//! centre and boundedness are one LP each; redundancy is decided for most faces without an LP,
//! by a ray from the centre along the face's normal that leaves C through that face alone (a
//! point feasible for every other face and outside it: `O(sigma^2 n)` in all), and by one LP of
//! `sigma` rows for each face the rays leave undecided (duplicates, faces through a vertex, C
//! without interior). The vertex enumeration is the one exponential part: it tries the
//! `C(sigma, rank)` subsets of faces (exponential in the dimension), and is skipped beyond
//! [`MAX_VERTEX_SUBSETS`] of them (face weights are then refused, `reaction_weights`
//! accepted), except on a crawler's chain ([`GeneralProblem::as_chain`]), whose structure
//! decides what the vertices would
//! ([`ChainView::check_face_weights`](crate::model::ChainView::check_face_weights)), so a
//! chain of any length is accepted.

use crate::error::{Error, Result};
use crate::model::general::{dot, ControlSet, GeneralProblem, Polyhedron, Reward};
use crate::optimal::solver::{Highs, SolveStatus};
use highs::{RowProblem, Sense};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Relative tolerance of the geometric decisions (interior, redundancy, activity at a vertex,
/// independence of normals), relative to C's scale (or to 1 for unit normals).
pub const REL_TOL: f64 = 1e-9;

/// Most `n`-subsets of faces (or of the normals' rank) enumerated for the vertices: beyond, the
/// vertices are not listed and face weights cannot be checked (`reaction_weights` can).
pub const MAX_VERTEX_SUBSETS: u64 = 200_000;

/// A vertex of C (or, when the normals do not span the space, a minimal face, given by one of
/// its points).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Vertex {
    /// The point.
    pub point: Vec<f64>,
    /// The faces active there (1-based).
    pub active: Vec<usize>,
}

/// What [`analyze_polyhedron`] finds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Geometry {
    /// Dimension `n`.
    pub dim: usize,
    /// Number of faces `sigma`.
    pub faces: usize,
    /// Rank of the normals (`n`: C is pointed, its minimal faces are vertices).
    pub rank: usize,
    /// A Chebyshev centre: the centre of a largest ball in C.
    pub chebyshev_centre: Vec<f64>,
    /// Its radius (0: empty interior).
    pub chebyshev_radius: f64,
    /// The radius reached the LP's cap `2 s` (C contains balls at least that large: it is
    /// unbounded, since a bounded C has radius at most `max_j c_j`).
    pub radius_capped: bool,
    /// Whether C is bounded (its normals span the space and positively: a strictly positive
    /// `y` with `sum_j y_j x*_j = 0`).
    pub bounded: bool,
    /// Faces implied by the others (1-based; of duplicates the first is listed).
    pub redundant_faces: Vec<usize>,
    /// The vertices (minimal faces when `rank < dim`), `None` when more than
    /// [`MAX_VERTEX_SUBSETS`] subsets would be tried.
    pub vertices: Option<Vec<Vertex>>,
    /// The first vertex whose active normals are dependent (1-based index into `vertices`),
    /// where face weights would not define `f1` uniquely.
    pub degenerate_vertex: Option<usize>,
}

impl Geometry {
    /// Whether C has a non-empty interior (PLICQ).
    pub fn has_interior(&self, scale: f64) -> bool {
        self.chebyshev_radius > REL_TOL * scale
    }
}

/// Analyses C: LPs for the centre, boundedness and redundancy, and the vertex enumeration.
pub fn analyze_polyhedron(c: &Polyhedron) -> Result<Geometry> {
    let s = c.scale();
    let (centre, radius, capped) = chebyshev(c, s)?;
    let rank = rank(&c.normals);
    let bounded = rank == c.dim() && positively_dependent(c)?;
    let redundant_faces = redundant(c, s, &centre, radius)?;
    let vertices = vertices(c, s, rank);
    let degenerate_vertex = vertices
        .as_ref()
        .and_then(|vs| vs.iter().position(|v| v.active.len() > rank).map(|i| i + 1));
    Ok(Geometry {
        dim: c.dim(),
        faces: c.faces(),
        rank,
        chebyshev_centre: centre,
        chebyshev_radius: radius,
        radius_capped: capped,
        bounded,
        redundant_faces,
        vertices,
        degenerate_vertex,
    })
}

/// The checks of a problem that need C's geometry: a non-empty interior (PLICQ), a non-empty
/// polytope U with interior, and face weights well defined (the active normals at every vertex
/// independent, so that the reaction's multipliers are unique). Returns C's geometry.
pub fn check_problem(p: &GeneralProblem) -> Result<Geometry> {
    let g = analyze_polyhedron(&p.c)?;
    check_with(p, &g)?;
    Ok(g)
}

/// [`check_problem`] with C's geometry at hand.
pub fn check_with(p: &GeneralProblem, g: &Geometry) -> Result<()> {
    let s = p.c.scale();
    if !g.has_interior(s) {
        // A radius that is not 0 but within the LPs' tolerance of C's scale: C may have an
        // interior, too thin for its size to be told from none (C = [-1, 1] with faces at
        // +-1e9 beside: radius 1, scale 1e9); saying that C has none would contradict the
        // radius shown.
        let why = if g.chebyshev_radius > 0.0 {
            format!(
                "C must have a non-empty interior (the paper's PLICQ): its largest ball is \
                 within the geometry's tolerance ({REL_TOL:e}) of C's scale {s:e} (the largest \
                 |offset|), so an interior, if any, is too thin to be told from none; if C is \
                 not flat, bring its offsets within about 1e8 of each other"
            )
        } else {
            "C must have a non-empty interior (the paper's PLICQ)".to_string()
        };
        return Err(Error::invalid(
            "sweeping_process",
            format!("Chebyshev radius {:e}", g.chebyshev_radius),
            why,
        ));
    }
    if let crate::model::general::ControlSet::Polytope(u) = &p.control {
        let (_, r, _) = chebyshev(u, u.scale()).map_err(|e| match e {
            Error::Infeasible(_) => Error::invalid("control", "{G u <= h}", "U is empty"),
            other => other,
        })?;
        if r <= REL_TOL * u.scale() {
            return Err(Error::invalid(
                "control",
                format!("Chebyshev radius {r:e}"),
                "U must have a non-empty interior",
            ));
        }
    }
    if let Reward::FaceWeights(_) = p.reward {
        match (&g.vertices, g.degenerate_vertex) {
            // A crawler's chain: decided by its uniqueness condition, whatever N.
            (None, _) => match p.as_chain() {
                Some(chain) => chain.check_face_weights()?,
                None => {
                    return Err(Error::invalid(
                        "objective.face_weights",
                        format!("{} faces in dimension {}", g.faces, g.dim),
                        format!(
                            "cannot check that the weights are well defined (more than \
                             {MAX_VERTEX_SUBSETS} vertex candidates); use reaction_weights"
                        ),
                    ))
                }
            },
            (Some(vs), Some(k)) => {
                let v = &vs[k - 1];
                return Err(Error::invalid(
                    "objective.face_weights",
                    format!("vertex {k} = {:?}", v.point),
                    format!(
                        "are not well defined: the active normals there (faces {:?}) are \
                         linearly dependent, so the reaction's multipliers are not unique; \
                         use reaction_weights or remove a face",
                        v.active
                    ),
                ));
            }
            _ => {}
        }
    }
    Ok(())
}

/// A Chebyshev centre: `max r` s.t. `<x*_j, x> + r <= c_j`, `0 <= r <= 2 s` (the cap bounds the
/// LP when C is unbounded; a bounded C has `r <= max_j c_j`: sum the rows with the weights of a
/// positive dependence). Solved for `x / s`. Errors: C empty ([`Error::Infeasible`]).
pub(super) fn chebyshev(c: &Polyhedron, s: f64) -> Result<(Vec<f64>, f64, bool)> {
    let n = c.dim();
    let mut pb = RowProblem::default();
    let x: Vec<_> = (0..n)
        .map(|_| pb.add_column(0.0, f64::NEG_INFINITY..f64::INFINITY))
        .collect();
    let r = pb.add_column(1.0, 0.0..=2.0);
    for j in 0..c.faces() {
        let mut row: Vec<_> = x.iter().zip(&c.normals[j]).map(|(&x, &a)| (x, a)).collect();
        row.push((r, 1.0));
        pb.add_row(..=c.offsets[j] / s, row);
    }
    let a = Highs::new(pb, Sense::Maximise, "Chebyshev centre")?.solve()?;
    match a.status {
        SolveStatus::Optimal => {
            let radius = a.columns[n];
            Ok((
                a.columns[..n].iter().map(|v| v * s).collect(),
                radius * s,
                radius >= 2.0 * (1.0 - REL_TOL),
            ))
        }
        _ => Err(Error::Infeasible(
            "the polyhedron is empty (no x satisfies every face)".into(),
        )),
    }
}

/// Whether some `y >= t > 0` has `sum_j y_j x*_j = 0` (`max t`, `t <= y_j <= 1`).
fn positively_dependent(c: &Polyhedron) -> Result<bool> {
    let mut pb = RowProblem::default();
    let t = pb.add_column(1.0, 0.0..=1.0);
    let y: Vec<_> = (0..c.faces())
        .map(|_| pb.add_column(0.0, 0.0..=1.0))
        .collect();
    for &yj in &y {
        pb.add_row(0.0.., [(yj, 1.0), (t, -1.0)]);
    }
    for i in 0..c.dim() {
        let row: Vec<_> = y.iter().zip(&c.normals).map(|(&y, n)| (y, n[i])).collect();
        pb.add_row(0.0..=0.0, row);
    }
    let a = Highs::new(pb, Sense::Maximise, "boundedness of C")?.solve()?;
    Ok(a.status == SolveStatus::Optimal && a.columns[0] > REL_TOL)
}

/// Whether a ray from the interior point `centre` (at distance at least `radius > 0` from every
/// face) along `x*_j` shows face `j` needed: the point where it crosses the next face lies
/// outside face `j` by more than the LP's tolerance, within the cap `s` (see [`redundant`]),
/// so that LP's optimum would exceed `c_j` by more than [`REL_TOL`]`s`.
fn ray_shows_needed(c: &Polyhedron, s: f64, centre: &[f64], j: usize) -> bool {
    let nj = &c.normals[j];
    let own = c.offsets[j] - dot(nj, centre);
    let mut next = f64::INFINITY;
    for k in (0..c.faces()).filter(|&k| k != j) {
        let rate = dot(&c.normals[k], nj);
        if rate > 0.0 {
            next = next.min((c.offsets[k] - dot(&c.normals[k], centre)) / rate);
        }
    }
    (next - own).min(s) > 100.0 * REL_TOL * s
}

/// The faces implied by the others, tested in order against the faces not yet found redundant
/// (so of two equal faces only the first is listed): `max <x*_j, x>` over the others and
/// `<x*_j, x> <= c_j + s` (which bounds the LP) is at most `c_j`. The LP is skipped for a face
/// that a ray from the Chebyshev centre shows needed ([`ray_shows_needed`]; module docs).
fn redundant(c: &Polyhedron, s: f64, centre: &[f64], radius: f64) -> Result<Vec<usize>> {
    let n = c.dim();
    let mut removed = vec![false; c.faces()];
    for j in 0..c.faces() {
        if radius > REL_TOL * s && ray_shows_needed(c, s, centre, j) {
            continue;
        }
        let mut pb = RowProblem::default();
        let x: Vec<_> = (0..n)
            .map(|i| pb.add_column(c.normals[j][i], f64::NEG_INFINITY..f64::INFINITY))
            .collect();
        let row =
            |k: usize| -> Vec<_> { x.iter().zip(&c.normals[k]).map(|(&x, &a)| (x, a)).collect() };
        for k in (0..c.faces()).filter(|&k| k != j && !removed[k]) {
            pb.add_row(..=c.offsets[k] / s, row(k));
        }
        pb.add_row(..=c.offsets[j] / s + 1.0, row(j));
        let a = Highs::new(pb, Sense::Maximise, "redundant faces of C")?.solve()?;
        if a.status == SolveStatus::Optimal && a.objective <= c.offsets[j] / s + REL_TOL {
            removed[j] = true;
        }
    }
    Ok((0..c.faces())
        .filter(|&j| removed[j])
        .map(|j| j + 1)
        .collect())
}

/// The numerical rank of the normals (singular values above [`REL_TOL`] times the largest).
pub(crate) fn rank(rows: &[Vec<f64>]) -> usize {
    let (m, n) = (rows.len(), rows[0].len());
    let a = DMatrix::from_fn(m, n, |i, k| rows[i][k]);
    // A decomposition that fails counts every row (the vertices are then enumerated over
    // more subsets, each checked).
    let Some(sv) = crate::linalg::singular_values(&a) else {
        return m.min(n);
    };
    let top = sv.iter().fold(0.0_f64, |t, v| t.max(*v));
    sv.iter().filter(|v| **v > REL_TOL * top.max(1.0)).count()
}

/// `C(sigma, r)`, saturating.
fn binomial(sigma: usize, r: usize) -> u64 {
    let mut b: u64 = 1;
    for i in 0..r.min(sigma) {
        b = b.saturating_mul((sigma - i) as u64) / (i as u64 + 1);
    }
    if r > sigma {
        0
    } else {
        b
    }
}

/// The vertices of C, or with `rank < n` the minimal faces (each by the point nearest to the
/// origin within the span of the normals): every `rank`-subset of faces whose normals are
/// independent (in the span) gives a candidate, kept when it satisfies every face.
fn vertices(c: &Polyhedron, s: f64, rank: usize) -> Option<Vec<Vertex>> {
    let (sigma, n) = (c.faces(), c.dim());
    if rank == 0 || binomial(sigma, rank) > MAX_VERTEX_SUBSETS {
        return None;
    }
    // An orthonormal basis Q (n x rank) of the normals' span: rows of V^T of the SVD.
    let basis: DMatrix<f64> = if rank == n {
        DMatrix::identity(n, n)
    } else {
        let a = DMatrix::from_fn(sigma, n, |i, k| c.normals[i][k]);
        let svd = crate::linalg::svd(a, false, true)?;
        let vt = svd.v_t?;
        // Singular values are sorted in decreasing order by nalgebra.
        vt.rows(0, rank).transpose()
    };
    let reduced: Vec<DVector<f64>> = c
        .normals
        .iter()
        .map(|nj| basis.transpose() * DVector::from_column_slice(nj))
        .collect();
    let tol = REL_TOL * s;
    let mut out: Vec<Vertex> = Vec::new();
    let mut subset: Vec<usize> = (0..rank).collect();
    loop {
        let m = DMatrix::from_fn(rank, rank, |i, k| reduced[subset[i]][k]);
        let rhs = DVector::from_iterator(rank, subset.iter().map(|&j| c.offsets[j]));
        if m.determinant().abs() > REL_TOL {
            if let Some(y) = m.lu().solve(&rhs) {
                let x: Vec<f64> = (&basis * y).iter().copied().collect();
                let feasible = (0..sigma).all(|j| c.slack(j, &x) <= tol);
                let new = !out
                    .iter()
                    .any(|v| v.point.iter().zip(&x).all(|(a, b)| (a - b).abs() <= tol));
                if feasible && new {
                    let active = (0..sigma)
                        .filter(|&j| c.slack(j, &x).abs() <= tol)
                        .map(|j| j + 1)
                        .collect();
                    out.push(Vertex { point: x, active });
                }
            }
        }
        if !next_subset(&mut subset, sigma) {
            break;
        }
    }
    Some(out)
}

/// The next `k`-subset of `0..n` in lexicographic order; `false` after the last.
pub(crate) fn next_subset(s: &mut [usize], n: usize) -> bool {
    let k = s.len();
    let mut i = k;
    while i > 0 {
        i -= 1;
        if s[i] < n - k + i {
            s[i] += 1;
            for t in i + 1..k {
                s[t] = s[t - 1] + 1;
            }
            return true;
        }
    }
    false
}

/// A solver's control moved into U (unchanged when it lies in U): a MILP or LP holds `u in U`
/// only to its feasibility tolerance, and a phase's control `U_j / tau_j` divides that error by
/// its duration (measured: 2.3 outside a row of U at `tau` near `1e-8`), which the replay
/// refused ("lies outside U"). A box U clips each component; a polytope U takes the Euclidean
/// projection (the exact active-set method from U's Chebyshev centre, computed once into
/// `centre`), which moves the control, and so the replayed increment, by as little: the
/// replay's check of the states still measures the solver's answer.
pub(crate) fn into_u(
    control: &ControlSet,
    centre: &mut Option<Vec<f64>>,
    u: Vec<f64>,
) -> Result<Vec<f64>> {
    let poly = match control {
        ControlSet::Box { lower, upper } => {
            return Ok(u
                .iter()
                .zip(lower.iter().zip(upper))
                .map(|(v, (lo, hi))| v.clamp(*lo, *hi))
                .collect())
        }
        ControlSet::Polytope(poly) => poly,
    };
    if poly.violation(&u, 0.0).is_none() {
        return Ok(u);
    }
    if centre.is_none() {
        *centre = Some(chebyshev(poly, poly.scale())?.0);
    }
    let start = centre.as_deref().expect("set above");
    Ok(crate::sweep::PolyProjector::new(poly.clone())
        .project(start, &u)?
        .x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(rows: &[[f64; 2]], c: &[f64]) -> Polyhedron {
        Polyhedron::new(rows.iter().map(|r| r.to_vec()).collect(), c.to_vec(), "C").unwrap()
    }

    /// A solver's control outside U by its tolerance is moved into U: a box clips each
    /// component, a polytope takes the nearest point (here a triangle's edge and vertex), and
    /// a control inside U is kept as it is.
    #[test]
    fn a_control_outside_u_is_moved_to_the_nearest_point_of_u() {
        let boxed = ControlSet::Box {
            lower: vec![-1.0, 0.0],
            upper: vec![1.0, 2.0],
        };
        let mut centre = None;
        let u = into_u(&boxed, &mut centre, vec![1.0 + 1e-9, -3.0]).unwrap();
        assert_eq!(u, vec![1.0, 0.0]);
        // U: x <= 1, y <= 1, -x - y <= 1.
        let tri = ControlSet::Polytope(poly(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]],
            &[1.0, 1.0, 1.0],
        ));
        let inside = vec![0.25, -0.5];
        assert_eq!(into_u(&tri, &mut centre, inside.clone()).unwrap(), inside);
        assert!(centre.is_none(), "a control inside U needs no centre");
        // Beyond the edge x = 1 by 1e-7: its foot on the edge.
        let u = into_u(&tri, &mut centre, vec![1.0 + 1e-7, 0.3]).unwrap();
        assert!(
            (u[0] - 1.0).abs() <= 1e-15 && (u[1] - 0.3).abs() <= 1e-15,
            "{u:?}"
        );
        // Beyond the vertex (1, 1) in its normal cone: the vertex.
        let u = into_u(&tri, &mut centre, vec![1.5, 2.0]).unwrap();
        assert!(
            (u[0] - 1.0).abs() <= 1e-15 && (u[1] - 1.0).abs() <= 1e-15,
            "{u:?}"
        );
        // Beyond the slanted edge -x - y = 1: the foot of the perpendicular.
        let u = into_u(&tri, &mut centre, vec![-1.0, -1.0]).unwrap();
        assert!(
            (u[0] + 0.5).abs() <= 1e-14 && (u[1] + 0.5).abs() <= 1e-14,
            "{u:?}"
        );
    }

    #[test]
    fn a_triangle_with_a_redundant_face() {
        // x <= 1, y <= 1, -x - y <= 1, and x <= 2 (redundant).
        let c = poly(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0], [1.0, 0.0]],
            &[1.0, 1.0, 1.0, 2.0],
        );
        let g = analyze_polyhedron(&c).unwrap();
        assert!(g.bounded && g.rank == 2 && !g.radius_capped);
        assert_eq!(g.redundant_faces, vec![4]);
        let vs = g.vertices.unwrap();
        assert_eq!(vs.len(), 3);
        let has = |p: [f64; 2]| {
            vs.iter()
                .any(|v| (v.point[0] - p[0]).abs() < 1e-12 && (v.point[1] - p[1]).abs() < 1e-12)
        };
        assert!(has([1.0, 1.0]) && has([1.0, -2.0]) && has([-2.0, 1.0]));
        assert_eq!(g.degenerate_vertex, None);
        // Inradius of the triangle with legs 3: area / semiperimeter = 4.5 / (3 + 1.5 sqrt 2).
        let r = 4.5 / (3.0 + 1.5 * 2f64.sqrt());
        assert!(
            (g.chebyshev_radius - r).abs() < 1e-9,
            "{}",
            g.chebyshev_radius
        );
        // The centre is at distance r from every side.
        for j in 0..3 {
            assert!((c.slack(j, &g.chebyshev_centre) + r).abs() < 1e-9);
        }
    }

    #[test]
    fn duplicates_unbounded_sets_and_degenerate_vertices() {
        // A slab |x| <= 1 in the plane with a repeated face: unbounded, rank 1, minimal faces
        // are the two lines; the first copy of x <= 1 is redundant.
        let c = poly(&[[1.0, 0.0], [1.0, 0.0], [-1.0, 0.0]], &[1.0, 1.0, 1.0]);
        let g = analyze_polyhedron(&c).unwrap();
        assert!(!g.bounded && g.rank == 1 && !g.radius_capped);
        assert!((g.chebyshev_radius - 1.0).abs() < 1e-9);
        assert_eq!(g.redundant_faces, vec![1]);
        let vs = g.vertices.unwrap();
        assert_eq!(vs.len(), 2);
        // The line x = 1 has both copies active: a degenerate minimal face.
        assert_eq!(g.degenerate_vertex, Some(1));
        assert_eq!(vs[0].active, vec![1, 2]);
        // A square with a diagonal cut through a vertex: 3 faces active at (1, 1).
        let c = poly(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 1.0]],
            &[1.0, 1.0, 1.0, 1.0, 2.0],
        );
        let g = analyze_polyhedron(&c).unwrap();
        assert_eq!(g.redundant_faces, vec![5]);
        let k = g.degenerate_vertex.unwrap();
        assert_eq!(g.vertices.as_ref().unwrap()[k - 1].active, vec![1, 2, 5]);
        // An empty set and one without interior.
        let c = poly(&[[1.0, 0.0], [-1.0, 0.0]], &[-1.0, 0.0]);
        assert!(matches!(analyze_polyhedron(&c), Err(Error::Infeasible(_))));
        let c = poly(&[[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0]], &[0.0, 0.0, 1.0]);
        let g = analyze_polyhedron(&c).unwrap();
        assert!(!g.has_interior(1.0));
    }

    #[test]
    fn subsets_and_binomials() {
        let mut s = vec![0, 1];
        let mut count = 1;
        while next_subset(&mut s, 5) {
            count += 1;
        }
        assert_eq!(count, 10);
        assert_eq!(binomial(5, 2), 10);
        assert_eq!(binomial(100, 3), 161_700);
        assert_eq!(binomial(2, 3), 0);
    }
}
