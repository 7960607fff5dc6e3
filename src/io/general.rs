//! The problem file of the general problem (P) (theory §11): a second top-level kind of model
//! file, recognised by its `[sweeping_process]` section (the crawler schema stays as it is).
//!
//! ```toml
//! [sweeping_process]
//! normals = [[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]]   # x*_j, one row per face (scaled to unit)
//! offsets = [1.0, 1.0, 1.0]                           # c_j
//! [dynamics]                # g(x, u) = A x + B u + b   (A and b may be omitted: 0)
//! A = [[-0.5, 0.0], [0.0, -0.5]]
//! B = [[1.0, 0.0], [0.0, 1.0]]
//! [control]                 # U: a box (lower, upper) or a polytope {u : G u <= h}
//! lower = [-1.0, -1.0]
//! upper = [1.0, 1.0]
//! zero_mean = true          # default: true for a periodic problem, false for a Cauchy one
//! [objective]               # f1 of the reaction eta = g - x' in N_C(x)
//! face_weights = [0.5, 0.5, 0.0]   # or reaction_weights = [q_1, .., q_n]: f1 = <q, eta>
//! cost = { kind = "quadratic", weight = 0.1 }  # none | quadratic (c/2)|u|^2 | matrix (1/2) u^T R u
//! [problem]
//! period = 10.0
//! periodic = true           # x(0) = x(T) (default); or periodic = false and initial_state
//! [input]                   # optional: the control `simulate` plays (T-periodic)
//! kind = "piecewise_constant"   # piecewise_constant | piecewise_linear | csv
//! times = [0.0, 5.0]            # knots from 0, increasing, below the period
//! values = [[1.0, 0.0], [-1.0, 0.0]]   # one row of u per knot
//! # csv: path = "u.csv" (rows t, u_1, .., u_m; header optional), interpolation = "piecewise_linear"
//! ```

use super::config::{parse_toml, MAX_MODEL_BYTES};
use crate::error::{Error, Result};
use crate::integrate::{ControlInput, InputKind};
use crate::model::general::{GeneralCost, GeneralParts, GeneralProblem};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// `[sweeping_process]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepingSpec {
    /// Rows `x*_j`.
    pub normals: Vec<Vec<f64>>,
    /// `c_j`.
    pub offsets: Vec<f64>,
}

/// `[dynamics]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DynamicsSpec {
    /// `A` (optional: 0).
    #[serde(skip_serializing_if = "Option::is_none", rename = "A")]
    pub a: Option<Vec<Vec<f64>>>,
    /// `B`.
    #[serde(rename = "B")]
    pub b: Vec<Vec<f64>>,
    /// `b` (optional: 0).
    #[serde(skip_serializing_if = "Option::is_none", rename = "b")]
    pub drift: Option<Vec<f64>>,
}

/// `[control]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ControlSpec {
    /// Box lower bounds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lower: Option<Vec<f64>>,
    /// Box upper bounds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub upper: Option<Vec<f64>>,
    /// Polytope rows.
    #[serde(skip_serializing_if = "Option::is_none", rename = "G")]
    pub g: Option<Vec<Vec<f64>>>,
    /// Polytope offsets.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h: Option<Vec<f64>>,
    /// The zero-mean constraint (default: the problem is periodic).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zero_mean: Option<bool>,
}

/// `cost = { kind = .., weight = .. }` or `{ kind = "matrix", matrix = [[..]] }`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GeneralCostSpec {
    /// `none | quadratic | matrix`.
    pub kind: String,
    /// `c` of `quadratic`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight: Option<f64>,
    /// `R` of `matrix`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub matrix: Option<Vec<Vec<f64>>>,
}

/// `[objective]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObjectiveSpec {
    /// `f1` as face weights.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub face_weights: Option<Vec<f64>>,
    /// `f1 = <q, eta>`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reaction_weights: Option<Vec<f64>>,
    /// `f2` (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost: Option<GeneralCostSpec>,
}

