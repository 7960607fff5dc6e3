//! The general problem's exact phase gaits ([`super::phase`]) with `K` raised until the value
//! stops improving: the general formulation as a [`PhaseFamily`] of the growth written once
//! for both families ([`crate::optimal::growth`]; the crawler's is
//! [`crate::optimal::grow_phases`]).

use super::discrete::{big_m, column_bound};
use super::geometry::Geometry;
use super::phase::{
    check_phase_growth, solve_general_phase, solve_general_transitions, GeneralPhaseGait,
};
use crate::error::Result;
use crate::model::general::{GeneralCost, GeneralProblem};
use crate::optimal::growth::{grow, Growth, GrowthRange, PhaseFamily, PhaseStep};
use crate::optimal::milp::{Certificate, MilpStatus, OA_TOL};

/// The general phase gaits of one problem: one `K` is [`solve_general_phase`], or
/// [`solve_general_transitions`] with `transitions`.
struct GeneralPhases<'a> {
    p: &'a GeneralProblem,
    g: &'a Geometry,
    transitions: bool,
}

impl PhaseFamily for GeneralPhases<'_> {
    type Gait = GeneralPhaseGait;

    // The general MILP takes no start: each K is solved from scratch (its symmetry breaking
    // keeps small K cheap).
    fn solve(&self, k: usize, _best: Option<&GeneralPhaseGait>) -> Result<GeneralPhaseGait> {
        if self.transitions {
            solve_general_transitions(self.p, self.g, k)
        } else {
            solve_general_phase(self.p, self.g, k)
        }
    }
    fn objective(g: &GeneralPhaseGait) -> f64 {
        g.objective
    }
    fn claim(g: &mut GeneralPhaseGait) -> (&mut usize, &mut Certificate) {
        (&mut g.max_phases, &mut g.certificate)
    }
    /// `J`'s scale: the largest face weight times C's length scale (`J = int sum_f w_f
    /// lambda_f dt`, the reactions integrated to lengths of C).
    fn length_scale(&self) -> f64 {
        self.p.j_scale().max(1e-300)
    }
    fn j_floor(&self) -> f64 {
        self.p.j_floor()
    }
    fn gain_tolerance(&self) -> f64 {
        match self.p.cost {
            GeneralCost::None => 1e-7,
            _ => OA_TOL,
        }
    }
    fn same(a: &GeneralPhaseGait, b: &GeneralPhaseGait) -> bool {
        a.durations == b.durations && a.states == b.states
    }
    /// The bound the reaction columns allow, `T M sum_f max(w_f, 0)`, valid for every gait.
    fn unproven(&self, g: &GeneralPhaseGait, phases: usize) -> GeneralPhaseGait {
        let bound = big_m(self.p, self.g, 1.0)
            .map(|bm| column_bound(self.p, bm.multiplier * self.p.period))
            .unwrap_or(f64::INFINITY)
            .max(g.objective);
        let mut g = g.clone();
        g.max_phases = phases;
        g.certificate = Certificate {
            status: MilpStatus::TimeLimit,
            milp_objective: g.objective,
            bound,
            gap: Certificate::gap_of(bound, g.objective, self.p.j_floor()),
        };
        g
    }
}

/// The best exact gait of a general problem (`A = 0`) with `K` raised over `range` (the crawler's
/// growth, [`crate::optimal::growth::grow`]): the gait of the largest `J_K` found, claimed for the
/// last `K` solved, the whole growth within the job's deadline ([`crate::progress::within`]).
/// `progress` sees each `K`. Errors name `max_phases`, `min_phases`, `patience` or what
/// `check_phase_growth` names.
pub fn grow_general_phases(
    p: &GeneralProblem,
    g: &Geometry,
    range: GrowthRange,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<Growth<GeneralPhaseGait>> {
    grow_general(p, g, range, false, progress)
}

/// [`grow_general_phases`] over slots of a free transition and a phase
/// ([`solve_general_transitions`]): `K` counts slots, each a free transition and a phase, as
/// the chain's formulation counts a transition and a slip phase.
pub fn grow_general_transitions(
    p: &GeneralProblem,
    g: &Geometry,
    range: GrowthRange,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<Growth<GeneralPhaseGait>> {
    grow_general(p, g, range, true, progress)
}

fn grow_general(
    p: &GeneralProblem,
    g: &Geometry,
    range: GrowthRange,
    transitions: bool,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<Growth<GeneralPhaseGait>> {
    check_phase_growth(p, g, range)?;
    let family = GeneralPhases { p, g, transitions };
    grow(&family, range, None, progress)
}
