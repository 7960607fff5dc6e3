//! Presentation: figures (SVG and PNG) and the self-contained HTML report.
//!
//! This layer turns what the others compute into pictures a researcher looks at: the actuation
//! and its rate, the space-time diagram of the blocks, the state in the polytope C, the heat map
//! of v_m, the convergence of J_m and the adjoint of a certificate ([`figures`]), and one HTML
//! file with the numbers, the figures and an animation of the crawler ([`report`]); for the
//! general problem (P) the set C with the state's path, the controls, reactions and the
//! objective's integrand ([`general`]) and their report ([`general_report`]); a result of either
//! kind rendered once, its text, figures and report ([`result`]). It depends on `model`,
//! `integrate`, `optimal`, `certify`, `fit` and `io`; only the API, the studies and the front ends
//! above it call it.
//!
//! Outputs are all-or-nothing: a set of figures is written under temporary names and renamed into
//! place only when every file has been written ([`write_figures`]).

pub mod figures;
pub mod general;
pub mod general_report;
pub mod report;
pub mod result;
pub mod text;

pub use general::{
    general_adjoint_figure, general_analysis_figures, general_answer_figures, general_path_figures,
    general_series, general_simulation_figures, general_state_space, GeneralPath,
};
pub use general_report::{build_general_report, GeneralReportInput};
pub use result::{
    build_result_report, conditions_text, result_figures, result_report, result_summary,
    result_text, PlotInput,
};

use crate::certify::MultiplierData;
use crate::error::{Error, Result};
use crate::integrate::{simulate, Actuation, Method, SimOptions, Simulation, Trajectory};
use crate::io::AtomicFile;
use crate::model::Crawler;
use crate::optimal::GaitResult;
use figures::{ActuationSeries, Figure};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Periods shown by the space-time diagram and the animation: enough to see the advance.
pub const SHOWN_PERIODS: usize = 4;

/// The piecewise-linear actuation of a gait result (its knots over one period).
pub fn gait_actuation(result: &GaitResult) -> Result<Actuation> {
    let g = &result.gait;
    let p = g.durations.len();
    Actuation::of_gait(
        result.problem.period,
        g.times[..p].to_vec(),
        g.lengths[..p].to_vec(),
    )
}

/// Replays a gait result from its initial state with the simulator that verified it (exact for
/// phase gaits, catching-up on the grid for P_m answers, global or local), recording `periods`
/// periods, and checks that it moves the crawler by the displacement the result states (a result
/// file is input: an edited one is refused rather than pictured).
pub fn replay_gait(result: &GaitResult, periods: usize) -> Result<(Crawler, Simulation)> {
    let crawler = result.crawler.crawler()?;
    crawler.require_unique()?;
    let act = gait_actuation(result)?;
    let sim = simulate(
        &crawler,
        &act,
        &SimOptions {
            method: result.verified_with(),
            steps_per_period: result.gait.durations.len(),
            record_periods: periods,
            initial_state: Some(result.gait.initial_state.clone()),
            ..SimOptions::default()
        },
    )?;
    let d = sim.displacement_per_period.ok_or_else(|| {
        Error::Numerical("the gait of the result did not reach a periodic regime".into())
    })?;
    let want = result.displacement_per_period;
    if (d - want).abs() > 1e-6 * (1.0 + want.abs()) {
        return Err(Error::invalid(
            "solution.displacement_per_period",
            want,
            format!("the result's gait moves the crawler {d} per period when replayed"),
        ));
    }
    Ok((crawler, sim))
}

/// Records `periods` periods of `act` on its periodic orbit (a second, cheap run from the orbit
/// state of `sim`, so that a figure can show more periods than the user recorded).
pub fn record_orbit(
    crawler: &Crawler,
    act: &Actuation,
    sim: &Simulation,
    periods: usize,
) -> Result<Trajectory> {
    let again = simulate(
        crawler,
        act,
        &SimOptions {
            method: sim.method,
            steps_per_period: sim.steps_per_period,
            record_periods: periods,
            initial_state: Some(sim.orbit_state.clone()),
            accelerate_after: None,
            ..SimOptions::default()
        },
    )?;
    again
        .trajectory
        .ok_or_else(|| Error::Numerical("no trajectory was recorded".into()))
}

/// Periods shown of the approach to the periodic orbit from rest, at most.
pub const TRANSIENT_PERIODS: usize = 12;