/// `[problem]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ProblemSpec {
    /// `T`.
    pub period: f64,
    /// `x(0) = x(T)` (default true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periodic: Option<bool>,
    /// `x(0)` of a Cauchy problem.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub initial_state: Option<Vec<f64>>,
}

/// `[input]`: the control that `simulate` plays.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct InputSpec {
    /// `piecewise_constant | piecewise_linear | csv`.
    pub kind: String,
    /// Knot times.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub times: Option<Vec<f64>>,
    /// Knot values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub values: Option<Vec<Vec<f64>>>,
    /// CSV file (relative to the problem file).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
    /// Interpolation of a CSV input (default piecewise_constant).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interpolation: Option<String>,
}

/// The whole problem file.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GeneralFile {
    /// `[sweeping_process]`.
    pub sweeping_process: SweepingSpec,
    /// `[dynamics]`.
    pub dynamics: DynamicsSpec,
    /// `[control]`.
    pub control: ControlSpec,
    /// `[objective]`.
    pub objective: ObjectiveSpec,
    /// `[problem]`.
    pub problem: ProblemSpec,
    /// `[input]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub input: Option<InputSpec>,
    /// Folder of the file, for relative paths.
    #[serde(skip)]
    pub base_dir: PathBuf,
}

/// Whether a model file's text is of the general kind (it has `[sweeping_process]`).
pub fn is_general(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.contains_key("sweeping_process"))
}

impl GeneralFile {
    /// Reads the file if it is of the general kind (`Ok(None)` for a crawler file, which
    /// [`super::ModelFile::load`] reads).
    pub fn load_if_general(path: &Path) -> Result<Option<Self>> {
        let text = super::read_input_text(path, MAX_MODEL_BYTES)?;
        if !is_general(&text) {
            return Ok(None);
        }
        let mut f = Self::parse(&text).map_err(|e| match e {
            Error::Io { reason, .. } => Error::Io {
                path: path.display().to_string(),
                reason,
            },
            other => other,
        })?;
        f.base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(Some(f))
    }

    /// Parses the TOML text.
    pub fn parse(text: &str) -> Result<Self> {
        parse_toml(text)
    }

