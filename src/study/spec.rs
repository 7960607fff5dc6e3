//! The sweep file: a base model, a job with its settings, and axes over the model's numeric
//! fields (see the module docs of [`crate::study`]).

use super::settings::{optimize_settings, setting_error, simulate_options, toml_err};
use crate::api::OptimizeSettings;
use crate::error::{Error, Result};
use crate::integrate::SimOptions;
use crate::io::{read_input_text, ModelFile};

/// Largest sweep file or base model read (bytes).
const MAX_MODEL_BYTES: u64 = 16 << 20;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Most points a sweep may have (each is a row kept in memory while the sweep runs).
pub const MAX_POINTS: usize = 1_000_000;

/// The numeric fields of a model file an axis may set, and whether each is a per-link
/// (`Some(true)`) or per-block (`Some(false)`) list that takes an index, or a plain number
/// (`None`).
const FIELDS: &[(&str, Option<bool>)] = &[
    ("crawler.blocks", None),
    ("crawler.stiffness", Some(true)),
    ("crawler.mu_forward", Some(false)),
    ("crawler.mu_backward", Some(false)),
    ("gait.period", None),
    ("gait.max_actuator_speed", Some(true)),
    ("gait.max_total_variation", None),
    ("gait.cost.weight", None),
    ("actuation.period", None),
    ("actuation.amplitude", Some(true)),
    ("actuation.phase_deg", Some(true)),
    ("actuation.mean", Some(true)),
    ("simulation.initial_state", Some(true)),
];

/// The job each point runs.
#[derive(Clone, Debug, PartialEq)]
pub enum Job {
    /// [`crate::api::analyze`]: for one link, J* in closed form (theory §9); the status is the
    /// class of v_m.
    Analyze,
    /// [`crate::api::simulate`] with these options: the displacement per period on the orbit.
    Simulate(SimOptions),
    /// [`crate::api::optimize`] with these settings: the verified optimum and its certificate.
    Optimize(Box<OptimizeSettings>),
}

