//! Actuations: the prescribed actuator lengths `L_l(t)`, `T`-periodic (theory §1, §3).
//!
//! The control of the sweeping process is `u_l = k_l L_l'`; integrators only ever use increments
//! `K (L(t') - L(t))`, so the actuation is rate-independent data plus a clock.

use crate::error::{Error, Result};
use std::f64::consts::PI;

/// Shape of a smooth periodic actuation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Waveform {
    /// `s = sin`.
    Sine,
    /// `s(th) = (2/pi) asin(sin th)`: a triangle wave with the sine's peaks.
    Triangle,
}

/// A `T`-periodic actuation of the `n` links.
#[derive(Debug, Clone, PartialEq)]
pub enum Actuation {
    /// `L_l(t) = mean_l + amplitude_l * s(2 pi t / T - phase_l)`.
    Wave {
        /// Sine or triangle.
        wave: Waveform,
        /// Period `T`.
        period: f64,
        /// Mean length per link.
        mean: Vec<f64>,
        /// Amplitude per link.
        amplitude: Vec<f64>,
        /// Phase lag per link, radians.
        phase: Vec<f64>,
    },
    /// Linear interpolation between knots, periodic: after the last knot the lengths return to
    /// the first knot's at `t = T`.
    PiecewiseLinear {
        /// Period `T`.
        period: f64,
        /// Knot times, strictly increasing in `[0, T)`.
        times: Vec<f64>,
        /// `lengths[j][l]`: length of link `l` at knot `j`.
        lengths: Vec<Vec<f64>>,
    },
}

fn positive(field: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(field, v, "must be positive and finite"))
    }
}

fn finite(field: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(Error::invalid(
            format!("{field}[{}]", i + 1),
            values[i],
            "must be finite",
        )),
        None => Ok(()),
    }
}

/// Largest ratio of an actuator length's offset to its stroke (the wave's mean to its
/// amplitude; the largest |L| of piecewise-linear knots to their range). Only the changes of L
/// move the crawler, and they are computed as differences of lengths: beyond this ratio they
/// lose more than 6 of their 16 digits to the offset (a mean of 1e300 once left a stroke of 2
/// as a motion of 0).
pub const MAX_OFFSET_RATIO: f64 = 1e6;

fn offset_error(field: String, offset: f64, stroke: f64) -> Error {
    Error::invalid(
        field,
        offset,
        format!(
            "an offset above {MAX_OFFSET_RATIO:e} times the stroke ({stroke}) leaves the \
             changes of length, which alone move the crawler, below double precision: subtract \
             a constant (it does not change the motion)"
        ),
    )
}

/// Which way a travelling wave runs along the body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WaveDirection {
    /// Link `l + 1` lags link `l`: the wave runs from link 1 to link `n` (the default).
    #[default]
    FirstToLast,
    /// Link `l` lags link `l + 1`: the wave runs from link `n` to link 1.
    LastToFirst,
}

/// A travelling wave on `links` links: `L_l(t) = mean + amplitude s(2 pi t / T - phase_l)`
/// with `phase_l = (l - 1) lag` ([`WaveDirection::FirstToLast`]) or `(n - l) lag`
/// ([`WaveDirection::LastToFirst`]). The lag is given in degrees (`lag_deg`) or as the
/// wavelength in links (`lag = 360 / wavelength`), not both; with neither, one wavelength spans
/// the body (`wavelength = links`). [`TravellingWave::new`] sets the documented defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct TravellingWave {
    /// Number of links `n >= 1`.
    pub links: usize,
    /// The shape `s` (default sine).
    pub wave: Waveform,
    /// Period `T` (default 1).
    pub period: f64,
    /// Amplitude of every link (default 1).
    pub amplitude: f64,
    /// Mean length of every link (default 0).
    pub mean: f64,
    /// Lag of a link behind its neighbour, degrees (default: from `wavelength`).
    pub lag_deg: Option<f64>,
    /// Wavelength in links (default: `links` when `lag_deg` is not given either).
    pub wavelength: Option<f64>,
    /// Which way the wave runs (default first to last).
    pub direction: WaveDirection,
}

impl TravellingWave {
    /// The wave on `links` links with the defaults: a sine of period 1, amplitude 1, mean 0,
    /// one wavelength along the body, running from link 1 to link `n`.
    pub fn new(links: usize) -> Self {
        TravellingWave {
            links,
            wave: Waveform::Sine,
            period: 1.0,
            amplitude: 1.0,
            mean: 0.0,
            lag_deg: None,
            wavelength: None,
            direction: WaveDirection::FirstToLast,
        }
    }

