//! `analyze` and `simulate` of a problem file of either kind, a crawler's model file or a
//! general problem (P) (`[sweeping_process]`), dispatched here once so that no front end forks
//! on the kind of file: [`analyze_file`] and [`simulate_file`] return one answer type each,
//! whose methods give its text, its figures, its trajectory file and its verdict, rendered by
//! [`crate::present`] for its kind.

use super::{analyze, analyze_general, general_sim_options, simulate, Hooks};
use super::{GeneralAnalysis, GeneralSimulated, ModelAnalysis};
use crate::error::Result;
use crate::integrate::{Actuation, SimOptions, Simulation};
use crate::io::{write_general_csv, write_trajectory_csv, ProblemFile, SimulationDocument};
use crate::model::general::GeneralProblem;
use crate::model::Crawler;
use crate::present::{self, figures::Figure, text};
use serde::Serialize;
use std::path::Path;

/// What [`analyze_file`] finds, of the file's kind (its JSON is the kind's own).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Analyzed {
    /// A crawler's model file ([`analyze`]).
    Crawler(Box<ModelAnalysis>),
    /// A general problem file ([`analyze_general`]).
    General(Box<GeneralAnalysis>),
}

/// The analysis of a problem file of either kind (module docs). A crawler that fails the
/// uniqueness condition, or a general problem that fails a check, is still analysed: the
/// failure is [`Analyzed::verdict`]'s.
pub fn analyze_file(file: &ProblemFile) -> Result<Analyzed> {
    Ok(match file {
        ProblemFile::Crawler(model) => Analyzed::Crawler(Box::new(analyze(model)?)),
        ProblemFile::General(general) => Analyzed::General(Box::new(analyze_general(general)?)),
    })
}

impl Analyzed {
    /// The human form.
    pub fn text(&self) -> String {
        match self {
            Analyzed::Crawler(a) => {
                let mut out = text::analysis(&a.crawler, &a.analysis);
                if let Some(g) = &a.gait {
                    let optimum = g.one_link_optimum.as_ref();
                    out.push_str(&text::gait_problem(&a.crawler, &g.problem, optimum));
                }
                out
            }
            Analyzed::General(a) => text::general_analysis(a),
        }
    }

    /// The figures (`--plot`): a crawler's C (and v_m for two links), a general problem's C
    /// (projected onto pairs of components beyond two).
    pub fn figures(&self) -> Result<Vec<Figure>> {
        match self {
            Analyzed::Crawler(a) => present::analysis_figures(&a.crawler),
            Analyzed::General(a) => present::general_analysis_figures(a),
        }
    }

    /// The analysis's verdict: the uniqueness condition of a crawler (paper eq. 3.6), the first
    /// failed check of a general problem.
    pub fn verdict(&self) -> Result<()> {
        match self {
            Analyzed::Crawler(a) => a.crawler.require_unique(),
            Analyzed::General(a) => a.failure.clone().map_or(Ok(()), Err),
        }
    }
}

/// What [`simulate_file`] played, of the file's kind (its JSON is [`Simulated::document`]: the
/// envelope of every simulation, then the kind's fields).
#[derive(Debug, Clone, PartialEq)]
pub enum Simulated {
    /// A crawler's actuation ([`simulate`]).
    Crawler {
        /// The crawler.
        crawler: Box<Crawler>,
        /// The actuation played.
        actuation: Box<Actuation>,
        /// The simulation.
        simulation: Box<Simulation>,
    },
    /// A general problem's `[input]` ([`simulate_general`](super::simulate_general)).
    General {
        /// The problem.
        problem: Box<GeneralProblem>,
        /// The simulation.
        answer: Box<GeneralSimulated>,
    },
}

impl Simulated {
    /// The simulation's document: one envelope over the kind's fields
    /// ([`SimulationDocument`]).
    pub fn document(&self) -> SimulationDocument<'_> {
        match self {
            Simulated::Crawler { simulation, .. } => SimulationDocument::crawler(simulation),
            Simulated::General { answer, .. } => SimulationDocument::general(answer),
        }
    }
}

