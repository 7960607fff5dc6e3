//! The linear programs of a fit: the least-absolute-deviations estimate, and the exact range of
//! each parameter over the polyhedron of parameters consistent with the data.
//!
//! Parameters are laid out flat: `p = [k_1..k_n, mu+_1..mu+_N, mu-_1..mu-_N]`. The force on
//! block `b` at sample `i` is linear in the stiffnesses, `F_b = k_(b-1) d_(b-1) - k_b d_b`
//! (theory §2, `d_l = L_l - (X_(l+1) - X_l)`), and a position error of at most `e` on every
//! `X` changes it by at most `2 e (k_(b-1) + k_b)`, linear too. Every condition of the model is
//! therefore a homogeneous linear inequality in `p`: the consistent parameters form a cone
//! (the scale invariance), cut by the fixed parameters.

use super::data::FitData;
use crate::error::{Error, Result};
use crate::optimal::solver::{Highs, SolveStatus};
use highs::{RowProblem, Sense};

/// Index of `k_l` (0-based link).
pub fn k_index(l: usize) -> usize {
    l
}

/// Index of `mu+_b` (0-based block) for `nb` blocks.
pub fn forward_index(nb: usize, b: usize) -> usize {
    nb - 1 + b
}

/// Index of `mu-_b`.
pub fn backward_index(nb: usize, b: usize) -> usize {
    2 * nb - 1 + b
}

/// The stiffness indices around block `b` and the force's coefficients on them:
/// `F_b = a k_(b-1) + c k_b` (a missing link has no index).
fn force(data: &FitData, i: usize, b: usize) -> [(Option<usize>, f64); 2] {
    let nb = data.blocks();
    let prev = (b > 0).then(|| (Some(k_index(b - 1)), data.compression(i, b - 1)));
    let next = (b + 1 < nb).then(|| (Some(k_index(b)), -data.compression(i, b)));
    [prev.unwrap_or((None, 0.0)), next.unwrap_or((None, 0.0))]
}

/// A homogeneous row `sum_j a_j p_j <= 0`.
pub type Row = Vec<(usize, f64)>;

/// `mu >= a k_prev + c k_next` (`upper = false`) or `mu <= ...` (`upper = true`), as a row.
fn mu_row(f: &[(Option<usize>, f64); 2], point: [f64; 2], mu: usize, upper: bool) -> Row {
    let s = if upper { -1.0 } else { 1.0 };
    let mut row = vec![(mu, -s)];
    for (j, (idx, _)) in f.iter().enumerate() {
        if let Some(idx) = idx {
            row.push((*idx, s * point[j]));
        }
    }
    row
}

/// What the data say, as rows: per block, `mu+ >= F - D` and `mu- >= -F - D` at every sample
/// kept, `mu+ <= F + D` where it slides forward and `mu- <= -F + D` where it slides backward,
/// `D = delta (k_(b-1) + k_b)`. Within each block and kind only the vertices of the convex hull
/// of the coefficient points are kept: a linear function's extremes over a set are at them, so
/// the polyhedron is the same.
pub fn consistency_rows(
    data: &FitData,
    sliding: &[Vec<i8>],
    keep: &[bool],
    delta: f64,
) -> Vec<Row> {
    let nb = data.blocks();
    let mut rows = Vec::new();
    for b in 0..nb {
        // Four groups of points: (mu index, upper, points).
        let mut groups: [(usize, bool, Vec<[f64; 2]>); 4] = [
            (forward_index(nb, b), false, Vec::new()),
            (forward_index(nb, b), true, Vec::new()),
            (backward_index(nb, b), false, Vec::new()),
            (backward_index(nb, b), true, Vec::new()),
        ];
        let mut template = None;
        for i in (0..data.samples()).filter(|&i| keep[i]) {
            let f = force(data, i, b);
            let (a, c) = (f[0].1, f[1].1);
            // Each missing link's coordinate stays 0.
            let (dp, dn) = (
                if f[0].0.is_some() { delta } else { 0.0 },
                if f[1].0.is_some() { delta } else { 0.0 },
            );
            groups[0].2.push([a - dp, c - dn]);
            groups[2].2.push([-a - dp, -c - dn]);
            if sliding[i][b] > 0 {
                groups[1].2.push([a + dp, c + dn]);
            }
            if sliding[i][b] < 0 {
                groups[3].2.push([-a + dp, -c + dn]);
            }
            template = Some(f);
        }
        let Some(f) = template else { continue };
        for (mu, upper, pts) in &groups {
            for v in hull(pts) {
                rows.push(mu_row(&f, pts[v], *mu, *upper));
            }
        }
    }
    rows
}

