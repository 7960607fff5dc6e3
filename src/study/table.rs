//! The table of a sweep: one row per point, as CSV or JSON Lines, appended and flushed as each
//! point finishes; read back for `--resume`, merged from shards, plotted.

use super::run::{Row, Shard};
use super::spec::SweepSpec;
use crate::error::{Error, Result};
use crate::io::{read_input_text, AtomicFile, MAX_RESULT_BYTES};
use std::collections::{BTreeMap, BTreeSet};
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// The columns after the axes (those of [`Row`], the same for both kinds of problem).
pub const RESULT_COLUMNS: [&str; 10] = [
    "objective",
    "displacement_per_period",
    "method",
    "certificate",
    "gap",
    "bound",
    "status",
    "verdict",
    "seconds",
    "error",
];

/// The file format of a table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Comma-separated values with a header line.
    Csv,
    /// One JSON object per line.
    JsonLines,
}

impl Format {
    /// JSON Lines for `.jsonl`, `.ndjson` and `.json`, CSV otherwise.
    pub fn of(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some("jsonl" | "ndjson" | "json") => Format::JsonLines,
            _ => Format::Csv,
        }
    }
}

/// The column names of a sweep's table: `point`, one per axis (its field), then
/// [`RESULT_COLUMNS`].
pub fn header(spec: &SweepSpec) -> Vec<String> {
    std::iter::once("point".to_string())
        .chain(spec.axes.iter().map(|a| a.field.clone()))
        .chain(RESULT_COLUMNS.iter().map(|c| c.to_string()))
        .collect()
}

/// A number as written: the shortest text that reads back to the same f64 (`-0` as `0`, as
/// every other output writes it).
fn num(v: f64) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    // Debug: exact, and with an exponent for tiny and huge values (`4e-15`, not 0.000...).
    let s = format!("{v:?}");
    s.strip_suffix(".0").map_or(s.clone(), str::to_string)
}

fn opt(v: Option<f64>) -> String {
    v.map(num).unwrap_or_default()
}

/// The cells of a row, in the order of [`header`].
fn cells(row: &Row) -> Vec<String> {
    let mut c = vec![row.point.to_string()];
    c.extend(row.values.iter().map(|v| num(*v)));
    c.extend([
        opt(row.objective),
        opt(row.displacement_per_period),
        row.method.clone().unwrap_or_default(),
        row.certificate.clone().unwrap_or_default(),
        opt(row.gap),
        opt(row.bound),
        row.status.clone(),
        row.verdict.clone().unwrap_or_default(),
        num(row.seconds),
        row.error.clone().unwrap_or_default(),
    ]);
    c
}

/// A row as one line of `format` (with its newline).
pub fn line(row: &Row, header: &[String], format: Format) -> String {
    match format {
        Format::Csv => {
            let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
            w.write_record(cells(row)).expect("in memory");
            String::from_utf8(w.into_inner().expect("in memory")).expect("UTF-8 cells")
        }
        Format::JsonLines => {
            let json_num = |v: f64| {
                if v.is_finite() {
                    num(v)
                } else {
                    "null".into()
                }
            };
            let json_opt = |v: Option<f64>| v.map_or("null".into(), json_num);
            let json_str = |s: &Option<String>| {
                s.as_ref().map_or("null".into(), |s| {
                    serde_json::to_string(s).expect("a string serialises")
                })
            };
            let mut parts = vec![format!("\"point\":{}", row.point)];
            for (name, v) in header[1..].iter().zip(&row.values) {
                parts.push(format!(
                    "{}:{}",
                    serde_json::to_string(name).expect("a string serialises"),
                    json_num(*v)
                ));
            }
            parts.extend([
                format!("\"objective\":{}", json_opt(row.objective)),
                format!(
                    "\"displacement_per_period\":{}",
                    json_opt(row.displacement_per_period)
                ),
                format!("\"method\":{}", json_str(&row.method)),
                format!("\"certificate\":{}", json_str(&row.certificate)),
                format!("\"gap\":{}", json_opt(row.gap)),
                format!("\"bound\":{}", json_opt(row.bound)),
                format!("\"status\":{}", json_str(&Some(row.status.clone()))),
                format!("\"verdict\":{}", json_str(&row.verdict)),
                format!("\"seconds\":{}", json_num(row.seconds)),
                format!("\"error\":{}", json_str(&row.error)),
            ]);
            format!("{{{}}}\n", parts.join(","))
        }
    }
}

