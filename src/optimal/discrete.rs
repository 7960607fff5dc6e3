//! The paper's discrete problem P_m (theory §6), solved globally as a mixed-integer linear program
//! in HiGHS.
//!
//! On the dyadic grid `h = T / 2^m` (`M = 2^m` steps), with `U^i = h u^i`:
//!
//! ```text
//! maximise   sum_i (1/N) sum_b D^i_b - (c/2) sum_{i,l} g^i_l            (g >= (U^i_l)^2 / h)
//! subject to x^{i+1} = x^i + U^i - K sum_b D^i_b nu_b,     x^M = x^0         (catching-up)
//!            -mu_b^- <= F_b(x^{i+1}) <= mu_b^+                               (x^{i+1} in C)
//!            D^i_b = P^i_b - Q^i_b,  0 <= P <= Md zp,  0 <= Q <= Md zq,  zp + zq <= 1
//!            mu_b^+ - F_b(x^{i+1}) <= W_b (1 - zp^i_b),  F_b(x^{i+1}) + mu_b^- <= W_b (1 - zq^i_b)
//!            |U^i_l| <= a_l h,  sum_i U^i = 0,
//!            sum_{i,l} |U^{i+1}_l - U^i_l| <= h V                   (optional: TV(u) <= V)
//! ```
//!
//! A quadratic cost `h sum_i (c/2)|u^i|^2 = (c/2) sum_{i,l} (U^i_l)^2 / h` enters through
//! epigraph variables cut by tangents (outer approximation, as in the phase formulation): the
//! bound stays valid, and tangents at the solution's rates are added until the incumbent's true
//! objective meets it. The total variation of the piecewise-constant periodic control is the sum
//! of its jumps, linear in `U` for a fixed `h`.
//!
//! The dynamics with the sign and complementarity conditions are exactly the KKT system of the
//! catching-up projection (theory §4), which has a unique solution, so every feasible point is a
//! catching-up trajectory. Constants, all derived from C and the rate bounds:
//! - `W_b = mu_b^+ + mu_b^-`: the range of `F_b` over C, the largest slack of either face;
//! - `Md = h sqrt(sum_l 1/k_l) sqrt(sum_l a_l^2 / k_l)` bounds `|D^i_b|`: some block is free
//!   (`D = 0`) and `D_{b+1} - D_b = (v_b - x_b)/k_b`, so `|D_b| <= sum_l |v_l - x_l| / k_l
//!   <= sqrt(sum 1/k) |v - x|_{K^-1}`, and `|v - x|_{K^-1} <= |U|_{K^-1}` because `x^i` is in C
//!   and the projection is the nearest point;
//! - the time-shift symmetry of a periodic gait is left to HiGHS: the rows that break it
//!   (step 0 carries the largest displacement; or `x^0_1` is the least `x^i_1`) made the solve
//!   slower, not faster, on the three-block instance at `2^m = 16` (143 s and 34 s against
//!   25 s without, one thread; `crawlopt optimize examples/three_blocks_gait.toml --method
//!   discrete --m 4`), because they cut off the incumbents HiGHS's heuristics find first. The
//!   phase formulation, whose phases are few, keeps its symmetry rows.
//!
//! Every answer is re-verified by the simulator: the returned increments are played by
//! catching-up (the simulator's [`simulate`](crate::integrate::simulate)) from the returned initial state until the periodic regime, and the verified
//! displacement is the one reported.

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::milp::{
    block_speed_bound, certify, control_knots, force, force_row, replay_grid, solve_max,
    GridColumns, GridReplay, TangentRates, OA_TOL,
};
use crate::optimal::polish::PolishRecord;
use crate::optimal::sample_increments;
use crate::optimal::{Certificate, Cost, GaitProblem, MilpStatus};
use highs::{Col, RowProblem};
use serde::Serialize;

/// Largest `m` accepted (`2^m` steps).
pub const MAX_M: u32 = 16;

