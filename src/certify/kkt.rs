//! A crawler process's combinatorial structure (active, held and biactive faces, slips, rates
//! at their bounds), its branch LPs, and the pieces of the multiplier LPs both certificates
//! share: the stages, the degenerate search's box and functional, the adjoint's columns and the
//! tight HiGHS solve (module docs of [`crate::certify`] for the mathematics). The multiplier LPs
//! themselves are the general problem's (`certify::general_kkt`), solved for a crawler on its
//! instance of (P) (`certify::crawler_general`).

use crate::certify::process::{d_tol, slip, Process, ProcessKind};
use crate::error::{Error, Result};
use crate::optimal::solver::{Highs, SolveStatus};
use crate::optimal::Cost;
use highs::{Col, RowProblem, Sense};

/// A face of C: block `b` (0-based) and side `s` (`+1`: `F_b <= mu_b^+`, outer normal `nu_b`;
/// `-1`: `-F_b <= mu_b^-`, outer normal `-nu_b`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FaceId {
    pub b: usize,
    pub s: i8,
}

/// The combinatorial data of a process: active faces, held faces, slips, biactive faces and
/// control bounds. Everything the KKT system needs besides the numbers.
pub(crate) struct Structure {
    pub n: usize,
    pub nb: usize,
    pub np: usize,
    /// Faces active at knot `j` (`j = 0..P`, knot `P` is knot 0).
    pub active: Vec<Vec<FaceId>>,
    /// Whether the face is held as an equality by a slipping block (then its multiplier in the
    /// branch LP has no sign).
    pub held: Vec<Vec<bool>>,
    /// Slack `c_f - <x*_f, x_j>` of each active face (for the complementarity residual).
    pub slack: Vec<Vec<f64>>,
    /// Slip direction of each block on each piece.
    pub slips: Vec<Vec<i8>>,
    /// Biactive (block, direction) pairs per piece: the block sticks but its face is active
    /// where slipping would need it (strong stationarity asks the relaxed sign condition).
    pub biactive: Vec<Vec<(usize, i8)>>,
    /// Control at its bound: `+1` upper, `-1` lower, `0` interior, per piece and link.
    pub bound: Vec<Vec<i8>>,
    /// `Df2(u_j)` per piece.
    pub grad_f2: Vec<Vec<f64>>,
    /// `k_l`.
    pub k: Vec<f64>,
    /// `Df2(u_j).u_j - f2(u_j)` per piece (the cost's part of the maximised Hamiltonian).
    pub cost_h: Vec<f64>,
}

/// The outer normal `x*_f` as (link, value) pairs (at most two).
pub(crate) fn normal(n: usize, f: FaceId) -> Vec<(usize, f64)> {
    let s = f64::from(f.s);
    let mut v = Vec::with_capacity(2);
    if f.b > 0 {
        v.push((f.b - 1, s));
    }
    if f.b < n {
        v.push((f.b, -s));
    }
    v
}

/// `K nu_b` as (link, value) pairs.
pub(crate) fn k_nu(n: usize, k: &[f64], b: usize) -> Vec<(usize, f64)> {
    normal(n, FaceId { b, s: 1 })
        .into_iter()
        .map(|(l, v)| (l, v * k[l]))
        .collect()
}

impl Structure {
    /// The structure of `p` at relative tolerance `tol` (faces relative to the crawler's state
    /// scale, displacements to [`d_tol`], controls to their bounds).
    pub fn of(p: &Process, tol: f64) -> Self {
        let c = &p.crawler;
        let (n, nb, np) = (c.links(), c.blocks(), p.durations.len());
        let dtol = d_tol(c, tol);
        let slips: Vec<Vec<i8>> = p
            .block_displacements
            .iter()
            .map(|d| d.iter().map(|&v| slip(v, dtol)).collect())
            .collect();
        let ActiveFaces {
            active,
            held,
            slack,
        } = active_faces(p, &slips, tol);
        let biactive = biactive_pairs(p.kind, &slips, &active, nb, np);
        let a = &p.problem.rate_bound;
        let bound = p
            .controls
            .iter()
            .map(|u| {
                (0..n)
                    .map(|l| {
                        if u[l] >= a[l] * (1.0 - tol) {
                            1
                        } else if u[l] <= -a[l] * (1.0 - tol) {
                            -1
                        } else {
                            0
                        }
                    })
                    .collect()
            })
            .collect();
        let (grad_f2, cost_h) = cost_terms(p, n);
        Structure {
            cost_h,
            n,
            nb,
            np,
            active,
            held,
            slack,
            slips,
            biactive,
            bound,
            grad_f2,
            k: c.stiffness().to_vec(),
        }
    }
}

