//! The model: crawler, actuation and gait problem as Python classes over the library's types,
//! `load` for a model file (the TOML schema of the command line) and `model_toml` to write one.
//!
//! Each class keeps the model file's section it was built from (`crawlopt::io::CrawlerSpec`,
//! `ActuationSpec`, `GaitSpec`): a single number stands for every link or block exactly as in
//! the file (the library expands it), the section is what `to_toml` writes, and it is the
//! pickled state (JSON), from which the library builds the same object again.

use crate::errors::to_py;
use crawlopt::integrate::{TravellingWave, WaveDirection, Waveform};
use crawlopt::io::{ActuationSpec, CostSpec, CrawlerSpec, GaitSpec, ModelFile, NumberOrList};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::path::Path;

/// A number for every entry, or one per entry (the file's `NumberOrList`).
#[derive(FromPyObject)]
pub enum Numbers {
    /// One number.
    One(f64),
    /// One per entry.
    Many(Vec<f64>),
}

impl From<Numbers> for NumberOrList {
    fn from(n: Numbers) -> Self {
        match n {
            Numbers::One(v) => NumberOrList::One(v),
            Numbers::Many(v) => NumberOrList::Many(v),
        }
    }
}

/// `value` as the JSON of a pickled state.
fn state<T: serde::Serialize>(value: &T) -> String {
    serde_json::to_string(value).expect("serialisable")
}

/// A pickled state read back (a ValueError if it was not written by `state`).
fn from_state<T: serde::de::DeserializeOwned>(text: &str) -> PyResult<T> {
    serde_json::from_str(text)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("not a crawlopt state: {e}")))
}

/// `(cls._from_state, (state,))`: what `__reduce__` returns.
pub fn reduce<'py>(slf: &Bound<'py, PyAny>, state: String) -> PyResult<Bound<'py, PyTuple>> {
    let rebuild = slf.get_type().getattr("_from_state")?;
    PyTuple::new(
        slf.py(),
        [
            rebuild.into_any(),
            PyTuple::new(slf.py(), [state])?.into_any(),
        ],
    )
}

/// A crawler: N blocks, N - 1 links (stiffness k_l), friction thresholds mu+ and mu- per block.
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct Crawler {
    pub inner: crawlopt::Crawler,
}

#[pymethods]
impl Crawler {
    /// Builds and validates a crawler as the model file's `[crawler]` section does: each of
    /// `stiffness` (per link), `mu_forward` and `mu_backward` (per block) a number for all or a
    /// list.
    #[new]
    fn new(
        py: Python<'_>,
        blocks: i64,
        stiffness: Numbers,
        mu_forward: Numbers,
        mu_backward: Numbers,
    ) -> PyResult<Self> {
        let spec = CrawlerSpec {
            blocks,
            stiffness: stiffness.into(),
            mu_forward: mu_forward.into(),
            mu_backward: mu_backward.into(),
        };
        spec.crawler()
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

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }

    /// The hash of the numbers (equal crawlers have equal numbers, so equal hashes).
    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        for v in [
            self.inner.stiffness(),
            self.inner.mu_forward(),
            self.inner.mu_backward(),
        ] {
            v.len().hash(&mut h);
            v.iter().for_each(|x| x.to_bits().hash(&mut h));
        }
        h.finish()
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        reduce(slf.as_any(), state(&CrawlerSpec::of(&slf.get().inner)))
    }

    #[staticmethod]
    fn _from_state(py: Python<'_>, text: &str) -> PyResult<Self> {
        let spec: CrawlerSpec = from_state(text)?;
        spec.crawler()
            .map(|inner| Crawler { inner })
            .map_err(|e| to_py(py, e))
    }
}

/// An actuation: the prescribed actuator lengths L(t), periodic, as the `[actuation]` section
/// it was built from. A section whose every value is a single number fits a crawler of any
/// size (`inner` None until bound to the crawler's links, as the file form is).
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct Actuation {
    pub spec: ActuationSpec,
    pub inner: Option<crawlopt::integrate::Actuation>,
}

