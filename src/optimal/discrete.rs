//! The paper's discrete problem P_m (SPEC §6), solved globally as a mixed-integer linear program
//! in HiGHS.
//!
//! On the dyadic grid `h = T / 2^m` (`M = 2^m` steps), with `U^i = h u^i`:
//!
//! ```text
//! maximise   sum_i (1/N) sum_b D^i_b                       (f2 = 0)
//! subject to x^{i+1} = x^i + U^i - K sum_b D^i_b nu_b,     x^M = x^0         (catching-up)
//!            -mu_b^- <= F_b(x^{i+1}) <= mu_b^+                               (x^{i+1} in C)
//!            D^i_b = P^i_b - Q^i_b,  0 <= P <= Md zp,  0 <= Q <= Md zq,  zp + zq <= 1
//!            mu_b^+ - F_b(x^{i+1}) <= W_b (1 - zp^i_b),  F_b(x^{i+1}) + mu_b^- <= W_b (1 - zq^i_b)
//!            |U^i_l| <= a_l h,  sum_i U^i = 0,
//!            sum_b D^0_b >= sum_b D^i_b                                      (symmetry)
//! ```
//!
//! The dynamics with the sign and complementarity conditions are exactly the KKT system of the
//! catching-up projection (SPEC §4), which has a unique solution, so every feasible point is a
//! catching-up trajectory. Constants, all derived from C and the rate bounds:
//! - `W_b = mu_b^+ + mu_b^-`: the range of `F_b` over C, the largest slack of either face;
//! - `Md = h sqrt(sum_l 1/k_l) sqrt(sum_l a_l^2 / k_l)` bounds `|D^i_b|`: some block is free
//!   (`D = 0`) and `D_{b+1} - D_b = (v_b - x_b)/k_b`, so `|D_b| <= sum_l |v_l - x_l| / k_l
//!   <= sqrt(sum 1/k) |v - x|_{K^-1}`, and `|v - x|_{K^-1} <= |U|_{K^-1}` because `x^i` is in C
//!   and the projection is the nearest point;
//! - the time-shift symmetry of a periodic gait is broken by letting step 0 carry the largest
//!   displacement (a rotation of any optimum does).
//!
//! Every answer is re-verified by the simulator: the returned increments are played by
//! catching-up (the simulator's [`simulate`](crate::integrate::simulate)) from the returned initial state until the periodic regime, and the verified
//! displacement is the one reported.

use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::milp::{
    block_speed_bound, certify, check_supported, force_row, replay, solve_max,
};
use crate::optimal::{Certificate, GaitProblem};
use highs::RowProblem;
use serde::Serialize;

/// Largest `m` accepted (`2^m` steps).
pub const MAX_M: u32 = 16;

/// A solution of P_m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiscreteSolution {
    /// `m` (the grid has `2^m` steps).
    pub m: u32,
    /// `h = T / 2^m`.
    pub step: f64,
    /// What the MILP proves (its bound is on the optimum of P_m).
    pub certificate: Certificate,
    /// Displacement per period, re-verified by simulating the returned gait.
    pub verified_displacement: f64,
    /// Initial state `x^0` (on the limit cycle).
    pub initial_state: Vec<f64>,
    /// States `x^i` at the grid times `i h`, `i = 0..=2^m` (the last equals the first).
    pub states: Vec<Vec<f64>>,
    /// Controls `u^i` (force per time), one row per step.
    pub controls: Vec<Vec<f64>>,
    /// Block displacements `D^i_b` per step, from the simulation.
    pub block_displacements: Vec<Vec<f64>>,
}

