//! The envelope every optimisation result carries, whichever the kind of problem (a crawler or
//! a general problem (P), theory §11) and the method: `format`, `version` and `kind` at the top
//! level, read here before the rest so that a reader of one kind names what is wrong with a
//! file of the other (or of neither) instead of failing on a missing field. The crawler's
//! reader ([`GaitResult::from_json`](super::GaitResult::from_json)) and the reader of either
//! kind (`crate::io::ResultFile`) both start here.

use crate::error::{Error, Result};
use crate::optimal::{LocalStop, MilpStatus};
use serde::{Deserialize, Serialize};

/// Value of the `format` field of every result (both kinds).
pub const RESULT_FORMAT: &str = "crawlopt-gait-result";
/// Version of the result format written by this build; others are refused on reading.
pub const RESULT_VERSION: u32 = 1;

/// Which kind of problem a result is of (its `kind` field; a crawler result written before the
/// field existed has none and is read as a crawler's).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResultKind {
    /// A crawler's gait ([`GaitResult`](super::GaitResult)).
    #[default]
    Crawler,
    /// A general problem's optimum (`crate::io::GeneralAnswer`).
    General,
}

impl ResultKind {
    /// The word of the `kind` field.
    pub fn as_str(self) -> &'static str {
        match self {
            ResultKind::Crawler => "crawler",
            ResultKind::General => "general",
        }
    }
}

/// The status of a local method's stop, as every result states it (crawler and general):
/// stationary, the time limit, or stalled (its round limit included).
pub fn local_status(stop: LocalStop) -> MilpStatus {
    match stop {
        LocalStop::Stationary => MilpStatus::Stationary,
        LocalStop::TimeLimit => MilpStatus::TimeLimit,
        LocalStop::Stalled | LocalStop::RoundLimit => MilpStatus::Stalled,
    }
}

/// Parses a result document and checks its envelope: `format` ([`RESULT_FORMAT`]), `version`
/// ([`RESULT_VERSION`]) and `kind` (absent: a crawler's). Returns the document and its kind;
/// errors name `what` and the field.
pub fn read_envelope(text: &str, what: &str) -> Result<(serde_json::Value, ResultKind)> {
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| Error::Io {
        path: what.into(),
        reason: format!("not a complete JSON document: {e}"),
    })?;
    match v.get("format").and_then(|f| f.as_str()) {
        Some(RESULT_FORMAT) => {}
        Some(other) => {
            return Err(Error::invalid(
                format!("{what}: format"),
                other,
                format!("is not a crawlopt gait result ({RESULT_FORMAT})"),
            ))
        }
        None => {
            return Err(Error::invalid(
                format!("{what}: format"),
                "nothing",
                format!("is missing: not a crawlopt gait result ({RESULT_FORMAT})"),
            ))
        }
    }
    match v.get("version") {
        Some(x) if x.as_u64() == Some(u64::from(RESULT_VERSION)) => {}
        found => {
            return Err(Error::invalid(
                format!("{what}: version"),
                described(found),
                format!("this build reads version {RESULT_VERSION} only"),
            ));
        }
    }
    let kind = match v.get("kind") {
        None => ResultKind::Crawler,
        Some(serde_json::Value::String(s)) if s == "crawler" => ResultKind::Crawler,
        Some(serde_json::Value::String(s)) if s == "general" => ResultKind::General,
        found => {
            return Err(Error::invalid(
                format!("{what}: kind"),
                described(found),
                "must be \"crawler\" or \"general\"",
            ))
        }
    };
    Ok((v, kind))
}

/// What was found in a field, for a message: `"1"` is a string, not the number 1.
fn described(found: Option<&serde_json::Value>) -> String {
    match found {
        None => "nothing".to_string(),
        Some(x @ (serde_json::Value::Number(_) | serde_json::Value::Null)) => x.to_string(),
        Some(x) => {
            let kind = match x {
                serde_json::Value::String(_) => "a string",
                serde_json::Value::Bool(_) => "a boolean",
                serde_json::Value::Array(_) => "an array",
                _ => "an object",
            };
            let mut text = x.to_string();
            if text.len() > 40 {
                let cut = (0..=37).rev().find(|&i| text.is_char_boundary(i));
                text.truncate(cut.unwrap_or(0));
                text.push_str("...");
            }
            format!("{text} ({kind})")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kind_is_read_and_checked() {
        let head = r#"{"format": "crawlopt-gait-result", "version": 1"#;
        let (_, k) = read_envelope(&format!("{head}}}"), "r.json").unwrap();
        assert_eq!(k, ResultKind::Crawler);
        let (_, k) = read_envelope(&format!("{head}, \"kind\": \"general\"}}"), "r").unwrap();
        assert_eq!(k, ResultKind::General);
        let e = read_envelope(&format!("{head}, \"kind\": \"robot\"}}"), "r.json").unwrap_err();
        assert!(e.to_string().starts_with("r.json: kind"), "{e}");
        let e = read_envelope(&format!("{head}, \"kind\": 3}}"), "r.json").unwrap_err();
        assert!(e.to_string().contains("must be \"crawler\""), "{e}");
    }
}
