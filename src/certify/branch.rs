//! The branch LP of a process (module docs of [`crate::certify`] and [`crate::certify::general`]),
//! one for (P) and for every instance of it: (P)'s LP on the process's own pieces, with the
//! durations fixed and the complementarity branch fixed so that every point of it is a process.
//! A crawler's is this LP on its instance of (P) (`certify::crawler_general`: the reacting
//! faces are its slipping blocks' faces, the biactive pairs its sticking blocks' faces).
//!
//! ```text
//! maximise   sum_{i,f} w_f L_{i,f}                                         (f2 = 0 only)
//! subject to x_(i+1) - (I + tau_i A) x_i - tau_i B u_i + sum_f L_{i,f} x*_f = tau_i b
//!              (dual q_i = -p_i)
//!            <x*_f, x_k> <= c_f at every knot, held as "=" where a reaction of the branch on
//!              the piece ending there (or, for a phase gait, starting there) is on f  (-xi_{k,f})
//!            u_i in U,  sum_i tau_i u_i = 0 (zero mean; omega),  cyclic: x_P = x_0
//!            L_{i,f} >= 0 on the faces reacting on piece i in this branch, absent elsewhere
//! ```
//!
//! On a P_m process `tau_i = h` and `L = mu` (the step of P_m, explicit in the drift); on a phase
//! gait `A = 0` and `L_{i,f} = tau_i lambda_{i,f}`. A biactive pair chosen to react becomes a
//! reacting face of its piece; relaxing it to both branches instead would admit reactions off
//! their face, and an optimum above every process.

use super::general_kkt::{GeneralRaw, GeneralStructure};
use crate::model::general::{ControlSet, GeneralCost, GeneralProblem};
use crate::optimal::solver::{Highs, SolveStatus};
use highs::{Col, RowProblem, Sense};
use std::collections::BTreeMap;

/// The branch LP of the process whose structure is `st`, the biactive pairs (the entries of
/// [`GeneralStructure::reacting`] without a reaction, in order) made to react where `choice`
/// says so: its optimum and HiGHS's dual solution in Theorem 2.2's signs (`lambda = 1`; `xi` on
/// the active faces of every knot, `rho` left empty). `None` for a cost `f2 != 0` (the branch
/// problem is then not an LP) or when HiGHS refuses the model or reports no optimum: the
/// branch LP is a cross-check of the certificate, never an error of it.
pub(crate) fn branch_lp(
    p: &GeneralProblem,
    st: &GeneralStructure,
    choice: &[bool],
) -> Option<(f64, GeneralRaw)> {
    if p.cost != GeneralCost::None {
        return None;
    }
    let reacts = reacting_faces(st, choice);
    let mut rows = Rows::default();
    let cols = Columns::add(&mut rows.pb, p, st, &reacts);
    let dyn_rows = rows.dynamics(p, st, &cols);
    let face_rows = rows.faces(p, st, &cols, &reacts);
    // A polytope U's rows (a box is the columns' bounds).
    if let ControlSet::Polytope(u) = &p.control {
        for us in &cols.u {
            for (g, &h) in u.normals.iter().zip(&u.offsets) {
                let c = us
                    .iter()
                    .zip(g)
                    .map(|(&c, &v)| (c.index(), (c, v)))
                    .collect();
                rows.add(f64::NEG_INFINITY, h, c);
            }
        }
    }
    let mean_rows: Vec<usize> = if p.zero_mean {
        (0..st.m)
            .map(|k| {
                let c = (0..st.steps)
                    .map(|i| (cols.u[i][k].index(), (cols.u[i][k], st.tau[i])))
                    .collect();
                rows.add(0.0, 0.0, c)
            })
            .collect()
    } else {
        Vec::new()
    };
    let (objective, y) = solve(rows.pb)?;
    // HiGHS's row duals y satisfy c = A^T y + (column duals) for either sense, so the
    // Lagrangian multiplier of "row = rhs" in the module's convention is y: q_i = y(dyn_i),
    // face dual = y(face); p = -q, xi = -(face dual), omega = y(mean).
    let p_adj = dyn_rows
        .iter()
        .map(|rows| rows.iter().map(|&r| -y[r]).collect())
        .collect();
    let xi = st
        .active
        .iter()
        .enumerate()
        .map(|(k, faces)| faces.iter().map(|&f| -y[face_rows[k][f]]).collect())
        .collect();
    Some((
        objective,
        GeneralRaw {
            lambda: 1.0,
            p: p_adj,
            xi,
            // Without the zero-mean constraint omega is 0 (module docs of `certify::general`).
            omega: if p.zero_mean {
                mean_rows.iter().map(|&r| y[r]).collect()
            } else {
                vec![0.0; st.m]
            },
            rho: Vec::new(),
        },
    ))
}