impl Job {
    /// Its name in the sweep file.
    pub fn name(&self) -> &'static str {
        match self {
            Job::Analyze => "analyze",
            Job::Simulate(_) => "simulate",
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

/// One axis: a field of the model and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The field as meant, whatever spaces it was written with (`crawler.mu_backward`,
    /// `crawler.mu_backward[2]` for `" crawler.mu_backward[ 2 ]"`): the column name.
    pub field: String,
    /// Its values, in order.
    pub values: Vec<f64>,
    /// The path of tables and the key.
    path: Vec<String>,
    /// The 1-based list entry, if any.
    index: Option<usize>,
    /// Per-link list (else per-block), for a field that takes an index.
    per_link: Option<bool>,
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
    /// The base model, as a TOML table.
    pub model: toml::Table,
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisFile {
    field: String,
    values: Option<Vec<f64>>,
    range: Option<RangeFile>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RangeFile {
    from: f64,
    to: f64,
    count: i64,
    scale: Option<String>,
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
        let (model, model_dir) =
            match (&f.base, f.model) {
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
                (None, None) => return Err(Error::invalid(
                    "base",
                    "nothing",
                    "a sweep needs a base model file (base = \"model.toml\") or an inline [model]",
                )),
            };
        // The base model must be a model file by itself (axes only change numbers).
        model_of(&model, &model_dir).map_err(|e| match e {
            Error::InvalidParameter {
                field,
                value,
                reason,
            } if field == "model" => Error::invalid("base", value, reason),
            other => other,
        })?;
        let settings = f.settings.unwrap_or_default();
        let job = match f.job.as_str() {
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
            "simulate" => Job::Simulate(simulate_options(settings)?),
            "optimize" => Job::Optimize(Box::new(optimize_settings(settings, dir)?)),
            other => {
                return Err(Error::invalid(
                    "job",
                    format!("\"{other}\""),
                    "must be analyze, simulate or optimize",
                ))
            }
        };
        let combine = match f.combine.as_deref() {
            None | Some("product") => Combine::Product,
            Some("zip") => Combine::Zip,
            Some(other) => {
                return Err(Error::invalid(
                    "combine",
                    format!("\"{other}\""),
                    "must be product or zip",
                ))
            }
        };
        if f.axis.is_empty() {
            return Err(Error::invalid(
                "axis",
                "nothing",
                "a sweep needs at least one [[axis]]",
            ));
        }
        let mut axes: Vec<Axis> = Vec::new();
        for (i, a) in f.axis.into_iter().enumerate() {
            let written = format!("\"{}\"", crate::io::escape_controls(&a.field));
            let axis = Axis::new(a, &format!("axis[{}]", i + 1))?;
            // Fields compare by what they set (path and entry), not by how they are written:
            // `gait.period` and `gait.period ` are one field, and a whole list overlaps each
            // of its entries (the row would show a value that one entry does not have).
            if let Some((j, b)) = axes.iter().enumerate().find(|(_, b)| b.overlaps(&axis)) {
                let reason = if b.index == axis.index {
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
        let spec = SweepSpec {
            model,
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
    fn check_job(&self) -> Result<()> {
        match &self.job {
            Job::Analyze => Ok(()),
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

    /// The model file of a point: the base with each axis's value set. Errors name the axis's
    /// field (e.g. an index beyond the list, a non-integer block count) or the model's.
    pub fn model_at(&self, point: &Point) -> Result<ModelFile> {
        let mut table = self.model.clone();
        // Plain fields first, so that an indexed entry is expanded with the point's N.
        let mut order: Vec<usize> = (0..self.axes.len()).collect();
        order.sort_by_key(|&j| self.axes[j].index.is_some());
        for j in order {
            self.axes[j].set(&mut table, point.values[j])?;
        }
        model_of(&table, &self.model_dir)
    }
}

/// A model file from its TOML table.
fn model_of(table: &toml::Table, dir: &Path) -> Result<ModelFile> {
    let mut m: ModelFile = toml::Value::Table(table.clone())
        .try_into()
        .map_err(|e| toml_err("model", e))?;
    m.base_dir = dir.to_path_buf();
    Ok(m)
}

impl Axis {
    fn new(a: AxisFile, name: &str) -> Result<Self> {
        let (path, index) = parse_field(&a.field, &format!("{name}.field"))?;
        let key = path.join(".");
        // The column name: the field as it is meant, whatever the spaces it was written with.
        let field = match index {
            Some(i) => format!("{key}[{i}]"),
            None => key.clone(),
        };
        let per_link = match FIELDS.iter().find(|(f, _)| *f == key) {
            Some((_, list)) => *list,
            None => {
                let known: Vec<&str> = FIELDS.iter().map(|(f, _)| *f).collect();
                return Err(Error::invalid(
                    format!("{name}.field"),
                    &a.field,
                    format!("must be a numeric model field: {}", known.join(", ")),
                ));
            }
        };
        if index.is_some() && per_link.is_none() {
            return Err(Error::invalid(
                format!("{name}.field"),
                &a.field,
                "is a number, not a list: it takes no index",
            ));
        }
        if index.is_none() && key == "simulation.initial_state" {
            return Err(Error::invalid(
                format!("{name}.field"),
                &a.field,
                "is a list: give one entry, e.g. simulation.initial_state[1]",
            ));
        }
        let values = match (a.values, a.range) {
            (Some(v), None) => v,
            (None, Some(r)) => range_values(&r, &format!("{name}.range"))?,
            _ => {
                return Err(Error::invalid(
                    name,
                    &a.field,
                    "give either values = [...] or range = { from, to, count, scale }",
                ))
            }
        };
        if values.is_empty() {
            return Err(Error::invalid(
                format!("{name}.values"),
                "[]",
                "needs at least one value",
            ));
        }
        if values.len() > MAX_POINTS {
            return Err(Error::invalid(
                format!("{name}.values"),
                format!("{} values", values.len()),
                format!("at most {MAX_POINTS} (the most points a sweep may have)"),
            ));
        }
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("{name}.values"),
                v,
                "must be finite",
            ));
        }
        if path == ["crawler", "blocks"] {
            if let Some(v) = values.iter().find(|&&v| block_count(v).is_err()) {
                let reason = block_count(*v).err().unwrap_or_default();
                return Err(Error::invalid(format!("{name}.values"), v, reason));
            }
        }
        Ok(Axis {
            field,
            values,
            path,
            index,
            per_link,
        })
    }

    /// Whether this axis and `other` set the same number: the same field and entry, or a whole
    /// list and one of its entries.
    fn overlaps(&self, other: &Axis) -> bool {
        self.path == other.path
            && (self.index == other.index || self.index.is_none() || other.index.is_none())
    }

    /// Sets this axis's field to `v` in a model table.
    fn set(&self, table: &mut toml::Table, v: f64) -> Result<()> {
        let bad = |reason: String| Error::invalid(&self.field, v, reason);
        let (key, parents) = self.path.split_last().expect("a field has a key");
        let links_blocks = |t: &toml::Table| -> Option<usize> {
            let n = t.get("crawler")?.get("blocks")?.as_integer()?;
            let n = usize::try_from(n).ok()?;
            Some(if self.per_link == Some(true) {
                n.saturating_sub(1)
            } else {
                n
            })
        };
        let len = links_blocks(table);
        let mut t = &mut *table;
        for p in parents {
            t = t
                .entry(p.clone())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .ok_or_else(|| bad(format!("{p} is not a table in the base model")))?;
        }
        let integer = self.path == ["crawler", "blocks"];
        let value = if integer {
            toml::Value::Integer(block_count(v).map_err(bad)?)
        } else {
            toml::Value::Float(v)
        };
        let Some(i) = self.index else {
            t.insert(key.clone(), value);
            return Ok(());
        };
        let entry = t.get(key).cloned();
        let mut list = match entry {
            Some(toml::Value::Array(a)) => a,
            // A number for every entry: expanded to one per link / block.
            Some(one @ (toml::Value::Float(_) | toml::Value::Integer(_))) => {
                let n = len.ok_or_else(|| bad("the base model has no crawler.blocks".into()))?;
                vec![one; n]
            }
            None if self.path == ["simulation", "initial_state"] => {
                let n = len.ok_or_else(|| bad("the base model has no crawler.blocks".into()))?;
                vec![toml::Value::Float(0.0); n]
            }
            _ => {
                return Err(bad(format!(
                    "the base model has no number or list {}",
                    self.path.join(".")
                )))
            }
        };
        if i == 0 || i > list.len() {
            return Err(bad(format!(
                "entry {i} does not exist: the list has {} entries (numbered from 1)",
                list.len()
            )));
        }
        list[i - 1] = value;
        t.insert(key.clone(), toml::Value::Array(list));
        Ok(())
    }
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

/// A value of a `crawler.blocks` axis as the block count, or why it is none: a whole number
/// from 2 to [`crate::io::MAX_BLOCKS`] (the model file's own range).
fn block_count(v: f64) -> std::result::Result<i64, String> {
    let max = crate::io::MAX_BLOCKS;
    if v.fract() != 0.0 {
        return Err("must be a whole number of blocks".into());
    }
    if !(2.0..=max as f64).contains(&v) {
        return Err(format!("must be in 2..={max} (blocks of a crawler)"));
    }
    Ok(v as i64)
}

/// `a.b.c` or `a.b.c[i]` (1-based i) as its path and index; spaces around the parts and the
/// index are not part of the field (`gait.period ` is `gait.period`).
fn parse_field(s: &str, name: &str) -> Result<(Vec<String>, Option<usize>)> {
    let bad = |reason: &str| Error::invalid(name, s, reason);
    let s = s.trim();
    let (path, index) = match s.strip_suffix(']') {
        Some(head) => {
            let (p, i) = head
                .split_once('[')
                .ok_or_else(|| bad("an index is written field[i]"))?;
            let i: usize = i
                .trim()
                .parse()
                .map_err(|_| bad("the index must be a whole number from 1"))?;
            if i == 0 {
                return Err(bad("entries are numbered from 1"));
            }
            (p, Some(i))
        }
        None => (s, None),
    };
    let parts: Vec<String> = path.split('.').map(|p| p.trim().to_string()).collect();
    if parts.len() < 2 || parts.iter().any(String::is_empty) {
        return Err(bad("must be section.key, e.g. crawler.mu_backward"));
    }
    Ok((parts, index))
}

/// The values of a range: `count` points from `from` to `to`, both included, equally spaced
/// (`linear`) or in ratio (`log`).
fn range_values(r: &RangeFile, name: &str) -> Result<Vec<f64>> {
    if !r.from.is_finite() || !r.to.is_finite() {
        return Err(Error::invalid(
            name,
            format!("{} to {}", r.from, r.to),
            "from and to must be finite",
        ));
    }
    if r.count < 1 || r.count as usize > MAX_POINTS {
        return Err(Error::invalid(
            format!("{name}.count"),
            r.count,
            format!("must be from 1 to {MAX_POINTS}"),
        ));
    }
    let n = r.count as usize;
    if n == 1 {
        if r.from != r.to {
            return Err(Error::invalid(
                format!("{name}.count"),
                1,
                "one point needs from = to",
            ));
        }
        return Ok(vec![r.from]);
    }
    let t = |i: usize| i as f64 / (n - 1) as f64;
    // Weighted ends, not from + step * i: 2 to 20 in 6 gives 12.8, not 12.799999999999999.
    let (a, b) = (r.from, r.to);
    let lin = |i: usize| ((n - 1 - i) as f64 * a + i as f64 * b) / (n - 1) as f64;
    let mut v: Vec<f64> = match r.scale.as_deref() {
        None | Some("linear") => (0..n).map(lin).collect(),
        Some("log") => {
            if r.from <= 0.0 || r.to <= 0.0 {
                return Err(Error::invalid(
                    format!("{name}.from"),
                    format!("{} to {}", r.from, r.to),
                    "scale = \"log\" needs positive ends",
                ));
            }
            let (a, b) = (r.from.ln(), r.to.ln());
            (0..n).map(|i| (a + (b - a) * t(i)).exp()).collect()
        }
        Some(other) => {
            return Err(Error::invalid(
                format!("{name}.scale"),
                format!("\"{other}\""),
                "must be linear or log",
            ))
        }
    };
    // The ends exactly as written.
    v[0] = r.from;
    v[n - 1] = r.to;
    Ok(v)
}