    /// The lag of a link behind its neighbour, degrees.
    pub fn lag_deg(&self) -> Result<f64> {
        if self.links == 0 {
            return Err(Error::invalid(
                "actuation.links",
                0,
                "a travelling wave needs at least one link",
            ));
        }
        match (self.lag_deg, self.wavelength) {
            (Some(_), Some(_)) => Err(Error::invalid(
                "actuation.wavelength",
                "given with lag_deg",
                "give the lag either in degrees (lag_deg) or as a wavelength, not both",
            )),
            (Some(lag), None) => {
                finite("actuation.lag_deg", &[lag])?;
                Ok(lag)
            }
            (None, w) => {
                let w = w.unwrap_or(self.links as f64);
                positive("actuation.wavelength", w)?;
                Ok(360.0 / w)
            }
        }
    }

    /// The phase lag of each link, degrees (`phase_deg` of the equivalent wave).
    pub fn phases_deg(&self) -> Result<Vec<f64>> {
        let lag = self.lag_deg()?;
        let n = self.links;
        Ok((0..n)
            .map(|l| match self.direction {
                WaveDirection::FirstToLast => l as f64 * lag,
                WaveDirection::LastToFirst => (n - 1 - l) as f64 * lag,
            })
            .collect())
    }
}

impl Actuation {
    /// A wave actuation with validated parameters; `phase_deg` in degrees.
    pub fn wave(
        wave: Waveform,
        period: f64,
        mean: Vec<f64>,
        amplitude: Vec<f64>,
        phase_deg: Vec<f64>,
    ) -> Result<Self> {
        positive("actuation.period", period)?;
        let n = amplitude.len();
        for (name, v) in [
            ("actuation.mean", &mean),
            ("actuation.phase_deg", &phase_deg),
        ] {
            if v.len() != n {
                return Err(Error::invalid(
                    name,
                    format!("{} values", v.len()),
                    format!("needs one value per link ({n})"),
                ));
            }
            finite(name, v)?;
        }
        for (i, &a) in amplitude.iter().enumerate() {
            positive(&format!("actuation.amplitude[{}]", i + 1), a)?;
            if mean[i].abs() > MAX_OFFSET_RATIO * a {
                return Err(offset_error(
                    format!("actuation.mean[{}]", i + 1),
                    mean[i],
                    a,
                ));
            }
        }
        Ok(Actuation::Wave {
            wave,
            period,
            mean,
            amplitude,
            phase: phase_deg.iter().map(|d| (d % 360.0).to_radians()).collect(),
        })
    }

    /// The travelling wave `w` (see [`TravellingWave`]): a wave of the same shape, amplitude
    /// and mean on every link, each link lagging its neighbour by the same phase.
    pub fn travelling_wave(w: &TravellingWave) -> Result<Self> {
        let n = w.links;
        Actuation::wave(
            w.wave,
            w.period,
            vec![w.mean; n],
            vec![w.amplitude; n],
            w.phases_deg()?,
        )
    }

    /// A periodic piecewise-linear actuation with validated knots.
    pub fn piecewise_linear(period: f64, times: Vec<f64>, lengths: Vec<Vec<f64>>) -> Result<Self> {
        positive("actuation.period", period)?;
        if times.len() < 2 {
            return Err(Error::invalid(
                "actuation.times",
                format!("{} knots", times.len()),
                "needs at least 2 knots",
            ));
        }
        if lengths.len() != times.len() {
            return Err(Error::invalid(
                "actuation.lengths",
                format!("{} rows", lengths.len()),
                format!("needs one row per knot ({})", times.len()),
            ));
        }
        finite("actuation.times", &times)?;
        if times[0] < 0.0 {
            return Err(Error::invalid(
                "actuation.times[1]",
                times[0],
                "must be >= 0",
            ));
        }
        for j in 1..times.len() {
            if times[j] <= times[j - 1] {
                return Err(Error::invalid(
                    format!("actuation.times[{}]", j + 1),
                    times[j],
                    "must be strictly increasing",
                ));
            }
        }
        let last = times[times.len() - 1];
        if last >= period {
            return Err(Error::invalid(
                format!("actuation.times[{}]", times.len()),
                last,
                format!("must be < period ({period})"),
            ));
        }
        let n = lengths[0].len();
        if n == 0 {
            return Err(Error::invalid(
                "actuation.lengths[1]",
                "[]",
                "needs one value per link",
            ));
        }
        for (j, row) in lengths.iter().enumerate() {
            if row.len() != n {
                return Err(Error::invalid(
                    format!("actuation.lengths[{}]", j + 1),
                    format!("{} values", row.len()),
                    format!("needs one value per link ({n}), like the first row"),
                ));
            }
            finite(&format!("actuation.lengths[{}]", j + 1), row)?;
        }
        for l in 0..n {
            let (lo, hi, big) = lengths.iter().fold(
                (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64),
                |(lo, hi, big), r| (lo.min(r[l]), hi.max(r[l]), big.max(r[l].abs())),
            );
            if hi > lo && big > MAX_OFFSET_RATIO * (hi - lo) {
                return Err(offset_error(
                    format!("actuation.lengths[*][{}]", l + 1),
                    big,
                    hi - lo,
                ));
            }
        }
        Ok(Actuation::PiecewiseLinear {
            period,
            times,
            lengths,
        })
    }