/// The rows of a branch LP as they are added, each given its index.
#[derive(Default)]
struct Rows {
    pb: RowProblem,
    count: usize,
}

impl Rows {
    /// Adds the row `lo <= sum coeffs <= hi` and returns its index.
    fn add(&mut self, lo: f64, hi: f64, coeffs: BTreeMap<usize, (Col, f64)>) -> usize {
        self.pb
            .add_row(lo..=hi, coeffs.into_values().collect::<Vec<_>>());
        self.count += 1;
        self.count - 1
    }

    /// The dynamics, one row per piece and state (a one-piece process's `x_1` is its `x_0`:
    /// the coefficients of a column met twice are summed); their indices per piece.
    fn dynamics(
        &mut self,
        p: &GeneralProblem,
        st: &GeneralStructure,
        cols: &Columns,
    ) -> Vec<Vec<usize>> {
        let (n, steps) = (st.n, st.steps);
        let d = &p.dynamics;
        let mut dyn_rows = vec![vec![0usize; n]; steps];
        for i in 0..steps {
            let tau = st.tau[i];
            let next = &cols.x[(i + 1) % steps];
            for r in 0..n {
                let mut c = BTreeMap::new();
                let mut put = |col: Col, v: f64| c.entry(col.index()).or_insert((col, 0.0)).1 += v;
                put(next[r], 1.0);
                for k in 0..n {
                    put(
                        cols.x[i][k],
                        -(f64::from(u8::from(k == r)) + tau * d.a[r][k]),
                    );
                }
                for (k, &u) in cols.u[i].iter().enumerate() {
                    put(u, -tau * d.b[r][k]);
                }
                for &(f, l) in &cols.l[i] {
                    put(l, p.c.normals[f][r]);
                }
                let rhs = tau * d.drift[r];
                dyn_rows[i][r] = self.add(rhs, rhs, c);
            }
        }
        dyn_rows
    }

    /// The faces of C at every knot, held as equalities where the branch `reacts` on them;
    /// their indices per knot and face.
    fn faces(
        &mut self,
        p: &GeneralProblem,
        st: &GeneralStructure,
        cols: &Columns,
        reacts: &[Vec<usize>],
    ) -> Vec<Vec<usize>> {
        let (n, steps) = (st.n, st.steps);
        let mut face_rows = vec![Vec::new(); steps];
        for k in 0..steps {
            let prev = (k + steps - 1) % steps;
            for f in 0..p.c.faces() {
                let held = reacts[prev].contains(&f) || (st.phase && reacts[k].contains(&f));
                let c: BTreeMap<_, _> = (0..n)
                    .map(|r| (cols.x[k][r].index(), (cols.x[k][r], p.c.normals[f][r])))
                    .collect();
                let cf = p.c.offsets[f];
                let lo = if held { cf } else { f64::NEG_INFINITY };
                face_rows[k].push(self.add(lo, cf, c));
            }
        }
        face_rows
    }
}

/// The branch LPs through one process, solved in (P)'s units of order one
/// ([`crate::optimal::general::Units`]: states in C's scale, controls in U's, time in the
/// time the fastest state crosses C or the period where that is shorter) and their optima converted back (`J = s_x J'`; the durations become
/// `tau / t_0`, the structure is otherwise the same). In the problem's own units HiGHS's
/// absolute tolerances failed them at short periods: the three-block crawler's phase
/// optimum with its period 1e-5 (and its rates 1e6) had no branch LP, where the same gait
/// at period 10 has all 8.
pub(crate) struct BranchLps {
    p: GeneralProblem,
    st: GeneralStructure,
    j_unit: f64,
}

