//! The one result of both kinds, [`ResultFile`]: what `optimize` answers on a problem file of
//! either kind (`crate::api::OptimizedFile::result`) and what a result file reads back as, the
//! one entry point of every reader that takes both (`crawlopt certify`, `plot`, `report`,
//! Python's `read_result`). Reading checks the envelope first ([`read_envelope`]: format,
//! version, kind), then the kind's shape and consistency: a crawler's by [`GaitResult`]'s
//! reader, a general problem's by [`GeneralAnswer`]'s ([`GeneralAnswer::check_consistent`]).
//! Errors name the source and the field.

use super::{GeneralAnswer, GeneralSolution};
use crate::certify::NecessaryConditions;
use crate::error::{Error, Result};
use crate::optimal::envelope::{ResultHead, SolutionKind};
use crate::optimal::{read_envelope, GaitResult, ResultKind};
use serde::Serialize;

/// A result of either kind ([`ResultFile::from_json`]), with its necessary conditions when
/// they were computed (never read back from a file: `crawlopt certify` recomputes them).
#[derive(Debug, Clone, PartialEq)]
pub enum ResultFile {
    /// A crawler's gait result.
    Crawler(Box<GaitAnswer>),
    /// A general problem's result.
    General(Box<GeneralAnswer>),
}

/// A crawler's gait result and, when computed, its necessary conditions (Theorem 2.2): the
/// crawler's kind of [`ResultFile`], as [`GeneralAnswer`] is the general one and holds its
/// conditions alike. Its fields are those `optimize --json` writes for a crawler's optimum: the
/// result's envelope with `necessary_conditions` beside them (in alphabetical order through
/// [`ResultFile`]'s `Serialize`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GaitAnswer {
    /// The result.
    #[serde(flatten)]
    pub result: GaitResult,
    /// The necessary conditions on its gait, when computed (`optimize --certify`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub necessary_conditions: Option<NecessaryConditions>,
}

impl GaitAnswer {
    /// `result` without its necessary conditions (as a file reads back).
    pub fn of(result: GaitResult) -> Self {
        GaitAnswer {
            result,
            necessary_conditions: None,
        }
    }
}

impl From<GaitResult> for ResultFile {
    /// A crawler's result, without necessary conditions.
    fn from(r: GaitResult) -> Self {
        ResultFile::Crawler(Box::new(GaitAnswer::of(r)))
    }
}

impl From<GeneralAnswer> for ResultFile {
    /// A general problem's result.
    fn from(a: GeneralAnswer) -> Self {
        ResultFile::General(Box::new(a))
    }
}

impl ResultFile {
    /// Reads a result of either kind from JSON text (`what` names the source in errors): the
    /// envelope, then the kind's shape and consistency (module docs).
    pub fn from_json(text: &str, what: &str) -> Result<Self> {
        let (v, kind, label) = read_envelope(text, what)?;
        let what = label.as_str();
        match kind {
            ResultKind::Crawler => GaitResult::from_checked_envelope(v, what).map(Self::from),
            ResultKind::General => {
                let r = GeneralAnswer::from_checked_envelope(v, what)?;
                r.check_consistent(what)?;
                Ok(ResultFile::General(Box::new(r)))
            }
        }
    }

    /// Checks a result in memory as [`ResultFile::from_json`] checks one it reads: that it is
    /// what it says (`what` names it in errors).
    pub fn check_consistent(&self, what: &str) -> Result<()> {
        match self {
            ResultFile::Crawler(g) => g.result.check_consistent(what),
            ResultFile::General(a) => a.check_consistent(what),
        }
    }

    /// The verdict of its necessary conditions, when it holds them.
    pub fn verdict(&self) -> Option<crate::certify::Verdict> {
        match self {
            ResultFile::Crawler(g) => g.necessary_conditions.as_ref().map(|c| c.verdict),
            ResultFile::General(a) => a.necessary_conditions.as_ref().map(|c| c.verdict),
        }
    }

