//! The general problem's P_m solved locally as a job ([`optimize_general_local`]): the start
//! policy (a given result, `--start`; else the file's `[input]`; else, where `A = 0`, the phase
//! optimum as a crawler's local method starts from it; else square waves along each control
//! axis; each at several time shifts), the time budget across starts, progress and
//! cancellation; and the default start of (P)'s global P_m made from it
//! ([`pm_default_start`]).

use super::events::{run_with, Emitter, Event, Hooks};
use super::general_phase::check_start_phases;
use super::general_start::given_start;
use super::settings::{DEFAULT_M_LOCAL, DEFAULT_SHIFTS};
use crate::error::{Error, Result};
use crate::io::{GeneralAnswer, GeneralFile, LocalStarts};
use crate::model::general::{GeneralCost, GeneralProblem};
use crate::optimal::general::{
    check_general_local, default_starts, grid_controls, phase_grid, rotated, rotation_shift,
    solve_general_local_best, GeneralLocal, Geometry, MultiStart,
};
use crate::optimal::{pm_start, shifted_origin, Named, StartKernels};

/// A control per step of a grid.
type Grid = Vec<Vec<f64>>;

/// Settings of [`optimize_general_local`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralLocalSettings {
    /// `m`: P_m on `2^m` steps (default [`DEFAULT_M_LOCAL`], as for crawlers).
    pub m: u32,
    /// Each start is tried advanced by `j 2^m / shifts` steps, `j = 0..shifts` (default
    /// [`DEFAULT_SHIFTS`], as for crawlers).
    pub shifts: usize,
    /// Seconds for all starts (`None`: no limit): the best answer so far when it runs out.
    pub time_limit: Option<f64>,
    /// A start (default `None`: the policy of the module docs): a general result of the same
    /// numbers of states and controls and the same period, its control averaged on the grid
    /// (a file is read when the job runs; errors name `start`).
    pub start: Option<super::Start>,
    /// The largest `K` of the phase gait that starts the method where `A = 0` and neither a
    /// start nor the file's `[input]` is given (default `None`: the phase method's default,
    /// [`super::GeneralPhaseSettings::max_phases_for`]), as `max_phases` bounds a crawler's
    /// phase start; refused, naming it, where no phase gait starts.
    pub max_phases: Option<usize>,
    /// Also check the necessary conditions (Theorem 2.2, discrete form Theorems 6.1–6.2) on
    /// the answer's P_m process (default false), as `crawlopt certify` checks a local result
    /// and as a crawler's local method certifies its gait.
    pub certify: bool,
    /// Also prove the crawler's upper bound over all periodic gaits (default `None`), where the
    /// problem is a crawler's gait problem (a chain; refused naming `bound` elsewhere), as the
    /// global methods and a crawler's local method do ([`crate::certify::bound`]).
    pub bound: Option<crate::certify::bound::BoundSettings>,
}

impl Default for GeneralLocalSettings {
    fn default() -> Self {
        GeneralLocalSettings {
            m: DEFAULT_M_LOCAL,
            shifts: DEFAULT_SHIFTS,
            time_limit: None,
            start: None,
            max_phases: None,
            certify: false,
            bound: None,
        }
    }
}

/// Whether the local method's starts (module docs) include the phase gait's: where `A = 0`,
/// without a start given or the file's `[input]`.
fn phase_starts(file: &GeneralFile, p: &GeneralProblem, s: &GeneralLocalSettings) -> bool {
    s.start.is_none() && file.input.is_none() && p.dynamics.is_state_independent()
}

/// Why `max_phases` is refused where no phase gait starts the local method.
const NO_PHASE_START: &str = "applies only where a phase gait is grown as the start (A = 0, \
                              without a start given or the file's [input])";

/// P_m of a problem file, locally ([`crate::optimal::general::local`]), from every start of
/// the policy (module docs), keeping the best verified answer (with its necessary conditions
/// under `certify`). Cancellable through `hooks`;
/// a stage event per start.
pub fn optimize_general_local(
    file: &GeneralFile,
    s: &GeneralLocalSettings,
    hooks: Hooks<'_>,
) -> Result<GeneralAnswer> {
    let (p, g) = super::general::general_problem(file)?;
    // `bound` first, as the global methods check it.
    let chain = super::general::check_additions(&p, s.bound.as_ref(), s.certify)?;
    check_general_local(&p, &g, s.m)?;
    crate::optimal::check_shifts(s.shifts)?;
    crate::optimal::check_time_limit(s.time_limit)?;
    check_start_phases(s.max_phases, phase_starts(file, &p, s), NO_PHASE_START)?;
    run_with(hooks, |em| {
        let mut r = crate::progress::within(s.time_limit, || {
            let (starts, start_from) = starts(file, &p, &g, s, em)?;
            let (answer, start_from) = match best_of(&p, &g, s, &starts, em) {
                // The phase gait's controls refused as a start on this grid (field `start`):
                // the square waves instead, as where there is no phase gait.
                Err(Error::InvalidParameter {
                    field,
                    value,
                    reason,
                }) if start_from == "phase" && field.starts_with("start") => {
                    em.send(Event::Note(format!(
                        "the phase gait is no start on this grid ({field}: {reason}, got \
                         {value}); trying square waves"
                    )));
                    (
                        best_of(&p, &g, s, &square_waves(&p, s)?, em)?,
                        "square_waves",
                    )
                }
                // The file's `[input]` refused as a start (its mean, its range): the input is
                // named, not the grid it was averaged on.
                Err(Error::InvalidParameter {
                    field,
                    value,
                    reason,
                }) if start_from == "input" && field.starts_with("start") => {
                    return Err(Error::InvalidParameter {
                        field: "input.values".into(),
                        value,
                        reason: format!(
                            "as the local method's start (averaged on its grid, {field}): {reason}"
                        ),
                    });
                }
                other => (other?, start_from),
            };
            let (solution, best_start, tried) = answer;
            let starts = LocalStarts {
                start_from,
                starts_tried: tried,
                best_start,
            };
            Ok(GeneralAnswer::local(file, p.period, starts, solution))
        })?;
        // Outside the time limit, as the global methods prove their bounds and certify.
        let bound = chain.as_ref().zip(s.bound.as_ref());
        super::general::add_bound_and_conditions(&p, &mut r, bound, s.certify, em)?;
        Ok(r)
    })
}