impl BranchLps {
    /// The branch LPs of the process whose structure is `st` on `p`.
    pub(crate) fn new(p: &GeneralProblem, st: &GeneralStructure) -> Self {
        let units = crate::optimal::general::Units::of(p);
        let mut st = st.clone();
        st.tau = st.tau.iter().map(|t| t / units.time).collect();
        BranchLps {
            p: units.problem(p),
            st,
            j_unit: units.state,
        }
    }

    /// The optimum of the branch `choice` ([`branch_lp`]), in the problem's units.
    pub(crate) fn optimum(&self, choice: &[bool]) -> Option<f64> {
        branch_lp(&self.p, &self.st, choice).map(|(j, _)| j * self.j_unit)
    }
}

/// The columns of the largest branch LP through the process (states and controls per piece,
/// and every face that may react: all biactive pairs reacting), the size the budget of
/// [`super::records::best_branch`] counts, for (P) and its instances alike.
pub(crate) fn columns(st: &GeneralStructure) -> usize {
    st.steps * (st.n + st.m) + st.reacting.iter().map(Vec::len).sum::<usize>()
}

/// The faces reacting on each piece in the branch: those with a reaction, and the biactive
/// pairs `choice` picks (in the order of [`GeneralStructure::reacting`]).
fn reacting_faces(st: &GeneralStructure, choice: &[bool]) -> Vec<Vec<usize>> {
    let mut pick = choice.iter();
    st.reacting
        .iter()
        .map(|faces| {
            faces
                .iter()
                .filter(|&&(_, reacts)| reacts || pick.next().copied().unwrap_or(false))
                .map(|&(f, _)| f)
                .collect()
        })
        .collect()
}

/// The columns of a branch LP: the states `x_k` (free), the controls `u_i` (within a box's
/// bounds, or free for a polytope U) and the integrated reactions `L_{i,f} >= 0` of the
/// reacting faces (weighted `w_f` in the objective).
struct Columns {
    x: Vec<Vec<Col>>,
    u: Vec<Vec<Col>>,
    l: Vec<Vec<(usize, Col)>>,
}

impl Columns {
    fn add(
        pb: &mut RowProblem,
        p: &GeneralProblem,
        st: &GeneralStructure,
        reacts: &[Vec<usize>],
    ) -> Self {
        const INF: f64 = f64::INFINITY;
        let x = (0..st.steps)
            .map(|_| (0..st.n).map(|_| pb.add_column(0.0, -INF..=INF)).collect())
            .collect();
        let u = (0..st.steps)
            .map(|_| {
                (0..st.m)
                    .map(|k| match &p.control {
                        ControlSet::Box { lower, upper } => pb.add_column(0.0, lower[k]..=upper[k]),
                        ControlSet::Polytope(_) => pb.add_column(0.0, -INF..=INF),
                    })
                    .collect()
            })
            .collect();
        let l = reacts
            .iter()
            .map(|faces| {
                faces
                    .iter()
                    .map(|&f| (f, pb.add_column(st.w[f], 0.0..=INF)))
                    .collect()
            })
            .collect();
        Columns { x, u, l }
    }
}

/// Solves a branch LP (a maximisation) to tight tolerances: its optimum and row duals, or
/// `None` when HiGHS refuses the model or an option, fails, or reports no optimum.
fn solve(pb: RowProblem) -> Option<(f64, Vec<f64>)> {
    let mut model = Highs::new(pb, Sense::Maximise, "certify: the branch LP").ok()?;
    model.option("primal_feasibility_tolerance", 1e-10).ok()?;
    model.option("dual_feasibility_tolerance", 1e-10).ok()?;
    let solved = model.solve().ok()?;
    (solved.status == SolveStatus::Optimal).then_some((solved.objective, solved.row_duals))
}
