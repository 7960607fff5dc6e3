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
//! there: `faces`). Then `J = y(T) - y(0) <= rho T`. Proof: `x`, `l` are Lipschitz; at almost
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
//! a superset of those that meet (a test on the simplex's vertices, `grid`), which only adds
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

/// The default grid `(resolution, box_resolution)` up to three blocks.
pub const DEFAULT_GRID: (usize, usize) = (8, 8);

/// The default grid on four blocks. Their 8 x 8 grid has about 1e8 simplices (beyond
/// [`MAX_SIMPLICES`]), and their 2 x 2 grid is an LP of 2.1e6 rows that ten minutes do not
/// finish (8.93 cut at 600 s); 2 x 1 proves 6.667 in 15 s (docs/guide/bound.md, "How tight it
/// is": four blocks, mu = 1 / 1.5, k = a = 1, T = 10).
pub const DEFAULT_GRID_FOUR_BLOCKS: (usize, usize) = (2, 1);

/// Largest number of rows of a bound's LP (about 600 bytes each as HiGHS holds them): a
/// four-block grid within [`MAX_SIMPLICES`] can still need 1e7 rows and more, over 10 GB.
pub const MAX_ROWS: usize = 4_000_000;

/// Settings of [`upper_bound`].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BoundSettings {
    /// Grid steps across the widest link-force range of C (the `x` step `h` is that range over
    /// this; C is tiled exactly when every friction threshold is a multiple of `h`). Unset (the
    /// default): see [`BoundSettings::grid`].
    pub resolution: Option<usize>,
    /// Grid steps across each actuator-length range `[0, a_l T / (2 k_l)]`. Unset (the
    /// default): see [`BoundSettings::grid`].
    pub box_resolution: Option<usize>,
    /// Time limit of the LP in seconds (a solve cut short still gives a valid, weaker bound).
    /// Unset (the default): [`DEFAULT_BOUND_TIME_LIMIT`].
    pub time_limit: Option<f64>,
    /// With a quadratic cost: tangents per link of its piecewise-linear under-estimator (taken
    /// at the centres of equal cells of `[-a_l, a_l]`; it is below the cost by at most
    /// `c a_l^2 / (2 m^2)`). More tangents tighten the bound and multiply the control vertices,
    /// hence the rows, by up to about `m^n`. Ignored without a cost. Unset (the default):
    /// [`DEFAULT_COST_TANGENTS`], on four blocks [`DEFAULT_COST_TANGENTS_FOUR_BLOCKS`].
    pub cost_tangents: Option<usize>,
}

/// The bound's time limit when [`BoundSettings::time_limit`] is unset: one minute.
pub const DEFAULT_BOUND_TIME_LIMIT: f64 = 60.0;

/// The cost's tangents per link when [`BoundSettings::cost_tangents`] is unset, up to three
/// blocks.
pub const DEFAULT_COST_TANGENTS: usize = 4;

/// The cost's tangents per link when unset, on four blocks: with 4, HiGHS's interior point
/// method ends the 2 x 1 grid's LP in a solve error after about 55 s (uniform crawler, mu = 1 /
/// 1.6, k = a = 1, T = 10, c = 0.1); with 2 it proves 6.042 in 34 s (1: 6.667 in 17 s).
pub const DEFAULT_COST_TANGENTS_FOUR_BLOCKS: usize = 2;

/// [`BoundSettings`] with every default applied for one crawler: the grid and LP that
/// [`upper_bound`] runs.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Resolved {
    resolution: usize,
    box_resolution: usize,
    time_limit: f64,
    cost_tangents: usize,
    /// The setting a grid too large is refused by.
    field: &'static str,
}

impl BoundSettings {
    /// The grid `(resolution, box_resolution)` for `crawler`: each setting given is kept, each
    /// unset one is its entry of [`DEFAULT_GRID`] (up to three blocks) or
    /// [`DEFAULT_GRID_FOUR_BLOCKS`].
    pub fn grid(&self, crawler: &Crawler) -> Result<(usize, usize)> {
        check_settings(self)?;
        check_crawler(crawler)?;
        let d = if crawler.links() <= 2 {
            DEFAULT_GRID
        } else {
            DEFAULT_GRID_FOUR_BLOCKS
        };
        Ok((
            self.resolution.unwrap_or(d.0),
            self.box_resolution.unwrap_or(d.1),
        ))
    }

