//! `optimize` and `report` of a problem file of either kind, a crawler's model file or a
//! general problem (P) (`[sweeping_process]`), dispatched here once so that no front end forks
//! on the kind of file: [`optimize_file`] takes the one [`OptimizeSettings`] of both kinds
//! (the library decides which settings apply to which kind and refuses the others, naming
//! them) and returns one answer type, [`OptimizedFile`], whose methods give its text, its
//! figures, its report, its summary line and its JSON (the kind's own), rendered by
//! [`crate::present`]. [`OptimizeJob`] is the same call in two steps, for a front end that
//! checks its own output paths after the input and before the work.

use super::events::Hooks;
use super::gait_problem;
use super::general_plan::{optimize_general_plan, GeneralPlan};
use super::optimize::optimize;
use super::settings::{GaitMethod, Naming, OptimizeSettings};
use crate::error::{Error, Result};
use crate::io::{ProblemFile, ResultFile};
use crate::model::Crawler;
use crate::optimal::GaitProblem;
use crate::present::{self, figures::Figure, text};
use serde::Serialize;

/// What [`optimize_file`] found: the one result of both kinds, [`ResultFile`] (as a result file
/// reads back, with the necessary conditions when computed), and the job's notes.
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizedFile {
    /// The result: a crawler's gait ([`optimize`]) or a general problem's optimum
    /// ([`OptimizeSettings::plan_general`], run).
    pub result: ResultFile,
    /// Notes on how the job went (the job's [`super::Event::Note`]s: such as a start refused
    /// and the one tried instead).
    pub notes: Vec<String>,
}

/// An optimisation of a problem file checked before its work ([`OptimizeJob::new`]): a front
/// end checks its output paths between [`OptimizeJob::new`] and [`OptimizeJob::run`], so that
/// every refusal of the input comes first and no work is done for an output it cannot write.
#[derive(Debug)]
pub struct OptimizeJob<'a> {
    file: &'a ProblemFile,
    settings: &'a OptimizeSettings,
    checked: Checked,
}

/// What [`OptimizeJob::new`] checked and built.
#[derive(Debug)]
enum Checked {
    Crawler {
        crawler: Box<Crawler>,
        problem: Box<GaitProblem>,
    },
    General {
        /// The size of C, the problem checked well posed.
        scale: f64,
        plan: Box<GeneralPlan>,
    },
}

impl<'a> OptimizeJob<'a> {
    /// Checks the problem file and the settings for it, in this order: a crawler's file must
    /// pose a `[gait]` problem whose crawler meets the uniqueness condition (paper eq. 3.6); a
    /// general file's settings must apply to it ([`OptimizeSettings::plan_general`], the first
    /// one that does not is named) and its problem must be well posed.
    pub fn new(file: &'a ProblemFile, settings: &'a OptimizeSettings) -> Result<Self> {
        let checked = match file {
            ProblemFile::Crawler(model) => {
                let (crawler, problem) = gait_problem(model)?;
                Checked::Crawler {
                    crawler: Box::new(crawler),
                    problem: Box::new(problem),
                }
            }
            ProblemFile::General(general) => {
                let plan = settings.plan_general(&[])?;
                Checked::General {
                    scale: general.problem()?.c.scale(),
                    plan: Box::new(plan),
                }
            }
        };
        Ok(OptimizeJob {
            file,
            settings,
            checked,
        })
    }

    /// The length in which the job's progress is shown: a crawler's gait scales, the size of a
    /// general problem's C.
    pub fn progress_length(&self) -> f64 {
        match &self.checked {
            Checked::Crawler { crawler, problem } => {
                text::GaitScales::of_problem(crawler, problem).length
            }
            Checked::General { scale, .. } => *scale,
        }
    }

    /// Runs the job with `hooks`: every answer is re-verified by simulation before it is
    /// returned, as each kind's job does.
    pub fn run(self, hooks: Hooks<'_>) -> Result<OptimizedFile> {
        match (self.checked, self.file) {
            (Checked::Crawler { crawler, problem }, _) => {
                let (answer, notes) = optimize(&crawler, &problem, self.settings, hooks)?.answer();
                Ok(OptimizedFile {
                    result: ResultFile::Crawler(Box::new(answer)),
                    notes,
                })
            }
            (Checked::General { plan, .. }, ProblemFile::General(general)) => {
                // The job's notes kept for the answer, every event passed on to the caller.
                let Hooks { mut events, cancel } = hooks;
                let mut notes = Vec::new();
                let mut keep = |e: &super::Event, t: f64| {
                    if let super::Event::Note(n) = e {
                        notes.push(n.clone());
                    }
                    if let Some(f) = events.as_mut() {
                        f(e, t);
                    }
                };
                let hooks = Hooks {
                    events: Some(&mut keep),
                    cancel,
                };
                let answer = optimize_general_plan(general, &plan, self.settings.naming, hooks)?;
                Ok(OptimizedFile {
                    result: ResultFile::General(Box::new(answer)),
                    notes,
                })
            }
            (Checked::General { .. }, ProblemFile::Crawler(_)) => {
                unreachable!("a general plan is made of a general file only")
            }
        }
    }
}