/// The header line of a CSV table (JSON Lines has none).
fn header_line(header: &[String]) -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    w.write_record(header).expect("in memory");
    String::from_utf8(w.into_inner().expect("in memory")).expect("UTF-8 cells")
}

/// The rows of a table file (CSV or JSON Lines by its extension, [`Format::of`]), checked
/// against the sweep's columns; a last line without its newline (a run killed while writing)
/// is left out. The second value is the length of the complete lines, in bytes.
pub fn read_table(path: &Path, header: &[String]) -> Result<(Vec<Row>, usize)> {
    let text = read_input_text(path, MAX_RESULT_BYTES)?;
    let complete = text.rfind('\n').map_or(0, |i| i + 1);
    let io = |reason: String| Error::Io {
        path: path.display().to_string(),
        reason,
    };
    // The torn last line must be the start of a line this sweep writes: what is cut off is
    // then only what a killed run left half-written, never a file that is not this table.
    let tail = &text[complete..];
    if !torn_fits(tail, complete == 0, Format::of(path), header) {
        let shown: String = tail.chars().take(40).collect();
        return Err(io(format!(
            "is not a table of this sweep: its last line \"{}{}\" (without a newline) is not \
             the beginning of {}; the file is left as it is",
            crate::io::escape_controls(&shown),
            if tail.chars().count() > 40 { "..." } else { "" },
            if complete == 0 && Format::of(path) == Format::Csv {
                "this sweep's header"
            } else {
                "a row"
            }
        )));
    }
    let text = &text[..complete];
    let axes = header.len() - 1 - RESULT_COLUMNS.len();
    let mut rows = Vec::new();
    match Format::of(path) {
        Format::Csv => {
            if text.is_empty() {
                return Ok((rows, 0));
            }
            let mut r = csv::ReaderBuilder::new()
                .has_headers(true)
                .from_reader(text.as_bytes());
            let found: Vec<String> = r
                .headers()
                .map_err(|e| io(format!("not a sweep table: {e}")))?
                .iter()
                .map(str::to_string)
                .collect();
            if found != header {
                return Err(io(format!(
                    "its columns ({}) are not this sweep's ({})",
                    found.join(","),
                    header.join(",")
                )));
            }
            for (i, rec) in r.records().enumerate() {
                let rec = rec.map_err(|e| io(format!("line {}: {e}", i + 2)))?;
                let cell: Vec<&str> = rec.iter().collect();
                rows.push(row_of(&cell, axes).map_err(|e| io(format!("line {}: {e}", i + 2)))?);
            }
        }
        Format::JsonLines => {
            for (i, l) in text.lines().enumerate() {
                if l.trim().is_empty() {
                    continue;
                }
                let v: serde_json::Map<String, serde_json::Value> = serde_json::from_str(l)
                    .map_err(|e| io(format!("line {}: not a JSON object: {e}", i + 1)))?;
                let mut cell = Vec::new();
                for name in header {
                    let c = v.get(name).ok_or_else(|| {
                        io(format!(
                            "line {}: no column {name}: not this sweep's",
                            i + 1
                        ))
                    })?;
                    cell.push(match c {
                        serde_json::Value::Null => String::new(),
                        serde_json::Value::String(s) => s.clone(),
                        other => other.to_string(),
                    });
                }
                if v.len() != header.len() {
                    return Err(io(format!(
                        "line {}: {} columns, this sweep has {}",
                        i + 1,
                        v.len(),
                        header.len()
                    )));
                }
                let cell: Vec<&str> = cell.iter().map(String::as_str).collect();
                rows.push(row_of(&cell, axes).map_err(|e| io(format!("line {}: {e}", i + 1)))?);
            }
        }
    }
    Ok((rows, complete))
}

/// Whether `tail`, a last line without its newline, is the beginning of a line of this sweep's
/// table in `format`: of the CSV header when it is the first line, else of a row (`point` then
/// a comma in CSV; `{"point":` then a digit in JSON Lines).
fn torn_fits(tail: &str, first: bool, format: Format, header: &[String]) -> bool {
    let prefix_of = |s: &str| s.starts_with(tail) || tail.starts_with(s);
    match format {
        Format::Csv if first => header_line(header).starts_with(tail),
        Format::Csv => {
            let digits = tail.bytes().take_while(u8::is_ascii_digit).count();
            digits == tail.len() || (digits > 0 && tail.as_bytes()[digits] == b',')
        }
        Format::JsonLines => {
            let start = "{\"point\":";
            match tail.strip_prefix(start) {
                Some(rest) => rest.is_empty() || rest.as_bytes()[0].is_ascii_digit(),
                None => prefix_of(start),
            }
        }
    }
}

