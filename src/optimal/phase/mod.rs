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
//! 10.5, but the `K = 5` proof took 1.1 s instead of 0.75 s). On long chains (issue 27; the
//! benchmarks page, "The phase MILP on long chains"), from 10 blocks: the
//! friction balance's speed rows (at most `m+` blocks hold their forward faces at once, a run
//! of them moves like a lever about neighbours that do not slip forward, so a block slides at
//! most `V_+ tau` and all together at most `C_+ tau`; uniform chain, `mu^- = 1.3`: `V_+ = 5`,
//! `C_+ = 15` at `N = 10` where `V = 9`), valid for every gait: they lowered the LP bound
//! from the work bound 28 to 15 (`N = 20`: 56.4 to 33) but closed no new `K` in 60 s, and the
//! one proof that closes, `N = 20`, `K = 2` from the triangle wave, took 9826 nodes and 439,636
//! LP iterations instead of 5871 and 326,775; a mirror row for chains symmetric under
//! reversing the blocks (the rear half slides at least as far as the front half; the mirror
//! image of a gait moves the chain as far, checked by the exact simulator) took 9353 nodes and
//! 496,126 iterations with the speed rows, and alone had not closed after 15,616 nodes.
//!
//! The quadratic cost is the perspective `(c/2) |U_j|^2 / tau_j` (likewise for `W_j`), handled
//! by outer approximation ([`TangentRates`](crate::optimal::milp::TangentRates)): tangent cuts under-estimate it, so the MILP's
//! bound stays valid; cuts at the rates of each solution are added and the MILP re-solved (from
//! the previous gait) until the true objective of the incumbent meets the bound; the answer is
//! then polished on its slip modes ([`polish`]: a convex problem, exact to rounding; (P)'s phase
//! polish on the crawler's instance) and kept
//! when the replay agrees and `J` is no worse. A
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

//!
//! The module is split at its seams: [`layout`] writes the MILP, [`decode`] reads a gait off
//! its columns (and writes a known gait back as a start), [`solve`] solves one `K`, [`growth`]
//! raises `K`, [`sequence`] searches over sequences of slip modes.

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::{Certificate, GaitProblem, MilpStatus};
use serde::Serialize;

mod decode;
mod growth;
mod layout;
mod polish;
mod sequence;
mod solve;
#[cfg(test)]
mod tests;

pub use decode::{phase_gait_of, slip_sequence};
pub use growth::{
    grow_phases, GrowOptions, GrowthStop, PhaseGrowth, PhaseStep, DEFAULT_MAX_PHASES,
    DEFAULT_PATIENCE,
};
pub use sequence::{search_sequences, slip_mode_is_valid, SequenceSearch};
pub use solve::{solve_phase_from, solve_phase_global, solve_phase_with};

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

    /// Its number of slip phases, runs of one slip mode merged cyclically (what `K` counts).
    pub fn slip_phases(&self) -> usize {
        slip_sequence(&self.modes).len()
    }

    /// The claim made true for the gait it is on: a gait of more slip phases than its
    /// certificate's `K` (a known start the `K`-phase MILP could not hold, kept because no gait
    /// of at most `K` slip phases beats it) is [`MilpStatus::DominatesKPhases`], not optimal
    /// among a class it is not in.
    pub(crate) fn settle_claim(&mut self) {
        if self.certificate.status == MilpStatus::OptimalAmongKPhases
            && self.slip_phases() > self.phases
        {
            self.certificate.status = MilpStatus::DominatesKPhases;
        }
    }
}

/// Optional rows of the phase MILP, each valid for every periodic gait (so the optimum is the
/// same with or without them; only the solver's effort changes). The defaults are what the
/// measurements in the benchmarks page ("The phase MILP on long chains") chose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Formulation {
    /// The dissipation row: over a period the friction dissipates exactly the actuators' work,
    /// `sum_{j,b} (mu_b^+ P_{j,b} + mu_b^- Q_{j,b}) = sum_l int x_l dL_l
    /// <= T sum_l a_l w_l / (2 k_l)`, `w_l` the width of link `l`'s force range over C (the
    /// argument of the work bound, `certify::bound::work_bound`). `None` (the default): on from
    /// [`DISSIPATION_ROW_BLOCKS`] blocks, where it capped the bound at the limit and, with the
    /// triangle wave as the start, closed `K = 2` at `N = 20`; off below, where it slowed the
    /// proofs (three blocks at `K = 6`: 4.3 s against 2.4 s).
    pub dissipation_row: Option<bool>,
}

