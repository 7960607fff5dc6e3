//! Identification of a crawler from a measured trajectory (`crawlopt fit`): the stiffnesses
//! and friction thresholds consistent with measured actuator lengths `L_l(t)` and block
//! positions `X_b(t)`, by linear programming.
//!
//! Sign conventions (theory §1–2): link `l` joins blocks `l` and `l + 1`; its spring is
//! compressed by `d_l = L_l - (X_(l+1) - X_l)` (length) and pushes with `x_l = k_l d_l`
//! (force); the net spring force on block `b` is `F_b = x_(b-1) - x_b` (`x_0 = x_N = 0`).
//! The flow rule says `F_b = mu_b^+` while block `b` slides forward, `F_b = -mu_b^-` while it
//! slides backward, and `-mu_b^- <= F_b <= mu_b^+` always. All of it is linear in the
//! parameters `p = (k, mu^+, mu^-)` and homogeneous: multiplying every force parameter by one
//! factor changes nothing, so a fit needs one known force scale ([`FitSettings::fixes`]), or
//! reports ratios to `stiffness[1]`.
//!
//! The method (docs/guide/fit.md):
//! 1. the noise `sigma` on positions is given or estimated ([`estimate_noise`]); the
//!    bound `e = noise_bound * sigma` on every position error is assumed;
//! 2. slips are detected against a threshold of `2 e` per interval (a sample is sliding when it
//!    moves the same way over both intervals around it);
//! 3. the estimate minimises the absolute deviations from the flow rule (an LP, robust to
//!    outliers), and samples whose residual exceeds the bound are outliers;
//! 4. each parameter's interval is its exact minimum and maximum over the polyhedron of
//!    parameters that satisfy the flow rule at every kept sample within the force error that
//!    the bound allows (LPs), and unboundedness is decided exactly on its recession cone;
//! 5. the fitted crawler is re-simulated under the measured actuation
//!    ([`crate::integrate::replay`]) and compared with the data.
//!
//! What the intervals guarantee: if every position error is at most `e`, every sample taken
//! as sliding is sliding (no stick shorter than a frame inside a slide) and the model holds,
//! then the true parameters (scaled by the fixed ones) lie in every interval.

mod data;
mod lp;
mod result;
mod slip;
mod synth;

pub use data::{column_names, FitData, MIN_SAMPLES};
pub use result::{
    FitResult, FitSettings, Fixed, NoiseUsed, Param, ParamKind, PerParam, Prediction, Residuals,
    Scale, SlipEpisode,
};
pub use slip::estimate_noise;
pub use synth::{record, Recording};

use crate::error::Result;
use crate::model::Crawler;

/// The relative rounding of the data that the bound on position errors never goes below.
pub const ROUNDING: f64 = 1e-11;