fn row_of(c: &[&str], axes: usize) -> std::result::Result<Row, String> {
    if c.len() != axes + 1 + RESULT_COLUMNS.len() {
        return Err(format!(
            "{} cells, expected {}",
            c.len(),
            axes + 1 + RESULT_COLUMNS.len()
        ));
    }
    let f = |s: &str| -> std::result::Result<f64, String> {
        s.parse().map_err(|_| format!("`{s}` is not a number"))
    };
    let of = |s: &str| -> std::result::Result<Option<f64>, String> {
        if s.is_empty() {
            Ok(None)
        } else {
            f(s).map(Some)
        }
    };
    let os = |s: &str| (!s.is_empty()).then(|| s.to_string());
    let r = &c[axes + 1..];
    Ok(Row {
        point: c[0]
            .parse()
            .map_err(|_| format!("point `{}` is not a whole number", c[0]))?,
        values: c[1..=axes]
            .iter()
            .map(|s| f(s))
            .collect::<std::result::Result<_, _>>()?,
        objective: of(r[0])?,
        displacement_per_period: of(r[1])?,
        method: os(r[2]),
        certificate: os(r[3]),
        gap: of(r[4])?,
        bound: of(r[5])?,
        status: r[6].to_string(),
        verdict: os(r[7]),
        seconds: f(r[8])?,
        error: os(r[9]),
    })
}

/// Checks that each row is a point of `spec` with that point's values (a table of another
/// sweep, or of an edited one, is refused naming the row), and returns their ids; a point
/// twice is an error too.
pub fn check_rows(spec: &SweepSpec, rows: &[Row], what: &Path) -> Result<BTreeSet<usize>> {
    let n = spec.len()?;
    let mut ids = BTreeSet::new();
    for r in rows {
        let bad = |reason: String| Error::Io {
            path: what.display().to_string(),
            reason: format!("point {}: {reason}", r.point),
        };
        if r.point >= n {
            return Err(bad(format!("the sweep has points 0..{}", n - 1)));
        }
        if spec.point(r.point).values != r.values {
            return Err(bad(format!(
                "its values {:?} are not the sweep's {:?}: a table of another sweep",
                r.values,
                spec.point(r.point).values
            )));
        }
        if !ids.insert(r.point) {
            return Err(bad("is there twice".into()));
        }
    }
    Ok(ids)
}

/// Where the rows of a sweep go: a file opened for appending (a new file gets the header), or
/// standard output. Each row is written whole and flushed at once, so that a crash loses no
/// finished point.
pub struct TableWriter {
    out: Box<dyn std::io::Write + Send>,
    header: Vec<String>,
    format: Format,
    path: Option<PathBuf>,
}

impl TableWriter {
    /// Opens `path` (CSV or JSON Lines by its extension; `None`: standard output in
    /// `format`). With `resume`, an existing file's rows are read and checked against `spec`
    /// and their points returned (to skip), a torn last line cut off; without it an existing
    /// non-empty file is refused (so that a finished sweep is not overwritten by mistake).
    pub fn open(
        spec: &SweepSpec,
        path: Option<&Path>,
        format: Format,
        resume: bool,
    ) -> Result<(Self, BTreeSet<usize>)> {
        let header = header(spec);
        // Where the rows go, the points already done, and whether the table starts here (and
        // so takes the CSV header line).
        let (mut out, done, fresh): (Box<dyn std::io::Write + Send>, _, _) = match path {
            None => (Box::new(std::io::stdout()), BTreeSet::new(), true),
            Some(path) => Self::open_file(spec, path, &header, resume)?,
        };
        let format = path.map_or(format, Format::of);
        if fresh && format == Format::Csv {
            let shown = path.unwrap_or(Path::new("<stdout>"));
            write_flush(&mut out, &header_line(&header), shown)?;
        }
        let w = TableWriter {
            out,
            header,
            format,
            path: path.map(Path::to_path_buf),
        };
        Ok((w, done))
    }

