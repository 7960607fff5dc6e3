//! Raising `K` until the value stops improving, written once for every family of exact phase
//! gaits: the crawler's (theory §7, `K` slip phases, [`crate::optimal::grow_phases`]) and the
//! general problem's (theory §11, `K` phases of constant control where `A = 0`,
//! [`crate::optimal::general::grow_general_phases`]). Each family solves one `K` globally
//! behind [`PhaseFamily`]; the growth (patience, plateaus, the time limit, what the answer
//! claims) is [`grow`].
//!
//! **What the answer claims.** The best verified gait found, with the certificate of the
//! largest `K` solved: `optimal_among_k_phases` when that `K`'s MILP was solved to optimality
//! (no gait of at most `K` phases does better than its bound; `dominates_k_phases` for the
//! crawler when the gait is a start of more slip phases than `K`), `time_limit` with that `K`'s
//! bound and gap when the limit cut it short. Both families' MILPs at `K` contain every gait
//! of fewer phases, so a growth's `J_K` never decreases; a growth stopped by its patience
//! claims only the `K` it reached.

use crate::error::{Error, Result};
use crate::optimal::milp::{Certificate, MilpStatus};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// The relative resolution (times the problem's length scale) above which a verified `J_K`
/// counts as moving the system in [`grow`]: the replay reproduces `J` to about `1e-14` of the
/// length scale, so `1e-9` leaves room for round-off and nothing else. It only decides whether
/// the growth's patience has started counting; the best verified gait is kept whatever its
/// size.
pub const MOVE_RESOLUTION: f64 = 1e-9;

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
    /// `"optimal_among_k_phases"`, `"dominates_k_phases"` (the start kept: no gait of at most
    /// `K` slip phases beats it), `"time_limit"` or `"approximation_limit"`.
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
    /// No gait moves the system forward and staying idle is globally optimal, for every `K`
    /// (a crawler with `v_m <= 0` for every shape rate, model analysis).
    NoForwardMotion,
    /// The time limit ended it.
    TimeLimit,
}

/// How far `K` is raised: from `min_phases` to `max_phases`, ending after `patience`
/// consecutive `K` without a gain (counted once `J_K` moves the system).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GrowthRange {
    /// First `K`.
    pub min_phases: usize,
    /// Last `K` tried.
    pub max_phases: usize,
    /// Consecutive `K` without a gain that end the growth.
    pub patience: usize,
}

impl GrowthRange {
    /// Refuses a range no growth can run: `1 <= min_phases <= max_phases <= most` (the
    /// family's largest `K`), `patience >= 1`; errors name the field.
    pub fn check(&self, most: usize) -> Result<()> {
        if self.min_phases < 1 {
            return Err(Error::invalid("min_phases", 0, "must be at least 1"));
        }
        if self.max_phases < self.min_phases || self.max_phases > most {
            return Err(Error::invalid(
                "max_phases",
                self.max_phases,
                format!("must be in {}..={most}", self.min_phases),
            ));
        }
        if self.patience == 0 {
            return Err(Error::invalid("patience", 0, "must be at least 1"));
        }
        Ok(())
    }
}

/// A family of exact phase gaits, each `K` solved globally by a MILP: what [`grow`] is written
/// against. The crawler's chain formulation (`K` slip phases, transitions free) and the general
/// one (`K` phases of constant control) implement it.
pub trait PhaseFamily {
    /// A verified gait with its certificate.
    type Gait: Clone;
    /// The globally optimal gait of at most `k` phases (or the best found and its gap when the
    /// job's deadline cuts the MILP short). `best`, the best gait so far, is the MILP's
    /// incumbent or cutoff where the family takes one.
    fn solve(&self, k: usize, best: Option<&Self::Gait>) -> Result<Self::Gait>;
    /// `J` of a gait, as re-verified.
    fn objective(g: &Self::Gait) -> f64;
    /// Its certificate and `K`, mutably (a growth re-states the best gait's claim for a larger
    /// `K` that did not beat it).
    fn claim(g: &mut Self::Gait) -> (&mut usize, &mut Certificate);
    /// The problem's length scale (what a `J` that moves is measured against).
    fn length_scale(&self) -> f64;
    /// The problem's floor of `J`, over which gaps are stated ([`Certificate::gap_of`]).
    fn j_floor(&self) -> f64;
    /// The relative gain below which a larger `K` counts as no gain (the values' accuracy:
    /// `1e-7`, or the outer approximation's tolerance with a quadratic cost).
    fn gain_tolerance(&self) -> f64;
    /// Whether no gait of any `K` moves the system forward (then the first `K` is final).
    fn idle(&self) -> bool {
        false
    }
    /// Whether two gaits are the same (a given start returned unbeaten).
    fn same(a: &Self::Gait, b: &Self::Gait) -> bool;
    /// A given start no MILP has certified anything about: its claim at `K = phases` with a
    /// bound valid for every gait.
    fn unproven(&self, g: &Self::Gait, phases: usize) -> Self::Gait;
}

