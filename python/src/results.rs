//! A gait result (what `crawlopt optimize --json` writes) as a Python class: read and written
//! as the same JSON, certified, drawn and reported by the library.

use crate::errors::to_py;
use crate::general::GeneralRecord;
use crate::run::run;
use crawlopt::api::certify_result_file;
use crawlopt::certify::NecessaryConditions;
use crawlopt::io::{GeneralAnswer, ResultFile};
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
        let r = self.file();
        certified_json(py, || Ok(r))
    }

    /// The figures of the gait (with the adjoint when `certified`): (name, caption, SVG).
    #[pyo3(signature = (certified=false))]
    fn figures(&self, py: Python<'_>, certified: bool) -> PyResult<Vec<(String, String, String)>> {
        let r = self.file();
        let figs = run(py, None, |_| {
            if certified {
                certify_result_file(r, "result")?.figures()
            } else {
                present::result_figures(&r)
            }
        })?;
        Ok(figs
            .into_iter()
            .map(|f| (f.name, f.caption, f.svg))
            .collect())
    }

    /// The self-contained HTML report (`source` names the input in the page; `conditions`, the
    /// JSON of the gait's necessary conditions, adds the certificate's section).
    #[pyo3(signature = (source="crawlopt", conditions=None))]
    fn report_html(
        &self,
        py: Python<'_>,
        source: &str,
        conditions: Option<&str>,
    ) -> PyResult<String> {
        let r = self.inner.clone();
        let c = certificate(py, conditions)?;
        run(py, None, |_| {
            report::build_report_with(&r, &context(source, c.as_ref()))
        })
    }

    /// Writes the report to `path` (atomically, as `crawlopt report -o`).
    #[pyo3(signature = (path, source="crawlopt", conditions=None))]
    fn write_report(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        source: &str,
        conditions: Option<&str>,
    ) -> PyResult<()> {
        let r = self.inner.clone();
        let c = certificate(py, conditions)?;
        run(py, None, |_| {
            crawlopt::io::AtomicFile::check(&path)?;
            let html = report::build_report_with(&r, &context(source, c.as_ref()))?;
            report::write_report(&path, &html)
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

impl GaitResult {
    /// The gait as the one result of both kinds (without necessary conditions).
    fn file(&self) -> ResultFile {
        self.inner.clone().into()
    }
}

/// The necessary conditions of a result of either kind (made by `result`, on the worker
/// thread), as the JSON `crawlopt certify --json` writes: the library's one certify of a
/// result ([`certify_result_file`]), which decides what applies to which method.
fn certified_json(
    py: Python<'_>,
    result: impl FnOnce() -> crawlopt::Result<ResultFile> + Send,
) -> PyResult<String> {
    let c = run(py, None, |_| certify_result_file(result()?, "result"))?;
    Ok(crawlopt::io::json::to_string(&c).expect("serialisable"))
}

/// The necessary conditions from their JSON (as `certify_json` writes them).
fn certificate(py: Python<'_>, conditions: Option<&str>) -> PyResult<Option<NecessaryConditions>> {
    conditions
        .map(|text| {
            serde_json::from_str(text).map_err(|e| {
                let e = crawlopt::Error::invalid(
                    "necessary_conditions",
                    "the JSON given",
                    e.to_string(),
                );
                to_py(py, e)
            })
        })
        .transpose()
}

/// A report made from Python: its footer names the method that made it.
fn context<'a>(source: &'a str, c: Option<&'a NecessaryConditions>) -> report::ReportContext<'a> {
    report::ReportContext {
        source,
        command: "crawlopt.GaitResult.report (Python)".into(),
        certificate: c,
    }
}

/// Reads a result document of either kind, checked as `crawlopt certify` checks it (`name`
/// for messages): a `GaitResult` for a crawler's; for a general problem's, the document as a
/// dict and the library's record of it, which `crawlopt/_documents.py` wraps in
/// `GeneralResult` (its figures and report come from the record).
#[pyfunction]
#[pyo3(signature = (text, name="result"))]
pub fn read_result<'py>(py: Python<'py>, text: &str, name: &str) -> PyResult<Bound<'py, PyAny>> {
    match ResultFile::from_json(text, name).map_err(|e| to_py(py, e))? {
        ResultFile::Crawler(r) => Ok(Bound::new(py, GaitResult { inner: r.result })?.into_any()),
        ResultFile::General(r) => general_pair(py, *r),
    }
}

/// A general result as (document, record).
fn general_pair(py: Python<'_>, r: GeneralAnswer) -> PyResult<Bound<'_, PyAny>> {
    let doc = pythonize::pythonize(py, &r)?;
    let record = GeneralRecord::of_answer(r).map_err(|e| to_py(py, e))?;
    Ok((doc, record).into_pyobject(py)?.into_any())
}

/// A general problem's result document read back (checked; a crawler's result is refused
/// naming `kind`), as the document (a dict) and the library's record of it.
#[pyfunction]
#[pyo3(signature = (text, name="result"))]
pub fn read_general_result<'py>(
    py: Python<'py>,
    text: &str,
    name: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let r = GeneralAnswer::from_json(text, name).map_err(|e| to_py(py, e))?;
    general_pair(py, r)
}

/// [`read_result`] of a file (read with the library's bounds; errors name the file).
#[pyfunction]
pub fn read_result_file(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Bound<'_, PyAny>> {
    let text = crawlopt::io::read_input_text(&path, crawlopt::io::MAX_RESULT_BYTES)
        .map_err(|e| to_py(py, e))?;
    read_result(py, &text, &path.display().to_string())
}

/// The necessary conditions (Theorem 2.2; discrete form Theorems 6.1–6.2) of a result
/// document of either kind, read back checked, as `crawlopt certify --json` writes them.
#[pyfunction]
#[pyo3(signature = (text, name="result"))]
pub fn certify_json(py: Python<'_>, text: &str, name: &str) -> PyResult<String> {
    certified_json(py, || ResultFile::from_json(text, name))
}
