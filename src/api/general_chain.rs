//! The crawler's local methods on a general problem that is a crawler's gait problem
//! ([`crate::model::general::GeneralProblem::as_chain`]): `sequence` (a search over the slip
//! modes of phase gaits) and `chain` (the long chains' pattern search over per-link ramp gaits)
//! run on the crawler the problem is, by the crawler's own job ([`super::optimize`]), and the
//! gait comes back in the problem's terms ([`crate::optimal::general::chain_gait`]): replayed
//! by the general exact simulator, which must give `lambda` times the crawler's `J`. Neither
//! method makes a global claim: the answer's certificate is `local`, its status the method's
//! stop (`stationary`, `stalled`, or `time_limit`), and the crawler job's record of a structured
//! gait kept as the answer is passed on (`structured`). On a problem that is not a chain both
//! are refused, naming `method`. As every method on (P), both take `certify` and, on at most
//! four blocks, `bound` (the chain's upper bound over all periodic gaits).

use super::events::{run_with, Hooks};
use super::settings::{GaitMethod, OptimizeSettings};
use crate::certify::bound::BoundSettings;
use crate::error::{Error, Result};
use crate::io::{GeneralAnswer, GeneralFile};
use crate::optimal::general::{chain_gait, chain_gait_problem, ChainPieces};
use crate::optimal::ResultCertificate;

/// Settings of [`optimize_general_on_chain`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralChainSettings {
    /// The crawler's settings the method runs with: `method` is [`GaitMethod::Sequence`] or
    /// [`GaitMethod::Chain`]; `time_limit`, and for sequence `phases` and `max_phases` (its
    /// slip modes and the growth of its start), as for a crawler, with the crawler's defaults
    /// and checks (which refuse what the method does not take, e.g. `patience`). Its
    /// `certify` and `bound` are not read (see below).
    pub crawler: OptimizeSettings,
    /// Also check the necessary conditions of Theorem 2.2 on the gait in the problem's terms
    /// (the general certificate on its phases, durations free; default false).
    pub certify: bool,
    /// Also prove the chain's upper bound over all periodic gaits ([`crate::certify::bound`],
    /// at most four blocks), in the problem's units, recorded beside the `local` certificate
    /// (default: none).
    pub bound: Option<BoundSettings>,
}

impl Default for GeneralChainSettings {
    fn default() -> Self {
        GeneralChainSettings {
            crawler: OptimizeSettings {
                method: GaitMethod::Sequence,
                ..Default::default()
            },
            certify: false,
            bound: None,
        }
    }
}

/// The crawler's `sequence` or `chain` method on the crawler a problem file is (module docs),
/// its gait as a general phase gait re-verified by the general exact simulator. Errors name
/// `method` (not a chain, or another method) or the crawler's settings as the crawler's job
/// names them. Cancellable, with the crawler job's events.
pub fn optimize_general_on_chain(
    file: &GeneralFile,
    s: &GeneralChainSettings,
    hooks: Hooks<'_>,
) -> Result<GeneralAnswer> {
    let method = s.crawler.method;
    if !matches!(method, GaitMethod::Sequence | GaitMethod::Chain) {
        return Err(Error::invalid(
            "method",
            method.name(),
            "only the sequence and chain methods run on a general problem's chain",
        ));
    }
    let (p, _) = super::general_problem(file)?;
    let view = p
        .as_chain()
        .filter(|v| v.crawler.require_unique().is_ok())
        .ok_or_else(|| {
            Error::invalid(
                "method",
                method.name(),
                "applies to a general problem only where it is a crawler's gait problem (a \
                 chain whose crawler meets the uniqueness condition; see `analyze`'s \
                 structure)",
            )
        })?;
    let chain = super::general::check_additions(&p, s.bound.as_ref(), s.certify)?;
    let gp = chain_gait_problem(&p, &view)?;
    let settings = OptimizeSettings {
        certify: false,
        bound: None,
        ..s.crawler.clone()
    };
    run_with(hooks, |em| {
        // The crawler's events in the problem's units of `J` (`lambda` times the crawler's).
        let o = em.scaled(view.objective_scale, || {
            super::optimize::optimize_in(&view.crawler, &gp, &settings, em)
        })?;
        let r = &o.result;
        if !r.is_phase_gait() {
            // The map back reads the gait as exact phases (a P_m process would be misread).
            return Err(Error::Numerical(format!(
                "the crawler's {} method answered with a {} gait, not an exact one",
                method.name(),
                r.head.method
            )));
        }
        let pieces = ChainPieces {
            durations: &r.gait.durations,
            controls: &r.gait.controls,
            states: &r.gait.states,
            block_displacements: &r.gait.block_displacements,
            modes: &r.gait.slip,
            objective: r.head.objective,
        };
        let mut gait = chain_gait(&p, &view, pieces)?;
        gait.certificate.status = r.head.status;
        let mut answer = GeneralAnswer::phase(file, p.period, gait);
        answer.head.method = method.name().into();
        answer.head.status = r.head.status;
        answer.head.certificate = ResultCertificate::local(None);
        answer.formulation = Some("chain".into());
        answer.records.structured = r.records.structured.clone();
        let bound = chain.as_ref().zip(s.bound.as_ref());
        super::general::add_bound_and_conditions(&p, &mut answer, bound, s.certify, em)?;
        Ok(answer)
    })
}
