//! P_m's branch LP as the local method holds it ([`super::local`]): one HiGHS model of
//! [`Form::Branches`] per start, whose branches are column bounds, so that each pivot re-sets
//! only the bounds that change and re-solves from the last basis. The best start's model is
//! kept for its finish, which goes on from the basis the start ended on. A finish on a model
//! built afresh from the best's controls solved its first LP cold: on five blocks at `m = 10`
//! that LP took 0.26 s of the finish's 0.42 s. A start on the model of the start before it,
//! its branches re-set, is no cheaper than on its own: the same five blocks' eight starts
//! took 0.23 to 0.36 s each for their first LP that way, 0.26 to 0.30 s built afresh.

use super::discrete::{
    build, holds_a_pair, opposite_faces, pair_bounds, pair_multiplier, replay_in, Form, Layout,
    PmPath,
};
use super::units::Units;
use crate::error::{Error, Result};
use crate::model::general::{GeneralProblem, Reward};
use crate::optimal::active_set::{self, LocalStop, Outcome};
use crate::optimal::solver::{Basis, Highs, SolveStatus};
use highs::Sense;
use serde::{Deserialize, Serialize};

/// A local solution of the general P_m, re-verified.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralLocal {
    /// `m`.
    pub m: u32,
    /// `J` of the controls, as the simulator replays them (written once, as the result's
    /// `objective`; filled from it on reading).
    #[serde(skip_serializing)]
    pub objective: f64,
    /// `J` of the last LP.
    pub lp_objective: f64,
    /// `J` of the start (its simulated process on this grid).
    pub start_objective: f64,
    /// LPs solved.
    pub lp_solves: usize,
    /// Branches switched in all.
    pub switches: usize,
    /// Why the method stopped.
    pub stop: LocalStop,
    /// The process on the grid ([`PmPath`]).
    #[serde(flatten)]
    pub path: PmPath,
}

/// Which switches the local method tests before it stops (module docs of [`super::local`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pivoting {
    /// The switches that pay by their reduced costs, then, where none does, each degenerate
    /// pair's neighbouring LP: `stationary` means that no single switch gains, as it does
    /// under `Finish`; but degenerate switches by the reduced costs can cycle (`stalled`).
    Neighbours,
    /// The switches that pay by their reduced costs only: the method stops where none pays by
    /// the reduced costs of the last basis (a first-order test; a degenerate LP has other
    /// bases), which costs no LP beyond the pivots. A screen for many starts, whose best is
    /// then finished under [`Pivoting::Finish`] (a crawler's shifted starts,
    /// `crate::optimal::solve_discrete_local_shifted`): a fine grid has many degenerate pairs,
    /// each neighbouring LP that can gain a solve (module docs of
    /// [`super::local`]).
    ReducedCosts,
    /// As `Neighbours`, except that after an LP that gained nothing the next round tests the
    /// neighbouring LPs alone (taking a switch only where its LP gains), so that degenerate
    /// switches by the reduced costs cannot cycle: the method ends `stationary` (or at a
    /// limit), never `stalled`. The default, for one start and for the finish of a screen's
    /// best (from the basis the screen ended on): on three blocks at `m = 3` and `m = 9` (one
    /// start, its branches read off its process) `Neighbours` ended `stalled`.
    #[default]
    Finish,
}

/// The branch LP of P_m on a problem, in units of order one (module docs of
/// [`super::local`]), with the branches it holds now.
pub(super) struct BranchLp {
    /// The problem in the LP's units, and those units.
    q: GeneralProblem,
    /// (See `q`.)
    units: Units,
    /// `m`.
    m: u32,
    /// The LP's columns.
    lay: Layout,
    /// The face weights of `q`.
    w: Vec<f64>,
    /// The model, at its last basis.
    model: Highs,
    /// The branch of each step and face: on face (`true`) or off it.
    active: Vec<Vec<bool>>,
    /// P_m named in errors.
    what: String,
}

/// A branch LP put away ([`BranchLp::keepsake`]): its branches and its basis.
pub(super) struct Keepsake {
    active: Vec<Vec<bool>>,
    basis: Option<Basis>,
}

impl BranchLp {
    /// The branch LP of `p` on `2^m` steps with branches `active`.
    pub(super) fn new(p: &GeneralProblem, m: u32, active: Vec<Vec<bool>>) -> Result<Self> {
        let what = format!("P_{m} of the general problem (local)");
        check_pairs(p, &active, &what)?;
        let units = Units::of(p);
        let q = units.problem(p);
        let (pb, lay) = build(&q, m, Form::Branches(&active), &[]);
        let mut model = Highs::new(pb, Sense::Maximise, &what)?;
        model.option("primal_feasibility_tolerance", 1e-10)?;
        model.option("dual_feasibility_tolerance", 1e-10)?;
        let w = q.face_weights();
        Ok(BranchLp {
            q,
            units,
            m,
            lay,
            w,
            model,
            active,
            what,
        })
    }

