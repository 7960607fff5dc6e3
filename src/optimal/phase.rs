//! Exact continuous-time gaits: the phase formulation (theory §7), solved globally over gaits of
//! at most `K` slip phases as a mixed-integer linear program in HiGHS.
//!
//! **What `K` counts.** A phase is a stretch of constant control and constant slip mode. A
//! phase in which every block sticks (a *transition*: `x` moves straight across C, `x' = u`) is
//! not counted: two consecutive transitions merge into one (C is convex, the rate bounds are
//! convex, nothing moves), and so do two consecutive slip phases of the same mode (their faces
//! are held throughout). So every gait whose slip phases number at most `K`, with any number
//! of transitions between them, is a gait of `K` *steps* `j`, each a transition followed by a
//! slip phase:
//!
//! ```text
//! x_j --(transition: sigma_j, W_j, all stick)--> y_j --(slip: tau_j, U_j, mode)--> x_{j+1}
//! ```
//!
//! A `K`-step gait has at most `2K` phases, and every gait of at most `K` phases is dominated
//! by one (its runs merged: the same displacement, no more cost), so "global among gaits of at
//! most `K` slip phases" is the stronger statement. Counting this way needs up to half the `K`
//! (the three-block optimum has 4 slip phases and 4 transitions, where phases counted 8), and
//! the MILP's effort grows steeply with `K`: on the three-block instance the growth certified
//! the optimum in 4.9 s instead of 10.3 s, before any other change (`crawlopt optimize
//! examples/three_blocks_gait.toml`). An optimum whose slip phases follow each other without
//! transitions needs as many steps as it has phases, and each step carries an unused
//! transition, so such MILPs are larger than before for the same `K`.
//!
//! Binaries `s+_{j,b}`, `s-_{j,b}` (`s+ + s- <= 1`) give the mode of slip phase `j`. With
//! `U_j = tau_j u_j`, `W_j = sigma_j w_j` and block displacements `D_{j,b} = P - Q`:
//!
//! ```text
//! maximise   (1/N) sum_{j,b} D_{j,b} - (c/2) sum_{j,l} (g_{j,l} + h_{j,l})
//!                                        (g >= U^2 / tau, h >= W^2 / sigma)
//! subject to y_j = x_j + W_j,   x_{j+1} = y_j + U_j - K sum_b D_{j,b} nu_b,   x_K = x_0
//!            x_j, y_j in C,   |W_{j,l}| <= a_l sigma_j,   |U_{j,l}| <= a_l tau_j
//!            sum_j (sigma_j + tau_j) = T,   sum_j (W_j + U_j) = 0
//!            0 <= P_{j,b} <= V tau_j,  P_{j,b} <= V T s+_{j,b}      (likewise Q with s-)
//!            s+_{j,b} = 1  =>  F_b(y_j) = F_b(x_{j+1}) = mu_b^+     (big-M W_b = mu^+ + mu^-)
//!            s-_{j,b} = 1  =>  F_b(y_j) = F_b(x_{j+1}) = -mu_b^-
//! ```
//!
//! Every feasible point is an exact solution of the sweeping process: in a transition `x`
//! moves on `[x_j, y_j]` (in C) with every block sticking, which is always admissible; in a slip
//! phase `x` moves on `[y_j, x_{j+1}]` at constant velocity, the faces of the slipping blocks
//! are held throughout (both ends lie on them) and the reaction `K sum_b D_{j,b} nu_b` is in
//! their normal cone; solutions being unique, it is *the* solution. So there is no
//! discretisation error. `V` is the block-speed bound of
//! [`block_speed_bound`](super::milp) (no motion in zero time).
//!
//! Symmetries are broken: unused steps come last, a used step holds at least one face (an
//! all-stick slip phase would merge into the next transition; an idle gait is a gait held on a
//! face with `D = 0`), and among the used steps step 0 carries the largest displacement.
//! Valid inequalities: at most `n` blocks slip in a phase (if all `N` did, the forces would sum
//! to `sum_b ±mu_b = 0`, which the uniqueness condition excludes). Tried and dropped, measured
//! on the same instance: a bound on the barycentre speed (it halves the root bound, from 20 to
//! 10.5, but the `K = 5` proof took 1.1 s instead of 0.75 s).
//!
//! The quadratic cost is the perspective `(c/2) |U_j|^2 / tau_j` (likewise for `W_j`), handled
//! by outer approximation ([`TangentRates`]): tangent cuts under-estimate it, so the MILP's
//! bound stays valid; cuts at the rates of each solution are added and the MILP re-solved (from
//! the previous gait) until the true objective of the incumbent meets the bound. A
//! total-variation bound on `u = U / tau` is not linear in these variables and is refused (the
//! discrete method has it).
//!
//! [`grow_phases`] raises `K` until the value stops improving, each MILP starting from the
//! previous optimum, so it has an incumbent from the outset.
//!
//! [`search_sequences`] is the local alternative where the MILP is too slow: the same model
//! with the slip modes fixed is an LP, and it searches over the sequences of modes.
//!
//! Every answer is re-verified by [`simulate`] (exact method) on the piecewise-linear actuation
//! whose knots are the phase boundaries (transitions and slip phases alike).

use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::milp::{
    block_speed_bound, certify, check_time_limit, force_row, replay, solve_max, TangentRates,
    OA_TOL,
};
use crate::optimal::units::Units;
use crate::optimal::{Certificate, Cost, GaitProblem, LocalStop, MilpStatus};
use highs::{Col, RowProblem};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Largest `K` (slip phases) accepted.
pub const MAX_PHASES: usize = 64;

/// Outer-approximation rounds at most (each a MILP solve).
const MAX_OA_ROUNDS: usize = 40;

/// A gait of at most `K` slip phases, globally optimal among them (or with its gap).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseSolution {
    /// `K`, the number of slip phases allowed (transitions between them are not counted).
    pub phases: usize,
    /// What the MILP proves (its bound is on `J` over gaits of at most `phases` slip phases).
    pub certificate: Certificate,
    /// Displacement per period re-verified by the exact simulator.
    pub verified_displacement: f64,
    /// `int f2(u) dt` of the gait.
    pub actuation_cost: f64,
    /// Phase durations, transitions and slip phases in time order (empty ones removed).
    pub durations: Vec<f64>,
    /// Controls `u_j` per phase.
    pub controls: Vec<Vec<f64>>,
    /// States `x_j` at the phase starts (and the end, equal to the start).
    pub states: Vec<Vec<f64>>,
    /// Block displacements per phase.
    pub block_displacements: Vec<Vec<f64>>,
    /// Slip mode per phase and block: -1, 0, 1.
    pub modes: Vec<Vec<i8>>,
    /// MILP solves (outer-approximation rounds for a quadratic cost, else 1).
    pub rounds: usize,
}