    /// Every default applied: the grid of [`BoundSettings::grid`], the time limit and tangents.
    fn resolve(&self, crawler: &Crawler) -> Result<Resolved> {
        let (resolution, box_resolution) = self.grid(crawler)?;
        // A grid too large is refused naming a resolution given (the box's when only it is).
        let field = if self.resolution.is_none() && self.box_resolution.is_some() {
            "bound.box_resolution"
        } else {
            "bound.resolution"
        };
        Ok(Resolved {
            resolution,
            box_resolution,
            time_limit: self.time_limit.unwrap_or(DEFAULT_BOUND_TIME_LIMIT),
            cost_tangents: self.cost_tangents.unwrap_or(if crawler.links() <= 2 {
                DEFAULT_COST_TANGENTS
            } else {
                DEFAULT_COST_TANGENTS_FOUR_BLOCKS
            }),
            field,
        })
    }
}

impl Resolved {
    /// The refusal of a grid whose LP has `rows` rows, beyond [`MAX_ROWS`].
    fn too_many_rows(&self, rows: usize) -> Error {
        Error::invalid(
            self.field,
            format!("{} x {}", self.resolution, self.box_resolution),
            format!("the bound's LP has {rows} rows (at most {MAX_ROWS}); take a coarser grid"),
        )
    }
}

/// Checks the settings given (unset ones take their defaults, which are valid).
fn check_settings(s: &BoundSettings) -> Result<()> {
    let counts = [
        ("bound.resolution", s.resolution),
        ("bound.box_resolution", s.box_resolution),
        ("bound.cost_tangents", s.cost_tangents),
    ];
    for (field, value) in counts {
        if let Some(v) = value.filter(|&v| v == 0 || v > 1000) {
            return Err(Error::invalid(field, v, "must be between 1 and 1000"));
        }
    }
    if let Some(t) = s.time_limit.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(Error::invalid(
            "bound.time_limit",
            t,
            "must be positive and finite",
        ));
    }
    Ok(())
}

/// Checks that the bound applies to `crawler`: a unique process, at most
/// [`MAX_BOUND_LINKS`] links.
fn check_crawler(crawler: &Crawler) -> Result<()> {
    crawler.require_unique()?;
    if crawler.links() > MAX_BOUND_LINKS {
        return Err(Error::invalid(
            "crawler.blocks",
            crawler.blocks(),
            format!(
                "the upper bound's grid has 2(N-1) dimensions: at most {} blocks",
                MAX_BOUND_LINKS + 1
            ),
        ));
    }
    Ok(())
}

/// The Kuhn grid of `C x box` at `resolution` steps across C's widest link-force range and
/// `box_resolution` across each actuator range, and whether it is aligned with every friction
/// threshold (the crawler checked by [`BoundSettings::grid`]).
fn grid_of(
    crawler: &Crawler,
    problem: &GaitProblem,
    resolution: usize,
    box_resolution: usize,
) -> (grid::Grid, bool) {
    let a = &problem.rate_bound;
    let k = crawler.stiffness();
    let lmax: Vec<f64> = (0..crawler.links())
        .map(|l| a[l] * problem.period / (2.0 * k[l]))
        .collect();
    let ranges = crawler.link_force_ranges();
    let width = ranges.iter().fold(0.0_f64, |w, r| w.max(r[1] - r[0]));
    let h = width / resolution as f64;
    let tol = 1e-9 * crawler.force_scale();
    let aligned = crawler
        .mu_forward()
        .iter()
        .chain(crawler.mu_backward())
        .all(|m| ((m / h).round() * h - m).abs() <= tol);
    let grid = grid::Grid::new(crawler, h, &lmax, box_resolution, aligned);
    (grid, aligned)
}

/// [`grid_of`] at `level`, refused naming the resolution given when it has more than
/// [`MAX_SIMPLICES`] simplices.
fn checked_grid(
    crawler: &Crawler,
    problem: &GaitProblem,
    level: &Resolved,
) -> Result<(grid::Grid, bool)> {
    let (grid, aligned) = grid_of(crawler, problem, level.resolution, level.box_resolution);
    let fact: usize = (1..=2 * crawler.links()).product();
    let simplices = grid.cells().saturating_mul(fact);
    if simplices > MAX_SIMPLICES {
        return Err(Error::invalid(
            level.field,
            format!("{} x {}", level.resolution, level.box_resolution),
            format!("the grid has {simplices} simplices (at most {MAX_SIMPLICES})"),
        ));
    }
    Ok((grid, aligned))
}

