//! The envelope every optimisation result carries, whichever the kind of problem (a crawler or
//! a general problem (P), theory §11) and the method: `format`, `version` and `kind` at the top
//! level, read here before the rest so that a reader of one kind names what is wrong with a
//! file of the other (or of neither) instead of failing on a missing field. The crawler's
//! reader ([`GaitResult::from_json`](super::GaitResult::from_json)) and the reader of either
//! kind (`crate::io::ResultFile`) both start here.

use crate::error::{Error, Result};
use crate::optimal::{Certificate, LocalStop, MilpStatus};
use serde::{Deserialize, Serialize};

/// Value of the `format` field of every result (both kinds).
pub const RESULT_FORMAT: &str = "crawlopt-gait-result";
/// Version of the result format written by this build. Version 2 is one envelope for both
/// kinds: `format`, `version`, `kind`, `method`, `problem`, `objective`, `status`,
/// `certificate`, `solver_objective` (the MILP methods') and `solution` (a crawler's gait was
/// under `gait` in version 1, and `kind` could be absent). Version 3 writes each number once
/// and names the solution's arrays alike for every method: a general result's `solution` no
/// longer repeats `objective` and the MILP's `certificate` (now the envelope's `status`,
/// `certificate` and `solver_objective`), its period is the problem's (no top-level
/// `period`), and a P_m process's `x`, `u`, `lambda` are `states`, `controls`, `reactions`,
/// as a phase gait's and a crawler's; a crawler's result is unchanged. Version 4 gives a
/// crawler's result the same places: its `problem` is `{crawler, gait}` (the model file's
/// sections, as (P)'s `problem` is its file's) where versions 1 to 3 had the crawler at the top
/// level and the gait problem as `problem`, and its solution's own numbers (`m`,
/// `displacement_per_period`, `actuation_cost`) and the records of how it was reached
/// (`local`, `polish`) are in `solution`, as (P)'s are, each written once (the displacement
/// was also written as `verified_displacement`); a general result is unchanged. Versions 1 to
/// 4 are read ([`read_envelope`] moves an older crawler's fields to their places; a version 2
/// general document reads as it is, its repeated numbers checked); others are refused.
pub const RESULT_VERSION: u32 = 4;

/// Default relative tolerance on the consistency of an input process (states in C, periodicity,
/// zero mean, dynamics): relative to the size of C, the rate bounds and the period. Loose enough
/// for a gait written with ten significant digits, tight enough that the first-order conditions
/// are meaningful at the `1e-9` level of the certificate. Every reader of a result checks to it
/// (here, where a document's envelope is read, so that its upgrade checks to it too; re-exported
/// by [`super::consistency`]).
pub const INPUT_TOL: f64 = 1e-7;

/// The oldest result version this build reads.
pub const RESULT_VERSION_READ_FROM: u32 = 1;

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

/// What a result's solution is, by the method that found it: a process on the grid of the
/// paper's P_m (§6) found globally (`Discrete`) or by the local active-set method (`Local`), or
/// an exact gait of slip phases (`Phase`). A crawler's result stores both grid kinds in one
/// shape (its gait with `m`); (P)'s stores each in its own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolutionKind {
    /// P_m solved globally (method `discrete`).
    Discrete,
    /// P_m by the active-set method on its LPCC (method `local`).
    Local,
    /// An exact gait of slip phases (methods `phase`, `sequence` and `chain`).
    Phase,
}

/// Every method a result names, for both kinds of problem, with the kind of its solution: the
/// one table that the readers accept methods from, that the consistency checks compare a
/// solution with, and that the refusal of an unknown method lists.
pub const RESULT_METHODS: [(&str, SolutionKind); 5] = [
    ("discrete", SolutionKind::Discrete),
    ("local", SolutionKind::Local),
    ("phase", SolutionKind::Phase),
    ("sequence", SolutionKind::Phase),
    ("chain", SolutionKind::Phase),
];

impl SolutionKind {
    /// The kind of solution a result of `method` has ([`RESULT_METHODS`]); `None` for a word
    /// that names no method.
    pub fn of_method(method: &str) -> Option<Self> {
        RESULT_METHODS
            .iter()
            .find(|(name, _)| *name == method)
            .map(|(_, kind)| *kind)
    }