    /// The actuation of a gait's knots over one period (`times` from 0, one row of `lengths`
    /// per knot, the closing knot at `T` left out). A gait of one piece has one knot: its
    /// zero-mean control is 0, so `L` is constant, and a second knot of the same length makes
    /// it an actuation (which needs two).
    pub fn of_gait(period: f64, mut times: Vec<f64>, mut lengths: Vec<Vec<f64>>) -> Result<Self> {
        if times.len() == 1 && lengths.len() == 1 {
            times.push(0.5 * period);
            lengths.push(lengths[0].clone());
        }
        Actuation::piecewise_linear(period, times, lengths)
    }

    /// The period `T`.
    pub fn period(&self) -> f64 {
        match self {
            Actuation::Wave { period, .. } | Actuation::PiecewiseLinear { period, .. } => *period,
        }
    }

    /// Number of actuated links.
    pub fn links(&self) -> usize {
        match self {
            Actuation::Wave { amplitude, .. } => amplitude.len(),
            Actuation::PiecewiseLinear { lengths, .. } => lengths[0].len(),
        }
    }

    /// Whether the actuation is itself piecewise linear (the exact method is then exact).
    pub fn is_piecewise_linear(&self) -> bool {
        matches!(self, Actuation::PiecewiseLinear { .. })
    }

    /// `L(t)` into `out`, for any `t` (periodic extension).
    pub fn lengths_at(&self, t: f64, out: &mut [f64]) {
        match self {
            Actuation::Wave {
                wave,
                period,
                mean,
                amplitude,
                phase,
            } => {
                let th = 2.0 * PI * t / period;
                for l in 0..out.len() {
                    let s = (th - phase[l]).sin();
                    let s = match wave {
                        Waveform::Sine => s,
                        Waveform::Triangle => 2.0 / PI * s.clamp(-1.0, 1.0).asin(),
                    };
                    out[l] = mean[l] + amplitude[l] * s;
                }
            }
            Actuation::PiecewiseLinear {
                period,
                times,
                lengths,
            } => {
                let mut tau = t.rem_euclid(*period);
                let k = times.len();
                // Segment j runs from knot j to knot j+1; the last one closes at knot 0 + T.
                let i = times.partition_point(|&tj| tj <= tau);
                let j = if i == 0 {
                    tau += period; // before the first knot: on the closing segment
                    k - 1
                } else {
                    i - 1
                };
                let t1 = if j + 1 < k {
                    times[j + 1]
                } else {
                    times[0] + period
                };
                let (a, b) = (&lengths[j], &lengths[(j + 1) % k]);
                let s = (tau - times[j]) / (t1 - times[j]);
                for l in 0..out.len() {
                    out[l] = a[l] + s * (b[l] - a[l]);
                }
            }
        }
    }

    /// The knots `(times, lengths)` of the piecewise-linear actuation the exact method plays:
    /// the actuation's own knots when it is piecewise linear (with a knot added at `t = 0` if
    /// needed, so that a period always starts at 0), otherwise its interpolant on `m` uniform
    /// knots `t_i = i T / m`.
    pub fn knots(&self, m: usize) -> (Vec<f64>, Vec<Vec<f64>>) {
        match self {
            Actuation::PiecewiseLinear { times, lengths, .. } => {
                let (mut t, mut l) = (times.clone(), lengths.clone());
                if t[0] > 0.0 {
                    // Start the period at t = 0, on the closing segment.
                    let mut row = vec![0.0; self.links()];
                    self.lengths_at(0.0, &mut row);
                    t.insert(0, 0.0);
                    l.insert(0, row);
                }
                (t, l)
            }
            Actuation::Wave { period, .. } => {
                let times: Vec<f64> = (0..m).map(|i| (i as f64 / m as f64) * period).collect();
                let lengths = times
                    .iter()
                    .map(|&t| {
                        let mut row = vec![0.0; self.links()];
                        self.lengths_at(t, &mut row);
                        row
                    })
                    .collect();
                (times, lengths)
            }
        }
    }

