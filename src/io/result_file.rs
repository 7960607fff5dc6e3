//! A result file of either kind read back: the one entry point of every reader that takes
//! both (`crawlopt certify`, Python's `read_result`). The envelope is checked first
//! ([`read_envelope`]: format, version, kind), then the kind's shape and consistency: a
//! crawler's by [`GaitResult`]'s reader, a general problem's by [`GeneralAnswer`]'s
//! ([`GeneralAnswer::check_consistent`]). Errors name the source and the field.

use super::{GeneralAnswer, GeneralLocalOptimized, GeneralOptimized, GeneralPhaseOptimized};
use crate::error::{Error, Result};
use crate::optimal::{read_envelope, GaitResult, MilpStatus, ResultCertificate, ResultKind};

/// A result of either kind ([`ResultFile::from_json`]).
#[derive(Debug, Clone, PartialEq)]
pub enum ResultFile {
    /// A crawler's gait result.
    Crawler(Box<GaitResult>),
    /// A general problem's result.
    General(Box<GeneralAnswer>),
}

impl ResultFile {
    /// Reads a result of either kind from JSON text (`what` names the source in errors): the
    /// envelope, then the kind's shape and consistency (module docs).
    pub fn from_json(text: &str, what: &str) -> Result<Self> {
        let (v, kind, label) = read_envelope(text, what)?;
        let what = label.as_str();
        match kind {
            ResultKind::Crawler => {
                GaitResult::from_checked_envelope(v, what).map(|r| ResultFile::Crawler(Box::new(r)))
            }
            ResultKind::General => {
                let r = GeneralAnswer::from_checked_envelope(v, what)?;
                r.check_consistent(what)?;
                Ok(ResultFile::General(Box::new(r)))
            }
        }
    }

    /// Which kind of problem it is of.
    pub fn kind(&self) -> ResultKind {
        match self {
            ResultFile::Crawler(_) => ResultKind::Crawler,
            ResultFile::General(_) => ResultKind::General,
        }
    }

    /// The method's name.
    pub fn method(&self) -> &str {
        match self {
            ResultFile::Crawler(r) => &r.method,
            ResultFile::General(r) => r.method(),
        }
    }

    /// `J`, re-verified.
    pub fn objective(&self) -> f64 {
        match self {
            ResultFile::Crawler(r) => r.objective,
            ResultFile::General(r) => r.objective(),
        }
    }

    /// What was proven.
    pub fn status(&self) -> MilpStatus {
        match self {
            ResultFile::Crawler(r) => r.status,
            ResultFile::General(r) => r.status(),
        }
    }

    /// The certificate.
    pub fn certificate(&self) -> &ResultCertificate {
        match self {
            ResultFile::Crawler(r) => &r.certificate,
            ResultFile::General(r) => r.certificate(),
        }
    }
}

impl GeneralAnswer {
    /// Reads a general problem's result from JSON text, checked as [`ResultFile::from_json`]
    /// checks it; a crawler's result is refused naming `kind`.
    pub fn from_json(text: &str, what: &str) -> Result<Self> {
        match ResultFile::from_json(text, what)? {
            ResultFile::General(r) => Ok(*r),
            ResultFile::Crawler(_) => Err(Error::invalid(
                format!("{what}: kind"),
                "crawler",
                "is a crawler's gait result, not a general problem's",
            )),
        }
    }

    /// The answer of a document whose envelope [`read_envelope`] has checked (kind general),
    /// told apart by its `method`; its shape checked (not yet its consistency).
    pub fn from_checked_envelope(v: serde_json::Value, what: &str) -> Result<Self> {
        fn parse<T: serde::de::DeserializeOwned>(v: serde_json::Value, what: &str) -> Result<T> {
            serde_json::from_value(v).map_err(|e| Error::Io {
                path: what.into(),
                reason: format!("malformed general result: {e}"),
            })
        }
        let method = v.get("method").and_then(|m| m.as_str()).map(String::from);
        Ok(match method.as_deref() {
            Some("discrete") => {
                GeneralAnswer::Discrete(Box::new(parse::<GeneralOptimized>(v, what)?))
            }
            Some("local") => {
                GeneralAnswer::Local(Box::new(parse::<GeneralLocalOptimized>(v, what)?))
            }
            // Exact gaits: of the phase MILPs, or of the crawler's local methods on a chain.
            Some("phase" | "sequence" | "chain") => {
                GeneralAnswer::Phase(Box::new(parse::<GeneralPhaseOptimized>(v, what)?))
            }
            other => {
                return Err(Error::invalid(
                    format!("{what}: method"),
                    other.unwrap_or("nothing"),
                    "a general result's method is \"discrete\", \"local\", \"phase\", \
                     \"sequence\" or \"chain\"",
                ))
            }
        })
    }
}
