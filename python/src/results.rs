//! A gait result (what `crawlopt optimize --json` writes) as a Python class: read and written
//! as the same JSON, certified, drawn and reported by the library.

use crate::errors::to_py;
use crate::run::run;
use crawlopt::certify::certify_result;
use crawlopt::present::{self, report, text};
use pyo3::prelude::*;

/// A gait result: the optimal gait, its certificate and status, verified by simulation.
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct GaitResult {
    pub inner: crawlopt::optimal::GaitResult,
}

#[pymethods]
impl GaitResult {
    /// Reads a result document, checked as `crawlopt certify` checks it (`name` for messages).
    #[staticmethod]
    #[pyo3(signature = (text, name="result"))]
    fn from_json(py: Python<'_>, text: &str, name: &str) -> PyResult<Self> {
        crawlopt::optimal::GaitResult::from_json(text, name)
            .map(|inner| GaitResult { inner })
            .map_err(|e| to_py(py, e))
    }

    /// The result document: the JSON `crawlopt optimize --json` writes (keys sorted).
    fn to_json(&self) -> String {
        crawlopt::io::json::to_string_sorted(&self.inner).expect("serialisable")
    }

    /// The necessary conditions of Theorem 2.2 (discrete form Theorems 6.1–6.2) on the gait,
    /// as the JSON `crawlopt certify --json` writes.
    fn certify_json(&self, py: Python<'_>) -> PyResult<String> {
        let r = self.inner.clone();
        let c = run(py, None, |_| certify_result(&r, "result"))?;
        Ok(crawlopt::io::json::to_string(&c).expect("serialisable"))
    }

    /// The figures of the gait (with the adjoint when `certified`): (name, caption, SVG).
    #[pyo3(signature = (certified=false))]
    fn figures(&self, py: Python<'_>, certified: bool) -> PyResult<Vec<(String, String, String)>> {
        let r = self.inner.clone();
        let figs = run(py, None, |_| {
            let mut figs = present::gait_figures(&r)?;
            if certified {
                let c = certify_result(&r, "result")?;
                figs.push(present::adjoint_figure_of(&c.multipliers)?);
            }
            Ok(figs)
        })?;
        Ok(figs
            .into_iter()
            .map(|f| (f.name, f.caption, f.svg))
            .collect())
    }

    /// The self-contained HTML report (`source` names the input in the page).
    #[pyo3(signature = (source="crawlopt"))]
    fn report_html(&self, py: Python<'_>, source: &str) -> PyResult<String> {
        let r = self.inner.clone();
        run(py, None, |_| report::build_report(&r, source))
    }

    /// Writes the report to `path` (atomically, as `crawlopt report -o`).
    #[pyo3(signature = (path, source="crawlopt"))]
    fn write_report(&self, py: Python<'_>, path: std::path::PathBuf, source: &str) -> PyResult<()> {
        let r = self.inner.clone();
        run(py, None, |_| {
            crawlopt::io::AtomicFile::check(&path)?;
            report::write_report(&path, &report::build_report(&r, source)?)
        })
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }

    /// Pickled as its result document (read back as `from_json` reads it).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let text = crawlopt::io::json::to_string(&slf.get().inner).expect("serialisable");
        crate::model::reduce(slf.as_any(), text)
    }

    #[staticmethod]
    fn _from_state(py: Python<'_>, text: &str) -> PyResult<Self> {
        GaitResult::from_json(py, text, "result")
    }

    /// The text `crawlopt optimize` prints.
    fn text(&self) -> String {
        text::gait_result(&self.inner)
    }
}
