//! P_m's MILP ([`super::discrete`]'s module docs) solved to its bound: the outer-approximation
//! loop of a quadratic cost, a start gait as HiGHS's first incumbent, a bound on the control's
//! total variation, and the time limit. One loop for (P) and for its instances: a crawler's P_m
//! ([`crate::optimal::solve_discrete_global`]) is this MILP on its instance
//! ([`crate::model::crawler_as_general`]), started from its previous gait and re-verified by
//! its own simulator.

use super::discrete::{big_m, build, check_solver_range, column_bound, initial_cuts, Layout};
use super::discrete::{BigM, MAX_OA_ROUNDS};
use super::discrete_rows::{cost_epigraphs, epigraph_floor, separable, Form};
use super::geometry::Geometry;
use super::units::Units;
use crate::error::{Error, Result};
use crate::model::general::{GeneralCost, GeneralProblem};
use crate::optimal::milp::{solve_max, MilpStatus, OA_TOL};
use crate::optimal::units::scale_rows;
use highs::{Col, RowProblem};

/// A P_m process of the problem, in its variables, to start the MILP from (its first
/// incumbent): states at the knots `x^0..x^M`, controls `u^0..u^(M-1)` and the projection's
/// multipliers `mu^i_j = h lambda^i_j`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PmStart {
    /// States `x^0..x^M`.
    pub x: Vec<Vec<f64>>,
    /// Controls per step.
    pub u: Vec<Vec<f64>>,
    /// Multipliers per step and face.
    pub mu: Vec<Vec<f64>>,
}

/// What a P_m MILP is asked beyond the problem; [`PmOptions::default`] is (P)'s own: no start,
/// no total-variation bound, HiGHS's absolute gap `1e-9` times C's scale, units of order one
/// where the problem's are not ([`Units::needed`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct PmOptions {
    /// The first incumbent (a start that does not fit the model is only a lost hint).
    pub start: Option<PmStart>,
    /// `TV(u) = sum_(i,k) |u^(i+1)_k - u^i_k| <= V` of the periodic piecewise-constant control.
    pub total_variation: Option<f64>,
    /// HiGHS's absolute gap (`None`: `1e-9` times C's scale).
    pub abs_gap: Option<f64>,
    /// A bound on `J` the caller knows (a crawler's work bound), used when the time limit cut
    /// HiGHS short before it had a dual bound, if tighter than the MILP's column bound.
    pub bound_hint: Option<f64>,
    /// Solve in the problem's own units, never converted to [`Units`] of order one: for a
    /// problem its caller has put in such units by its own rule, a crawler's instance in the
    /// crawler's internal units ([`crate::optimal::units`]), where a second conversion only
    /// moves HiGHS's path. On the three-block crawler at `max_actuator_speed = 30` (its
    /// instance's controls 245 times its unit, so converted otherwise), P_4 took 105 s as given
    /// and over 300 s converted.
    pub keep_units: bool,
}

/// The MILP's last round: its layout and columns, objective and bound, status and rounds.
pub(crate) struct PmRun {
    /// The columns of the last round's model.
    pub(super) lay: Layout,
    /// Their values.
    pub(super) cols: Vec<f64>,
    /// The MILP's objective (with the cost's outer approximation).
    pub milp_objective: f64,
    /// Its bound on P_m's optimum.
    pub bound: f64,
    /// What it proves.
    pub status: MilpStatus,
    /// MILP solves (outer-approximation rounds).
    pub rounds: usize,
}

impl PmRun {
    /// The values of a family of columns, row by row.
    fn values(&self, cols: &[Vec<Col>]) -> Vec<Vec<f64>> {
        cols.iter()
            .map(|r| r.iter().map(|c| self.cols[c.index()]).collect())
            .collect()
    }

    /// The states `x^0..x^M`.
    pub fn states(&self) -> Vec<Vec<f64>> {
        self.values(&self.lay.x)
    }

    /// The controls `u^0..u^(M-1)`.
    pub fn controls(&self) -> Vec<Vec<f64>> {
        self.values(&self.lay.u)
    }

