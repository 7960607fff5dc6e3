//! `crawlopt._crawlopt`: the Python extension, a thin layer over `crawlopt::api`. Each function
//! converts its arguments into the library's types and settings, runs the job with the GIL
//! released (on a worker thread, so that Ctrl-C can cancel it: `run`), and converts the answer
//! (NumPy arrays for series, JSON text for documents, which `crawlopt/__init__.py` wraps in
//! Python classes). No decision is taken here.

mod errors;
mod fit;
mod general;
mod jobs;
mod model;
mod results;
mod run;
mod settings;
mod sweep;

use pyo3::prelude::*;

/// The extension's Rust allocations go to mimalloc, not to the C heap it shares with Python:
/// a recorded trajectory is thousands of small vectors, and in a heap that Python and NumPy
/// have fragmented glibc's malloc spent a quarter of a short simulation consolidating and
/// unlinking chunks (`perf`; the same job in a Rust process: a few percent). As polars does.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[pymodule]
fn _crawlopt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<model::Crawler>()?;
    m.add_class::<model::Actuation>()?;
    m.add_class::<model::GaitProblem>()?;
    m.add_class::<results::GaitResult>()?;
    m.add_class::<general::GeneralProblem>()?;
    m.add_class::<general::GeneralRecord>()?;
    m.add_function(wrap_pyfunction!(model::load, m)?)?;
    m.add_function(wrap_pyfunction!(model::model_toml, m)?)?;
    m.add_function(wrap_pyfunction!(general::load_general, m)?)?;
    m.add_function(wrap_pyfunction!(results::read_result, m)?)?;
    m.add_function(wrap_pyfunction!(results::read_result_file, m)?)?;
    m.add_function(wrap_pyfunction!(results::read_general_result, m)?)?;
    m.add_function(wrap_pyfunction!(results::certify_json, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::optimize, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(jobs::simulation_figures, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_size, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_point, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::sweep_run, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