/// Outer-approximation rounds at most.
const MAX_OA_ROUNDS: usize = 40;

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
    /// `h sum_i f2(u^i)`.
    pub actuation_cost: f64,
    /// Initial state `x^0` (on the limit cycle).
    pub initial_state: Vec<f64>,
    /// States `x^i` at the grid times `i h`, `i = 0..=2^m` (the last equals the first).
    pub states: Vec<Vec<f64>>,
    /// Controls `u^i` (force per time), one row per step.
    pub controls: Vec<Vec<f64>>,
    /// Block displacements `D^i_b` per step, from the simulation.
    pub block_displacements: Vec<Vec<f64>>,
    /// MILP solves (outer-approximation rounds for a quadratic cost, else 1).
    pub rounds: usize,
    /// `J` of the start gait on this grid, when the solve had one
    /// ([`super::solve_discrete_global_from`]).
    pub start_objective: Option<f64>,
    /// What polishing on the fixed slip pattern did ([`crate::optimal::polish`]); `None`
    /// without a quadratic cost (the MILP's answer is then exact) or with polishing off.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub polish: Option<PolishRecord>,
}

impl DiscreteSolution {
    /// `J_m` = verified displacement minus actuation cost.
    pub fn objective(&self) -> f64 {
        self.verified_displacement - self.actuation_cost
    }

    /// The gait's knots: times `i h` and actuator lengths from `L(0) = 0` (see
    /// [`gait_knots`](crate::optimal::gait_knots)).
    pub fn knots(&self, stiffness: &[f64]) -> (Vec<f64>, Vec<Vec<f64>>) {
        control_knots(
            &vec![self.step; self.controls.len()],
            &self.controls,
            stiffness,
        )
    }
}

struct Layout {
    grid: GridColumns,
    ps: Vec<Vec<Col>>,
    qs: Vec<Vec<Col>>,
    zps: Vec<Vec<Col>>,
    zqs: Vec<Vec<Col>>,
    /// Cost epigraphs `g^i_l` (quadratic cost only).
    gs: Vec<Vec<Col>>,
    /// Jumps `s^i_l` of the control (TV bound only).
    jumps: Vec<Vec<Col>>,
}

impl Layout {
    /// `(1/N) sum_{i,b} D^i_b` of a solution.
    fn displacement(&self, cols: &[f64], blocks: usize) -> f64 {
        self.ps
            .iter()
            .flatten()
            .zip(self.qs.iter().flatten())
            .map(|(p, q)| cols[p.index()] - cols[q.index()])
            .sum::<f64>()
            / blocks as f64
    }

    /// The MILP's columns at a catching-up trajectory on the grid (increments `incs` played
    /// from its orbit state, `traj`): a feasible point, given to HiGHS as its first incumbent.
    /// A block is marked slipping only when its face holds at the end of the step; a
    /// displacement of rounding size elsewhere is dropped (within the solver's tolerances).
    fn start_columns(
        &self,
        ncols: usize,
        crawler: &Crawler,
        incs: &[Vec<f64>],
        h: f64,
        traj: &GridReplay,
    ) -> Vec<f64> {
        let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
        let steps = incs.len();
        let mut cols = vec![0.0; ncols];
        for i in 0..steps {
            let next = &traj.states[i + 1];
            for (l, &u) in incs[i].iter().enumerate() {
                cols[self.grid.xs[i][l].index()] = traj.states[i][l];
                cols[self.grid.us[i][l].index()] = u;
                if let Some(g) = self.gs.get(i) {
                    cols[g[l].index()] = u * u / h;
                }
                if let Some(s) = self.jumps.get(i) {
                    cols[s[l].index()] = (incs[(i + 1) % steps][l] - u).abs();
                }
            }
            for (b, &d) in traj.block_displacements[i].iter().enumerate() {
                let f = force(next, b);
                let tol = 1e-10 * (mp[b] + mm[b]);
                if d > 0.0 && (f - mp[b]).abs() <= tol {
                    cols[self.ps[i][b].index()] = d;
                    cols[self.zps[i][b].index()] = 1.0;
                } else if d < 0.0 && (f + mm[b]).abs() <= tol {
                    cols[self.qs[i][b].index()] = -d;
                    cols[self.zqs[i][b].index()] = 1.0;
                }
            }
        }
        cols
    }
}