/// Indices of the vertices of the convex hull of `pts` (Andrew's monotone chain; collinear
/// points give the two ends, one distinct point itself).
fn hull(pts: &[[f64; 2]]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    idx.sort_by(|&a, &b| {
        pts[a][0]
            .total_cmp(&pts[b][0])
            .then(pts[a][1].total_cmp(&pts[b][1]))
    });
    idx.dedup_by(|a, b| pts[*a] == pts[*b]);
    if idx.len() <= 2 {
        return idx;
    }
    let cross = |o: usize, a: usize, b: usize| {
        (pts[a][0] - pts[o][0]) * (pts[b][1] - pts[o][1])
            - (pts[a][1] - pts[o][1]) * (pts[b][0] - pts[o][0])
    };
    let mut h: Vec<usize> = Vec::with_capacity(2 * idx.len());
    for pass in 0..2 {
        let start = h.len();
        let iter: Box<dyn Iterator<Item = &usize>> = if pass == 0 {
            Box::new(idx.iter())
        } else {
            Box::new(idx.iter().rev())
        };
        for &p in iter {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], p) <= 0.0 {
                h.pop();
            }
            h.push(p);
        }
        h.pop();
    }
    h.sort_unstable();
    h.dedup();
    h
}

/// A fresh LP with one column per parameter (`>= 0`, or fixed), the rows, and `objective`
/// on the columns; tight tolerances (the data may be exact).
fn model(
    np: usize,
    rows: &[Row],
    fixed: &[(usize, f64)],
    objective: &[(usize, f64)],
    cap: Option<(usize, f64)>,
    sense: Sense,
    what: &str,
) -> Result<Highs> {
    let mut pb = RowProblem::default();
    let cols: Vec<_> = (0..np)
        .map(|j| {
            let cost = objective.iter().find(|(i, _)| *i == j).map_or(0.0, |o| o.1);
            match (fixed.iter().find(|(i, _)| *i == j), cap) {
                (Some(&(_, v)), _) => pb.add_column(cost, v..=v),
                (None, Some((c, hi))) if c == j => pb.add_column(cost, 0.0..=hi),
                _ => pb.add_column(cost, 0.0..),
            }
        })
        .collect();
    for r in rows {
        pb.add_row(..=0.0, r.iter().map(|&(j, a)| (cols[j], a)));
    }
    let mut h = Highs::new(pb, sense, what)?;
    tight(&mut h)?;
    Ok(h)
}

fn tight(h: &mut Highs) -> Result<()> {
    h.option("primal_feasibility_tolerance", 1e-10)?;
    h.option("dual_feasibility_tolerance", 1e-10)
}

/// The range of each parameter over `{p >= 0 : rows, fixed}`: per parameter `[lo, hi]` with
/// `hi = None` when unbounded; `Ok(None)` when no parameter vector satisfies them.
/// `unbounded` comes from [`unbounded_above`].
pub fn ranges(
    np: usize,
    rows: &[Row],
    fixed: &[(usize, f64)],
    unbounded: &[bool],
) -> Result<Option<Vec<[Option<f64>; 2]>>> {
    let mut out = Vec::with_capacity(np);
    for j in 0..np {
        crate::progress::check()?;
        let mut lo = model(np, rows, fixed, &[(j, 1.0)], None, Sense::Minimise, "fit")?;
        let a = lo.solve()?;
        match a.status {
            SolveStatus::Optimal => {}
            SolveStatus::Infeasible => return Ok(None),
            SolveStatus::TimeLimit { .. } => {
                return Err(Error::Numerical("fit: an interval LP stopped early".into()))
            }
        }
        let hi = if unbounded[j] {
            None
        } else {
            let mut hi = model(np, rows, fixed, &[(j, 1.0)], None, Sense::Maximise, "fit")?;
            let b = hi.solve()?;
            if b.status != SolveStatus::Optimal {
                return Err(Error::Numerical(format!(
                    "fit: the maximum of parameter {j} ended {:?}",
                    b.status
                )));
            }
            Some(b.objective)
        };
        out.push([Some(a.objective.max(0.0)), hi]);
    }
    Ok(Some(out))
}

/// Per parameter, whether the data leave it unbounded above: whether the cone of the rows
/// holds a direction with the fixed parameters at 0 and this one positive (the recession cone
/// of the consistent set; exact, one LP per parameter).
pub fn unbounded_above(np: usize, rows: &[Row], fixed: &[(usize, f64)]) -> Result<Vec<bool>> {
    let zero: Vec<(usize, f64)> = fixed.iter().map(|&(j, _)| (j, 0.0)).collect();
    (0..np)
        .map(|j| {
            if zero.iter().any(|&(f, _)| f == j) {
                return Ok(false);
            }
            let mut h = model(
                np,
                rows,
                &zero,
                &[(j, 1.0)],
                Some((j, 1.0)),
                Sense::Maximise,
                "fit: recession cone",
            )?;
            let a = h.solve()?;
            Ok(a.status == SolveStatus::Optimal && a.objective > 0.5)
        })
        .collect()
}

