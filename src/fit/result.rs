//! The settings of a fit, the names of the parameters, and the result.

use crate::error::{Error, Result};
use crate::model::Crawler;
use serde::Serialize;

/// Which family a parameter belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ParamKind {
    /// Link stiffness `k_l` (force / length).
    Stiffness,
    /// Threshold `mu_b^+` against forward motion (force).
    MuForward,
    /// Threshold `mu_b^-` against backward motion (force).
    MuBackward,
}

impl ParamKind {
    /// The name used in files, flags and messages.
    pub fn name(self) -> &'static str {
        match self {
            ParamKind::Stiffness => "stiffness",
            ParamKind::MuForward => "mu_forward",
            ParamKind::MuBackward => "mu_backward",
        }
    }
}

/// One parameter of a crawler: a family and a 0-based index (shown 1-based:
/// `stiffness[1]`, `mu_backward[3]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Param {
    /// The family.
    pub kind: ParamKind,
    /// 0-based link or block.
    pub index: usize,
}

impl std::fmt::Display for Param {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}[{}]", self.kind.name(), self.index + 1)
    }
}

impl std::str::FromStr for Param {
    type Err = Error;

    /// Parses `stiffness[1]`, `mu_forward[2]`, `mu_backward[3]` (1-based).
    fn from_str(s: &str) -> Result<Self> {
        let bad = || {
            Error::invalid(
                "fix",
                s,
                "expected NAME[i] with NAME one of stiffness, mu_forward, mu_backward and i from 1",
            )
        };
        let s = s.trim();
        let (name, rest) = s.split_once('[').ok_or_else(bad)?;
        let idx = rest.strip_suffix(']').ok_or_else(bad)?;
        let kind = match name.trim() {
            "stiffness" => ParamKind::Stiffness,
            "mu_forward" => ParamKind::MuForward,
            "mu_backward" => ParamKind::MuBackward,
            _ => return Err(bad()),
        };
        let i: usize = idx.trim().parse().map_err(|_| bad())?;
        if i == 0 {
            return Err(bad());
        }
        Ok(Param { kind, index: i - 1 })
    }
}

/// Defaults of [`FitSettings`].
impl FitSettings {
    /// Default [`FitSettings::noise_bound`].
    pub const NOISE_BOUND: f64 = 5.0;
    /// Default [`FitSettings::max_outlier_fraction`].
    pub const MAX_OUTLIER_FRACTION: f64 = 0.02;
    /// Default [`FitSettings::unbounded_factor`].
    pub const UNBOUNDED_FACTOR: f64 = 2.0;
}

/// How to fit a crawler to a measured trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSettings {
    /// Parameters whose value is known (`stiffness[1] = 1`, ...). Positions alone only
    /// determine ratios of forces (multiplying every `k` and `mu` by one factor leaves the
    /// motion unchanged), so one fixed parameter sets the force scale; several are allowed (the
    /// data may then contradict them). Empty (the default): the fit reports ratios to
    /// `stiffness[1]`, which it sets to 1.
    pub fixes: Vec<(Param, f64)>,
    /// Standard deviation `sigma` of the measurement noise on each position `X_b` (length
    /// units). `None` (the default): estimated from the data and reported.
    pub noise: Option<f64>,
    /// The intervals assume every position error is at most `noise_bound * sigma` (default 5:
    /// for Gaussian noise each value exceeds it with probability 5.7e-7).
    pub noise_bound: f64,
    /// When no parameter vector is consistent with every sample, the samples whose
    /// least-absolute-deviations residual exceeds the noise bound are outliers and left out of
    /// the intervals, up to this fraction of the samples (default 0.02); more such samples, or
    /// none consistent without them, mean the data contradict the model (a warning, no
    /// intervals), and none is left out.
    pub max_outlier_fraction: f64,
    /// A parameter the data bound only from below (a threshold never seen sliding that way) has
    /// no estimate; the model file takes this factor times its lower bound (default 2), with a
    /// warning.
    pub unbounded_factor: f64,
    /// Re-simulate the fitted crawler under the measured actuation and report the prediction
    /// error (default true).
    pub predict: bool,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            fixes: Vec::new(),
            noise: None,
            noise_bound: Self::NOISE_BOUND,
            max_outlier_fraction: Self::MAX_OUTLIER_FRACTION,
            unbounded_factor: Self::UNBOUNDED_FACTOR,
            predict: true,
        }
    }
}

