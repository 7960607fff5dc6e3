//! A general problem file (`[sweeping_process]`, the paper's §2 problem (P)) as a Python class:
//! `analyze`, `simulate` and `optimize` of `crawlopt::api::general`, run through
//! [`crate::run::run`]; answers as dicts (`pythonize`), which `crawlopt/__init__.py` turns into
//! NumPy arrays where they are series.

use crate::errors::to_py;
use crate::run::run;
use crawlopt::api::{self, OptimizeSettings};
use crawlopt::integrate::{GeneralMethod, GeneralSimOptions, Method};
use crawlopt::io::{GeneralFile, ProblemFile, ResultFile};
use crawlopt::present::{self, GeneralReportInput};
use pyo3::prelude::*;

/// A general problem read from its file, every check of `crawlopt analyze` passed or reported.
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct GeneralProblem {
    pub inner: GeneralFile,
}

#[pymethods]
impl GeneralProblem {
    /// A problem from the file's sections as a dict (`sweeping_process`, `dynamics`,
    /// `control`, `objective`, `problem`, optional `input`, each with the file's keys), checked
    /// as the file is (the checks that need no linear program; `analyze` does the rest).
    #[staticmethod]
    fn from_sections(py: Python<'_>, sections: &Bound<'_, PyAny>) -> PyResult<Self> {
        let inner: GeneralFile = pythonize::depythonize(sections).map_err(|e| {
            to_py(
                py,
                crawlopt::Error::invalid("sections", "the arrays given", e.to_string()),
            )
        })?;
        inner.problem().map_err(|e| to_py(py, e))?;
        Ok(GeneralProblem { inner })
    }

    /// The file's sections as a dict (the keys of the file).
    fn sections<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(pythonize::pythonize(py, &self.inner)?)
    }

    /// The problem file as TOML text (`crawlopt.load` and the command line read it back).
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        self.inner.to_toml().map_err(|e| to_py(py, e))
    }

    /// Equal sections; and the same folder when the input is read from a CSV file (the
    /// folder a file was read from matters only for that path).
    fn __eq__(&self, other: &Self) -> bool {
        let csv = |f: &GeneralFile| f.input.as_ref().is_some_and(|i| i.kind == "csv");
        let (mut a, mut b) = (self.inner.clone(), other.inner.clone());
        if !csv(&a) && !csv(&b) {
            (a.base_dir, b.base_dir) = Default::default();
        }
        a == b
    }

    /// Pickled as its sections and folder (for a CSV input's relative path).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let f = &slf.get().inner;
        let text = serde_json::to_string(&(f, &f.base_dir)).expect("serialisable");
        crate::model::reduce(slf.as_any(), text)
    }

    #[staticmethod]
    fn _from_state(text: &str) -> PyResult<Self> {
        let (mut inner, dir): (GeneralFile, std::path::PathBuf) = serde_json::from_str(text)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
        inner.base_dir = dir;
        Ok(GeneralProblem { inner })
    }

    /// The analysis `crawlopt analyze --json` prints (faces, redundant faces, vertices, the
    /// Chebyshev centre, the checks), and the first failed check's message (or None).
    fn analyze<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Option<String>)> {
        let f = self.inner.clone();
        let a = run(py, None, |_| api::analyze_general(&f))?;
        let failure = a.failure.as_ref().map(|e| e.to_string());
        Ok((pythonize::pythonize(py, &a)?, failure))
    }

    /// The file's `[input]` simulated (`crawlopt simulate --json`); `method` "exact" (where it
    /// applies, else catching-up) or "catching_up"; None takes the library's default. Returns
    /// the document and the record the library draws and reports.
    #[pyo3(signature = (method, steps_per_period, max_periods, tol))]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        method: &str,
        steps_per_period: Option<usize>,
        max_periods: Option<usize>,
        tol: Option<f64>,
    ) -> PyResult<(Bound<'py, PyAny>, GeneralRecord)> {
        let d = GeneralSimOptions::DEFAULT;
        let method: GeneralMethod = Method::from_name(method).map_err(|e| to_py(py, e))?.into();
        let opts = GeneralSimOptions {
            method,
            steps_per_period: steps_per_period.unwrap_or(d.steps_per_period),
            max_periods: max_periods.unwrap_or(d.max_periods),
            tol: tol.unwrap_or(d.tol),
            ..d
        };
        let f = self.inner.clone();
        let s = run(py, None, |_| api::simulate_general(&f, &opts))?;
        let doc = pythonize::pythonize(py, &crawlopt::io::SimulationDocument::general(&s))?;
        let problem = self.inner.problem().map_err(|e| to_py(py, e))?;
        Ok((
            doc,
            GeneralRecord::new(problem, Record::Simulated(Box::new(s))),
        ))
    }

    /// P_m of the problem (`crawlopt optimize --json`) with the settings `keys` (a dict of
    /// the settings' own names, `crate::settings::optimize_settings`): `method` "discrete"
    /// (global MILP, its first incumbent the process of `start` when given) or "local" (the
    /// LPCC active-set method, `shifts` rotations of each start, from `start` when given;
    /// `start` a general result's JSON); "phase" (exact gaits where `A = 0`,
    /// globally among those of at most `phases` phases, or `K` grown to `max_phases` until
    /// `patience` K bring no gain); None takes the library's default. Cancellable (Ctrl-C);
    /// `progress` receives the events. Returns the document and the record the library draws
    /// and reports.
    #[pyo3(signature = (keys, start, progress))]
    fn optimize<'py>(
        &self,
        py: Python<'py>,
        keys: &Bound<'py, pyo3::types::PyDict>,
        start: Option<&str>,
        progress: Option<PyObject>,
    ) -> PyResult<(Bound<'py, PyAny>, GeneralRecord, Vec<String>)> {
        let f = self.inner.clone();
        // A start is a general result's document, read and checked as `certify` reads it.
        let start = start
            .map(|text| crawlopt::io::GeneralAnswer::from_json(text, "start"))
            .transpose()
            .map_err(|e| to_py(py, e))?
            .map(|answer| api::Start::Result {
                result: Box::new(answer.into()),
                name: "start".into(),
            });
        // The library decides what applies to a general problem, with its defaults.
        let settings = OptimizeSettings {
            start,
            ..crate::settings::optimize_settings(py, keys)?
        };
        // The one optimisation of a problem file, as the command line runs it.
        let file = ProblemFile::General(Box::new(f));
        let done = run(py, progress, |hooks| {
            api::optimize_file(&file, &settings, hooks)
        })?;
        let api::OptimizedFile {
            result: ResultFile::General(answer),
            notes,
        } = done
        else {
            return Err(pyo3::exceptions::PyRuntimeError::new_err(
                "a general problem file gave a crawler's answer",
            ));
        };
        let doc = pythonize::pythonize(py, &answer)?;
        let record = GeneralRecord::of_answer(*answer).map_err(|e| to_py(py, e))?;
        Ok((doc, record, notes))
    }
}

