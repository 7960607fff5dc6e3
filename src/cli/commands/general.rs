//! `analyze` and `simulate` on a problem file of the general kind (`[sweeping_process]`, the
//! paper's §2 problem (P)): [`crawlopt::api::analyze_general`] and
//! [`crawlopt::api::simulate_general`] rendered.

use crate::commands::analyze::AnalyzeArgs;
use crate::commands::optimize::{OptimizeArgs, OptimizeMethod};
use crate::commands::simulate::{MethodArg, SimulateArgs};
use crate::output::{json_line, out, write_json};
use crawlopt::api::{self, rename_fields};
use crawlopt::integrate::{GeneralMethod, GeneralSimOptions};
use crawlopt::io::GeneralFile;
use crawlopt::present::text;
use crawlopt::Error;
use std::process::ExitCode;

/// `crawlopt analyze` of a general problem: the analysis printed, then exit 2 with the first
/// failed check's message if any.
pub fn analyze(file: &GeneralFile, a: &AnalyzeArgs) -> Result<ExitCode, Error> {
    if a.plot.is_some() {
        return Err(Error::invalid(
            "--plot",
            "a directory",
            "has no figures for a general problem file yet",
        ));
    }
    let found = api::analyze_general(file)?;
    if a.json {
        write_json(&found);
    } else {
        out(&text::general_analysis(&found));
    }
    match found.failure {
        Some(e) => {
            eprintln!("error: {e}");
            Ok(ExitCode::from(2))
        }
        None => Ok(ExitCode::SUCCESS),
    }
}

/// `crawlopt simulate` of a general problem: exact where it applies (`A = 0`, piecewise-constant
/// input) unless `--method catching-up`, else catching-up.
pub fn simulate(file: &GeneralFile, a: &SimulateArgs) -> Result<ExitCode, Error> {
    let unsupported = |flag: &str| {
        Err(Error::invalid(
            flag,
            "a value",
            "is not supported for a general problem file yet",
        ))
    };
    if let Some(path) = &a.output {
        crawlopt::io::AtomicFile::check(path)?;
    }
    if a.plot.is_some() {
        return unsupported("--plot");
    }
    if a.periods != 1 {
        return unsupported("--periods");
    }
    if a.no_newton {
        return unsupported("--no-newton");
    }
    let opts = GeneralSimOptions {
        method: match a.method {
            MethodArg::Exact => GeneralMethod::Auto,
            MethodArg::CatchingUp => GeneralMethod::CatchingUp,
        },
        steps_per_period: a.steps_per_period,
        max_periods: a.max_periods,
        tol: a.tol,
        ..GeneralSimOptions::DEFAULT
    };
    let names = [
        ("steps_per_period", "--steps-per-period"),
        ("max_periods", "--max-periods"),
        ("tol", "--tol"),
    ];
    let r = api::simulate_general(file, &opts)
        .map_err(|e| rename_fields(e, &names.map(|(f, flag)| (f, flag.to_string()))))?;
    // The recorded period, only once the periodic regime is reached.
    let written = match &a.output {
        Some(path) if r.simulation.converged => {
            crawlopt::io::write_general_csv(path, &r.simulation)?;
            true
        }
        _ => false,
    };
    if a.json {
        json_line(&r);
    } else {
        out(&text::general_simulation(&r));
        if let (true, Some(path)) = (written, &a.output) {
            out(&format!("trajectory written to {}\n", path.display()));
        }
    }
    if r.simulation.converged {
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "error: the periodic regime was not reached within {} periods; J is not reported \
             (raise --max-periods or --tol)",
            r.simulation.periods
        );
        Ok(ExitCode::from(3))
    }
}