/// The states from rest (`x = 0`) towards the periodic orbit of `act`: whole periods, each
/// integrated from where the last ended, until the state repeats or after
/// [`TRANSIENT_PERIODS`] periods.
pub fn transient_states(
    crawler: &Crawler,
    act: &Actuation,
    method: Method,
    steps_per_period: usize,
) -> Result<Vec<Vec<f64>>> {
    let mut x = vec![0.0; crawler.links()];
    let mut states: Vec<Vec<f64>> = Vec::new();
    for _ in 0..TRANSIENT_PERIODS {
        let sim = simulate(
            crawler,
            act,
            &SimOptions {
                method,
                steps_per_period,
                record_periods: 1,
                max_periods: 1,
                accelerate_after: None,
                initial_state: Some(x.clone()),
                ..SimOptions::default()
            },
        )?;
        let tr = sim
            .trajectory
            .ok_or_else(|| Error::Numerical("no trajectory was recorded".into()))?;
        let skip = usize::from(!states.is_empty());
        states.extend(tr.x.into_iter().skip(skip));
        match states.last() {
            Some(last) => x.clone_from(last),
            None => break,
        }
        if sim.converged {
            break;
        }
    }
    Ok(states)
}

/// The actuation of `act` over one period as the figure draws it: its own knots when piecewise
/// linear, else its interpolant on `m` knots.
pub fn actuation_series(
    crawler: &Crawler,
    act: &Actuation,
    m: usize,
    rate_bound: Option<Vec<f64>>,
) -> Result<ActuationSeries> {
    let (mut times, mut lengths) = act.knots(m.max(2));
    times.push(act.period());
    lengths.push(lengths[0].clone());
    ActuationSeries::from_knots(&times, &lengths, crawler.stiffness(), rate_bound)
}

/// The figures of a crawler alone: C, and v_m for two links.
pub fn analysis_figures(crawler: &Crawler) -> Result<Vec<Figure>> {
    let mut v = vec![figures::polytope_figure(crawler, None, None)?];
    if crawler.links() == 2 && crawler.uniqueness().holds() {
        v.push(figures::vm_figure(crawler)?);
    }
    Ok(v)
}

/// The figures of a simulation: actuation, space-time diagram over `periods` periods, and the
/// orbit in C.
pub fn simulation_figures(
    crawler: &Crawler,
    act: &Actuation,
    sim: &Simulation,
    periods: usize,
) -> Result<Vec<Figure>> {
    let traj = record_orbit(crawler, act, sim, periods.max(1))?;
    let series = actuation_series(crawler, act, sim.steps_per_period.min(2000), None)?;
    Ok(vec![
        figures::actuation_figure(&series)?,
        figures::spacetime_figure(&traj, act.period())?,
        figures::polytope_figure(
            crawler,
            Some(&traj),
            Some(&transient_states(
                crawler,
                act,
                sim.method,
                sim.steps_per_period,
            )?),
        )?,
    ])
}

/// The figures of a gait result: actuation with its rate bounds, space-time diagram over
/// [`SHOWN_PERIODS`] periods, the orbit in C, and v_m for two links.
pub fn gait_figures(result: &GaitResult) -> Result<Vec<Figure>> {
    let (crawler, sim) = replay_gait(result, SHOWN_PERIODS)?;
    let traj = sim
        .trajectory
        .as_ref()
        .ok_or_else(|| Error::Numerical("no trajectory was recorded".into()))?;
    gait_figures_from(result, &crawler, traj)
}

/// [`gait_figures`] from an already replayed trajectory.
pub fn gait_figures_from(
    result: &GaitResult,
    crawler: &Crawler,
    traj: &Trajectory,
) -> Result<Vec<Figure>> {
    let g = &result.gait;
    let series = ActuationSeries::from_knots(
        &g.times,
        &g.lengths,
        crawler.stiffness(),
        Some(result.problem.rate_bound.clone()),
    )?;
    let mut v = vec![
        figures::actuation_figure(&series)?,
        figures::spacetime_figure(traj, result.problem.period)?,
        figures::polytope_figure(
            crawler,
            Some(traj),
            Some(&transient_states(
                crawler,
                &gait_actuation(result)?,
                result.verified_with(),
                g.durations.len(),
            )?),
        )?,
    ];
    if crawler.links() == 2 {
        v.push(figures::vm_figure(crawler)?);
    }
    // J_m against m when the result carries a convergence table (`optimize --convergence`).
    if let Some(table) = &result.records.convergence {
        v.push(figures::convergence_figure(table)?);
    }
    Ok(v)
}

/// Figure `adjoint` of a certificate: `p(t)`, `p(t) + omega` and `u(t)` from its multipliers,
/// `p` extended as the certificate says (piecewise linear on P_m grids, piecewise constant with
/// jumps at the knots on phase gaits); `u` is piecewise constant.
pub fn adjoint_figure_of(m: &MultiplierData) -> Result<Figure> {
    let pieces = m.u.len();
    if pieces == 0 || m.times.len() != pieces + 1 || m.p.len() != pieces {
        return Err(Error::invalid(
            "multipliers",
            format!("{pieces} pieces"),
            "need one row per piece and one more time",
        ));
    }
    let linear = m.extension == "piecewise_linear";
    let (mut t, mut p, mut ppo, mut u) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for j in 0..pieces {
        let end = if linear { (j + 1) % pieces } else { j };
        for (time, row) in [(m.times[j], j), (m.times[j + 1], end)] {
            t.push(time);
            p.push(m.p[row].clone());
            ppo.push(m.p_plus_omega[row].clone());
            u.push(m.u[j].clone());
        }
    }
    figures::adjoint_figure(&t, &p, &ppo, &u)
}