/// What a [`GeneralRecord`] holds.
pub(crate) enum Record {
    Simulated(Box<crawlopt::io::GeneralSimulated>),
    Answer(Box<crawlopt::io::GeneralAnswer>),
}

/// A simulation or an optimum of a general problem as the library returned it, with its
/// problem: the library's figures and report of it (`crawlopt simulate --plot`, `crawlopt
/// optimize --plot --report`).
#[pyclass(module = "crawlopt._crawlopt", frozen)]
pub struct GeneralRecord {
    problem: crawlopt::model::general::GeneralProblem,
    record: Record,
}

impl GeneralRecord {
    /// The record of a general result read back from its document (the problem its envelope
    /// stores), so that a result file draws and reports as the object `optimize` returned.
    pub(crate) fn of_answer(r: crawlopt::io::GeneralAnswer) -> crawlopt::Result<Self> {
        let problem = r.problem.problem()?;
        Ok(GeneralRecord::new(problem, Record::Answer(Box::new(r))))
    }

    pub(crate) fn new(problem: crawlopt::model::general::GeneralProblem, record: Record) -> Self {
        GeneralRecord { problem, record }
    }

    fn input(&self) -> GeneralReportInput<'_> {
        match &self.record {
            Record::Simulated(s) => GeneralReportInput::Simulation(s),
            Record::Answer(a) => GeneralReportInput::Answer(a),
        }
    }

    fn html(&self, source: &str) -> crawlopt::Result<String> {
        let command = match self.record {
            Record::Simulated(_) => "crawlopt.GeneralSimulation.report (Python)",
            Record::Answer(_) => "crawlopt.GeneralResult.report (Python)",
        };
        present::build_general_report(&self.problem, self.input(), source, command)
    }
}

#[pymethods]
impl GeneralRecord {
    /// The library's figures: (name, caption, SVG) each.
    fn figures(&self, py: Python<'_>) -> PyResult<Vec<(String, String, String)>> {
        let figs = run(py, None, |_| match &self.record {
            Record::Simulated(s) => present::general_simulation_figures(&self.problem, s),
            Record::Answer(a) => present::general_answer_figures(&self.problem, a),
        })?;
        Ok(figs
            .into_iter()
            .map(|f| (f.name, f.caption, f.svg))
            .collect())
    }

    /// The self-contained HTML report (`source` names the input in the page).
    #[pyo3(signature = (source="crawlopt"))]
    fn report_html(&self, py: Python<'_>, source: &str) -> PyResult<String> {
        run(py, None, |_| self.html(source))
    }

    /// Writes the report to `path` (atomically, as `crawlopt optimize --report`).
    #[pyo3(signature = (path, source="crawlopt"))]
    fn write_report(&self, py: Python<'_>, path: std::path::PathBuf, source: &str) -> PyResult<()> {
        run(py, None, |_| {
            crawlopt::io::AtomicFile::check(&path)?;
            crawlopt::present::report::write_report(&path, &self.html(source)?)
        })
    }
}

/// Reads a problem file if it is of the general kind (None for a crawler file).
#[pyfunction]
pub fn load_general(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Option<GeneralProblem>> {
    GeneralFile::load_if_general(&path)
        .map(|f| f.map(|inner| GeneralProblem { inner }))
        .map_err(|e| to_py(py, e))
}
