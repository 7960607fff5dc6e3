//! The `[settings]` of a sweep file: the job's options, named as the command's flags, read
//! into the library's settings ([`OptimizeSettings`], [`SimOptions`]); their errors named
//! `settings.KEY`.

use crate::api::{rename_fields, OptimizeSettings, Start};
use crate::error::{Error, Result};
use crate::integrate::{GeneralSimOptions, Method, SimOptions};
use serde::Deserialize;
use std::path::Path;

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct SimulateKeys {
    method: Option<String>,
    #[serde(alias = "steps-per-period")]
    steps_per_period: Option<usize>,
    #[serde(alias = "max-periods")]
    max_periods: Option<usize>,
    tol: Option<f64>,
    #[serde(alias = "accelerate-after")]
    accelerate_after: Option<usize>,
    #[serde(default, alias = "no-accelerate")]
    no_accelerate: bool,
}

/// A library error of the settings renamed `settings.KEY`.
fn in_settings(e: Error, keys: &[&str]) -> Error {
    let names: Vec<(&str, String)> = keys.iter().map(|k| (*k, format!("settings.{k}"))).collect();
    rename_fields(e, &names)
}

/// The settings of `job = "optimize"`, named as `crawlopt optimize`'s flags (`time_limit` or
/// `time-limit`): the library reads them ([`OptimizeSettings::from_keys`]), but for `start`, a
/// result file's path relative to the sweep file. The upper bound over all gaits (`bound`) is
/// refused: a sweep's table has no column for it, and its grid and LP are a study of their own.
pub(super) fn optimize_settings(mut t: toml::Table, dir: &Path) -> Result<OptimizeSettings> {
    if let Some(bound) = t.get("bound") {
        return Err(Error::invalid(
            "settings.bound",
            bound,
            "is not a sweep setting: a sweep's table has no column for the upper bound over all \
             gaits (run `crawlopt optimize --bound` on one point's model)",
        ));
    }
    let start = match t.remove("start") {
        None => None,
        Some(toml::Value::String(p)) => Some(Start::File(dir.join(p))),
        Some(other) => {
            return Err(Error::invalid(
                "settings.start",
                other,
                "must be the path of a result file",
            ))
        }
    };
    let settings = OptimizeSettings::from_keys(&t).map_err(setting_error)?;
    Ok(OptimizeSettings { start, ..settings })
}

/// The keys of `job = "simulate"` and its method.
fn simulate_keys(t: toml::Table) -> Result<(SimulateKeys, Method)> {
    let k: SimulateKeys = toml::Value::Table(t)
        .try_into()
        .map_err(|e| toml_err("settings", e))?;
    let method = match k.method.as_deref() {
        None => Method::Exact,
        Some(name) => Method::from_name(name).map_err(|e| in_settings(e, &["method"]))?,
    };
    Ok((k, method))
}

/// The options of `job = "simulate"` on a general problem, named as `crawlopt simulate`'s
/// flags on a general problem file: `exact` where it applies (`A = 0`, a piecewise-constant
/// input; else catching-up) or `catching-up`, steps per period, periods, tolerance, with
/// [`GeneralSimOptions::DEFAULT`] for those not given. The crawler's acceleration of the
/// periodic regime does not apply (refused naming it).
pub(super) fn general_simulate_options(t: toml::Table) -> Result<GeneralSimOptions> {
    let (k, method) = simulate_keys(t)?;
    let given = [
        ("accelerate_after", k.accelerate_after.is_some()),
        ("no_accelerate", k.no_accelerate),
    ];
    if let Some((key, _)) = given.iter().find(|(_, g)| *g) {
        return Err(Error::invalid(
            format!("settings.{key}"),
            "a value",
            "does not apply to a general problem (the crawler's acceleration of the periodic \
             regime)",
        ));
    }
    let d = GeneralSimOptions::DEFAULT;
    Ok(GeneralSimOptions {
        method: method.into(),
        steps_per_period: k.steps_per_period.unwrap_or(d.steps_per_period),
        max_periods: k.max_periods.unwrap_or(d.max_periods),
        tol: k.tol.unwrap_or(d.tol),
        ..d
    })
}

/// The options of `job = "simulate"`, named as `crawlopt simulate`'s flags.
pub(super) fn simulate_options(t: toml::Table) -> Result<SimOptions> {
    let (k, method) = simulate_keys(t)?;
    let d = SimOptions::DEFAULT;
    Ok(SimOptions {
        method,
        steps_per_period: k.steps_per_period.unwrap_or(d.steps_per_period),
        record_periods: 0,
        max_periods: k.max_periods.unwrap_or(d.max_periods),
        tol: k.tol.unwrap_or(d.tol),
        accelerate_after: if k.no_accelerate {
            None
        } else {
            k.accelerate_after.or(d.accelerate_after)
        },
        newton: SimOptions::DEFAULT.newton,
        initial_state: None,
        increment_budget: d.increment_budget,
    })
}

/// The settings keys of a job, for renaming the library's errors.
pub(crate) const SETTING_KEYS: &[&str] = &[
    "method",
    "phases",
    "patience",
    "max_phases",
    "m",
    "convergence",
    "start",
    "shifts",
    "time_limit",
    "certify",
    "formulation",
    "polish",
    "steps_per_period",
    "max_periods",
    "tol",
    "accelerate_after",
];

/// Renames a job's error on a setting to `settings.KEY`.
pub(crate) fn setting_error(e: Error) -> Error {
    in_settings(e, SETTING_KEYS)
}

/// A TOML error as one line naming `what`.
pub(super) fn toml_err(what: &str, e: toml::de::Error) -> Error {
    let msg = crate::io::escape_controls(&e.message().trim().replace('\n', "; "));
    Error::invalid(what, "the table given", msg)
}
