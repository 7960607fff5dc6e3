//! The one multiplier linear program of the certificate (module docs of
//! [`crate::certify::general`] for the mathematics): the combinatorial structure of a process of
//! (P) (active faces, held faces, active rows of U) and the KKT system of its branch LP, solved
//! by HiGHS for multipliers that violate it least, in the stages of the search
//! (`certify::stages`: [`Stage`], [`Norm`], a generic functional for the degenerate case). A
//! crawler's certificate solves it on the crawler's instance (`certify::crawler_general`).

use super::general_process::{GeneralProcess, ProcessKind};
use crate::error::{Error, Result};
use crate::model::general::{dot, GeneralCost, GeneralProblem};
use crate::optimal::process::control_rows;
use crate::optimal::solver::{Highs, SolveStatus};
use highs::{Col, RowProblem, Sense};

/// The cost's Hessian `R` (`f2 = (1/2) u^T R u`; zero for `f2 = 0`).
pub(crate) fn cost_hessian(cost: &GeneralCost, m: usize) -> Vec<Vec<f64>> {
    let diag = |c: f64| {
        (0..m)
            .map(|i| (0..m).map(|k| if i == k { c } else { 0.0 }).collect())
            .collect()
    };
    match cost {
        GeneralCost::None => diag(0.0),
        GeneralCost::Quadratic { weight } => diag(*weight),
        GeneralCost::Matrix { matrix } => matrix.clone(),
    }
}

/// What the KKT system needs besides the numbers.
#[derive(Clone)]
pub(crate) struct GeneralStructure {
    /// States `n`, controls `m`, pieces `P` (`2^m` steps of P_m, or a gait's phases).
    pub n: usize,
    pub m: usize,
    pub steps: usize,
    /// Piece durations `tau_i` (`h = T / 2^m` on P_m).
    pub tau: Vec<f64>,
    /// Whether the process is a phase gait (held faces active at both ends of their phase;
    /// the durations free in the phase LP).
    pub phase: bool,
    /// Faces active at knot `k = 0..P-1` (knot `P` is knot 0), 0-based.
    pub active: Vec<Vec<usize>>,
    /// Whether the face is held at the knot (a reaction on it on the piece ending there, or, for
    /// a phase gait, starting there): its multiplier is then free in the branch LP; otherwise
    /// the face is a true inequality there.
    pub held: Vec<Vec<bool>>,
    /// `c_j - <x*_j, x^k>` of each active face.
    pub slack: Vec<Vec<f64>>,
    /// The faces that may carry a reaction on piece `i` in its branch (P_m: active at
    /// `x^(i+1)`; a phase: active at both ends), 0-based, and whether the piece has a reaction
    /// on it (else the pair is biactive).
    pub reacting: Vec<Vec<(usize, bool)>>,
    /// Rows of U active at `u^i`, per piece.
    pub urows_active: Vec<Vec<usize>>,
    /// Whether those rows span `R^m` (`u^i` a vertex of U).
    pub at_vertex: Vec<bool>,
    /// `R u^i` per piece.
    pub grad_f2: Vec<Vec<f64>>,
    /// `Df2(u^i).u^i - f2(u^i)` per piece (the cost's part of the maximised Hamiltonian).
    pub cost_h: Vec<f64>,
    /// `w_j`.
    pub w: Vec<f64>,
    /// The rows of U.
    pub urows: Vec<(Vec<f64>, f64)>,
    /// The unit of each face's rows in the violations `r` and `s` of the staged LPs: a face's
    /// reaction stationarity counts `r / face_scale`, its sign and branch-LP face sign
    /// `face_scale * (r or s)`. 1 for (P)'s own faces; `s_b` for a crawler's instance, so that
    /// the least violations are the crawler's, in the units of `nu_b` (`certify::crawler_general`).
    pub face_scale: Vec<f64>,
    /// The unit of each state's adjoint row in the recomputed residuals
    /// (`general_conditions::residuals`): 1 for (P)'s own states; `1 / sqrt(k_l)` for a
    /// crawler's instance, whose adjoint `p~ = K^(1/2) p`, so that the residual is the crawler's,
    /// in the units of its own `p` (with `face_scale` for the faces' rows and `xi`).
    pub state_scale: Vec<f64>,
    /// Whether the margin stage also weighs the pieces off a vertex of U. (P)'s certificate
    /// takes the margin on the pieces at a vertex only (off one it is 0 by definition); a
    /// crawler's on every rate at its bound, as its margin `min |p + omega|` reads. Where every
    /// piece is at a vertex the two agree; elsewhere they only pick among non-unique
    /// multipliers differently (both margins are then 0).
    pub margin_off_vertex: bool,
    /// The natural unit of the switching function `B^T p + omega`, the floor of the
    /// non-degeneracy threshold `1e-6 max(sup |sigma|, switching_unit)` when `sigma` vanishes
    /// identically: `max |w|` times [`ResidualUnits::psi`] for (P); `1 / (N k_max)` for a crawler's instance (its `p` is then
    /// `lambda / N` per `K nu_b` while block `b` slips).
    pub switching_unit: f64,
    /// The units of the residuals whose terms are not of the adjoint's size, so that a
    /// verdict is the same for the problem in any units (an exact twin: states times `a`,
    /// time times `s`, controls times `s_u`): [`ResidualUnits`].
    pub units: ResidualUnits,
    /// The bound on the margin `delta` of the last stage (in the units of the switching
    /// function), so that the LP is bounded where every rate's margin could grow without end:
    /// `10 max(max |w|, 1) max |B_ij|` for (P); `10 / (N k_min)` for a crawler's instance (ten times the
    /// largest `p` one slipping block asks).
    pub margin_cap: f64,
}