/// Fits a crawler with `data.blocks()` blocks to `data` under `settings` (see the module
/// docs). Errors: invalid settings (naming the field), a solver failure; a contradiction
/// between the data and the model is not an error but a warning, with `intervals: None`.
pub fn fit(data: &FitData, settings: &FitSettings) -> Result<FitResult> {
    data.check()?;
    let nb = data.blocks();
    settings.check(nb)?;
    let (m, np) = (data.samples(), 3 * nb - 1);
    let mut warnings = Vec::new();

    let (sigma, estimated) = match settings.noise {
        Some(s) => (s, false),
        None => (slip::estimate_noise(data), true),
    };
    let bound = (settings.noise_bound * sigma).max(ROUNDING * data.length_scale());
    let delta = 2.0 * bound;
    let slips = slip::detect(data, 2.0 * bound);

    let (fixed, scale) = normalisation(settings, nb);

    let (p_hat, lad_objective) = lp::lad(data, &slips.sliding, &fixed)?;
    let res = lp::residuals(data, &slips.sliding, &p_hat);
    let iv = intervals(
        data,
        (&slips.sliding, &res),
        &fixed,
        delta,
        settings.max_outlier_fraction,
    )?;
    let (keep, unbounded, ranges, bad) = (iv.keep, iv.unbounded, iv.ranges, iv.bad);
    let mut outlier_rows = Vec::new();
    if iv.outliers_left_out {
        outlier_rows = bad.iter().map(|i| i + 1).collect();
        warnings.push(format!(
            "{} sample(s) left out of the intervals as outliers (no parameters are \
             consistent with them within the noise bound {}): rows {}",
            bad.len(),
            short(bound),
            rows_text(&outlier_rows)
        ));
    }
    if ranges.is_none() {
        warnings.push(contradiction(
            data,
            &slips.sliding,
            &p_hat,
            delta,
            bad.len(),
        ));
    }

    let names: Vec<Param> = (0..np).map(|j| param_of(nb, j)).collect();
    let estimates: Vec<Option<f64>> = (0..np)
        .map(|j| (!unbounded[j]).then_some(p_hat[j]))
        .collect();
    let model = model_values(
        &estimates,
        ranges.as_deref(),
        &p_hat,
        &names,
        settings.unbounded_factor,
        &mut warnings,
    );
    let model_params = PerParam::from_flat(&model, nb);
    let fitted = fitted_crawler(&model_params, &model, &mut warnings);
    let prediction = match (&fitted, settings.predict) {
        (Some(c), true) => predict(data, c)
            .map_err(|e| {
                warnings.push(format!("the fitted crawler could not be re-simulated: {e}"))
            })
            .ok(),
        _ => None,
    };
    let (max_per_block, rms_sliding) = residual_summary(&res, &keep, &slips.sliding);
    Ok(FitResult {
        crawler: PerParam::from_flat(&estimates, nb),
        intervals: ranges.map(|r| PerParam::from_flat(&r, nb)),
        model: fitted.as_ref().map(|_| model_params),
        fitted,
        scale,
        noise: NoiseUsed {
            sigma,
            estimated,
            bound,
            slip_threshold: 2.0 * bound,
        },
        slip_episodes: slips.episodes,
        outlier_rows,
        residuals: Residuals {
            lad_objective,
            max_per_block,
            rms_sliding,
        },
        prediction,
        warnings,
        samples: m,
        blocks: nb,
        sliding: slips.sliding,
    })
}

/// Each parameter's exact interval `[lower, upper]` (`None`: unbounded), none when no
/// parameter vector is consistent with the samples kept.
type Ranges = Option<Vec<[Option<f64>; 2]>>;

/// The parameters' exact intervals at the noise bound (`delta` on every kept sample's
/// residual), which parameters the data leave unbounded above, and the samples kept.
struct Intervals {
    keep: Vec<bool>,
    unbounded: Vec<bool>,
    ranges: Ranges,
    /// The samples whose LAD residual exceeds the bound.
    bad: Vec<usize>,
    /// Whether the `bad` samples were left out as outliers.
    outliers_left_out: bool,
}

/// [`Intervals`] over every sample first; only when no parameter vector is consistent with all
/// of them are the `bad` samples (LAD residual `res` above the bound `delta`) left out, if they
/// are at most `max_fraction` of them, and the intervals computed again (still none: every
/// sample is kept).
fn intervals(
    data: &FitData,
    (sliding, res): (&[Vec<i8>], &[Vec<f64>]),
    fixed: &[(usize, f64)],
    delta: f64,
    max_fraction: f64,
) -> Result<Intervals> {
    let (m, np) = (data.samples(), 3 * data.blocks() - 1);
    let limit = delta * (1.0 + 1e-9);
    let bad: Vec<usize> = (0..m)
        .filter(|&i| res[i].iter().fold(0.0_f64, |a, &v| a.max(v)) > limit)
        .collect();
    let solve = |keep: &[bool]| -> Result<(Vec<bool>, Ranges)> {
        let rows = lp::consistency_rows(data, sliding, keep, delta);
        let unbounded = lp::unbounded_above(np, &rows, fixed)?;
        let ranges = lp::ranges(np, &rows, fixed, &unbounded)?;
        Ok((unbounded, ranges))
    };
    let keep = vec![true; m];
    let (unbounded, ranges) = solve(&keep)?;
    if ranges.is_some() || bad.is_empty() || bad.len() as f64 > max_fraction * m as f64 {
        return Ok(Intervals {
            keep,
            unbounded,
            ranges,
            bad,
            outliers_left_out: false,
        });
    }
    let mut without = keep.clone();
    for &i in &bad {
        without[i] = false;
    }
    let (unbounded, ranges) = solve(&without)?;
    let outliers_left_out = ranges.is_some();
    Ok(Intervals {
        keep: if outliers_left_out { without } else { keep },
        unbounded,
        ranges,
        bad,
        outliers_left_out,
    })
}

