//! Exact continuous-time gaits of a general problem where `A = 0`
//! ([`crate::optimal::general::phase`]) as a job: one `K`, or `K` raised until the value stops
//! improving by the growth the crawler's phase method uses ([`crate::optimal::growth`]), with
//! progress events per `K` and cancellation.

use super::events::{run_with, Event, Hooks};
use crate::error::Result;
use crate::io::GeneralFile;
pub use crate::io::GeneralPhaseOptimized;
use crate::optimal::general::grow_general_phases;
use crate::optimal::growth::GrowthRange;
use crate::optimal::PhaseGrowthRecord;

/// Default `K` of [`GeneralPhaseSettings`]: 4 phases, what the paper's §4 one-link optimum
/// needs (free rise, slide on one face, free fall, slide on the other).
pub const DEFAULT_GENERAL_PHASES: usize = 4;

/// Settings of [`optimize_general_phase`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralPhaseSettings {
    /// `K` when it grows: the largest number of phases tried (default
    /// [`DEFAULT_GENERAL_PHASES`]; at most [`crate::optimal::general::MAX_GENERAL_PHASES`]).
    pub max_phases: usize,
    /// A fixed `K`: one MILP over gaits of at most `K` phases (default `None`: `K` grows from
    /// 1 to `max_phases`).
    pub phases: Option<usize>,
    /// Consecutive `K` without a gain that end the growth, counted once a `J_K` is positive
    /// (default [`crate::api::DEFAULT_PATIENCE`], as for crawlers).
    pub patience: usize,
    /// Seconds for all the MILPs (`None`, the default: no limit): the best gait so far, claimed
    /// with the bound of the `K` the limit cut short.
    pub time_limit: Option<f64>,
}

impl Default for GeneralPhaseSettings {
    fn default() -> Self {
        GeneralPhaseSettings {
            max_phases: DEFAULT_GENERAL_PHASES,
            phases: None,
            patience: super::DEFAULT_PATIENCE,
            time_limit: None,
        }
    }
}

/// The best exact gait of a problem file (`A = 0`; a quadratic `f2` by outer approximation)
/// among those of at most `K` phases, `K` fixed or grown (the settings), re-verified by the
/// exact simulator, with the table of the `K` solved. Errors name `dynamics.A`, `max_phases`,
/// `phases`, `patience` or `time_limit`. Cancellable; an event per `K` solved.
pub fn optimize_general_phase(
    file: &GeneralFile,
    s: &GeneralPhaseSettings,
    hooks: Hooks<'_>,
) -> Result<GeneralPhaseOptimized> {
    let (p, g) = super::general_problem(file)?;
    let range = match s.phases {
        Some(k) => GrowthRange {
            min_phases: k,
            max_phases: k,
            patience: 1,
        },
        None => GrowthRange {
            min_phases: 1,
            max_phases: s.max_phases,
            patience: s.patience,
        },
    };
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
    run_with(hooks, |em| {
        em.stage(match s.phases {
            Some(k) => format!("the phase MILP of the general problem (K = {k})"),
            None => format!(
                "the phase MILPs of the general problem, K = 1..{} grown",
                s.max_phases
            ),
        });
        let mut progress = |st: &crate::optimal::PhaseStep| {
            em.send(Event::PhaseSolved {
                step: st.clone(),
                start: false,
            })
        };
        let grown =
            grow_general_phases(&p, &g, range, s.time_limit, &mut progress).map_err(named)?;
        let mut r = GeneralPhaseOptimized::new(file, p.period, grown.best);
        if s.phases.is_none() {
            r.phase_growth = Some(PhaseGrowthRecord {
                table: grown.table,
                stop: grown.stop,
            });
        }
        Ok(r)
    })
}