/// One column per step and block, step by step: a binary, or a continuous column in
/// `[0, md]` of objective `cost` (the block displacements `D^+`, `D^-`).
fn per_block(
    pb: &mut RowProblem,
    (steps, nb): (usize, usize),
    cost: f64,
    integer: bool,
    md: f64,
) -> Vec<Vec<Col>> {
    (0..steps)
        .map(|_| {
            (0..nb)
                .map(|_| {
                    if integer {
                        pb.add_integer_column(0.0, 0..=1)
                    } else {
                        pb.add_column(cost, 0.0..=md)
                    }
                })
                .collect()
        })
        .collect()
}

/// The columns the rows of one step of [`build`] use: states, increments, the forward and
/// backward block displacements and their binaries.
struct StepColumns<'a> {
    xs: &'a [Vec<Col>],
    us: &'a [Vec<Col>],
    ps: &'a [Vec<Col>],
    qs: &'a [Vec<Col>],
    zps: &'a [Vec<Col>],
    zqs: &'a [Vec<Col>],
}

/// The link rows of step `i` (of `h`), link by link: the dynamics
/// `x^{i+1}_l - x^i_l - U^i_l + k_l (D_{l+1} - D_l) = 0` and, with a quadratic cost's tangent
/// `rates`, its epigraph column `g` (objective `-c/2`, pushed onto `gs`) and its cuts.
fn add_link_rows(
    pb: &mut RowProblem,
    crawler: &Crawler,
    problem: &GaitProblem,
    cols: &StepColumns<'_>,
    (i, h): (usize, f64),
    rates: Option<&TangentRates>,
    gs: &mut Vec<Vec<Col>>,
) {
    let (xs, us, ps, qs) = (cols.xs, cols.us, cols.ps, cols.qs);
    let n = crawler.links();
    let k = crawler.stiffness();
    let a = &problem.rate_bound;
    let weight = match problem.cost {
        Cost::Quadratic { weight } => weight,
        Cost::None => 0.0,
    };
    let next = &xs[(i + 1) % xs.len()];
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
        if let Some(r) = rates {
            let g = pb.add_column(-0.5 * weight, 0.0..=a[l] * a[l] * h);
            r.add_cuts(&mut *pb, l, g, us[i][l], None, h);
            if l == 0 {
                gs.push(Vec::with_capacity(n));
            }
            gs[i].push(g);
        }
    }
}

/// The block rows of step `i`, block by block: the force range at `x^{i+1}`, `D^± <= md z^±`,
/// `z^+ + z^- <= 1`, and the big-M complementarity that a block moves forward (backward) only
/// with its force at `mu^+` (`-mu^-`).
fn add_block_rows(
    pb: &mut RowProblem,
    crawler: &Crawler,
    cols: &StepColumns<'_>,
    i: usize,
    md: f64,
) {
    let (ps, qs, zps, zqs) = (cols.ps, cols.qs, cols.zps, cols.zqs);
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    let next = &cols.xs[(i + 1) % cols.xs.len()];
    for b in 0..crawler.blocks() {
        let f = force_row(next, b);
        let w = mp[b] + mm[b];
        pb.add_row(-mm[b]..=mp[b], &f);
        pb.add_row(..=0.0, [(ps[i][b], 1.0), (zps[i][b], -md)]);
        pb.add_row(..=0.0, [(qs[i][b], 1.0), (zqs[i][b], -md)]);
        pb.add_row(..=1.0, [(zps[i][b], 1.0), (zqs[i][b], 1.0)]);
        // mu^+ - F <= W (1 - zp)  <=>  -F + W zp <= mu^-.
        let mut row: Vec<(Col, f64)> = f.iter().map(|&(c, v)| (c, -v)).collect();
        row.push((zps[i][b], w));
        pb.add_row(..=mm[b], &row);
        // F + mu^- <= W (1 - zq)  <=>  F + W zq <= mu^+.
        let mut row = f.clone();
        row.push((zqs[i][b], w));
        pb.add_row(..=mp[b], &row);
    }
}

