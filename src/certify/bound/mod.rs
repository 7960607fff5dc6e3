//! An upper bound on the continuous-time gait problem (P) over *all* `T`-periodic gaits (theory
//! §12), by a piecewise-linear storage function: no limit on the number of slip phases.
//!
//! # The argument
//!
//! Let `(x, L)` be any `T`-periodic gait (`|u_l| <= a_l`, `u = K L'`, `x(0) = x(T)`,
//! `L(0) = L(T)`) and `l = L - min_t L` componentwise. `L_l` rises and falls back within a period at
//! rate at most `a_l / k_l`, so `l_l(t) in [0, lmax_l]`, `lmax_l = a_l T / (2 k_l)`: the state
//! `p = (x, l)` stays in `C x box`. Let `V` be continuous on a simplicial grid covering
//! `C x box`, linear on each simplex `S` with gradient `g_S`, and suppose
//!
//! ```text
//! (R)   <g_S, (x', l')> + rho >= y'     for every simplex S, every face F of C that S meets,
//!                                       and every control u with which x stays on F,
//! ```
//!
//! where `(x', l', y')` are the rates on the relative interior of `F` under `u` (linear in `u`
//! there: [`faces`]). Then `J = y(T) - y(0) <= rho T`. Proof: `x`, `l` are Lipschitz; at almost
//! every `t` they are differentiable, `V(p(t))` is differentiable, and
//! - `x'(t)` lies in the lineality space of the tangent cone of C at `x(t)` (`x` stays in C both
//!   forward and backward in time), so with `F(t)` the face whose relative interior holds
//!   `x(t)`, `x'` is along `F(t)` and, by the Moreau decomposition of `u = x' + K eta`,
//!   `eta in N_C(x)`, `x'` is the projection of `u` and the reaction multipliers `lambda(u)` are
//!   non-negative: `u` is one of the controls of (R) for `F(t)`, and `y'(t)` is its `y'` (the
//!   block velocities are the multipliers, theory §4);
//! - `d/dt V(p(t))` is the one-sided directional derivative of `V` at `p(t)` along
//!   `p'(t)` (Lipschitz `V`: `V(p + h p' + o(h)) = V(p + h p') + o(h)`). The finitely many closed
//!   simplices cover a neighbourhood of `p(t)` in `C x box`, and `p(t) + e p'(t)` lies in
//!   `C x box` for small `e > 0` (`x'` is along `F(t)`, and `l_l' = 0` wherever `l_l` is at an
//!   end of its range, an extremum of a differentiable function); so
//!   one simplex `S` holds `p + e p'` for all small `e` (each simplex meets the ray in an
//!   interval starting at `e = 0` or not at all), and the derivative is `<g_S, p'>`. That `S`
//!   holds points whose `x` lies in the relative interior of `F(t)`, so `S` meets `F(t)` and
//!   (R) applies to the pair `(S, F(t))`, whether `p(t)` is inside a simplex, on a boundary
//!   between simplices, on a face of C or on a face of the box.
//!
//! So `y' <= rho + d/dt V(p(t))` almost everywhere; integrate over the period: `V(p(T)) =
//! V(p(0))`. Each inequality of (R) is linear in `u` on the polytope of controls that keep `x`
//! on `F`, so it holds on that polytope iff at its vertices: (R) is a finite LP in the node
//! values of `V` and `rho`; minimising `rho` gives the bound. The pairs `(S, F)` are taken from
//! a superset of those that meet (a test on the simplex's vertices, [`grid`]), which only adds
//! rows. Whatever `V` the solver returns, the bound reported is recomputed from it,
//! `rho = max over rows of (y' - <g_S, d>)`, so it holds exactly for that `V` (an unfinished
//! solve gives a weaker but still valid bound).
//!
//! A quadratic cost `f2(u) = (c/2) |u|^2` enters through a piecewise-linear under-estimator
//! `f2_low <= f2`, per link the largest of `m` tangents ([`BoundSettings::cost_tangents`]), and
//! the rows read `<g_S, d> + rho >= y' - f2_low(u)`: then `y' - f2 <= rho + dV/dt` and
//! `J <= rho T` as above. `f2_low` is affine on each cell of a product of intervals of the
//! control box, so the row, affine in `u` there, holds on `U_F` iff it holds at the vertices
//! of `U_F` cut by each cell (module `faces`). A bound on the total variation is ignored (a
//! relaxation).
//!
//! # Tightness
//!
//! The LP's dual is a measure on (simplex, face, control vertex) invariant under the flow when
//! tested against piecewise-linear functions on the grid: controls are relaxed (convex
//! combinations) and positions are blurred within a simplex, so the bound is above the optimum
//! and tightens as the grid is refined (measured in the README, "Upper bound over all gaits").
//!
//! Where it stops: the rows hold along *every* motion with `l` in the box, not only the
//! `T`-periodic ones, so `rho` is at least the displacement per unit time of any periodic gait
//! of any period whose actuator lengths fit the box. Without a cost and for one link the best of
//! those is the `T`-periodic optimum (the bound converges to it); with a quadratic cost a
//! slower gait of a longer period over the whole box pays less: for one link, sweep
//! `D = a T / 2` at rate `r = (D - w) / (2 D k c)` moves `(D - w)^2 / (8 D^2 k^2 c)` per unit
//! time, above `J* / T` unless `r >= a`, i.e. `c <= (1 - 2 w / (a T)) / (2 a k)` (the optimum
//! runs at the rate bound). Beyond that the bound stays above `J*` on every grid.
//!
//! # A time-dependent `V(t, x, l)` cannot do better
//!
//! The problem is autonomous (neither the motions nor `y'` depend on `t`). Continuous form: if
//! `V(t, p)`, `T`-periodic in `t`, satisfies `rho + d_t V + <grad_p V, p'> >= y'` for every
//! `(t, p, u)`, average over `t`: `int_0^T d_t V dt = V(T, p) - V(0, p) = 0`, so `Vbar =
//! (1/T) int V dt` satisfies the time-independent inequality with the same `rho`. In the dual:
//! a measure `mu(p, u)` invariant for `V(p)` lifts to `(dt / T) x mu`, invariant for `V(t, p)`
//! with the same value. Discrete form, on the same spatial grid: take `V_k(p)`, `k = 0..nt-1`
//! (`V_nt = V_0`), linear in `t` between the times `k dt`, `dt = T / nt`. On the slab
//! `t = (k + theta) dt` and a simplex `S` with control `u`,
//! `d/dt V = (V_{k+1}(p) - V_k(p)) / dt + <(1 - theta) g_k + theta g_{k+1}, d(u)>`: affine in
//! `p` (through the first term), affine in `theta`, affine in `u`, separately (the product is
//! `theta` times a function of `u`), so on the product `S x [0, 1] x U_F` its minimum is at a
//! vertex of each factor: the rows
//! `rho + (V_{k+1}(v) - V_k(v)) / dt + <g_{k+theta}, d(u)> >= y'(u)` at the vertices `v` of `S`,
//! `theta in {0, 1}`, the control vertices `u`, are valid (the slab ends are a null set of
//! times, and motion along simplex boundaries is handled as above, with prisms `S x slab`).
//! Summing the `theta = 0` rows over `k` at a fixed `v` telescopes the time-derivative terms to
//! 0 and leaves `nt (rho + <gbar, d(u)> - y'(u)) >= 0`, the time-independent row for
//! `Vbar = mean_k V_k` (`gbar` its gradient on `S`); a time-independent `V` is a time-dependent
//! one with `V_k = V`. So both LPs have the same optimal `rho`. The time-dependent LP is built in
//! the tests (`timed`) and agrees to solver tolerance (README, "Upper bound over all gaits");
//! the period enters the bound only through the box `[0, a_l T / (2 k_l)]`.