impl Actuation {
    /// The actuation of `spec`, built for `links` (or the links its lists imply); checked
    /// (on one link) even when it is not bound.
    fn of(spec: ActuationSpec, links: Option<usize>) -> crawlopt::Result<Self> {
        match links.or_else(|| spec.implied_links()) {
            Some(n) => {
                let inner = spec.actuation(n, Path::new(""))?;
                Ok(Actuation {
                    spec: spec.self_contained(&inner),
                    inner: Some(inner),
                })
            }
            None => {
                spec.actuation(1, Path::new(""))?;
                Ok(Actuation { spec, inner: None })
            }
        }
    }

    /// The actuation for a crawler of `links` links.
    pub fn bound(&self, links: usize) -> crawlopt::Result<crawlopt::integrate::Actuation> {
        match &self.inner {
            Some(a) => Ok(a.clone()),
            None => self.spec.actuation(links, Path::new("")),
        }
    }
}

fn waveform(py: Python<'_>, field: &str, kind: &str) -> PyResult<Waveform> {
    match kind {
        "sine" => Ok(Waveform::Sine),
        "triangle" => Ok(Waveform::Triangle),
        other => Err(to_py(
            py,
            crawlopt::Error::invalid(field, other, "must be \"sine\" or \"triangle\""),
        )),
    }
}

#[pymethods]
impl Actuation {
    /// The actuation of an `[actuation]` section of `kind` "sine", "triangle" or
    /// "piecewise_linear" with the section's fields (each a number for every link or a list);
    /// `links` binds it to that many links (default: the length of its lists, or unbound).
    #[staticmethod]
    #[pyo3(signature = (kind, period, amplitude=None, phase_deg=None, mean=None, times=None, lengths=None, links=None))]
    #[allow(clippy::too_many_arguments)]
    fn section(
        py: Python<'_>,
        kind: String,
        period: f64,
        amplitude: Option<Numbers>,
        phase_deg: Option<Numbers>,
        mean: Option<Numbers>,
        times: Option<Vec<f64>>,
        lengths: Option<Vec<Numbers>>,
        links: Option<usize>,
    ) -> PyResult<Self> {
        if kind == "csv" {
            let e = crawlopt::Error::invalid(
                "actuation.kind",
                "\"csv\"",
                "a CSV actuation is read from a model file (crawlopt.load)",
            );
            return Err(to_py(py, e));
        }
        let spec = ActuationSpec {
            kind,
            period,
            amplitude: amplitude.map(Into::into),
            phase_deg: phase_deg.map(Into::into),
            mean: mean.map(Into::into),
            times,
            lengths: lengths.map(|rows| rows.into_iter().map(Into::into).collect()),
            path: None,
        };
        Actuation::of(spec, links).map_err(|e| to_py(py, e))
    }

