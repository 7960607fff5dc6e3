//! The jobs: `simulate` and `optimize`, their keyword arguments turned into the library's
//! settings, run through [`crate::run::run`].

use crate::errors::to_py;
use crate::model::{Actuation, Crawler, GaitProblem};
use crate::results::GaitResult;
use crate::run::run;
use crate::settings::optimize_settings;
use crawlopt::api::{self, OptimizeSettings, Start};
use crawlopt::integrate::{Method, SimOptions, Simulation};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// Rows of equal length as a 2-D array (`cols` columns when there are no rows).
fn matrix<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    rows: &[Vec<T>],
    cols: usize,
) -> Bound<'py, PyArray2<T>> {
    let flat: Vec<T> = rows.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat)
        .reshape([rows.len(), cols])
        .expect("rows of equal length")
}

/// A simulation: its scalar results as a dict, the library's document of a simulation (its
/// envelope: format, version, kind, objective; converted straight from the struct: a JSON text
/// parsed again in Python cost a fifth of the call's overhead), and the recorded trajectory as
/// arrays (`t`, `x`, `X`, `y`, `slip`) when periods were recorded (taken out before the
/// summary is converted: it is most of the work otherwise).
fn simulation_out(
    py: Python<'_>,
    mut s: Simulation,
    links: usize,
    blocks: usize,
) -> PyResult<(Bound<'_, PyAny>, Bound<'_, PyDict>)> {
    let trajectory = s.trajectory.take();
    let summary = pythonize::pythonize(py, &crawlopt::io::SimulationDocument::crawler(&s))?;
    let arrays = PyDict::new(py);
    if let Some(tr) = &trajectory {
        arrays.set_item("t", PyArray1::from_slice(py, &tr.t))?;
        arrays.set_item("x", matrix(py, &tr.x, links))?;
        arrays.set_item("X", matrix(py, &tr.positions, blocks))?;
        arrays.set_item("y", PyArray1::from_slice(py, &tr.barycentre))?;
        arrays.set_item("slip", matrix(py, &tr.slip, blocks))?;
    }
    Ok((summary, arrays))
}

/// Simulates `actuation` on `crawler` to the periodic regime (theory §3–4); see
/// `crawlopt.simulate` for the arguments.
#[pyfunction]
#[pyo3(signature = (crawler, actuation, method, steps_per_period, record_periods, max_periods, tol, accelerate, accelerate_after, initial_state, progress, newton = true, increment_budget = None))]
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    crawler: &Crawler,
    actuation: &Actuation,
    method: &str,
    steps_per_period: Option<usize>,
    record_periods: Option<usize>,
    max_periods: Option<usize>,
    tol: Option<f64>,
    accelerate: bool,
    accelerate_after: Option<usize>,
    initial_state: Option<Vec<f64>>,
    progress: Option<PyObject>,
    newton: bool,
    increment_budget: Option<usize>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let method = Method::from_name(method).map_err(|e| to_py(py, e))?;
    // None: the library's default.
    let d = SimOptions::DEFAULT;
    let opts = SimOptions {
        method,
        steps_per_period: steps_per_period.unwrap_or(d.steps_per_period),
        record_periods: record_periods.unwrap_or(d.record_periods),
        max_periods: max_periods.unwrap_or(d.max_periods),
        tol: tol.unwrap_or(d.tol),
        accelerate_after: accelerate
            .then(|| accelerate_after.or(d.accelerate_after))
            .flatten(),
        newton: d.newton.filter(|_| newton),
        initial_state,
        increment_budget: increment_budget.unwrap_or(d.increment_budget),
    };
    let c = crawler.inner.clone();
    let a = actuation.bound(c.links()).map_err(|e| to_py(py, e))?;
    let s = run(py, progress, |hooks| api::simulate(&c, &a, &opts, hooks))?;
    simulation_out(py, s, c.links(), c.blocks())
}

/// An optimal gait of `problem` for `crawler` (`crawlopt::api::optimize`) with the settings
/// `keys` ([`optimize_settings`], the upper bound's `bound` among them) and the gait `start`; see
/// `crawlopt.optimize` for the arguments.
#[pyfunction]
#[pyo3(signature = (crawler, problem, keys, start, progress))]
pub fn optimize(
    py: Python<'_>,
    crawler: &Crawler,
    problem: &GaitProblem,
    keys: &Bound<'_, PyDict>,
    start: Option<&GaitResult>,
    progress: Option<PyObject>,
) -> PyResult<(GaitResult, Option<String>, Vec<String>)> {
    let settings = OptimizeSettings {
        start: start.map(|r| Start::Result {
            result: Box::new(r.inner.clone().into()),
            name: "start".into(),
        }),
        ..optimize_settings(py, keys)?
    };
    let (c, p) = (crawler.inner.clone(), problem.inner.clone());
    let done = run(py, progress, |hooks| {
        api::optimize(&c, &p, &settings, hooks)
    })?;
    let conditions = done
        .necessary_conditions
        .as_ref()
        .map(|n| crawlopt::io::json::to_string(n).expect("serialisable"));
    Ok((GaitResult { inner: done.result }, conditions, done.notes))
}

/// The library's figures of a simulation's periodic regime (`crawlopt simulate --plot`): the
/// orbit replayed from `orbit_state` (the regime's start, as the simulation found it) with the
/// simulation's `method` and `steps_per_period`, drawn over `periods` periods; (name, caption,
/// SVG) each.
#[pyfunction]
pub fn simulation_figures(
    py: Python<'_>,
    crawler: &Crawler,
    actuation: &Actuation,
    method: &str,
    steps_per_period: usize,
    orbit_state: Vec<f64>,
    periods: usize,
) -> PyResult<Vec<(String, String, String)>> {
    let method = Method::from_name(method).map_err(|e| to_py(py, e))?;
    let c = crawler.inner.clone();
    let a = actuation.bound(c.links()).map_err(|e| to_py(py, e))?;
    let opts = SimOptions {
        method,
        steps_per_period,
        initial_state: Some(orbit_state),
        ..SimOptions::DEFAULT
    };
    let figs = run(py, None, |hooks| {
        let sim = api::simulate(&c, &a, &opts, hooks)?;
        crawlopt::present::simulation_figures(&c, &a, &sim, periods)
    })?;
    Ok(figs
        .into_iter()
        .map(|f| (f.name, f.caption, f.svg))
        .collect())
}