mod faces;
mod grid;
mod work;
// Built only to measure it against the time-independent bound (module doc: it never helps).
#[cfg(test)]
mod timed;

pub use crate::optimal::bound_record::{BoundStatus, UpperBound, METHOD};
pub use work::work_bound;

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::solver::{Highs, SolveStatus};
use crate::optimal::{Cost, GaitProblem};
use crate::progress;
use highs::{ColProblem, Row, Sense};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Largest number of links the bound accepts (the grid has `2n` dimensions).
pub const MAX_BOUND_LINKS: usize = 3;

/// Largest number of grid simplices (an LP with a few rows each).
pub const MAX_SIMPLICES: usize = 4_000_000;

/// Settings of [`upper_bound`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BoundSettings {
    /// Grid steps across the widest link-force range of C (the `x` step `h` is that range over
    /// this; C is tiled exactly when every friction threshold is a multiple of `h`).
    pub resolution: usize,
    /// Grid steps across each actuator-length range `[0, a_l T / (2 k_l)]`.
    pub box_resolution: usize,
    /// Time limit of the LP in seconds (a solve cut short still gives a valid, weaker bound).
    pub time_limit: f64,
    /// With a quadratic cost: tangents per link of its piecewise-linear under-estimator (taken
    /// at the centres of equal cells of `[-a_l, a_l]`; it is below the cost by at most
    /// `c a_l^2 / (2 m^2)`). More tangents tighten the bound and multiply the control vertices,
    /// hence the rows, by up to about `m^n`. Ignored without a cost.
    pub cost_tangents: usize,
}