/// The units the recomputed residuals are counted in ([`GeneralStructure::units`]), each a
/// size of the problem that scales as its residual does under a change of units (the adjoint
/// `p`, in units of `J` per state, does not change). Without them the residuals were absolute:
/// the one-link optimum of the phase method `fails` at C's scale `1e5` (complementarity and
/// duration stationarity `1.3e-9`, rounding of slacks of size `1e5`), and P_3's switching
/// function was held to the unit of `max |w|` where `B` is `1e-6` (a twin in slow time, small
/// states or large controls), which made its verdict `degenerate` where the twin's `holds`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidualUnits {
    /// The slacks' unit, C's scale `max |c_f|` (complementarity counts `xi slack / slack`).
    pub slack: f64,
    /// The unit of `psi = -B^T p - omega - lambda Df2(u)` and of the switching function per
    /// unit of `p`: `max |B_ij|` (weak maximality counts `|psi - cone| / psi`, the switching
    /// function's floor is `max |w| psi`).
    pub psi: f64,
    /// The unit of the maximised Hamiltonian at `|p|` of `p`'s unit: for (P) the fastest rate
    /// of a state, `max_i (sum_j |B_ij| u_unit + |b_i|)` with `u_unit` U's largest scale; for a
    /// crawler `max_l a_l / k_max` (the duration stationarity counts
    /// `(max H - min H) / 2 / speed`, relative to `max(p_unit, ||p||) / p_unit`).
    pub speed: f64,
    /// The unit of `p` itself: 1 for (P), whose `p` is `J` per state and so does not change
    /// with the units; a crawler's `p` is a length per force, and its unit `1 / k_max` (the
    /// duration stationarity is relative to `max(p_unit, ||p||)`, so that it is the same for
    /// a crawler in any units).
    pub p: f64,
    /// The user's unit of time in the process's: 1 for (P); a crawler is certified with time in
    /// periods (`super::crawler_units`), and the times a reason states and the paper's norm's
    /// `sum_k tau_k |psi_k|` are in its own time.
    pub time: f64,
}

