//! The human form of a fit ([`crate::fit::FitResult`]).

use super::{num, wln};
use crate::fit::FitResult;

/// What `crawlopt fit` prints: the scale, the noise, each parameter with its estimate and
/// interval, the slips, the residuals, the prediction error, the warnings; `written` names the
/// model file written, if any.
pub fn fit(r: &FitResult, written: Option<&std::path::Path>) -> String {
    let mut o = String::new();
    wln!(o, "fit of {} blocks to {} samples", r.blocks, r.samples);
    scale_and_noise(&mut o, r);
    wln!(
        o,
        "parameter        estimate       interval consistent with the data"
    );
    let iv = r.intervals.as_ref();
    o += &parameter_rows("stiffness", &r.crawler.stiffness, iv.map(|p| &p.stiffness));
    o += &parameter_rows(
        "mu_forward",
        &r.crawler.mu_forward,
        iv.map(|p| &p.mu_forward),
    );
    o += &parameter_rows(
        "mu_backward",
        &r.crawler.mu_backward,
        iv.map(|p| &p.mu_backward),
    );
    for (b, eps) in r.slip_episodes.iter().enumerate() {
        let (f, bk) = eps.iter().fold((0, 0), |(f, bk), e| {
            if e.direction == "forward" {
                (f + 1, bk)
            } else {
                (f, bk + 1)
            }
        });
        let used: usize = eps.iter().map(|e| e.samples_used).sum();
        wln!(
            o,
            "block {}: {f} forward and {bk} backward slip episode(s), {used} sliding sample(s)",
            b + 1
        );
    }
    errors(&mut o, r);
    if let Some(path) = written {
        wln!(o, "fitted model written to {}", path.display());
    }
    for w in &r.warnings {
        wln!(o, "warning: {w}");
    }
    o
}

/// The lines of the force scale (the parameters fixed, or the one the others are ratios to)
/// and of the noise.
fn scale_and_noise(o: &mut String, r: &FitResult) {
    match &r.scale.ratios_to {
        Some(p) => wln!(
            o,
            "force scale: none given; every force parameter is a ratio to {p} (= 1)"
        ),
        None => {
            let f: Vec<String> = r
                .scale
                .fixed
                .iter()
                .map(|f| format!("{} = {}", f.parameter, num(f.value, 0.0)))
                .collect();
            wln!(o, "force scale: {}", f.join(", "));
        }
    }
    wln!(
        o,
        "noise: sigma = {} ({}), positions assumed within {}, slip threshold {} per frame",
        num(r.noise.sigma, 0.0),
        if r.noise.estimated {
            "estimated"
        } else {
            "given"
        },
        num(r.noise.bound, 0.0),
        num(r.noise.slip_threshold, 0.0)
    );
}

/// The rows of one kind of parameter `name`: each estimate `e` and its interval in `i` (none
/// when the data contradict the model).
fn parameter_rows(name: &str, e: &[Option<f64>], i: Option<&Vec<[Option<f64>; 2]>>) -> String {
    let mut s = String::new();
    for (j, v) in e.iter().enumerate() {
        let est = v.map_or("-".to_string(), |v| num(v, 0.0));
        let range = match i {
            Some(i) => format!(
                "[{}, {}]",
                i[j][0].map_or("-".into(), |v| num(v, 0.0)),
                i[j][1].map_or("unbounded".into(), |v| num(v, 0.0))
            ),
            None => "none (contradiction)".into(),
        };
        wln!(
            s,
            "  {:<15}{:<15}{range}",
            format!("{name}[{}]", j + 1),
            est
        );
    }
    s
}

/// The lines of the residuals and of the prediction error of the fitted model.
fn errors(o: &mut String, r: &FitResult) {
    let worst = r
        .residuals
        .max_per_block
        .iter()
        .fold(0.0_f64, |a, &v| a.max(v));
    wln!(
        o,
        "residuals: largest {} (length), rms over sliding samples {}",
        num(worst, 0.0),
        num(r.residuals.rms_sliding, 0.0)
    );
    if let Some(p) = &r.prediction {
        wln!(
            o,
            "prediction (fitted model re-simulated under the measured actuation): rms {}, max {}{}",
            num(p.rms, 0.0),
            num(p.max, 0.0),
            p.relative.map_or(String::new(), |v| format!(
                " ({} of the motion)",
                num(v, 0.0)
            ))
        );
    }
}