/// The faces active at every knot with their held flags and slacks, as [`active_faces`] finds
/// them (the fields of [`Structure`] of the same names).
struct ActiveFaces {
    active: Vec<Vec<FaceId>>,
    held: Vec<Vec<bool>>,
    slack: Vec<Vec<f64>>,
}

/// The faces active at every knot (slack within `tol` of the state scale), whether each is held
/// (by the piece ending there, or for a phase gait starting there, slipping on it) and its
/// slack: [`Structure::active`], [`Structure::held`], [`Structure::slack`].
fn active_faces(p: &Process, slips: &[Vec<i8>], tol: f64) -> ActiveFaces {
    let c = &p.crawler;
    let (nb, np) = (c.blocks(), p.durations.len());
    let scale = c.state_scale();
    let mut active = Vec::with_capacity(np);
    let mut held = Vec::with_capacity(np);
    let mut slack = Vec::with_capacity(np);
    let is_active = |j: usize, f: FaceId| -> Option<f64> {
        let force = c.block_forces(&p.states[j])[f.b];
        let s = if f.s > 0 {
            c.mu_forward()[f.b] - force
        } else {
            c.mu_backward()[f.b] + force
        };
        (s <= tol * scale).then_some(s)
    };
    for j in 0..np {
        let prev = (j + np - 1) % np;
        let (mut a, mut h, mut sl) = (Vec::new(), Vec::new(), Vec::new());
        for b in 0..nb {
            for s in [1i8, -1] {
                let f = FaceId { b, s };
                if let Some(v) = is_active(j, f) {
                    // Held by the piece ending here (both kinds) or starting here (phase).
                    let by_prev = slips[prev][b] == s;
                    let by_next = p.kind == ProcessKind::Phase && slips[j][b] == s;
                    a.push(f);
                    h.push(by_prev || by_next);
                    sl.push(v);
                }
            }
        }
        active.push(a);
        held.push(h);
        slack.push(sl);
    }
    ActiveFaces {
        active,
        held,
        slack,
    }
}

/// The biactive (block, direction) pairs of every piece ([`Structure::biactive`]): a sticking
/// block whose face is active where a slip on it would need it (P_m: at the piece's end; a
/// phase: at both ends).
fn biactive_pairs(
    kind: ProcessKind,
    slips: &[Vec<i8>],
    active: &[Vec<FaceId>],
    nb: usize,
    np: usize,
) -> Vec<Vec<(usize, i8)>> {
    let mut biactive = Vec::with_capacity(np);
    for j in 0..np {
        let mut v = Vec::new();
        for b in 0..nb {
            if slips[j][b] != 0 {
                continue;
            }
            for s in [1i8, -1] {
                let f = FaceId { b, s };
                let end = active[(j + 1) % np].contains(&f);
                let start = active[j].contains(&f);
                let avail = match kind {
                    ProcessKind::Discrete { .. } => end,
                    ProcessKind::Phase => end && start,
                };
                if avail {
                    v.push((b, s));
                }
            }
        }
        biactive.push(v);
    }
    biactive
}

/// The cost's terms per piece: `Df2(u_j)` and `Df2(u_j).u_j - f2(u_j)`
/// ([`Structure::grad_f2`], [`Structure::cost_h`]).
fn cost_terms(p: &Process, n: usize) -> (Vec<Vec<f64>>, Vec<f64>) {
    let grad_f2: Vec<Vec<f64>> = p
        .controls
        .iter()
        .map(|u| match p.problem.cost {
            Cost::None => vec![0.0; n],
            Cost::Quadratic { weight } => u.iter().map(|v| weight * v).collect(),
        })
        .collect();
    let cost_h = p
        .controls
        .iter()
        .zip(&grad_f2)
        .map(|(u, g)| u.iter().zip(g).map(|(u, g)| u * g).sum::<f64>() - p.problem.cost.eval(u))
        .collect();
    (grad_f2, cost_h)
}

/// Raw multipliers: `p_j` per piece, `xi` per active face of every knot (same layout as
/// [`Structure::active`]), `omega`, at the given `lambda`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Raw {
    pub lambda: f64,
    pub p: Vec<Vec<f64>>,
    pub xi: Vec<Vec<f64>>,
    pub omega: Vec<f64>,
}

