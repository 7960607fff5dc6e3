//! `crawlopt._crawlopt`: the Python extension, a thin layer over `crawlopt::api`. Each function
//! converts its arguments into the library's types and settings, runs the job with the GIL
//! released (on a worker thread, so that Ctrl-C can cancel it: `run`), and converts the answer
//! (NumPy arrays for series, JSON text for documents, which `crawlopt/__init__.py` wraps in
//! Python classes). No decision is taken here.

mod errors;
mod jobs;
mod model;
mod results;
mod run;
mod sweep;

use pyo3::prelude::*;

#[pymodule]
fn _crawlopt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<model::Crawler>()?;
    m.add_class::<model::Actuation>()?;
    m.add_class::<model::GaitProblem>()?;
    m.add_class::<results::GaitResult>()?;
    m.add_function(wrap_pyfunction!(model::load, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::optimize, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_size, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_point, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_run, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
