//! Exact continuous-time gaits: the phase formulation (SPEC §7), solved globally over gaits of
//! at most `K` phases as a mixed-integer linear program in HiGHS.
//!
//! Phase `j` lasts `tau_j >= 0` with a constant control `u_j` and a slip mode per block
//! (stick, slip+, slip-), encoded by binaries `s+_{j,b}`, `s-_{j,b}` (`s+ + s- <= 1`). With
//! `U_j = tau_j u_j`, states `x_j` at phase starts and block displacements `D_{j,b} = P - Q`:
//!
//! ```text
//! maximise   (1/N) sum_{j,b} D_{j,b} - (c/2) sum_{j,l} g_{j,l}         (g >= U^2 / tau)
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
//! Valid inequalities: at most `n` blocks slip in a phase (if all `N` did, the forces would
//! sum to `sum_b ±mu_b = 0`, which the uniqueness condition excludes).
//!
//! The quadratic cost is the perspective `(c/2) |U_j|^2 / tau_j`, handled by outer
//! approximation ([`TangentRates`]): tangent cuts under-estimate it, so the MILP's bound stays
//! valid; cuts at the rates of each solution are added and the MILP re-solved (from the previous
//! gait) until the true objective of the incumbent meets the bound. A total-variation bound on
//! `u = U / tau` is not linear in these variables and is refused (the discrete method has it).
//!
//! [`grow_phases`] raises `K` until the value stops improving, each MILP starting from the
//! previous optimum (an empty phase appended), so it has an incumbent from the outset.
//!
//! Every answer is re-verified by [`simulate`] (exact method) on the piecewise-linear actuation
//! whose knots are the phase boundaries.

use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::milp::{
    block_speed_bound, certify, check_time_limit, force_row, replay, solve_max, TangentRates,
    OA_TOL,
};
use crate::optimal::{Certificate, Cost, GaitProblem, MilpStatus};
use highs::{Col, RowProblem};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Largest number of phases accepted.
pub const MAX_PHASES: usize = 64;

/// Outer-approximation rounds at most (each a MILP solve).
const MAX_OA_ROUNDS: usize = 40;

/// A gait of at most `K` phases, globally optimal among them (or with its gap).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PhaseSolution {
    /// `K`, the number of phases allowed.
    pub phases: usize,
    /// What the MILP proves (its bound is on `J` over gaits of at most `phases` phases).
    pub certificate: Certificate,
    /// Displacement per period re-verified by the exact simulator.
    pub verified_displacement: f64,
    /// `int f2(u) dt` of the gait.
    pub actuation_cost: f64,
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
    /// MILP solves (outer-approximation rounds for a quadratic cost, else 1).
    pub rounds: usize,
}

impl PhaseSolution {
    /// `J` = verified displacement minus actuation cost.
    pub fn objective(&self) -> f64 {
        self.verified_displacement - self.actuation_cost
    }
}

/// Columns of the phase MILP.
struct Layout {
    tau: Vec<Col>,
    used: Vec<Col>,
    xs: Vec<Vec<Col>>,
    us: Vec<Vec<Col>>,
    ps: Vec<Vec<Col>>,
    qs: Vec<Vec<Col>>,
    sp: Vec<Vec<Col>>,
    sq: Vec<Vec<Col>>,
    /// Cost epigraph `g_{j,l} >= U_{j,l}^2 / tau_j` (quadratic cost only).
    g: Vec<Vec<Col>>,
}

