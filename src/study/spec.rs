//! The sweep file: a base problem file (a crawler's model, or a general problem (P)), a job
//! with its settings, and axes over the file's numeric fields (see the module docs of
//! [`crate::study`]).

use super::axis::{Axis, AxisFile, Kind, MAX_POINTS};
use super::settings::{
    general_simulate_options, optimize_settings, setting_error, simulate_options, toml_err,
};
use crate::api::{GeneralPlan, OptimizeSettings};
use crate::error::{Error, Result};
use crate::integrate::{GeneralSimOptions, SimOptions};
use crate::io::{read_input_text, GeneralFile, ModelFile, ProblemFile};

/// Largest sweep file or base model read (bytes).
const MAX_MODEL_BYTES: u64 = 16 << 20;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// The job each point runs.
#[derive(Clone, Debug, PartialEq)]
pub enum Job {
    /// [`crate::api::analyze`]: for one link, J* in closed form (theory §9); the status is the
    /// class of v_m. Of a general problem, [`crate::api::analyze_general`]: the status is
    /// `well_posed`, an ill-posed point a row with the failed check as its error.
    Analyze,
    /// [`crate::api::simulate`] with these options: the displacement per period on the orbit.
    Simulate(SimOptions),
    /// [`crate::api::simulate_general`] of the base's `[input]` with these options (a general
    /// problem's `job = "simulate"`): J of a period on the orbit.
    SimulateGeneral(GeneralSimOptions),
    /// [`crate::api::optimize_file`] with these settings, on a problem of either kind (as
    /// `crawlopt optimize` runs it): the verified optimum and its certificate.
    Optimize(Box<OptimizeSettings>),
}

impl Job {
    /// Its name in the sweep file.
    pub fn name(&self) -> &'static str {
        match self {
            Job::Analyze => "analyze",
            Job::Simulate(_) | Job::SimulateGeneral(_) => "simulate",
            Job::Optimize(_) => "optimize",
        }
    }
}

/// How the axes combine into points.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Combine {
    /// Every combination (the first axis varies slowest).
    #[default]
    Product,
    /// The i-th value of every axis together (all axes of one length).
    Zip,
}

/// One point of a sweep: its id (its place in the expansion, from 0) and one value per axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// The id: the same for the same sweep file on every machine.
    pub id: usize,
    /// One value per axis, in the order of the axes.
    pub values: Vec<f64>,
}

/// A parsed sweep file.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSpec {
    /// The base problem file, as a TOML table.
    pub model: toml::Table,
    /// Its kind: a crawler's model file, or a general problem file (`[sweeping_process]`).
    pub kind: Kind,
    /// Folder of the base model file (relative paths inside it, e.g. a CSV actuation).
    pub model_dir: PathBuf,
    /// The job.
    pub job: Job,
    /// How the axes combine.
    pub combine: Combine,
    /// The axes.
    pub axes: Vec<Axis>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    base: Option<String>,
    model: Option<toml::Table>,
    job: String,
    combine: Option<String>,
    settings: Option<toml::Table>,
    #[serde(default)]
    axis: Vec<AxisFile>,
}

impl SweepSpec {
    /// Reads a sweep file; `base` is relative to it.
    pub fn load(path: &Path) -> Result<Self> {
        let text = read_input_text(path, MAX_MODEL_BYTES)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::parse(&text, &dir).map_err(|e| match e {
            Error::Io { path: p, reason } if p == "<sweep>" => Error::Io {
                path: path.display().to_string(),
                reason,
            },
            other => other,
        })
    }

    /// Parses the text of a sweep file whose relative paths start at `dir`.
    pub fn parse(text: &str, dir: &Path) -> Result<Self> {
        // Before the TOML parser holds every number of the file (about 170 bytes each).
        check_value_counts(text)?;
        let f: SweepFile = toml::from_str(text).map_err(|e| Error::Io {
            path: "<sweep>".into(),
            reason: format!(
                "invalid sweep file: {}",
                crate::io::escape_controls(&e.to_string().trim().replace('\n', "; "))
            ),
        })?;
        Self::from_file(f, dir)
    }