/// The crawler of the model file's values, `None` with a warning where they make none (a
/// parameter the data leave without a value, or values that are no crawler).
fn fitted_crawler(
    params: &PerParam<f64>,
    model: &[f64],
    warnings: &mut Vec<String>,
) -> Option<Crawler> {
    match Crawler::new(
        params.stiffness.clone(),
        params.mu_forward.clone(),
        params.mu_backward.clone(),
    ) {
        Ok(c) => Some(c),
        Err(e) if model.iter().all(|v| *v > 0.0) => {
            warnings.push(format!("no fitted crawler: {e}"));
            None
        }
        Err(_) => {
            warnings.push("no fitted crawler: the data leave a parameter without a value".into());
            None
        }
    }
}

/// How the fit's scale is set: the fixed parameters (flat index, value) and their record; with
/// none given, the first link's stiffness is fixed to 1 and the rest are ratios to it (friction
/// and stiffness are identified from positions only up to one common factor).
fn normalisation(settings: &FitSettings, nb: usize) -> (Vec<(usize, f64)>, Scale) {
    let flat = |p: Param| match p.kind {
        ParamKind::Stiffness => lp::k_index(p.index),
        ParamKind::MuForward => lp::forward_index(nb, p.index),
        ParamKind::MuBackward => lp::backward_index(nb, p.index),
    };
    let reference = Param {
        kind: ParamKind::Stiffness,
        index: 0,
    };
    if settings.fixes.is_empty() {
        (
            vec![(flat(reference), 1.0)],
            Scale {
                fixed: Vec::new(),
                ratios_to: Some(reference.to_string()),
            },
        )
    } else {
        (
            settings.fixes.iter().map(|&(p, v)| (flat(p), v)).collect(),
            Scale {
                fixed: settings
                    .fixes
                    .iter()
                    .map(|(p, v)| Fixed {
                        parameter: p.to_string(),
                        value: *v,
                    })
                    .collect(),
                ratios_to: None,
            },
        )
    }
}

/// The values a model file takes: the estimates where the data bound a parameter, else
/// `unbounded_factor` times its lower end (`p_hat` where there is none), each such value with a
/// warning that says why (e.g. a block never seen sliding forward).
fn model_values(
    estimates: &[Option<f64>],
    ranges: Option<&[[Option<f64>; 2]]>,
    p_hat: &[f64],
    names: &[Param],
    unbounded_factor: f64,
    warnings: &mut Vec<String>,
) -> Vec<f64> {
    let np = estimates.len();
    let mut model = Vec::with_capacity(np);
    for j in 0..np {
        let v = match estimates[j] {
            Some(v) => v,
            None => {
                let lo = ranges.and_then(|r| r[j][0]).unwrap_or(p_hat[j]);
                let v = unbounded_factor * lo;
                let why = match names[j].kind {
                    ParamKind::MuForward => ": the block is never seen sliding forward",
                    ParamKind::MuBackward => ": the block is never seen sliding backward",
                    ParamKind::Stiffness => "",
                };
                warnings.push(if v > 0.0 {
                    format!(
                        "{}: the data bound it only from below (>= {}){why}; no estimate, the \
                         model file takes {}",
                        names[j],
                        short(lo),
                        short(v)
                    )
                } else {
                    format!(
                        "{}: the data do not bound it{why}; no estimate and no value for a \
                         model file",
                        names[j]
                    )
                });
                v
            }
        };
        model.push(v);
    }
    model
}

/// The residuals' summary over the samples kept: the largest per block, and the RMS over the
/// sliding blocks' samples (0 with none).
fn residual_summary(res: &[Vec<f64>], keep: &[bool], sliding: &[Vec<i8>]) -> (Vec<f64>, f64) {
    let (m, nb) = (res.len(), res.first().map_or(0, Vec::len));
    let max_per_block = (0..nb)
        .map(|b| {
            (0..m)
                .filter(|&i| keep[i])
                .fold(0.0_f64, |a, i| a.max(res[i][b]))
        })
        .collect();
    let sliding_res: Vec<f64> = (0..m)
        .flat_map(|i| (0..nb).map(move |b| (i, b)))
        .filter(|&(i, b)| keep[i] && sliding[i][b] != 0)
        .map(|(i, b)| res[i][b])
        .collect();
    let rms_sliding = if sliding_res.is_empty() {
        0.0
    } else {
        (sliding_res.iter().map(|r| r * r).sum::<f64>() / sliding_res.len() as f64).sqrt()
    };
    (max_per_block, rms_sliding)
}