impl FitSettings {
    /// Refuses settings no fit runs with, naming the field; `blocks` checks the fixes' indices.
    pub fn check(&self, blocks: usize) -> Result<()> {
        if let Some(s) = self.noise {
            if !(s.is_finite() && s >= 0.0) {
                return Err(Error::invalid("noise", s, "must be finite and >= 0"));
            }
        }
        if !(self.noise_bound.is_finite() && self.noise_bound > 0.0) {
            return Err(Error::invalid(
                "noise_bound",
                self.noise_bound,
                "must be positive and finite",
            ));
        }
        if !(0.0..1.0).contains(&self.max_outlier_fraction) {
            return Err(Error::invalid(
                "max_outlier_fraction",
                self.max_outlier_fraction,
                "must be in [0, 1)",
            ));
        }
        if !(self.unbounded_factor.is_finite() && self.unbounded_factor >= 1.0) {
            return Err(Error::invalid(
                "unbounded_factor",
                self.unbounded_factor,
                "must be finite and >= 1",
            ));
        }
        for (i, (p, v)) in self.fixes.iter().enumerate() {
            let count = match p.kind {
                ParamKind::Stiffness => blocks - 1,
                _ => blocks,
            };
            if p.index >= count {
                return Err(Error::invalid(
                    format!("fix {p}"),
                    p.index + 1,
                    format!("a {blocks}-block crawler has {count} of {}", p.kind.name()),
                ));
            }
            if !(v.is_finite() && *v > 0.0) {
                return Err(Error::invalid(
                    format!("fix {p}"),
                    v,
                    "must be positive and finite",
                ));
            }
            if self.fixes[..i].iter().any(|(q, _)| q == p) {
                return Err(Error::invalid(format!("fix {p}"), v, "fixed twice"));
            }
        }
        Ok(())
    }
}

/// One value per parameter, by family (the JSON shape `{"stiffness": [...], "mu_forward":
/// [...], "mu_backward": [...]}`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PerParam<T> {
    /// Per link.
    pub stiffness: Vec<T>,
    /// Per block.
    pub mu_forward: Vec<T>,
    /// Per block.
    pub mu_backward: Vec<T>,
}

impl<T: Clone> PerParam<T> {
    /// From the flat layout `[k_1..k_n, mu+_1..mu+_N, mu-_1..mu-_N]`.
    pub fn from_flat(v: &[T], blocks: usize) -> Self {
        let n = blocks - 1;
        PerParam {
            stiffness: v[..n].to_vec(),
            mu_forward: v[n..n + blocks].to_vec(),
            mu_backward: v[n + blocks..n + 2 * blocks].to_vec(),
        }
    }

    /// The value of one parameter.
    pub fn get(&self, p: Param) -> &T {
        match p.kind {
            ParamKind::Stiffness => &self.stiffness[p.index],
            ParamKind::MuForward => &self.mu_forward[p.index],
            ParamKind::MuBackward => &self.mu_backward[p.index],
        }
    }
}

/// How the force scale was set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scale {
    /// The fixed parameters and their values, as given (e.g. `stiffness[1] = 1`).
    pub fixed: Vec<Fixed>,
    /// With nothing fixed: every force parameter is a ratio to this one (set to 1).
    pub ratios_to: Option<String>,
}