/// Which optimisation over the multiplier set.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Stage {
    /// Minimise the largest violation `r` of the branch LP's KKT system.
    Kkt,
    /// Keeping `r <= r_max`, minimise the largest violation `s` of `xi >= 0`.
    Sign { r_max: f64 },
    /// Keeping `r <= r_max` and `s <= s_max`, maximise the margin `delta`: every normal-cone
    /// weight `rho >= delta` (on a box's bound, `-sign(u_l) sigma_l >= delta`) on the pieces
    /// where the control is a vertex of U, or on every piece for a crawler
    /// (`GeneralStructure::margin_off_vertex`).
    Margin { r_max: f64, s_max: f64, cap: f64 },
}

impl Stage {
    /// The stage's three scalar columns of a multiplier LP, with its objective and bounds:
    /// the KKT violation `r`, the sign violation `s` and the margin `delta`. A degenerate
    /// search (`norm`) holds the KKT system exactly (`r = 0`), and `s = 0` where it imposes
    /// `xi >= 0`.
    pub(crate) fn columns(self, pb: &mut RowProblem, norm: Option<Norm>) -> (Col, Col, Col) {
        const INF: f64 = f64::INFINITY;
        let (r_cost, r_hi) = match self {
            Stage::Kkt if norm.is_some() => (0.0, 0.0),
            Stage::Kkt => (1.0, INF),
            Stage::Sign { r_max } | Stage::Margin { r_max, .. } => (0.0, r_max),
        };
        let r = pb.add_column(r_cost, 0.0..=r_hi);
        let (s_cost, s_hi) = match self {
            Stage::Kkt if norm.is_some_and(|n| n.sign_hard) => (0.0, 0.0),
            Stage::Kkt => (0.0, INF),
            Stage::Sign { .. } => (1.0, INF),
            Stage::Margin { s_max, .. } => (0.0, s_max),
        };
        let s = pb.add_column(s_cost, 0.0..=s_hi);
        let (d_cost, d_hi) = match self {
            Stage::Margin { cap, .. } => (-1.0, cap),
            _ => (0.0, INF),
        };
        let delta = pb.add_column(d_cost, -INF..=d_hi);
        (r, s, delta)
    }
}

/// The search for degenerate multipliers (`lambda = 0`): the conditions are then homogeneous,
/// so a non-zero `(p, omega)` exists iff the fixed generic linear functional `sign * c` has a
/// positive maximum over them within the box `|p|, |omega| <= 1`, for `sign = 1` or `-1` (a
/// non-zero `v` has `c.v != 0` for generic `c`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Norm {
    pub sign: f64,
    /// Whether `xi >= 0` is imposed too (phase gaits, whose verdict includes it).
    pub sign_hard: bool,
}

/// The box `|p|, |omega| <= box` and the weight of the generic functional in the objective:
/// `(1, sign)` in a degenerate search, `(inf, 0)` otherwise.
pub(crate) fn norm_box(norm: Option<Norm>) -> (f64, f64) {
    match norm {
        Some(Norm { sign, .. }) => (1.0, sign),
        None => (f64::INFINITY, 0.0),
    }
}

/// The adjoint's columns `p_j` (`pieces` x `n`, in [`norm_box`]'s box, weighted by the generic
/// functional) and the free reaction multipliers `xi`, one per knot and active face.
pub(crate) fn adjoint_columns<F>(
    pb: &mut RowProblem,
    norm: Option<Norm>,
    pieces: usize,
    n: usize,
    active: &[Vec<F>],
) -> (Vec<Vec<Col>>, Vec<Vec<Col>>) {
    let (box_, weight) = norm_box(norm);
    let p = (0..pieces)
        .map(|j| {
            (0..n)
                .map(|l| pb.add_column(-weight * functional(j, l), -box_..=box_))
                .collect()
        })
        .collect();
    let xi = active
        .iter()
        .map(|a| {
            a.iter()
                .map(|_| pb.add_column(0.0, f64::NEG_INFINITY..=f64::INFINITY))
                .collect()
        })
        .collect();
    (p, xi)
}

/// The generic functional: irrational, deterministic weights.
pub(crate) fn functional(j: usize, l: usize) -> f64 {
    (1.0 + j as f64 * 0.618_033_988_749_895 + l as f64 * 0.414_213_562_373_095).sin() + 0.1
}

/// Solves a multiplier LP (a minimisation) to tight tolerances, both certificates' (`what`
/// names it in errors): its columns, or `None` when HiGHS proves it infeasible (no multipliers
/// of that stage); a time limit is a numerical error (these LPs are small and untimed).
pub(crate) fn solve_multiplier_lp(pb: RowProblem, what: &str) -> Result<Option<Vec<f64>>> {
    let mut model = Highs::new(pb, Sense::Minimise, what)?;
    model.option("primal_feasibility_tolerance", 1e-10)?;
    model.option("dual_feasibility_tolerance", 1e-10)?;
    let solved = model.solve()?;
    match solved.status {
        SolveStatus::Optimal => Ok(Some(solved.columns)),
        SolveStatus::Infeasible => Ok(None),
        SolveStatus::TimeLimit { .. } => {
            Err(Error::Numerical(format!("{what} stopped at a time limit")))
        }
    }
}