    /// Parses a sweep given as JSON (the same keys and tables as the TOML file: the Python
    /// package's dictionaries), relative paths starting at `dir`.
    pub fn from_json(text: &str, dir: &Path) -> Result<Self> {
        let f: SweepFile = serde_json::from_str(text).map_err(|e| {
            Error::invalid(
                "spec",
                "the dictionary given",
                format!(
                    "not a sweep: {}",
                    crate::io::escape_controls(&e.to_string())
                ),
            )
        })?;
        Self::from_file(f, dir)
    }

    fn from_file(f: SweepFile, dir: &Path) -> Result<Self> {
        let (model, model_dir) = base_model(f.base.as_deref(), f.model, dir)?;
        // The base must be a problem file by itself (axes only change numbers).
        let kind = Kind::of(&model);
        file_of(&model, &model_dir, kind).map_err(|e| match e {
            Error::InvalidParameter {
                field,
                value,
                reason,
            } if field == "model" => Error::invalid("base", value, reason),
            other => other,
        })?;
        let job = job_of(&f.job, f.settings.unwrap_or_default(), kind, dir)?;
        let combine = combine_of(f.combine.as_deref())?;
        let axes = axes_of(f.axis, &model, kind)?;
        let spec = SweepSpec {
            model,
            kind,
            model_dir,
            job,
            combine,
            axes,
        };
        spec.len()?;
        spec.check_job()?;
        Ok(spec)
    }

    /// Refuses, before any point runs, job settings that no point could run with: the
    /// library's own checks of the options ([`SimOptions::check`],
    /// [`OptimizeSettings::check_values`]), and for optimize what the settings decide for the
    /// problem ([`OptimizeSettings::decide`]: which options apply to the method), taken from
    /// the first point (the axes change numbers, not the kind of problem: a TV bound or a
    /// quadratic cost is the base model's for every point). Errors name `settings.KEY`.
    ///
    /// Of a general problem: simulate needs the base's `[input]` and options the simulator
    /// takes for the problem's size ([`GeneralSimOptions::check`]); optimize needs settings
    /// that apply to a general problem ([`OptimizeSettings::plan_general`]) with numbers in
    /// the method's range ([`plan_values`]).
    fn check_job(&self) -> Result<()> {
        match &self.job {
            Job::Analyze => Ok(()),
            Job::SimulateGeneral(options) => {
                let first = self.general_at(&self.point(0))?;
                if first.input.is_none() {
                    return Err(Error::invalid(
                        "base",
                        "no [input]",
                        "job = \"simulate\" plays the base problem's [input] (the control), and \
                         the file has none",
                    ));
                }
                // Recorded values a step, n + m + sigma: the same at every point (the axes
                // change numbers, not dimensions), whether or not the first is well posed.
                let normals = &first.sweeping_process.normals;
                let per_step = normals.first().map_or(0, Vec::len)
                    + first.dynamics.b.first().map_or(0, Vec::len)
                    + normals.len();
                options.check(per_step).map_err(setting_error)
            }
            Job::Optimize(settings) if self.kind == Kind::General => {
                settings.check_values().map_err(setting_error)?;
                let plan = settings.plan_general(&[]).map_err(setting_error)?;
                plan_values(&plan).map_err(setting_error)
            }
            // A sweep's simulate settings always step on the grid's default or the value
            // written, so 0 is refused here too (not only where a point would use it).
            Job::Simulate(options) => options
                .check()
                .and_then(|()| options.check_steps())
                .map_err(setting_error),
            Job::Optimize(settings) => {
                settings.check_values().map_err(setting_error)?;
                // A start gait every point would fail to read.
                if let Some(crate::api::Start::File(path)) = &settings.start {
                    if !path.is_file() {
                        return Err(Error::invalid(
                            "settings.start",
                            path.display(),
                            "is not a file (a result file of optimize --json, relative to the \
                             sweep file)",
                        ));
                    }
                }
                // A first point that is not a gait problem is its row's error, as before.
                let first = self.model_at(&self.point(0)).ok();
                let problem = first.and_then(|m| crate::api::gait_problem(&m).ok());
                match problem {
                    Some((_, problem)) => {
                        settings.decide(&problem).map(|_| ()).map_err(setting_error)
                    }
                    None => Ok(()),
                }
            }
        }
    }