/// The parameter at flat index `j`.
fn param_of(nb: usize, j: usize) -> Param {
    let (kind, index) = if j < nb - 1 {
        (ParamKind::Stiffness, j)
    } else if j < 2 * nb - 1 {
        (ParamKind::MuForward, j - (nb - 1))
    } else {
        (ParamKind::MuBackward, j - (2 * nb - 1))
    };
    Param { kind, index }
}

/// A number for a message: 6 significant digits, without trailing zeros.
fn short(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) {
        return format!("{v:.5e}");
    }
    let digits = (5 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Rows for a message: up to 10, then how many more.
fn rows_text(rows: &[usize]) -> String {
    let shown: Vec<String> = rows.iter().take(10).map(ToString::to_string).collect();
    match rows.len() {
        n if n > 10 => format!("{} and {} more", shown.join(", "), n - 10),
        _ => shown.join(", "),
    }
}

/// The warning of data that contradict the model: the blocks whose sliding forces (with the
/// estimated stiffnesses) spread beyond what the noise bound allows, or a general sentence.
fn contradiction(data: &FitData, sliding: &[Vec<i8>], p: &[f64], delta: f64, bad: usize) -> String {
    let nb = data.blocks();
    let mut parts = Vec::new();
    for b in 0..nb {
        let w = if b > 0 { p[b - 1] } else { 0.0 } + if b + 1 < nb { p[b] } else { 0.0 };
        for (dir, word) in [(1i8, "forward"), (-1i8, "backward")] {
            let mut lo = (f64::INFINITY, 0);
            let mut hi = (f64::NEG_INFINITY, 0);
            for i in (0..data.samples()).filter(|&i| sliding[i][b] == dir) {
                let mut f = 0.0;
                if b > 0 {
                    f += p[b - 1] * data.compression(i, b - 1);
                }
                if b + 1 < nb {
                    f -= p[b] * data.compression(i, b);
                }
                if f < lo.0 {
                    lo = (f, i + 1);
                }
                if f > hi.0 {
                    hi = (f, i + 1);
                }
            }
            if hi.0 - lo.0 > 2.0 * delta * w {
                parts.push(format!(
                    "block {} slides {word} at forces from {} (row {}) to {} (row {}), \
                     which differ by more than the noise allows ({})",
                    b + 1,
                    short(lo.0),
                    lo.1,
                    short(hi.0),
                    hi.1,
                    short(2.0 * delta * w)
                ));
            }
        }
    }
    let head = format!(
        "the data contradict the model at the noise bound ({bad} sample(s) with a least-absolute-deviations residual beyond it): no \
         parameters are consistent with every sample, so there are no intervals"
    );
    if parts.is_empty() {
        format!("{head} (or the fixed values contradict the data)")
    } else {
        format!("{head}; {}", parts.join("; "))
    }
}

/// The fitted crawler re-simulated under the measured actuation from the measured first
/// state, against the measured positions.
fn predict(data: &FitData, crawler: &Crawler) -> Result<Prediction> {
    let k = crawler.stiffness();
    let x0: Vec<f64> = (0..crawler.links())
        .map(|l| k[l] * data.compression(0, l))
        .collect();
    let positions =
        crate::integrate::replay(crawler, &data.t, &data.lengths, &x0, &data.positions[0])?;
    let (mut sum, mut max, mut count) = (0.0, 0.0_f64, 0usize);
    for (p, q) in positions.iter().zip(&data.positions) {
        for (a, b) in p.iter().zip(q) {
            let e = (a - b).abs();
            sum += e * e;
            max = max.max(e);
            count += 1;
        }
    }
    let bary: Vec<f64> = data
        .positions
        .iter()
        .map(|r| r.iter().sum::<f64>() / r.len() as f64)
        .collect();
    let range = bary.iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v))
        - bary.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    Ok(Prediction {
        rms: (sum / count as f64).sqrt(),
        max,
        relative: (range > 0.0).then(|| max / range),
        positions,
    })
}
