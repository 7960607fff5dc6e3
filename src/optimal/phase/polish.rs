//! Polishing a phase gait of a quadratic cost on its own sequence of slip modes.
//!
//! The phase MILP carries `f2` by an outer approximation (tangent cuts of the perspective
//! `tau f2(U / tau) = (c/2) |U|^2 / tau`, refined until the incumbent's true objective meets the
//! bound to [`OA_TOL`](crate::optimal::milp::OA_TOL)), so a rate off the bounds is only as
//! accurate as the cuts (about 1e-4 on the one-link example with `c = 0.6`), and the necessary
//! conditions fail at that size although the gait is the MILP's optimum to its gap (the same
//! defect P_m's polish, [`crate::optimal::polish`], removes).
//!
//! With the slip mode of every piece fixed, the phase problem is convex in the durations, the
//! increments, the states and the block displacements: the dynamics, the faces and the rate
//! bounds are linear (`|U_l| <= a_l tau`), and the cost is the perspective, a rotated
//! second-order cone `U_l^2 <= g_l tau` under the linear `(c/2) sum g`. Every feasible point is
//! an exact gait (the argument of the phase formulation, [`super`]: a slipping block's face is
//! held at both ends of its piece, a sticking block's forces stay in their range at both ends,
//! and the reaction `K sum_b D_b nu_b` has the mode's signs), and the MILP's answer is one of
//! them, so the optimum is no worse. It is solved by Clarabel to `1e-10`; pieces that shrink to
//! nothing are dropped, and the caller replays the result with the exact simulator and keeps it
//! only when the replay agrees and `J` is no worse.

use super::decode::RawGait;
use crate::model::Crawler;
use crate::optimal::discrete_polish::link_columns;
use crate::optimal::milp::block_speed_bound;
use crate::optimal::polish::Qp;
use crate::optimal::{Cost, GaitProblem};

/// The columns of the polish QP, family by family in the order [`add_columns`] adds them.
struct Columns {
    /// Durations `tau_i`.
    tau: Vec<usize>,
    /// Link states `x_i`.
    x: Vec<Vec<usize>>,
    /// Increments `U_i`.
    u: Vec<Vec<usize>>,
    /// Block displacements `D_{i,b}` of the slipping blocks (none where a block sticks).
    d: Vec<Vec<Option<usize>>>,
    /// Perspective epigraphs `g_{i,l} >= U_{i,l}^2 / tau_i`.
    g: Vec<Vec<usize>>,
}

/// Adds the columns of the polish QP: the durations, the link states and increments, the block
/// displacements of the slipping blocks with the mode's sign (bounded by the block speed bound
/// `v`, with the barycentre's objective) and the cost's epigraphs (weight `c/2`).
fn add_columns(
    qp: &mut Qp,
    crawler: &Crawler,
    problem: &GaitProblem,
    raw: &RawGait,
    (weight, v): (f64, f64),
) -> Columns {
    let (n, nb, pieces) = (crawler.links(), crawler.blocks(), raw.durations.len());
    let t = problem.period;
    let inf = f64::INFINITY;
    let tau: Vec<usize> = (0..pieces).map(|_| qp.add_column(0.0, 0.0, t)).collect();
    let (x, u) = link_columns(qp, crawler, problem, pieces, t);
    // Block displacements of the slipping blocks, with the mode's sign (none where a block
    // sticks).
    let d: Vec<Vec<Option<usize>>> = raw
        .modes
        .iter()
        .map(|m| {
            m.iter()
                .map(|&s| match s {
                    1 => Some(qp.add_column(-1.0 / nb as f64, 0.0, v * t)),
                    -1 => Some(qp.add_column(-1.0 / nb as f64, -v * t, 0.0)),
                    _ => None,
                })
                .collect()
        })
        .collect();
    let g: Vec<Vec<usize>> = (0..pieces)
        .map(|_| {
            (0..n)
                .map(|_| qp.add_column(0.5 * weight, 0.0, inf))
                .collect()
        })
        .collect();
    Columns { tau, x, u, d, g }
}

/// The force on block `b` of `n + 1` in the link states `x` (`x_{b-1} - x_b`, the end blocks
/// with one link), as row entries.
fn force(x: &[usize], b: usize, n: usize) -> Vec<(usize, f64)> {
    let mut f = Vec::with_capacity(2);
    if b > 0 {
        f.push((x[b - 1], 1.0));
    }
    if b < n {
        f.push((x[b], -1.0));
    }
    f
}