/// The slip directions of one branch through the process: its own slips, and at the biactive
/// pairs (flattened piece by piece, in `st.biactive`'s order) the pair's direction where
/// `choice` says the block slips on its face, sticking elsewhere.
pub(crate) fn branch_dirs(st: &Structure, choice: &[bool]) -> Vec<Vec<i8>> {
    let mut dirs = st.slips.clone();
    let pairs = st
        .biactive
        .iter()
        .enumerate()
        .flat_map(|(j, v)| v.iter().map(move |&(b, d)| (j, b, d)));
    for ((j, b, d), &slips) in pairs.zip(choice) {
        if slips {
            dirs[j][b] = d;
        }
    }
    dirs
}

/// A branch LP (module docs of [`crate::certify`]), `f2 = 0` only: each block's slip fixed to
/// `dirs` (a direction or sticking; [`branch_dirs`]), a face held as an equality at a knot where
/// a slip on it ends (or, for a phase gait, starts), so that every point of it is a process
/// (relaxing a biactive pair to both branches would admit slips off their face, and an optimum
/// above every process). Its optimum and HiGHS's dual solution mapped to Theorem 2.2's signs
/// (`lambda = 1`). `None` for a quadratic cost (then the branch problem is not an LP) or when
/// HiGHS reports no optimum.
pub(crate) fn branch_lp(
    pr: &Process,
    st: &Structure,
    dirs: &[Vec<i8>],
) -> Result<Option<(f64, Raw)>> {
    if pr.problem.cost != Cost::None {
        return Ok(None);
    }
    let mut pb = RowProblem::default();
    let cols = BranchCols::add(&mut pb, pr, st, dirs);
    let mut row = 0usize;
    let dyn_rows = branch_dynamics_rows(&mut pb, st, &cols, &mut row);
    let face_rows = branch_face_rows(&mut pb, pr, st, dirs, &cols, &mut row);
    let mut mean_rows = vec![0usize; st.n];
    for l in 0..st.n {
        pb.add_row(
            0.0..=0.0,
            cols.us.iter().map(|u| (u[l], 1.0)).collect::<Vec<_>>(),
        );
        mean_rows[l] = row;
        row += 1;
    }
    let Some((objective, y)) = solve_branch(pb) else {
        return Ok(None);
    };
    // HiGHS's row duals y satisfy c = A^T y + (column duals) for either sense, so the
    // Lagrangian multiplier of "row = rhs" in the text's convention is y: q_j = y(dyn_j),
    // face dual = y(face), and p = -q, xi = -(face dual), omega = y(mean).
    let p: Vec<Vec<f64>> = (0..st.np)
        .map(|j| (0..st.n).map(|l| -y[dyn_rows[j][l]]).collect())
        .collect();
    let xi: Vec<Vec<f64>> = (0..st.np)
        .map(|j| {
            st.active[j]
                .iter()
                .map(|f| {
                    // Every active face of piece j got a row above (the same loop over
                    // st.active[j]), so the search cannot miss; a miss would read as 0.
                    face_rows[j]
                        .iter()
                        .find(|(g, _)| g == f)
                        .map_or(0.0, |(_, r)| -y[*r])
                })
                .collect()
        })
        .collect();
    let omega = (0..st.n).map(|l| y[mean_rows[l]]).collect();
    Ok(Some((
        objective,
        Raw {
            lambda: 1.0,
            p,
            xi,
            omega,
        },
    )))
}

/// The columns of a branch LP: the states `x_j` (free), the actuator increments `u_j` (within
/// `a_l tau_j`) and the block displacements `D_j` (signed as `dirs` fixes them, weighted `1/N`
/// in the objective), added in that order.
struct BranchCols {
    xs: Vec<Vec<Col>>,
    us: Vec<Vec<Col>>,
    ds: Vec<Vec<Col>>,
}