    /// `sum_i f1(mu^i)`: the reward of the MILP's multipliers.
    pub fn reward(&self, p: &GeneralProblem) -> f64 {
        let w = p.face_weights();
        self.values(&self.lay.mu)
            .iter()
            .map(|mu| mu.iter().zip(&w).map(|(m, w)| m * w).sum::<f64>())
            .sum()
    }
}

/// Solves P_m's MILP of `p` on `2^m` steps (`m` checked by the caller) within the current
/// deadline, in [`Units`] of order one: `p`'s data are checked against the solver's range in its
/// own units, then, where those are not of order one already ([`Units::needed`]) and the caller
/// did not choose them ([`PmOptions::keep_units`]), the MILP of `p` in units of order one is
/// solved ([`solve_scaled`]) and its answer converted back, or,
/// where HiGHS fails on it numerically, the MILP in `p`'s own units. `what` names the problem
/// in errors.
pub(crate) fn solve_pm_milp(
    p: &GeneralProblem,
    g: &Geometry,
    m: u32,
    opts: &PmOptions,
    what: &str,
) -> Result<PmRun> {
    let h = p.period / (1usize << m) as f64;
    check_solver_range(p, h, None)?;
    let bm = big_m(p, g, h)?;
    check_solver_range(p, h, Some(&bm))?;
    let units = Units::of(p);
    // The outer approximation's absolute floor in `p`'s units of `J` (a crawler's instance
    // keeps the crawler's: 1 in its internal units).
    let floor = if opts.keep_units { 1.0 } else { p.j_floor() };
    if opts.keep_units || !units.needed() {
        return solve_scaled(p, &bm, m, opts, what, floor);
    }
    // HiGHS's progress is of the scaled objective: reported times `s_x`.
    let scaled = crate::progress::with_objective_factor(units.state, || {
        let q = units.problem(p);
        let o = opts.in_units(&units);
        solve_scaled(&q, &in_units(&units, &bm), m, &o, what, floor / units.state)
    });
    match scaled {
        Ok(run) => Ok(run.in_own_units(&units)),
        Err(Error::Numerical(_)) => solve_scaled(p, &bm, m, opts, what, floor),
        Err(e) => Err(e),
    }
}

/// The big-M constants of P_m in `units`: the slacks and the multipliers' bound are lengths
/// (`M_mu = h G / sigma_*`, where `h` and `G` scale by `t_0` and `s_x / t_0`).
fn in_units(units: &Units, bm: &BigM) -> BigM {
    BigM {
        slack: bm.slack.iter().map(|s| s / units.state).collect(),
        multiplier: bm.multiplier / units.state,
    }
}

impl PmOptions {
    /// The options in `units`: the start's states and multipliers over `s_x`, its controls and a
    /// total variation over `s_u`, a gap and a bound on `J` over `s_x`.
    fn in_units(&self, units: &Units) -> PmOptions {
        let (sx, su) = (units.state, units.control);
        PmOptions {
            start: self.start.as_ref().map(|s| PmStart {
                x: scale_rows(&s.x, 1.0 / sx),
                u: scale_rows(&s.u, 1.0 / su),
                mu: scale_rows(&s.mu, 1.0 / sx),
            }),
            total_variation: self.total_variation.map(|v| v / su),
            abs_gap: self.abs_gap.map(|v| v / sx),
            bound_hint: self.bound_hint.map(|v| v / sx),
            keep_units: self.keep_units,
        }
    }
}