impl ResidualUnits {
    /// The units of `p` ([`ResidualUnits`]); each is 1 on a problem in units of one, and never
    /// below `1e-300`.
    pub fn of(p: &GeneralProblem) -> Self {
        let (_, speed) = crate::optimal::general::control_and_speed(p);
        let psi = p
            .dynamics
            .b
            .iter()
            .flatten()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        ResidualUnits {
            slack: p.c.scale(),
            psi: psi.max(1e-300),
            speed: speed.max(1e-300),
            p: 1.0,
            time: 1.0,
        }
    }
}

impl GeneralStructure {
    /// The structure of `pr` at relative tolerance `tol` (faces relative to C's scale, rows of
    /// U to U's, integrated reactions `tau lambda` to C's scale).
    pub fn of(p: &GeneralProblem, pr: &GeneralProcess, tol: f64) -> Self {
        let (n, m, steps) = (p.states(), p.controls(), pr.u.len());
        let phase = pr.kind == ProcessKind::Phase;
        let scale = p.c.scale();
        let reacts = |i: usize, j: usize| pr.durations[i] * pr.lambda[i][j] > tol * scale;
        let (mut active, mut held, mut slack) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..steps {
            let prev = (k + steps - 1) % steps;
            let (mut a, mut hd, mut sl) = (Vec::new(), Vec::new(), Vec::new());
            for j in 0..p.c.faces() {
                let s = -p.c.slack(j, &pr.x[k]);
                if s <= tol * scale {
                    a.push(j);
                    hd.push(reacts(prev, j) || (phase && reacts(k, j)));
                    sl.push(s.max(0.0));
                }
            }
            active.push(a);
            held.push(hd);
            slack.push(sl);
        }
        let reacting = (0..steps)
            .map(|i| {
                let end = (i + 1) % steps;
                active[end]
                    .iter()
                    .filter(|f| !phase || active[i].contains(f))
                    .map(|&f| (f, reacts(i, f)))
                    .collect()
            })
            .collect();
        let urows = control_rows(&p.control);
        let uscale = urows
            .iter()
            .fold(0.0_f64, |s, (_, h)| s.max(h.abs()))
            .max(1e-300);
        let (mut urows_active, mut at_vertex) = (Vec::new(), Vec::new());
        for u in &pr.u {
            let act: Vec<usize> = (0..urows.len())
                .filter(|&r| dot(&urows[r].0, u) >= urows[r].1 - tol * uscale)
                .collect();
            let mat = nalgebra::DMatrix::from_fn(act.len(), m, |i, k| urows[act[i]].0[k]);
            at_vertex.push(act.len() >= m && crate::linalg::rank(&mat, 1e-9) == Some(m));
            urows_active.push(act);
        }
        let r = cost_hessian(&p.cost, m);
        let grad_f2: Vec<Vec<f64>> =
            pr.u.iter()
                .map(|u| r.iter().map(|row| dot(row, u)).collect())
                .collect();
        let cost_h =
            pr.u.iter()
                .zip(&grad_f2)
                .map(|(u, g)| dot(g, u) - p.cost.eval(u))
                .collect();
        let w = p.face_weights();
        let wmax = w.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
        let units = ResidualUnits::of(p);
        GeneralStructure {
            n,
            m,
            steps,
            tau: pr.durations.clone(),
            phase,
            active,
            held,
            slack,
            reacting,
            urows_active,
            at_vertex,
            grad_f2,
            cost_h,
            switching_unit: wmax * units.psi,
            margin_cap: 10.0 * wmax.max(1.0) * units.psi,
            units,
            w,
            urows,
            face_scale: vec![1.0; p.c.faces()],
            state_scale: vec![1.0; n],
            margin_off_vertex: false,
        }
    }
}

