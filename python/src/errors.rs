//! The library's errors as Python exceptions: one class per kind, with the library's message
//! and its fields as attributes.

use crawlopt::Error;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::IntoPyObjectExt;

pyo3::create_exception!(
    _crawlopt,
    InputError,
    PyValueError,
    "Bad input: `.field` names it, `.value` is the value as given."
);
pyo3::create_exception!(_crawlopt, NonUniqueError, InputError, "The uniqueness condition (paper eq. 3.6) fails: `.subset` (1-based blocks), `.forward_sum`, `.backward_sum`.");
pyo3::create_exception!(
    _crawlopt,
    InadmissibleError,
    InputError,
    "A state outside the polytope C: `.field` names it."
);
pyo3::create_exception!(
    _crawlopt,
    FileError,
    InputError,
    "A file could not be read or written: `.field` is its path."
);
pyo3::create_exception!(
    _crawlopt,
    CrawloptError,
    PyRuntimeError,
    "A computation could not answer."
);
pyo3::create_exception!(_crawlopt, TimeLimitError, CrawloptError, "The time limit ended a job before it had any gait (a job with one returns it, status 'time_limit'); `.incumbent` is None.");
pyo3::create_exception!(
    _crawlopt,
    InfeasibleError,
    CrawloptError,
    "The problem has no feasible point."
);
pyo3::create_exception!(
    _crawlopt,
    NumericalError,
    CrawloptError,
    "A numerical kernel or the solver failed."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("NonUniqueError", py.get_type::<NonUniqueError>())?;
    m.add("InadmissibleError", py.get_type::<InadmissibleError>())?;
    m.add("FileError", py.get_type::<FileError>())?;
    m.add("CrawloptError", py.get_type::<CrawloptError>())?;
    m.add("TimeLimitError", py.get_type::<TimeLimitError>())?;
    m.add("InfeasibleError", py.get_type::<InfeasibleError>())?;
    m.add("NumericalError", py.get_type::<NumericalError>())?;
    Ok(())
}

/// `v` as a Python object (the conversions used here cannot fail; None if one did).
fn obj<'py, T: IntoPyObject<'py>>(py: Python<'py>, v: T) -> PyObject {
    v.into_py_any(py).unwrap_or_else(|_| py.None())
}

/// The Python exception of a library error, its fields set as attributes.
pub fn to_py(py: Python<'_>, e: Error) -> PyErr {
    let msg = e.to_string();
    let (err, attrs): (PyErr, Vec<(&str, PyObject)>) = match e {
        Error::InvalidParameter { field, value, .. } => (
            InputError::new_err(msg),
            vec![("field", obj(py, field)), ("value", obj(py, value))],
        ),
        Error::WrongType { field, value, .. } => (
            PyTypeError::new_err(msg),
            vec![("field", obj(py, field)), ("value", obj(py, value))],
        ),
        Error::NonUnique {
            subset,
            forward_sum,
            backward_sum,
        } => (
            NonUniqueError::new_err(msg),
            vec![
                ("field", obj(py, "crawler")),
                ("value", py.None()),
                ("subset", obj(py, subset)),
                ("forward_sum", obj(py, forward_sum)),
                ("backward_sum", obj(py, backward_sum)),
            ],
        ),
        Error::UniquenessUndecided(_) => (
            NonUniqueError::new_err(msg),
            vec![
                ("field", obj(py, "crawler")),
                ("value", py.None()),
                ("subset", py.None()),
            ],
        ),
        Error::Inadmissible { what, .. } => (
            InadmissibleError::new_err(msg),
            vec![("field", obj(py, what)), ("value", py.None())],
        ),
        Error::Io { path, .. } => (
            FileError::new_err(msg),
            vec![("field", obj(py, path)), ("value", py.None())],
        ),
        Error::TimeLimit(_) => (TimeLimitError::new_err(msg), vec![("incumbent", py.None())]),
        Error::Infeasible(_) => (InfeasibleError::new_err(msg), vec![]),
        Error::Numerical(_) => (NumericalError::new_err(msg), vec![]),
        Error::Cancelled => (PyKeyboardInterrupt::new_err(msg), vec![]),
    };
    let value = err.value(py);
    for (name, v) in attrs {
        // Setting an attribute on a fresh exception instance cannot fail.
        let _ = value.setattr(name, v);
    }
    err
}