impl PmRun {
    /// The run of `p` in `units` read in `p`'s own: the states and multipliers times `s_x`, the
    /// controls times `s_u`, the objective and bound times `s_x` (the other columns, binaries,
    /// epigraphs and the control's jumps, stay as solved: no caller reads them).
    fn in_own_units(mut self, units: &Units) -> PmRun {
        let (sx, su) = (units.state, units.control);
        // A column is scaled once, though it may stand for two states (`x^M = x^0`).
        let mut factor = vec![1.0; self.cols.len()];
        for (family, f) in [(&self.lay.x, sx), (&self.lay.u, su), (&self.lay.mu, sx)] {
            for c in family.iter().flatten() {
                factor[c.index()] = f;
            }
        }
        for (v, f) in self.cols.iter_mut().zip(factor) {
            *v *= f;
        }
        self.milp_objective *= sx;
        self.bound *= sx;
        self
    }
}

/// P_m's MILP of `p` with big-M constants `bm` (module docs), in `p`'s units: for a quadratic
/// cost, the controls of each round's answer become cut points until the MILP's reward less the
/// true cost of its controls meets the bound within
/// [`OA_TOL`](crate::optimal::milp::OA_TOL) (else `approximation_limit`, after
/// [`MAX_OA_ROUNDS`] rounds or when no control is new); each later round starts from the
/// previous answer, its epigraphs raised onto the new cuts. The approximation's tolerance is
/// relative where `|J| >= floor` in `p`'s units of `J` and absolute below
/// ([`GeneralProblem::j_floor`], converted to `p`'s units).
fn solve_scaled(
    p: &GeneralProblem,
    bm: &BigM,
    m: u32,
    opts: &PmOptions,
    what: &str,
    floor: f64,
) -> Result<PmRun> {
    let mm = 1usize << m;
    let h = p.period / mm as f64;
    let gap = opts.abs_gap.unwrap_or(1e-9 * p.c.scale().max(1e-300));
    let fallback =
        column_bound(p, mm as f64 * bm.multiplier).min(opts.bound_hint.unwrap_or(f64::INFINITY));
    let mut cuts = initial_cuts(p)?;
    let mut last: Option<PmRun> = None;
    loop {
        let rounds = last.as_ref().map_or(0, |r| r.rounds) + 1;
        let (mut pb, lay) = build(p, m, Form::Milp(bm), &cuts);
        let jumps = add_total_variation(&mut pb, &lay.u, opts.total_variation);
        if crate::progress::out_of_time()? {
            return match last {
                Some(run) => Ok(PmRun {
                    status: MilpStatus::TimeLimit,
                    ..run
                }),
                None => Err(Error::TimeLimit(format!(
                    "{what}: the time limit was reached before any feasible point was found"
                ))),
            };
        }
        let start = match (&last, &opts.start) {
            (Some(run), _) => Some(raised(p, &cuts, &lay, run.cols.clone())),
            (None, Some(s)) => Some(start_columns(p, &cuts, &lay, &jumps, pb.num_cols(), s)),
            (None, None) => None,
        };
        let (cols, milp_objective, bound, status) = match solve_max(pb, what, start.as_deref(), gap)
        {
            // Out of time before this round had a point: the last round's answer stands.
            Err(Error::TimeLimit(_)) if last.is_some() => {
                let run = last.expect("checked");
                return Ok(PmRun {
                    status: MilpStatus::TimeLimit,
                    ..run
                });
            }
            r => r?,
        };
        // Without a dual bound from HiGHS: the last round's (a relaxation of this one, with
        // fewer cuts) or the fallback, never below the incumbent.
        let earlier = last.as_ref().map_or(fallback, |r| r.bound.min(fallback));
        let bound = bound.unwrap_or_else(|| earlier.max(milp_objective));
        let run = PmRun {
            lay,
            cols,
            milp_objective,
            bound,
            status,
            rounds,
        };
        if p.cost == GeneralCost::None {
            return Ok(run);
        }
        let u = run.values(&run.lay.u);
        let cost: f64 = u.iter().map(|u| h * p.cost.eval(u)).sum();
        let true_objective = run.reward(p) - cost;
        let converged = run.bound - true_objective <= OA_TOL * true_objective.abs().max(floor);
        if converged || status == MilpStatus::TimeLimit {
            return Ok(run);
        }
        let fresh = new_points(p, &cuts, &u);
        if rounds >= MAX_OA_ROUNDS || fresh.is_empty() {
            return Ok(PmRun {
                status: MilpStatus::ApproximationLimit,
                ..run
            });
        }
        cuts.extend(fresh);
        last = Some(run);
    }
}

