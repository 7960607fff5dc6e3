//! The phase MILP's columns and rows (module docs of [`super`]).

use super::{link_work, Formulation};
use crate::model::Crawler;
use crate::optimal::milp::{block_speed_bound, force_row, TangentRates};
use crate::optimal::{Cost, GaitProblem};
use highs::{Col, RowProblem};

/// Rows beyond the model itself: the optional valid rows and a cutoff on `J` (in the units of
/// the problem built).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ExtraRows {
    pub formulation: Formulation,
    pub cutoff: Option<f64>,
}

/// Columns of the phase MILP: per phase `j`, a transition (`sigma_j`, `W_j`, from `x_j` to
/// `y_j`, every block sticking) followed by a slip segment (`tau_j`, `U_j`, from `y_j` to
/// `x_{j+1}`, in the mode of the binaries).
pub(super) struct Layout {
    pub(super) sigma: Vec<Col>,
    pub(super) tau: Vec<Col>,
    pub(super) used: Vec<Col>,
    pub(super) xs: Vec<Vec<Col>>,
    pub(super) ys: Vec<Vec<Col>>,
    pub(super) ws: Vec<Vec<Col>>,
    pub(super) us: Vec<Vec<Col>>,
    pub(super) ps: Vec<Vec<Col>>,
    pub(super) qs: Vec<Vec<Col>>,
    pub(super) sp: Vec<Vec<Col>>,
    pub(super) sq: Vec<Vec<Col>>,
    /// Cost epigraphs `g_{j,l} >= U_{j,l}^2 / tau_j` and `h_{j,l} >= W_{j,l}^2 / sigma_j`
    /// (quadratic cost only).
    pub(super) g: Vec<Vec<Col>>,
    pub(super) h: Vec<Vec<Col>>,
}

/// The MILP of `phases` steps; with `fixed`, the slip modes of the steps are fixed to it (an LP
/// over the gaits whose slip phases follow that cyclic sequence, some possibly empty), and the
/// symmetry rows, which would restrict a fixed sequence, are left out. `rows` adds the optional
/// valid rows and, with a cutoff, the row `J >= cutoff` on the MILP's objective. Columns first,
/// then each phase's rows, then the period's.
pub(super) fn build(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    rates: Option<&TangentRates>,
    fixed: Option<&[Vec<i8>]>,
    rows: &ExtraRows,
) -> (RowProblem, Layout) {
    let mut pb = RowProblem::default();
    let lay = columns(&mut pb, crawler, problem, phases, rates.is_some(), fixed);
    for j in 0..phases {
        phase_rows(&mut pb, &lay, crawler, problem, j, rates, fixed.is_some());
    }
    period_rows(&mut pb, &lay, crawler, problem, rows);
    (pb, lay)
}

/// The MILP's columns (the objective on the slips and the cost epigraphs, `epigraphs` with a
/// quadratic cost), with their bounds: durations within the period, states within the link
/// forces' ranges, increments within the rates, slips within the block speed bound; the slip
/// binaries fixed to `fixed`'s modes where given.
fn columns(
    pb: &mut RowProblem,
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    epigraphs: bool,
    fixed: Option<&[Vec<i8>]>,
) -> Layout {
    let nb = crawler.blocks();
    let (a, t) = (&problem.rate_bound, problem.period);
    let v = block_speed_bound(crawler, problem);
    let ranges = crawler.link_force_ranges();
    let inv_n = 1.0 / nb as f64;
    let weight = cost_weight(problem);
    let durations = |pb: &mut RowProblem| -> Vec<Col> {
        (0..phases).map(|_| pb.add_column(0.0, 0.0..=t)).collect()
    };
    let sigma = durations(pb);
    let tau = durations(pb);
    let used: Vec<Col> = (0..phases)
        .map(|_| {
            let lo = i32::from(fixed.is_some());
            pb.add_integer_column(0.0, lo..=1)
        })
        .collect();
    let states = |pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| {
                ranges
                    .iter()
                    .map(|r| pb.add_column(0.0, r[0]..=r[1]))
                    .collect()
            })
            .collect()
    };
    let xs = states(pb);
    let ys = states(pb);
    let increments = |pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| {
                a.iter()
                    .map(|&al| pb.add_column(0.0, -al * t..=al * t))
                    .collect()
            })
            .collect()
    };
    let ws = increments(pb);
    let us = increments(pb);
    let cols = |cost: f64, hi: f64, pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| (0..nb).map(|_| pb.add_column(cost, 0.0..=hi)).collect())
            .collect()
    };
    let ps = cols(inv_n, v * t, pb);
    let qs = cols(-inv_n, v * t, pb);
    let sp = slip_binaries(pb, phases, nb, fixed, 1);
    let sq = slip_binaries(pb, phases, nb, fixed, -1);
    let epigraph = |pb: &mut RowProblem| -> Vec<Vec<Col>> {
        if !epigraphs {
            return Vec::new();
        }
        (0..phases)
            .map(|_| {
                a.iter()
                    .map(|&al| pb.add_column(-0.5 * weight, 0.0..=al * al * t))
                    .collect()
            })
            .collect()
    };
    let g = epigraph(pb);
    let h = epigraph(pb);
    Layout {
        sigma,
        tau,
        used,
        xs,
        ys,
        ws,
        us,
        ps,
        qs,
        sp,
        sq,
        g,
        h,
    }
}