/// The MILP of P_m on `2^m` steps: the grid's columns, the block displacements `D^+`, `D^-`
/// (objective `±1/N`) and their binaries, then step by step the link rows
/// ([`add_link_rows`]) and the block rows ([`add_block_rows`]), then the control rows.
fn build(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    rates: Option<&TangentRates>,
) -> (RowProblem, Layout) {
    let nb = crawler.blocks();
    let big_m = 1usize << m;
    let h = problem.period / big_m as f64;
    let md = h * block_speed_bound(crawler, problem);

    let mut pb = RowProblem::default();
    let grid = GridColumns::new(&mut pb, crawler, problem, big_m);
    let mut gs = Vec::new();
    let inv_n = 1.0 / nb as f64;
    let ps = per_block(&mut pb, (big_m, nb), inv_n, false, md);
    let qs = per_block(&mut pb, (big_m, nb), -inv_n, false, md);
    let zps = per_block(&mut pb, (big_m, nb), 0.0, true, md);
    let zqs = per_block(&mut pb, (big_m, nb), 0.0, true, md);
    let cols = StepColumns {
        xs: &grid.xs,
        us: &grid.us,
        ps: &ps,
        qs: &qs,
        zps: &zps,
        zqs: &zqs,
    };
    for i in 0..big_m {
        add_link_rows(&mut pb, crawler, problem, &cols, (i, h), rates, &mut gs);
        add_block_rows(&mut pb, crawler, &cols, i, md);
    }
    let jumps = grid.add_control_rows(&mut pb, problem);
    (
        pb,
        Layout {
            grid,
            ps,
            qs,
            zps,
            zqs,
            gs,
            jumps,
        },
    )
}

/// [`super::solve_discrete_global_from`] in internal units, arguments checked.
pub(super) fn solve_discrete_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    start: Option<(&[f64], &[Vec<f64>])>,
) -> Result<DiscreteSolution> {
    let nb = crawler.blocks();
    let big_m = 1usize << m;
    let h = problem.period / big_m as f64;
    let a = &problem.rate_bound;
    let what = format!("P_{m}");
    let mut rates = match problem.cost {
        Cost::Quadratic { .. } => Some(TangentRates::new(a)),
        Cost::None => None,
    };
    let start = match start {
        Some((times, lengths)) => Some(grid_start(crawler, problem, m, times, lengths, &what)?),
        None => None,
    };
    let mut rounds = 0;
    let mut last: Option<(Vec<f64>, f64, Layout)> = None;
    let (cols, lay, bound, status) = loop {
        rounds += 1;
        let (pb, lay) = build(crawler, problem, m, rates.as_ref());
        if crate::progress::out_of_time()? {
            match last {
                Some((cols, bound, lay)) => break (cols, lay, bound, MilpStatus::TimeLimit),
                None => {
                    return Err(Error::TimeLimit(format!(
                        "{what}: the time limit was reached before any feasible gait was found"
                    )))
                }
            }
        }
        // The first round starts from the start gait, later ones from the previous round's
        // solution (the same columns), its cost epigraphs raised onto the cost, which the new
        // cuts were placed to exceed.
        let start_cols = round_start(&last, &start, &lay, pb.num_cols(), crawler, h);
        let gap = problem.length_scale(crawler) * 1e-9;
        let (cols, objective, bound, status) = solve_max(pb, &what, start_cols.as_deref(), gap)?;
        // Cut short before HiGHS had a bound: the work bound, valid for every gait.
        let bound =
            bound.unwrap_or_else(|| crate::optimal::work_limit(crawler, problem).max(objective));
        let Some(r) = rates.as_mut() else {
            break (cols, lay, bound, status);
        };
        let incs = lay.grid.increments(&cols);
        let true_objective = lay.displacement(&cols, nb) - grid_cost(problem, &incs, h);
        let converged = bound - true_objective <= OA_TOL * true_objective.abs().max(1.0);
        if converged || status == MilpStatus::TimeLimit || rounds >= MAX_OA_ROUNDS {
            let status = match status {
                MilpStatus::Optimal if !converged => MilpStatus::ApproximationLimit,
                s => s,
            };
            break (cols, lay, bound, status);
        }
        let mut added = false;
        for u in &incs {
            for (l, &ul) in u.iter().enumerate() {
                added |= r.add(l, ul / h, a[l]);
            }
        }
        if !added {
            break (cols, lay, bound, MilpStatus::ApproximationLimit);
        }
        last = Some((cols, bound, lay));
    };
    let start_objective = start.map(|s| s.2);
    let end = MilpEnd {
        cols,
        lay,
        bound,
        status,
    };
    replayed_solution(crawler, problem, m, end, rounds, start_objective, &what)
}