    /// The table file `path`: a device, FIFO or socket (or this process's standard output) is
    /// written straight into, as every output is (`AtomicFile`), and has no table to continue;
    /// a regular file is created, or continued with `resume` (its rows read back, checked
    /// against the sweep, a torn last line cut off).
    #[allow(clippy::type_complexity)]
    fn open_file(
        spec: &SweepSpec,
        path: &Path,
        header: &[String],
        resume: bool,
    ) -> Result<(Box<dyn std::io::Write + Send>, BTreeSet<usize>, bool)> {
        let io = |reason: String| Error::Io {
            path: path.display().to_string(),
            reason,
        };
        if let Some(stream) = AtomicFile::open_stream(path)? {
            if resume {
                return Err(io(
                    "is not a regular file: --resume continues a table file (a device, FIFO \
                     or socket is only written into)"
                        .into(),
                ));
            }
            return Ok((Box::new(stream), BTreeSet::new(), true));
        }
        let exists = std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.len() > 0);
        let mut done = BTreeSet::new();
        let mut keep = 0;
        if exists {
            if !resume {
                return Err(io(
                    "exists: pass --resume to continue it, or remove it to start over".into(),
                ));
            }
            let (rows, complete) = read_table(path, header)?;
            done = check_rows(spec, &rows, path)?;
            keep = complete;
        }
        AtomicFile::check(path)?;
        let file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| io(format!("cannot write: {e}")))?;
        // A torn last line (a run killed while writing it) is cut off.
        file.set_len(keep as u64)
            .map_err(|e| io(format!("cannot write: {e}")))?;
        Ok((Box::new(file), done, keep == 0))
    }

    /// Appends one row and flushes it.
    pub fn write(&mut self, row: &Row) -> Result<()> {
        let l = line(row, &self.header, self.format);
        let p = self.path.clone().unwrap_or_else(|| "<stdout>".into());
        write_flush(&mut self.out, &l, &p)
    }
}

fn write_flush(out: &mut dyn std::io::Write, text: &str, path: &Path) -> Result<()> {
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: format!("cannot write: {e}"),
        })
}

/// Writes the full result of point `id` as `DIR/point-ID.json` (atomically).
pub fn write_full(dir: &Path, id: usize, value: &serde_json::Value) -> Result<()> {
    let path = dir.join(format!("point-{id}.json"));
    let mut f = AtomicFile::create(&path)?;
    serde_json::to_writer(f.writer(), value)
        .map_err(std::io::Error::from)
        .and_then(|()| writeln!(f.writer()))
        .map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: format!("cannot write: {e}"),
        })?;
    f.commit()
}

/// What [`merge`] found wrong: missing points (grouped by shard when the shard count is
/// known), points given twice, input files that do not exist.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MergeProblems {
    /// Input files that could not be read, with the reason.
    pub unreadable: Vec<String>,
    /// Shards (1-based, of `shards`) with missing points, and those points.
    pub missing: BTreeMap<usize, Vec<usize>>,
    /// Points found more than once, with the files holding them.
    pub duplicates: BTreeMap<usize, Vec<String>>,
}

impl MergeProblems {
    /// Whether nothing is wrong.
    pub fn is_empty(&self) -> bool {
        self.unreadable.is_empty() && self.missing.is_empty() && self.duplicates.is_empty()
    }

    /// One line per problem.
    pub fn lines(&self, shards: usize) -> Vec<String> {
        let mut out: Vec<String> = self.unreadable.clone();
        for (s, ids) in &self.missing {
            let shown: Vec<String> = ids.iter().take(10).map(usize::to_string).collect();
            let more = if ids.len() > 10 { ", ..." } else { "" };
            let all = if shards > 1 {
                format!("shard {s}/{shards}: ")
            } else {
                String::new()
            };
            out.push(format!(
                "{all}{} point(s) missing: {}{more}",
                ids.len(),
                shown.join(", ")
            ));
        }
        for (id, files) in &self.duplicates {
            out.push(format!(
                "point {id} appears {} times (in {})",
                files.len(),
                files.join(", ")
            ));
        }
        out
    }
}

