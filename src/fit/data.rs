//! A measured trajectory: times, actuator lengths and block positions, read from CSV text or
//! given as arrays, and checked before any fit (every refusal names the column and the row).

use crate::error::{Error, Result};

/// Fewest samples a fit accepts: a slide is seen at a sample whose two neighbouring intervals
/// both show the motion, so a fit needs at least three, and a handful more to say anything.
pub const MIN_SAMPLES: usize = 5;

/// A measured trajectory of a crawler with `N` blocks and `n = N - 1` links (theory §1): at
/// each time `t[i]` the actuator lengths `L_l(t_i)` and the block positions `X_b(t_i)` (one
/// frame, any origin). Times strictly increase; any sampling.
#[derive(Debug, Clone, PartialEq)]
pub struct FitData {
    /// Sample times, strictly increasing.
    pub t: Vec<f64>,
    /// `lengths[i][l]`: actuator length `L_(l+1)` at sample `i`.
    pub lengths: Vec<Vec<f64>>,
    /// `positions[i][b]`: position `X_(b+1)` at sample `i`.
    pub positions: Vec<Vec<f64>>,
}

/// The column names of a trajectory with `blocks` blocks: `t, L_1..L_n, X_1..X_N`.
pub fn column_names(blocks: usize) -> Vec<String> {
    let mut names = vec!["t".to_string()];
    names.extend((1..blocks).map(|l| format!("L_{l}")));
    names.extend((1..=blocks).map(|b| format!("X_{b}")));
    names
}

fn check_blocks(blocks: usize) -> Result<()> {
    if blocks < 2 {
        return Err(Error::invalid(
            "blocks",
            blocks,
            "a crawler needs at least 2 blocks",
        ));
    }
    Ok(())
}

impl FitData {
    /// A trajectory from arrays, checked ([`FitData::check`]): `lengths` has one row of `N - 1`
    /// values per sample and `positions` one row of `N` values, `N = blocks`.
    pub fn new(
        blocks: usize,
        t: Vec<f64>,
        lengths: Vec<Vec<f64>>,
        positions: Vec<Vec<f64>>,
    ) -> Result<Self> {
        check_blocks(blocks)?;
        for (name, rows, width) in [("L", &lengths, blocks - 1), ("X", &positions, blocks)] {
            if rows.len() != t.len() {
                return Err(Error::invalid(
                    name,
                    format!("{} rows", rows.len()),
                    format!("needs one row per time ({} times)", t.len()),
                ));
            }
            if let Some(i) = rows.iter().position(|r| r.len() != width) {
                return Err(Error::invalid(
                    format!("{name}, row {}", i + 1),
                    format!("{} values", rows[i].len()),
                    format!("needs {width} values ({blocks} blocks)"),
                ));
            }
        }
        let d = FitData {
            t,
            lengths,
            positions,
        };
        d.check()?;
        Ok(d)
    }

    /// Parses CSV text with the header `t,L_1,...,L_n,X_1,...,X_N` (columns in any order, each
    /// exactly once, no other column; `#` starts a comment line) for a crawler of `blocks`
    /// blocks. `name` (the file) prefixes the errors, which name the column and the row (data
    /// rows count from 1, the header is row 0).
    pub fn from_csv(text: &str, name: &str, blocks: usize) -> Result<Self> {
        check_blocks(blocks)?;
        let at = |what: String| format!("{name}: {what}");
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(false)
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .flexible(true)
            .from_reader(text.as_bytes());
        let mut records = rdr.records();
        let header = match records.next() {
            Some(Ok(h)) => h,
            Some(Err(e)) => return Err(Error::invalid(at("header".into()), "CSV", e.to_string())),
            None => {
                return Err(Error::invalid(
                    at("header".into()),
                    "nothing",
                    format!(
                        "the file is empty: expected the header {}",
                        column_names(blocks).join(",")
                    ),
                ))
            }
        };
        let header: Vec<String> = header.iter().map(str::to_string).collect();
        let wanted = column_names(blocks);
        let index = column_index(&header, &wanted, blocks, &at)?;
        let (mut t, mut lengths, mut positions) = (Vec::new(), Vec::new(), Vec::new());
        for (i, rec) in records.enumerate() {
            let row = i + 1;
            let vals = row_values(rec, row, &header, &index, &wanted, &at)?;
            t.push(vals[0]);
            lengths.push(vals[1..blocks].to_vec());
            positions.push(vals[blocks..].to_vec());
        }
        let d = FitData {
            t,
            lengths,
            positions,
        };
        d.check().map_err(|e| match e {
            Error::InvalidParameter {
                field,
                value,
                reason,
            } => Error::InvalidParameter {
                field: at(field),
                value,
                reason,
            },
            other => other,
        })?;
        Ok(d)
    }

