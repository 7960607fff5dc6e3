//! The one boundary to HiGHS: every LP and MILP of the library is built, tuned, solved and read
//! here, and nothing here can panic on any answer HiGHS gives.
//!
//! The `highs` crate panics where HiGHS rejects a model (`Problem::optimise`: "invalid
//! problem", e.g. a coefficient of 1e20 or more, which HiGHS reads as infinite), where an option
//! or a bound change fails, and on status codes it does not know. So this module uses only the
//! crate's fallible calls (`try_optimise`, `try_set_option`, `try_set_solution`) and reaches
//! `highs-sys` directly for the rest (running, bound changes, statuses, the solution), mapping
//! every status to a typed [`Error`] or to a [`SolveStatus`] of the answer.
//!
//! Instances whose scale the solvers cannot honour are refused earlier, naming the field, by
//! the problem's range checks ([`GaitProblem::check_scales`](crate::optimal::GaitProblem));
//! HiGHS's own refusal of a model (a coefficient it reads as infinite) is the last line, and
//! arrives here as an error.

use crate::error::{Error, Result};
use crate::progress;
use highs::{Col, ColMatrix, HighsOptionValue, Model, Problem, Sense};
use highs_sys::HighsInt;
use std::ffi::CString;

/// How a solve ended, for the answers that carry a solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SolveStatus {
    /// Proven optimal within the tolerances.
    Optimal,
    /// The time limit ended the solve; `feasible` says whether a feasible point is at hand.
    TimeLimit {
        /// A primal feasible solution exists (the incumbent of a MILP).
        feasible: bool,
    },
    /// No feasible point exists.
    Infeasible,
}

/// What a solve returned: the status, the primal and dual solution and the bounds.
#[derive(Debug, Clone)]
pub(crate) struct Answer {
    /// How it ended.
    pub status: SolveStatus,
    /// Column values.
    pub columns: Vec<f64>,
    /// Reduced costs of the columns (LPs).
    pub column_duals: Vec<f64>,
    /// Row duals (LPs).
    pub row_duals: Vec<f64>,
    /// Objective value of the solution, in the model's sense.
    pub objective: f64,
    /// The MILP's dual bound, when HiGHS reports one.
    pub dual_bound: Option<f64>,
}

/// The status of every column and row of an LP's basis, as HiGHS reports it
/// ([`Highs::basis`]).
#[derive(Debug)]
pub(crate) struct Basis {
    columns: Vec<HighsInt>,
    rows: Vec<HighsInt>,
}

/// An LP or MILP handed to HiGHS (one thread, quiet), which can be re-solved after bound
/// changes (the local method's active-set loop).
pub(crate) struct Highs {
    model: Model,
    what: String,
    /// Whether each solve is limited to the time left of the job ([`Highs::until_deadline`]).
    timed: bool,
}

impl Highs {
    /// Checks and passes the problem to HiGHS; `what` names the computation in errors.
    pub fn new<M: Default>(pb: Problem<M>, sense: Sense, what: &str) -> Result<Self>
    where
        Problem<ColMatrix>: From<Problem<M>>,
    {
        let model = pb.try_optimise(sense).map_err(|s| {
            Error::Numerical(format!(
                "{what}: HiGHS refused the model ({s:?}): a coefficient, cost or bound outside \
                 the range it represents"
            ))
        })?;
        let mut h = Highs {
            model,
            what: what.to_string(),
            timed: false,
        };
        let log = std::env::var_os("CRAWLOPT_HIGHS_LOG").is_some();
        h.option("output_flag", log)?;
        h.option("log_to_console", log)?;
        h.option("threads", 1)?;
        Ok(h)
    }

    /// Sets a HiGHS option (an unknown name or a refused value is an error, not a panic).
    pub fn option<V: HighsOptionValue>(&mut self, name: &str, value: V) -> Result<()> {
        self.model
            .try_set_option(name, value)
            .map_err(|e| Error::Numerical(format!("{}: HiGHS option {name}: {e:?}", self.what)))
    }

    /// Limits every later solve to what is left of this thread's deadline
    /// ([`progress::remaining`], at least 1 ms: HiGHS takes no zero limit, and a solve begun
    /// at the deadline ends at once with status time limit); without a deadline, no limit. The
    /// solves of the optimisers' time-limited loops are timed; an auxiliary LP (a geometry, a
    /// polish, a certificate) is not, as it was never cut short by the time limit.
    pub fn until_deadline(&mut self) {
        self.timed = true;
    }