    /// What it takes to rebuild this LP where it stands ([`BranchLp::resume`]): its branches
    /// and its basis. Kept instead of the LP itself, whose solver holds far more (a search over
    /// several starts keeps its best for a finishing pass while the next start is solved).
    pub(super) fn keepsake(mut self) -> Keepsake {
        Keepsake {
            basis: self.model.basis(),
            active: self.active,
        }
    }

    /// The LP of `p` on `2^m` steps rebuilt from `kept`, at the basis it ended on (a basis
    /// HiGHS does not take only costs its next solve the iterations back to it).
    pub(super) fn resume(p: &GeneralProblem, m: u32, kept: Keepsake) -> Result<Self> {
        let mut lp = BranchLp::new(p, m, kept.active)?;
        if let Some(basis) = &kept.basis {
            lp.model.set_basis(basis);
        }
        Ok(lp)
    }

    /// The active-set loop from the branches held now under `pivoting` (module docs of
    /// [`super::local`]), within the job's deadline; returns its outcome and the neighbouring
    /// LPs it solved beside the loop's own.
    pub(super) fn run(&mut self, pivoting: Pivoting) -> Result<(Outcome, usize)> {
        let BranchLp {
            q,
            units,
            m,
            lay,
            w,
            model,
            active,
            what,
        } = self;
        let (q, lay, w, what) = (&*q, &*lay, &w[..], &what[..]);
        let mm = 1usize << *m;
        let scale = q.c.scale();
        let tol_x = 1e-9 * scale;
        let w_max = match &q.reward {
            Reward::FaceWeights(w) | Reward::ReactionWeights(w) => {
                w.iter().fold(0.0_f64, |s, v| s.max(v.abs()))
            }
        };
        let tol_red = 1e-9 * w_max.max(1e-300);
        let tol_j = 1e-9 * (w_max * scale).max(1e-300);
        let sigma = q.c.faces();
        // Switches at degenerate pairs (module docs of `super::local`): the reduced cost of a
        // column is the rate at which J changes as it rises from its bound; where none pays
        // (the reduced costs of a degenerate LP are those of one of its bases), each
        // degenerate pair's neighbouring LP is solved and the first flip that gains is taken.
        let mut trials = 0;
        let flip = |model: &mut Highs, active: &mut [Vec<bool>], i: usize, j: usize| {
            active[i][j] = !active[i][j];
            set_branch(model, (q, lay, w), active, (i, j), what)
        };
        // The objective of the previous round, for `Pivoting::Finish`.
        let mut last_j: Option<f64> = None;
        let pivot = |model: &mut Highs, cols: &[f64], red: &[f64], j_now: f64| -> Result<usize> {
            let neighbours_only = pivoting == Pivoting::Finish
                && last_j.is_some_and(|last: f64| j_now <= last + tol_j);
            last_j = Some(j_now);
            let mut changed = 0;
            let mut degenerate = Vec::new();
            for i in 0..mm {
                for j in 0..sigma {
                    let s = lay.s[i][j];
                    // A face whose opposite face is held stays off (no point is on both).
                    if lay.partner_of(j).is_some_and(|k| active[i][k]) {
                        continue;
                    }
                    let red_mu = red[lay.mu[i][j].index()];
                    // The rate of J as the slack rises from 0: its column's reduced cost,
                    // signed; as the multiplier does: its column's, or for a pair's signed
                    // column (cost 0 while both are off) with the face's weight, signed.
                    let (zero, rate) = if active[i][j] {
                        (
                            lay.multiplier(i, j, cols) <= tol_x,
                            s.sign * red[s.col.index()],
                        )
                    } else {
                        let rate = match lay.partner_of(j) {
                            None => red_mu,
                            Some(k) if j < k => red_mu + w[j],
                            Some(_) => w[j] - red_mu,
                        };
                        (s.value(cols) <= tol_x, rate)
                    };
                    if !zero {
                        continue;
                    }
                    if rate > tol_red && !neighbours_only {
                        flip(model, active, i, j)?;
                        changed += 1;
                    } else {
                        // Only these neighbours can gain (`super::local`): a switch that does not
                        // pay by its rate keeps the basis optimal, unless it changes the cost of
                        // a basic column, a pair's signed column (a basic column's reduced cost
                        // is 0).
                        let can_gain = rate > tol_red
                            || lay.partner_of(j).is_some() && red_mu.abs() <= tol_red;
                        degenerate.push((i, j, can_gain));
                    }
                }
            }
            if changed > 0 || pivoting == Pivoting::ReducedCosts {
                return Ok(changed);
            }
            for (i, j, can_gain) in degenerate {
                if !can_gain && !every_neighbour() {
                    continue;
                }
                flip(model, active, i, j)?;
                trials += 1;
                let a = model.solve()?;
                flip(model, active, i, j)?;
                let gains = matches!(a.status, SolveStatus::Optimal) && a.objective > j_now + tol_j;
                if !can_gain {
                    pruned_trial(gains);
                }
                match a.status {
                    SolveStatus::Optimal if gains => {
                        flip(model, active, i, j)?;
                        return Ok(1);
                    }
                    SolveStatus::TimeLimit { .. } => return Ok(0),
                    _ => {}
                }
            }
            Ok(0)
        };
        let floor = q.j_floor();
        // HiGHS's progress is of the scaled objective: reported times `s_x`.
        let run = crate::progress::with_objective_factor(units.state, || {
            active_set::run(model, 20 * mm * sigma, 3, floor, what, pivot)
        })?;
        Ok((run, trials))
    }

