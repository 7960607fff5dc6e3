//! What the jobs on a general problem (P) return (theory §11): the records that
//! [`crate::api`] builds, text output renders ([`crate::present::text`]) and `--json` writes.
//! They sit here, below presentation and the API, so that both can name them.
//!
//! Every optimisation answer opens with the head of every result, the crawler's included
//! ([`ResultHead`], flattened: `format`, `version`, `kind` (`"general"`), `method`,
//! `objective`, `status` (what was proven, the crawler's [`crate::optimal::MilpStatus`]) and
//! `certificate` (the crawler's [`ResultCertificate`])), then `problem` (the problem (P) in
//! the file's form, its `[input]` left out, so that the result is re-verified from itself
//! alone) and the method's `solution`. [`super::ResultFile`] reads them back, checked
//! ([`GeneralAnswer::check_consistent`]).

use super::GeneralFile;
use crate::error::Error;
use crate::integrate::{ControlInput, GeneralSimulation};
use crate::model::general::GeneralProblem;
use crate::optimal::envelope::ResultHead;
use crate::optimal::general::{GeneralLocal, GeneralPhaseGait, GeneralPm, Geometry};
use crate::optimal::{
    local_status, ConvergenceRow, PhaseGrowthRecord, ResultCertificate, ResultKind,
};
use serde::{Deserialize, Deserializer, Serialize};

/// How a check came out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CheckStatus {
    /// Holds.
    Pass,
    /// Fails: the problem is refused.
    Fail,
    /// A property reported, not required of every method.
    Info,
}

/// One check of the problem.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// What is checked.
    pub name: String,
    /// The outcome.
    pub status: CheckStatus,
    /// Numbers and reasons.
    pub detail: String,
}

/// [`crate::api::analyze_general`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralAnalysis {
    /// `"general"` (a crawler's analysis has no such field).
    pub kind: &'static str,
    /// The problem (rows of C scaled to unit normals).
    pub problem: GeneralProblem,
    /// C's geometry.
    pub geometry: Geometry,
    /// The checks, in order.
    pub checks: Vec<Check>,
    /// The first failed check as the error a solver would return (`None`: well posed).
    #[serde(skip)]
    pub failure: Option<Error>,
}

/// [`crate::api::simulate_general`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralSimulated {
    /// `"general"`.
    pub kind: &'static str,
    /// `J` of one period on the periodic orbit (over `[0, T]` for a Cauchy problem), as
    /// `simulation.objective`; `None` when the periodic regime was not reached.
    pub objective: Option<f64>,
    /// `"exact"` (event-driven, where `A = 0` and the input is piecewise constant, unless
    /// catching-up is asked) or `"catching-up"`.
    pub method: &'static str,
    /// Steps per period.
    pub steps_per_period: usize,
    /// Where the integration started: `x(0)` of a Cauchy problem, else the origin when it
    /// lies in C, else C's Chebyshev centre.
    pub start: Vec<f64>,
    /// Which of the three `start` is (`initial_state`, `origin`, `chebyshev_centre`).
    pub start_from: &'static str,
    /// How the periodic regime was searched: `"chain"` by the crawler's simulator on the chain
    /// the problem is (its Newton steps; `crate::integrate::chain_regime`), the period then
    /// played from the state found by the general simulator; `"plain"` by iterating the
    /// general period map from `start` (also for a Cauchy problem, which has no regime).
    pub regime_search: &'static str,
    /// The control played.
    pub input: ControlInput,
    /// The simulation.
    pub simulation: GeneralSimulation,
}

/// A word of a fixed set (a result's `method`, `start_from`): read back by [`word`], which
/// maps the text onto the set's `&'static str` (named through this alias so that serde's
/// derive does not take the field for a string borrowed from the input).
pub type Word = &'static str;

/// One of a fixed set of words, as a `&'static str` (the words a result's fields take).
fn word<'de, D: Deserializer<'de>>(
    d: D,
    words: &[&'static str],
) -> std::result::Result<&'static str, D::Error> {
    let s = String::deserialize(d)?;
    words
        .iter()
        .copied()
        .find(|w| *w == s)
        .ok_or_else(|| serde::de::Error::custom(format!("\"{s}\" is not one of {words:?}")))
}

fn start_word<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<&'static str, D::Error> {
    word(d, &["input", "phase", "square_waves", "start"])
}

/// The problem as a result stores it: the file's sections without `[input]` (a control to
/// simulate, not part of (P), and possibly a path to another file).
fn stored_problem(file: &GeneralFile) -> GeneralFile {
    GeneralFile {
        input: None,
        base_dir: Default::default(),
        ..file.clone()
    }
}