impl GeneralStructure {
    /// Per active row of U at piece `i` (layout of [`GeneralStructure::urows_active`]): `Some((l,
    /// v))` where the row is `v e_l` and no other active row there involves control `l` (a box
    /// bound, or a polytope's lone axis-aligned row). Its weight is then determined by `psi_i`,
    /// `rho = sign(v) psi_(i,l) / |v|`, and the LP needs no column for it: `rho >= 0` is the
    /// one row `sign(v) psi_(i,l) >= 0` (the crawler's `psi >= 0` at an upper bound).
    pub fn axis_rows(&self, i: usize) -> Vec<Option<(usize, f64)>> {
        let act = &self.urows_active[i];
        let touches = |l: usize| act.iter().filter(|&&r| self.urows[r].0[l] != 0.0).count();
        act.iter()
            .map(|&r| {
                let row = &self.urows[r].0;
                let mut nz = (0..self.m).filter(|&l| row[l] != 0.0);
                match (nz.next(), nz.next()) {
                    (Some(l), None) if touches(l) == 1 => Some((l, row[l])),
                    _ => None,
                }
            })
            .collect()
    }
}

/// Raw multipliers at the given `lambda`: `p_i` per step, `xi` per active face of every knot
/// (layout of [`GeneralStructure::active`]), `omega`, and the normal-cone weights `rho` of
/// `psi_i` on the active rows of U (layout of [`GeneralStructure::urows_active`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct GeneralRaw {
    pub lambda: f64,
    pub p: Vec<Vec<f64>>,
    pub xi: Vec<Vec<f64>>,
    pub omega: Vec<f64>,
    pub rho: Vec<Vec<f64>>,
}

/// `psi_i = -B^T p_i - omega - lambda R u^i`.
pub(crate) fn psi_of(
    p: &GeneralProblem,
    st: &GeneralStructure,
    raw: &GeneralRaw,
    i: usize,
) -> Vec<f64> {
    (0..st.m)
        .map(|l| {
            let btp: f64 = (0..st.n).map(|q| p.dynamics.b[q][l] * raw.p[i][q]).sum();
            -btp - raw.omega[l] - raw.lambda * st.grad_f2[i][l]
        })
        .collect()
}

/// The columns of one general multiplier LP: the adjoint `p_i` and reactions `xi` (of
/// [`adjoint_columns`]), `omega`, the normal-cone weights `rho >= 0` on the active rows of U
/// but the axis rows ([`GeneralStructure::axis_rows`]: their weight is `psi`'s, `None` here),
/// and the stage's scalars `r`, `s`, `delta` ([`Stage::columns`]).
struct GeneralCols {
    pc: Vec<Vec<Col>>,
    xi: Vec<Vec<Col>>,
    omega: Vec<Col>,
    rho: Vec<Vec<Option<Col>>>,
    axis: Vec<Vec<Option<(usize, f64)>>>,
    r: Col,
    s: Col,
    delta: Col,
}

impl GeneralCols {
    /// Adds the columns to `pb`, in this order: `p`, `xi`, `omega` (boxed only under a zero
    /// mean: otherwise `omega = 0`), `rho` (off the axis rows), then `r`, `s`, `delta`.
    fn add(
        pb: &mut RowProblem,
        p: &GeneralProblem,
        st: &GeneralStructure,
        stage: Stage,
        norm: Option<Norm>,
    ) -> Self {
        let (n, m, steps) = (st.n, st.m, st.steps);
        const INF: f64 = f64::INFINITY;
        let (pc, xi) = adjoint_columns(pb, norm, steps, n, &st.active);
        let (box_, weight) = norm_box(norm);
        let om_box = if p.zero_mean { box_ } else { 0.0 };
        let omega: Vec<Col> = (0..m)
            .map(|l| pb.add_column(-weight * functional(steps, l), -om_box..=om_box))
            .collect();
        let axis: Vec<Vec<Option<(usize, f64)>>> = (0..steps).map(|i| st.axis_rows(i)).collect();
        let rho: Vec<Vec<Option<Col>>> = axis
            .iter()
            .map(|a| {
                a.iter()
                    .map(|ax| ax.is_none().then(|| pb.add_column(0.0, 0.0..=INF)))
                    .collect()
            })
            .collect();
        let (r, s, delta) = stage.columns(pb, norm);
        GeneralCols {
            pc,
            xi,
            omega,
            rho,
            axis,
            r,
            s,
            delta,
        }
    }
}