/// The controls of an answer that would add a cut: for a separable cost, those with a component
/// of non-zero weight `r_k` farther than `1e-9` times the component's largest size over the cut
/// points (which hold U's extremes) from every cut point's; else those farther than that from
/// every cut point.
fn new_points(p: &GeneralProblem, cuts: &[Vec<f64>], u: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let range = |k: usize| {
        cuts.iter()
            .fold(0.0_f64, |r, c| r.max(c[k].abs()))
            .max(1e-300)
    };
    let ranges: Vec<f64> = (0..p.controls()).map(range).collect();
    let diagonal =
        super::discrete_rows::cost_matrix(&p.cost, p.controls()).and_then(|r| separable(&r));
    let mut known: Vec<Vec<f64>> = cuts.to_vec();
    let mut fresh = Vec::new();
    for ui in u {
        let near = |c: &Vec<f64>, k: usize| (c[k] - ui[k]).abs() <= 1e-9 * ranges[k];
        let is_new = if let Some(r) = &diagonal {
            (0..ui.len()).any(|k| r[k] != 0.0 && !known.iter().any(|c| near(c, k)))
        } else {
            !known.iter().any(|c| (0..ui.len()).all(|k| near(c, k)))
        };
        if is_new {
            known.push(ui.clone());
            fresh.push(ui.clone());
        }
    }
    fresh
}

/// `TV(u) <= V` on the periodic control: a jump column `s^i_k >= |u^(i+1)_k - u^i_k|` per
/// step and component and `sum s <= V`; returns the jump columns (none without a bound).
fn add_total_variation(pb: &mut RowProblem, us: &[Vec<Col>], bound: Option<f64>) -> Vec<Vec<Col>> {
    let Some(v) = bound else {
        return Vec::new();
    };
    let steps = us.len();
    let mut total = Vec::new();
    let jumps: Vec<Vec<Col>> = (0..steps)
        .map(|i| {
            us[i]
                .iter()
                .zip(&us[(i + 1) % steps])
                .map(|(&u0, &u1)| {
                    let s = pb.add_column(0.0, 0.0..);
                    pb.add_row(0.0.., [(s, 1.0), (u1, -1.0), (u0, 1.0)]);
                    pb.add_row(0.0.., [(s, 1.0), (u1, 1.0), (u0, -1.0)]);
                    total.push((s, 1.0));
                    s
                })
                .collect()
        })
        .collect();
    pb.add_row(..=v, total);
    jumps
}

/// A previous round's columns as the next round's start: the epigraphs raised onto the new
/// cuts (the controls and everything else are the same columns in the same order).
fn raised(p: &GeneralProblem, cuts: &[Vec<f64>], lay: &Layout, mut cols: Vec<f64>) -> Vec<f64> {
    let epigraphs = cost_epigraphs(p, cuts);
    for (e_i, u_i) in lay.e.iter().zip(&lay.u) {
        let u: Vec<f64> = u_i.iter().map(|c| cols[c.index()]).collect();
        for (e, ep) in e_i.iter().zip(&epigraphs) {
            cols[e.index()] = cols[e.index()].max(epigraph_floor(ep, &u));
        }
    }
    cols
}