    /// Number of samples.
    pub fn samples(&self) -> usize {
        self.t.len()
    }

    /// Number of blocks `N`.
    pub fn blocks(&self) -> usize {
        self.positions.first().map_or(0, Vec::len)
    }

    /// Refuses what no fit can use: fewer than [`MIN_SAMPLES`] samples, a value that is NaN or
    /// infinite, times that do not strictly increase. Errors name the column and the row (data
    /// rows from 1).
    pub fn check(&self) -> Result<()> {
        let m = self.t.len();
        if m < MIN_SAMPLES {
            return Err(Error::invalid(
                "samples",
                m,
                format!("a fit needs at least {MIN_SAMPLES} samples"),
            ));
        }
        let blocks = self.blocks();
        let names = column_names(blocks);
        for i in 0..m {
            let row = std::iter::once(self.t[i])
                .chain(self.lengths[i].iter().copied())
                .chain(self.positions[i].iter().copied());
            for (c, v) in row.enumerate() {
                if !v.is_finite() {
                    return Err(Error::invalid(
                        format!("row {}, column {}", i + 1, names[c]),
                        v,
                        "must be a finite number",
                    ));
                }
            }
            if i > 0 && self.t[i] <= self.t[i - 1] {
                return Err(Error::invalid(
                    format!("row {}, column t", i + 1),
                    self.t[i],
                    format!(
                        "times must strictly increase (row {} has t = {})",
                        i,
                        self.t[i - 1]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `d_l(t_i) = L_l - (X_(l+1) - X_l)`: how far spring `l` is compressed, in length units
    /// (theory §2: `x_l = k_l d_l`).
    pub fn compression(&self, i: usize, l: usize) -> f64 {
        let x = &self.positions[i];
        self.lengths[i][l] - (x[l + 1] - x[l])
    }

    /// A scale of the lengths in the data (the largest |L| or |X|, at least the largest
    /// motion): rounding errors of the data are relative to it.
    pub fn length_scale(&self) -> f64 {
        self.lengths
            .iter()
            .chain(&self.positions)
            .flatten()
            .fold(0.0_f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE)
    }
}

/// Where each wanted column is in `header`: a header of numbers, a column twice, one not of a
/// `blocks`-block trajectory or one missing is refused naming it (`at` prefixes the file).
fn column_index(
    header: &[String],
    wanted: &[String],
    blocks: usize,
    at: &dyn Fn(String) -> String,
) -> Result<Vec<usize>> {
    if header
        .first()
        .is_some_and(|h| h.parse::<f64>().is_ok() || h.is_empty())
    {
        return Err(Error::invalid(
            at("header".into()),
            header.join(","),
            format!(
                "the first line must be the header {} (got numbers)",
                wanted.join(",")
            ),
        ));
    }
    // Where each wanted column is.
    let mut index = vec![usize::MAX; wanted.len()];
    for (c, h) in header.iter().enumerate() {
        match wanted.iter().position(|w| w == h) {
            Some(j) if index[j] != usize::MAX => {
                return Err(Error::invalid(
                    at(format!("column {h}")),
                    h,
                    "appears twice in the header",
                ))
            }
            Some(j) => index[j] = c,
            None => {
                return Err(Error::invalid(
                    at(format!("column {}", c + 1)),
                    h,
                    format!(
                        "not a column of a {blocks}-block trajectory (expected {})",
                        wanted.join(",")
                    ),
                ))
            }
        }
    }
    if let Some(j) = index.iter().position(|&c| c == usize::MAX) {
        return Err(Error::invalid(
            at(format!("column {}", wanted[j])),
            "missing",
            format!(
                "the header has no {} (a {blocks}-block trajectory needs {})",
                wanted[j],
                wanted.join(",")
            ),
        ));
    }
    Ok(index)
}

/// The wanted values of data row `row` (numbered from 1), in the order of `wanted`.
fn row_values(
    rec: std::result::Result<csv::StringRecord, csv::Error>,
    row: usize,
    header: &[String],
    index: &[usize],
    wanted: &[String],
    at: &dyn Fn(String) -> String,
) -> Result<Vec<f64>> {
    let rec = rec.map_err(|e| Error::invalid(at(format!("row {row}")), "CSV", e.to_string()))?;
    if rec.len() != header.len() {
        return Err(Error::invalid(
            at(format!("row {row}")),
            format!("{} fields", rec.len()),
            format!("the header has {} columns", header.len()),
        ));
    }
    let mut vals = Vec::with_capacity(wanted.len());
    for (j, &c) in index.iter().enumerate() {
        let f = &rec[c];
        let v = f.parse::<f64>().map_err(|_| {
            Error::invalid(
                at(format!("row {row}, column {}", wanted[j])),
                format!("{f:?}"),
                "not a number",
            )
        })?;
        vals.push(v);
    }
    Ok(vals)
}