    /// Re-verification (module docs of [`super::local`]): the LP's controls of `run`,
    /// converted back (`x = s_x x'`, `u = s_u u'`, `J = s_x J'`), replayed through the
    /// general simulator on `p` itself (the problem of [`BranchLp::new`]), whose `J` must
    /// agree with the LP's; the replayed process is the one reported, with `trials`
    /// neighbouring LPs counted beside the loop's and the start's `J`.
    pub(super) fn answer(
        &self,
        p: &GeneralProblem,
        (run, trials): (Outcome, usize),
        start_objective: f64,
    ) -> Result<GeneralLocal> {
        let (units, m, what) = (&self.units, self.m, &self.what);
        let scale = p.c.scale();
        let r = replay_in(
            p,
            (units.state, units.control),
            (m, &self.lay, &run.cols),
            what,
        )?;
        let lp_objective = units.state * run.objective;
        if (r.objective - lp_objective).abs() > 1e-6 * (scale + r.objective.abs()) {
            return Err(Error::Numerical(format!(
                "{what}: the controls give J = {} when simulated, not {lp_objective}",
                r.objective
            )));
        }
        Ok(GeneralLocal {
            m,
            objective: r.objective,
            lp_objective,
            start_objective,
            lp_solves: run.lp_solves + trials,
            switches: run.switches,
            stop: run.stop,
            path: r.path,
        })
    }
}

/// Refuses branches that hold two opposite faces at one step (no point is on both).
fn check_pairs(p: &GeneralProblem, active: &[Vec<bool>], what: &str) -> Result<()> {
    if holds_a_pair(&opposite_faces(p), active) {
        return Err(Error::Numerical(format!(
            "{what}: the start's process holds two opposite faces at once"
        )));
    }
    Ok(())
}

/// Sets the bounds of face `j`'s columns at step `i` to its branch in `active` (and, for a
/// pair of opposite faces, their signed multiplier column's bounds and cost), on `q`'s LP of
/// layout `lay` and face weights `w`.
fn set_branch(
    model: &mut Highs,
    (q, lay, w): (&GeneralProblem, &Layout, &[f64]),
    active: &[Vec<bool>],
    (i, j): (usize, usize),
    what: &str,
) -> Result<()> {
    let slack = lay.s[i][j];
    let Some(k) = lay.partner_of(j) else {
        let [bm, bs] = super::discrete::branch_bounds(active[i][j]);
        model.set_bounds(lay.mu[i][j], bm.0, bm.1)?;
        return model.set_bounds(slack.col, bs.0, bs.1);
    };
    // The pair's signed multiplier and value column, bounded by both branches (`a < b`).
    let (a, b) = (j.min(k), j.max(k));
    let (on_a, on_b) = (active[i][a], active[i][b]);
    let (lo, hi) = pair_bounds((q.c.offsets[a], q.c.offsets[b]), on_a, on_b).ok_or_else(|| {
        Error::Numerical(format!(
            "{what}: a switch held two opposite faces, {} and {}",
            a + 1,
            b + 1
        ))
    })?;
    let (cost, nu_lo, nu_hi) = pair_multiplier((w[a], w[b]), on_a, on_b);
    model.set_bounds(lay.mu[i][j], nu_lo, nu_hi)?;
    model.set_cost(lay.mu[i][j], cost)?;
    model.set_bounds(slack.col, lo, hi)
}

#[cfg(test)]
use std::cell::Cell;

#[cfg(test)]
thread_local! {
    /// Tries every degenerate pair's neighbouring LP (the pruning off) while set.
    pub(super) static EVERY_NEIGHBOUR: Cell<bool> = const { Cell::new(false) };
    /// Switches the pruning would skip: how many were tried, and how many of them gained.
    pub(super) static PRUNED_TRIALS: Cell<(usize, usize)> = const { Cell::new((0, 0)) };
}

/// Whether the neighbours' test tries every degenerate pair, the pruning of `super::local`
/// off: only in unit tests, which count the pruned switches that gain ([`pruned_trial`]).
#[cfg(test)]
fn every_neighbour() -> bool {
    EVERY_NEIGHBOUR.with(|e| e.get())
}

#[cfg(not(test))]
fn every_neighbour() -> bool {
    false
}

/// A switch the pruning skips was tried, and whether it gained (never, by the module docs
/// of [`super::local`]; counted in unit tests).
#[cfg(test)]
fn pruned_trial(gained: bool) {
    PRUNED_TRIALS.with(|n| {
        let (tried, gains) = n.get();
        n.set((tried + 1, gains + usize::from(gained)));
    });
}

#[cfg(not(test))]
fn pruned_trial(_: bool) {}