impl BranchCols {
    /// Adds the columns to `pb` (`x`, then `u`, then `D`).
    fn add(pb: &mut RowProblem, pr: &Process, st: &Structure, dirs: &[Vec<i8>]) -> Self {
        let (n, nb, np) = (st.n, st.nb, st.np);
        let a = &pr.problem.rate_bound;
        const INF: f64 = f64::INFINITY;
        let xs: Vec<Vec<Col>> = (0..np)
            .map(|_| (0..n).map(|_| pb.add_column(0.0, -INF..=INF)).collect())
            .collect();
        let us: Vec<Vec<Col>> = (0..np)
            .map(|j| {
                (0..n)
                    .map(|l| {
                        let w = a[l] * pr.durations[j];
                        pb.add_column(0.0, -w..=w)
                    })
                    .collect()
            })
            .collect();
        let inv_n = 1.0 / nb as f64;
        let ds: Vec<Vec<Col>> = (0..np)
            .map(|j| {
                (0..nb)
                    .map(|b| match dirs[j][b] {
                        1 => pb.add_column(inv_n, 0.0..=INF),
                        -1 => pb.add_column(inv_n, -INF..=0.0),
                        _ => pb.add_column(inv_n, 0.0..=0.0),
                    })
                    .collect()
            })
            .collect();
        BranchCols { xs, us, ds }
    }
}

/// The branch LP's dynamics, one row per piece and link: `x_{j+1} - x_j - u_j + sum_b D_{j,b}
/// K nu_b = 0` (cyclic). Returns each row's index (counted in `row`), for reading its dual `p`.
fn branch_dynamics_rows(
    pb: &mut RowProblem,
    st: &Structure,
    cols: &BranchCols,
    row: &mut usize,
) -> Vec<Vec<usize>> {
    let (n, nb, np) = (st.n, st.nb, st.np);
    let (xs, us, ds) = (&cols.xs, &cols.us, &cols.ds);
    let mut dyn_rows = vec![vec![0usize; n]; np];
    for j in 0..np {
        let next = &xs[(j + 1) % np];
        for l in 0..n {
            let mut r = vec![(next[l], 1.0), (xs[j][l], -1.0), (us[j][l], -1.0)];
            for b in 0..nb {
                for (ll, v) in k_nu(n, &st.k, b) {
                    if ll == l {
                        r.push((ds[j][b], v));
                    }
                }
            }
            pb.add_row(0.0..=0.0, r);
            dyn_rows[j][l] = *row;
            *row += 1;
        }
    }
    dyn_rows
}

/// The branch LP's faces of C at every knot, two per block: `<x*_f, x_j> <= c_f`, an equality
/// where this branch holds the face. Returns each (face, row index) per knot (counted in
/// `row`), for reading its dual `xi`.
fn branch_face_rows(
    pb: &mut RowProblem,
    pr: &Process,
    st: &Structure,
    dirs: &[Vec<i8>],
    cols: &BranchCols,
    row: &mut usize,
) -> Vec<Vec<(FaceId, usize)>> {
    let (n, nb, np) = (st.n, st.nb, st.np);
    let phase = pr.kind == ProcessKind::Phase;
    let c = &pr.crawler;
    let xs = &cols.xs;
    const INF: f64 = f64::INFINITY;
    let mut face_rows = vec![Vec::new(); np];
    for j in 0..np {
        for b in 0..nb {
            for s in [1i8, -1] {
                let f = FaceId { b, s };
                let cf = if s > 0 {
                    c.mu_forward()[b]
                } else {
                    c.mu_backward()[b]
                };
                let coeffs: Vec<(Col, f64)> =
                    normal(n, f).iter().map(|&(l, v)| (xs[j][l], v)).collect();
                // Held by the piece ending here (both kinds) or starting here (phase), as in
                // `Structure::of`, with this branch's slips.
                let prev = (j + np - 1) % np;
                let held =
                    st.active[j].contains(&f) && (dirs[prev][b] == s || (phase && dirs[j][b] == s));
                if held {
                    pb.add_row(cf..=cf, coeffs);
                } else {
                    pb.add_row(-INF..=cf, coeffs);
                }
                face_rows[j].push((f, *row));
                *row += 1;
            }
        }
    }
    face_rows
}

/// Solves a branch LP (a maximisation) to tight tolerances: its optimum and row duals, or
/// `None` when HiGHS refuses the model or an option, fails, or reports no optimum.
fn solve_branch(pb: RowProblem) -> Option<(f64, Vec<f64>)> {
    // The branch LP is a cross-check of the certificate: a model HiGHS refuses or does not
    // solve to optimality gives no cross-check (None), never an error of the certificate.
    let Ok(mut model) = Highs::new(pb, Sense::Maximise, "certify: the branch LP") else {
        return None;
    };
    if model.option("primal_feasibility_tolerance", 1e-10).is_err()
        || model.option("dual_feasibility_tolerance", 1e-10).is_err()
    {
        return None;
    }
    let Ok(solved) = model.solve() else {
        return None;
    };
    if solved.status != SolveStatus::Optimal {
        return None;
    }
    Some((solved.objective, solved.row_duals))
}