/// The default start of (P)'s global P_m on `s.m` steps under a time limit: the one policy
/// of P_m's default start ([`pm_start`], as a crawler's [`crate::optimal::discrete_start`])
/// with (P)'s kernels ([`GeneralStart`]), within half of the time left: the local method's
/// answer on the same grid (settings `s`: `shifts` rotations of its own starts, [`starts`]:
/// the file's `[input]`, else where `A = 0` the phase optimum grown to `max_phases` within
/// half of that half, else square waves), as the grid's controls and their name, a crawler's
/// start's (`"local on P_3, from phase (K = 5) shifted by 0.25"`, `"local on P_3, from
/// input"`). Where the local method does not apply (a quadratic cost), the first
/// half is spent, or it fails, its start itself, unsolved (`"input"`, or `"phase (K = 4)"` as
/// a crawler's start is named); none from square waves. `None`, with a note saying why, where
/// no start was had in time; a cancelled job ends. `max_phases` is refused (naming it) where
/// no phase gait starts.
pub(super) fn pm_default_start(
    file: &GeneralFile,
    p: &GeneralProblem,
    g: &Geometry,
    s: &GeneralLocalSettings,
    em: &Emitter<'_>,
) -> Result<Option<(Grid, String)>> {
    check_start_phases(s.max_phases, phase_starts(file, p, s), NO_PHASE_START)?;
    let mut kernels = GeneralStart { file, p, g, s, em };
    Ok(pm_start(&mut kernels, s.m)?.map(|start| (start.gait.grid, start.name)))
}

/// (P)'s [`StartKernels`]: the local method's start gait ([`gait_start`]) and its active-set
/// method ([`best_of`]; square waves without a gait).
struct GeneralStart<'a, 'e> {
    file: &'a GeneralFile,
    p: &'a GeneralProblem,
    g: &'a Geometry,
    s: &'a GeneralLocalSettings,
    em: &'a Emitter<'e>,
}

impl StartKernels for GeneralStart<'_, '_> {
    type Gait = GaitStart;

    fn gait(&mut self) -> Result<Option<Named<GaitStart>>> {
        let gait = gait_start(self.file, self.p, self.g, self.s, self.em)?;
        Ok(gait.map(|start| Named {
            name: match start.phases {
                Some(k) => format!("phase (K = {k})"),
                None => start.from.to_string(),
            },
            gait: start,
        }))
    }

    fn local_refused(&self) -> Option<String> {
        let e = check_general_local(self.p, self.g, self.s.m).err()?;
        Some(if self.p.cost == GeneralCost::None {
            format!("the local method does not apply: {e}")
        } else {
            "the local method takes no cost f2".to_string()
        })
    }

    fn local(&mut self, gait: Option<&Named<GaitStart>>) -> Result<Option<Named<GaitStart>>> {
        let (p, s, m) = (self.p, self.s, self.s.m);
        let starts = match starts_of(gait.map(|start| &start.gait), p, s) {
            Ok((starts, _)) => starts,
            // No square wave through 0 in U: the local method has no start.
            Err(e) => {
                self.note(&format!("no square-wave start ({e})"));
                return Ok(None);
            }
        };
        let (answer, best, _) = best_of(p, self.g, s, &starts, self.em)?;
        // Named as a crawler's: the start advanced in time by `shift`.
        let origin = match gait {
            Some(start) => {
                let shift = rotation_shift(start.gait.grid.len(), s.shifts, best, p.period);
                shifted_origin(&start.name, shift)
            }
            None => "square waves".to_string(),
        };
        Ok(Some(Named {
            gait: GaitStart {
                grid: answer.path.u,
                from: "local",
                phases: None,
            },
            name: format!("local on P_{m}, from {origin}"),
        }))
    }

