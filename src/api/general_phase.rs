//! Exact continuous-time gaits of a general problem where `A = 0`
//! ([`crate::optimal::general::phase`]) as a job: one `K`, or `K` raised until the value stops
//! improving by the growth the crawler's phase method uses ([`crate::optimal::growth`]), with
//! progress events per `K` and cancellation.

use super::events::{run_with, Event, Hooks};
use super::settings::PhaseFormulation;
use crate::error::Result;
use crate::io::{GeneralAnswer, GeneralFile};
use crate::model::general::GeneralProblem;
use crate::model::ChainView;
use crate::optimal::general::{
    grow_chain_phases, grow_general_phases, grow_general_transitions, GeneralPhaseGait, Geometry,
};
use crate::optimal::growth::{Growth, GrowthRange};
use crate::optimal::{PhaseGrowthRecord, PhaseStep, StructuredRecord};

/// Default largest `K` of [`GeneralPhaseSettings`] in (P)'s own formulations: 4 phases in the
/// general one, what the paper's §4 one-link optimum needs (free rise, slide on one face, free
/// fall, slide on the other), and 4 slots of a free transition and a phase with free
/// transitions. The chain's formulation counts slip phases and takes the crawler's default,
/// [`crate::optimal::DEFAULT_MAX_PHASES`] ([`GeneralPhaseSettings::max_phases`]).
pub const DEFAULT_GENERAL_PHASES: usize = 4;

/// Settings of [`optimize_general_phase`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralPhaseSettings {
    /// `K` when it grows: the largest number of phases tried, at most
    /// [`crate::optimal::general::MAX_GENERAL_PHASES`]. `None` (the default) takes the
    /// formulation's default: [`DEFAULT_GENERAL_PHASES`] phases in the general one (slots with free
    /// transitions), the crawler's [`crate::optimal::DEFAULT_MAX_PHASES`] slip phases in the
    /// chain's, so that a crawler and its general form grow `K` alike
    /// ([`GeneralPhaseSettings::max_phases_for`]).
    pub max_phases: Option<usize>,
    /// A fixed `K`: one MILP over gaits of at most `K` phases (slots with free transitions,
    /// slip phases in the chain's formulation; default `None`: `K` grows from 1 to
    /// `max_phases`).
    pub phases: Option<usize>,
    /// Consecutive `K` without a gain that end the growth, counted once a `J_K` moves the
    /// system (above `1e-9` of its length scale; default [`crate::api::DEFAULT_PATIENCE`], as
    /// for crawlers). At least 1, also with a fixed `phases`.
    pub patience: usize,
    /// Seconds for all the MILPs (`None`, the default: no limit): the best gait so far, claimed
    /// with the bound of the `K` the limit cut short.
    pub time_limit: Option<f64>,
    /// The formulation: `None` (the default) takes the strongest that applies: the chain's
    /// where the problem is a crawler's gait problem, the slots of a free transition and a
    /// phase elsewhere (`Transitions`: at equal `K` at least as good as the general one, as
    /// strong as the chain's on every crawler measured). `Some(General)` forces the general
    /// one, `K` phases with no free transition (to compare them); `Some(Transitions)` the
    /// slots on any problem; `Some(Chain)` asks for the chain's and is refused, naming
    /// `formulation`, where the problem is not a chain.
    pub formulation: Option<PhaseFormulation>,
    /// Also prove the crawler's upper bound over all periodic gaits (default none): only for
    /// a problem that is a crawler's gait problem (`super::general::chain_upper_bound`).
    pub bound: Option<crate::certify::bound::BoundSettings>,
    /// Also check the necessary conditions of Theorem 2.2 on the gait, on its own phases with
    /// the durations free (default false; [`crate::certify::general`]).
    pub certify: bool,
}

impl Default for GeneralPhaseSettings {
    fn default() -> Self {
        GeneralPhaseSettings {
            max_phases: None,
            phases: None,
            patience: super::DEFAULT_PATIENCE,
            time_limit: None,
            formulation: None,
            bound: None,
            certify: false,
        }
    }
}

impl GeneralPhaseSettings {
    /// The `K` the MILPs run over: `phases` alone, or `1..=max_phases` grown with `patience`.
    fn range(&self, max_phases: usize) -> GrowthRange {
        match self.phases {
            Some(k) => GrowthRange {
                min_phases: k,
                max_phases: k,
                patience: 1,
            },
            None => GrowthRange {
                min_phases: 1,
                max_phases,
                patience: self.patience,
            },
        }
    }

    /// The largest `K` of a growth: `max_phases`, or the formulation's default where it is
    /// `None` (the chain's, `chain`: [`crate::optimal::DEFAULT_MAX_PHASES`] slip phases as for
    /// a crawler; else [`DEFAULT_GENERAL_PHASES`] phases).
    pub fn max_phases_for(&self, chain: bool) -> usize {
        self.max_phases.unwrap_or(if chain {
            crate::optimal::DEFAULT_MAX_PHASES
        } else {
            DEFAULT_GENERAL_PHASES
        })
    }
}

/// The chain the phase MILP runs on (module docs): a chain (a crawler's gait problem whose
/// crawler meets the uniqueness condition) takes the chain's stronger formulation, K slip
/// phases with transitions free (`optimal::general::chain_phase`), unless `formulation` asks
/// for one of (P)'s; `Some(Chain)` on a problem that is not such a chain is refused, naming
/// `formulation`.
fn chain_formulation(
    p: &GeneralProblem,
    formulation: Option<PhaseFormulation>,
) -> Result<Option<ChainView>> {
    let chain = p.as_chain().filter(|v| {
        v.crawler.require_unique().is_ok()
            && !matches!(
                formulation,
                Some(PhaseFormulation::General | PhaseFormulation::Transitions)
            )
    });
    if chain.is_none() && formulation == Some(PhaseFormulation::Chain) {
        return Err(crate::Error::invalid(
            "formulation",
            "chain",
            "the chain's formulation needs a crawler's gait problem (a chain whose crawler \
             meets the uniqueness condition; see `analyze`)",
        ));
    }
    Ok(chain)
}