/// [`crate::api::optimize_general`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralOptimized {
    /// The envelope ([`ResultHead`]): kind `"general"`, method `"discrete"` (the paper's P_m,
    /// globally), `J` re-verified by simulation, what was proven, and the certificate
    /// `"global"` with the MILP's bound and gap.
    #[serde(flatten)]
    pub head: ResultHead,
    /// The problem (P) in the file's form (module docs).
    pub problem: GeneralFile,
    /// The MILP's own objective, before re-verification (as a crawler's result has it).
    pub solver_objective: f64,
    /// The period (not written: it is the problem's `[problem] period`; filled from it on
    /// reading).
    #[serde(skip_serializing)]
    pub period: f64,
    /// The verified optimum of P_m with its certificate.
    pub solution: GeneralPm,
    /// The necessary conditions on it, when asked ([`crate::api::GeneralPmSettings::certify`]);
    /// not read back from a file (`crawlopt certify` recomputes them).
    #[serde(skip_serializing_if = "Option::is_none", skip_deserializing)]
    pub necessary_conditions: Option<crate::certify::GeneralNecessaryConditions>,
    /// The table of `J_m` for `m` up to the solution's, when asked
    /// ([`crate::api::GeneralPmSettings::convergence`]), as for crawlers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<Vec<ConvergenceRow>>,
}

impl GeneralOptimized {
    /// The answer of `solution` for the problem of `file`, with its envelope.
    pub fn new(
        file: &GeneralFile,
        period: f64,
        solution: GeneralPm,
        necessary_conditions: Option<crate::certify::GeneralNecessaryConditions>,
    ) -> Self {
        GeneralOptimized {
            head: ResultHead::new(
                ResultKind::General,
                "discrete",
                solution.objective,
                solution.certificate.status,
                ResultCertificate::of_milp(&solution.certificate, None),
            ),
            problem: stored_problem(file),
            solver_objective: solution.certificate.milp_objective,
            period,
            solution,
            necessary_conditions,
            convergence: None,
        }
    }
}

/// [`crate::api::optimize_general_local`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralLocalOptimized {
    /// The envelope ([`ResultHead`]): kind `"general"`, method `"local"` (the paper's P_m by
    /// the active-set method on its LPCC), `J` re-verified by simulation, how the method
    /// stopped ([`local_status`] of `solution.stop`: `stationary`, `stalled` or `time_limit`)
    /// and the certificate `"local"` (no bound, no gap).
    #[serde(flatten)]
    pub head: ResultHead,
    /// The problem (P) in the file's form (module docs).
    pub problem: GeneralFile,
    /// The period (not written: it is the problem's `[problem] period`; filled from it on
    /// reading).
    #[serde(skip_serializing)]
    pub period: f64,
    /// Where the starts came from: `"start"` (a given result, `--start`), `"input"` (the file's
    /// `[input]`), `"phase"` (the phase optimum, where `A = 0`) or `"square_waves"`.
    #[serde(deserialize_with = "start_word")]
    pub start_from: Word,
    /// Starts solved from (all of them unless the time limit ended the search).
    pub starts_tried: usize,
    /// Which of them gave the answer (0-based, the first of equals).
    pub best_start: usize,
    /// The best local solution, re-verified by simulation.
    pub solution: GeneralLocal,
}