impl Default for BoundSettings {
    /// Resolution 8 in `x` and in `l`, one minute, 4 tangents of the cost per link.
    fn default() -> Self {
        BoundSettings {
            resolution: 8,
            box_resolution: 8,
            time_limit: 60.0,
            cost_tangents: 4,
        }
    }
}

fn check_settings(s: &BoundSettings) -> Result<()> {
    if s.resolution == 0 || s.resolution > 1000 {
        return Err(Error::invalid(
            "bound.resolution",
            s.resolution,
            "must be between 1 and 1000",
        ));
    }
    if s.box_resolution == 0 || s.box_resolution > 1000 {
        return Err(Error::invalid(
            "bound.box_resolution",
            s.box_resolution,
            "must be between 1 and 1000",
        ));
    }
    if s.cost_tangents == 0 || s.cost_tangents > 1000 {
        return Err(Error::invalid(
            "bound.cost_tangents",
            s.cost_tangents,
            "must be between 1 and 1000",
        ));
    }
    if !(s.time_limit.is_finite() && s.time_limit > 0.0) {
        return Err(Error::invalid(
            "bound.time_limit",
            s.time_limit,
            "must be positive and finite",
        ));
    }
    Ok(())
}

/// The grid and the face motions of one bound computation.
struct Prepared {
    grid: grid::Grid,
    motions: Vec<(Vec<usize>, faces::FaceMotion)>,
    tol: f64,
    aligned: bool,
}

/// Checks the settings and the crawler, and builds the grid of `C x box` and the face motions.
fn prepare(crawler: &Crawler, problem: &GaitProblem, settings: &BoundSettings) -> Result<Prepared> {
    check_settings(settings)?;
    crawler.require_unique()?;
    let n = crawler.links();
    if n > MAX_BOUND_LINKS {
        return Err(Error::invalid(
            "crawler.blocks",
            crawler.blocks(),
            format!(
                "the upper bound's grid has 2(N-1) dimensions: at most {} blocks",
                MAX_BOUND_LINKS + 1
            ),
        ));
    }
    let a = &problem.rate_bound;
    let k = crawler.stiffness();
    let lmax: Vec<f64> = (0..n)
        .map(|l| a[l] * problem.period / (2.0 * k[l]))
        .collect();
    let ranges = crawler.link_force_ranges();
    let width = ranges.iter().fold(0.0_f64, |w, r| w.max(r[1] - r[0]));
    let h = width / settings.resolution as f64;
    let scale = crawler.force_scale();
    let tol = 1e-9 * scale;
    let aligned = crawler
        .mu_forward()
        .iter()
        .chain(crawler.mu_backward())
        .all(|m| ((m / h).round() * h - m).abs() <= tol);
    let grid = grid::Grid::new(crawler, h, &lmax, settings.box_resolution, aligned);
    let fact: usize = (1..=2 * n).product();
    let simplices = grid.cells().saturating_mul(fact);
    if simplices > MAX_SIMPLICES {
        return Err(Error::invalid(
            "bound.resolution",
            format!("{} x {}", settings.resolution, settings.box_resolution),
            format!("the grid has {simplices} simplices (at most {MAX_SIMPLICES})"),
        ));
    }
    let cost = faces::CostModel {
        weight: match problem.cost {
            Cost::None => 0.0,
            Cost::Quadratic { weight } => weight,
        },
        tangents: settings.cost_tangents,
    };
    let motions: Vec<_> = faces::faces(crawler, tol)
        .into_iter()
        .map(|f| {
            let m = faces::face_motion(crawler, a, &f, cost);
            (f, m)
        })
        .collect();
    Ok(Prepared {
        grid,
        motions,
        tol,
        aligned,
    })
}

