//! The one result of both kinds ([`ResultFile`]) rendered: its text, its figures, its report
//! and its summary line, each dispatched on the kind once, here, for every caller (`optimize`
//! on a problem file, and `certify`, `plot` and `report` of a result file); and what `plot`
//! draws ([`PlotInput`]: a result or a J_m table). Each kind draws its
//! necessary conditions when it holds them (a crawler's gait with the adjoint `p + omega` and
//! `u(t)`, a general process with its adjoint `p(t)`).

use super::general::general_answer_figures;
use super::general_report::{build_general_report, GeneralReportInput};
use super::report::{build_report_with, ReportContext};
use super::{adjoint_figure_of, figures, figures::Figure, gait_figures, text};
use super::{JmTable, JM_TABLE_FORMAT};
use crate::error::{Error, Result};
use crate::io::ResultFile;

/// The human form: the answer, and its necessary conditions when computed.
pub fn result_text(r: &ResultFile) -> String {
    let answer = match r {
        ResultFile::Crawler(g) => text::gait_result(&g.result),
        ResultFile::General(a) => text::general_answer(a),
    };
    answer + &conditions_text(r).unwrap_or_default()
}

/// A result's key numbers in one line, of either kind ([`text::gait_summary`]: J and the
/// displacement per period; [`text::general_summary`]: J).
pub fn result_summary(r: &ResultFile) -> String {
    match r {
        ResultFile::Crawler(g) => text::gait_summary(&g.result),
        ResultFile::General(a) => text::general_summary(a),
    }
}

/// The text of the necessary conditions a result holds (`crawlopt certify`): a crawler's
/// certificate read in its gait's scales, a general one's; `None` when it holds none.
pub fn conditions_text(r: &ResultFile) -> Option<String> {
    match r {
        ResultFile::Crawler(g) => g
            .necessary_conditions
            .as_ref()
            .map(|c| text::certificate(c, &g.result)),
        ResultFile::General(a) => a
            .necessary_conditions
            .as_ref()
            .map(text::general_certificate),
    }
}

/// The figures (`--plot`): a crawler's gait (and the adjoint when certified); a general
/// optimum's C with the orbit, states, controls, reactions and the objective's integrand (and
/// the adjoint when certified, and `J_m` against `m` with a convergence table), drawn with the
/// problem its envelope stores.
pub fn result_figures(r: &ResultFile) -> Result<Vec<Figure>> {
    match r {
        ResultFile::Crawler(g) => {
            let mut figs = gait_figures(&g.result)?;
            if let Some(c) = &g.necessary_conditions {
                figs.push(adjoint_figure_of(&c.multipliers)?);
            }
            Ok(figs)
        }
        ResultFile::General(a) => general_answer_figures(&a.problem.problem()?, a),
    }
}

/// The self-contained HTML report: a crawler's gait report or a general problem's, drawn with
/// the problem its envelope stores; `source` names the input in the page and `command` the
/// command that made it.
pub fn result_report(r: &ResultFile, source: &str, command: &str) -> Result<String> {
    match r {
        ResultFile::Crawler(g) => {
            let ctx = ReportContext {
                source,
                command: command.to_string(),
                certificate: g.necessary_conditions.as_ref(),
            };
            build_report_with(&g.result, &ctx)
        }
        ResultFile::General(a) => build_general_report(
            &a.problem.problem()?,
            GeneralReportInput::Answer(a),
            source,
            command,
        ),
    }
}

/// The report of a result file as `crawlopt report RESULT.json` makes it ([`result_report`],
/// `source` naming the file).
pub fn build_result_report(r: &ResultFile, source: &str) -> Result<String> {
    result_report(r, source, &ReportContext::report_command(source).command)
}

/// What `crawlopt plot` can draw.
#[derive(Debug, Clone)]
pub enum PlotInput {
    /// A result of either kind (`crawlopt optimize --json`), drawn as [`result_figures`] draws
    /// it.
    Result(Box<ResultFile>),
    /// A J_m table.
    Jm(JmTable),
}

impl PlotInput {
    /// Reads a gait result or a J_m table from JSON text, telling them apart by `format`;
    /// truncated files, other formats and other versions are errors naming `what`.
    pub fn from_json(text: &str, what: &str) -> Result<Self> {
        let format = serde_json::from_str::<serde_json::Value>(text)
            .ok()
            .and_then(|v| v.get("format").and_then(|f| f.as_str()).map(String::from));
        if format.as_deref() == Some(JM_TABLE_FORMAT) {
            let t: JmTable = serde_json::from_str(text).map_err(|e| Error::Io {
                path: what.into(),
                reason: format!("malformed J_m table: {e}"),
            })?;
            if t.version != 1 {
                return Err(Error::invalid(
                    format!("{what}: version"),
                    t.version,
                    "this build reads J_m tables of version 1 only",
                ));
            }
            return Ok(PlotInput::Jm(t));
        }
        // Everything else must be a result of either kind, read back and checked as `certify`
        // reads it; its reader explains what is wrong.
        let r = ResultFile::from_json(text, what)?;
        Ok(PlotInput::Result(Box::new(r)))
    }

    /// Its figures.
    pub fn figures(&self) -> Result<Vec<Figure>> {
        match self {
            PlotInput::Result(r) => result_figures(r),
            PlotInput::Jm(t) => Ok(vec![figures::jm_figure(&t.m, &t.values, t.continuous)?]),
        }
    }
}
