//! The one result of both kinds ([`ResultFile`]) rendered: its text, its figures, its report
//! and its summary line, each dispatched on the kind once, here, for every caller (`optimize`
//! on a problem file, and `certify`, `plot` and `report` of a result file). Each kind draws its
//! necessary conditions when it holds them (a crawler's gait with the adjoint `p + omega` and
//! `u(t)`, a general process with its adjoint `p(t)`).

use super::general::general_answer_figures;
use super::general_report::{build_general_report, GeneralReportInput};
use super::report::{build_report_with, ReportContext};
use super::{adjoint_figure_of, figures::Figure, gait_figures, text};
use crate::error::Result;
use crate::io::ResultFile;

/// The human form: the answer, and its necessary conditions when computed.
pub fn result_text(r: &ResultFile) -> String {
    match r {
        ResultFile::Crawler(g) => {
            let mut out = text::gait_result(&g.result);
            if let Some(c) = &g.necessary_conditions {
                out.push_str(&text::certificate(c, &g.result));
            }
            out
        }
        ResultFile::General(a) => text::general_answer(a),
    }
}

/// The figures (`--plot`): a crawler's gait (and the adjoint when certified); a general
/// optimum's C with the orbit, states, controls, reactions and the objective's integrand (and
/// the adjoint when certified), drawn with the problem its envelope stores.
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
    result_report(r, source, &format!("crawlopt report {source}"))
}
