//! The column families and row blocks of the general P_m ([`super::discrete::build`], module
//! docs there), one function each, in the order `build` adds them (the solvers' results depend
//! on that order).

use crate::model::general::{dot, ControlSet, GeneralCost, GeneralProblem};
use highs::{Col, RowProblem};

/// The big-M constants (module docs of [`super::discrete`]).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct BigM {
    /// `S_j`, the largest slack of face `j` over C.
    pub(super) slack: Vec<f64>,
    /// `M_mu` (with `h = 1`: a bound on the reaction rates `lambda_j`).
    pub(super) multiplier: f64,
}

/// Which form of P_m [`super::discrete::build`] makes.
#[derive(Clone, Copy)]
pub(super) enum Form<'a> {
    /// The MILP: a binary per step and face, big-M rows.
    Milp(&'a BigM),
    /// The LP of fixed complementarity branches: on branch `active[i][j]`, `s^i_j = 0` and
    /// `mu^i_j >= 0`, off it `mu^i_j = 0` and `s^i_j >= 0`, the slack being
    /// `s^i_j = c_j - <x*_j, x^(i+1)>`. The branches are column bounds ([`branch_bounds`],
    /// [`pair_bounds`]), which the local method changes between solves. A face's slack is a
    /// column of its own (`<x*_j, x^(i+1)> + s^i_j = c_j`), except for two opposite faces
    /// ([`opposite_faces`]): they share one value column `f = <x*_j, x^(i+1)>`, within
    /// `[-c_k, c_j]`, and one row, as a crawler's block has one force column between its two
    /// friction bounds, and one signed multiplier column ([`pair_multiplier`]), as the block
    /// has one displacement. Per step that is one row and two columns fewer a pair (three
    /// blocks: 10 columns and 5 rows a step, not 16 and 8), the same LP.
    Branches(&'a [Vec<bool>]),
}

/// The slack of face `j` at step `i` in a branch LP ([`Form::Branches`]): the value
/// `offset + sign * col`, with `col` its own slack column (`sign = 1`, `offset = 0`) or the
/// value column `f` of its pair of opposite faces (`c_j - f` for the pair's first face,
/// `c_k + f` for the second).
#[derive(Debug, Clone, Copy)]
pub(super) struct Slack {
    /// The column the slack is read from.
    pub(super) col: Col,
    /// `ds / d(col)`: `1` for a face's own slack, `-1` and `1` for a pair's first and second.
    pub(super) sign: f64,
    /// The slack where the column is 0.
    pub(super) offset: f64,
}

impl Slack {
    /// The slack's value in the solution `cols`.
    pub(super) fn value(&self, cols: &[f64]) -> f64 {
        self.offset + self.sign * cols[self.col.index()]
    }
}

/// Each face's opposite face, if C has one: `x*_k = -x*_j` exactly, with `c_j + c_k > 0` (C is
/// a slab of positive width between them, so no point lies on both). Each face is paired at
/// most once, with the first such face.
pub(super) fn opposite_faces(p: &GeneralProblem) -> Vec<Option<usize>> {
    let sigma = p.c.faces();
    let mut partner = vec![None; sigma];
    for j in 0..sigma {
        if partner[j].is_some() {
            continue;
        }
        let opposite = (j + 1..sigma).find(|&k| {
            partner[k].is_none()
                && p.c.offsets[j] + p.c.offsets[k] > 0.0
                && p.c.normals[k]
                    .iter()
                    .zip(&p.c.normals[j])
                    .all(|(a, b)| *a == -*b)
        });
        if let Some(k) = opposite {
            partner[j] = Some(k);
            partner[k] = Some(j);
        }
    }
    partner
}

/// The bounds of a pair's value column `f = <x*_j, x>` (`j < k` opposite faces, offsets `c_j`
/// and `c_k`) on branches `on_j`, `on_k`: `c_j` on face `j`, `-c_k` on face `k`, `[-c_k, c_j]`
/// off both. Both faces held at once is infeasible (the slab has positive width,
/// [`opposite_faces`]); `None` then, which the callers refuse before they build.
pub(super) fn pair_bounds((c_j, c_k): (f64, f64), on_j: bool, on_k: bool) -> Option<(f64, f64)> {
    match (on_j, on_k) {
        (true, true) => None,
        (true, false) => Some((c_j, c_j)),
        (false, true) => Some((-c_k, -c_k)),
        (false, false) => Some((-c_k, c_j)),
    }
}

/// Whether `active` holds both faces of a pair of opposite faces at some step (no point of C
/// does: that branch LP is infeasible).
pub(super) fn holds_a_pair(partner: &[Option<usize>], active: &[Vec<bool>]) -> bool {
    active.iter().any(|row| {
        partner
            .iter()
            .enumerate()
            .any(|(j, k)| k.is_some_and(|k| row[j] && row[k]))
    })
}

/// The bounds of `(mu^i_j, s^i_j)` on branch `active` (see [`Form::Branches`]).
pub(super) fn branch_bounds(active: bool) -> [(f64, f64); 2] {
    if active {
        [(0.0, f64::INFINITY), (0.0, 0.0)]
    } else {
        [(0.0, 0.0), (0.0, f64::INFINITY)]
    }
}

/// `R` of a quadratic cost (`None` for `f2 = 0`).
pub(super) fn cost_matrix(cost: &GeneralCost, m: usize) -> Option<Vec<Vec<f64>>> {
    match cost {
        GeneralCost::None => None,
        GeneralCost::Quadratic { weight } => Some(
            (0..m)
                .map(|i| (0..m).map(|k| if i == k { *weight } else { 0.0 }).collect())
                .collect(),
        ),
        GeneralCost::Matrix { matrix } => Some(matrix.clone()),
    }
}

/// The control columns `u^i`, step by step: within the box's bounds, or free for a polytope U
/// (whose rows [`add_control_rows`] adds).
pub(super) fn add_control_columns(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    mm: usize,
) -> Vec<Vec<Col>> {
    let free = || f64::NEG_INFINITY..f64::INFINITY;
    (0..mm)
        .map(|_| match &p.control {
            ControlSet::Box { lower, upper } => (0..p.controls())
                .map(|k| pb.add_column(0.0, lower[k]..=upper[k]))
                .collect(),
            ControlSet::Polytope(_) => (0..p.controls())
                .map(|_| pb.add_column(0.0, free()))
                .collect(),
        })
        .collect()
}

/// The order in which the MILP makes its per-face columns (multipliers, then binaries, all
/// before the rows) where (P) is a chain ([`GeneralProblem::as_chain`]): by class, every step's
/// forward faces (block by block), then every step's backward faces, the order of the
/// crawler's former MILP of its own. `None` for other problems: step by step, face by face,
/// each step's binaries made with its rows. HiGHS's search depends on the order, not only on
/// the model: on the four-block crawler's P_3 (`T = 10`, `mu = 1, 1.5`) the default order took
/// 24.9 s and the chain's 12.1 s (the former MILP 10.5 s; one run each; the side-by-side runs
/// with the former MILP are in the changelog).
pub(super) fn face_classes(p: &GeneralProblem) -> Option<Vec<Vec<usize>>> {
    p.as_chain().map(|view| {
        (0..2)
            .map(|side| view.faces.iter().map(|pair| pair[side]).collect())
            .collect()
    })
}

/// Per-face columns of `mm` steps made by `column(pb, i, j)` in the order of `classes` (each
/// class step by step, its faces in turn), returned per step and face (the binaries of a chain
/// are made so, all before the rows, multipliers first).
pub(super) fn per_face_columns(
    pb: &mut RowProblem,
    (mm, faces): (usize, usize),
    classes: &[Vec<usize>],
    mut column: impl FnMut(&mut RowProblem, usize, usize) -> Col,
) -> Vec<Vec<Col>> {
    let mut cols: Vec<Vec<Option<Col>>> = vec![vec![None; faces]; mm];
    for class in classes {
        for (i, row) in cols.iter_mut().enumerate() {
            for &j in class {
                row[j] = Some(column(pb, i, j));
            }
        }
    }
    cols.into_iter()
        .map(|row| {
            row.into_iter()
                .map(|c| c.expect("classes cover the faces"))
                .collect()
        })
        .collect()
}

/// The multiplier columns `mu^i_j` with the objective weights `w_j`: within `[0, M_mu]` for the
/// MILP (in the order of `classes`, [`face_classes`], if given), within the branch's bounds
/// ([`branch_bounds`]) for a branch LP, step by step, face by face, where two opposite faces
/// (`partner`, [`opposite_faces`]) share one signed column `nu = mu_j - mu_k`
/// ([`pair_multiplier`]): both faces' entries are that column.
pub(super) fn add_multiplier_columns(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    mm: usize,
    (form, classes): (Form<'_>, Option<&[Vec<usize>]>),
    partner: &[Option<usize>],
    w: &[f64],
) -> Vec<Vec<Col>> {
    let sigma = p.c.faces();
    let bm = match form {
        Form::Milp(bm) => bm,
        Form::Branches(b) => {
            return (0..mm)
                .map(|i| {
                    let mut row: Vec<Option<Col>> = vec![None; sigma];
                    for j in 0..sigma {
                        if row[j].is_some() {
                            continue;
                        }
                        row[j] = Some(match partner.get(j).copied().flatten() {
                            Some(k) => {
                                let (cost, lo, hi) =
                                    pair_multiplier((w[j], w[k]), b[i][j], b[i][k]);
                                let nu = pb.add_column(cost, lo..=hi);
                                row[k] = Some(nu);
                                nu
                            }
                            None => {
                                let (lo, hi) = branch_bounds(b[i][j])[0];
                                pb.add_column(w[j], lo..=hi)
                            }
                        });
                    }
                    row.into_iter()
                        .map(|c| c.expect("every face has its multiplier"))
                        .collect()
                })
                .collect();
        }
    };
    let all = [(0..sigma).collect::<Vec<_>>()];
    let classes = classes.unwrap_or(&all[..]);
    per_face_columns(pb, (mm, sigma), classes, |pb, _, j| {
        pb.add_column(w[j], 0.0..=bm.multiplier)
    })
}

/// The cost and bounds of a pair's signed multiplier column `nu = mu_j - mu_k` (`j < k`
/// opposite faces of weights `w_j`, `w_k`) on branches `on_j`, `on_k`: on face `j`,
/// `nu = mu_j >= 0` with cost `w_j`; on face `k`, `nu = -mu_k <= 0` with cost `-w_k`; off both
/// (or, refused before, on both), `nu = 0`. The dynamics see `nu x*_j = mu_j x*_j + mu_k x*_k`.
pub(super) fn pair_multiplier((w_j, w_k): (f64, f64), on_j: bool, on_k: bool) -> (f64, f64, f64) {
    match (on_j, on_k) {
        (true, false) => (w_j, 0.0, f64::INFINITY),
        (false, true) => (-w_k, f64::NEG_INFINITY, 0.0),
        _ => (0.0, 0.0, 0.0),
    }
}

/// `u^i in U` for a polytope U: `G u^i <= h` (a box U is in the columns' bounds).
pub(super) fn add_control_rows(pb: &mut RowProblem, p: &GeneralProblem, u_i: &[Col]) {
    if let ControlSet::Polytope(u) = &p.control {
        for k in 0..u.faces() {
            let row: Vec<_> = u_i
                .iter()
                .zip(&u.normals[k])
                .map(|(&c, &a)| (c, a))
                .collect();
            pb.add_row(..=u.offsets[k], row);
        }
    }
}

/// The catching-up step from `x^i` to `x^(i+1)` of step `h`, one row per state component:
/// `x^(i+1) - (I + h A) x^i - h B u^i + sum_j mu_j x*_j = h b` (a pair of opposite faces,
/// `partner`, by its signed column: `nu x*_j`).
pub(super) fn add_dynamics_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    h: f64,
    (x_i, x_next): (&[Col], &[Col]),
    (u_i, mu_i, partner): (&[Col], &[Col], &[Option<usize>]),
) {
    let n = p.states();
    for r in 0..n {
        let mut row = vec![(x_next[r], 1.0)];
        for k in 0..n {
            let a = -(if k == r { 1.0 } else { 0.0 }) - h * p.dynamics.a[r][k];
            if a != 0.0 {
                row.push((x_i[k], a));
            }
        }
        for k in 0..p.controls() {
            let b = p.dynamics.b[r][k];
            if b != 0.0 {
                row.push((u_i[k], -h * b));
            }
        }
        for j in 0..p.c.faces() {
            // A pair's second face: its signed column is in the row through the first.
            if partner.get(j).copied().flatten().is_some_and(|k| k < j) {
                continue;
            }
            let a = p.c.normals[j][r];
            if a != 0.0 {
                row.push((mu_i[j], a));
            }
        }
        let rhs = h * p.dynamics.drift[r];
        pb.add_row(rhs..=rhs, row);
    }
}

/// The complementarity of step `i` of a branch LP, face by face, at `x^(i+1)`
/// ([`Form::Branches`]): a slack column `s^i_j` with `<x*_j, x^(i+1)> + s^i_j = c_j`, or for
/// two opposite faces (`partner`, [`opposite_faces`]) one value column
/// `f = <x*_j, x^(i+1)>` within [`pair_bounds`]. Returns the step's slacks.
pub(super) fn add_branch_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    (active, partner): (&[bool], &[Option<usize>]),
    x_next: &[Col],
) -> Vec<Slack> {
    let sigma = p.c.faces();
    let mut slacks: Vec<Option<Slack>> = vec![None; sigma];
    for j in 0..sigma {
        if slacks[j].is_some() {
            continue;
        }
        let mut row: Vec<_> = x_next
            .iter()
            .zip(&p.c.normals[j])
            .map(|(&c, &a)| (c, a))
            .collect();
        let c = p.c.offsets[j];
        match partner[j] {
            Some(k) => {
                let cs = (c, p.c.offsets[k]);
                // Both held is refused before building; then the column is left free.
                let (lo, hi) = pair_bounds(cs, active[j], active[k])
                    .unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
                let f = pb.add_column(0.0, lo..=hi);
                row.push((f, -1.0));
                pb.add_row(0.0..=0.0, row);
                let slack = |sign, offset| Slack {
                    col: f,
                    sign,
                    offset,
                };
                slacks[j] = Some(slack(-1.0, cs.0));
                slacks[k] = Some(slack(1.0, cs.1));
            }
            None => {
                let (lo, hi) = branch_bounds(active[j])[1];
                let s = pb.add_column(0.0, lo..=hi);
                row.push((s, 1.0));
                pb.add_row(c..=c, row);
                slacks[j] = Some(Slack {
                    col: s,
                    sign: 1.0,
                    offset: 0.0,
                });
            }
        }
    }
    slacks
        .into_iter()
        .map(|s| s.expect("every face has its slack"))
        .collect()
}

