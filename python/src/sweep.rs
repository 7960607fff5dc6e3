//! Parameter studies: a sweep (a file, or a dictionary as JSON) sized, run whole on the
//! library's thread pool, or point by point (for a `concurrent.futures` executor: each call is
//! independent, so any process or machine that can import `crawlopt` can run it).

use crate::errors::to_py;
use crate::run::run;
use crawlopt::study::{self, Format, SweepSettings, SweepSpec};
use pyo3::prelude::*;
use std::path::Path;
use std::sync::Mutex;

/// The sweep of `source`: a file's path (`is_path`) or a JSON document, relative paths from
/// `base_dir`.
fn spec_of(source: &str, is_path: bool, base_dir: &str) -> crawlopt::Result<SweepSpec> {
    if is_path {
        SweepSpec::load(Path::new(source))
    } else {
        SweepSpec::from_json(source, Path::new(base_dir))
    }
}

/// The columns of the sweep's table and its number of points.
#[pyfunction]
pub fn sweep_size(
    py: Python<'_>,
    source: &str,
    is_path: bool,
    base_dir: &str,
) -> PyResult<(Vec<String>, usize)> {
    let spec = spec_of(source, is_path, base_dir).map_err(|e| to_py(py, e))?;
    let n = spec.len().map_err(|e| to_py(py, e))?;
    Ok((study::header(&spec), n))
}

/// Point `id` of the sweep run on this thread (GIL released): its row as a JSON object.
#[pyfunction]
pub fn sweep_point(
    py: Python<'_>,
    source: &str,
    is_path: bool,
    base_dir: &str,
    id: usize,
) -> PyResult<String> {
    let spec = spec_of(source, is_path, base_dir).map_err(|e| to_py(py, e))?;
    let n = spec.len().map_err(|e| to_py(py, e))?;
    if id >= n {
        let e = crawlopt::Error::invalid("point", id, format!("the sweep has points 0..{n}"));
        return Err(to_py(py, e));
    }
    let out = py.allow_threads(|| study::run_point(&spec, &spec.point(id), false, None));
    Ok(study::line(
        &out.row,
        &study::header(&spec),
        Format::JsonLines,
    ))
}

/// Every point of the sweep on `threads` threads (0: one per core), with the GIL released and
/// Ctrl-C cancelling: the rows as JSON objects, in the order they finished.
#[pyfunction]
pub fn sweep_run(
    py: Python<'_>,
    source: &str,
    is_path: bool,
    base_dir: &str,
    threads: i64,
) -> PyResult<Vec<String>> {
    // A Python int of any sign: a negative one is refused naming `threads` (not an
    // OverflowError of the conversion).
    let threads = usize::try_from(threads).map_err(|_| {
        let e = crawlopt::Error::invalid(
            "threads",
            threads,
            "must be 0 (one per core) or a positive number of threads",
        );
        to_py(py, e)
    })?;
    let spec = spec_of(source, is_path, base_dir).map_err(|e| to_py(py, e))?;
    let header = study::header(&spec);
    run(py, None, |hooks| {
        let settings = SweepSettings {
            threads,
            cancel: hooks.cancel.cloned(),
            ..Default::default()
        };
        let rows = Mutex::new(Vec::new());
        study::run(&spec, &settings, &|o, _| {
            let line = study::line(&o.row, &header, Format::JsonLines);
            rows.lock().expect("not poisoned").push(line);
        })?;
        Ok(rows.into_inner().expect("not poisoned"))
    })
}
