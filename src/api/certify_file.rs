//! `certify` of a result file of either kind ([`certify_result_file`]): which conditions apply
//! to which method is decided here, not in the front ends. A crawler's gait gets the crawler
//! certificate ([`crate::certify::certify_result`]: P_m gaits, global or local, and phase
//! gaits); a general problem's P_m process (methods `discrete` and `local`) the general one
//! ([`crate::certify::certify_general`]), the problem rebuilt from the file itself and checked
//! in full ([`super::general_problem`]); so does a general phase gait (`A = 0`; the general or
//! the chain formulation's), on its own phases.

use crate::certify::{certify_general, certify_result, CertifyOptions, GeneralNecessaryConditions};
use crate::error::Result;
use crate::io::{GeneralAnswer, ResultFile};
use crate::present::{self, figures::Figure};
use serde::Serialize;

/// A result file certified ([`certify_result_file`]): the result holding its necessary
/// conditions, as `optimize --certify` answers it. Its text, figures and JSON are rendered
/// for both kinds here, so that no front end forks on the kind.
#[derive(Debug, Clone, PartialEq)]
pub struct Certified {
    /// The result, its `necessary_conditions` set.
    result: ResultFile,
}

impl Certified {
    /// The result with its necessary conditions.
    pub fn result(&self) -> &ResultFile {
        &self.result
    }

    /// The result with its necessary conditions, by value.
    pub fn into_result(self) -> ResultFile {
        self.result
    }

    /// The human form of the conditions (`crawlopt certify`): a crawler's certificate read in
    /// its gait's scales, a general one's ([`present::conditions_text`]).
    pub fn text(&self) -> String {
        present::conditions_text(&self.result).unwrap_or_default()
    }

    /// The figures (`crawlopt certify --plot`): the result's own with the adjoint p(t) (a
    /// crawler's with p + omega and u(t) beside it), as [`present::result_figures`] draws a
    /// certified result.
    pub fn figures(&self) -> Result<Vec<Figure>> {
        present::result_figures(&self.result)
    }
}

/// The conditions alone, the kind's own ([`crate::certify::NecessaryConditions`] or
/// [`GeneralNecessaryConditions`]): what `crawlopt certify --json` prints.
impl Serialize for Certified {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match &self.result {
            ResultFile::Crawler(g) => g.necessary_conditions.serialize(s),
            ResultFile::General(a) => a.necessary_conditions.serialize(s),
        }
    }
}

/// The necessary conditions of Theorem 2.2 (discrete form Theorems 6.1–6.2) on the process a
/// result file holds (module docs), attached to it; `what` names the source in errors.
pub fn certify_result_file(mut result: ResultFile, what: &str) -> Result<Certified> {
    match &mut result {
        ResultFile::Crawler(g) => {
            g.necessary_conditions = Some(certify_result(&g.result, what)?);
        }
        ResultFile::General(a) => {
            a.necessary_conditions = Some(certify_general_answer(a, what)?);
        }
    }
    Ok(Certified { result })
}

/// [`certify_result_file`] of a general answer: P_m processes (global or local) and phase gaits
/// are certified; a Cauchy problem is refused naming `problem.periodic` (the conditions are
/// stated for periodic problems).
fn certify_general_answer(r: &GeneralAnswer, what: &str) -> Result<GeneralNecessaryConditions> {
    let (p, _) = super::general_problem(&r.problem)?;
    let pr = r.solution.process(&p);
    // Checked first as the file's solution, so that a message names the file and its field.
    let at = format!("{what}: solution");
    pr.check_as(
        &p,
        crate::optimal::consistency::INPUT_TOL,
        &crate::optimal::process::FieldNames::record(&at),
    )?;
    certify_general(&p, &pr, &CertifyOptions::default())
}