/// The least-absolute-deviations estimate: minimises the sum of `|F - mu+|` over the samples
/// sliding forward, of `|-F - mu-|` over those sliding backward, and of the excesses
/// `max(0, F - mu+)`, `max(0, -F - mu-)` over every sample (force units). Returns the
/// parameters and the objective.
pub fn lad(data: &FitData, sliding: &[Vec<i8>], fixed: &[(usize, f64)]) -> Result<(Vec<f64>, f64)> {
    let nb = data.blocks();
    let np = 3 * nb - 1;
    let mut pb = RowProblem::default();
    let cols: Vec<_> = (0..np)
        .map(|j| match fixed.iter().find(|(i, _)| *i == j) {
            Some(&(_, v)) => pb.add_column(0.0, v..=v),
            None => pb.add_column(0.0, 0.0..),
        })
        .collect();
    for i in 0..data.samples() {
        for b in 0..nb {
            let f = force(data, i, b);
            let terms = |s: f64| {
                f.iter()
                    .filter_map(move |(idx, a)| idx.map(|j| (j, s * a)))
                    .collect::<Vec<_>>()
            };
            for (s, mu, dir) in [
                (1.0, forward_index(nb, b), 1i8),
                (-1.0, backward_index(nb, b), -1i8),
            ] {
                // s F - mu = r+ - r- (sliding that way) or s F - mu <= e (otherwise).
                let mut row: Vec<_> = terms(s).into_iter().map(|(j, a)| (cols[j], a)).collect();
                row.push((cols[mu], -1.0));
                let e = pb.add_column(1.0, 0.0..);
                row.push((e, -1.0));
                if sliding[i][b] == dir {
                    let e2 = pb.add_column(1.0, 0.0..);
                    row.push((e2, 1.0));
                    pb.add_row(0.0..=0.0, row);
                } else {
                    pb.add_row(..=0.0, row);
                }
            }
        }
    }
    let mut h = Highs::new(pb, Sense::Minimise, "fit: least absolute deviations")?;
    tight(&mut h)?;
    let a = h.solve()?;
    match a.status {
        SolveStatus::Optimal => Ok((a.columns[..np].to_vec(), a.objective)),
        SolveStatus::Infeasible => Err(Error::Infeasible(
            "fit: the least-absolute-deviations LP has no solution".into(),
        )),
        SolveStatus::TimeLimit { .. } => Err(Error::Numerical(
            "fit: the least-absolute-deviations LP stopped early".into(),
        )),
    }
}

/// Per sample and block, the residual of `p` in length units: `|F - mu|` where the block
/// slides, the excess of `F` over its thresholds elsewhere, divided by `k_(b-1) + k_b`.
pub fn residuals(data: &FitData, sliding: &[Vec<i8>], p: &[f64]) -> Vec<Vec<f64>> {
    let nb = data.blocks();
    (0..data.samples())
        .map(|i| {
            (0..nb)
                .map(|b| {
                    let f = force(data, i, b);
                    let (mut fv, mut w) = (0.0, 0.0);
                    for (idx, a) in f {
                        if let Some(j) = idx {
                            fv += a * p[j];
                            w += p[j];
                        }
                    }
                    let (mf, mb) = (p[forward_index(nb, b)], p[backward_index(nb, b)]);
                    let r = match sliding[i][b] {
                        1 => (fv - mf).abs().max(-fv - mb),
                        -1 => (fv + mb).abs().max(fv - mf),
                        _ => (fv - mf).max(-fv - mb).max(0.0),
                    };
                    r / w.max(f64::MIN_POSITIVE)
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hull_keeps_the_extreme_points() {
        let pts = [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.5, 0.1],
            [0.0, 1.0],
            [0.2, 0.2],
            [1.0, 1.0],
        ];
        assert_eq!(hull(&pts), vec![0, 1, 3, 5]);
        // Collinear (one link): the two ends.
        let pts = [[0.3, 0.0], [-1.0, 0.0], [2.0, 0.0], [0.0, 0.0]];
        assert_eq!(hull(&pts), vec![1, 2]);
        assert_eq!(hull(&[[1.0, 1.0], [1.0, 1.0]]), vec![0]);
    }
}