/// The result of [`grow`].
#[derive(Debug, Clone, PartialEq)]
pub struct Growth<G> {
    /// The best gait, certified for the last `K` solved.
    pub best: G,
    /// Every `K` solved.
    pub table: Vec<PhaseStep>,
    /// Why it stopped.
    pub stop: GrowthStop,
}

/// Raises `K` over `range` (module docs), from `start` if given (the best gait before the
/// first `K`: every MILP takes it as its incumbent where it fits, and a `K` whose MILP proves
/// that nothing of at most `K` phases beats it does not count towards the patience), within
/// the job's deadline. `progress` sees each `K` as it is solved.
pub fn grow<F: PhaseFamily>(
    family: &F,
    range: GrowthRange,
    start: Option<F::Gait>,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<Growth<F::Gait>> {
    let mut best = start.clone();
    let mut table = Vec::new();
    let mut without_gain = 0;
    let mut stop = GrowthStop::MaxPhases;
    let idle = family.idle();
    // Whether a verified J_K moves the system: above the replay's resolution, relative to the
    // problem's own length scale (not to 1: lengths may be 1e-6 or 1e6).
    let scale = family.length_scale();
    let moves = |j: f64| j > MOVE_RESOLUTION * scale;
    for k in range.min_phases..=range.max_phases {
        if crate::progress::out_of_time()? {
            stop = GrowthStop::TimeLimit;
            break;
        }
        let t0 = Instant::now();
        let mut s = match family.solve(k, best.as_ref()) {
            Ok(s) => s,
            Err(Error::TimeLimit(_)) if best.is_some() => {
                stop = GrowthStop::TimeLimit;
                break;
            }
            Err(e) => return Err(e),
        };
        let j = F::objective(&s);
        let (_, cert) = F::claim(&mut s);
        let step = PhaseStep {
            phases: k,
            objective: j,
            bound: cert.bound,
            gap: cert.gap,
            status: cert.status,
            seconds: t0.elapsed().as_secs_f64(),
        };
        let timed_out = cert.status == MilpStatus::TimeLimit;
        progress(&step);
        table.push(step);
        let gain = best.as_ref().map_or(f64::INFINITY, |b| {
            let jb = F::objective(b);
            j - jb - family.gain_tolerance() * jb.abs().max(scale)
        });
        if timed_out {
            // The best gait stays if it is better, but the claim is now this K's: a time limit
            // with this K's bound (not "optimal" for the smaller K it was proven for, which
            // read as if the growth had finished).
            keep_or_recertify(family, &mut best, s);
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
        } else if best.as_ref().is_some_and(|b| !moves(F::objective(b))) {
            // Nothing moves yet (at the replay's resolution): K is still too small. A verified
            // gait better than the best so far is never overruled by the gain tolerance, which
            // is relative to the length scale and can exceed a small true optimum (one link
            // with T just above 2w/a: J* = 5e-8 against a tolerance of 3e-7).
            keep_or_recertify(family, &mut best, s);
        } else {
            // The given start returned because nothing of at most K phases beats it: the
            // MILPs have not reached it yet, so this K is no plateau.
            let is_start = start.as_ref().is_some_and(|st| F::same(st, &s));
            if !is_start {
                without_gain += 1;
            }
            // Better within the tolerance only, or the same gait.
            keep_or_recertify(family, &mut best, s);
            if without_gain >= range.patience {
                stop = GrowthStop::NoGain;
                break;
            }
        }
    }
    let mut best = best.ok_or_else(|| {
        // One fixed K is one MILP, not a growth: say which.
        let what = if range.min_phases == range.max_phases {
            format!("the phase MILP (K = {})", range.max_phases)
        } else {
            "phase growth".to_string()
        };
        Error::TimeLimit(format!(
            "{what}: the time limit was reached before any feasible gait was found"
        ))
    })?;
    // The given start, never certified (the limit came before any K): say what is known.
    if F::claim(&mut best).1.bound.is_nan() {
        best = family.unproven(&best, range.min_phases);
    }
    Ok(Growth { best, table, stop })
}

/// The best gait after solving a larger `K`: `s` when it is better (with its own
/// certificate), else the best so far, now certified for `s`'s `K` (its bound, gap and
/// status).
fn keep_or_recertify<F: PhaseFamily>(family: &F, best: &mut Option<F::Gait>, mut s: F::Gait) {
    match best.as_mut() {
        Some(b) if F::objective(&s) <= F::objective(b) => {
            let jb = F::objective(b);
            let (k, cert) = F::claim(&mut s);
            let (bk, bcert) = F::claim(b);
            *bk = *k;
            bcert.bound = cert.bound;
            bcert.gap = Certificate::gap_of(cert.bound, jb, family.j_floor());
            bcert.status = cert.status;
        }
        _ => *best = Some(s),
    }
}