/// Solves P_m globally (module docs). `time_limit` in seconds.
pub fn solve_discrete_global(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    time_limit: Option<f64>,
) -> Result<DiscreteSolution> {
    crawler.require_unique()?;
    if m > MAX_M {
        return Err(Error::invalid("m", m, format!("must be at most {MAX_M}")));
    }
    check_supported(problem, time_limit)?;
    let (n, nb) = (crawler.links(), crawler.blocks());
    let big_m = 1usize << m;
    let h = problem.period / big_m as f64;
    let (k, mp, mm) = (
        crawler.stiffness(),
        crawler.mu_forward(),
        crawler.mu_backward(),
    );
    let a = &problem.rate_bound;
    let md = h * block_speed_bound(crawler, problem);
    let ranges = crawler.link_force_ranges();

    let mut pb = RowProblem::default();
    let xs: Vec<Vec<highs::Col>> = (0..big_m)
        .map(|_| {
            ranges
                .iter()
                .map(|r| pb.add_column(0.0, r[0]..=r[1]))
                .collect()
        })
        .collect();
    let us: Vec<Vec<highs::Col>> = (0..big_m)
        .map(|_| {
            a.iter()
                .map(|&al| pb.add_column(0.0, -al * h..=al * h))
                .collect()
        })
        .collect();
    let inv_n = 1.0 / nb as f64;
    let mut ps = Vec::with_capacity(big_m);
    let mut qs = Vec::with_capacity(big_m);
    let mut zps = Vec::with_capacity(big_m);
    let mut zqs = Vec::with_capacity(big_m);
    for _ in 0..big_m {
        ps.push(
            (0..nb)
                .map(|_| pb.add_column(inv_n, 0.0..=md))
                .collect::<Vec<_>>(),
        );
        qs.push(
            (0..nb)
                .map(|_| pb.add_column(-inv_n, 0.0..=md))
                .collect::<Vec<_>>(),
        );
        zps.push(
            (0..nb)
                .map(|_| pb.add_integer_column(0.0, 0..=1))
                .collect::<Vec<_>>(),
        );
        zqs.push(
            (0..nb)
                .map(|_| pb.add_integer_column(0.0, 0..=1))
                .collect::<Vec<_>>(),
        );
    }
    for i in 0..big_m {
        let next = &xs[(i + 1) % big_m];
        // Dynamics: x^{i+1}_l - x^i_l - U^i_l + k_l (D_{l+1} - D_l) = 0.
        for l in 0..n {
            pb.add_row(
                0.0..=0.0,
                [
                    (next[l], 1.0),
                    (xs[i][l], -1.0),
                    (us[i][l], -1.0),
                    (ps[i][l + 1], k[l]),
                    (qs[i][l + 1], -k[l]),
                    (ps[i][l], -k[l]),
                    (qs[i][l], k[l]),
                ],
            );
        }
        for b in 0..nb {
            let f = force_row(next, b);
            let w = mp[b] + mm[b];
            pb.add_row(-mm[b]..=mp[b], &f);
            pb.add_row(..=0.0, [(ps[i][b], 1.0), (zps[i][b], -md)]);
            pb.add_row(..=0.0, [(qs[i][b], 1.0), (zqs[i][b], -md)]);
            pb.add_row(..=1.0, [(zps[i][b], 1.0), (zqs[i][b], 1.0)]);
            // mu^+ - F <= W (1 - zp)  <=>  -F + W zp <= mu^-.
            let mut row: Vec<(highs::Col, f64)> = f.iter().map(|&(c, v)| (c, -v)).collect();
            row.push((zps[i][b], w));
            pb.add_row(..=mm[b], &row);
            // F + mu^- <= W (1 - zq)  <=>  F + W zq <= mu^+.
            let mut row = f.clone();
            row.push((zqs[i][b], w));
            pb.add_row(..=mp[b], &row);
        }
        if i > 0 {
            // Symmetry: sum_b D^0_b - sum_b D^i_b >= 0.
            let mut row = Vec::with_capacity(4 * nb);
            for b in 0..nb {
                row.extend([
                    (ps[0][b], 1.0),
                    (qs[0][b], -1.0),
                    (ps[i][b], -1.0),
                    (qs[i][b], 1.0),
                ]);
            }
            pb.add_row(0.0.., &row);
        }
    }
    for l in 0..n {
        let row: Vec<(highs::Col, f64)> = us.iter().map(|u| (u[l], 1.0)).collect();
        pb.add_row(0.0..=0.0, &row);
    }
    let (cols, milp_objective, bound, status) = solve_max(pb, time_limit, &format!("P_{m}"))?;
    // The gait: clean the increments to exact zero mean within the bounds, then simulate it.
    let mut incs: Vec<f64> = Vec::with_capacity(big_m * n);
    for u in &us {
        incs.extend(u.iter().map(|c| cols[c.index()]));
    }
    for l in 0..n {
        let mean = (0..big_m).map(|i| incs[i * n + l]).sum::<f64>() / big_m as f64;
        for i in 0..big_m {
            incs[i * n + l] -= mean;
        }
    }
    let x0: Vec<f64> = xs[0].iter().map(|c| cols[c.index()]).collect();
    let what = format!("P_{m}");
    let rows: Vec<Vec<f64>> = incs.chunks(n).map(<[f64]>::to_vec).collect();
    let sim = replay(
        crawler,
        problem.period,
        &vec![h; big_m],
        &rows,
        &x0,
        Method::CatchingUp,
        &what,
    )?;
    let verified = sim.displacement_per_period.expect("converged");
    let tr = sim.trajectory.expect("one period recorded");
    Ok(DiscreteSolution {
        m,
        step: h,
        certificate: certify(&what, status, milp_objective, bound, verified)?,
        verified_displacement: verified,
        initial_state: sim.orbit_state,
        block_displacements: tr
            .positions
            .windows(2)
            .map(|w| w[1].iter().zip(&w[0]).map(|(a, b)| a - b).collect())
            .collect(),
        states: tr.x,
        controls: rows
            .iter()
            .map(|r| r.iter().map(|v| v / h).collect())
            .collect(),
    })
}