/// The rows of piece `i` on its slip mode: per link the update `x_(i+1) = x_i + U_i -
/// K sum_b D_b nu_b`, the rate bounds `|U_l| <= a_l tau` and the cost's perspective cone; per
/// block the force range and, for a slipping block, its face held at both ends and no motion
/// in zero time (`|D| <= v tau`).
fn add_piece_rows(
    qp: &mut Qp,
    crawler: &Crawler,
    problem: &GaitProblem,
    (raw, cols, v): (&RawGait, &Columns, f64),
    i: usize,
) {
    let (n, nb, pieces) = (crawler.links(), crawler.blocks(), raw.durations.len());
    let (k, mp, mm) = (
        crawler.stiffness(),
        crawler.mu_forward(),
        crawler.mu_backward(),
    );
    let a = &problem.rate_bound;
    let inf = f64::INFINITY;
    let (tau, x, u, d, g) = (&cols.tau, &cols.x, &cols.u, &cols.d, &cols.g);
    let next = &x[(i + 1) % pieces];
    for l in 0..n {
        // x_(i+1) = x_i + U_i - K sum_b D_b nu_b.
        let mut row = vec![(next[l], 1.0), (x[i][l], -1.0), (u[i][l], -1.0)];
        if let Some(c) = d[i][l + 1] {
            row.push((c, k[l]));
        }
        if let Some(c) = d[i][l] {
            row.push((c, -k[l]));
        }
        qp.add_row(0.0, 0.0, row);
        qp.add_row(-inf, 0.0, vec![(u[i][l], 1.0), (tau[i], -a[l])]);
        qp.add_row(-inf, 0.0, vec![(u[i][l], -1.0), (tau[i], -a[l])]);
        qp.add_perspective(u[i][l], g[i][l], tau[i]);
    }
    for b in 0..nb {
        qp.add_row(-mm[b], mp[b], force(&x[i], b, n));
        if let Some(c) = d[i][b] {
            // The face held at both ends; no motion in zero time.
            let held = if raw.modes[i][b] > 0 { mp[b] } else { -mm[b] };
            qp.add_row(held, held, force(&x[i], b, n));
            qp.add_row(held, held, force(next, b, n));
            let s = f64::from(raw.modes[i][b]);
            qp.add_row(-inf, 0.0, vec![(c, s), (tau[i], -v)]);
        }
    }
}

/// The polished gait read from the QP's solution `sol`: the pieces of `raw`'s modes that keep
/// a duration above `1e-12 T`, the first state repeated at the end; `None` when none is left.
fn read_gait(sol: &[f64], cols: &Columns, raw: &RawGait, t: f64) -> Option<RawGait> {
    let val = |c: usize| sol[c];
    let mut out = RawGait::default();
    for i in 0..raw.durations.len() {
        let d_i = val(cols.tau[i]);
        if d_i <= 1e-12 * t {
            continue;
        }
        out.durations.push(d_i);
        out.increments
            .push(cols.u[i].iter().map(|&c| val(c)).collect());
        out.states.push(cols.x[i].iter().map(|&c| val(c)).collect());
        out.block_displacements
            .push(cols.d[i].iter().map(|c| c.map_or(0.0, val)).collect());
        out.modes.push(raw.modes[i].clone());
    }
    let x0 = out.states.first()?.clone();
    out.states.push(x0);
    Some(out)
}

/// The gait of the best durations, increments and states on `raw`'s sequence of slip modes
/// (module docs); `None` without a quadratic cost or when Clarabel finds no solution.
pub(super) fn polish_phases(
    crawler: &Crawler,
    problem: &GaitProblem,
    raw: &RawGait,
) -> Option<RawGait> {
    let Cost::Quadratic { weight } = problem.cost else {
        return None;
    };
    // After the deadline the MILP's answer stands (the polish is not part of the limit).
    if crate::progress::out_of_time().unwrap_or(true) {
        return None;
    }
    let (n, pieces) = (crawler.links(), raw.durations.len());
    if pieces == 0 {
        return None;
    }
    let t = problem.period;
    let v = block_speed_bound(crawler, problem);
    let mut qp = Qp::default();
    let cols = add_columns(&mut qp, crawler, problem, raw, (weight, v));
    for i in 0..pieces {
        add_piece_rows(&mut qp, crawler, problem, (raw, &cols, v), i);
    }
    qp.add_row(t, t, cols.tau.iter().map(|&c| (c, 1.0)).collect());
    for l in 0..n {
        qp.add_row(0.0, 0.0, cols.u.iter().map(|r| (r[l], 1.0)).collect());
    }
    let sol = qp.solve("the phase gait's polish").ok()?;
    read_gait(&sol.v, &cols, raw, t)
}