fn build(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    rates: Option<&TangentRates>,
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
    let cols = |cost: f64, hi: f64, pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| (0..nb).map(|_| pb.add_column(cost, 0.0..=hi)).collect())
            .collect()
    };
    let ps = cols(inv_n, v * t, &mut pb);
    let qs = cols(-inv_n, v * t, &mut pb);
    let bins = |pb: &mut RowProblem| -> Vec<Vec<Col>> {
        (0..phases)
            .map(|_| (0..nb).map(|_| pb.add_integer_column(0.0, 0..=1)).collect())
            .collect()
    };
    let sp = bins(&mut pb);
    let sq = bins(&mut pb);
    let g: Vec<Vec<Col>> = if rates.is_some() {
        (0..phases)
            .map(|_| {
                a.iter()
                    .map(|&al| pb.add_column(-0.5 * weight, 0.0..=al * al * t))
                    .collect()
            })
            .collect()
    } else {
        Vec::new()
    };
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
            if let Some(r) = rates {
                r.add_cuts(&mut pb, l, g[j][l], us[j][l], Some(tau[j]), 0.0);
            }
        }
        let mut slipping = Vec::with_capacity(2 * nb);
        for b in 0..nb {
            let w = mp[b] + mm[b];
            pb.add_row(-mm[b]..=mp[b], force_row(&xs[j], b));
            pb.add_row(..=0.0, [(ps[j][b], 1.0), (tau[j], -v)]);
            pb.add_row(..=0.0, [(qs[j][b], 1.0), (tau[j], -v)]);
            pb.add_row(..=0.0, [(ps[j][b], 1.0), (sp[j][b], -v * t)]);
            pb.add_row(..=0.0, [(qs[j][b], 1.0), (sq[j][b], -v * t)]);
            pb.add_row(..=1.0, [(sp[j][b], 1.0), (sq[j][b], 1.0)]);
            slipping.extend([(sp[j][b], 1.0), (sq[j][b], 1.0)]);
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
        // At most n blocks slip (module docs).
        pb.add_row(..=n as f64, slipping);
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
    let layout = Layout {
        tau,
        used,
        xs,
        us,
        ps,
        qs,
        sp,
        sq,
        g,
    };
    (pb, layout)
}

/// A gait read off the MILP's columns, empty phases removed.
struct RawGait {
    durations: Vec<f64>,
    increments: Vec<Vec<f64>>,
    states: Vec<Vec<f64>>,
    block_displacements: Vec<Vec<f64>>,
    modes: Vec<Vec<i8>>,
}

