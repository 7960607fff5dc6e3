//! The shape a crawler's result is written in (result version 4), the one envelope both kinds
//! share: `format`, `version`, `kind`, `method`, `objective`, `status`, `certificate`, then
//! `problem` (the file's own sections: a crawler's `{crawler, gait}` as (P)'s is its
//! `sweeping_process`, `dynamics`, ...), `solver_objective`, `solution` (the gait with its own
//! numbers: `m` on a grid, `displacement_per_period`, `actuation_cost`, and the records of how
//! it was reached, `local` and `polish`, as (P)'s solution keeps its `m`, local counts and
//! `polish`), the records beside it (`phase_growth`, `convergence`, `structured`) and
//! `discrete_start`. Each number is written once (versions 1 to 3 wrote the displacement
//! twice, as `displacement_per_period` and `verified_displacement`; they are read through
//! [`super::envelope::read_envelope`], which moves their fields to these places).
//!
//! [`GaitResult`] keeps its fields for the library's callers; this module is the map between
//! them and the written shape, both ways.

use super::polish::PolishRecord;
use super::records::ResultRecords;
use super::result::{CrawlerParams, GaitData, GaitResult, LocalRecord, StartRecord};
use super::GaitProblem;
use crate::optimal::envelope::ResultHead;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A crawler result's `problem`: the crawler and its gait problem, under the names of the
/// model file's sections (`[crawler]`, `[gait]`).
#[derive(Serialize)]
struct ProblemOut<'a> {
    crawler: &'a CrawlerParams,
    gait: &'a GaitProblem,
}

/// A crawler result's `solution`: the gait's own numbers, then its arrays, then how it was
/// reached.
#[derive(Serialize)]
struct SolutionOut<'a> {
    #[serde(skip_serializing_if = "Option::is_none")]
    m: Option<u32>,
    displacement_per_period: f64,
    actuation_cost: f64,
    #[serde(flatten)]
    gait: &'a GaitData,
    #[serde(skip_serializing_if = "Option::is_none")]
    local: Option<&'a LocalRecord>,
    #[serde(skip_serializing_if = "Option::is_none")]
    polish: Option<&'a PolishRecord>,
}

/// The whole document, as written.
#[derive(Serialize)]
struct ResultOut<'a> {
    #[serde(flatten)]
    head: &'a ResultHead,
    problem: ProblemOut<'a>,
    solver_objective: f64,
    solution: SolutionOut<'a>,
    #[serde(flatten)]
    records: &'a ResultRecords,
    #[serde(skip_serializing_if = "Option::is_none")]
    discrete_start: Option<&'a StartRecord>,
}

impl Serialize for GaitResult {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        ResultOut {
            head: &self.head,
            problem: ProblemOut {
                crawler: &self.crawler,
                gait: &self.problem,
            },
            solver_objective: self.solver_objective,
            solution: SolutionOut {
                m: self.m,
                displacement_per_period: self.displacement_per_period,
                actuation_cost: self.actuation_cost,
                gait: &self.gait,
                local: self.local.as_ref(),
                polish: self.polish.as_ref(),
            },
            records: &self.records,
            discrete_start: self.discrete_start.as_ref(),
        }
        .serialize(s)
    }
}

/// [`ProblemOut`], read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ProblemIn {
    crawler: CrawlerParams,
    gait: GaitProblem,
}

/// [`SolutionOut`], read: [`GaitData`]'s fields named one by one, so that an unknown or
/// misspelt key (`polsh`) is refused, not dropped.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SolutionIn {
    #[serde(default)]
    m: Option<u32>,
    displacement_per_period: f64,
    actuation_cost: f64,
    times: Vec<f64>,
    durations: Vec<f64>,
    lengths: Vec<Vec<f64>>,
    controls: Vec<Vec<f64>>,
    states: Vec<Vec<f64>>,
    block_displacements: Vec<Vec<f64>>,
    slip: Vec<Vec<i8>>,
    initial_state: Vec<f64>,
    #[serde(default)]
    local: Option<LocalRecord>,
    #[serde(default)]
    polish: Option<PolishRecord>,
}

/// [`ResultOut`], read.
#[derive(Deserialize)]
struct ResultIn {
    #[serde(flatten)]
    head: ResultHead,
    problem: ProblemIn,
    solver_objective: f64,
    solution: SolutionIn,
    #[serde(flatten)]
    records: ResultRecords,
    #[serde(default)]
    discrete_start: Option<StartRecord>,
}

impl<'de> Deserialize<'de> for GaitResult {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let r = ResultIn::deserialize(d)?;
        let s = r.solution;
        Ok(GaitResult {
            head: r.head,
            crawler: r.problem.crawler,
            problem: r.problem.gait,
            m: s.m,
            displacement_per_period: s.displacement_per_period,
            actuation_cost: s.actuation_cost,
            solver_objective: r.solver_objective,
            gait: GaitData {
                times: s.times,
                durations: s.durations,
                lengths: s.lengths,
                controls: s.controls,
                states: s.states,
                block_displacements: s.block_displacements,
                slip: s.slip,
                initial_state: s.initial_state,
            },
            records: r.records,
            local: s.local,
            discrete_start: r.discrete_start,
            polish: s.polish,
        })
    }
}
