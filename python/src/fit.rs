//! `fit`: a crawler identified from a measured trajectory (`crawlopt::api::fit`), its keyword
//! arguments turned into the library's settings, run through [`crate::run::run`].

use crate::errors::to_py;
use crate::run::run;
use crawlopt::api;
use crawlopt::fit::{FitData, FitSettings, Param};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

/// The re-simulated positions (samples x blocks).
type Predicted<'py> = Bound<'py, PyArray2<f64>>;

/// Fits a crawler of `blocks` blocks to the samples `t`, `lengths` (one row of `N - 1` per
/// sample) and `positions` (one row of `N`); see `crawlopt.fit` for the arguments. Returns the
/// result as a dict (the document of `crawlopt fit --json`) and the predicted positions as an
/// array (samples x blocks) when the fitted crawler was re-simulated.
#[pyfunction]
#[pyo3(signature = (t, lengths, positions, blocks, fixes, noise, noise_bound, progress))]
#[allow(clippy::too_many_arguments)]
pub fn fit<'py>(
    py: Python<'py>,
    t: Vec<f64>,
    lengths: Vec<Vec<f64>>,
    positions: Vec<Vec<f64>>,
    blocks: usize,
    fixes: Vec<(String, f64)>,
    noise: Option<f64>,
    noise_bound: Option<f64>,
    progress: Option<PyObject>,
) -> PyResult<(Bound<'py, PyAny>, Option<Predicted<'py>>)> {
    let fixes = fixes
        .iter()
        .map(|(name, v)| Ok((name.parse::<Param>()?, *v)))
        .collect::<crawlopt::Result<Vec<_>>>()
        .map_err(|e| to_py(py, e))?;
    let settings = FitSettings {
        fixes,
        noise,
        noise_bound: noise_bound.unwrap_or(FitSettings::NOISE_BOUND),
        ..FitSettings::default()
    };
    let data = FitData::new(blocks, t, lengths, positions).map_err(|e| to_py(py, e))?;
    let mut r = run(py, progress, |hooks| api::fit(&data, &settings, hooks))?;
    let predicted = r.prediction.as_mut().map(|p| {
        let rows = std::mem::take(&mut p.positions);
        let flat: Vec<f64> = rows.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat)
            .reshape([rows.len(), blocks])
            .expect("rows of equal length")
    });
    Ok((pythonize::pythonize(py, &r)?, predicted))
}