    /// The file as TOML text, which [`GeneralFile::parse`] reads back to the same problem
    /// (numbers in their shortest form that reads back exactly).
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string(self).map_err(|e| Error::Io {
            path: "<model>".into(),
            reason: format!("cannot write the problem as TOML: {e}"),
        })
    }

    /// The problem, with the checks that need no linear program (see
    /// [`crate::api::general_problem`] for all of them).
    pub fn problem(&self) -> Result<GeneralProblem> {
        let c = &self.control;
        let o = &self.objective;
        let periodic = self.problem.periodic.unwrap_or(true);
        let cost = match &o.cost {
            None => None,
            Some(s) => Some(match (s.kind.as_str(), s.weight, &s.matrix) {
                ("none", None, None) => GeneralCost::None,
                ("quadratic", Some(weight), None) => GeneralCost::Quadratic { weight },
                ("matrix", None, Some(m)) => GeneralCost::Matrix { matrix: m.clone() },
                ("none" | "quadratic" | "matrix", _, _) => {
                    return Err(Error::invalid(
                        "objective.cost",
                        format!("kind = \"{}\"", s.kind),
                        "none takes nothing, quadratic a weight, matrix a matrix",
                    ))
                }
                (other, _, _) => {
                    return Err(Error::invalid(
                        "objective.cost.kind",
                        format!("\"{other}\""),
                        "must be none, quadratic or matrix",
                    ))
                }
            }),
        };
        GeneralProblem::new(GeneralParts {
            normals: self.sweeping_process.normals.clone(),
            offsets: self.sweeping_process.offsets.clone(),
            a: self.dynamics.a.clone(),
            b: self.dynamics.b.clone(),
            drift: self.dynamics.drift.clone(),
            lower: c.lower.clone(),
            upper: c.upper.clone(),
            g: c.g.clone(),
            h: c.h.clone(),
            zero_mean: c.zero_mean.unwrap_or(periodic),
            face_weights: o.face_weights.clone(),
            reaction_weights: o.reaction_weights.clone(),
            cost,
            period: self.problem.period,
            periodic,
            initial_state: self.problem.initial_state.clone(),
        })
    }

    /// The control of `[input]` for `p`.
    pub fn input(&self, p: &GeneralProblem) -> Result<ControlInput> {
        let s = self.input.as_ref().ok_or_else(|| {
            Error::invalid(
                "input",
                "nothing",
                "the problem file has no [input] section (the control to simulate)",
            )
        })?;
        let unused = |name: &str, present: bool| -> Result<()> {
            if present {
                Err(Error::invalid(
                    format!("input.{name}"),
                    "a value",
                    format!("is not used by kind = \"{}\"", s.kind),
                ))
            } else {
                Ok(())
            }
        };
        let kind_of = |name: &str, field: &str| match name {
            "piecewise_constant" => Ok(InputKind::PiecewiseConstant),
            "piecewise_linear" => Ok(InputKind::PiecewiseLinear),
            other => Err(Error::invalid(
                field,
                format!("\"{other}\""),
                "must be piecewise_constant, piecewise_linear or csv",
            )),
        };
        let (kind, times, values) = if s.kind == "csv" {
            unused("times", s.times.is_some())?;
            unused("values", s.values.is_some())?;
            let path = s.path.as_ref().ok_or_else(|| {
                Error::invalid("input.path", "nothing", "is required for kind = \"csv\"")
            })?;
            let kind = kind_of(
                s.interpolation.as_deref().unwrap_or("piecewise_constant"),
                "input.interpolation",
            )?;
            let (t, v) = super::read_actuation_csv(&self.base_dir.join(path), p.controls())?;
            (kind, t, v)
        } else {
            let kind = kind_of(&s.kind, "input.kind")?;
            unused("path", s.path.is_some())?;
            unused("interpolation", s.interpolation.is_some())?;
            let req = |name: &str| {
                Error::invalid(
                    format!("input.{name}"),
                    "nothing",
                    format!("is required for kind = \"{}\"", s.kind),
                )
            };
            (
                kind,
                s.times.clone().ok_or_else(|| req("times"))?,
                s.values.clone().ok_or_else(|| req("values"))?,
            )
        };
        ControlInput::new(kind, p.period, times, values, &p.control, "input")
    }
}

/// Writes a simulated period of the general problem as CSV:
/// `t, x_1..x_n, u_1..u_m, lambda_1..lambda_sigma` (1-based names); `u` and `lambda` are those of
/// the step (or segment) ending at `t`, empty on the first row. Written atomically.
pub fn write_general_csv(path: &Path, sim: &crate::integrate::GeneralSimulation) -> Result<()> {
    let io = |e: csv::Error| Error::Io {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    let mut out = super::AtomicFile::create(path)?;
    let n = sim.x.first().map_or(0, Vec::len);
    let m = sim.mean_control.len();
    let sigma = sim.lambda.first().map_or(0, Vec::len);
    {
        let mut w = csv::Writer::from_writer(out.writer());
        let mut header = vec!["t".to_string()];
        header.extend((1..=n).map(|k| format!("x_{k}")));
        header.extend((1..=m).map(|k| format!("u_{k}")));
        header.extend((1..=sigma).map(|j| format!("lambda_{j}")));
        w.write_record(&header).map_err(io)?;
        for i in 0..sim.t.len() {
            let mut row = vec![format!("{}", sim.t[i])];
            row.extend(sim.x[i].iter().map(|v| format!("{v}")));
            match i.checked_sub(1) {
                Some(k) if k < sim.u.len() => {
                    row.extend(sim.u[k].iter().map(|v| format!("{v}")));
                    row.extend(sim.lambda[k].iter().map(|v| format!("{v}")));
                }
                _ => row.extend(std::iter::repeat_n(String::new(), m + sigma)),
            }
            w.write_record(&row).map_err(io)?;
        }
        w.flush().map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
    }
    out.commit()
}