    fn what(gait: &GaitStart) -> &'static str {
        match (gait.phases, gait.from) {
            (Some(_), _) => "phase gait",
            (None, "input") => "file's [input]",
            (None, "start") => "given start",
            _ => "local method's answer",
        }
    }

    fn note(&mut self, text: &str) {
        self.em.send(Event::Note(text.to_string()))
    }
}

/// The starts of [`optimize_general_local`] (module docs) on `2^m` steps, each at
/// `s.shifts` rotations, and where they came from: the first gait of the policy
/// ([`gait_start`]), else the square waves.
fn starts(
    file: &GeneralFile,
    p: &GeneralProblem,
    g: &Geometry,
    s: &GeneralLocalSettings,
    em: &Emitter<'_>,
) -> Result<(Vec<Vec<Vec<f64>>>, &'static str)> {
    starts_of(gait_start(file, p, g, s, em)?.as_ref(), p, s)
}

/// The local method's starts from `gait` (its `s.shifts` rotations), else the square waves,
/// and where they came from.
fn starts_of(
    gait: Option<&GaitStart>,
    p: &GeneralProblem,
    s: &GeneralLocalSettings,
) -> Result<(Vec<Grid>, &'static str)> {
    match gait {
        Some(start) => Ok((rotated(&start.grid, s.shifts), start.from)),
        None => Ok((square_waves(p, s)?, "square_waves")),
    }
}

/// A start of the local method's policy that is a gait ([`gait_start`]).
#[derive(Debug, Clone, PartialEq)]
struct GaitStart {
    /// Its controls on the grid.
    grid: Grid,
    /// Where it came from: `"start"`, `"input"` or `"phase"`.
    from: &'static str,
    /// The phase gait's `K`.
    phases: Option<usize>,
}

/// The first start of the policy that is a gait, on `2^m` steps, and where it came from: a
/// given result ([`given_start`]); else the file's `[input]`; else, where `A = 0`, the phase
/// optimum grown to `s.max_phases` (within half of the time left, without a limit to the end
/// of its growth, as a crawler's). `None` where `A != 0`, or where the phase gait cannot be
/// had (a note says why).
fn gait_start(
    file: &GeneralFile,
    p: &GeneralProblem,
    g: &Geometry,
    s: &GeneralLocalSettings,
    em: &Emitter<'_>,
) -> Result<Option<GaitStart>> {
    let gait = |grid, from| {
        Ok(Some(GaitStart {
            grid,
            from,
            phases: None,
        }))
    };
    if let Some(start) = &s.start {
        return gait(given_start(start, p, s.m)?.0, "start");
    }
    if file.input.is_some() {
        return gait(grid_controls(&file.input(p)?, s.m), "input");
    }
    if !p.dynamics.is_state_independent() {
        return Ok(None);
    }
    em.stage("start: the phase gait, K grown");
    let mut progress = |st: &crate::optimal::PhaseStep| {
        em.send(Event::PhaseSolved {
            step: st.clone(),
            start: true,
        })
    };
    let gait = crate::progress::share(0.5, || {
        super::general_phase::phase_start(p, g, s.max_phases, &mut progress)
    });
    let grid = gait.and_then(|gait| {
        let grid = phase_grid(p, &gait.durations, &gait.controls, s.m)?;
        Ok(GaitStart {
            grid,
            from: "phase",
            phases: Some(gait.max_phases),
        })
    });
    match grid {
        Ok(start) => Ok(Some(start)),
        Err(Error::Cancelled) => Err(Error::Cancelled),
        Err(e) => {
            em.send(Event::Note(format!("no phase gait to start from ({e})")));
            Ok(None)
        }
    }
}

/// Solves P_m locally from each of `starts` in turn, within the job's deadline, and keeps the
/// best verified answer ([`solve_general_local_best`], each start by (P)'s rules):
/// `(answer, its start, starts tried)`; a stage event per start.
fn best_of(
    p: &GeneralProblem,
    g: &Geometry,
    s: &GeneralLocalSettings,
    starts: &[Vec<Vec<f64>>],
    em: &Emitter<'_>,
) -> Result<(GeneralLocal, usize, usize)> {
    let n = starts.len();
    let mut on_start = |k: usize| {
        em.stage(format!(
            "local LPCC method on P_{} ({} steps), start {} of {n}",
            s.m,
            1usize << s.m,
            k + 1
        ))
    };
    let plan = MultiStart::for_starts(starts.len());
    let best = solve_general_local_best(p, g, s.m, starts, plan, &mut on_start)?;
    Ok((best.solution, best.best_start, best.tried))
}

/// The square-wave starts ([`default_starts`]); refused, naming `control`, where U holds no
/// segment through 0 along any control axis.
fn square_waves(p: &GeneralProblem, s: &GeneralLocalSettings) -> Result<Vec<Vec<Vec<f64>>>> {
    let starts = default_starts(p, s.m, s.shifts);
    if starts.is_empty() {
        return Err(Error::invalid(
            "control",
            "U",
            "holds no segment through 0 along any control axis: no square-wave start; give \
             one as [input]",
        ));
    }
    Ok(starts)
}