    /// The time limit in seconds (positive and finite; anything else is refused here).
    pub fn time_limit(&mut self, seconds: f64) -> Result<()> {
        if !(seconds.is_finite() && seconds > 0.0) {
            return Err(Error::invalid(
                "time_limit",
                seconds,
                "must be positive and finite",
            ));
        }
        self.option("time_limit", seconds)
    }

    /// Changes the bounds of a column (finite or infinite, `lo <= hi`, no NaN).
    pub fn set_bounds(&mut self, col: Col, lo: f64, hi: f64) -> Result<()> {
        if lo.is_nan() || hi.is_nan() || lo > hi || lo == f64::INFINITY || hi == -f64::INFINITY {
            return Err(Error::Numerical(format!(
                "{}: invalid column bounds [{lo}, {hi}]",
                self.what
            )));
        }
        self.change_column(col, &format!("bounds [{lo}, {hi}]"), |ptr, idx| {
            // SAFETY: see `change_column`.
            unsafe { highs_sys::Highs_changeColBounds(ptr, idx, lo, hi) }
        })
    }

    /// Changes the objective coefficient of a column (finite).
    pub fn set_cost(&mut self, col: Col, cost: f64) -> Result<()> {
        if !cost.is_finite() {
            return Err(Error::Numerical(format!(
                "{}: invalid column cost {cost}",
                self.what
            )));
        }
        self.change_column(col, &format!("cost {cost}"), |ptr, idx| {
            // SAFETY: see `change_column`.
            unsafe { highs_sys::Highs_changeColCost(ptr, idx, cost) }
        })
    }

    /// One change of column `col` (`what_changed` names it in errors) by `change`, called with
    /// the live HiGHS instance owned by `self.model` and the index of a column of that instance
    /// (a `Col` handed out when the problem was built), which is what makes its call safe.
    fn change_column(
        &mut self,
        col: Col,
        what_changed: &str,
        change: impl FnOnce(*mut std::ffi::c_void, HighsInt) -> HighsInt,
    ) -> Result<()> {
        let idx = HighsInt::try_from(col.index())
            .map_err(|_| Error::Numerical(format!("{}: too many columns", self.what)))?;
        if change(self.model.as_mut_ptr(), idx) == highs_sys::STATUS_ERROR {
            return Err(Error::Numerical(format!(
                "{}: HiGHS refused the {what_changed} of column {}",
                self.what,
                col.index()
            )));
        }
        Ok(())
    }

    /// The basis HiGHS holds (the status of every column and row), for a model rebuilt later
    /// to start from it ([`Highs::set_basis`]) instead of keeping this one alive; `None` when
    /// HiGHS has none to give.
    pub fn basis(&mut self) -> Option<Basis> {
        let ptr = self.model.as_mut_ptr();
        // SAFETY: `ptr` is the live HiGHS instance owned by `self.model`; the buffers are
        // sized from HiGHS's own counts.
        let ncol = usize::try_from(unsafe { highs_sys::Highs_getNumCol(ptr) }).ok()?;
        let nrow = usize::try_from(unsafe { highs_sys::Highs_getNumRow(ptr) }).ok()?;
        let (mut columns, mut rows) = (vec![0; ncol], vec![0; nrow]);
        let st = unsafe { highs_sys::Highs_getBasis(ptr, columns.as_mut_ptr(), rows.as_mut_ptr()) };
        (st != highs_sys::STATUS_ERROR).then_some(Basis { columns, rows })
    }

    /// Starts the next solve from `basis` (of a model of the same shape). A basis HiGHS does
    /// not take is only a lost hint, never a wrong answer, so its refusal is reported as
    /// `false`, not as an error.
    pub fn set_basis(&mut self, basis: &Basis) -> bool {
        let ptr = self.model.as_mut_ptr();
        // SAFETY: as in `basis`; the lengths are checked against HiGHS's counts first.
        let ncol = usize::try_from(unsafe { highs_sys::Highs_getNumCol(ptr) }).ok();
        let nrow = usize::try_from(unsafe { highs_sys::Highs_getNumRow(ptr) }).ok();
        ncol == Some(basis.columns.len())
            && nrow == Some(basis.rows.len())
            && unsafe {
                highs_sys::Highs_setBasis(ptr, basis.columns.as_ptr(), basis.rows.as_ptr())
            } != highs_sys::STATUS_ERROR
    }

    /// Offers a start point (all columns). A start HiGHS does not take is only a lost hint,
    /// never a wrong answer, so its refusal is reported as `false`, not as an error.
    pub fn start(&mut self, columns: &[f64]) -> bool {
        columns.iter().all(|v| v.is_finite())
            && self
                .model
                .try_set_solution(Some(columns), None, None, None)
                .is_ok()
    }