/// Solves one multiplier LP (`None` when HiGHS reports no optimum). `drift_term = false` drops
/// `h A^T p_k` from the adjoint equation: only for showing, in tests, that the term matters.
/// `durations_free` (phase gaits) adds the phase LP's stationarity in the durations: the
/// maximised Hamiltonian `H_i = sum_r rho_{i,r} h_r - <p_i, b> + lambda (Df2(u^i).u^i -
/// f2(u^i))` equal on every phase.
pub(crate) fn solve_general(
    p: &GeneralProblem,
    st: &GeneralStructure,
    lambda: f64,
    stage: Stage,
    norm: Option<Norm>,
    drift_term: bool,
    durations_free: bool,
) -> Result<Option<GeneralRaw>> {
    let mut pb = RowProblem::default();
    let c = GeneralCols::add(&mut pb, p, st, stage, norm);
    adjoint_rows(&mut pb, p, st, &c, drift_term);
    for k in 0..st.steps {
        for (fi, &h) in st.held[k].iter().enumerate() {
            if !h {
                // A face held by no reaction: an inequality of the branch LP, xi <= 0 (up to r).
                let sf = st.face_scale[st.active[k][fi]];
                pb.add_row(..=0.0, [(c.xi[k][fi], 1.0), (c.r, -sf)]);
            }
        }
    }
    for i in 0..st.steps {
        reaction_rows(&mut pb, p, st, &c, lambda, i);
        maximality_rows(&mut pb, p, st, &c, lambda, i);
    }
    if st.phase && durations_free {
        duration_rows(&mut pb, p, st, &c, lambda);
    }
    // Theorem 2.2 / 6.1 sign: xi >= -s.
    for (k, row) in c.xi.iter().enumerate() {
        for (fi, &col) in row.iter().enumerate() {
            let sf = st.face_scale[st.active[k][fi]];
            pb.add_row(0.0.., [(col, 1.0), (c.s, sf)]);
        }
    }
    let Some(cols) = solve_multiplier_lp(pb, "certify: the general multiplier LP")? else {
        return Ok(None);
    };
    let val = |c: &Col| cols[c.index()];
    let vals = |rows: &Vec<Vec<Col>>| -> Vec<Vec<f64>> {
        rows.iter().map(|r| r.iter().map(val).collect()).collect()
    };
    let mut raw = GeneralRaw {
        lambda,
        p: vals(&c.pc),
        xi: vals(&c.xi),
        omega: c.omega.iter().map(val).collect(),
        rho: Vec::new(),
    };
    // An axis row's weight is psi's (clipped at 0: the LP keeps sign(v) psi >= -r).
    raw.rho = (0..st.steps)
        .map(|i| {
            let psi = psi_of(p, st, &raw, i);
            c.rho[i]
                .iter()
                .zip(&c.axis[i])
                .map(|(col, ax)| match (col, ax) {
                    (Some(col), _) => val(col),
                    (None, Some((l, v))) => (psi[*l] / v).max(0.0),
                    (None, None) => unreachable!("a row without a column is an axis row"),
                })
                .collect()
        })
        .collect();
    Ok(Some(raw))
}