/// Joins the tables of shards of `spec` into one, sorted by point. Every point must be present
/// exactly once: otherwise the problems are returned (missing points grouped by their shard of
/// `shards`, 1 when unknown), and nothing is written.
pub fn merge(
    spec: &SweepSpec,
    inputs: &[PathBuf],
    shards: usize,
) -> Result<std::result::Result<Vec<Row>, MergeProblems>> {
    if shards == 0 {
        return Err(Error::invalid("shards", 0, "must be at least 1"));
    }
    let header = header(spec);
    let n = spec.len()?;
    let mut p = MergeProblems::default();
    let mut by_id: BTreeMap<usize, (Row, Vec<String>)> = BTreeMap::new();
    for path in inputs {
        let name = path.display().to_string();
        let rows = match read_table(path, &header) {
            Ok((rows, _)) => rows,
            Err(e) => {
                p.unreadable.push(e.to_string());
                continue;
            }
        };
        for r in rows {
            if r.point >= n || spec.point(r.point).values != r.values {
                return Err(Error::Io {
                    path: name,
                    reason: format!("point {}: not a point of this sweep", r.point),
                });
            }
            by_id
                .entry(r.point)
                .or_insert_with(|| (r.clone(), Vec::new()))
                .1
                .push(name.clone());
        }
    }
    for id in 0..n {
        match by_id.get(&id) {
            None => p
                .missing
                .entry(Shard::of(id, shards).index)
                .or_default()
                .push(id),
            Some((_, files)) if files.len() > 1 => {
                p.duplicates.insert(id, files.clone());
            }
            _ => {}
        }
    }
    if !p.is_empty() {
        return Ok(Err(p));
    }
    Ok(Ok(by_id.into_values().map(|(r, _)| r).collect()))
}

/// Writes rows as a whole table (atomically): CSV or JSON Lines by the extension of `path`.
pub fn write_table(spec: &SweepSpec, rows: &[Row], path: &Path) -> Result<()> {
    let header = header(spec);
    let format = Format::of(path);
    let mut f = AtomicFile::create(path)?;
    let mut text = String::new();
    if format == Format::Csv {
        text.push_str(&header_line(&header));
    }
    for r in rows {
        text.push_str(&line(r, &header, format));
    }
    f.writer()
        .write_all(text.as_bytes())
        .map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: format!("cannot write: {e}"),
        })?;
    f.commit()
}

/// The keys of a JSON object in the order written.
struct KeysInOrder(Vec<String>);

impl<'de> serde::Deserialize<'de> for KeysInOrder {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = KeysInOrder;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut m: A,
            ) -> std::result::Result<KeysInOrder, A::Error> {
                let mut keys = Vec::new();
                while let Some(k) = m.next_key::<String>()? {
                    m.next_value::<serde::de::IgnoredAny>()?;
                    keys.push(k);
                }
                Ok(KeysInOrder(keys))
            }
        }
        d.deserialize_map(V)
    }
}

/// A sweep table read without its sweep file: the axes from its columns (CSV header, or the
/// keys of the first JSON line in order), and its rows.
pub fn read_any_table(path: &Path) -> Result<(Vec<String>, Vec<Row>)> {
    let text = read_input_text(path, MAX_RESULT_BYTES)?;
    let first = text.lines().next().unwrap_or("");
    let header: Vec<String> = match Format::of(path) {
        Format::Csv => csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(first.as_bytes())
            .records()
            .next()
            .and_then(|r| r.ok())
            .map(|r| r.iter().map(str::to_string).collect())
            .unwrap_or_default(),
        Format::JsonLines => serde_json::from_str::<KeysInOrder>(first)
            .map(|k| k.0)
            .unwrap_or_default(),
    };
    let axes = axes_of_header(&header, path)?;
    let (rows, _) = read_table(path, &header)?;
    Ok((axes, rows))
}

/// The axes of a table's header (the columns between `point` and [`RESULT_COLUMNS`]), or an
/// error naming the file when it is not a sweep's table.
pub fn axes_of_header(header: &[String], path: &Path) -> Result<Vec<String>> {
    let n = header.len();
    let ok = n > 1 + RESULT_COLUMNS.len()
        && header[0] == "point"
        && header[n - RESULT_COLUMNS.len()..]
            .iter()
            .zip(RESULT_COLUMNS)
            .all(|(a, b)| a == b);
    if !ok {
        return Err(Error::Io {
            path: path.display().to_string(),
            reason: format!(
                "not a sweep table: its columns must be point, the axes, then {}",
                RESULT_COLUMNS.join(",")
            ),
        });
    }
    Ok(header[1..n - RESULT_COLUMNS.len()].to_vec())
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn numbers_read_back_and_negative_zero_is_zero() {
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(0.0), "0");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(-3.0), "-3");
        assert_eq!(num(4e-15), "4e-15");
        for v in [0.1, -1.0 / 3.0, 1e300, 5e-324] {
            assert_eq!(num(v).parse::<f64>().unwrap(), v);
        }
    }
}