/// A parameter fixed to a value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fixed {
    /// Its name, e.g. `stiffness[1]`.
    pub parameter: String,
    /// Its value.
    pub value: f64,
}

/// The noise the fit assumed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoiseUsed {
    /// Standard deviation of the position noise (length units).
    pub sigma: f64,
    /// Whether `sigma` was estimated from the data (else given).
    pub estimated: bool,
    /// The bound on every position error the intervals assume: `noise_bound * sigma`, at least
    /// the data's rounding (1e-11 of the largest |L| or |X|).
    pub bound: f64,
    /// A block is taken as moving over a sample interval when it moves by more than this
    /// (twice the bound: no noise within the bound makes a still block look moving).
    pub slip_threshold: f64,
}

/// A run of sample intervals over which a block moved the same way.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SlipEpisode {
    /// `"forward"` or `"backward"`.
    pub direction: &'static str,
    /// First and last data row (from 1) of the run.
    pub rows: [usize; 2],
    /// Times of those rows.
    pub times: [f64; 2],
    /// Samples inside the run (moving on both sides) whose force was equated to the threshold.
    pub samples_used: usize,
}

/// What is left of the data after the fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Residuals {
    /// The least-absolute-deviations objective (force units): the sum of |F - mu| over the
    /// sliding samples and of the excess of |F| over its threshold elsewhere.
    pub lad_objective: f64,
    /// Per block, the largest residual over its samples, in length units (the force residual
    /// divided by the stiffness of the links at the block): compare with the noise bound.
    pub max_per_block: Vec<f64>,
    /// Root mean square of the residuals of the sliding samples, length units (0 when none).
    pub rms_sliding: f64,
}

/// The fitted model re-simulated under the measured actuation from the measured first state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// Root mean square over samples and blocks of `X_predicted - X_measured` (length units).
    pub rms: f64,
    /// Largest `|X_predicted - X_measured|`.
    pub max: f64,
    /// `max` over the range of the measured barycentre's motion (`None` when it did not move).
    pub relative: Option<f64>,
    /// Predicted positions, one row per sample (for figures; not in JSON).
    #[serde(skip)]
    pub positions: Vec<Vec<f64>>,
}

/// The answer of [`crate::fit::fit`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitResult {
    /// The estimates (`null` where the data do not bound a parameter above).
    pub crawler: PerParam<Option<f64>>,
    /// Per parameter `[lo, hi]`, the exact range over every parameter vector consistent with
    /// the data at the noise bound (`hi` null where unbounded); `None` when no parameter vector
    /// is (the data contradict the model: see the warnings).
    pub intervals: Option<PerParam<[Option<f64>; 2]>>,
    /// The values written to the model file: the estimates, and for a parameter without one
    /// [`FitSettings::unbounded_factor`] times its lower bound.
    pub model: Option<PerParam<f64>>,
    /// The crawler of `model` (not in JSON).
    #[serde(skip)]
    pub fitted: Option<Crawler>,
    /// How the force scale was set.
    pub scale: Scale,
    /// The noise used.
    pub noise: NoiseUsed,
    /// Per block, the slip episodes found.
    pub slip_episodes: Vec<Vec<SlipEpisode>>,
    /// Data rows (from 1) left out of the intervals as outliers.
    pub outlier_rows: Vec<usize>,
    /// What is left of the data.
    pub residuals: Residuals,
    /// The fitted crawler re-simulated against the data (`None` when it could not be built or
    /// simulated: see the warnings, or when not asked for).
    pub prediction: Option<Prediction>,
    /// Everything a reader must know: contradictions, outliers, unbounded parameters.
    pub warnings: Vec<String>,
    /// Number of samples.
    pub samples: usize,
    /// Number of blocks.
    pub blocks: usize,
    /// Per sample and block: 1 sliding forward, -1 backward, 0 otherwise (for figures).
    #[serde(skip)]
    pub sliding: Vec<Vec<i8>>,
}