/// Checks before any work that [`upper_bound`] can run on `crawler` and `problem` under
/// `settings`: the settings and the crawler ([`BoundSettings::grid`]) and the size of its
/// finest grid (at most [`MAX_SIMPLICES`] simplices), in the units the bound is proven in. The
/// LP's rows ([`MAX_ROWS`]) are counted as the LP is built. The optimisers call it before they
/// run, so that a bound that cannot be proven is not found after the search.
pub fn check_upper_bound(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
) -> Result<()> {
    settings.grid(crawler)?;
    let units = crate::optimal::units::Units::of(crawler, problem);
    let (c, p) = (units.crawler(crawler)?, units.problem(problem));
    checked_grid(&c, &p, &settings.resolve(&c)?).map(|_| ())
}

/// The grid and the face motions of one bound computation.
struct Prepared {
    grid: grid::Grid,
    motions: Vec<(Vec<usize>, faces::FaceMotion)>,
    tol: f64,
    aligned: bool,
}

/// Builds the grid of `C x box` of `level` (checked by [`BoundSettings::grid`]) and the face
/// motions.
fn prepare(crawler: &Crawler, problem: &GaitProblem, level: &Resolved) -> Result<Prepared> {
    let (grid, aligned) = checked_grid(crawler, problem, level)?;
    let cost = faces::CostModel {
        weight: match problem.cost {
            Cost::None => 0.0,
            Cost::Quadratic { weight } => weight,
        },
        tangents: level.cost_tangents,
    };
    let tol = 1e-9 * crawler.force_scale();
    let motions: Vec<_> = faces::faces(crawler, tol)
        .into_iter()
        .map(|f| {
            let m = faces::face_motion(crawler, &problem.rate_bound, &f, cost);
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
fn solve_storage_lp(
    columns: usize,
    rows: &RowSource,
    refuse: &dyn Fn(usize) -> Error,
) -> Result<LpOutcome> {
    // The LP  min rho  s.t.  <g_S, d> + rho >= y  (one row per (S, F, u)) has far more rows
    // than node values, and rho is in every row: HiGHS's interior point method chokes on that
    // dense column (measured: 465 s for 6.4e5 rows), so its dual is solved,
    //   max sum_r y'_r m_r  s.t.  sum_r A_{r,p} m_r = 0 (every node p but one),
    //                             sum_r m_r <= 1,  m >= 0,
    // (an occupation measure on (simplex, face, control) that is invariant when tested against
    // the piecewise-linear functions of the grid), and V is read from its node duals.
    let used = used_columns(columns, rows, refuse)?;
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
    // of HiGHS's duals is a convention; both signs give valid bounds, and so does V = 0 (an
    // LP cut short early can return a V worse than it): the smallest is reported.
    let mut rate = [f64::NEG_INFINITY; 3];
    rows(&mut |cols, coefs, y| {
        let g: f64 = cols.iter().zip(coefs).map(|(&p, c)| c * dual[p]).sum();
        rate[0] = rate[0].max(y - g);
        rate[1] = rate[1].max(y + g);
        rate[2] = rate[2].max(y);
    });
    let rate = rate[0].min(rate[1]).min(rate[2]);
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

/// Which of `columns` storage values some row refers to, in one pass over the rows that also
/// counts them: beyond [`MAX_ROWS`] the LP is refused (`refuse`) before it is built.
fn used_columns(
    columns: usize,
    rows: &RowSource,
    refuse: &dyn Fn(usize) -> Error,
) -> Result<Vec<bool>> {
    let mut used = vec![false; columns];
    let mut total = 0usize;
    rows(&mut |cols, _, _| {
        total += 1;
        if total <= MAX_ROWS {
            cols.iter().for_each(|&p| used[p] = true)
        }
    });
    if total > MAX_ROWS {
        return Err(refuse(total));
    }
    Ok(used)
}

/// The tangents of the cost used (0 without a cost), as recorded in results.
fn cost_tangents(problem: &GaitProblem, level: &Resolved) -> usize {
    match problem.cost {
        Cost::None => 0,
        Cost::Quadratic { .. } => level.cost_tangents,
    }
}

/// The grids [`upper_bound`] solves, coarse to fine, for the finest grid `(resolution,
/// box_resolution)`: both halved while both stay at least 2 (and stay whole), then the grid
/// itself. Halving keeps the grids nested (a coarse grid's piecewise-linear functions are
/// piecewise linear on the finer one), so a finished finer LP is never worse.
pub fn refinement_ladder(resolution: usize, box_resolution: usize) -> Vec<(usize, usize)> {
    let mut ladder = vec![(resolution, box_resolution)];
    let (mut r, mut b) = (resolution, box_resolution);
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
/// [`refinement_ladder`] up to the grid of [`BoundSettings::grid`], coarse to fine, while the
/// time limit lasts. Every grid's bound is valid, so the smallest is returned, with the grid and
/// LP status that proved it: a fine grid cut short by the time limit no longer hides a coarser
/// grid's better bound (three blocks, 8 x 8 cut at 60 s gave 3.548; the 4 x 4 grid proves 3.333
/// in well under a second of LP). Solved in the optimisers' internal units, its value
/// converted back (exact twins prove one bound).
pub fn upper_bound(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
) -> Result<UpperBound> {
    in_units(crawler, problem, |c, p| upper_bound_in(c, p, settings))
}

/// `bound` of the crawler and problem in the optimisers' internal units (forces of the friction
/// thresholds' size, the period 1, the length unit 1: `optimal::units`), its value converted
/// back (`J` is a length). The LP in the user's units lost its tolerances at extreme scales:
/// one link with thresholds `1e6`, period `1e-5` and speed `1e12` ended "status unknown", and
/// at speed `1e-12` the bound was `5.0` where the problem in units of one proves `3.5`.
fn in_units(
    crawler: &Crawler,
    problem: &GaitProblem,
    bound: impl FnOnce(&Crawler, &GaitProblem) -> Result<UpperBound>,
) -> Result<UpperBound> {
    let units = crate::optimal::units::Units::of(crawler, problem);
    let mut ub = bound(&units.crawler(crawler)?, &units.problem(problem))?;
    ub.value *= units.length;
    Ok(ub)
}

/// [`upper_bound`] in the units given.
fn upper_bound_in(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
) -> Result<UpperBound> {
    let started = Instant::now();
    let finest = settings.resolve(crawler)?;
    let mut best: Option<UpperBound> = None;
    progress::within(Some(finest.time_limit), || {
        // The finest grid is checked (size, crawler) before any coarse LP spends the time.
        prepare(crawler, problem, &finest)?;
        for (resolution, box_resolution) in
            refinement_ladder(finest.resolution, finest.box_resolution)
        {
            if best.is_some() && progress::out_of_time()? {
                break;
            }
            let level = Resolved {
                resolution,
                box_resolution,
                ..finest
            };
            let ub = bound_on(crawler, problem, &level)?;
            if best.as_ref().is_none_or(|b| ub.value <= b.value) {
                best = Some(ub);
            }
        }
        Ok::<(), crate::Error>(())
    })?;
    let mut best = best.expect("the ladder has at least the finest grid");
    best.seconds = started.elapsed().as_secs_f64();
    Ok(best)
}

/// The bound from the storage function the LP finds on the one grid of
/// [`BoundSettings::grid`].
pub fn upper_bound_on_grid(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
) -> Result<UpperBound> {
    in_units(crawler, problem, |c, p| {
        bound_on(c, p, &settings.resolve(c)?)
    })
}

/// The bound on the one grid of `level`.
fn bound_on(crawler: &Crawler, problem: &GaitProblem, level: &Resolved) -> Result<UpperBound> {
    let started = Instant::now();
    let pre = prepare(crawler, problem, level)?;
    let rows = |sink: &mut RowSink| {
        pre.grid
            .for_each_row(crawler, &pre.motions, pre.tol, |nodes, coefs, y| {
                sink(nodes, coefs, y)
            });
    };
    let lp = progress::within(Some(level.time_limit), || {
        solve_storage_lp(pre.grid.nodes(), &rows, &|n| level.too_many_rows(n))
    })?;
    Ok(UpperBound {
        method: METHOD.to_string(),
        resolution: level.resolution,
        box_resolution: level.box_resolution,
        cost_tangents: cost_tangents(problem, level),
        value: lp.rate * problem.period,
        status: lp.status,
        aligned: pre.aligned,
        rows: lp.rows,
        columns: lp.columns,
        seconds: started.elapsed().as_secs_f64(),
    })
}