/// The optimum of a problem file of either kind under `settings` (module docs):
/// [`OptimizeJob::new`] then [`OptimizeJob::run`].
pub fn optimize_file(
    file: &ProblemFile,
    settings: &OptimizeSettings,
    hooks: Hooks<'_>,
) -> Result<OptimizedFile> {
    OptimizeJob::new(file, settings)?.run(hooks)
}

/// Settings of a report job ([`report_file`], [`report_result`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ReportSettings {
    /// A crawler's optimum with at most this many slip phases (default `None`: `K` grown, as
    /// `optimize`'s phase method grows it); a problem file's setting only.
    pub phases: Option<usize>,
    /// Seconds for computing the optimum (default `None`: no limit); a problem file's setting
    /// only.
    pub time_limit: Option<f64>,
    /// How errors spell the settings (default [`Naming::Keywords`]).
    pub naming: Naming,
}

/// The report of a result file of either kind (`crawlopt report RESULT.json`): `text` read back
/// and checked as `certify` reads it (`name` labels its errors), then its HTML page. The
/// settings that compute a gait (`phases`, `time_limit`) are refused when given, not ignored:
/// a result's gait is computed already. Errors name them as `naming` spells them.
pub fn report_result(
    text: &str,
    name: &str,
    s: &ReportSettings,
) -> Result<(crate::io::ResultFile, String)> {
    let naming = s.naming;
    let given = [
        ("phases", s.phases.map(|k| k.to_string())),
        ("time_limit", s.time_limit.map(|t| t.to_string())),
    ];
    if let Some((setting, Some(v))) = given.into_iter().find(|(_, v)| v.is_some()) {
        return Err(Error::invalid(
            naming.setting(setting),
            v,
            "applies to a problem file only (a result file's gait is computed already)",
        ));
    }
    let r = crate::io::ResultFile::from_json(text, name)?;
    let html = present::build_result_report(&r, name)?;
    Ok((r, html))
}

/// The optimum a report of a problem file shows (`crawlopt report FILE.toml`): a crawler's by
/// the phase method with at most `phases` slip phases (K grown when `None`), a general
/// problem's by `optimize`'s default method; `time_limit` applies to both. Errors name the
/// settings as `naming` spells them.
pub fn report_file(
    file: &ProblemFile,
    s: &ReportSettings,
    hooks: Hooks<'_>,
) -> Result<OptimizedFile> {
    let ReportSettings {
        phases,
        time_limit,
        naming,
    } = *s;
    let method = match file {
        ProblemFile::Crawler(_) => GaitMethod::Phase,
        ProblemFile::General(_) => GaitMethod::Auto,
    };
    if let (ProblemFile::General(_), Some(k)) = (file, phases) {
        return Err(Error::invalid(
            naming.setting("phases"),
            k,
            "applies to a crawler's model file only: the report of a general problem shows \
             the optimum of optimize's default method (P_m)",
        ));
    }
    let settings = OptimizeSettings {
        method,
        phases,
        time_limit,
        naming,
        ..OptimizeSettings::default()
    };
    optimize_file(file, &settings, hooks).map_err(|e| match e {
        Error::InvalidParameter {
            field,
            value,
            reason,
        } if field == "gait" => Error::InvalidParameter {
            field,
            value,
            reason: format!("{reason} (a report shows an optimal gait)"),
        },
        other => other,
    })
}

impl OptimizedFile {
    /// The answer's key numbers in one line: J (and a crawler's displacement per period).
    pub fn summary(&self) -> String {
        present::result_summary(&self.result)
    }

    /// The objective J of the answer (verified by simulation).
    pub fn objective(&self) -> f64 {
        self.result.head().objective
    }

    /// Notes on how the job went.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The human form: the answer, and its necessary conditions when computed.
    pub fn text(&self) -> String {
        present::result_text(&self.result)
    }

    /// The figures (`--plot`, [`present::result_figures`]): a crawler's gait (and the adjoint
    /// when certified); a general optimum's C with the orbit, states, controls, reactions and
    /// the objective's integrand (and the adjoint when certified).
    pub fn figures(&self) -> Result<Vec<Figure>> {
        present::result_figures(&self.result)
    }

    /// The self-contained HTML report; `source` names the input in the page and `command` the
    /// command that made it.
    pub fn report_html(&self, source: &str, command: &str) -> Result<String> {
        present::result_report(&self.result, source, command)
    }
}

/// The kind's own JSON ([`ResultFile`]'s): a crawler's result with its keys in alphabetical
/// order (as `optimize --json` has always printed it), a general answer as its envelope.
impl Serialize for OptimizedFile {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.result.serialize(s)
    }
}
