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
use crate::certify::GeneralProcess;
use crate::error::Error;
use crate::integrate::{ControlInput, GeneralSimulation};
use crate::model::general::GeneralProblem;
use crate::optimal::envelope::{ResultHead, SolutionKind};
use crate::optimal::general::{GeneralLocal, GeneralPhaseGait, GeneralPm, Geometry};
use crate::optimal::{local_status, ResultCertificate, ResultKind, ResultRecords};
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

/// Where the starts of (P)'s local method came from and which gave the answer (written only
/// by the local method, flattened into the answer: `start_from`, `starts_tried`,
/// `best_start`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct LocalStarts {
    /// `"start"` (a given result, `--start`), `"input"` (the file's `[input]`), `"phase"` (the
    /// phase optimum, where `A = 0`) or `"square_waves"`.
    #[serde(deserialize_with = "start_word")]
    pub start_from: Word,
    /// Starts solved from (all of them unless the time limit ended the search).
    pub starts_tried: usize,
    /// Which of them gave the answer (0-based, the first of equals).
    pub best_start: usize,
}

/// The solution of an answer on (P), by the kind of method that found it. Written bare (the
/// answer's `method` says which); read back by its shape: a phase gait has `durations`, a
/// local P_m process `lp_objective`, a global one neither.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum GeneralSolution {
    /// The paper's P_m, solved globally (method `discrete`).
    Pm(GeneralPm),
    /// P_m by the active-set method on its LPCC (method `local`).
    Local(GeneralLocal),
    /// An exact gait (methods `phase`, `sequence`, `chain`).
    Phase(GeneralPhaseGait),
}

impl GeneralSolution {
    /// The kind of this solution ([`SolutionKind`]), which names the methods that answer with
    /// it ([`SolutionKind::methods`]).
    pub fn kind(&self) -> SolutionKind {
        match self {
            GeneralSolution::Pm(_) => SolutionKind::Discrete,
            GeneralSolution::Local(_) => SolutionKind::Local,
            GeneralSolution::Phase(_) => SolutionKind::Phase,
        }
    }

    /// The global P_m process, if the solution is one.
    pub fn as_pm(&self) -> Option<&GeneralPm> {
        match self {
            GeneralSolution::Pm(s) => Some(s),
            _ => None,
        }
    }

    /// The local P_m process, if the solution is one.
    pub fn as_local(&self) -> Option<&GeneralLocal> {
        match self {
            GeneralSolution::Local(s) => Some(s),
            _ => None,
        }
    }

    /// The phase gait, if the solution is one.
    pub fn as_phase(&self) -> Option<&GeneralPhaseGait> {
        match self {
            GeneralSolution::Phase(s) => Some(s),
            _ => None,
        }
    }

    /// `J`, re-verified by simulation.
    pub fn objective(&self) -> f64 {
        match self {
            GeneralSolution::Pm(s) => s.objective,
            GeneralSolution::Local(s) => s.objective,
            GeneralSolution::Phase(s) => s.objective,
        }
    }

    /// The process of the solution on the problem `p` it solves: what (P)'s checks and the
    /// necessary conditions (Theorem 2.2) read.
    pub fn process(&self, p: &GeneralProblem) -> GeneralProcess {
        match self {
            GeneralSolution::Pm(s) => GeneralProcess::from_pm(p, s),
            GeneralSolution::Local(s) => GeneralProcess::from_local(p, s),
            GeneralSolution::Phase(s) => GeneralProcess::from_phase(s),
        }
    }

    /// The kind of solution a solution's JSON object has, told by its keys (a phase gait's
    /// `durations`, a local process's `lp_objective`, else a global P_m process).
    pub(super) fn shape(v: &serde_json::Value) -> SolutionKind {
        if v.get("durations").is_some() {
            SolutionKind::Phase
        } else if v.get("lp_objective").is_some() {
            SolutionKind::Local
        } else {
            SolutionKind::Discrete
        }
    }

    /// Reads a solution of the kind `kind`.
    pub(super) fn from_value(v: serde_json::Value, kind: SolutionKind) -> serde_json::Result<Self> {
        Ok(match kind {
            SolutionKind::Discrete => GeneralSolution::Pm(serde_json::from_value(v)?),
            SolutionKind::Local => GeneralSolution::Local(serde_json::from_value(v)?),
            SolutionKind::Phase => GeneralSolution::Phase(serde_json::from_value(v)?),
        })
    }
}

impl<'de> Deserialize<'de> for GeneralSolution {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        let shape = GeneralSolution::shape(&v);
        GeneralSolution::from_value(v, shape).map_err(serde::de::Error::custom)
    }
}