    /// A travelling wave on `links` links (`crawlopt::integrate::TravellingWave`; None takes
    /// its default): `waveform` "sine" or "triangle", `direction` "first_to_last" or
    /// "last_to_first".
    #[staticmethod]
    #[pyo3(signature = (links, waveform=None, period=None, amplitude=None, mean=None, lag_deg=None, wavelength=None, direction=None))]
    #[allow(clippy::too_many_arguments)]
    fn travelling_wave(
        py: Python<'_>,
        links: usize,
        waveform: Option<&str>,
        period: Option<f64>,
        amplitude: Option<f64>,
        mean: Option<f64>,
        lag_deg: Option<f64>,
        wavelength: Option<f64>,
        direction: Option<&str>,
    ) -> PyResult<Self> {
        let d = TravellingWave::new(links);
        let w = TravellingWave {
            links,
            wave: match waveform {
                None => d.wave,
                Some(k) => self::waveform(py, "actuation.waveform", k)?,
            },
            period: period.unwrap_or(d.period),
            amplitude: amplitude.unwrap_or(d.amplitude),
            mean: mean.unwrap_or(d.mean),
            lag_deg,
            wavelength,
            direction: match direction {
                None => d.direction,
                Some("first_to_last") => WaveDirection::FirstToLast,
                Some("last_to_first") => WaveDirection::LastToFirst,
                Some(other) => {
                    let e = crawlopt::Error::invalid(
                        "actuation.direction",
                        other,
                        "must be \"first_to_last\" or \"last_to_first\"",
                    );
                    return Err(to_py(py, e));
                }
            },
        };
        let go = || -> crawlopt::Result<Self> {
            let inner = crawlopt::integrate::Actuation::travelling_wave(&w)?;
            let spec = ActuationSpec {
                kind: match w.wave {
                    Waveform::Sine => "sine",
                    Waveform::Triangle => "triangle",
                }
                .into(),
                period: w.period,
                amplitude: Some(NumberOrList::One(w.amplitude)),
                phase_deg: Some(NumberOrList::Many(w.phases_deg()?)),
                mean: Some(NumberOrList::One(w.mean)),
                times: None,
                lengths: None,
                path: None,
            };
            Ok(Actuation {
                spec,
                inner: Some(inner),
            })
        };
        go().map_err(|e| to_py(py, e))
    }

    /// This actuation for a crawler of `links` links.
    fn bind(&self, py: Python<'_>, links: usize) -> PyResult<Self> {
        let inner = self.bound(links).map_err(|e| to_py(py, e))?;
        Ok(Actuation {
            spec: self.spec.clone(),
            inner: Some(inner),
        })
    }

    #[getter]
    fn period(&self) -> f64 {
        self.spec.period
    }

    /// The number of links (None: every value is a single number, for any crawler).
    #[getter]
    fn links(&self) -> Option<usize> {
        self.inner.as_ref().map(|a| a.links())
    }

    #[getter]
    fn kind(&self) -> String {
        self.spec.kind.clone()
    }

    /// The lengths L(t) at the times `t`, one row per time (one entry if not bound).
    fn lengths_at(&self, py: Python<'_>, t: Vec<f64>) -> PyResult<Vec<Vec<f64>>> {
        let a = self.bound(1).map_err(|e| to_py(py, e))?;
        let mut row = vec![0.0; a.links()];
        Ok(t.iter()
            .map(|&ti| {
                a.lengths_at(ti, &mut row);
                row.clone()
            })
            .collect())
    }

    /// The `[actuation]` section as TOML text.
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        self.spec.to_toml().map_err(|e| to_py(py, e))
    }

    fn __eq__(&self, other: &Self) -> bool {
        match (&self.inner, &other.inner) {
            (Some(a), Some(b)) => a == b,
            (None, None) => self.spec == other.spec,
            _ => false,
        }
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let a = slf.get();
        reduce(slf.as_any(), state(&(&a.spec, a.links())))
    }

    #[staticmethod]
    fn _from_state(py: Python<'_>, text: &str) -> PyResult<Self> {
        let (spec, links): (ActuationSpec, Option<usize>) = from_state(text)?;
        Actuation::of(spec, links).map_err(|e| to_py(py, e))
    }
}

/// The gait problem (P) of a crawler (theory §5): period T, rate bounds a_l = k_l x
/// max_actuator_speed_l, cost f2 (none or (c/2)|u|^2), optional bound on TV(u); with the
/// `[gait]` section and the crawler it was posed for.
#[pyclass(module = "crawlopt._crawlopt", frozen)]
#[derive(Clone)]
pub struct GaitProblem {
    pub inner: crawlopt::optimal::GaitProblem,
    pub spec: GaitSpec,
    pub crawler: crawlopt::Crawler,
}

impl GaitProblem {
    fn of(spec: GaitSpec, crawler: crawlopt::Crawler) -> crawlopt::Result<Self> {
        let inner = spec.problem(&crawler)?;
        Ok(GaitProblem {
            inner,
            spec,
            crawler,
        })
    }
}