/// The adjoint equation with transversality (cyclic; Theorem 6.2 (px), (p2mx)), one row per
/// step and state: `p_k - p_{k-1} + h A^T p_k - sum xi_{k,f} x*_f = 0` (without the `h A^T p_k`
/// term when `drift_term` is false).
fn adjoint_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    st: &GeneralStructure,
    c: &GeneralCols,
    drift_term: bool,
) {
    let (n, steps) = (st.n, st.steps);
    let a = &p.dynamics.a;
    for k in 0..steps {
        let prev = (k + steps - 1) % steps;
        for l in 0..n {
            // Coefficients of p_k and p_(k-1), merged (HiGHS refuses repeated columns in a row).
            let mut coef = vec![0.0; n];
            coef[l] = 1.0;
            if drift_term {
                for (q, arow) in a.iter().enumerate() {
                    coef[q] += st.tau[k] * arow[l];
                }
            }
            let mut row: Vec<(Col, f64)> = Vec::new();
            if prev == k {
                coef[l] -= 1.0;
            } else {
                row.push((c.pc[prev][l], -1.0));
            }
            row.extend(
                (0..n)
                    .filter(|&q| coef[q] != 0.0)
                    .map(|q| (c.pc[k][q], coef[q])),
            );
            for (fi, &f) in st.active[k].iter().enumerate() {
                let v = p.c.normals[f][l];
                if v != 0.0 {
                    row.push((c.xi[k][fi], -v));
                }
            }
            pb.add_row(0.0..=0.0, row);
        }
    }
}

/// Reaction stationarity on piece `i` (Theorem 6.2 (pr)): `lambda w_f + <p_i, x*_f> <= 0` (up
/// to `r`) on every face that may react there, and `= 0` where it does react.
fn reaction_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    st: &GeneralStructure,
    c: &GeneralCols,
    lambda: f64,
    i: usize,
) {
    let n = st.n;
    // Reaction stationarity on the faces that may react on piece i: lambda w_f + <p_i, x*_f>.
    for &(f, reacts) in &st.reacting[i] {
        let lw = lambda * st.w[f];
        let dot_row = |extra: (Col, f64)| {
            let mut row: Vec<(Col, f64)> = (0..n)
                .filter(|&l| p.c.normals[f][l] != 0.0)
                .map(|l| (c.pc[i][l], p.c.normals[f][l]))
                .collect();
            row.push(extra);
            row
        };
        let sf = st.face_scale[f];
        pb.add_row(..=-lw, dot_row((c.r, -1.0 / sf)));
        if reacts {
            pb.add_row(-lw.., dot_row((c.r, 1.0 / sf)));
        }
    }
}

/// Weak maximality on piece `i` (Theorem 6.2 (pw)): `psi_i = -B^T p_i - omega - lambda R u_i`
/// equal to `sum rho G` over the active rows of U (up to `r` in units of `psi`,
/// [`ResidualUnits::psi`], as the recomputed residual counts it), two rows per control, where a
/// control's only active row is an axis row `v e_l` one row `sign(v) psi_(i,l) >= -r` (its weight
/// `psi_(i,l) / v`, [`GeneralStructure::axis_rows`]); and, at a vertex of U (or anywhere with
/// [`GeneralStructure::margin_off_vertex`]), the margin rows on every active row (`rho >= delta`,
/// the relative interior of `N_U(u_i)`; on an axis row the switching function `-sign(v)
/// sigma_(i,l) >= delta`, the margin a box's verdict reads, the crawler's `-(p + omega) sign(u)
/// >= delta` at every rate at its bound).
fn maximality_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    st: &GeneralStructure,
    c: &GeneralCols,
    lambda: f64,
    i: usize,
) {
    let (n, m) = (st.n, st.m);
    // -B^T p_i - omega as (column, coefficient) pairs, for control l.
    let minus_sigma = |l: usize, scale: f64| -> Vec<(Col, f64)> {
        let mut row: Vec<(Col, f64)> = (0..n)
            .filter(|&q| p.dynamics.b[q][l] != 0.0)
            .map(|q| (c.pc[i][q], -scale * p.dynamics.b[q][l]))
            .collect();
        row.push((c.omega[l], -scale));
        row
    };
    let margin = st.at_vertex[i] || st.margin_off_vertex;
    let unit = st.units.psi;
    for l in 0..m {
        let g = lambda * st.grad_f2[i][l];
        if let Some(&(_, v)) = c.axis[i].iter().flatten().find(|(al, _)| *al == l) {
            // sign(v) psi >= -r, psi = -sigma - g with the switching function sigma = B^T p +
            // omega; the margin on sigma, the one the verdict reads for a box:
            // -sign(v) sigma >= delta (the crawler's -(p + omega) sign(u) >= delta).
            let sg = v.signum();
            let mut row = minus_sigma(l, sg);
            row.push((c.r, unit));
            pb.add_row(sg * g.., row);
            if margin {
                let mut row = minus_sigma(l, sg);
                row.push((c.delta, -1.0));
                pb.add_row(0.0.., row);
            }
            continue;
        }
        // psi = sum rho G (up to r).
        let mut row = minus_sigma(l, 1.0);
        for (ri, &rr) in st.urows_active[i].iter().enumerate() {
            let v = st.urows[rr].0[l];
            if let (Some(col), true) = (c.rho[i][ri], v != 0.0) {
                row.push((col, -v));
            }
        }
        let mut lo = row.clone();
        lo.push((c.r, unit));
        row.push((c.r, -unit));
        pb.add_row(..=g, row);
        pb.add_row(g.., lo);
    }
    // Margin: psi in the relative interior of N_U(u_i), every weight at least delta.
    if margin {
        for col in c.rho[i].iter().flatten() {
            pb.add_row(0.0.., [(*col, 1.0), (c.delta, -1.0)]);
        }
    }
}