/// From this many blocks the dissipation row is on by default ([`Formulation`]).
pub const DISSIPATION_ROW_BLOCKS: usize = 10;

impl Formulation {
    /// Whether the dissipation row is written for `crawler`.
    pub fn dissipation_row_for(&self, crawler: &Crawler) -> bool {
        self.dissipation_row
            .unwrap_or(crawler.blocks() >= DISSIPATION_ROW_BLOCKS)
    }
}

/// How one `K` of the phase MILP is seeded and written ([`solve_phase_with`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PhaseOptions {
    /// A known gait, e.g. the best structured gait turned into phases by [`phase_gait_of`], or
    /// an optimum of a smaller `K`. When it has at most `K` slip phases it is the MILP's first
    /// incumbent; when it has more, its `J` is the [`cutoff`](Self::cutoff) unless one is
    /// given. If no gait of at most `K` slip phases beats the cutoff, the answer is this gait
    /// with bound `J` of this gait: no gait of at most `K` slip phases does better. Its status
    /// is `dominates_k_phases` when it has more than `K` slip phases
    /// ([`MilpStatus::DominatesKPhases`]), `optimal_among_k_phases` otherwise; a MILP answer as
    /// good as it up to `1e-9` of the length scale is preferred (its claim is the stronger).
    pub start: Option<PhaseSolution>,
    /// Search only the gaits with `J >= cutoff` (less `1e-9` of the length scale), a row on the
    /// MILP's objective. Without a start and with no such gait, the answer is an
    /// [`Error::Infeasible`] that says so (a proof that `J_K < cutoff`). Default: none.
    pub cutoff: Option<f64>,
    /// Optional valid rows.
    pub formulation: Formulation,
}

/// The work bound on `J` over every periodic gait, `T sum_l w_l a_l / (2 k_l) / sum_b mu_b^+`
/// (`w_l` the width of link `l`'s force range over C): friction dissipates the actuators' work
/// (the argument is the module doc of `certify::bound::work`, which reports it). The bound a
/// known start keeps when no MILP has certified anything about it.
pub(crate) fn work_limit(crawler: &Crawler, problem: &GaitProblem) -> f64 {
    problem.period * link_work(crawler, problem) / crawler.mu_forward().iter().sum::<f64>()
}

/// `sum_l w_l a_l / (2 k_l)`: the actuators' work per unit time at most (times `T`, a bound on
/// the friction's dissipation per period).
fn link_work(crawler: &Crawler, problem: &GaitProblem) -> f64 {
    crawler
        .link_force_ranges()
        .iter()
        .zip(&problem.rate_bound)
        .zip(crawler.stiffness())
        .map(|((r, a), k)| (r[1] - r[0]) * a / (2.0 * k))
        .sum()
}

/// A known start with the certificate of what is known without a MILP: `time_limit`, `K`
/// = `phases`, the work bound (valid for every gait) as its bound.
fn start_unproven(
    crawler: &Crawler,
    problem: &GaitProblem,
    s: &PhaseSolution,
    phases: usize,
) -> PhaseSolution {
    let j = s.objective();
    let bound = work_limit(crawler, problem).max(j);
    let mut s = s.clone();
    s.phases = phases;
    s.certificate = Certificate {
        status: MilpStatus::TimeLimit,
        milp_objective: s.verified_displacement,
        bound,
        gap: Certificate::gap_of(bound, j, problem.j_floor(crawler)),
    };
    s
}

/// Refuses what no phase problem accepts: a crawler failing the uniqueness condition,
/// `phases` outside `1..=MAX_PHASES`, a total-variation bound.
fn check_phase_args(crawler: &Crawler, problem: &GaitProblem, phases: usize) -> Result<()> {
    crawler.require_unique()?;
    problem.check_scales(crawler)?;
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