    /// The methods whose results have this kind of solution ([`RESULT_METHODS`]).
    pub fn methods(self) -> Vec<&'static str> {
        RESULT_METHODS
            .iter()
            .filter(|(_, kind)| *kind == self)
            .map(|(name, _)| *name)
            .collect()
    }

    /// The kind of solution of a result's `method`, or the refusal (field `method`, under the
    /// source `what`) listing the methods of [`RESULT_METHODS`].
    pub fn of_result(method: Option<&str>, what: &str) -> Result<Self> {
        method.and_then(SolutionKind::of_method).ok_or_else(|| {
            let names: Vec<String> = RESULT_METHODS
                .iter()
                .map(|(name, _)| format!("\"{name}\""))
                .collect();
            Error::invalid(
                format!("{what}: method"),
                method.unwrap_or("nothing"),
                format!("must be {}", in_words(&names, "or")),
            )
        })
    }
}

/// What is proven about the returned gait.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultCertificate {
    /// `"global"` (optimal for P_m), `"global_k_phases"` (optimal among gaits of at most
    /// `phases` slip phases, with any all-stick transitions between them) or `"local"` (a
    /// stationary point, no global claim).
    pub kind: String,
    /// Gap between the bound and the verified value (relative above the problem's floor of `J`,
    /// in units of it below, [`crate::optimal::Certificate::gap_of`]); `None` for local answers.
    pub gap: Option<f64>,
    /// Upper bound on the optimum of the problem solved; `None` for local answers.
    pub bound: Option<f64>,
    /// `K` (slip phases) for phase gaits.
    pub phases: Option<usize>,
    /// A bound on `J` over *all* periodic gaits (`optimize --bound`, [`crate::certify::bound`]),
    /// with the method and grid that proved it; read from a file it is taken as recorded
    /// (checked to be finite and at least the objective, not recomputed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub upper_bound: Option<crate::optimal::bound_record::UpperBound>,
}

impl ResultCertificate {
    /// A local answer's certificate: no bound and no gap (no global claim), `phases` for a
    /// phase gait.
    pub fn local(phases: Option<usize>) -> Self {
        ResultCertificate {
            kind: "local".into(),
            gap: None,
            bound: None,
            phases,
            upper_bound: None,
        }
    }
}

impl ResultCertificate {
    /// A MILP's certificate: `"global"` (P_m), or `"global_k_phases"` with `phases = K` when
    /// `phases` is given (gaits of at most `K` phases); its bound and gap.
    pub fn of_milp(c: &Certificate, phases: Option<usize>) -> Self {
        ResultCertificate {
            kind: if phases.is_some() {
                "global_k_phases"
            } else {
                "global"
            }
            .into(),
            gap: Some(c.gap),
            bound: Some(c.bound),
            phases,
            upper_bound: None,
        }
    }
}

/// The fields every optimisation result carries, whichever its kind and method (module docs):
/// one struct, flattened into the crawler's [`GaitResult`](super::GaitResult) and each of
/// (P)'s answers (`crate::io::GeneralAnswer`), so that a reader of either asks one place what
/// was solved by which method, what `J` it verified and what it proved
/// (`crate::io::ResultFile::head`). The problem and the solution, whose shapes are the
/// kind's and the method's, sit beside it in each result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResultHead {
    /// Always [`RESULT_FORMAT`].
    pub format: String,
    /// [`RESULT_VERSION`] of the writer (an older file is upgraded on reading,
    /// [`read_envelope`]).
    pub version: u32,
    /// Which kind of problem (a version 1 crawler's file has none: read as a crawler's).
    #[serde(default)]
    pub kind: ResultKind,
    /// The method that ran: `"phase"`, `"sequence"` or `"chain"` (an exact phase gait),
    /// `"discrete"` (the paper's P_m, globally) or `"local"` (P_m by the active-set method).
    pub method: String,
    /// `J`, re-verified by simulation (the exact simulator for a phase gait, catching-up on
    /// the grid for P_m).
    pub objective: f64,
    /// What was proven ([`MilpStatus`]).
    pub status: MilpStatus,
    /// The claim: global with the MILP's bound and gap, among `K` phases, or local.
    pub certificate: ResultCertificate,
}

impl ResultHead {
    /// The head of a result of this build: `format` and `version` filled in.
    pub fn new(
        kind: ResultKind,
        method: &str,
        objective: f64,
        status: MilpStatus,
        certificate: ResultCertificate,
    ) -> Self {
        ResultHead {
            format: RESULT_FORMAT.into(),
            version: RESULT_VERSION,
            kind,
            method: method.into(),
            objective,
            status,
            certificate,
        }
    }
}