impl PhaseSolution {
    /// `J` = verified displacement minus actuation cost.
    pub fn objective(&self) -> f64 {
        self.verified_displacement - self.actuation_cost
    }
}

/// Columns of the phase MILP: per phase `j`, a transition (`sigma_j`, `W_j`, from `x_j` to
/// `y_j`, every block sticking) followed by a slip segment (`tau_j`, `U_j`, from `y_j` to
/// `x_{j+1}`, in the mode of the binaries).
struct Layout {
    sigma: Vec<Col>,
    tau: Vec<Col>,
    used: Vec<Col>,
    xs: Vec<Vec<Col>>,
    ys: Vec<Vec<Col>>,
    ws: Vec<Vec<Col>>,
    us: Vec<Vec<Col>>,
    ps: Vec<Vec<Col>>,
    qs: Vec<Vec<Col>>,
    sp: Vec<Vec<Col>>,
    sq: Vec<Vec<Col>>,
    /// Cost epigraphs `g_{j,l} >= U_{j,l}^2 / tau_j` and `h_{j,l} >= W_{j,l}^2 / sigma_j`
    /// (quadratic cost only).
    g: Vec<Vec<Col>>,
    h: Vec<Vec<Col>>,
}

/// The MILP of `phases` steps; with `fixed`, the slip modes of the steps are fixed to it (an LP
/// over the gaits whose slip phases follow that cyclic sequence, some possibly empty), and the
/// symmetry rows, which would restrict a fixed sequence, are left out.
fn build(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    rates: Option<&TangentRates>,
    fixed: Option<&[Vec<i8>]>,
) -> (RowProblem, Layout) {
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
    let weight = match problem.cost {
        Cost::Quadratic { weight } => weight,
        Cost::None => 0.0,
    };

    let mut pb = RowProblem::default();
    let durations = |pb: &mut RowProblem| -> Vec<Col> {
        (0..phases).map(|_| pb.add_column(0.0, 0.0..=t)).collect()
    };
    let sigma = durations(&mut pb);
    let tau = durations(&mut pb);
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
    let xs = states(&mut pb);
    let ys = states(&mut pb);
    let increments = |pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| {
                a.iter()
                    .map(|&al| pb.add_column(0.0, -al * t..=al * t))
                    .collect()
            })
            .collect()
    };
    let ws = increments(&mut pb);
    let us = increments(&mut pb);
    let cols = |cost: f64, hi: f64, pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| (0..nb).map(|_| pb.add_column(cost, 0.0..=hi)).collect())
            .collect()
    };
    let ps = cols(inv_n, v * t, &mut pb);
    let qs = cols(-inv_n, v * t, &mut pb);
    let bins = |pb: &mut RowProblem, sign: i8| -> Vec<Vec<Col>> {
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
    };
    let sp = bins(&mut pb, 1);
    let sq = bins(&mut pb, -1);
    let epigraphs = |pb: &mut RowProblem| -> Vec<Vec<Col>> {
        if rates.is_none() {
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
    let g = epigraphs(&mut pb);
    let h = epigraphs(&mut pb);
    for j in 0..phases {
        let next = &xs[(j + 1) % phases];
        // Empty phases last.
        pb.add_row(..=0.0, [(sigma[j], 1.0), (tau[j], 1.0), (used[j], -t)]);
        if j + 1 < phases && fixed.is_none() {
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
                r.add_cuts(&mut pb, l, g[j][l], us[j][l], Some(tau[j]), 0.0);
                r.add_cuts(&mut pb, l, h[j][l], ws[j][l], Some(sigma[j]), 0.0);
            }
        }
        let mut slipping = Vec::with_capacity(2 * nb);
        for b in 0..nb {
            let w = mp[b] + mm[b];
            pb.add_row(-mm[b]..=mp[b], force_row(&xs[j], b));
            pb.add_row(-mm[b]..=mp[b], force_row(&ys[j], b));
            pb.add_row(..=0.0, [(ps[j][b], 1.0), (tau[j], -v)]);
            pb.add_row(..=0.0, [(qs[j][b], 1.0), (tau[j], -v)]);
            pb.add_row(..=0.0, [(ps[j][b], 1.0), (sp[j][b], -v * t)]);
            pb.add_row(..=0.0, [(qs[j][b], 1.0), (sq[j][b], -v * t)]);
            pb.add_row(..=1.0, [(sp[j][b], 1.0), (sq[j][b], 1.0)]);
            slipping.extend([(sp[j][b], 1.0), (sq[j][b], 1.0)]);
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
        // At most n blocks slip (module docs).
        pb.add_row(..=n as f64, slipping.clone());
        // A used phase holds a face: an all-stick slip segment would merge into the next
        // transition.
        slipping.push((used[j], -1.0));
        pb.add_row(0.0.., slipping);
        if j > 0 && fixed.is_none() {
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
    pb.add_row(
        t..=t,
        tau.iter()
            .chain(&sigma)
            .map(|&c| (c, 1.0))
            .collect::<Vec<_>>(),
    );
    for l in 0..n {
        pb.add_row(
            0.0..=0.0,
            us.iter()
                .chain(&ws)
                .map(|u| (u[l], 1.0))
                .collect::<Vec<_>>(),
        );
    }
    let layout = Layout {
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
    };
    (pb, layout)
}

/// A gait read off the MILP's columns, empty phases removed.
#[derive(Default)]
struct RawGait {
    durations: Vec<f64>,
    increments: Vec<Vec<f64>>,
    states: Vec<Vec<f64>>,
    block_displacements: Vec<Vec<f64>>,
    modes: Vec<Vec<i8>>,
}

impl RawGait {
    /// Reads the gait: each used phase gives its transition and its slip segment, those of
    /// positive duration, in order.
    fn read(lay: &Layout, cols: &[f64], t: f64) -> Self {
        let val = |c: &Col| cols[c.index()];
        let vals = |cs: &[Col]| -> Vec<f64> { cs.iter().map(val).collect() };
        let nb = lay.ps.first().map_or(0, Vec::len);
        let mut g = RawGait::default();
        for j in 0..lay.tau.len() {
            let sigma = val(&lay.sigma[j]);
            if sigma > 1e-12 * t {
                g.durations.push(sigma);
                g.increments.push(vals(&lay.ws[j]));
                g.states.push(vals(&lay.xs[j]));
                g.block_displacements.push(vec![0.0; nb]);
                g.modes.push(vec![0; nb]);
            }
            let tau = val(&lay.tau[j]);
            if tau > 1e-12 * t {
                g.durations.push(tau);
                g.increments.push(vals(&lay.us[j]));
                g.states.push(vals(&lay.ys[j]));
                g.block_displacements.push(
                    lay.ps[j]
                        .iter()
                        .zip(&lay.qs[j])
                        .map(|(p, q)| val(p) - val(q))
                        .collect(),
                );
                g.modes.push(
                    lay.sp[j]
                        .iter()
                        .zip(&lay.sq[j])
                        .map(|(p, q)| match (val(p) > 0.5, val(q) > 0.5) {
                            (true, _) => 1,
                            (_, true) => -1,
                            _ => 0,
                        })
                        .collect(),
                );
            }
        }
        let x0 = g
            .states
            .first()
            .cloned()
            .unwrap_or_else(|| vals(&lay.xs[0]));
        g.states.push(x0);
        g
    }

    /// Number of slip phases, runs of one mode merged cyclically (what `K` counts).
    fn slip_phases(&self) -> usize {
        slip_sequence(&self.modes).len()
    }

    /// The same gait with each run of consecutive phases of one mode (all-stick runs included)
    /// merged into one phase, cyclically: the run's duration, increment and displacements are
    /// summed and `x` goes straight from the run's first state to its last. For an all-stick
    /// run that is a straight move inside the convex C with every block sticking; for a slip
    /// run the faces are held at both ends, hence on the segment. Displacements are unchanged
    /// and, by convexity, so is or drops the cost.
    fn merged(&self) -> RawGait {
        let p = self.durations.len();
        let first = (0..p)
            .find(|&j| self.modes[j] != self.modes[(j + p - 1) % p])
            .unwrap_or(0);
        let mut g = RawGait::default();
        for i in 0..p {
            let j = (first + i) % p;
            if i > 0 && g.modes.last() == Some(&self.modes[j]) {
                let last = g.durations.len() - 1;
                g.durations[last] += self.durations[j];
                for (a, b) in g.increments[last].iter_mut().zip(&self.increments[j]) {
                    *a += b;
                }
                for (a, b) in g.block_displacements[last]
                    .iter_mut()
                    .zip(&self.block_displacements[j])
                {
                    *a += b;
                }
            } else {
                g.durations.push(self.durations[j]);
                g.increments.push(self.increments[j].clone());
                g.states.push(self.states[j].clone());
                g.block_displacements
                    .push(self.block_displacements[j].clone());
                g.modes.push(self.modes[j].clone());
            }
        }
        if let Some(x0) = g.states.first().cloned() {
            g.states.push(x0);
        }
        g
    }

    fn displacement(&self) -> f64 {
        self.block_displacements
            .iter()
            .map(|d| d.iter().sum::<f64>() / d.len() as f64)
            .sum()
    }

    fn cost(&self, problem: &GaitProblem) -> f64 {
        self.durations
            .iter()
            .zip(&self.increments)
            .map(|(&d, u)| {
                let rate: Vec<f64> = u.iter().map(|v| v / d).collect();
                d * problem.cost.eval(&rate)
            })
            .sum()
    }

    /// All columns of a `K`-step layout holding this gait, with exact cost epigraphs: a
    /// feasible start for the MILP, or `None` when no block ever holds a face (an idle gait,
    /// which the layout writes differently) or the gait has too many slip phases.
    ///
    /// The gait is rotated to start just after a slip phase; each run of all-stick phases
    /// becomes one transition (a straight move of `x` inside the convex C, every block
    /// sticking, with the run's total increment and duration), followed by its slip phase.
    /// The phase of largest displacement goes first, as the symmetry rows require, and unused
    /// phases come last.
    fn columns(&self, lay: &Layout, ncols: usize) -> Option<Vec<f64>> {
        self.merged().columns_merged(lay, ncols)
    }

    /// [`RawGait::columns`] of a gait whose runs are merged.
    fn columns_merged(&self, lay: &Layout, ncols: usize) -> Option<Vec<f64>> {
        let p = self.durations.len();
        let slips: Vec<usize> = (0..p)
            .filter(|&j| self.modes[j].iter().any(|&s| s != 0))
            .collect();
        let last = *slips.last()?;
        if slips.len() > lay.tau.len() {
            return None;
        }
        let n = self.increments[0].len();
        // (sigma, W, x, slip phase index)
        let mut macros: Vec<(f64, Vec<f64>, Vec<f64>, usize)> = Vec::new();
        let (mut sigma, mut w, mut x0): (f64, Vec<f64>, Option<&Vec<f64>>) =
            (0.0, vec![0.0; n], None);
        for i in 1..=p {
            let j = (last + i) % p;
            if self.modes[j].iter().any(|&s| s != 0) {
                let x = x0.unwrap_or(&self.states[j]).clone();
                macros.push((sigma, w, x, j));
                (sigma, w, x0) = (0.0, vec![0.0; n], None);
            } else {
                sigma += self.durations[j];
                for (wl, ul) in w.iter_mut().zip(&self.increments[j]) {
                    *wl += ul;
                }
                x0.get_or_insert(&self.states[j]);
            }
        }
        let disp = |m: &(f64, Vec<f64>, Vec<f64>, usize)| -> f64 {
            self.block_displacements[m.3].iter().sum()
        };
        let first = (0..macros.len())
            .max_by(|&i, &j| disp(&macros[i]).total_cmp(&disp(&macros[j])))
            .unwrap_or(0);
        macros.rotate_left(first);
        let mut x = vec![0.0; ncols];
        let mut set = |cols: &[Col], vals: &[f64]| {
            for (c, v) in cols.iter().zip(vals) {
                x[c.index()] = *v;
            }
        };
        let home = macros[0].2.clone();
        for j in 0..lay.tau.len() {
            let Some((sig, w, xj, s)) = macros.get(j) else {
                set(&lay.xs[j], &home);
                set(&lay.ys[j], &home);
                continue;
            };
            let d = self.durations[*s];
            set(&lay.xs[j], xj);
            set(&lay.ys[j], &self.states[*s]);
            set(&lay.ws[j], w);
            set(&lay.us[j], &self.increments[*s]);
            set(&[lay.sigma[j], lay.tau[j], lay.used[j]], &[*sig, d, 1.0]);
            if let (Some(g), Some(h)) = (lay.g.get(j), lay.h.get(j)) {
                let sq: Vec<f64> = self.increments[*s].iter().map(|u| u * u / d).collect();
                set(g, &sq);
                let sq: Vec<f64> = w
                    .iter()
                    .map(|u| if *sig > 0.0 { u * u / sig } else { 0.0 })
                    .collect();
                set(h, &sq);
            }
            let dj = &self.block_displacements[*s];
            let mj = &self.modes[*s];
            let pos: Vec<f64> = dj.iter().map(|v| v.max(0.0)).collect();
            let neg: Vec<f64> = dj.iter().map(|v| (-v).max(0.0)).collect();
            set(&lay.ps[j], &pos);
            set(&lay.qs[j], &neg);
            let bp: Vec<f64> = mj.iter().map(|&m| f64::from(u8::from(m > 0))).collect();
            let bq: Vec<f64> = mj.iter().map(|&m| f64::from(u8::from(m < 0))).collect();
            set(&lay.sp[j], &bp);
            set(&lay.sq[j], &bq);
        }
        Some(x)
    }

    fn of(s: &PhaseSolution) -> Self {
        RawGait {
            durations: s.durations.clone(),
            increments: s
                .controls
                .iter()
                .zip(&s.durations)
                .map(|(u, d)| u.iter().map(|v| v * d).collect())
                .collect(),
            states: s.states.clone(),
            block_displacements: s.block_displacements.clone(),
            modes: s.modes.clone(),
        }
    }
}

/// Refuses what no phase problem accepts: a crawler failing the uniqueness condition, a bad
/// time limit, `phases` outside `1..=MAX_PHASES`, a total-variation bound.
fn check_phase_args(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
) -> Result<()> {
    crawler.require_unique()?;
    problem.check_scales(crawler)?;
    check_time_limit(time_limit)?;
    if !(1..=MAX_PHASES).contains(&phases) {
        return Err(Error::invalid(
            "phases",
            phases,
            format!("must be in 1..={MAX_PHASES}"),
        ));
    }
    crate::optimal::check_size(crawler, phases, "phases", phases)?;
    if let Some(v) = problem.max_total_variation {
        return Err(Error::invalid(
            "gait.max_total_variation",
            v,
            "bounds the total variation of u = U / tau, which the phase formulation cannot \
             express linearly; use --method discrete",
        ));
    }
    Ok(())
}

/// Solves (P) globally over gaits of at most `phases` slip phases (module docs).
pub fn solve_phase_global(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
) -> Result<PhaseSolution> {
    solve_phase_from(crawler, problem, phases, time_limit, None)
}

/// [`solve_phase_global`] with a known gait of at most `phases` slip phases as the first
/// incumbent.
pub fn solve_phase_from(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
    start: Option<&PhaseSolution>,
) -> Result<PhaseSolution> {
    check_phase_args(crawler, problem, phases, time_limit)?;
    if let Some(s) = start {
        let slips = RawGait::of(s).slip_phases();
        if slips > phases {
            return Err(Error::invalid(
                "start",
                slips,
                format!("has more than {phases} slip phases"),
            ));
        }
    }
    solve_steps(crawler, problem, phases, time_limit, start, None)
}

/// [`solve_steps_in`] in the optimisers' internal units ([`Units`]): the problem and the start
/// converted in, the answer converted back.
fn solve_steps(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
    start: Option<&PhaseSolution>,
    fixed: Option<&[Vec<i8>]>,
) -> Result<PhaseSolution> {
    let units = Units::of(crawler, problem);
    let (c, p) = (units.crawler(crawler)?, units.problem(problem));
    let start = start.map(|s| units.phase(s, false));
    let s = crate::progress::with_objective_scale(units.objective_scale(), || {
        solve_steps_in(&c, &p, phases, time_limit, start.as_ref(), fixed)
    })?;
    Ok(units.phase(&s, true))
}

/// The phase MILP of `phases` steps (or, with `fixed` modes, its LP), solved with outer
/// approximation of a quadratic cost, the answer replayed by the exact simulator and certified.
/// Arguments are checked by the callers.
fn solve_steps_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
    start: Option<&PhaseSolution>,
    fixed: Option<&[Vec<i8>]>,
) -> Result<PhaseSolution> {
    let t = problem.period;
    let a = &problem.rate_bound;
    let what = format!("gait of at most {phases} slip phases");
    let began = Instant::now();
    let mut rates = match problem.cost {
        Cost::Quadratic { .. } => Some(TangentRates::new(a)),
        Cost::None => None,
    };
    let mut incumbent = start.map(RawGait::of);
    let mut rounds = 0;
    let mut last_bound = f64::INFINITY;
    let (raw, bound, status) = loop {
        rounds += 1;
        let (pb, lay) = build(crawler, problem, phases, rates.as_ref(), fixed);
        let ncols = pb.num_cols();
        let start_cols = incumbent.as_ref().and_then(|g| g.columns(&lay, ncols));
        let left = match time_limit {
            Some(tl) => {
                let left = tl - began.elapsed().as_secs_f64();
                if left <= 0.0 {
                    break match incumbent {
                        Some(g) if rounds > 1 => (g, last_bound, MilpStatus::TimeLimit),
                        _ => {
                            return Err(Error::TimeLimit(format!(
                            "{what}: the time limit was reached before any feasible gait was found"
                        )))
                        }
                    };
                }
                Some(left)
            }
            None => None,
        };
        let gap = problem.length_scale(crawler) * 1e-9;
        let (cols, _, bound, status) = solve_max(pb, left, &what, start_cols.as_deref(), gap)?;
        let raw = RawGait::read(&lay, &cols, t);
        last_bound = bound;
        let Some(r) = rates.as_mut() else {
            break (raw, bound, status);
        };
        let true_objective = raw.displacement() - raw.cost(problem);
        let converged = bound - true_objective <= OA_TOL * true_objective.abs().max(1.0);
        if converged || status == MilpStatus::TimeLimit || rounds >= MAX_OA_ROUNDS {
            let status = match status {
                MilpStatus::Optimal if !converged => MilpStatus::ApproximationLimit,
                s => s,
            };
            break (raw, bound, status);
        }
        let mut added = false;
        for (d, u) in raw.durations.iter().zip(&raw.increments) {
            for (l, &ul) in u.iter().enumerate() {
                added |= r.add(l, ul / d, a[l]);
            }
        }
        if !added {
            break (raw, bound, MilpStatus::ApproximationLimit);
        }
        incumbent = Some(raw);
    };
    let cost = raw.cost(problem);
    let verified = if raw.durations.len() < 2 {
        0.0
    } else {
        replay(
            crawler,
            t,
            &raw.durations,
            &raw.increments,
            Some(&raw.states[0]),
            Method::Exact,
            &what,
        )?
        .displacement_per_period
        .ok_or_else(|| Error::Numerical(format!("{what}: the replay did not converge")))?
    };
    let scale = problem.length_scale(crawler);
    // What the MILP proved is optimality among gaits of at most `phases` slip phases.
    let status = match status {
        MilpStatus::Optimal => MilpStatus::OptimalAmongKPhases,
        s => s,
    };
    let certificate = certify(
        &what,
        scale,
        status,
        raw.displacement(),
        bound,
        verified,
        cost,
    )?;
    Ok(PhaseSolution {
        phases,
        certificate,
        verified_displacement: verified,
        actuation_cost: cost,
        controls: raw
            .increments
            .iter()
            .zip(&raw.durations)
            .map(|(u, d)| u.iter().map(|v| v / d).collect())
            .collect(),
        durations: raw.durations,
        states: raw.states,
        block_displacements: raw.block_displacements,
        modes: raw.modes,
        rounds,
    })
}

/// The relative gain in `J` below which a larger `K` or a move of [`search_sequences`] counts
/// as no gain: `1e-7` for a linear objective (LP round-off), and the outer-approximation
/// tolerance [`OA_TOL`] with a quadratic cost, whose values are only that accurate (a gain
/// within it would be noise: on three blocks with c = 0.2, `J_4 - J_3 = 1.5e-7` kept the
/// growth going for another 54 s).
fn gain_tolerance(problem: &GaitProblem) -> f64 {
    match problem.cost {
        Cost::None => 1e-7,
        Cost::Quadratic { .. } => OA_TOL,
    }
}

/// The relative resolution (times the problem's length scale) above which a verified `J_K`
/// counts as moving the crawler in [`grow_phases`]: the replay reproduces `J` to about `1e-14`
/// of the length scale, so `1e-9` leaves room for round-off and nothing else. It only decides
/// whether the growth's patience has started counting; the best verified gait is kept whatever
/// its size.
pub const MOVE_RESOLUTION: f64 = 1e-9;

/// How [`grow_phases`] raises `K`.
#[derive(Debug, Clone, PartialEq)]
pub struct GrowOptions {
    /// First `K`.
    pub min_phases: usize,
    /// Last `K` tried.
    pub max_phases: usize,
    /// Stop after this many consecutive `K` without a gain, counted once `J_K` moves the crawler
    /// (above [`MOVE_RESOLUTION`] times the length scale; before,
    /// `K` is too small for any gait to move the crawler, e.g. one link needs 2 slip phases).
    /// The default is 2: plateaus `J_K = J_{K+1} < J_{K+2}` occur (a 4-block crawler with
    /// per-block friction had `J_3 = J_4 = 6.575 < J_5 = 6.600`).
    pub patience: usize,
    /// Wall-clock limit for the whole growth, seconds.
    pub time_limit: Option<f64>,
}

impl Default for GrowOptions {
    fn default() -> Self {
        GrowOptions {
            min_phases: 1,
            max_phases: 8,
            patience: 2,
            time_limit: None,
        }
    }
}

impl GrowOptions {
    /// Refuses options no growth can run with: `1 <= min_phases <= max_phases <= MAX_PHASES`,
    /// `patience >= 1`, a positive finite time limit.
    pub fn check(&self) -> Result<()> {
        check_time_limit(self.time_limit)?;
        if self.min_phases < 1 {
            return Err(Error::invalid("min_phases", 0, "must be at least 1"));
        }
        if self.max_phases < self.min_phases || self.max_phases > MAX_PHASES {
            return Err(Error::invalid(
                "max_phases",
                self.max_phases,
                format!("must be in {}..={MAX_PHASES}", self.min_phases),
            ));
        }
        if self.patience == 0 {
            return Err(Error::invalid("patience", 0, "must be at least 1"));
        }
        Ok(())
    }
}

/// One `K` of a growth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PhaseStep {
    /// `K`.
    pub phases: usize,
    /// Its optimum `J_K` (verified).
    pub objective: f64,
    /// The MILP's bound on `J_K`.
    pub bound: f64,
    /// Its gap.
    pub gap: f64,
    /// `"optimal_among_k_phases"`, `"time_limit"` or `"approximation_limit"`.
    pub status: MilpStatus,
    /// Wall time of this `K`, seconds.
    pub seconds: f64,
}

/// Why a growth stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GrowthStop {
    /// `patience` consecutive `K` brought no gain.
    NoGain,
    /// `max_phases` was reached while the value still improved (or was still 0).
    MaxPhases,
    /// v_m <= 0 for every shape rate (model analysis), so no gait moves the crawler forward and
    /// staying idle is globally optimal, for every `K`.
    NoForwardMotion,
    /// The time limit ended it.
    TimeLimit,
}

