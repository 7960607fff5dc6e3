//! An optimisation's settings from Python's keyword arguments, for both kinds of problem: the
//! library reads them ([`crawlopt::api::OptimizeSettings::from_keys`]).

use crate::errors::to_py;
use crawlopt::api::OptimizeSettings;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The settings of an optimisation from Python's keyword arguments, a dict of the settings'
/// own names (those left at None left out): each value converted as it is (a number, a
/// boolean, a word, a dict such as `bound`'s) and the dict read by the library
/// ([`OptimizeSettings::from_keys`]), which names the key of a value it refuses (a `TypeError`
/// for a value of the wrong type). A value that is not a number, a boolean, a word or a dict of
/// those is an `InputError` naming its key (`bound.resolution` inside a dict).
pub(crate) fn optimize_settings(
    py: Python<'_>,
    keys: &Bound<'_, PyDict>,
) -> PyResult<OptimizeSettings> {
    let table = table(py, keys, "")?;
    // A value of the wrong type (`m="three"`) is the library's `WrongType`: Python's TypeError.
    OptimizeSettings::from_keys(&table).map_err(|e| to_py(py, e))
}

/// A dict of keys as a table, each value converted on its own so that a refusal names its
/// path (`prefix` and the key).
fn table(py: Python<'_>, keys: &Bound<'_, PyDict>, prefix: &str) -> PyResult<toml::Table> {
    let mut out = toml::Table::new();
    for (key, value) in keys.iter() {
        let key: String = key.extract()?;
        let path = format!("{prefix}{key}");
        let v = match value.downcast::<PyDict>() {
            Ok(dict) => toml::Value::Table(table(py, dict, &format!("{path}."))?),
            Err(_) => pythonize::depythonize(&value).map_err(|e| {
                let shown = value.repr().map(|r| r.to_string()).unwrap_or_default();
                // A Python int beyond 64 bits, which no setting reaches.
                let reason = if value.is_instance_of::<pyo3::types::PyInt>() {
                    "is beyond the range of a 64-bit integer".to_string()
                } else {
                    e.to_string()
                };
                to_py(py, crawlopt::Error::invalid(path, shown, reason))
            })?,
        };
        out.insert(key, v);
    }
    Ok(out)
}
