//! The model: crawler, actuation and gait problem as Python classes over the library's types,
//! and `load` for a model file (the TOML schema of the command line).

use crate::errors::to_py;
use crawlopt::integrate::Waveform;
use crawlopt::io::ModelFile;
use crawlopt::optimal::Cost;
use pyo3::prelude::*;

/// A crawler: N blocks, N - 1 links (stiffness k_l), friction thresholds mu+ and mu- per block.
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct Crawler {
    pub inner: crawlopt::Crawler,
}

#[pymethods]
impl Crawler {
    /// Builds and validates a crawler: `stiffness` one per link, `mu_forward` and
    /// `mu_backward` one per block (the Python layer expands scalars).
    #[new]
    fn new(
        py: Python<'_>,
        stiffness: Vec<f64>,
        mu_forward: Vec<f64>,
        mu_backward: Vec<f64>,
    ) -> PyResult<Self> {
        crawlopt::Crawler::new(stiffness, mu_forward, mu_backward)
            .map(|inner| Crawler { inner })
            .map_err(|e| to_py(py, e))
    }

    #[getter]
    fn stiffness(&self) -> Vec<f64> {
        self.inner.stiffness().to_vec()
    }

    #[getter]
    fn mu_forward(&self) -> Vec<f64> {
        self.inner.mu_forward().to_vec()
    }

    #[getter]
    fn mu_backward(&self) -> Vec<f64> {
        self.inner.mu_backward().to_vec()
    }

    /// The analysis as JSON text (the document of `crawlopt analyze --json`).
    fn analyze_json(&self) -> String {
        crawlopt::io::json::to_string(&self.inner.analyze()).expect("serialisable")
    }

    /// v_m(z'): the barycentre velocity produced by the shape rate z' (paper eq. 3.8).
    fn vm(&self, py: Python<'_>, rates: Vec<f64>) -> PyResult<f64> {
        if rates.len() != self.inner.links() || rates.iter().any(|v| !v.is_finite()) {
            return Err(to_py(
                py,
                crawlopt::Error::invalid(
                    "rates",
                    format!("{rates:?}"),
                    format!(
                        "must be {} finite numbers (one per link)",
                        self.inner.links()
                    ),
                ),
            ));
        }
        Ok(self.inner.vm(&rates))
    }

    /// Raises NonUniqueError when the uniqueness condition (paper eq. 3.6) fails.
    fn require_unique(&self, py: Python<'_>) -> PyResult<()> {
        self.inner.require_unique().map_err(|e| to_py(py, e))
    }
}

/// An actuation: the prescribed actuator lengths L(t), periodic.
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct Actuation {
    pub inner: crawlopt::integrate::Actuation,
}

#[pymethods]
impl Actuation {
    /// A wave `L_l(t) = mean_l + amplitude_l w(2 pi t / T - phase_l)`; `kind` "sine" or
    /// "triangle".
    #[staticmethod]
    fn wave(
        py: Python<'_>,
        kind: &str,
        period: f64,
        mean: Vec<f64>,
        amplitude: Vec<f64>,
        phase_deg: Vec<f64>,
    ) -> PyResult<Self> {
        let wave = match kind {
            "sine" => Waveform::Sine,
            "triangle" => Waveform::Triangle,
            other => {
                let e = crawlopt::Error::invalid("kind", other, "must be sine or triangle");
                return Err(to_py(py, e));
            }
        };
        crawlopt::integrate::Actuation::wave(wave, period, mean, amplitude, phase_deg)
            .map(|inner| Actuation { inner })
            .map_err(|e| to_py(py, e))
    }

    /// A periodic piecewise-linear actuation through knots (`times` in [0, period), one row of
    /// `lengths` per knot).
    #[staticmethod]
    fn piecewise_linear(
        py: Python<'_>,
        period: f64,
        times: Vec<f64>,
        lengths: Vec<Vec<f64>>,
    ) -> PyResult<Self> {
        crawlopt::integrate::Actuation::piecewise_linear(period, times, lengths)
            .map(|inner| Actuation { inner })
            .map_err(|e| to_py(py, e))
    }

    #[getter]
    fn period(&self) -> f64 {
        self.inner.period()
    }

    #[getter]
    fn links(&self) -> usize {
        self.inner.links()
    }

    /// The lengths L(t) at the times `t`, one row per time.
    fn lengths_at(&self, t: Vec<f64>) -> Vec<Vec<f64>> {
        let mut row = vec![0.0; self.inner.links()];
        t.iter()
            .map(|&ti| {
                self.inner.lengths_at(ti, &mut row);
                row.clone()
            })
            .collect()
    }
}

/// The gait problem (P) of a crawler (theory §5): period T, rate bounds a_l = k_l x
/// max_actuator_speed_l, cost f2 (none or (c/2)|u|^2), optional bound on TV(u).
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct GaitProblem {
    pub inner: crawlopt::optimal::GaitProblem,
}

#[pymethods]
impl GaitProblem {
    /// Builds and validates the problem for `crawler` (`quadratic_weight` None: no cost).
    #[new]
    #[pyo3(signature = (crawler, period, max_actuator_speed, quadratic_weight=None, max_total_variation=None))]
    fn new(
        py: Python<'_>,
        crawler: &Crawler,
        period: f64,
        max_actuator_speed: Vec<f64>,
        quadratic_weight: Option<f64>,
        max_total_variation: Option<f64>,
    ) -> PyResult<Self> {
        let cost = quadratic_weight.map_or(Cost::None, |weight| Cost::Quadratic { weight });
        crawlopt::optimal::GaitProblem::new(
            &crawler.inner,
            period,
            &max_actuator_speed,
            cost,
            max_total_variation,
        )
        .map(|inner| GaitProblem { inner })
        .map_err(|e| to_py(py, e))
    }

    /// The problem as JSON text (as results record it).
    fn to_json(&self) -> String {
        crawlopt::io::json::to_string(&self.inner).expect("serialisable")
    }
}

/// What a model file holds: (crawler, gait problem, actuation, initial state).
type Loaded = (
    Crawler,
    Option<GaitProblem>,
    Option<Actuation>,
    Option<Vec<f64>>,
);

/// Reads a model file: (crawler, gait problem or None, actuation or None, initial state or
/// None), each checked as the command line checks it.
#[pyfunction]
pub fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Loaded> {
    let go = || -> crawlopt::Result<_> {
        let model = ModelFile::load(&path)?;
        let crawler = model.crawler()?;
        let gait = model.gait(&crawler)?;
        let act = match model.actuation.is_some() {
            true => Some(model.actuation(crawler.links())?),
            false => None,
        };
        Ok((crawler, gait, act, model.simulation.initial_state.clone()))
    };
    let (crawler, gait, act, x0) = go().map_err(|e| to_py(py, e))?;
    Ok((
        Crawler { inner: crawler },
        gait.map(|inner| GaitProblem { inner }),
        act.map(|inner| Actuation { inner }),
        x0,
    ))
}