/// Receives one row `sum_i c_i V[col_i] + rho >= y` of a storage LP: `(cols, c, y)`.
type RowSink<'a> = dyn FnMut(&[usize], &[f64], f64) + 'a;

/// Emits every row of a storage LP to the sink it is given.
type RowSource<'a> = dyn Fn(&mut RowSink) + 'a;

/// What [`solve_storage_lp`] found.
struct LpOutcome {
    /// The smallest `rho` the returned storage function satisfies every row with.
    rate: f64,
    status: BoundStatus,
    rows: usize,
    /// Storage values referred to by some row, plus `rho`.
    columns: usize,
}

/// Minimises `rho` subject to the rows of `rows` over `columns` storage values (a column may
/// appear twice in a row: its coefficients are added), then re-evaluates `rho` from the storage
/// function read off the dual, so the rate returned is valid for whatever the solver returned.
/// The LP runs within the current deadline ([`progress::within`]).
fn solve_storage_lp(columns: usize, rows: &RowSource) -> Result<LpOutcome> {
    // The LP  min rho  s.t.  <g_S, d> + rho >= y  (one row per (S, F, u)) has far more rows
    // than node values, and rho is in every row: HiGHS's interior point method chokes on that
    // dense column (measured: 465 s for 6.4e5 rows), so its dual is solved,
    //   max sum_r y'_r m_r  s.t.  sum_r A_{r,p} m_r = 0 (every node p but one),
    //                             sum_r m_r <= 1,  m >= 0,
    // (an occupation measure on (simplex, face, control) that is invariant when tested against
    // the piecewise-linear functions of the grid), and V is read from its node duals.
    let mut used = vec![false; columns];
    rows(&mut |cols, _, _| cols.iter().for_each(|&p| used[p] = true));
    let pinned = used.iter().position(|&u| u);
    let mut pb = ColProblem::default();
    // Each constrained node's row handle and its index (HiGHS numbers rows as they are added).
    let mut added = 0usize;
    let node_rows: Vec<Option<(Row, usize)>> = used
        .iter()
        .enumerate()
        .map(|(p, &u)| {
            (u && Some(p) != pinned).then(|| {
                added += 1;
                (pb.add_row(0.0..=0.0), added - 1)
            })
        })
        .collect();
    let mass = pb.add_row(..=1.0);
    let mut count = 0usize;
    let mut entries: Vec<(Row, f64)> = Vec::new();
    let mut merged: Vec<(usize, f64)> = Vec::new();
    rows(&mut |cols, coefs, y| {
        merged.clear();
        for (&p, &c) in cols.iter().zip(coefs) {
            match merged.iter_mut().find(|(q, _)| *q == p) {
                Some(e) => e.1 += c,
                None => merged.push((p, c)),
            }
        }
        entries.clear();
        for &(p, c) in &merged {
            if let (Some((r, _)), true) = (node_rows[p], c != 0.0) {
                entries.push((r, c));
            }
        }
        entries.push((mass, 1.0));
        pb.add_column(y, 0.0.., &entries);
        count += 1;
    });
    progress::check()?;
    let mut solver = Highs::new(pb, Sense::Maximise, "upper bound LP")?;
    // Interior point without crossover: a vertex is not needed, as the bound is re-evaluated
    // from V below.
    solver.option("solver", "ipm")?;
    solver.option("run_crossover", "off")?;
    // Presolve off: without a basis HiGHS's postsolve cannot restore the duals V is read from.
    solver.option("presolve", "off")?;
    solver.until_deadline();
    let answer = solver.solve()?;
    let status = match answer.status {
        SolveStatus::Optimal => BoundStatus::Optimal,
        SolveStatus::TimeLimit { .. } => BoundStatus::TimeLimit,
        SolveStatus::Infeasible => {
            return Err(Error::Numerical(
                "upper bound LP: HiGHS reports it infeasible (it has the feasible point m = 0)"
                    .into(),
            ))
        }
    };
    let dual: Vec<f64> = node_rows
        .iter()
        .map(|r| r.map_or(0.0, |(_, i)| answer.row_duals[i]))
        .collect();
    // Re-evaluation: the smallest rho the storage function satisfies every row with. The sign
    // of HiGHS's duals is a convention; both signs give valid bounds, the smaller is reported.
    let mut rate = [f64::NEG_INFINITY; 2];
    rows(&mut |cols, coefs, y| {
        let g: f64 = cols.iter().zip(coefs).map(|(&p, c)| c * dual[p]).sum();
        rate[0] = rate[0].max(y - g);
        rate[1] = rate[1].max(y + g);
    });
    let rate = rate[0].min(rate[1]);
    if !rate.is_finite() {
        return Err(Error::Numerical(
            "upper bound LP: the storage function is not finite".into(),
        ));
    }
    Ok(LpOutcome {
        rate,
        status,
        rows: count,
        columns: used.iter().filter(|&&u| u).count() + 1,
    })
}

