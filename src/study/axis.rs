//! The axes of a sweep: which numeric fields of the base problem file an axis may set (those of
//! a crawler's model file, or of a general problem file (P), theory §11), the values it takes
//! (a list or a range), and the setting of one value into the file's TOML table.

use crate::error::{Error, Result};
use serde::Deserialize;

/// Most points a sweep may have (each is a row kept in memory while the sweep runs), and so
/// most values on one axis.
pub const MAX_POINTS: usize = 1_000_000;

/// The two kinds of base problem file a sweep runs over ([`crate::io::ProblemFile`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A crawler's model file.
    Crawler,
    /// A general problem file (P) (`[sweeping_process]`, theory §11).
    General,
}

impl Kind {
    /// The kind of a base file's table: general when it has `[sweeping_process]`, as
    /// [`crate::io::ProblemFile::load`] tells them apart.
    pub fn of(table: &toml::Table) -> Self {
        if table.contains_key("sweeping_process") {
            Kind::General
        } else {
            Kind::Crawler
        }
    }

    /// The fields an axis may set in a file of this kind.
    fn fields(self) -> &'static [(&'static str, Shape)] {
        match self {
            Kind::Crawler => CRAWLER_FIELDS,
            Kind::General => GENERAL_FIELDS,
        }
    }
}

/// What a field holds, and so which indices an axis on it takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shape {
    /// A number: no index.
    Number,
    /// A crawler's per-link list (or one number for every link): one index or none.
    PerLink,
    /// A crawler's per-block list (or one number for every block): one index or none.
    PerBlock,
    /// A general file's list: one index, or none (every entry set to the value).
    List,
    /// A general file's matrix (rows of lists): two indices, `field[i][j]`.
    Matrix,
    /// A symmetric matrix (`R` of a matrix cost): `[i][j]` sets `[j][i]` too.
    Symmetric,
}

/// The numeric fields of a crawler's model file.
const CRAWLER_FIELDS: &[(&str, Shape)] = &[
    ("crawler.blocks", Shape::Number),
    ("crawler.stiffness", Shape::PerLink),
    ("crawler.mu_forward", Shape::PerBlock),
    ("crawler.mu_backward", Shape::PerBlock),
    ("gait.period", Shape::Number),
    ("gait.max_actuator_speed", Shape::PerLink),
    ("gait.max_total_variation", Shape::Number),
    ("gait.cost.weight", Shape::Number),
    ("actuation.period", Shape::Number),
    ("actuation.amplitude", Shape::PerLink),
    ("actuation.phase_deg", Shape::PerLink),
    ("actuation.mean", Shape::PerLink),
    ("simulation.initial_state", Shape::PerLink),
];

/// The numeric fields of a general problem file ([`crate::io::GeneralFile`]): C's faces and
/// offsets `c_j`, the dynamics `A`, `B`, `b`, the control set U, `f1`'s weights, `f2`'s
/// weight or matrix, the period, `x(0)` of a Cauchy problem, and the `[input]` to simulate.
const GENERAL_FIELDS: &[(&str, Shape)] = &[
    ("sweeping_process.normals", Shape::Matrix),
    ("sweeping_process.offsets", Shape::List),
    ("dynamics.A", Shape::Matrix),
    ("dynamics.B", Shape::Matrix),
    ("dynamics.b", Shape::List),
    ("control.lower", Shape::List),
    ("control.upper", Shape::List),
    ("control.G", Shape::Matrix),
    ("control.h", Shape::List),
    ("objective.face_weights", Shape::List),
    ("objective.reaction_weights", Shape::List),
    ("objective.cost.weight", Shape::Number),
    ("objective.cost.matrix", Shape::Symmetric),
    ("problem.period", Shape::Number),
    ("problem.initial_state", Shape::List),
    ("input.times", Shape::List),
    ("input.values", Shape::Matrix),
];