    /// The number of points (an error naming `axis` when the axes do not combine, or give
    /// more than [`MAX_POINTS`]).
    pub fn len(&self) -> Result<usize> {
        let lens: Vec<usize> = self.axes.iter().map(|a| a.values.len()).collect();
        match self.combine {
            Combine::Zip => {
                if let Some(i) = lens.iter().position(|&l| l != lens[0]) {
                    return Err(Error::invalid(
                        format!("axis[{}]", i + 1),
                        format!("{} values", lens[i]),
                        format!(
                            "combine = \"zip\" needs axes of one length ({} values on axis[1])",
                            lens[0]
                        ),
                    ));
                }
                if lens[0] > MAX_POINTS {
                    return Err(Error::invalid(
                        "axis",
                        format!("{} values", lens[0]),
                        format!("combine = \"zip\" gives more than {MAX_POINTS} points"),
                    ));
                }
                Ok(lens[0])
            }
            Combine::Product => lens
                .iter()
                .try_fold(1usize, |acc, &l| acc.checked_mul(l))
                .filter(|&n| n <= MAX_POINTS)
                .ok_or_else(|| {
                    Error::invalid(
                        "axis",
                        format!("{lens:?} values"),
                        format!("the product has more than {MAX_POINTS} points"),
                    )
                }),
        }
    }

    /// Whether the sweep has no point (never: every axis has a value).
    pub fn is_empty(&self) -> bool {
        self.len().map_or(true, |n| n == 0)
    }

    /// The point `id` (the first axis varies slowest in a product).
    pub fn point(&self, id: usize) -> Point {
        let values = match self.combine {
            Combine::Zip => self.axes.iter().map(|a| a.values[id]).collect(),
            Combine::Product => {
                let mut rest = id;
                let mut v = vec![0.0; self.axes.len()];
                for (j, a) in self.axes.iter().enumerate().rev() {
                    v[j] = a.values[rest % a.values.len()];
                    rest /= a.values.len();
                }
                v
            }
        };
        Point { id, values }
    }

    /// Every point, in order of id.
    pub fn points(&self) -> Vec<Point> {
        (0..self.len().unwrap_or(0))
            .map(|i| self.point(i))
            .collect()
    }

    /// The problem file of a point: the base with each axis's value set. Errors name the
    /// axis's field (e.g. an index beyond the list, a non-integer block count) or the file's.
    pub fn problem_at(&self, point: &Point) -> Result<ProblemFile> {
        let mut table = self.model.clone();
        // Plain fields first, so that an indexed entry is expanded with the point's N.
        let mut order: Vec<usize> = (0..self.axes.len()).collect();
        order.sort_by_key(|&j| !self.axes[j].is_plain());
        for j in order {
            self.axes[j].set(&mut table, point.values[j], self.kind)?;
        }
        file_of(&table, &self.model_dir, self.kind)
    }

    /// The crawler's model file of a point ([`SweepSpec::problem_at`]); an error naming `base`
    /// for a sweep over a general problem.
    pub fn model_at(&self, point: &Point) -> Result<ModelFile> {
        match self.problem_at(point)? {
            ProblemFile::Crawler(m) => Ok(*m),
            ProblemFile::General(_) => Err(Error::invalid(
                "base",
                "a general problem file",
                "is not a crawler's model file",
            )),
        }
    }

    /// The general problem file of a point ([`SweepSpec::problem_at`]); an error naming
    /// `base` for a sweep over a crawler.
    pub fn general_at(&self, point: &Point) -> Result<GeneralFile> {
        match self.problem_at(point)? {
            ProblemFile::General(g) => Ok(*g),
            ProblemFile::Crawler(_) => Err(Error::invalid(
                "base",
                "a crawler's model file",
                "is not a general problem file ([sweeping_process])",
            )),
        }
    }
}

/// A problem file of `kind` from its TOML table, relative paths from `dir`.
fn file_of(table: &toml::Table, dir: &Path, kind: Kind) -> Result<ProblemFile> {
    let value = toml::Value::Table(table.clone());
    Ok(match kind {
        Kind::Crawler => {
            let mut m: ModelFile = value.try_into().map_err(|e| toml_err("model", e))?;
            m.base_dir = dir.to_path_buf();
            ProblemFile::Crawler(Box::new(m))
        }
        Kind::General => {
            let mut g: GeneralFile = value.try_into().map_err(|e| toml_err("model", e))?;
            g.base_dir = dir.to_path_buf();
            ProblemFile::General(Box::new(g))
        }
    })
}

