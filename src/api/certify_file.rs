//! `certify` of a result file of either kind ([`certify_result_file`]): which conditions apply
//! to which method is decided here, not in the front ends. A crawler's gait gets the crawler
//! certificate ([`crate::certify::certify_result`]: P_m gaits, global or local, and phase
//! gaits); a general problem's P_m process (methods `discrete` and `local`) the general one
//! ([`crate::certify::certify_general`]), the problem rebuilt from the file itself and checked
//! in full ([`super::general_problem`]); so does a general phase gait (`A = 0`; the general or
//! the chain formulation's), on its own phases.

use crate::certify::{
    certify_general, certify_result, CertifyOptions, GeneralNecessaryConditions,
    NecessaryConditions,
};
use crate::error::{Error, Result};
use crate::io::{GeneralAnswer, ResultFile};
use crate::present::{self, figures::Figure};
use serde::Serialize;

/// The necessary conditions of a result, of its kind.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Certified {
    /// Of a crawler's gait.
    Crawler(Box<NecessaryConditions>),
    /// Of a general problem's P_m process or phase gait.
    General(Box<GeneralNecessaryConditions>),
}

/// The necessary conditions of Theorem 2.2 (discrete form Theorems 6.1–6.2) on the process a
/// result file holds (module docs); `what` names the source in errors.
pub fn certify_result_file(r: &ResultFile, what: &str) -> Result<Certified> {
    match r {
        ResultFile::Crawler(r) => Ok(Certified::Crawler(Box::new(certify_result(
            &r.result, what,
        )?))),
        ResultFile::General(r) => Ok(Certified::General(Box::new(certify_general_answer(
            r, what,
        )?))),
    }
}

/// [`certify_result_file`] of a general answer: P_m processes (global or local) and phase gaits
/// are certified; a Cauchy problem is refused naming `problem.periodic` (the conditions are
/// stated for periodic problems).
pub fn certify_general_answer(r: &GeneralAnswer, what: &str) -> Result<GeneralNecessaryConditions> {
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

/// `r` with `cert`, its necessary conditions, as `optimize --certify` answers it (a result
/// read back holds none); an error when `cert` is of the other kind.
fn with_conditions(r: &ResultFile, cert: &Certified) -> Result<ResultFile> {
    let mut r = r.clone();
    match (&mut r, cert) {
        (ResultFile::Crawler(g), Certified::Crawler(c)) => {
            g.necessary_conditions = Some((**c).clone());
        }
        (ResultFile::General(a), Certified::General(c)) => {
            a.necessary_conditions = Some((**c).clone());
        }
        _ => {
            return Err(Error::Numerical(
                "the certificate is not of the result's kind".into(),
            ))
        }
    }
    Ok(r)
}

/// The figures of a certified result file (`crawlopt certify --plot`): the result's own
/// figures with the adjoint p(t) of its necessary conditions (a crawler's with p + omega and
/// u(t) beside it), as [`present::result_figures`] draws a certified result.
pub fn certified_figures(r: &ResultFile, cert: &Certified) -> Result<Vec<Figure>> {
    present::result_figures(&with_conditions(r, cert)?)
}
