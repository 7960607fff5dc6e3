//! What the jobs on a general problem (P) return (theory §11): the records that
//! [`crate::api`] builds, text output renders ([`crate::present::text`]) and `--json` writes.
//! They sit here, below presentation and the API, so that both can name them.

use crate::error::Error;
use crate::integrate::{ControlInput, GeneralSimulation};
use crate::model::general::GeneralProblem;
use crate::optimal::general::{GeneralLocal, GeneralPhaseGait, Geometry};
use serde::Serialize;

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
    /// The control played.
    pub input: ControlInput,
    /// The simulation.
    pub simulation: GeneralSimulation,
}

/// [`crate::api::optimize_general`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralOptimized {
    /// `"general"`.
    pub kind: &'static str,
    /// `"discrete"`: the paper's P_m, globally.
    pub method: &'static str,
    /// The period.
    pub period: f64,
    /// The verified optimum of P_m with its certificate.
    pub solution: crate::optimal::general::GeneralPm,
    /// The necessary conditions on it, when asked ([`crate::api::GeneralPmSettings::certify`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub necessary_conditions: Option<crate::certify::GeneralNecessaryConditions>,
}

/// [`crate::api::optimize_general_local`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralLocalOptimized {
    /// `"general"`.
    pub kind: &'static str,
    /// `"local"`: the paper's P_m by the active-set method on its LPCC (no global claim).
    pub method: &'static str,
    /// The period.
    pub period: f64,
    /// Where the starts came from: `"input"` (the file's `[input]`) or `"square_waves"`.
    pub start_from: &'static str,
    /// Starts solved from (all of them unless the time limit ended the search).
    pub starts_tried: usize,
    /// Which of them gave the answer (0-based, the first of equals).
    pub best_start: usize,
    /// The best local solution, re-verified by simulation.
    pub solution: GeneralLocal,
}

/// [`crate::api::optimize_general_phase`]'s answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralPhaseOptimized {
    /// `"general"`.
    pub kind: &'static str,
    /// `"phase"`: exact gaits of at most `K` phases, globally.
    pub method: &'static str,
    /// The period.
    pub period: f64,
    /// The verified optimum with its certificate.
    pub solution: GeneralPhaseGait,
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