/// The complementarity of step `i` of the MILP, face by face, at `x^(i+1)`: a binary `z^i_j`
/// (made here, or the step's row of `made`, [`face_classes`]) with `mu <= M_mu z`,
/// `c - <x*, x> <= S (1 - z)` and `<x*_j, x^(i+1)> <= c_j`. Returns the step's binaries.
pub(super) fn add_face_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    bm: &BigM,
    (x_next, mu_i): (&[Col], &[Col]),
    made: Option<&[Col]>,
) -> Vec<Col> {
    (0..p.c.faces())
        .map(|j| {
            let face: Vec<_> = x_next
                .iter()
                .zip(&p.c.normals[j])
                .map(|(&c, &a)| (c, a))
                .collect();
            let c = p.c.offsets[j];
            // mu <= M_mu z and c - <x*, x> <= S (1 - z), i.e. <x*, x> - S z >= c - S.
            let z = match made {
                Some(z) => z[j],
                None => pb.add_integer_column(0.0, 0..=1),
            };
            pb.add_row(..=0.0, [(mu_i[j], 1.0), (z, -bm.multiplier)]);
            let mut row = face.clone();
            row.push((z, -bm.slack[j]));
            pb.add_row(c - bm.slack[j]..=f64::INFINITY, row);
            pb.add_row(..=c, face);
            z
        })
        .collect()
}