    /// Runs HiGHS. Optimal, time-limited and infeasible ends are answers; every other end
    /// (unbounded, a solver error, an unknown status) is an [`Error::Numerical`] naming it.
    ///
    /// Inside a [`progress`] scope the run is watched through HiGHS's callback: it is
    /// interrupted once the job is cancelled ([`Error::Cancelled`]), and a MILP reports its
    /// incumbent and bound.
    pub fn solve(&mut self) -> Result<Answer> {
        progress::check()?;
        if let Some(left) = progress::remaining().filter(|_| self.timed) {
            self.time_limit(left.max(1e-3))?;
        }
        let what = &self.what;
        let ptr = self.model.as_mut_ptr();
        let mut watch = Watch::new();
        let watched = progress::in_scope() && watch.install(ptr);
        // SAFETY (every call below): `ptr` is the live HiGHS instance owned by `self.model`,
        // borrowed mutably for the whole function; buffers are sized from HiGHS's own counts.
        // `watch` outlives the run and its callback is removed right after it.
        let run = unsafe { highs_sys::Highs_run(ptr) };
        if watched {
            Watch::remove(ptr);
        }
        let model_status = unsafe { highs_sys::Highs_getModelStatus(ptr) };
        if model_status == highs_sys::kHighsModelStatusInterrupt && progress::cancelled() {
            return Err(Error::Cancelled);
        }
        if run == highs_sys::STATUS_ERROR && model_status != highs_sys::MODEL_STATUS_INFEASIBLE {
            return Err(Error::Numerical(format!(
                "{what}: HiGHS failed to solve the model ({})",
                model_status_name(model_status)
            )));
        }
        let feasible = int_info(ptr, "primal_solution_status")
            == Some(i64::from(highs_sys::SOLUTION_STATUS_FEASIBLE));
        let status = match model_status {
            highs_sys::MODEL_STATUS_OPTIMAL => SolveStatus::Optimal,
            highs_sys::MODEL_STATUS_REACHED_TIME_LIMIT => SolveStatus::TimeLimit { feasible },
            highs_sys::MODEL_STATUS_INFEASIBLE => SolveStatus::Infeasible,
            other => {
                return Err(Error::Numerical(format!(
                    "{what}: HiGHS ended with status {}",
                    model_status_name(other)
                )))
            }
        };
        let ncol = usize::try_from(unsafe { highs_sys::Highs_getNumCol(ptr) }).unwrap_or(0);
        let nrow = usize::try_from(unsafe { highs_sys::Highs_getNumRow(ptr) }).unwrap_or(0);
        let (mut x, mut dx) = (vec![0.0; ncol], vec![0.0; ncol]);
        let (mut r, mut dr) = (vec![0.0; nrow], vec![0.0; nrow]);
        if status != SolveStatus::Infeasible {
            let st = unsafe {
                highs_sys::Highs_getSolution(
                    ptr,
                    x.as_mut_ptr(),
                    dx.as_mut_ptr(),
                    r.as_mut_ptr(),
                    dr.as_mut_ptr(),
                )
            };
            if st == highs_sys::STATUS_ERROR {
                return Err(Error::Numerical(format!(
                    "{what}: HiGHS has no solution to read"
                )));
            }
        }
        let objective = unsafe { highs_sys::Highs_getObjectiveValue(ptr) };
        let dual_bound = double_info(ptr, "mip_dual_bound").filter(|b| b.is_finite());
        let has_solution =
            status == SolveStatus::Optimal || status == (SolveStatus::TimeLimit { feasible: true });
        if has_solution && (!objective.is_finite() || x.iter().any(|v| !v.is_finite())) {
            return Err(Error::Numerical(format!(
                "{what}: HiGHS returned a non-finite solution"
            )));
        }
        Ok(Answer {
            status,
            columns: x,
            column_duals: dx,
            row_duals: dr,
            objective,
            dual_bound,
        })
    }
}

/// What HiGHS's callback needs between calls: when MILP progress was last reported (at most
/// [`Watch::EVERY`] apart, improving solutions always).
struct Watch {
    last: Option<std::time::Instant>,
}

impl Watch {
    /// Shortest time between two reports of MILP progress, seconds.
    const EVERY: f64 = 0.2;