/// The quadratic cost's weight, 0 without a cost.
fn cost_weight(problem: &GaitProblem) -> f64 {
    match problem.cost {
        Cost::Quadratic { weight } => weight,
        Cost::None => 0.0,
    }
}

/// The rows of phase `j`: its durations and increments within the rates, the transition (every
/// block sticking) and the slip segment's dynamics, the force bounds and the slip modes' big-M
/// rows, at most `n` blocks slipping, a used phase holding a face, the cost's tangent cuts
/// (`rates`), and, unless the modes are `fixed`, the symmetry rows (empty phases last, phase 0
/// first in the order of net slips).
fn phase_rows(
    pb: &mut RowProblem,
    lay: &Layout,
    crawler: &Crawler,
    problem: &GaitProblem,
    j: usize,
    rates: Option<&TangentRates>,
    fixed: bool,
) {
    let (n, nb, k) = (crawler.links(), crawler.blocks(), crawler.stiffness());
    let (a, t) = (&problem.rate_bound, problem.period);
    let v = block_speed_bound(crawler, problem);
    let phases = lay.xs.len();
    let Layout {
        sigma,
        tau,
        used,
        xs,
        ys,
        ws,
        us,
        ps,
        qs,
        sp,
        sq,
        g,
        h,
    } = lay;
    let next = &xs[(j + 1) % phases];
    // Empty phases last.
    pb.add_row(..=0.0, [(sigma[j], 1.0), (tau[j], 1.0), (used[j], -t)]);
    if j + 1 < phases && !fixed {
        pb.add_row(..=0.0, [(used[j + 1], 1.0), (used[j], -1.0)]);
    }
    for l in 0..n {
        pb.add_row(..=0.0, [(ws[j][l], 1.0), (sigma[j], -a[l])]);
        pb.add_row(..=0.0, [(ws[j][l], -1.0), (sigma[j], -a[l])]);
        pb.add_row(..=0.0, [(us[j][l], 1.0), (tau[j], -a[l])]);
        pb.add_row(..=0.0, [(us[j][l], -1.0), (tau[j], -a[l])]);
        // Transition: every block sticks.
        pb.add_row(
            0.0..=0.0,
            [(ys[j][l], 1.0), (xs[j][l], -1.0), (ws[j][l], -1.0)],
        );
        pb.add_row(
            0.0..=0.0,
            [
                (next[l], 1.0),
                (ys[j][l], -1.0),
                (us[j][l], -1.0),
                (ps[j][l + 1], k[l]),
                (qs[j][l + 1], -k[l]),
                (ps[j][l], -k[l]),
                (qs[j][l], k[l]),
            ],
        );
        if let Some(r) = rates {
            r.add_cuts(pb, l, g[j][l], us[j][l], Some(tau[j]), 0.0);
            r.add_cuts(pb, l, h[j][l], ws[j][l], Some(sigma[j]), 0.0);
        }
    }
    let mut slipping = Vec::with_capacity(2 * nb);
    for b in 0..nb {
        block_rows(pb, lay, crawler, (v, t), j, b);
        slipping.extend([(sp[j][b], 1.0), (sq[j][b], 1.0)]);
    }
    // At most n blocks slip (module docs).
    pb.add_row(..=n as f64, slipping.clone());
    // A used phase holds a face: an all-stick slip segment would merge into the next
    // transition.
    slipping.push((used[j], -1.0));
    pb.add_row(0.0.., slipping);
    if j > 0 && !fixed {
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

/// Block `b`'s rows in phase `j`: its force within the friction bounds at both ends of the
/// transition, its slips within the speed bound `v` (over `tau_j`, and over the period `t`
/// unless their binary is set), one direction at a time, and the slip modes' big-M rows at
/// both ends of the slip segment.
fn block_rows(
    pb: &mut RowProblem,
    lay: &Layout,
    crawler: &Crawler,
    (v, t): (f64, f64),
    j: usize,
    b: usize,
) {
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    let (xs, ys, ps, qs, sp, sq, tau) = (
        &lay.xs, &lay.ys, &lay.ps, &lay.qs, &lay.sp, &lay.sq, &lay.tau,
    );
    let next = &xs[(j + 1) % xs.len()];
    let w = mp[b] + mm[b];
    pb.add_row(-mm[b]..=mp[b], force_row(&xs[j], b));
    pb.add_row(-mm[b]..=mp[b], force_row(&ys[j], b));
    pb.add_row(..=0.0, [(ps[j][b], 1.0), (tau[j], -v)]);
    pb.add_row(..=0.0, [(qs[j][b], 1.0), (tau[j], -v)]);
    pb.add_row(..=0.0, [(ps[j][b], 1.0), (sp[j][b], -v * t)]);
    pb.add_row(..=0.0, [(qs[j][b], 1.0), (sq[j][b], -v * t)]);
    pb.add_row(..=1.0, [(sp[j][b], 1.0), (sq[j][b], 1.0)]);
    for x in [&ys[j], next] {
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

/// The slip binaries of direction `sign` per phase and block, fixed to `fixed`'s modes where
/// given.
fn slip_binaries(
    pb: &mut RowProblem,
    phases: usize,
    nb: usize,
    fixed: Option<&[Vec<i8>]>,
    sign: i8,
) -> Vec<Vec<Col>> {
    (0..phases)
        .map(|j| {
            (0..nb)
                .map(|b| match fixed {
                    Some(m) => {
                        let v = i32::from(m[j][b] == sign);
                        pb.add_integer_column(0.0, v..=v)
                    }
                    None => pb.add_integer_column(0.0, 0..=1),
                })
                .collect()
        })
        .collect()
}

/// The period's rows: the durations fill it, the increments have zero mean, and `rows`' extras
/// (the dissipation row, a cutoff on `J`).
fn period_rows(
    pb: &mut RowProblem,
    lay: &Layout,
    crawler: &Crawler,
    problem: &GaitProblem,
    rows: &ExtraRows,
) {
    let (n, nb) = (crawler.links(), crawler.blocks());
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    let t = problem.period;
    let phases = lay.xs.len();
    let inv_n = 1.0 / nb as f64;
    let weight = cost_weight(problem);
    let Layout {
        sigma,
        tau,
        ws,
        us,
        ps,
        qs,
        g,
        h,
        ..
    } = lay;
    pb.add_row(
        t..=t,
        tau.iter()
            .chain(sigma.iter())
            .map(|&c| (c, 1.0))
            .collect::<Vec<_>>(),
    );
    for l in 0..n {
        pb.add_row(
            0.0..=0.0,
            us.iter()
                .chain(ws.iter())
                .map(|u| (u[l], 1.0))
                .collect::<Vec<_>>(),
        );
    }
    if rows.formulation.dissipation_row_for(crawler) {
        // Friction dissipates the actuators' work, at most T sum_l a_l w_l / (2 k_l) (the
        // work bound).
        let work = link_work(crawler, problem);
        let mut row = Vec::with_capacity(2 * nb * phases);
        for j in 0..phases {
            for b in 0..nb {
                row.extend([(ps[j][b], mp[b]), (qs[j][b], mm[b])]);
            }
        }
        pb.add_row(..=t * work, row);
    }
    if let Some(cut) = rows.cutoff {
        let mut row = Vec::with_capacity(2 * nb * phases + 2 * n * phases);
        for j in 0..phases {
            for b in 0..nb {
                row.extend([(ps[j][b], inv_n), (qs[j][b], -inv_n)]);
            }
        }
        for e in g.iter().chain(h.iter()) {
            row.extend(e.iter().map(|&c| (c, -0.5 * weight)));
        }
        pb.add_row(cut.., row);
    }
}