fn io_err(path: &Path, reason: impl ToString) -> Error {
    Error::Io {
        path: path.display().to_string(),
        reason: reason.to_string(),
    }
}

/// Refuses, without writing anything, a figure directory [`write_figures`] could not write
/// into: an existing path that is not a directory (a regular file, a device), a symbolic link
/// that resolves to nothing, or a missing directory under something that is not one. So that
/// a command can say so before it computes the figures.
pub fn check_figure_dir(dir: &Path) -> Result<()> {
    if let Ok(link) = std::fs::symlink_metadata(dir) {
        return match std::fs::metadata(dir) {
            Ok(m) if m.is_dir() => Ok(()),
            Ok(_) => Err(io_err(dir, "exists and is not a directory")),
            Err(e) if link.file_type().is_symlink() => Err(io_err(
                dir,
                format!("is a symbolic link that does not resolve to a directory ({e})"),
            )),
            Err(e) => Err(io_err(dir, format!("cannot write: {e}"))),
        };
    }
    // Missing: its nearest existing ancestor must be a directory.
    match dir
        .ancestors()
        .skip(1)
        .find(|a| a.as_os_str().is_empty() || std::fs::symlink_metadata(a).is_ok())
    {
        Some(a) if !a.as_os_str().is_empty() && !a.is_dir() => Err(io_err(
            dir,
            format!(
                "cannot create the directory: {} is not a directory",
                a.display()
            ),
        )),
        _ => Ok(()),
    }
}

/// The directories `create_dir_all(dir)` would create, deepest first.
fn missing_dirs(dir: &Path) -> Vec<PathBuf> {
    dir.ancestors()
        .take_while(|a| !a.as_os_str().is_empty() && std::fs::symlink_metadata(a).is_err())
        .map(Path::to_path_buf)
        .collect()
}

/// Writes every figure as `DIR/name.svg` and `DIR/name.png`, all or nothing: the directory is
/// created if needed, every file is written under a temporary name first, and only when all are
/// complete are they renamed into place. On failure nothing new is left behind (the
/// directories this call created are removed again). `DIR` must be a directory (or missing);
/// each file follows the rules of [`AtomicFile`] (a directory in the way is refused). Returns
/// the paths written.
pub fn write_figures(dir: &Path, figs: &[Figure]) -> Result<Vec<PathBuf>> {
    check_figure_dir(dir)?;
    if dir.is_dir() {
        for f in figs {
            for ext in ["svg", "png"] {
                AtomicFile::check(&dir.join(format!("{}.{ext}", f.name)))?;
            }
        }
    }
    let created = missing_dirs(dir);
    if !created.is_empty() {
        std::fs::create_dir_all(dir)
            .map_err(|e| io_err(dir, format!("cannot create the directory: {e}")))?;
    }
    let staged = (|| -> Result<Vec<(AtomicFile, PathBuf)>> {
        let mut staged = Vec::new();
        for f in figs {
            for (ext, bytes) in [("svg", f.svg.as_bytes()), ("png", f.png.as_slice())] {
                let path = dir.join(format!("{}.{ext}", f.name));
                let mut file = AtomicFile::create(&path)?;
                let w = file.writer();
                w.write_all(bytes)
                    .and_then(|_| w.flush())
                    .map_err(|e| io_err(&path, format!("cannot write: {e}")))?;
                staged.push((file, path));
            }
        }
        Ok(staged)
    })();
    let staged = match staged {
        Ok(s) => s,
        Err(e) => {
            for d in &created {
                let _ = std::fs::remove_dir(d);
            }
            return Err(e);
        }
    };
    let mut written = Vec::with_capacity(staged.len());
    for (file, path) in staged {
        file.commit()?;
        written.push(path);
    }
    Ok(written)
}

/// Value of [`JmTable::format`].
pub const JM_TABLE_FORMAT: &str = "crawlopt-jm-table";

/// A table of discrete optima `J_m` against `m` (for the convergence figure), as JSON:
/// `{"format": "crawlopt-jm-table", "version": 1, "m": [1, 2, 3], "values": [..],
/// "continuous": 3.0}` (`continuous` optional).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JmTable {
    /// Always [`JM_TABLE_FORMAT`].
    pub format: String,
    /// Always 1.
    pub version: u32,
    /// The `m` values.
    pub m: Vec<u32>,
    /// `J_m`, one per `m`.
    pub values: Vec<f64>,
    /// The continuous-time value, if known.
    pub continuous: Option<f64>,
}