/// The result of [`grow_phases`].
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseGrowth {
    /// The best gait, certified for the last `K` solved to optimality (`best.phases`).
    pub best: PhaseSolution,
    /// Every `K` solved.
    pub table: Vec<PhaseStep>,
    /// Why it stopped.
    pub stop: GrowthStop,
}

/// Raises `K` from `min_phases` until `J_K` has not improved (by more than a relative `1e-7`,
/// or the outer-approximation tolerance `1e-6` with a quadratic cost, whose values are only
/// that accurate) for `patience` consecutive `K`, or `max_phases` or the time limit is reached
/// (module docs). The returned gait is the best found, and its certificate is that of the largest
/// `K` solved: `optimal_among_k_phases` when that `K` was solved to optimality (the gait has at
/// most that many slip phases, and no gait of that many does better than the bound), `time_limit`
/// with that `K`'s bound and gap when the limit cut its MILP short. `progress` sees each `K` as it
/// is solved.
pub fn grow_phases(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &GrowOptions,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<PhaseGrowth> {
    opts.check()?;
    let began = Instant::now();
    let mut best: Option<PhaseSolution> = None;
    let mut table = Vec::new();
    let mut without_gain = 0;
    let mut stop = GrowthStop::MaxPhases;
    // y' = v_m(z') (theory §3): when v_m <= 0 everywhere, J <= 0 for every gait.
    let idle = crawler.analyze().moves_forward == Some(false);
    // Whether a verified J_K moves the crawler: above the replay's resolution, relative to the
    // problem's own length scale (not to 1: lengths may be 1e-6 or 1e6).
    let resolution = MOVE_RESOLUTION * problem.length_scale(crawler);
    let moves = |j: f64| j > resolution;
    for k in opts.min_phases..=opts.max_phases {
        let left = match opts.time_limit {
            Some(tl) => {
                let left = tl - began.elapsed().as_secs_f64();
                if left <= 0.0 {
                    stop = GrowthStop::TimeLimit;
                    break;
                }
                Some(left)
            }
            None => None,
        };
        let t0 = Instant::now();
        let s = match solve_phase_from(crawler, problem, k, left, best.as_ref()) {
            Ok(s) => s,
            Err(Error::TimeLimit(_)) if best.is_some() => {
                stop = GrowthStop::TimeLimit;
                break;
            }
            Err(e) => return Err(e),
        };
        let step = PhaseStep {
            phases: k,
            objective: s.objective(),
            bound: s.certificate.bound,
            gap: s.certificate.gap,
            status: s.certificate.status,
            seconds: t0.elapsed().as_secs_f64(),
        };
        progress(&step);
        table.push(step);
        let timed_out = s.certificate.status == MilpStatus::TimeLimit;
        let gain = best.as_ref().map_or(f64::INFINITY, |b| {
            s.objective()
                - b.objective()
                - gain_tolerance(problem) * b.objective().abs().max(problem.length_scale(crawler))
        });
        if timed_out {
            match best.as_mut() {
                Some(b) if s.objective() <= b.objective() => {
                    // The best gait stays, but the claim is now this K's: a time limit with
                    // this K's bound (not "optimal" for the smaller K it was proven for, which
                    // read as if the growth had finished).
                    b.phases = s.phases;
                    b.certificate.bound = s.certificate.bound;
                    b.certificate.gap = ((s.certificate.bound - b.objective())
                        / b.objective().abs().max(1.0))
                    .max(0.0);
                    b.certificate.status = MilpStatus::TimeLimit;
                }
                _ => best = Some(s),
            }
            stop = GrowthStop::TimeLimit;
            break;
        }
        if idle {
            best = Some(s);
            stop = GrowthStop::NoForwardMotion;
            break;
        }
        if gain > 0.0 {
            without_gain = 0;
            best = Some(s);
        } else if best.as_ref().is_some_and(|b| !moves(b.objective())) {
            // Nothing moves yet (at the replay's resolution): K is still too small. A verified
            // gait better than the best so far is never overruled by the gain tolerance, which
            // is relative to the length scale and can exceed a small true optimum (one link
            // with T just above 2w/a: J* = 5e-8 against a tolerance of 3e-7).
            if best.as_ref().is_some_and(|b| s.objective() > b.objective()) {
                best = Some(s);
            } else if let Some(b) = best.as_mut() {
                // The idle gait, now certified for this larger K.
                b.phases = s.phases;
                b.certificate.bound = s.certificate.bound;
                b.certificate.gap =
                    ((s.certificate.bound - b.objective()) / b.objective().abs().max(1.0)).max(0.0);
                b.certificate.status = s.certificate.status;
            }
        } else {
            without_gain += 1;
            if best.as_ref().is_some_and(|b| s.objective() > b.objective()) {
                // Better within the tolerance only: keep the better gait, with its own
                // certificate for this larger K.
                best = Some(s);
            } else if let Some(b) = best.as_mut() {
                // Same gait, now certified for this larger K.
                b.phases = s.phases;
                b.certificate.bound = s.certificate.bound;
                b.certificate.gap =
                    ((s.certificate.bound - b.objective()) / b.objective().abs().max(1.0)).max(0.0);
                b.certificate.status = s.certificate.status;
            }
            if without_gain >= opts.patience {
                stop = GrowthStop::NoGain;
                break;
            }
        }
    }
    let best = best.ok_or_else(|| {
        Error::TimeLimit(
            "phase growth: the time limit was reached before any feasible gait was found".into(),
        )
    })?;
    Ok(PhaseGrowth { best, table, stop })
}

/// Whether a slip mode (per block `-1`, `0`, `1`) names a nonempty face of C on which some
/// block slips.
///
/// The forces `F_b` sum to zero and determine `x` (`x_l = -sum_{b <= l} F_b`). The face holds
/// `F_b = mu_b^+` on the blocks `S+` slipping forward, `F_b = -mu_b^-` on `S-`, and leaves the
/// others free in `[-mu_b^-, mu_b^+]`; it is nonempty iff
/// `-sum_free mu^+ <= sum_{S+} mu^+ - sum_{S-} mu^- <= sum_free mu^-` with some block free (with
/// none, equality would violate the uniqueness condition).
pub fn slip_mode_is_valid(crawler: &Crawler, mode: &[i8]) -> bool {
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    if mode.len() != mp.len() || mode.iter().any(|&m| !(-1..=1).contains(&m)) {
        return false;
    }
    let (mut held, mut free_p, mut free_m, mut slipping) = (0.0, 0.0, 0.0, 0);
    for (b, &m) in mode.iter().enumerate() {
        match m {
            1 => held += mp[b],
            -1 => held -= mm[b],
            _ => {
                free_p += mp[b];
                free_m += mm[b];
            }
        }
        slipping += usize::from(m != 0);
    }
    slipping > 0 && slipping < mode.len() && -free_p <= held && held <= free_m
}

/// The valid slip modes that differ from `mode` in one or two blocks.
fn neighbours(crawler: &Crawler, mode: &[i8]) -> Vec<Vec<i8>> {
    let nb = mode.len();
    let mut out: Vec<Vec<i8>> = Vec::new();
    let mut push = |m: Vec<i8>| {
        if slip_mode_is_valid(crawler, &m) && !out.contains(&m) {
            out.push(m);
        }
    };
    for b in 0..nb {
        for vb in [-1i8, 0, 1] {
            if vb == mode[b] {
                continue;
            }
            let mut m = mode.to_vec();
            m[b] = vb;
            push(m.clone());
            for c in b + 1..nb {
                for vc in [-1i8, 0, 1] {
                    if vc != mode[c] {
                        let mut m2 = m.clone();
                        m2[c] = vc;
                        push(m2);
                    }
                }
            }
        }
    }
    out
}

/// The slip phases of a gait, in order: the modes of its phases where some block slips, a run
/// of consecutive phases of one mode merged (it is one slip phase), cyclically.
pub fn slip_sequence(modes: &[Vec<i8>]) -> Vec<Vec<i8>> {
    let mut runs: Vec<&Vec<i8>> = Vec::new();
    for m in modes {
        if runs.last() != Some(&m) {
            runs.push(m);
        }
    }
    if runs.len() > 1 && runs.first() == runs.last() {
        runs.pop();
    }
    runs.into_iter()
        .filter(|m| m.iter().any(|&s| s != 0))
        .cloned()
        .collect()
}

/// The result of [`search_sequences`].
#[derive(Debug, Clone, PartialEq)]
pub struct SequenceSearch {
    /// The best gait found: optimal for its sequence of slip modes (an LP), no global claim.
    pub best: PhaseSolution,
    /// Its sequence of slip modes, one per step (some steps may be empty in the gait).
    pub sequence: Vec<Vec<i8>>,
    /// `J` of the start sequence (its LP optimum, at least the start gait's `J`).
    pub start_objective: f64,
    /// LPs solved.
    pub lp_solves: usize,
    /// Improving moves made.
    pub moves: usize,
    /// Why it stopped: [`LocalStop::Stationary`] when no single move improves, or the time
    /// limit.
    pub stop: LocalStop,
}

/// Local search over the sequences of slip modes of phase gaits with `phases` steps, for
/// crawlers or `K` where the MILP is too slow (theory §7: "local search over sequences scales
/// further").
///
/// For a fixed cyclic sequence, the best gait following it is an LP (the MILP of the module
/// docs with its binaries fixed), so every candidate is an exact continuous-time gait, solved
/// to optimality for its sequence and re-verified by the exact simulator. A move replaces the
/// mode of one step by a valid mode differing in one or two blocks ([`slip_mode_is_valid`]);
/// the first improving move is taken, scanning the steps cyclically, until a whole cycle brings
/// none (a local optimum for these moves) or the time limit. The start sequence is
/// `start_modes` (e.g. the [`slip_sequence`] of a gait), each mode repeated in turn until there
/// are `phases` steps: a repeated mode is a slip phase that may stay empty, so the start's
/// value is kept. An empty start (an idle gait) is seeded with each block slipping forward in
/// turn, from the front (where that is a face of C; else one block slipping).
pub fn search_sequences(
    crawler: &Crawler,
    problem: &GaitProblem,
    start_modes: &[Vec<i8>],
    phases: usize,
    time_limit: Option<f64>,
) -> Result<SequenceSearch> {
    check_phase_args(crawler, problem, phases, time_limit)?;
    // An idle start has no slip phase: seed it with each block slipping forward in turn, from
    // the front (a peristaltic wave), or one block slipping; the LP may leave them all empty
    // (the idle gait held on a face), so nothing is lost.
    let seed: Vec<Vec<i8>>;
    let start_modes = if start_modes.is_empty() {
        let nb = crawler.blocks();
        let single = (0..nb).rev().flat_map(|b| {
            [1i8, -1].map(|s| {
                let mut m = vec![0i8; nb];
                m[b] = s;
                m
            })
        });
        let forward: Vec<Vec<i8>> = single
            .clone()
            .filter(|m| m.contains(&1) && slip_mode_is_valid(crawler, m))
            .take(phases)
            .collect();
        seed = if forward.is_empty() {
            single
                .filter(|m| slip_mode_is_valid(crawler, m))
                .take(1)
                .collect()
        } else {
            forward
        };
        &seed[..]
    } else {
        start_modes
    };
    if start_modes.is_empty() || start_modes.len() > phases {
        return Err(Error::invalid(
            "start",
            format!("{} slip phases", start_modes.len()),
            format!("needs 1 to {phases} slip phases (--phases)"),
        ));
    }
    if let Some(m) = start_modes.iter().find(|m| !slip_mode_is_valid(crawler, m)) {
        return Err(Error::invalid(
            "start",
            format!("{m:?}"),
            "is not a slip mode of a face of C",
        ));
    }
    let mut seq: Vec<Vec<i8>> = Vec::with_capacity(phases);
    for (i, m) in start_modes.iter().enumerate() {
        seq.push(m.clone());
        let extra = (phases - start_modes.len()) / start_modes.len()
            + usize::from(i < (phases - start_modes.len()) % start_modes.len());
        seq.extend(std::iter::repeat_n(m.clone(), extra));
    }
    let began = Instant::now();
    let left = || match time_limit {
        Some(tl) => {
            let l = tl - began.elapsed().as_secs_f64();
            if l > 0.0 {
                Ok(Some(l))
            } else {
                Err(())
            }
        }
        None => Ok(None),
    };
    let mut lp_solves = 1;
    let Ok(first_left) = left() else {
        return Err(Error::TimeLimit(
            "sequence search: the time limit was reached before any gait was found".into(),
        ));
    };
    let mut best = solve_steps(crawler, problem, phases, first_left, None, Some(&seq)).map_err(
        |e| match e {
            Error::Infeasible(_) => Error::invalid(
                "start",
                format!("{} slip phases", start_modes.len()),
                "no gait of the period follows this sequence of slip modes",
            ),
            e => e,
        },
    )?;
    let start_objective = best.objective();
    let (mut moves, mut quiet, mut j) = (0, 0, 0);
    let stop = 'search: loop {
        let mut improved = false;
        for cand in neighbours(crawler, &seq[j]) {
            let Ok(l) = left() else {
                break 'search LocalStop::TimeLimit;
            };
            let mut next = seq.clone();
            next[j] = cand;
            lp_solves += 1;
            match solve_steps(crawler, problem, phases, l, None, Some(&next)) {
                Ok(s)
                    if s.objective()
                        > best.objective()
                            + gain_tolerance(problem)
                                * best.objective().abs().max(problem.length_scale(crawler)) =>
                {
                    best = s;
                    seq = next;
                    improved = true;
                    break;
                }
                // A sequence no gait can follow, or whose LP answer the simulator does not
                // reproduce, is no candidate; the search goes on.
                Ok(_) | Err(Error::Infeasible(_) | Error::Numerical(_)) => {}
                Err(Error::TimeLimit(_)) => break 'search LocalStop::TimeLimit,
                Err(e) => return Err(e),
            }
        }
        if improved {
            moves += 1;
            quiet = 0;
        } else {
            quiet += 1;
            if quiet >= phases {
                break LocalStop::Stationary;
            }
        }
        j = (j + 1) % phases;
    };
    Ok(SequenceSearch {
        best,
        sequence: seq,
        start_objective,
        lp_solves,
        moves,
        stop,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every column of `lay`, in no particular order.
    fn all_columns(lay: &Layout) -> Vec<Col> {
        let mut v: Vec<Col> = Vec::new();
        for c in [&lay.sigma, &lay.tau, &lay.used] {
            v.extend(c.iter().copied());
        }
        for c in [
            &lay.xs, &lay.ys, &lay.ws, &lay.us, &lay.ps, &lay.qs, &lay.sp, &lay.sq, &lay.g, &lay.h,
        ] {
            v.extend(c.iter().flatten().copied());
        }
        v
    }

    /// Whether `gait` written into a `phases`-step layout satisfies every row: each column is
    /// pinned to its value and HiGHS must find the problem feasible.
    fn start_is_feasible(c: &Crawler, p: &GaitProblem, phases: usize, gait: &RawGait) -> bool {
        let rates = match p.cost {
            Cost::Quadratic { .. } => Some(TangentRates::new(&p.rate_bound)),
            Cost::None => None,
        };
        let (mut pb, lay) = build(c, p, phases, rates.as_ref(), None);
        let Some(x) = gait.columns(&lay, pb.num_cols()) else {
            return false;
        };
        let cols = all_columns(&lay);
        assert_eq!(cols.len(), pb.num_cols(), "the layout holds every column");
        for col in cols {
            let v = x[col.index()];
            let tol = 1e-9 * v.abs().max(1.0);
            pb.add_row(v - tol..=v + tol, [(col, 1.0)]);
        }
        solve_max(pb, Some(30.0), "start check", None, 1e-9).is_ok()
    }

    fn rotated(g: &RawGait, r: usize) -> RawGait {
        let p = g.durations.len();
        let rot = |v: &Vec<Vec<f64>>| -> Vec<Vec<f64>> {
            (0..p).map(|i| v[(i + r) % p].clone()).collect()
        };
        let mut states = rot(&g.states[..p].to_vec());
        states.push(states[0].clone());
        RawGait {
            durations: (0..p).map(|i| g.durations[(i + r) % p]).collect(),
            increments: rot(&g.increments),
            states,
            block_displacements: rot(&g.block_displacements),
            modes: (0..p).map(|i| g.modes[(i + r) % p].clone()).collect(),
        }
    }

    /// Whether the face of `mode` is nonempty, by an LP over `x` (independent of the closed
    /// form of [`slip_mode_is_valid`]).
    fn face_is_nonempty(c: &Crawler, mode: &[i8]) -> bool {
        let (mp, mm) = (c.mu_forward(), c.mu_backward());
        let mut pb = RowProblem::default();
        let x: Vec<Col> = (0..c.links())
            .map(|_| pb.add_column(0.0, f64::NEG_INFINITY..f64::INFINITY))
            .collect();
        for (b, &m) in mode.iter().enumerate() {
            let row = force_row(&x, b);
            match m {
                1 => pb.add_row(mp[b]..=mp[b], row),
                -1 => pb.add_row(-mm[b]..=-mm[b], row),
                _ => pb.add_row(-mm[b]..=mp[b], row),
            }
        }
        let mut h = crate::optimal::solver::Highs::new(pb, highs::Sense::Maximise, "test").unwrap();
        h.solve().unwrap().status == crate::optimal::solver::SolveStatus::Optimal
    }

    #[test]
    fn valid_slip_modes_are_the_nonempty_faces_of_c() {
        let cases = [
            (vec![1.0, 1.0, 1.0], vec![1.5, 1.5, 1.5]),
            (vec![1.0, 0.7, 1.3, 0.9], vec![1.6, 2.9, 0.8, 1.1]),
            (vec![1.0, 1.0, 1.0, 1.0, 1.0], vec![1.6, 1.6, 1.6, 1.6, 1.6]),
            (vec![2.5, 2.5, 2.5], vec![1.0, 1.0, 1.0]),
        ];
        for (mp, mm) in cases {
            let nb = mp.len();
            let c = Crawler::new(vec![1.0; nb - 1], mp, mm).unwrap();
            let mut valid = 0;
            for code in 0..3usize.pow(nb as u32) {
                let mode: Vec<i8> = (0..nb)
                    .map(|b| (code / 3usize.pow(b as u32) % 3) as i8 - 1)
                    .collect();
                let slipping = mode.iter().any(|&m| m != 0);
                let expect = slipping && face_is_nonempty(&c, &mode);
                assert_eq!(slip_mode_is_valid(&c, &mode), expect, "{mode:?}");
                valid += usize::from(expect);
            }
            if nb == 3 && c.mu_forward()[0] == 1.0 {
                // One block forward or backward (6), or one each way (6): the hexagon's
                // edges and vertices.
                assert_eq!(valid, 12);
            }
        }
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        assert!(!slip_mode_is_valid(&c, &[0, 0, 0]));
        assert!(!slip_mode_is_valid(&c, &[1, 0]));
        assert!(!slip_mode_is_valid(&c, &[2, 0, 0]));
        for m in neighbours(&c, &[1, 0, 0]) {
            assert!(slip_mode_is_valid(&c, &m) && m != vec![1, 0, 0]);
        }
        assert!(neighbours(&c, &[1, 0, 0]).contains(&vec![0, 1, 0]));
    }

    #[test]
    fn slip_sequence_merges_repeats_cyclically() {
        let m = |v: &[i8]| v.to_vec();
        let modes = vec![
            m(&[1, 0, 0]),
            m(&[0, 0, 0]),
            m(&[0, 1, 0]),
            m(&[0, 1, 0]),
            m(&[0, 0, 0]),
            m(&[0, 1, 0]),
            m(&[1, 0, 0]),
        ];
        // Equal modes separated by a transition are two slip phases; the last merges with the
        // first across the period's end.
        assert_eq!(
            slip_sequence(&modes),
            vec![m(&[1, 0, 0]), m(&[0, 1, 0]), m(&[0, 1, 0])]
        );
        assert!(slip_sequence(&[m(&[0, 0])]).is_empty());
    }

    #[test]
    fn any_rotation_of_a_gait_is_a_feasible_start_for_as_many_steps_or_more() {
        for cost in [Cost::None, Cost::Quadratic { weight: 0.1 }] {
            let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
            let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], cost, None).unwrap();
            let s = solve_phase_global(&c, &p, 4, Some(60.0)).unwrap();
            let g = RawGait::of(&s);
            let slips = g.slip_phases();
            assert!(g.durations.len() > slips, "the optimum has transitions");
            for r in 0..g.durations.len() {
                let h = rotated(&g, r);
                for k in [slips, slips + 1] {
                    assert!(start_is_feasible(&c, &p, k, &h), "rotation {r}, K = {k}");
                }
                assert!(!start_is_feasible(&c, &p, slips - 1, &h), "too few steps");
            }
            // A slip phase cut in two halves, the gait rotated so that they sit at its two
            // ends: still one slip phase, so it fits as many steps.
            let j = (0..g.durations.len())
                .find(|&j| g.modes[j].iter().any(|&m| m != 0))
                .unwrap();
            let half = |v: &Vec<f64>| -> Vec<f64> { v.iter().map(|x| 0.5 * x).collect() };
            let mut cut = RawGait {
                durations: g.durations.clone(),
                increments: g.increments.clone(),
                states: g.states.clone(),
                block_displacements: g.block_displacements.clone(),
                modes: g.modes.clone(),
            };
            let mid: Vec<f64> = g.states[j]
                .iter()
                .zip(&g.states[j + 1])
                .map(|(a, b)| 0.5 * (a + b))
                .collect();
            cut.durations[j] *= 0.5;
            cut.durations.insert(j, cut.durations[j]);
            cut.increments[j] = half(&g.increments[j]);
            cut.increments.insert(j, cut.increments[j].clone());
            cut.block_displacements[j] = half(&g.block_displacements[j]);
            cut.block_displacements
                .insert(j, cut.block_displacements[j].clone());
            cut.modes.insert(j, g.modes[j].clone());
            cut.states.insert(j + 1, mid);
            let cut = rotated(&cut, j + 1);
            assert_eq!(cut.slip_phases(), slips);
            assert!(start_is_feasible(&c, &p, slips, &cut), "split slip phase");
        }
    }
}