/// The diagonal of `R` when `f2` is separable (`R` diagonal: a `quadratic` cost, or a diagonal
/// `matrix`): its outer approximation then cuts one epigraph per component, tangents of the
/// parabola `(r_k / 2) u_k^2` (as the crawler's per-link cost), far tighter than tangent planes
/// of the sum at the same points.
pub(super) fn separable(r: &[Vec<f64>]) -> Option<Vec<f64>> {
    let off_diagonal = r
        .iter()
        .enumerate()
        .any(|(i, row)| row.iter().enumerate().any(|(k, &v)| k != i && v != 0.0));
    (!off_diagonal).then(|| (0..r.len()).map(|k| r[k][k]).collect())
}

/// The distinct values of component `k` over the cut points (a separable cost's tangent
/// points on that component).
pub(super) fn component_points(cuts: &[Vec<f64>], k: usize) -> Vec<f64> {
    let mut v: Vec<f64> = cuts.iter().map(|u0| u0[k]).collect();
    v.sort_by(f64::total_cmp);
    let tol = 1e-12 * v.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
    v.dedup_by(|a, b| (*a - *b).abs() <= tol);
    v
}

/// One epigraph of a quadratic cost's outer approximation: its cuts `e >= a . u - c`, each as
/// `a` (per control component, its non-zero entries) and `c`.
pub(super) type Epigraph = Vec<(Vec<(usize, f64)>, f64)>;