/// The phase LP's stationarity in the durations (phase gaits): a free column `H` (added here,
/// after all the others) and `H_i = sum_r rho_{i,r} h_r - <p_i, b> + lambda cost_h_i` equal to
/// it on every phase, up to `r` in units of a state's rate ([`ResidualUnits::speed`]).
fn duration_rows(
    pb: &mut RowProblem,
    p: &GeneralProblem,
    st: &GeneralStructure,
    c: &GeneralCols,
    lambda: f64,
) {
    const INF: f64 = f64::INFINITY;
    // Stationarity in the durations: H_i = sum_r rho_{i,r} h_r - <p_i, b> + lambda cost_h_i
    // equal on every phase (up to r).
    let ham = pb.add_column(0.0, -INF..=INF);
    for i in 0..st.steps {
        let mut row: Vec<(Col, f64)> = vec![(ham, -1.0)];
        let mut cst = lambda * st.cost_h[i];
        // The coefficients of p_i and omega, merged: an axis row's weight and the drift both
        // bring p_i in (HiGHS refuses a column repeated in a row).
        let mut cp = vec![0.0; st.n];
        let mut co = vec![0.0; st.m];
        for (ri, &rr) in st.urows_active[i].iter().enumerate() {
            let h = st.urows[rr].1;
            match (c.rho[i][ri], c.axis[i][ri]) {
                (Some(col), _) => row.push((col, h)),
                // rho h = (psi_l / v) h, psi_l = -B^T p - omega - lambda (R u)_l.
                (None, Some((l, v))) => {
                    let w = h / v;
                    for (q, cq) in cp.iter_mut().enumerate() {
                        *cq -= w * p.dynamics.b[q][l];
                    }
                    co[l] -= w;
                    cst -= w * lambda * st.grad_f2[i][l];
                }
                (None, None) => unreachable!("a row without a column is an axis row"),
            }
        }
        for (q, cq) in cp.iter_mut().enumerate() {
            *cq -= p.dynamics.drift[q];
        }
        row.extend(
            (0..st.n)
                .filter(|&q| cp[q] != 0.0)
                .map(|q| (c.pc[i][q], cp[q])),
        );
        row.extend(
            (0..st.m)
                .filter(|&l| co[l] != 0.0)
                .map(|l| (c.omega[l], co[l])),
        );
        let mut lo = row.clone();
        lo.push((c.r, st.units.speed));
        row.push((c.r, -st.units.speed));
        pb.add_row(..=-cst, row);
        pb.add_row(-cst.., lo);
    }
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