/// The start gait `(times, lengths)` on the grid of P_m: its increments (checked against a bound
/// on TV(u)), its trajectory from rest and its objective `J` there; the MILP's first incumbent.
fn grid_start(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    times: &[f64],
    lengths: &[Vec<f64>],
    what: &str,
) -> Result<(Vec<Vec<f64>>, GridReplay, f64)> {
    let big_m = 1usize << m;
    let h = problem.period / big_m as f64;
    let a = &problem.rate_bound;
    let incs = sample_increments(
        times,
        lengths,
        crawler.stiffness(),
        a,
        problem.period,
        big_m,
    );
    // Sampling keeps the rate bounds and the zero mean; a TV bound it may break, and
    // HiGHS would drop such a start without a word.
    if let Some(v) = problem.max_total_variation {
        let tv: f64 = (0..big_m)
            .flat_map(|i| {
                let next = &incs[(i + 1) % big_m];
                incs[i].iter().zip(next).map(|(u0, u1)| (u1 - u0).abs())
            })
            .sum::<f64>()
            / h;
        if tv > v * (1.0 + 1e-9) {
            return Err(Error::invalid(
                "start",
                format!("TV(u) = {tv}"),
                format!("exceeds gait.max_total_variation = {v} on the grid of P_{m}"),
            ));
        }
    }
    let from_rest = vec![0.0; crawler.links()];
    let traj = replay_grid(crawler, problem.period, &incs, &from_rest, what)?;
    let objective = traj.verified - grid_cost(problem, &incs, h);
    Ok((incs, traj, objective))
}

/// The MILP start of an outer-approximation round: the previous round's solution (the same
/// columns) with its cost epigraphs raised onto the cost, which the new cuts were placed to
/// exceed; in the first round the start gait's columns, if any.
fn round_start(
    last: &Option<(Vec<f64>, f64, Layout)>,
    start: &Option<(Vec<Vec<f64>>, GridReplay, f64)>,
    lay: &Layout,
    ncols: usize,
    crawler: &Crawler,
    h: f64,
) -> Option<Vec<f64>> {
    match (last, start) {
        (Some((cols, _, _)), _) => {
            let mut cols = cols.clone();
            for (g, u) in lay.gs.iter().flatten().zip(lay.grid.us.iter().flatten()) {
                let u = cols[u.index()];
                cols[g.index()] = cols[g.index()].max(u * u / h);
            }
            Some(cols)
        }
        (None, Some((incs, traj, _))) => Some(lay.start_columns(ncols, crawler, incs, h, traj)),
        (None, None) => None,
    }
}

/// The last round of the outer approximation: its columns, layout, bound and status.
struct MilpEnd {
    cols: Vec<f64>,
    lay: Layout,
    bound: f64,
    status: MilpStatus,
}

/// The MILP's gait, with increments of exact zero mean, replayed by the simulator (module
/// docs: the verified displacement is the one reported) and certified against the bound.
fn replayed_solution(
    crawler: &Crawler,
    problem: &GaitProblem,
    m: u32,
    end: MilpEnd,
    rounds: usize,
    start_objective: Option<f64>,
    what: &str,
) -> Result<DiscreteSolution> {
    let nb = crawler.blocks();
    let h = problem.period / (1usize << m) as f64;
    let MilpEnd {
        cols,
        lay,
        bound,
        status,
    } = end;
    let incs = lay.grid.increments(&cols);
    let x0: Vec<f64> = lay.grid.xs[0].iter().map(|c| cols[c.index()]).collect();
    let cost = grid_cost(problem, &incs, h);
    let g = replay_grid(crawler, problem.period, &incs, &x0, what)?;
    Ok(DiscreteSolution {
        m,
        step: h,
        certificate: certify(
            what,
            problem.length_scale(crawler),
            status,
            lay.displacement(&cols, nb),
            bound,
            g.verified,
            cost,
        )?,
        verified_displacement: g.verified,
        actuation_cost: cost,
        initial_state: g.initial_state,
        block_displacements: g.block_displacements,
        states: g.states,
        controls: g.controls,
        rounds,
        start_objective,
        polish: None,
    })
}