/// The growth of `K` in the formulation chosen: the chain's where `chain` is given, else the
/// slots of a free transition and a phase (`transitions`) or (P)'s own.
fn grow(
    p: &GeneralProblem,
    g: &Geometry,
    chain: Option<&ChainView>,
    transitions: bool,
    range: GrowthRange,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<(Growth<GeneralPhaseGait>, Option<StructuredRecord>)> {
    match chain {
        Some(view) => grow_chain_phases(p, g, view, range, progress),
        None if transitions => grow_general_transitions(p, g, range, progress).map(|g| (g, None)),
        None => grow_general_phases(p, g, range, progress).map(|g| (g, None)),
    }
}

/// The phase gait that starts (P)'s local method where `A = 0` (as the phase optimum starts
/// a crawler's): `K` grown from 1 in the default formulation (the strongest that applies,
/// [`GeneralPhaseSettings`]'s default) up to `max_phases` (`None`: the formulation's default,
/// [`GeneralPhaseSettings::max_phases_for`]), with patience 1 (a start need not be certified),
/// within the job's deadline.
pub(super) fn phase_start(
    p: &GeneralProblem,
    g: &Geometry,
    max_phases: Option<usize>,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<GeneralPhaseGait> {
    let chain = chain_formulation(p, None)?;
    let range = GrowthRange {
        min_phases: 1,
        max_phases: GeneralPhaseSettings {
            max_phases,
            ..GeneralPhaseSettings::default()
        }
        .max_phases_for(chain.is_some()),
        patience: 1,
    };
    grow(p, g, chain.as_ref(), true, range, progress).map(|(grown, _)| grown.best)
}

/// Refuses `max_phases` (the largest `K` of a start's phase growth, [`phase_start`]) where no
/// phase start grows (`grows` false: its reason `why`), or outside `1..=`
/// [`crate::optimal::general::MAX_GENERAL_PHASES`]; errors name `max_phases`.
pub(super) fn check_start_phases(max_phases: Option<usize>, grows: bool, why: &str) -> Result<()> {
    let Some(k) = max_phases else {
        return Ok(());
    };
    if !grows {
        return Err(crate::Error::invalid("max_phases", k, why));
    }
    let range = GrowthRange {
        min_phases: 1,
        max_phases: k,
        patience: 1,
    };
    range.check(crate::optimal::general::MAX_GENERAL_PHASES)
}

/// The best exact gait of a problem file (`A = 0`; a quadratic `f2` by outer approximation)
/// among those of at most `K` phases, `K` fixed or grown (the settings), re-verified by the
/// exact simulator, with the table of the `K` solved. Errors name `dynamics.A`, `max_phases`,
/// `phases`, `patience` or `time_limit`. Cancellable; an event per `K` solved.
pub fn optimize_general_phase(
    file: &GeneralFile,
    s: &GeneralPhaseSettings,
    hooks: Hooks<'_>,
) -> Result<GeneralAnswer> {
    if s.patience == 0 {
        return Err(crate::Error::invalid("patience", 0, "must be at least 1"));
    }
    let (p, g) = super::general_problem(file)?;
    let bound_chain = super::general::check_additions(&p, s.bound.as_ref(), s.certify)?;
    let chain = chain_formulation(&p, s.formulation)?;
    let max_phases = s.max_phases_for(chain.is_some());
    let range = s.range(max_phases);
    let named = |e: crate::Error| match (s.phases, e) {
        (
            Some(_),
            crate::Error::InvalidParameter {
                field,
                value,
                reason,
            },
        ) if field == "max_phases" => crate::Error::InvalidParameter {
            field: "phases".into(),
            value,
            reason,
        },
        (_, e) => e,
    };
    crate::optimal::check_time_limit(s.time_limit)?;
    run_with(hooks, |em| {
        em.stage(match s.phases {
            Some(k) => format!("the phase MILP of the general problem (K = {k})"),
            None => format!("the phase MILPs of the general problem, K = 1..{max_phases} grown"),
        });
        let mut progress = |st: &PhaseStep| {
            em.send(Event::PhaseSolved {
                step: st.clone(),
                start: false,
            })
        };
        let transitions = matches!(s.formulation, None | Some(PhaseFormulation::Transitions));
        // The job's deadline: `time_limit` over the growth (the bound and the certificate
        // after it run to completion).
        let (grown, structured) = crate::progress::within(s.time_limit, || {
            grow(&p, &g, chain.as_ref(), transitions, range, &mut progress)
        })
        .map_err(named)?;
        let mut r = GeneralAnswer::phase(file, p.period, grown.best);
        if chain.is_some() {
            r.formulation = Some(PhaseFormulation::Chain.name().into());
        } else if transitions {
            r.formulation = Some(PhaseFormulation::Transitions.name().into());
        }
        r.records.structured = structured;
        if s.phases.is_none() {
            r.records.phase_growth = Some(PhaseGrowthRecord {
                table: grown.table,
                stop: grown.stop,
            });
        }
        let bound = bound_chain.as_ref().zip(s.bound.as_ref());
        super::general::add_bound_and_conditions(&p, &mut r, bound, s.certify, em)?;
        Ok(r)
    })
}