/// The epigraphs of a quadratic cost's outer approximation at the points `cuts` (module docs of
/// [`super::discrete`]), for P_m's steps and the phase MILP's phases alike (none for `f2 = 0`):
/// one whose cuts are the tangent planes `e >= (R u0) . u - (1/2) u0^T R u0`, or for a separable
/// cost ([`separable`]) one per component `k` with `r_k != 0`, cut by the tangents
/// `e_k >= r_k v u_k - (r_k / 2) v^2` of its parabola at the points' components `v`.
pub(super) fn cost_epigraphs(p: &GeneralProblem, cuts: &[Vec<f64>]) -> Vec<Epigraph> {
    let Some(r) = cost_matrix(&p.cost, p.controls()) else {
        return Vec::new();
    };
    match separable(&r) {
        Some(d) => d
            .iter()
            .enumerate()
            .filter(|(_, &rk)| rk != 0.0)
            .map(|(k, &rk)| {
                component_points(cuts, k)
                    .into_iter()
                    .map(|v| (vec![(k, rk * v)], 0.5 * rk * v * v))
                    .collect()
            })
            .collect(),
        None => vec![cuts
            .iter()
            .map(|u0| {
                let ru0: Vec<f64> = r.iter().map(|row| dot(row, u0)).collect();
                let c = 0.5 * dot(u0, &ru0);
                (ru0.into_iter().enumerate().collect(), c)
            })
            .collect()],
    }
}