/// Refuses the numbers of a general plan outside the method's range whatever the problem (the
/// optimisers check them again, with the problem): `m` of P_m up to
/// [`MAX_GENERAL_M`](crate::optimal::general::MAX_GENERAL_M) globally and
/// [`MAX_GENERAL_LOCAL_M`](crate::optimal::general::MAX_GENERAL_LOCAL_M) locally, `K` of the
/// phase method (`max_phases`, and `phases` when fixed) up to
/// [`MAX_GENERAL_PHASES`](crate::optimal::general::MAX_GENERAL_PHASES) with a patience of at
/// least 1; the crawler's ranges for its sequence and chain methods.
fn plan_values(plan: &GeneralPlan) -> Result<()> {
    use crate::optimal::general::{MAX_GENERAL_LOCAL_M, MAX_GENERAL_M, MAX_GENERAL_PHASES};
    let mut checks = match plan {
        GeneralPlan::Discrete(s) => vec![("m", s.m as usize, 1, MAX_GENERAL_M as usize)],
        GeneralPlan::Local(s) => vec![("m", s.m as usize, 1, MAX_GENERAL_LOCAL_M as usize)],
        GeneralPlan::Phase(s) => vec![("patience", s.patience, 1, usize::MAX)],
        // The crawler's methods: the crawler's ranges.
        GeneralPlan::OnChain(s) => return s.crawler.check_values(),
    };
    if let GeneralPlan::Phase(s) = plan {
        checks.extend(
            s.max_phases
                .map(|k| ("max_phases", k, 1, MAX_GENERAL_PHASES)),
        );
        checks.extend(s.phases.map(|k| ("phases", k, 1, MAX_GENERAL_PHASES)));
    }
    for (name, value, min, max) in checks {
        if !(min..=max).contains(&value) {
            let reason = if max == usize::MAX {
                format!("must be at least {min}")
            } else {
                format!("must be in {min}..={max}")
            };
            return Err(Error::invalid(name, value, reason));
        }
    }
    Ok(())
}

/// Refuses, by a scan of the text before it is parsed, a `values = [...]` list of more than
/// [`MAX_POINTS`] entries, naming its axis (`axis[i].values`): parsed, a list of 3 million
/// numbers held over a gigabyte and took 18 s before the limit could refuse it. The count is of
/// the commas inside the brackets, so it can only count more than the entries (a comment in
/// the list), never fewer.
fn check_value_counts(text: &str) -> Result<()> {
    let bytes = text.as_bytes();
    let (mut axis, mut pos) = (0usize, 0usize);
    while pos < bytes.len() {
        let end = text[pos..].find('\n').map_or(bytes.len(), |i| pos + i + 1);
        let t = text[pos..end].trim_start();
        if t.starts_with("[[") && t.trim_start_matches('[').trim_start().starts_with("axis") {
            axis += 1;
        }
        let list = t
            .strip_prefix("values")
            .or_else(|| t.strip_prefix("\"values\""))
            .map(str::trim_start)
            .and_then(|r| r.strip_prefix('='))
            .map(str::trim_start)
            .filter(|r| r.starts_with('['));
        let mut next = end;
        if let Some(list) = list {
            // `list` ends the line: it starts at `end - list.len()` and runs, over lines if
            // need be, to its closing bracket.
            let (mut depth, mut commas) = (0usize, 0usize);
            for (i, b) in bytes[end - list.len()..].iter().enumerate() {
                match b {
                    b'[' => depth += 1,
                    b']' => {
                        depth = depth.saturating_sub(1);
                        if depth == 0 {
                            next = next.max(end - list.len() + i + 1);
                            break;
                        }
                    }
                    b',' => commas += 1,
                    _ => {}
                }
            }
            if commas > MAX_POINTS {
                return Err(Error::invalid(
                    format!("axis[{}].values", axis.max(1)),
                    format!("more than {MAX_POINTS} values"),
                    format!("at most {MAX_POINTS} (the most points a sweep may have)"),
                ));
            }
        }
        pos = next;
    }
    Ok(())
}