#[pymethods]
impl GaitProblem {
    /// Builds and validates the problem for `crawler` as the `[gait]` section does
    /// (`max_actuator_speed` a number for every link or a list; `quadratic_weight` None: no
    /// cost).
    #[new]
    #[pyo3(signature = (crawler, period, max_actuator_speed, quadratic_weight=None, max_total_variation=None))]
    fn new(
        py: Python<'_>,
        crawler: &Crawler,
        period: f64,
        max_actuator_speed: Numbers,
        quadratic_weight: Option<f64>,
        max_total_variation: Option<f64>,
    ) -> PyResult<Self> {
        let spec = GaitSpec {
            period,
            max_actuator_speed: max_actuator_speed.into(),
            cost: quadratic_weight.map(|w| CostSpec {
                kind: "quadratic".into(),
                weight: Some(w),
            }),
            max_total_variation,
        };
        GaitProblem::of(spec, crawler.inner.clone()).map_err(|e| to_py(py, e))
    }

    /// The problem as JSON text (as results record it).
    fn to_json(&self) -> String {
        crawlopt::io::json::to_string(&self.inner).expect("serialisable")
    }

    /// `max_actuator_speed` as the section gives it (a number, or one per link).
    #[getter]
    fn max_actuator_speed(&self, py: Python<'_>) -> PyResult<PyObject> {
        Ok(match &self.spec.max_actuator_speed {
            NumberOrList::One(v) => v.into_pyobject(py)?.into_any().unbind(),
            NumberOrList::Many(v) => v.into_pyobject(py)?.into_any().unbind(),
        })
    }

    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let p = slf.get();
        reduce(slf.as_any(), state(&(&p.spec, CrawlerSpec::of(&p.crawler))))
    }

    #[staticmethod]
    fn _from_state(py: Python<'_>, text: &str) -> PyResult<Self> {
        let (spec, crawler): (GaitSpec, CrawlerSpec) = from_state(text)?;
        let go = || GaitProblem::of(spec, crawler.crawler()?);
        go().map_err(|e| to_py(py, e))
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
/// None), each checked as the command line checks it. A CSV actuation is kept as the
/// piecewise-linear one through its knots (so that it can be written without the CSV file).
#[pyfunction]
pub fn load(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Loaded> {
    let go = || -> crawlopt::Result<_> {
        let model = ModelFile::load(&path)?;
        let crawler = model.crawler()?;
        let gait = match &model.gait {
            Some(g) => Some(GaitProblem::of(g.clone(), crawler.clone())?),
            None => None,
        };
        let act = match &model.actuation {
            Some(spec) => {
                let inner = model.actuation(crawler.links())?;
                Some(Actuation {
                    spec: spec.self_contained(&inner),
                    inner: Some(inner),
                })
            }
            None => None,
        };
        Ok((crawler, gait, act, model.simulation.initial_state.clone()))
    };
    let (crawler, gait, act, x0) = go().map_err(|e| to_py(py, e))?;
    Ok((Crawler { inner: crawler }, gait, act, x0))
}

/// The model file of a crawler, its actuation, its gait problem and the initial state, as TOML
/// text; checked as `load` checks it (each part for this crawler) before it is written.
#[pyfunction]
#[pyo3(signature = (crawler, actuation=None, gait=None, initial_state=None))]
pub fn model_toml(
    py: Python<'_>,
    crawler: &Crawler,
    actuation: Option<&Actuation>,
    gait: Option<&GaitProblem>,
    initial_state: Option<Vec<f64>>,
) -> PyResult<String> {
    let model = ModelFile {
        crawler: CrawlerSpec::of(&crawler.inner),
        actuation: actuation.map(|a| a.spec.clone()),
        simulation: crawlopt::io::SimulationSpec { initial_state },
        gait: gait.map(|g| g.spec.clone()),
        base_dir: Default::default(),
    };
    let go = || -> crawlopt::Result<String> {
        model.check()?;
        model.to_toml()
    };
    go().map_err(|e| to_py(py, e))
}