/// The MILP's columns at a start process: its states, controls and multipliers, a face's
/// binary set where its multiplier is positive and the face holds at the step's end (to `1e-10`
/// of C's scale; elsewhere a multiplier of rounding size is dropped), the epigraphs at their
/// floors and the control's jumps.
fn start_columns(
    p: &GeneralProblem,
    cuts: &[Vec<f64>],
    lay: &Layout,
    jumps: &[Vec<Col>],
    ncols: usize,
    s: &PmStart,
) -> Vec<f64> {
    let mut cols = vec![0.0; ncols];
    let mm = lay.u.len();
    let epigraphs = cost_epigraphs(p, cuts);
    let tol = 1e-10 * p.c.scale();
    // Every state column: a periodic process's `x^M` is its `x^0`'s column, a Cauchy
    // problem's its own.
    for (cs, x) in lay.x.iter().zip(&s.x) {
        for (c, v) in cs.iter().zip(x) {
            cols[c.index()] = *v;
        }
    }
    for i in 0..mm {
        for (c, v) in lay.u[i].iter().zip(&s.u[i]) {
            cols[c.index()] = *v;
        }
        for (j, &mu) in s.mu[i].iter().enumerate() {
            if mu > 0.0 && p.c.slack(j, &s.x[i + 1]).abs() <= tol {
                cols[lay.mu[i][j].index()] = mu;
                cols[lay.z[i][j].index()] = 1.0;
            }
        }
        for (e, ep) in lay.e[i].iter().zip(&epigraphs) {
            cols[e.index()] = epigraph_floor(ep, &s.u[i]);
        }
        for (k, c) in jumps.get(i).into_iter().flatten().enumerate() {
            cols[c.index()] = (s.u[(i + 1) % mm][k] - s.u[i][k]).abs();
        }
    }
    cols
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Crawler;
    use crate::optimal::general::geometry::analyze_polyhedron;
    use crate::optimal::milp::replay_grid;
    use crate::optimal::{sample_increments, Cost, GaitProblem};

    /// Whether the start columns of a crawler's gait (knots) on P_m's grid pin a feasible point
    /// of the MILP of its instance: each column is fixed to its value (with `flip`, the binary of
    /// the first face with a reaction switched off) and HiGHS must find the problem feasible.
    fn start_is_feasible(
        c: &Crawler,
        p: &GaitProblem,
        m: u32,
        (times, lengths): (&[f64], &[Vec<f64>]),
        flip: bool,
    ) -> bool {
        let inst = p.instance(c).unwrap();
        let q = &inst.problem;
        let g = analyze_polyhedron(&q.c).unwrap();
        let steps = 1usize << m;
        let h = p.period / steps as f64;
        let bm = big_m(q, &g, h).unwrap();
        let cuts = initial_cuts(q).unwrap();
        let (mut pb, lay) = build(q, m, Form::Milp(&bm), &cuts);
        let jumps = add_total_variation(&mut pb, &lay.u, p.max_total_variation);
        let incs = sample_increments(
            times,
            lengths,
            c.stiffness(),
            &p.rate_bound,
            p.period,
            steps,
        );
        let traj = replay_grid(c, p.period, &incs, &vec![0.0; c.links()], "test").unwrap();
        let start = crate::optimal::discrete::pm_start(c, &inst, &incs, h, &traj);
        let mut x = start_columns(q, &cuts, &lay, &jumps, pb.num_cols(), &start);
        let mut cols: Vec<Col> = lay.x[..steps].iter().flatten().copied().collect();
        for family in [&lay.u, &lay.mu, &lay.z, &lay.e, &jumps] {
            cols.extend(family.iter().flatten().copied());
        }
        assert_eq!(cols.len(), pb.num_cols(), "the layout holds every column");
        let slipping = *lay
            .z
            .iter()
            .flatten()
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
    fn a_crawlers_start_columns_are_a_feasible_point_of_its_instances_milp() {
        // A travelling wave of two links (L_2 lags L_1 by a quarter period, strokes longer than
        // C is wide), sampled on 2 and 8 steps: blocks slip. On a uniform crawler and on one
        // with per-link stiffness and per-block friction, with no cost, a quadratic cost
        // (epigraph columns) and a TV bound loose enough for the wave (jump columns), its
        // columns satisfy every row; with one binary switched off they do not (the check can
        // fail).
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
                    let knots = (&times[..], &lengths[..]);
                    assert!(start_is_feasible(c, &p, m, knots, false), "{what}");
                    assert!(!start_is_feasible(c, &p, m, knots, true), "{what}");
                }
            }
        }
    }
}