    /// A crawler's displacement per period (its barycentre's, re-verified by simulation);
    /// `None` for a general problem, whose objective is not a displacement.
    pub fn displacement_per_period(&self) -> Option<f64> {
        match self {
            ResultFile::Crawler(g) => Some(g.result.displacement_per_period),
            ResultFile::General(_) => None,
        }
    }

    /// The envelope every result opens with: kind, method, `J` re-verified, what was proven
    /// and the certificate ([`ResultHead`]).
    pub fn head(&self) -> &ResultHead {
        match self {
            ResultFile::Crawler(r) => &r.result.head,
            ResultFile::General(r) => &r.head,
        }
    }
}

/// The kind's own JSON, as `optimize --json` prints it: a crawler's answer with its keys in
/// alphabetical order (as it has always been printed), a general answer as its envelope.
impl Serialize for ResultFile {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::Error as _;
        match self {
            ResultFile::Crawler(g) => serde_json::to_value(g)
                .map_err(S::Error::custom)?
                .serialize(s),
            ResultFile::General(a) => a.serialize(s),
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
        fn malformed(e: serde_json::Error, what: &str) -> Error {
            Error::Io {
                path: what.into(),
                reason: format!("malformed general result: {e}"),
            }
        }
        fn parse<T: serde::de::DeserializeOwned>(v: serde_json::Value, what: &str) -> Result<T> {
            serde_json::from_value(v).map_err(|e| malformed(e, what))
        }
        let method = v.get("method").and_then(|m| m.as_str());
        let kind = SolutionKind::of_result(method, what)?;
        let v = with_repeated_fields(v);
        // The solution is read as the method's kind, so that a solution of another shape is
        // refused naming what it lacks.
        let solution = match v.get("solution") {
            Some(s) if GeneralSolution::shape(s) != kind => {
                let read = GeneralSolution::from_value(s.clone(), kind);
                Some(read.map_err(|e| malformed(e, what))?)
            }
            _ => None,
        };
        let mut answer = parse::<GeneralAnswer>(v, what)?;
        if let Some(s) = solution {
            answer.solution = s;
        }
        Ok(answer)
    }
}

/// A general result document with the fields the record repeats filled in where absent.
/// Version 3 writes each number once: the period is the problem's (`problem.problem.period`),
/// `J` the envelope's `objective`, and the MILP's certificate the envelope's `status`,
/// `solver_objective` and `certificate` (bound and gap). The record keeps them beside its
/// solution (the solvers' own types), so they are copied in before the shape is read. A
/// version 2 document has them all (and no `solver_objective`, which is copied from its
/// `solution.certificate.milp_objective`), and then every copy is checked against the
/// original as before ([`GeneralAnswer::check_consistent`]): a file whose repeated numbers
/// disagree is refused naming the field.
fn with_repeated_fields(mut v: serde_json::Value) -> serde_json::Value {
    use serde_json::{json, Value};
    let Some(o) = v.as_object_mut() else {
        return v;
    };
    let get = |o: &serde_json::Map<String, Value>, path: &[&str]| {
        let mut at = o.get(path[0])?;
        for k in &path[1..] {
            at = at.get(k)?;
        }
        Some(at.clone())
    };
    if !o.contains_key("period") {
        if let Some(t) = get(o, &["problem", "problem", "period"]) {
            o.insert("period".into(), t);
        }
    }
    if !o.contains_key("solver_objective") {
        if let Some(j) = get(o, &["solution", "certificate", "milp_objective"]) {
            o.insert("solver_objective".into(), j);
        }
    }
    let objective = get(o, &["objective"]);
    let certificate = match (get(o, &["status"]), get(o, &["solver_objective"])) {
        (Some(status), Some(j)) => Some(json!({
            "status": status,
            "milp_objective": j,
            "bound": get(o, &["certificate", "bound"]).unwrap_or(Value::Null),
            "gap": get(o, &["certificate", "gap"]).unwrap_or(Value::Null),
        })),
        _ => None,
    };
    if let Some(Value::Object(s)) = o.get_mut("solution") {
        if let Some(j) = objective {
            s.entry("objective").or_insert(j);
        }
        if let Some(c) = certificate {
            s.entry("certificate").or_insert(c);
        }
    }
    v
}