/// The answer of every method on (P) ([`crate::api::optimize_general_plan`] and the per-method
/// calls): the envelope, the problem, the solution and the records the method keeps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneralAnswer {
    /// The envelope ([`ResultHead`]): kind `"general"`; method `"discrete"` (the paper's P_m,
    /// globally), `"local"` (P_m by the active-set method on its LPCC), `"phase"` (exact gaits
    /// of at most `K` phases, globally) or `"sequence"` or `"chain"` (the crawler's local
    /// methods on the problem's chain, [`crate::api::optimize_general_on_chain`], an exact gait
    /// without a global claim); `J` re-verified by simulation; what was proven (for the local
    /// method [`local_status`] of its stop: `stationary`, `stalled` or `time_limit`); and the
    /// certificate (`"global"`, `"global_k_phases"` with `phases = K`, with the MILP's bound
    /// and gap, or `"local"`).
    #[serde(flatten)]
    pub head: ResultHead,
    /// The problem (P) in the file's form (module docs).
    pub problem: GeneralFile,
    /// The MILP's own objective, before re-verification (of the crawler's methods on a chain:
    /// the crawler's, in this problem's units; as a crawler's result has it); absent for the
    /// local method, which solves no MILP.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver_objective: Option<f64>,
    /// The period (not written: it is the problem's `[problem] period`; filled from it on
    /// reading).
    #[serde(skip_serializing)]
    pub period: f64,
    /// The local method's starts (absent for the other methods).
    #[serde(flatten)]
    pub starts: Option<LocalStarts>,
    /// The verified solution (with the MILP's certificate where one was solved).
    pub solution: GeneralSolution,
    /// The records beside the solution ([`ResultRecords`], as a crawler's result has them):
    /// how `K` was grown (phase gaits; absent for a fixed `K`), the table of `J_m` for `m` up
    /// to the solution's (global P_m, [`crate::api::GeneralPmSettings::convergence`]), and the
    /// crawler job's structured gait when it is the answer (methods `sequence` and `chain`:
    /// the method's own gait was below it, or it was the start of a search the time limit cut
    /// short), its `J` in the crawler's units.
    #[serde(flatten)]
    pub records: ResultRecords,
    /// `"chain"` when the problem is a crawler's gait problem and the chain's phase formulation
    /// ran (`K` slip phases, transitions free: the gait may have up to `2K` phases),
    /// `"transitions"` for the general one with a free transition before each phase; absent
    /// for the general formulation and for P_m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub formulation: Option<String>,
    /// The start a global P_m MILP took as its first incumbent, when it was given one
    /// ([`crate::api::GeneralPmSettings::start`]), as a crawler's result records it: where it
    /// came from and `J` of its process on the grid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub discrete_start: Option<crate::optimal::StartRecord>,
    /// The necessary conditions on the solution, when asked (a global P_m optimum's or a
    /// phase gait's, [`crate::api::GeneralPmSettings::certify`],
    /// [`crate::api::GeneralPhaseSettings::certify`]); not read back from a file (`crawlopt
    /// certify` recomputes them).
    #[serde(skip_serializing_if = "Option::is_none", skip_deserializing)]
    pub necessary_conditions: Option<crate::certify::GeneralNecessaryConditions>,
}

impl GeneralAnswer {
    /// The answer of `solution` for the problem of `file` under the envelope `head`; the
    /// records are empty.
    fn with(
        file: &GeneralFile,
        period: f64,
        head: ResultHead,
        solver_objective: Option<f64>,
        solution: GeneralSolution,
    ) -> Self {
        GeneralAnswer {
            head,
            problem: stored_problem(file),
            solver_objective,
            period,
            starts: None,
            solution,
            records: ResultRecords::default(),
            formulation: None,
            discrete_start: None,
            necessary_conditions: None,
        }
    }

    /// The global P_m optimum `solution` (method `discrete`, certificate `"global"`).
    pub fn discrete(file: &GeneralFile, period: f64, solution: GeneralPm) -> Self {
        let c = &solution.certificate;
        let head = ResultHead::new(
            ResultKind::General,
            "discrete",
            solution.objective,
            c.status,
            ResultCertificate::of_milp(c, None),
        );
        let j = Some(c.milp_objective);
        Self::with(file, period, head, j, GeneralSolution::Pm(solution))
    }

    /// The local P_m `solution` (method `local`, certificate `"local"`) from `starts`.
    pub fn local(
        file: &GeneralFile,
        period: f64,
        starts: LocalStarts,
        solution: GeneralLocal,
    ) -> Self {
        let head = ResultHead::new(
            ResultKind::General,
            "local",
            solution.objective,
            local_status(solution.stop),
            ResultCertificate::local(None),
        );
        let mut a = Self::with(file, period, head, None, GeneralSolution::Local(solution));
        a.starts = Some(starts);
        a
    }

    /// The phase gait `solution` (method `phase`, certificate `"global_k_phases"`).
    pub fn phase(file: &GeneralFile, period: f64, solution: GeneralPhaseGait) -> Self {
        let c = &solution.certificate;
        let head = ResultHead::new(
            ResultKind::General,
            "phase",
            solution.objective,
            c.status,
            ResultCertificate::of_milp(c, Some(solution.max_phases)),
        );
        let j = Some(c.milp_objective);
        Self::with(file, period, head, j, GeneralSolution::Phase(solution))
    }

    /// The answer's control as pieces `(durations, controls)`: a P_m answer's `2^m` equal steps,
    /// a phase gait's phases (how a result starts (P)'s local method, `--start`).
    pub fn pieces(&self) -> (Vec<f64>, &[Vec<f64>]) {
        let steps = |u: &[Vec<f64>]| vec![self.period / u.len().max(1) as f64; u.len()];
        match &self.solution {
            GeneralSolution::Pm(s) => (steps(&s.path.u), &s.path.u),
            GeneralSolution::Local(s) => (steps(&s.path.u), &s.path.u),
            GeneralSolution::Phase(s) => (s.durations.clone(), &s.controls),
        }
    }
}
