//! The checks of a general problem's data (`super::general`): finite entries, consistent
//! lengths and matrix shapes, a cost that is convex, and weights whose size keeps `J` within
//! the floating-point range; each error names the file's field.

use crate::error::{Error, Result};

/// `e` naming the field `to...` where it named `from...` (the file's name of a field checked
/// under another's).
pub(super) fn rename(e: Error, from: &str, to: &str) -> Error {
    e.map_field(|field| field.replacen(from, to, 1))
}

pub(super) fn check_len(field: &str, v: &[f64], len: usize, what: &str) -> Result<()> {
    if v.len() == len {
        Ok(())
    } else {
        Err(Error::invalid(
            field,
            format!("{} values", v.len()),
            format!("needs one value per {what} ({len})"),
        ))
    }
}

pub(super) fn check_finite(field: &str, v: &[f64]) -> Result<()> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::invalid(
            format!("{field}[{}]", i + 1),
            v[i],
            "must be finite",
        )),
    }
}

/// A `rows x cols` matrix of finite entries (`cols = None`: as the first row).
pub(super) fn check_matrix(
    field: &str,
    m: &[Vec<f64>],
    rows: usize,
    cols: Option<usize>,
    cols_what: &str,
) -> Result<()> {
    if m.len() != rows {
        return Err(Error::invalid(
            field,
            format!("{} rows", m.len()),
            format!("needs {rows} rows"),
        ));
    }
    let cols = cols.unwrap_or_else(|| m.first().map_or(0, Vec::len));
    for (i, row) in m.iter().enumerate() {
        let f = format!("{field}[{}]", i + 1);
        if row.len() != cols {
            return Err(Error::invalid(
                &f,
                format!("{} values", row.len()),
                format!("needs {cols} columns ({cols_what} dimension)"),
            ));
        }
        check_finite(&f, row)?;
    }
    Ok(())
}