    /// The callbacks that are started: the interrupts of each solver, and the MILP's reports.
    const KINDS: [HighsInt; 5] = [
        highs_sys::kHighsCallbackSimplexInterrupt,
        highs_sys::kHighsCallbackIpmInterrupt,
        highs_sys::kHighsCallbackMipInterrupt,
        highs_sys::kHighsCallbackMipImprovingSolution,
        highs_sys::kHighsCallbackMipLogging,
    ];

    fn new() -> Self {
        Watch { last: None }
    }

    /// Installs [`callback`] with `self` as its data; `false` if HiGHS refuses (the solve then
    /// runs unwatched: a cancellation is seen at the next check between solves).
    fn install(&mut self, ptr: *mut std::ffi::c_void) -> bool {
        let data = (self as *mut Watch).cast();
        // SAFETY: `ptr` is a live HiGHS instance; `data` points to `self`, which the caller
        // keeps alive until `remove` after the run.
        let set = unsafe { highs_sys::Highs_setCallback(ptr, Some(callback), data) };
        set != highs_sys::STATUS_ERROR
            && Self::KINDS.iter().all(
                |&k| unsafe { highs_sys::Highs_startCallback(ptr, k) } != highs_sys::STATUS_ERROR,
            )
    }

    /// Stops the callbacks and forgets the data pointer.
    fn remove(ptr: *mut std::ffi::c_void) {
        // SAFETY: as in `install`.
        unsafe {
            for k in Self::KINDS {
                highs_sys::Highs_stopCallback(ptr, k);
            }
            highs_sys::Highs_setCallback(ptr, None, std::ptr::null_mut());
        }
    }
}

/// HiGHS's callback: sets `user_interrupt` once the job is cancelled, and reports a MILP's
/// incumbent and bound (HiGHS gives both in the sense of the model: for our maximisations,
/// incumbent <= bound). Never unwinds into C.
unsafe extern "C" fn callback(
    kind: std::os::raw::c_int,
    _message: *const std::os::raw::c_char,
    out: *const highs_sys::HighsCallbackDataOut,
    input: *mut highs_sys::HighsCallbackDataIn,
    data: *mut std::ffi::c_void,
) {
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: HiGHS passes valid pointers for the duration of the call; `data` is the
        // `Watch` installed for this run.
        let (out, watch) = unsafe { (out.as_ref(), data.cast::<Watch>().as_mut()) };
        let interrupt = [
            highs_sys::kHighsCallbackSimplexInterrupt,
            highs_sys::kHighsCallbackIpmInterrupt,
            highs_sys::kHighsCallbackMipInterrupt,
        ];
        if interrupt.contains(&kind) && progress::cancelled() {
            if let Some(input) = unsafe { input.as_mut() } {
                input.user_interrupt = 1;
            }
            return;
        }
        let (Some(out), Some(watch)) = (out, watch) else {
            return;
        };
        let mip = [
            highs_sys::kHighsCallbackMipImprovingSolution,
            highs_sys::kHighsCallbackMipLogging,
            highs_sys::kHighsCallbackMipInterrupt,
        ];
        let due = kind == highs_sys::kHighsCallbackMipImprovingSolution
            || watch
                .last
                .is_none_or(|t| t.elapsed().as_secs_f64() >= Watch::EVERY);
        if mip.contains(&kind) && due {
            watch.last = Some(std::time::Instant::now());
            let finite = |v: f64| Some(v).filter(|v| v.is_finite());
            progress::report_milp(progress::MilpProgress {
                incumbent: finite(out.mip_primal_bound),
                bound: finite(out.mip_dual_bound),
                seconds: out.running_time,
            });
        }
    }));
}

/// An integer info value of the last solve, if HiGHS knows the name.
fn int_info(ptr: *mut std::ffi::c_void, name: &str) -> Option<i64> {
    let name = CString::new(name).ok()?;
    let mut v: HighsInt = -1;
    // SAFETY: `ptr` is a live HiGHS instance (callers), `name` a NUL-terminated string that
    // outlives the call, `v` a valid out-pointer.
    let st = unsafe { highs_sys::Highs_getIntInfoValue(ptr, name.as_ptr(), &mut v) };
    (st != highs_sys::STATUS_ERROR).then_some(i64::from(v))
}

/// A double info value of the last solve, if HiGHS knows the name.
fn double_info(ptr: *mut std::ffi::c_void, name: &str) -> Option<f64> {
    let name = CString::new(name).ok()?;
    let mut v = f64::NAN;
    // SAFETY: as in `int_info`.
    let st = unsafe { highs_sys::Highs_getDoubleInfoValue(ptr, name.as_ptr(), &mut v) };
    (st != highs_sys::STATUS_ERROR).then_some(v)
}