    /// One sentence for outputs: what the exact method plays with `m` knots.
    pub fn exact_description(&self, m: usize) -> String {
        match self {
            Actuation::PiecewiseLinear { times, .. } => {
                format!("the piecewise-linear actuation itself ({} knots): no discretisation error", times.len())
            }
            Actuation::Wave { .. } => format!(
                "the piecewise-linear interpolant of the actuation on {m} uniform knots (exact for that interpolant)"
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_travelling_wave_lags_each_link_behind_its_neighbour() {
        let mut w = TravellingWave::new(4);
        w.period = 2.0;
        w.amplitude = 1.5;
        w.lag_deg = Some(45.0);
        let a = Actuation::travelling_wave(&w).unwrap();
        // L_{l+1}(t + T lag / 360) = L_l(t): the wave runs from link 1 to link n.
        let (mut now, mut later) = (vec![0.0; 4], vec![0.0; 4]);
        for t in [0.0, 0.3, 1.1] {
            a.lengths_at(t, &mut now);
            a.lengths_at(t + 2.0 * 45.0 / 360.0, &mut later);
            for l in 0..3 {
                assert!((later[l + 1] - now[l]).abs() < 1e-12, "{t} {l}");
            }
        }
        w.direction = WaveDirection::LastToFirst;
        assert_eq!(w.phases_deg().unwrap(), vec![135.0, 90.0, 45.0, 0.0]);
        // Default: one wavelength along the body.
        w.lag_deg = None;
        assert_eq!(w.lag_deg().unwrap(), 90.0);
        w.wavelength = Some(8.0);
        assert_eq!(w.lag_deg().unwrap(), 45.0);
        w.lag_deg = Some(10.0);
        let e = w.lag_deg().unwrap_err().to_string();
        assert!(e.starts_with("actuation.wavelength"), "{e}");
        w.lag_deg = None;
        w.wavelength = Some(0.0);
        let e = w.lag_deg().unwrap_err().to_string();
        assert!(e.starts_with("actuation.wavelength"), "{e}");
    }

    #[test]
    fn piecewise_linear_wraps_periodically() {
        let a =
            Actuation::piecewise_linear(4.0, vec![1.0, 2.0], vec![vec![0.0], vec![2.0]]).unwrap();
        let mut l = [0.0];
        for (t, want) in [
            (1.0, 0.0),
            (1.5, 1.0),
            (2.0, 2.0),
            (3.5, 1.0),
            (0.5, 1.0 / 3.0),
            (5.5, 1.0),
            (-2.5, 1.0),
        ] {
            a.lengths_at(t, &mut l);
            assert!((l[0] - want).abs() < 1e-15, "t = {t}: {} vs {want}", l[0]);
        }
    }

    #[test]
    fn triangle_has_sine_peaks_and_is_linear() {
        let a = Actuation::wave(Waveform::Triangle, 1.0, vec![0.5], vec![2.0], vec![0.0]).unwrap();
        let mut l = [0.0];
        a.lengths_at(0.25, &mut l);
        assert!((l[0] - 2.5).abs() < 1e-12);
        a.lengths_at(0.125, &mut l);
        assert!((l[0] - 1.5).abs() < 1e-12);
        a.lengths_at(0.75, &mut l);
        assert!((l[0] + 1.5).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_named() {
        let e = Actuation::wave(Waveform::Sine, 0.0, vec![0.0], vec![1.0], vec![0.0]).unwrap_err();
        assert!(e.to_string().starts_with("actuation.period"), "{e}");
        let e = Actuation::wave(Waveform::Sine, 1.0, vec![0.0], vec![-1.0], vec![0.0]).unwrap_err();
        assert!(e.to_string().starts_with("actuation.amplitude[1]"), "{e}");
        let e = Actuation::piecewise_linear(1.0, vec![0.0, 0.0], vec![vec![0.0], vec![1.0]])
            .unwrap_err();
        assert!(e.to_string().starts_with("actuation.times[2]"), "{e}");
    }
}