impl GeneralLocalOptimized {
    /// The answer of `solution` for the problem of `file`, with its envelope; the starts
    /// as [`GeneralLocalOptimized::start_from`] and the following fields say.
    pub fn new(
        file: &GeneralFile,
        period: f64,
        (start_from, starts_tried, best_start): (&'static str, usize, usize),
        solution: GeneralLocal,
    ) -> Self {
        GeneralLocalOptimized {
            head: ResultHead::new(
                ResultKind::General,
                "local",
                solution.objective,
                local_status(solution.stop),
                ResultCertificate::local(None),
            ),
            problem: stored_problem(file),
            period,
            start_from,
            starts_tried,
            best_start,
            solution,
        }
    }
}

/// [`crate::api::optimize_general_phase`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralPhaseOptimized {
    /// The envelope ([`ResultHead`]): kind `"general"`, method `"phase"` (exact gaits of at
    /// most `K` phases, globally) or `"sequence"` or `"chain"` (the crawler's local method on
    /// the problem's chain, [`crate::api::optimize_general_on_chain`], an exact gait without a
    /// global claim), `J` re-verified by the exact simulation, what was proven
    /// (`optimal_among_k_phases`, ...) and the certificate (`"global_k_phases"` with
    /// `phases = K`, the MILP's bound and gap).
    #[serde(flatten)]
    pub head: ResultHead,
    /// The problem (P) in the file's form (module docs).
    pub problem: GeneralFile,
    /// The MILP's own objective, before re-verification (of the crawler's methods on a chain:
    /// the crawler's, in this problem's units; as a crawler's result has it).
    pub solver_objective: f64,
    /// The period (not written: it is the problem's `[problem] period`; filled from it on
    /// reading).
    #[serde(skip_serializing)]
    pub period: f64,
    /// The verified optimum with its certificate.
    pub solution: GeneralPhaseGait,
    /// How `K` was grown (absent for a fixed `K`): one row per `K` solved and why the growth
    /// stopped, as for crawlers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub phase_growth: Option<PhaseGrowthRecord>,
    /// `"chain"` when the problem is a crawler's gait problem and the chain's formulation ran
    /// (`K` slip phases, transitions free: the gait may have up to `2K` phases); absent for
    /// the general formulation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub formulation: Option<String>,
    /// The crawler job's record of a best structured gait that is the answer (methods
    /// `sequence` and `chain`: the method's own gait was below it, or it was the start of a
    /// search the time limit cut short; [`crate::optimal::GaitResult::structured`]), its `J`
    /// in the crawler's units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structured: Option<crate::optimal::StructuredRecord>,
    /// The necessary conditions on the gait, when asked
    /// ([`crate::api::GeneralPhaseSettings::certify`]); not read back from a file (`crawlopt
    /// certify` recomputes them).
    #[serde(skip_serializing_if = "Option::is_none", skip_deserializing)]
    pub necessary_conditions: Option<crate::certify::GeneralNecessaryConditions>,
}

impl GeneralPhaseOptimized {
    /// The answer of `solution` for the problem of `file`, with its envelope.
    pub fn new(file: &GeneralFile, period: f64, solution: GeneralPhaseGait) -> Self {
        GeneralPhaseOptimized {
            head: ResultHead::new(
                ResultKind::General,
                "phase",
                solution.objective,
                solution.certificate.status,
                ResultCertificate::of_milp(&solution.certificate, Some(solution.max_phases)),
            ),
            problem: stored_problem(file),
            solver_objective: solution.certificate.milp_objective,
            period,
            solution,
            phase_growth: None,
            formulation: None,
            structured: None,
            necessary_conditions: None,
        }
    }
}

/// The answer of [`crate::api::optimize_general_plan`]: one of the three methods' (serialised as that
/// answer, whose `method` says which).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum GeneralAnswer {
    /// P_m globally, with its necessary conditions when asked.
    Discrete(Box<GeneralOptimized>),
    /// P_m locally.
    Local(Box<GeneralLocalOptimized>),
    /// Exact gaits of at most `K` phases.
    Phase(Box<GeneralPhaseOptimized>),
}

impl GeneralAnswer {
    /// The necessary conditions computed with the answer (`certify`), if any: a global P_m
    /// optimum's or a phase gait's.
    pub fn necessary_conditions(&self) -> Option<&crate::certify::GeneralNecessaryConditions> {
        match self {
            GeneralAnswer::Discrete(r) => r.necessary_conditions.as_ref(),
            GeneralAnswer::Local(_) => None,
            GeneralAnswer::Phase(r) => r.necessary_conditions.as_ref(),
        }
    }

    /// The envelope: kind, method, `J`, status and certificate ([`ResultHead`]).
    pub fn head(&self) -> &ResultHead {
        match self {
            GeneralAnswer::Discrete(r) => &r.head,
            GeneralAnswer::Local(r) => &r.head,
            GeneralAnswer::Phase(r) => &r.head,
        }
    }

    /// The answer's control as pieces `(durations, controls)`: a P_m answer's `2^m` equal steps,
    /// a phase gait's phases (how a result starts (P)'s local method, `--start`).
    pub fn pieces(&self) -> (Vec<f64>, &[Vec<f64>]) {
        let steps = |period: f64, u: &[Vec<f64>]| vec![period / u.len().max(1) as f64; u.len()];
        match self {
            GeneralAnswer::Discrete(r) => (steps(r.period, &r.solution.u), &r.solution.u),
            GeneralAnswer::Local(r) => (steps(r.period, &r.solution.u), &r.solution.u),
            GeneralAnswer::Phase(r) => (r.solution.durations.clone(), &r.solution.controls),
        }
    }

    /// The problem (P) in the file's form.
    pub fn problem(&self) -> &GeneralFile {
        match self {
            GeneralAnswer::Discrete(r) => &r.problem,
            GeneralAnswer::Local(r) => &r.problem,
            GeneralAnswer::Phase(r) => &r.problem,
        }
    }
}