impl Serialize for Simulated {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.document().serialize(s)
    }
}

/// The periodic regime of a problem file's actuation or input (module docs) under `opts`,
/// the options of either kind: a crawler's model file plays its `[actuation]` from its
/// `[simulation]` initial state when it has one ([`simulate`], with `hooks`); a general file
/// plays its `[input]` with the options that apply to it ([`general_sim_options`] refuses the
/// others, naming them).
pub fn simulate_file(file: &ProblemFile, opts: &SimOptions, hooks: Hooks<'_>) -> Result<Simulated> {
    match file {
        ProblemFile::Crawler(model) => {
            let crawler = model.crawler()?;
            crawler.require_unique()?;
            let actuation = model.actuation(crawler.links())?;
            let opts = SimOptions {
                initial_state: model.simulation.initial_state.clone(),
                ..opts.clone()
            };
            let simulation = simulate(&crawler, &actuation, &opts, hooks)?;
            Ok(Simulated::Crawler {
                crawler: Box::new(crawler),
                actuation: Box::new(actuation),
                simulation: Box::new(simulation),
            })
        }
        ProblemFile::General(general) => {
            let (problem, answer) =
                super::general::simulate_general_problem(general, &general_sim_options(opts)?)?;
            Ok(Simulated::General {
                problem: Box::new(problem),
                answer: Box::new(answer),
            })
        }
    }
}

impl Simulated {
    /// Whether the periodic regime was reached (a Cauchy problem's horizon always is).
    pub fn converged(&self) -> bool {
        match self {
            Simulated::Crawler { simulation, .. } => simulation.converged,
            Simulated::General { answer, .. } => answer.simulation.converged,
        }
    }

    /// The figures of the recorded regime (`--plot`; a crawler's over `periods` periods, at
    /// least 3), once the regime is reached.
    pub fn figures(&self, periods: usize) -> Result<Vec<Figure>> {
        match self {
            Simulated::Crawler {
                crawler,
                actuation,
                simulation,
            } => present::simulation_figures(crawler, actuation, simulation, periods.max(3)),
            Simulated::General { problem, answer } => {
                present::general_simulation_figures(problem, answer)
            }
        }
    }

    /// Writes the recorded trajectory as CSV (atomically) when the regime was reached and a
    /// trajectory was recorded; whether it was written.
    pub fn write_csv(&self, path: &Path) -> Result<bool> {
        if !self.converged() {
            return Ok(false);
        }
        match self {
            Simulated::Crawler { simulation, .. } => match &simulation.trajectory {
                Some(traj) => write_trajectory_csv(path, traj).map(|()| true),
                None => Ok(false),
            },
            Simulated::General { answer, .. } => {
                write_general_csv(path, &answer.simulation).map(|()| true)
            }
        }
    }

    /// The human form; `csv` the trajectory file written.
    pub fn text(&self, csv: Option<&Path>) -> String {
        match self {
            Simulated::Crawler {
                crawler,
                actuation,
                simulation,
            } => text::simulation(simulation, crawler, actuation, csv),
            Simulated::General { answer, .. } => {
                let mut out = text::general_simulation(answer);
                if let Some(path) = csv {
                    out.push_str(&format!("trajectory written to {}\n", path.display()));
                }
                out
            }
        }
    }

    /// Without the periodic regime, what was not found (the front ends' error line, before
    /// what they did not write and how to go on).
    pub fn not_converged(&self) -> Option<String> {
        if self.converged() {
            return None;
        }
        Some(match self {
            Simulated::Crawler { simulation, .. } => format!(
                "the periodic regime was not reached within {} periods (residual {:.3e}); \
                 displacement_per_period is not reported",
                simulation.periods_simulated, simulation.period_residual
            ),
            Simulated::General { answer, .. } => format!(
                "the periodic regime was not reached within {} periods; J is not reported",
                answer.simulation.periods
            ),
        })
    }
}