/// `h sum_i f2(U^i / h)`.
pub(super) fn grid_cost(problem: &GaitProblem, increments: &[Vec<f64>], h: f64) -> f64 {
    increments
        .iter()
        .map(|u| {
            let rate: Vec<f64> = u.iter().map(|v| v / h).collect();
            h * problem.cost.eval(&rate)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether the start columns of a gait (knots) pin a feasible point of the MILP of P_m:
    /// each column is fixed to its value (with `flip`, the slip binary of the first slipping
    /// block toggled) and HiGHS must find the problem feasible.
    fn start_is_feasible(
        c: &Crawler,
        p: &GaitProblem,
        m: u32,
        times: &[f64],
        lengths: &[Vec<f64>],
        flip: bool,
    ) -> bool {
        let rates = match p.cost {
            Cost::Quadratic { .. } => Some(TangentRates::new(&p.rate_bound)),
            Cost::None => None,
        };
        let (mut pb, lay) = build(c, p, m, rates.as_ref());
        let steps = 1usize << m;
        let h = p.period / steps as f64;
        let incs = sample_increments(
            times,
            lengths,
            c.stiffness(),
            &p.rate_bound,
            p.period,
            steps,
        );
        let traj = replay_grid(c, p.period, &incs, &vec![0.0; c.links()], "test").unwrap();
        let mut x = lay.start_columns(pb.num_cols(), c, &incs, h, &traj);
        let mut cols: Vec<Col> = Vec::new();
        for g in [
            &lay.grid.xs,
            &lay.grid.us,
            &lay.ps,
            &lay.qs,
            &lay.zps,
            &lay.zqs,
            &lay.gs,
            &lay.jumps,
        ] {
            cols.extend(g.iter().flatten().copied());
        }
        assert_eq!(cols.len(), pb.num_cols(), "the layout holds every column");
        let slipping = lay.zps.iter().chain(&lay.zqs).flatten();
        let slipping = *slipping
            .clone()
            .find(|z| x[z.index()] == 1.0)
            .expect("the start gait slips");
        if flip {
            x[slipping.index()] = 0.0;
        }
        for col in cols {
            let v = x[col.index()];
            let tol = 1e-9 * v.abs().max(1.0);
            pb.add_row(v - tol..=v + tol, [(col, 1.0)]);
        }
        // Every column is fixed: an LP feasibility question, asked without presolve (which
        // fails on this all-fixed model with an error status).
        use crate::optimal::solver::{Highs, SolveStatus};
        let mut model = Highs::new(pb, highs::Sense::Maximise, "test").unwrap();
        model.option("presolve", "off").unwrap();
        model.option("primal_feasibility_tolerance", 1e-9).unwrap();
        model.solve().unwrap().status == SolveStatus::Optimal
    }

    #[test]
    fn start_columns_are_a_feasible_point_of_the_milp() {
        // A travelling wave of two links (L_2 lags L_1 by a quarter period, strokes longer than C
        // is wide), sampled on 2 and 8 steps: blocks slip. On a uniform crawler and on one with per-link stiffness
        // and per-block friction, with no cost, a quadratic cost (epigraph columns) and a TV
        // bound loose enough for the wave (jump columns), its columns satisfy every row; with
        // one slip binary switched off they do not (the check can fail).
        let crawlers = [
            Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap(),
            Crawler::new(vec![1.0, 3.0], vec![0.9, 1.2, 0.7], vec![1.6, 2.1, 1.3]).unwrap(),
        ];
        let times = [0.0, 2.5, 5.0, 7.5, 10.0];
        let lengths = [
            vec![0.0, 0.0],
            vec![4.0, 0.0],
            vec![4.0, 4.0],
            vec![0.0, 4.0],
            vec![0.0, 0.0],
        ];
        let variants = [
            (Cost::None, None),
            (Cost::Quadratic { weight: 0.2 }, None),
            (Cost::None, Some(40.0)),
        ];
        for c in &crawlers {
            for (cost, tv) in variants {
                let p = GaitProblem::new(c, 10.0, &[1.0, 1.0], cost, tv).unwrap();
                for m in [1, 3] {
                    let what = format!("{c:?} {cost:?} {tv:?} m = {m}");
                    assert!(
                        start_is_feasible(c, &p, m, &times, &lengths, false),
                        "{what}"
                    );
                    assert!(
                        !start_is_feasible(c, &p, m, &times, &lengths, true),
                        "{what}"
                    );
                }
            }
        }
    }
}
