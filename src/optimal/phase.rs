//! Exact continuous-time gaits: the phase formulation (SPEC §7), solved globally over gaits of
//! at most `K` phases as a mixed-integer linear program in HiGHS.
//!
//! Phase `j` lasts `tau_j >= 0` with a constant control `u_j` and a slip mode per block
//! (stick, slip+, slip-), encoded by binaries `s+_{j,b}`, `s-_{j,b}` (`s+ + s- <= 1`). With
//! `U_j = tau_j u_j`, states `x_j` at phase starts and block displacements `D_{j,b} = P - Q`:
//!
//! ```text
//! maximise   (1/N) sum_{j,b} D_{j,b}
//! subject to x_{j+1} = x_j + U_j - K sum_b D_{j,b} nu_b,   x_K = x_0,   x_j in C
//!            |U_{j,l}| <= a_l tau_j,   sum_j tau_j = T,   sum_j U_j = 0
//!            0 <= P_{j,b} <= V tau_j,  P_{j,b} <= V T s+_{j,b}      (likewise Q with s-)
//!            s+_{j,b} = 1  =>  F_b(x_j) = F_b(x_{j+1}) = mu_b^+     (big-M W_b = mu^+ + mu^-)
//!            s-_{j,b} = 1  =>  F_b(x_j) = F_b(x_{j+1}) = -mu_b^-
//! ```
//!
//! Every feasible point is an exact solution of the sweeping process: inside a phase `x` moves
//! on the segment `[x_j, x_{j+1}]` (in C, which is convex) at constant velocity, the faces of the
//! slipping blocks are held throughout (both ends lie on them), and the reaction
//! `K sum_b D_{j,b} nu_b` is in their normal cone; solutions being unique, it is *the* solution.
//! So there is no discretisation error. `V` is the block-speed bound of
//! [`block_speed_bound`](super::milp) (no motion in zero time). Symmetries are broken: empty
//! phases come last, and among the rest phase 0 carries the largest displacement.
//!
//! Every answer is re-verified by [`simulate`] (exact method) on the piecewise-linear actuation
//! whose knots are the phase boundaries.

use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::milp::{
    block_speed_bound, certify, check_supported, force_row, replay, solve_max,
};
use crate::optimal::{Certificate, GaitProblem};
use highs::{Col, RowProblem};
use serde::Serialize;

/// Largest number of phases accepted.
pub const MAX_PHASES: usize = 64;

/// A gait of at most `K` phases, globally optimal among them (or with its gap).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseSolution {
    /// `K`, the number of phases allowed.
    pub phases: usize,
    /// What the MILP proves (its bound is over gaits of at most `phases` phases).
    pub certificate: Certificate,
    /// Displacement per period re-verified by the exact simulator.
    pub verified_displacement: f64,
    /// Phase durations `tau_j` (empty phases removed).
    pub durations: Vec<f64>,
    /// Controls `u_j` per phase.
    pub controls: Vec<Vec<f64>>,
    /// States `x_j` at the phase starts (and the end, equal to the start).
    pub states: Vec<Vec<f64>>,
    /// Block displacements per phase.
    pub block_displacements: Vec<Vec<f64>>,
    /// Slip mode per phase and block: -1, 0, 1.
    pub modes: Vec<Vec<i8>>,
}