/// The tangents of the cost used (0 without a cost), as recorded in results.
fn cost_tangents(problem: &GaitProblem, settings: &BoundSettings) -> usize {
    match problem.cost {
        Cost::None => 0,
        Cost::Quadratic { .. } => settings.cost_tangents,
    }
}

/// The grids [`upper_bound`] solves, coarse to fine: `settings`' resolutions halved while both
/// stay at least 2 (and stay whole), then `settings`' own. Halving keeps the grids nested (a
/// coarse grid's piecewise-linear functions are piecewise linear on the finer one), so a
/// finished finer LP is never worse.
pub fn refinement_ladder(settings: &BoundSettings) -> Vec<(usize, usize)> {
    let mut ladder = vec![(settings.resolution, settings.box_resolution)];
    let (mut r, mut b) = (settings.resolution, settings.box_resolution);
    while r % 2 == 0 && b % 2 == 0 && r / 2 >= 2 && b / 2 >= 2 {
        r /= 2;
        b /= 2;
        ladder.push((r, b));
    }
    ladder.reverse();
    ladder
}

/// A valid upper bound on `J` over every `T`-periodic gait of `problem` for `crawler` (the
/// module's argument): the best of the piecewise-linear storage functions found on the grids of
/// [`refinement_ladder`], coarse to fine, while `settings.time_limit` lasts. Every grid's bound
/// is valid, so the smallest is returned, with the grid and LP status that proved it: a fine
/// grid cut short by the time limit no longer hides a coarser grid's better bound (three blocks,
/// 8 x 8 cut at 60 s gave 3.548; the 4 x 4 grid proves 3.333 in well under a second of LP).
pub fn upper_bound(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
) -> Result<UpperBound> {
    let started = Instant::now();
    let mut best: Option<UpperBound> = None;
    progress::within(Some(settings.time_limit), || {
        // The requested grid is checked (size, crawler) before any coarse LP spends the time.
        prepare(crawler, problem, settings)?;
        for (resolution, box_resolution) in refinement_ladder(settings) {
            if best.is_some() && progress::out_of_time()? {
                break;
            }
            let level = BoundSettings {
                resolution,
                box_resolution,
                ..*settings
            };
            let ub = upper_bound_on_grid(crawler, problem, &level)?;
            if best.as_ref().is_none_or(|b| ub.value <= b.value) {
                best = Some(ub);
            }
        }
        Ok::<(), crate::Error>(())
    })?;
    let mut best = best.expect("the ladder has at least settings' own grid");
    best.seconds = started.elapsed().as_secs_f64();
    Ok(best)
}

/// The bound from the storage function the LP finds on the one grid of `settings`.
pub fn upper_bound_on_grid(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
) -> Result<UpperBound> {
    let started = Instant::now();
    let pre = prepare(crawler, problem, settings)?;
    let rows = |sink: &mut RowSink| {
        pre.grid
            .for_each_row(crawler, &pre.motions, pre.tol, |nodes, coefs, y| {
                sink(nodes, coefs, y)
            });
    };
    let lp = progress::within(Some(settings.time_limit), || {
        solve_storage_lp(pre.grid.nodes(), &rows)
    })?;
    Ok(UpperBound {
        method: METHOD.to_string(),
        resolution: settings.resolution,
        box_resolution: settings.box_resolution,
        cost_tangents: cost_tangents(problem, settings),
        value: lp.rate * problem.period,
        status: lp.status,
        aligned: pre.aligned,
        rows: lp.rows,
        columns: lp.columns,
        seconds: started.elapsed().as_secs_f64(),
    })
}