/// The outer approximation of a quadratic cost on P_m's steps ([`cost_epigraphs`]): per step
/// and epigraph a column `e` (objective `-h`) with its cuts `e - a . u^i >= -c`. Returns the
/// columns, per step and epigraph.
pub(super) fn add_cost_cuts(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    h: f64,
    us: &[Vec<Col>],
    cuts: &[Vec<f64>],
) -> Vec<Vec<Col>> {
    let epigraphs = cost_epigraphs(p, cuts);
    us.iter()
        .map(|u| {
            epigraphs
                .iter()
                .map(|cuts| {
                    let e = pb.add_column(-h, 0.0..);
                    for (a, c) in cuts {
                        let mut row = vec![(e, 1.0)];
                        row.extend(a.iter().map(|&(k, v)| (u[k], -v)));
                        pb.add_row(-c..=f64::INFINITY, row);
                    }
                    e
                })
                .collect()
        })
        .collect()
}

/// The least value of an epigraph's column at the control `u` that its cuts allow:
/// `max(0, max_cuts a . u - c)` (at most `f2`'s share, the cuts being below it).
pub(super) fn epigraph_floor(cuts: &Epigraph, u: &[f64]) -> f64 {
    cuts.iter().fold(0.0_f64, |m, (a, c)| {
        m.max(a.iter().map(|&(k, v)| v * u[k]).sum::<f64>() - c)
    })
}

/// `sum_i u^i = 0` under the zero-mean constraint, one row per control component.
pub(super) fn add_zero_mean_rows(pb: &mut RowProblem, p: &GeneralProblem, us: &[Vec<Col>]) {
    if p.zero_mean {
        for k in 0..p.controls() {
            let row: Vec<_> = us.iter().map(|u| (u[k], 1.0)).collect();
            pb.add_row(0.0..=0.0, row);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal `R` is separable (its diagonal), any off-diagonal entry makes it not; the
    /// tangent points of a component are its distinct values, sorted.
    #[test]
    fn separable_costs_and_their_tangent_points() {
        assert_eq!(
            separable(&[vec![0.1, 0.0], vec![0.0, 0.3]]),
            Some(vec![0.1, 0.3])
        );
        assert_eq!(separable(&[vec![1.0, 0.5], vec![0.5, 1.0]]), None);
        let cuts = [
            vec![1.0, 0.0],
            vec![-1.0, 0.0],
            vec![1.0, 2.0],
            vec![0.5, 0.0],
        ];
        assert_eq!(component_points(&cuts, 0), [-1.0, 0.5, 1.0]);
        assert_eq!(component_points(&cuts, 1), [0.0, 2.0]);
    }
}