/// Solves (P) globally over gaits of at most `phases` phases (module docs).
pub fn solve_phase_global(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
) -> Result<PhaseSolution> {
    crawler.require_unique()?;
    check_supported(problem, time_limit)?;
    if !(2..=MAX_PHASES).contains(&phases) {
        return Err(Error::invalid(
            "phases",
            phases,
            format!("must be in 2..={MAX_PHASES}"),
        ));
    }
    let (n, nb) = (crawler.links(), crawler.blocks());
    let (k, mp, mm) = (
        crawler.stiffness(),
        crawler.mu_forward(),
        crawler.mu_backward(),
    );
    let (a, t) = (&problem.rate_bound, problem.period);
    let v = block_speed_bound(crawler, problem);
    let ranges = crawler.link_force_ranges();
    let inv_n = 1.0 / nb as f64;

    let mut pb = RowProblem::default();
    let tau: Vec<Col> = (0..phases).map(|_| pb.add_column(0.0, 0.0..=t)).collect();
    let used: Vec<Col> = (0..phases)
        .map(|_| pb.add_integer_column(0.0, 0..=1))
        .collect();
    let xs: Vec<Vec<Col>> = (0..phases)
        .map(|_| {
            ranges
                .iter()
                .map(|r| pb.add_column(0.0, r[0]..=r[1]))
                .collect()
        })
        .collect();
    let us: Vec<Vec<Col>> = (0..phases)
        .map(|_| {
            a.iter()
                .map(|&al| pb.add_column(0.0, -al * t..=al * t))
                .collect()
        })
        .collect();
    let mut ps = Vec::new();
    let mut qs = Vec::new();
    let mut sp = Vec::new();
    let mut sq = Vec::new();
    for _ in 0..phases {
        ps.push(
            (0..nb)
                .map(|_| pb.add_column(inv_n, 0.0..=v * t))
                .collect::<Vec<_>>(),
        );
        qs.push(
            (0..nb)
                .map(|_| pb.add_column(-inv_n, 0.0..=v * t))
                .collect::<Vec<_>>(),
        );
        sp.push(
            (0..nb)
                .map(|_| pb.add_integer_column(0.0, 0..=1))
                .collect::<Vec<_>>(),
        );
        sq.push(
            (0..nb)
                .map(|_| pb.add_integer_column(0.0, 0..=1))
                .collect::<Vec<_>>(),
        );
    }
    for j in 0..phases {
        let next = &xs[(j + 1) % phases];
        // Empty phases last.
        pb.add_row(..=0.0, [(tau[j], 1.0), (used[j], -t)]);
        if j + 1 < phases {
            pb.add_row(..=0.0, [(used[j + 1], 1.0), (used[j], -1.0)]);
        }
        for l in 0..n {
            pb.add_row(..=0.0, [(us[j][l], 1.0), (tau[j], -a[l])]);
            pb.add_row(..=0.0, [(us[j][l], -1.0), (tau[j], -a[l])]);
            pb.add_row(
                0.0..=0.0,
                [
                    (next[l], 1.0),
                    (xs[j][l], -1.0),
                    (us[j][l], -1.0),
                    (ps[j][l + 1], k[l]),
                    (qs[j][l + 1], -k[l]),
                    (ps[j][l], -k[l]),
                    (qs[j][l], k[l]),
                ],
            );
        }
        for b in 0..nb {
            let w = mp[b] + mm[b];
            pb.add_row(-mm[b]..=mp[b], force_row(&xs[j], b));
            pb.add_row(..=0.0, [(ps[j][b], 1.0), (tau[j], -v)]);
            pb.add_row(..=0.0, [(qs[j][b], 1.0), (tau[j], -v)]);
            pb.add_row(..=0.0, [(ps[j][b], 1.0), (sp[j][b], -v * t)]);
            pb.add_row(..=0.0, [(qs[j][b], 1.0), (sq[j][b], -v * t)]);
            pb.add_row(..=1.0, [(sp[j][b], 1.0), (sq[j][b], 1.0)]);
            for x in [&xs[j], next] {
                // slip+: F_b >= mu^+ - W (1 - s+)  <=>  F_b - W s+ >= -mu^-.
                let mut row = force_row(x, b);
                row.push((sp[j][b], -w));
                pb.add_row(-mm[b].., row);
                // slip-: F_b <= -mu^- + W (1 - s-)  <=>  F_b + W s- <= mu^+.
                let mut row = force_row(x, b);
                row.push((sq[j][b], w));
                pb.add_row(..=mp[b], row);
            }
        }
        if j > 0 {
            let mut row = Vec::with_capacity(4 * nb);
            for b in 0..nb {
                row.extend([
                    (ps[0][b], 1.0),
                    (qs[0][b], -1.0),
                    (ps[j][b], -1.0),
                    (qs[j][b], 1.0),
                ]);
            }
            pb.add_row(0.0.., row);
        }
    }
    pb.add_row(t..=t, tau.iter().map(|&c| (c, 1.0)).collect::<Vec<_>>());
    for l in 0..n {
        pb.add_row(
            0.0..=0.0,
            us.iter().map(|u| (u[l], 1.0)).collect::<Vec<_>>(),
        );
    }
    let what = format!("{phases}-phase gait");
    let (cols, milp_objective, bound, status) = solve_max(pb, time_limit, &what)?;
    let val = |c: &Col| cols[c.index()];

    // The gait without its empty phases.
    let keep: Vec<usize> = (0..phases).filter(|&j| val(&tau[j]) > 1e-12 * t).collect();
    let durations: Vec<f64> = keep.iter().map(|&j| val(&tau[j])).collect();
    let incs: Vec<Vec<f64>> = keep
        .iter()
        .map(|&j| us[j].iter().map(val).collect())
        .collect();
    let x0: Vec<f64> = xs[keep.first().copied().unwrap_or(0)]
        .iter()
        .map(val)
        .collect();
    let verified = if keep.len() < 2 {
        0.0
    } else {
        replay(crawler, t, &durations, &incs, &x0, Method::Exact, &what)?
            .displacement_per_period
            .expect("converged")
    };
    let certificate = certify(&what, status, milp_objective, bound, verified)?;
    let mut states: Vec<Vec<f64>> = keep
        .iter()
        .map(|&j| xs[j].iter().map(val).collect())
        .collect();
    states.push(x0);
    let block_displacements: Vec<Vec<f64>> = keep
        .iter()
        .map(|&j| (0..nb).map(|b| val(&ps[j][b]) - val(&qs[j][b])).collect())
        .collect();
    let modes = keep
        .iter()
        .map(|&j| {
            (0..nb)
                .map(|b| match (val(&sp[j][b]) > 0.5, val(&sq[j][b]) > 0.5) {
                    (true, _) => 1,
                    (_, true) => -1,
                    _ => 0,
                })
                .collect()
        })
        .collect();
    Ok(PhaseSolution {
        phases,
        certificate,
        verified_displacement: verified,
        controls: incs
            .iter()
            .zip(&durations)
            .map(|(u, d)| u.iter().map(|v| v / d).collect())
            .collect(),
        durations,
        states,
        block_displacements,
        modes,
    })
}