/// One axis: a field of the base file and its values.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The field as meant, whatever spaces it was written with (`crawler.mu_backward`,
    /// `crawler.mu_backward[2]` for `" crawler.mu_backward[ 2 ]"`, `dynamics.A[1][2]`): the
    /// column name.
    pub field: String,
    /// Its values, in order.
    pub values: Vec<f64>,
    /// The path of tables and the key.
    path: Vec<String>,
    /// The 1-based entry: none, `[i]` of a list, `[i, j]` of a matrix.
    index: Vec<usize>,
    /// What the field holds.
    shape: Shape,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AxisFile {
    pub(super) field: String,
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

impl Axis {
    /// The axis `name` (`axis[i]`) of a file of `kind`: its field known and indexed as its
    /// shape takes, its values finite and each one the field can hold (errors name
    /// `axis[i].field` or `axis[i].values`).
    pub(super) fn new(a: AxisFile, name: &str, kind: Kind) -> Result<Self> {
        let (path, index) = parse_field(&a.field, &format!("{name}.field"))?;
        let key = path.join(".");
        // The column name: the field as it is meant, whatever the spaces it was written with.
        let field = index.iter().fold(key.clone(), |f, i| format!("{f}[{i}]"));
        let bad_field = |reason: String| Error::invalid(format!("{name}.field"), &a.field, reason);
        let shape = match kind.fields().iter().find(|(f, _)| *f == key) {
            Some((_, shape)) => *shape,
            None => {
                let known: Vec<&str> = kind.fields().iter().map(|(f, _)| *f).collect();
                let what = match kind {
                    Kind::Crawler => "a numeric model field",
                    Kind::General => "a numeric field of a general problem file",
                };
                return Err(bad_field(format!("must be {what}: {}", known.join(", "))));
            }
        };
        match (shape, index.len()) {
            (Shape::Number, 1..) => {
                return Err(bad_field(
                    "is a number, not a list: it takes no index".into(),
                ))
            }
            (Shape::PerLink | Shape::PerBlock | Shape::List, 2..) => {
                return Err(bad_field(format!(
                    "is a list: it takes one index, e.g. {key}[1]"
                )))
            }
            (Shape::Matrix | Shape::Symmetric, 0 | 1) => {
                return Err(bad_field(format!(
                    "is a matrix: give one entry, e.g. {key}[1][2]"
                )))
            }
            _ => {}
        }
        if index.is_empty() && key == "simulation.initial_state" {
            return Err(bad_field(
                "is a list: give one entry, e.g. simulation.initial_state[1]".into(),
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
        for &v in &values {
            if let Err(reason) = check_value(&key, v) {
                return Err(Error::invalid(format!("{name}.values"), v, reason));
            }
        }
        Ok(Axis {
            field,
            values,
            path,
            index,
            shape,
        })
    }

    /// Whether the axis is on a plain field (no index): set before the indexed ones, so that
    /// an entry of a crawler's list is expanded with the point's number of blocks.
    pub(super) fn is_plain(&self) -> bool {
        self.index.is_empty()
    }

    /// Whether this axis and `other` set the same number: the same field and entry (of a
    /// symmetric matrix, `[i][j]` and `[j][i]` alike), or a whole list and one of its entries.
    pub(super) fn overlaps(&self, other: &Axis) -> bool {
        self.path == other.path
            && (self.same_entry(other) || self.index.is_empty() || other.index.is_empty())
    }

    /// Whether the two axes name the same entry of a field (else, when they overlap, one is a
    /// whole list holding the other).
    pub(super) fn same_entry(&self, other: &Axis) -> bool {
        let entry = |a: &Axis| {
            let mut i = a.index.clone();
            if a.shape == Shape::Symmetric {
                i.sort_unstable();
            }
            i
        };
        self.path == other.path && entry(self) == entry(other)
    }

    /// Sets this axis's field to `v` in a file's table of `kind`.
    pub(super) fn set(&self, table: &mut toml::Table, v: f64, kind: Kind) -> Result<()> {
        match kind {
            Kind::Crawler => self.set_crawler(table, v),
            Kind::General => self.set_general(table, v),
        }
    }

    /// Sets a crawler's field (a table missing from the base is made; a per-link or
    /// per-block number is expanded to one entry per link / block before one is set).
    fn set_crawler(&self, table: &mut toml::Table, v: f64) -> Result<()> {
        let bad = |reason: String| Error::invalid(&self.field, v, reason);
        let (key, parents) = self.path.split_last().expect("a field has a key");
        let links_blocks = |t: &toml::Table| -> Option<usize> {
            let n = t.get("crawler")?.get("blocks")?.as_integer()?;
            let n = usize::try_from(n).ok()?;
            Some(if self.shape == Shape::PerLink {
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
        let Some(&i) = self.index.first() else {
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
        set_entry(&mut list, i, value).map_err(bad)?;
        t.insert(key.clone(), toml::Value::Array(list));
        Ok(())
    }

    /// Sets a general file's field: its table and the field must be in the base (but for
    /// `dynamics.A` and `dynamics.b`, which default to 0 there), each entry named must exist
    /// (the axes change numbers, never the dimensions); a list without an index has every
    /// entry set.
    fn set_general(&self, table: &mut toml::Table, v: f64) -> Result<()> {
        let bad = |reason: String| Error::invalid(&self.field, v, reason);
        let key = self.path.join(".");
        // n, for the zeros of an omitted A or b.
        let states = table
            .get("sweeping_process")
            .and_then(|s| s.get("normals"))
            .and_then(|n| n.as_array())
            .and_then(|rows| rows.first())
            .and_then(|r| r.as_array())
            .map_or(0, Vec::len);
        let (last, parents) = self.path.split_last().expect("a field has a key");
        let mut t = &mut *table;
        for p in parents {
            t = t
                .get_mut(p)
                .and_then(toml::Value::as_table_mut)
                .ok_or_else(|| bad(format!("the base problem has no table {p}")))?;
        }
        let zero = || toml::Value::Float(0.0);
        let absent = match key.as_str() {
            "dynamics.A" => Some(toml::Value::Array(vec![
                toml::Value::Array(vec![
                    zero();
                    states
                ]);
                states
            ])),
            "dynamics.b" => Some(toml::Value::Array(vec![zero(); states])),
            _ => None,
        };
        let current = t.get(last).cloned().or(absent).ok_or_else(|| {
            bad(format!(
                "the base problem has no {key} (an axis changes a number the file has)"
            ))
        })?;
        let value = toml::Value::Float(v);
        let new = match (self.shape, self.index.as_slice(), current) {
            (Shape::Number, [], toml::Value::Float(_) | toml::Value::Integer(_)) => value,
            (Shape::List, [], toml::Value::Array(a)) => toml::Value::Array(vec![value; a.len()]),
            (Shape::List, &[i], toml::Value::Array(mut a)) => {
                set_entry(&mut a, i, value).map_err(bad)?;
                toml::Value::Array(a)
            }
            (Shape::Matrix | Shape::Symmetric, &[i, j], toml::Value::Array(mut rows)) => {
                let mut put = |i: usize, j: usize| -> std::result::Result<(), String> {
                    let n = rows.len();
                    let row = rows
                        .get_mut(i.wrapping_sub(1))
                        .and_then(toml::Value::as_array_mut)
                        .ok_or_else(|| {
                            format!(
                                "row {i} does not exist: the matrix has {n} rows (numbered from 1)"
                            )
                        })?;
                    set_entry(row, j, value.clone())
                };
                put(i, j).map_err(bad)?;
                if self.shape == Shape::Symmetric && i != j {
                    put(j, i).map_err(bad)?;
                }
                toml::Value::Array(rows)
            }
            _ => {
                return Err(bad(format!(
                    "is not a {} in the base problem",
                    match self.shape {
                        Shape::Number => "number",
                        Shape::Matrix | Shape::Symmetric => "matrix",
                        _ => "list",
                    }
                )))
            }
        };
        t.insert(last.clone(), new);
        Ok(())
    }
}

/// Sets entry `i` (1-based) of a list, or says why it does not exist.
fn set_entry(
    list: &mut [toml::Value],
    i: usize,
    value: toml::Value,
) -> std::result::Result<(), String> {
    if i == 0 || i > list.len() {
        return Err(format!(
            "entry {i} does not exist: the list has {} entries (numbered from 1)",
            list.len()
        ));
    }
    list[i - 1] = value;
    Ok(())
}

/// Whether `v` is a value the field `key` can hold whatever the other fields are (checked
/// when the sweep file is read, so that no point runs with it): a whole number of blocks, a
/// positive period of (P), a non-negative weight of its quadratic cost.
fn check_value(key: &str, v: f64) -> std::result::Result<(), String> {
    match key {
        "crawler.blocks" => block_count(v).map(|_| ()),
        "problem.period" if v <= 0.0 => Err("must be positive (the period T)".into()),
        "objective.cost.weight" if v < 0.0 => {
            Err("must be non-negative (f2 = (c/2)|u|^2 convex)".into())
        }
        _ => Ok(()),
    }
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

/// `a.b.c`, `a.b.c[i]` or `a.b.c[i][j]` (1-based indices) as its path and indices; spaces
/// around the parts and the indices are not part of the field (`gait.period ` is
/// `gait.period`).
fn parse_field(s: &str, name: &str) -> Result<(Vec<String>, Vec<usize>)> {
    let bad = |reason: &str| Error::invalid(name, s, reason);
    let s = s.trim();
    let (path, mut rest) = match s.find('[') {
        Some(k) => (&s[..k], s[k..].trim()),
        None if s.ends_with(']') => return Err(bad("an index is written field[i]")),
        None => (s, ""),
    };
    let mut index = Vec::new();
    while !rest.is_empty() {
        let (i, after) = rest
            .strip_prefix('[')
            .and_then(|r| r.split_once(']'))
            .ok_or_else(|| bad("an index is written field[i] (or field[i][j] for a matrix)"))?;
        let i: usize = i
            .trim()
            .parse()
            .map_err(|_| bad("the index must be a whole number from 1"))?;
        if i == 0 {
            return Err(bad("entries are numbered from 1"));
        }
        index.push(i);
        rest = after.trim_start();
    }
    if index.len() > 2 {
        return Err(bad(
            "takes at most two indices: field[i], or field[i][j] of a matrix",
        ));
    }
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