/// An error of a result's problem, named as in the problem's file (a crawler's
/// `crawler.stiffness[2]`, `gait.period`; (P)'s `dynamics.B`), named at its place in the result:
/// `r.json: problem.crawler.stiffness[2]`. Both kinds' readers name their problems so.
pub fn in_problem(e: Error, what: &str) -> Error {
    e.map_field(|field| format!("{what}: problem.{field}"))
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
/// (1 to [`RESULT_VERSION`]), `kind` (absent in version 1 only: a crawler's), and the key of
/// the solution (`solution`; a version 1 crawler's `gait`, neither under the other's name).
/// Returns the document in the shape of [`RESULT_VERSION`] (a version 1 crawler's `gait`
/// becomes its `solution`), its kind, and the name its reader's errors give the source:
/// `what`, or for a version 1 crawler's file `what (version 1, its gait read as solution)`,
/// since they name the fields of later versions. Errors name `what` and the field.
pub fn read_envelope(text: &str, what: &str) -> Result<(serde_json::Value, ResultKind, String)> {
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
    let version = match v.get("version").and_then(|x| x.as_u64()) {
        Some(x)
            if (u64::from(RESULT_VERSION_READ_FROM)..=u64::from(RESULT_VERSION)).contains(&x) =>
        {
            x
        }
        _ => {
            return Err(Error::invalid(
                format!("{what}: version"),
                described(v.get("version")),
                format!("this build reads versions {} only", versions_read()),
            ));
        }
    };
    let kind = match v.get("kind") {
        None if version == 1 => ResultKind::Crawler,
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
    // The solution under the key of its version (a stray key of the other is refused: the
    // reader would silently ignore it).
    let (key, other) = if version == 1 && kind == ResultKind::Crawler {
        ("gait", "solution")
    } else {
        ("solution", "gait")
    };
    if v.get(other).is_some() {
        return Err(Error::invalid(
            format!("{what}: {other}"),
            "given",
            format!(
                "is not a field of a version {version} {} result (its solution is `{key}`)",
                kind.as_str()
            ),
        ));
    }
    if kind == ResultKind::Crawler {
        check_crawler_places(&v, version, key, what)?;
    }
    let label = if key == "solution" {
        what.to_string()
    } else {
        format!("{what} (version {version}, its {key} read as solution)")
    };
    Ok((upgraded(v, version, kind, &label)?, kind, label))
}

/// A crawler's fields at their places of the other versions (the top level up to version 3,
/// the solution from version 4; [`MOVED_INTO_SOLUTION`]): refused naming them, not dropped.
/// `key` is the version's name of the solution.
fn check_crawler_places(v: &serde_json::Value, version: u64, key: &str, what: &str) -> Result<()> {
    let at_top = version >= u64::from(RESULT_VERSION);
    let (found, place, places) = if at_top {
        let top = MOVED_INTO_SOLUTION
            .iter()
            .chain(&["crawler", "verified_displacement"]);
        (
            top.copied().find(|k| v.get(*k).is_some()),
            "",
            "in `solution`, the crawler in `problem`",
        )
    } else {
        let solution = v.get(key);
        let inside = MOVED_INTO_SOLUTION
            .iter()
            .find(|k| solution.and_then(|s| s.get(**k)).is_some());
        (inside.copied(), "solution.", "at the top level")
    };
    if let Some(k) = found {
        return Err(Error::invalid(
            format!("{what}: {place}{k}"),
            "given",
            format!(
                "is not a field of a version {version} crawler's result here (it is \
                 {places})"
            ),
        ));
    }
    Ok(())
}

/// The fields a crawler's result of versions 1 to 3 kept at the top level and version 4 keeps
/// in its `solution`.
const MOVED_INTO_SOLUTION: [&str; 5] = [
    "m",
    "displacement_per_period",
    "actuation_cost",
    "local",
    "polish",
];

/// A document of `version` in the shape of [`RESULT_VERSION`], the version becoming the
/// current one. A crawler's of version 1 wrote its solution under `gait`; one of versions 1
/// to 3 had the crawler at the top level beside its gait problem `problem` (both now under
/// `problem`, as `crawler` and `gait`), and its solution's numbers and records at the top
/// level ([`MOVED_INTO_SOLUTION`]), the displacement twice: `verified_displacement` is
/// dropped once it is found equal to `displacement_per_period` (an older file that disagrees
/// with itself is refused naming it, as its reader then did). A field that is missing stays
/// missing, and the reader names it at its new place.
fn upgraded(
    mut v: serde_json::Value,
    version: u64,
    kind: ResultKind,
    what: &str,
) -> Result<serde_json::Value> {
    if version == u64::from(RESULT_VERSION) {
        return Ok(v);
    }
    if let Some(o) = v.as_object_mut() {
        if kind == ResultKind::Crawler {
            if let Some(g) = o.remove("gait") {
                o.insert("solution".to_string(), g);
            }
            if let Some(d) = o.remove("verified_displacement") {
                check_twice_written(&d, o.get("displacement_per_period"), what)?;
            }
            let mut problem = serde_json::Map::new();
            for (from, to) in [("crawler", "crawler"), ("problem", "gait")] {
                if let Some(x) = o.remove(from) {
                    problem.insert(to.to_string(), x);
                }
            }
            o.insert("problem".to_string(), problem.into());
            let moved: Vec<(&str, serde_json::Value)> = MOVED_INTO_SOLUTION
                .iter()
                .filter_map(|k| o.remove(*k).map(|x| (*k, x)))
                .collect();
            if let Some(solution) = o.get_mut("solution").and_then(|s| s.as_object_mut()) {
                for (k, x) in moved {
                    solution.insert(k.to_string(), x);
                }
            }
        }
        o.insert("kind".to_string(), kind.as_str().into());
        o.insert("version".to_string(), RESULT_VERSION.into());
    }
    Ok(v)
}

/// A version 1 to 3 crawler's `verified_displacement` `d` against its
/// `displacement_per_period` `once` (the same number, written twice): a number, and where the
/// other is one too, equal within [`INPUT_TOL`] (the reader of
/// those versions compared both with the gait's displacement to that tolerance). A missing
/// `displacement_per_period` is left to the reader, which names it at its new place.
fn check_twice_written(
    d: &serde_json::Value,
    once: Option<&serde_json::Value>,
    what: &str,
) -> Result<()> {
    let field = format!("{what}: verified_displacement");
    let Some(d) = d.as_f64() else {
        return Err(Error::invalid(
            field,
            described(Some(d)),
            "must be a number",
        ));
    };
    if let Some(once) = once.and_then(|x| x.as_f64()) {
        let tol = INPUT_TOL * (1.0 + once.abs().max(d.abs()));
        if (d - once).abs() > tol {
            return Err(Error::invalid(
                field,
                d,
                format!(
                    "differs from displacement_per_period ({once}): a result of versions 1 to \
                     3 writes the one displacement twice"
                ),
            ));
        }
    }
    Ok(())
}

/// The versions read, in words: `1, 2, 3 and 4`.
fn versions_read() -> String {
    let all: Vec<String> = (RESULT_VERSION_READ_FROM..=RESULT_VERSION)
        .map(|v| v.to_string())
        .collect();
    in_words(&all, "and")
}

/// A list for a message: `a, b and c` (with `word` = `"and"`), `a` alone, nothing for none.
pub(crate) fn in_words(items: &[String], word: &str) -> String {
    match items.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} {word} {last}", rest.join(", ")),
        _ => items.join(""),
    }
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
        let (_, k, _) = read_envelope(&format!("{head}}}"), "r.json").unwrap();
        assert_eq!(k, ResultKind::Crawler);
        let (_, k, _) = read_envelope(&format!("{head}, \"kind\": \"general\"}}"), "r").unwrap();
        assert_eq!(k, ResultKind::General);
        let e = read_envelope(&format!("{head}, \"kind\": \"robot\"}}"), "r.json").unwrap_err();
        assert!(e.to_string().starts_with("r.json: kind"), "{e}");
        let e = read_envelope(&format!("{head}, \"kind\": 3}}"), "r.json").unwrap_err();
        assert!(e.to_string().contains("must be \"crawler\""), "{e}");
        // Version 2 names its kind; a version 1 crawler's gait becomes its solution.
        let v2 = r#"{"format": "crawlopt-gait-result", "version": 2"#;
        let e = read_envelope(&format!("{v2}}}"), "r.json").unwrap_err();
        assert!(e.to_string().starts_with("r.json: kind"), "{e}");
        let (v, _, label) = read_envelope(&format!("{head}, \"gait\": [7]}}"), "r").unwrap();
        assert_eq!(label, "r (version 1, its gait read as solution)");
        assert_eq!(v["solution"], serde_json::json!([7]));
        assert_eq!(
            (v["version"].as_u64(), v["kind"].as_str()),
            (Some(u64::from(RESULT_VERSION)), Some("crawler"))
        );
        assert!(v.get("gait").is_none());
        // A key of the other version is refused, not ignored.
        for doc in [
            format!("{head}, \"gait\": [7], \"solution\": [8]}}"),
            format!("{v2}, \"kind\": \"crawler\", \"solution\": [7], \"gait\": 1}}"),
            format!("{v2}, \"kind\": \"general\", \"solution\": [7], \"gait\": 1}}"),
        ] {
            let e = read_envelope(&doc, "r").unwrap_err();
            assert!(e.to_string().contains("is not a field of a version"), "{e}");
        }
        let v5 = r#"{"format": "crawlopt-gait-result", "version": 5, "kind": "crawler"}"#;
        let e = read_envelope(v5, "r").unwrap_err();
        assert!(
            e.to_string().contains("reads versions 1, 2, 3 and 4 only"),
            "{e}"
        );
    }
}