/// `crawlopt optimize` of a general problem: P_m globally (`--method discrete`, or `auto`),
/// with `--certify` its necessary conditions, or locally (`--method local`).
pub fn optimize(file: &GeneralFile, a: &OptimizeArgs) -> Result<ExitCode, Error> {
    let local = a.method == OptimizeMethod::Local;
    if a.method == OptimizeMethod::Phase {
        return optimize_phase(file, a);
    }
    if !(local || matches!(a.method, OptimizeMethod::Auto | OptimizeMethod::Discrete)) {
        return Err(Error::invalid(
            "--method",
            "sequence",
            "only discrete (P_m, globally), local (P_m, locally) and phase (exact gaits where \
             A = 0) apply to a general problem file",
        ));
    }
    let refused = [
        ("--phases", a.phases.is_some()),
        ("--patience", a.patience.is_some()),
        ("--max-phases", a.max_phases.is_some()),
        ("--convergence", a.convergence),
        ("--start", a.start.is_some()),
        ("--shifts", a.shifts.is_some() && !local),
        ("--certify", a.certify && local),
        ("--no-polish", a.no_polish && local),
        ("--plot", a.plot.is_some()),
        ("--report", a.report.is_some()),
    ];
    if let Some((flag, _)) = refused.iter().find(|(_, given)| *given) {
        return Err(Error::invalid(
            *flag,
            "given",
            "does not apply to a general problem file (P_m only, so far; --certify with the global \
             method, --shifts with --method local)",
        ));
    }
    let names = [
        ("m", "--m"),
        ("time_limit", "--time-limit"),
        ("shifts", "--shifts"),
    ];
    let flags = |e| rename_fields(e, &names.map(|(f, flag)| (f, flag.to_string())));
    if local {
        let defaults = api::GeneralLocalSettings::default();
        let settings = api::GeneralLocalSettings {
            m: a.m.unwrap_or(defaults.m),
            shifts: a.shifts.unwrap_or(defaults.shifts),
            time_limit: a.time_limit,
        };
        let r =
            api::optimize_general_local(file, &settings, api::Hooks::default()).map_err(flags)?;
        if a.json {
            json_line(&r);
        } else {
            out(&text::general_local(&r));
        }
        return Ok(ExitCode::SUCCESS);
    }
    let settings = api::GeneralPmSettings {
        m: a.m.unwrap_or(api::GeneralPmSettings::default().m),
        time_limit: a.time_limit,
        certify: a.certify,
        polish: !a.no_polish,
    };
    let r = api::optimize_general(file, &settings).map_err(flags)?;
    if a.json {
        json_line(&r);
    } else {
        out(&text::general_optimum(&r));
        if let Some(c) = &r.necessary_conditions {
            out(&text::general_certificate(c));
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// `crawlopt optimize GENERAL.toml --method phase`: the exact gait of at most `--max-phases`
/// phases, globally ([`crawlopt::api::optimize_general_phase`]).
fn optimize_phase(file: &GeneralFile, a: &OptimizeArgs) -> Result<ExitCode, Error> {
    let refused = [
        ("--phases", a.phases.is_some()),
        ("--patience", a.patience.is_some()),
        ("--m", a.m.is_some()),
        ("--convergence", a.convergence),
        ("--start", a.start.is_some()),
        ("--shifts", a.shifts.is_some()),
        ("--certify", a.certify),
        ("--no-polish", a.no_polish),
        ("--plot", a.plot.is_some()),
        ("--report", a.report.is_some()),
    ];
    if let Some((flag, _)) = refused.iter().find(|(_, given)| *given) {
        return Err(Error::invalid(
            *flag,
            "given",
            "does not apply to --method phase on a general problem file (--max-phases, \
             --time-limit, --json)",
        ));
    }
    let settings = api::GeneralPhaseSettings {
        max_phases: a.max_phases.unwrap_or(api::DEFAULT_GENERAL_PHASES),
        time_limit: a.time_limit,
    };
    let names = [
        ("max_phases", "--max-phases"),
        ("time_limit", "--time-limit"),
    ];
    let r = api::optimize_general_phase(file, &settings)
        .map_err(|e| rename_fields(e, &names.map(|(f, flag)| (f, flag.to_string()))))?;
    if a.json {
        json_line(&r);
    } else {
        out(&text::general_phase(&r));
    }
    Ok(ExitCode::SUCCESS)
}