impl RawGait {
    fn read(lay: &Layout, cols: &[f64], t: f64) -> Self {
        let val = |c: &Col| cols[c.index()];
        let keep: Vec<usize> = (0..lay.tau.len())
            .filter(|&j| val(&lay.tau[j]) > 1e-12 * t)
            .collect();
        let mut states: Vec<Vec<f64>> = keep
            .iter()
            .map(|&j| lay.xs[j].iter().map(val).collect())
            .collect();
        let x0 = lay.xs[keep.first().copied().unwrap_or(0)]
            .iter()
            .map(val)
            .collect();
        states.push(x0);
        RawGait {
            durations: keep.iter().map(|&j| val(&lay.tau[j])).collect(),
            increments: keep
                .iter()
                .map(|&j| lay.us[j].iter().map(val).collect())
                .collect(),
            states,
            block_displacements: keep
                .iter()
                .map(|&j| {
                    lay.ps[j]
                        .iter()
                        .zip(&lay.qs[j])
                        .map(|(p, q)| val(p) - val(q))
                        .collect()
                })
                .collect(),
            modes: keep
                .iter()
                .map(|&j| {
                    lay.sp[j]
                        .iter()
                        .zip(&lay.sq[j])
                        .map(|(p, q)| match (val(p) > 0.5, val(q) > 0.5) {
                            (true, _) => 1,
                            (_, true) => -1,
                            _ => 0,
                        })
                        .collect()
                })
                .collect(),
        }
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

    /// All columns of a `phases`-phase layout holding this gait (empty phases appended), with
    /// exact cost epigraphs: a feasible start for the MILP.
    fn columns(&self, lay: &Layout, ncols: usize) -> Vec<f64> {
        let mut x = vec![0.0; ncols];
        let p = self.durations.len();
        for j in 0..lay.tau.len() {
            let state = if j < p {
                &self.states[j]
            } else {
                &self.states[p]
            };
            for (c, v) in lay.xs[j].iter().zip(state) {
                x[c.index()] = *v;
            }
            if j >= p {
                continue;
            }
            let d = self.durations[j];
            x[lay.tau[j].index()] = d;
            x[lay.used[j].index()] = 1.0;
            for (l, (c, u)) in lay.us[j].iter().zip(&self.increments[j]).enumerate() {
                x[c.index()] = *u;
                if let Some(g) = lay.g.get(j) {
                    x[g[l].index()] = u * u / d;
                }
            }
            for (b, &dv) in self.block_displacements[j].iter().enumerate() {
                x[lay.ps[j][b].index()] = dv.max(0.0);
                x[lay.qs[j][b].index()] = (-dv).max(0.0);
                x[lay.sp[j][b].index()] = f64::from(u8::from(self.modes[j][b] > 0));
                x[lay.sq[j][b].index()] = f64::from(u8::from(self.modes[j][b] < 0));
            }
        }
        x
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

/// Solves (P) globally over gaits of at most `phases` phases (module docs).
pub fn solve_phase_global(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
) -> Result<PhaseSolution> {
    solve_phase_from(crawler, problem, phases, time_limit, None)
}

/// [`solve_phase_global`] with a known gait of at most `phases` phases as the first incumbent.
pub fn solve_phase_from(
    crawler: &Crawler,
    problem: &GaitProblem,
    phases: usize,
    time_limit: Option<f64>,
    start: Option<&PhaseSolution>,
) -> Result<PhaseSolution> {
    crawler.require_unique()?;
    check_time_limit(time_limit)?;
    if !(2..=MAX_PHASES).contains(&phases) {
        return Err(Error::invalid(
            "phases",
            phases,
            format!("must be in 2..={MAX_PHASES}"),
        ));
    }
    if let Some(v) = problem.max_total_variation {
        return Err(Error::invalid(
            "gait.max_total_variation",
            v,
            "bounds the total variation of u = U / tau, which the phase formulation cannot \
             express linearly; use --method discrete",
        ));
    }
    if let Some(s) = start {
        if s.durations.len() > phases {
            return Err(Error::invalid(
                "start",
                s.durations.len(),
                format!("has more than {phases} phases"),
            ));
        }
    }
    let t = problem.period;
    let a = &problem.rate_bound;
    let what = format!("{phases}-phase gait");
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
        let (pb, lay) = build(crawler, problem, phases, rates.as_ref());
        let ncols = pb.num_cols();
        let start_cols = incumbent.as_ref().map(|g| g.columns(&lay, ncols));
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
        let (cols, _, bound, status) = solve_max(pb, left, &what, start_cols.as_deref())?;
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
            &raw.states[0],
            Method::Exact,
            &what,
        )?
        .displacement_per_period
        .expect("converged")
    };
    let certificate = certify(&what, status, raw.displacement(), bound, verified, cost)?;
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

/// How [`grow_phases`] raises `K`.
#[derive(Debug, Clone, PartialEq)]
pub struct GrowOptions {
    /// First `K`.
    pub min_phases: usize,
    /// Last `K` tried.
    pub max_phases: usize,
    /// Stop after this many consecutive `K` without a gain, counted once `J_K > 0` (before,
    /// `K` is too small for any gait to move the crawler, e.g. one link needs 4 phases).
    pub patience: usize,
    /// Wall-clock limit for the whole growth, seconds.
    pub time_limit: Option<f64>,
}

impl Default for GrowOptions {
    fn default() -> Self {
        GrowOptions {
            min_phases: 2,
            max_phases: 16,
            patience: 2,
            time_limit: None,
        }
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
    /// `"optimal"` or `"time_limit"`.
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

/// Raises `K` from `min_phases` until `J_K` has not improved (beyond `1e-7` relative) for
/// `patience` consecutive `K`, or `max_phases` or the time limit is reached (module docs). The
/// returned gait is the best found, and its certificate is that of the largest `K` solved to
/// optimality (the gait has at most that many phases, and no gait of that many does better
/// than the bound). `progress` sees each `K` as it is solved.
pub fn grow_phases(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &GrowOptions,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<PhaseGrowth> {
    check_time_limit(opts.time_limit)?;
    if opts.min_phases < 2 || opts.max_phases < opts.min_phases || opts.max_phases > MAX_PHASES {
        return Err(Error::invalid(
            "phases",
            format!("{}..={}", opts.min_phases, opts.max_phases),
            format!("needs 2 <= min <= max <= {MAX_PHASES}"),
        ));
    }
    if opts.patience == 0 {
        return Err(Error::invalid("patience", 0, "must be at least 1"));
    }
    let began = Instant::now();
    let mut best: Option<PhaseSolution> = None;
    let mut table = Vec::new();
    let mut without_gain = 0;
    let mut stop = GrowthStop::MaxPhases;
    // y' = v_m(z') (SPEC §3): when v_m <= 0 everywhere, J <= 0 for every gait.
    let idle = crawler.analyze().moves_forward == Some(false);
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
            s.objective() - b.objective() - 1e-7 * b.objective().abs().max(1.0)
        });
        if timed_out {
            if gain > 0.0 || best.is_none() {
                best = Some(s);
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
        } else if best.as_ref().is_some_and(|b| b.objective() <= 0.0) {
            // Nothing moves yet: K is still too small.
        } else {
            without_gain += 1;
            // Same gait, now certified for this larger K.
            if let Some(b) = best.as_mut() {
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