/// A readable name of a HiGHS model status code.
fn model_status_name(s: HighsInt) -> String {
    let name = match s {
        highs_sys::MODEL_STATUS_NOTSET => "not set",
        highs_sys::MODEL_STATUS_LOAD_ERROR => "load error",
        highs_sys::MODEL_STATUS_MODEL_ERROR => "model error",
        highs_sys::MODEL_STATUS_PRESOLVE_ERROR => "presolve error",
        highs_sys::MODEL_STATUS_SOLVE_ERROR => "solve error",
        highs_sys::MODEL_STATUS_POSTSOLVE_ERROR => "postsolve error",
        highs_sys::MODEL_STATUS_MODEL_EMPTY => "empty model",
        highs_sys::MODEL_STATUS_OPTIMAL => "optimal",
        highs_sys::MODEL_STATUS_INFEASIBLE => "infeasible",
        highs_sys::MODEL_STATUS_UNBOUNDED_OR_INFEASIBLE => "unbounded or infeasible",
        highs_sys::MODEL_STATUS_UNBOUNDED => "unbounded",
        highs_sys::MODEL_STATUS_REACHED_TIME_LIMIT => "time limit",
        highs_sys::MODEL_STATUS_REACHED_ITERATION_LIMIT => "iteration limit",
        highs_sys::MODEL_STATUS_UNKNOWN => "unknown",
        highs_sys::MODEL_STATUS_REACHED_INTERRUPT => "interrupted",
        highs_sys::MODEL_STATUS_REACHED_MEMORY_LIMIT => "memory limit",
        _ => return format!("unrecognised status code {s}"),
    };
    name.to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use highs::RowProblem;

    #[test]
    fn a_coefficient_highs_reads_as_infinite_is_an_error_not_a_panic() {
        let mut pb = RowProblem::default();
        let x = pb.add_column(1.0, 0.0..=1.0);
        pb.add_row(..=1.0, [(x, 1e300)]);
        let r = Highs::new(pb, Sense::Maximise, "test").and_then(|mut h| h.solve());
        assert!(matches!(r, Err(Error::Numerical(_))), "{r:?}");
    }

    #[test]
    fn statuses_map_to_answers() {
        // max x, x <= 2: optimal at 2, with the row's dual.
        let mut pb = RowProblem::default();
        let x = pb.add_column(1.0, 0.0..);
        pb.add_row(..=2.0, [(x, 1.0)]);
        let a = Highs::new(pb, Sense::Maximise, "test")
            .unwrap()
            .solve()
            .unwrap();
        assert_eq!(a.status, SolveStatus::Optimal);
        assert!((a.objective - 2.0).abs() < 1e-12 && (a.columns[0] - 2.0).abs() < 1e-12);
        assert!((a.row_duals[0].abs() - 1.0).abs() < 1e-12);
        // x >= 3 and x <= 2: infeasible.
        let mut pb = RowProblem::default();
        let x = pb.add_column(1.0, 3.0..);
        pb.add_row(..=2.0, [(x, 1.0)]);
        let a = Highs::new(pb, Sense::Maximise, "test")
            .unwrap()
            .solve()
            .unwrap();
        assert_eq!(a.status, SolveStatus::Infeasible);
        // max x unbounded: an error naming the status.
        let mut pb = RowProblem::default();
        let x = pb.add_column(1.0, 0.0..);
        pb.add_row(0.0.., [(x, 1.0)]);
        let e = Highs::new(pb, Sense::Maximise, "test")
            .unwrap()
            .solve()
            .unwrap_err();
        assert!(e.to_string().contains("unbounded"), "{e}");
    }

    #[test]
    fn bounds_are_changed_and_bad_bounds_refused() {
        let mut pb = RowProblem::default();
        let x = pb.add_column(1.0, 0.0..=5.0);
        pb.add_row(..=10.0, [(x, 1.0)]);
        let mut h = Highs::new(pb, Sense::Maximise, "test").unwrap();
        assert!((h.solve().unwrap().objective - 5.0).abs() < 1e-12);
        h.set_bounds(x, 0.0, 1.5).unwrap();
        assert!((h.solve().unwrap().objective - 1.5).abs() < 1e-12);
        assert!(h.set_bounds(x, 2.0, 1.0).is_err());
        assert!(h.set_bounds(x, f64::NAN, 1.0).is_err());
        assert!(h.option("no_such_option", 1).is_err());
        assert!(h.time_limit(f64::NAN).is_err());
    }
}