/// The sweep's base model and the directory its relative paths are read from: the file
/// `base` (relative to `dir`) or the inline `[model]`, exactly one of them.
fn base_model(
    base: Option<&str>,
    model: Option<toml::Table>,
    dir: &Path,
) -> Result<(toml::Table, PathBuf)> {
    Ok(match (base, model) {
        (Some(base), None) => {
            let path = dir.join(base);
            let text = read_input_text(&path, MAX_MODEL_BYTES)?;
            let table: toml::Table = toml::from_str(&text).map_err(|e| Error::Io {
                path: path.display().to_string(),
                reason: format!("invalid model file: {}", e.message().trim()),
            })?;
            let model_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
            (table, model_dir)
        }
        (None, Some(table)) => (table, dir.to_path_buf()),
        (Some(_), Some(_)) => {
            return Err(Error::invalid(
                "base",
                "a file and a [model]",
                "give either a base model file or an inline [model], not both",
            ))
        }
        (None, None) => {
            return Err(Error::invalid(
                "base",
                "nothing",
                "a sweep needs a base model file (base = \"model.toml\") or an inline [model]",
            ))
        }
    })
}

/// The job of a sweep file, with its settings (`job = "analyze"` takes none).
fn job_of(job: &str, settings: toml::Table, kind: Kind, dir: &Path) -> Result<Job> {
    Ok(match job {
        "analyze" => {
            if let Some(key) = settings.keys().next() {
                return Err(Error::invalid(
                    format!("settings.{key}"),
                    "a value",
                    "job = \"analyze\" takes no settings",
                ));
            }
            Job::Analyze
        }
        "simulate" => match kind {
            Kind::Crawler => Job::Simulate(simulate_options(settings)?),
            Kind::General => Job::SimulateGeneral(general_simulate_options(settings)?),
        },
        "optimize" => Job::Optimize(Box::new(optimize_settings(settings, dir)?)),
        other => {
            return Err(Error::invalid(
                "job",
                format!("\"{other}\""),
                "must be analyze, simulate or optimize",
            ))
        }
    })
}

/// How the axes combine: `product` (the default) or `zip`.
fn combine_of(combine: Option<&str>) -> Result<Combine> {
    Ok(match combine {
        None | Some("product") => Combine::Product,
        Some("zip") => Combine::Zip,
        Some(other) => {
            return Err(Error::invalid(
                "combine",
                format!("\"{other}\""),
                "must be product or zip",
            ))
        }
    })
}

/// The sweep's axes, each checked against the base `model` (a general problem's entry must
/// exist in it) and against the axes before it (no field twice, no list beside its entry).
fn axes_of(files: Vec<AxisFile>, model: &toml::Table, kind: Kind) -> Result<Vec<Axis>> {
    if files.is_empty() {
        return Err(Error::invalid(
            "axis",
            "nothing",
            "a sweep needs at least one [[axis]]",
        ));
    }
    let mut axes: Vec<Axis> = Vec::new();
    for (i, a) in files.into_iter().enumerate() {
        let written = format!("\"{}\"", crate::io::escape_controls(&a.field));
        let name = format!("axis[{}]", i + 1);
        let axis = Axis::new(a, &name, kind)?;
        if kind == Kind::General {
            // The entry must be in the base (axes change numbers, not dimensions): set
            // into a copy, any error is the field's.
            axis.set(&mut model.clone(), axis.values[0], kind)
                .map_err(|e| match e {
                    Error::InvalidParameter { reason, .. } => {
                        Error::invalid(format!("{name}.field"), &written, reason)
                    }
                    other => other,
                })?;
        }
        // Fields compare by what they set (path and entry), not by how they are written:
        // `gait.period` and `gait.period ` are one field, and a whole list overlaps each
        // of its entries (the row would show a value that one entry does not have).
        if let Some((j, b)) = axes.iter().enumerate().find(|(_, b)| b.overlaps(&axis)) {
            let reason = if b.same_entry(&axis) {
                format!("is already axis[{}] ({})", j + 1, b.field)
            } else {
                format!(
                    "overlaps axis[{}] ({}): a whole list and one of its entries cannot \
                     both be axes",
                    j + 1,
                    b.field
                )
            };
            return Err(Error::invalid(
                format!("axis[{}].field", i + 1),
                written,
                reason,
            ));
        }
        axes.push(axis);
    }
    Ok(axes)
}
