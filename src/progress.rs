//! Cancellation and in-solve progress, below every layer that computes.
//!
//! A front end gives a job (see [`crate::api`]) a [`Cancel`] token and an observer of
//! [`crate::api::Event`]s. The job opens a [`Scope`] on its thread for its duration; the kernels
//! underneath (the HiGHS boundary `optimal::solver`, the loops over K, m, shifts, sequences and
//! periods) ask it, without new parameters on every function between:
//! - [`check`] between units of work (a MILP, a period, a local iteration): `Err(Cancelled)`
//!   once the token is tripped;
//! - [`cancelled`] from inside a running MILP or LP (HiGHS's interrupt callback), so that a long
//!   solve stops within its next callback, not at its time limit;
//! - [`report_milp`] with the incumbent and the bound of a running MILP.
//!
//! The scope also carries the job's [`Deadline`]: the token and the deadline travel together as
//! one [`Stop`]. A job's time limit (the user's `time_limit` setting, seconds) becomes a
//! deadline once, where the job starts ([`within`]); a part of the job given a share of what is
//! left (a start gait, a sub-search) narrows it ([`share`], or [`within`] with its own limit),
//! never beyond the enclosing deadline. The kernels ask [`out_of_time`] between units of work (a
//! loop that runs out of time returns its best answer so far with status `time_limit`), and the
//! HiGHS boundary gives each timed solve [`remaining`] seconds. Cancellation wins over the time:
//! [`out_of_time`] is `Err(Cancelled)` once the token is tripped, expired or not.
//!
//! A scope is per thread and nests (the innermost wins). Its observer is taken out while it
//! runs, so an observer that calls back into the library sees no scope (and cannot alias it).

use crate::error::{Error, Result};
use std::cell::Cell;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A cancellation token: cheap to clone, shared between the caller (who trips it, from any
/// thread or a signal handler's flag) and the job (which stops at its next check and returns
/// [`Error::Cancelled`]).
#[derive(Clone, Debug, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A token that is not tripped.
    pub fn new() -> Self {
        Self::default()
    }

    /// Trips the token: every job holding it stops at its next check.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::SeqCst);
    }

    /// Whether [`Cancel::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }

    /// The flag itself, for a signal handler to trip with one atomic store (storing `true` is
    /// [`Cancel::cancel`]; a handler may not call anything that allocates or locks).
    pub fn flag(&self) -> &AtomicBool {
        &self.0
    }
}

/// When a job's time is up: an instant, or none (no time limit). Copied freely; a sub-budget
/// ([`Deadline::child`], [`Deadline::share`]) never ends after its parent.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Deadline(Option<Instant>);

impl Deadline {
    /// No deadline: the job runs until its work is done (or it is cancelled).
    pub const NONE: Deadline = Deadline(None);

    /// The deadline `seconds` from now (none without a limit). A limit too large for the clock
    /// is no limit; a negative or NaN one has already expired (the settings refuse both, naming
    /// the field, before any deadline is made).
    pub fn after(seconds: Option<f64>) -> Self {
        Self::NONE.child(seconds)
    }

    /// The instant, if there is one.
    pub fn at(self) -> Option<Instant> {
        self.0
    }

    /// Seconds left (0 once expired); `None` without a deadline.
    pub fn remaining(self) -> Option<f64> {
        self.0
            .map(|d| d.saturating_duration_since(Instant::now()).as_secs_f64())
    }

    /// Whether the deadline has passed (never, without one).
    pub fn expired(self) -> bool {
        self.0.is_some_and(|d| Instant::now() >= d)
    }

    /// A sub-budget of `seconds` from now, within this deadline: the earlier of the two
    /// (`None`: this deadline).
    pub fn child(self, seconds: Option<f64>) -> Self {
        let Some(s) = seconds else {
            return self;
        };
        let own = match Duration::try_from_secs_f64(s) {
            Ok(d) => Instant::now().checked_add(d),
            // Negative or NaN: already expired.
            Err(_) if s.is_nan() || s < 0.0 => Some(Instant::now()),
            // Beyond what a duration holds: no limit of its own.
            Err(_) => None,
        };
        match (self.0, own) {
            (Some(p), Some(o)) => Deadline(Some(p.min(o))),
            (p, o) => Deadline(p.or(o)),
        }
    }

    /// A share of what is left: `fraction` (in `[0, 1]`) of [`Deadline::remaining`] from now;
    /// no deadline stays none.
    pub fn share(self, fraction: f64) -> Self {
        match self.remaining() {
            Some(left) => self.child(Some(fraction.clamp(0.0, 1.0) * left)),
            None => self,
        }
    }
}

/// How a job is stopped: its cancellation token and its deadline, together.
#[derive(Clone, Debug, Default)]
pub struct Stop {
    /// The token the caller trips (none: the job cannot be cancelled).
    pub cancel: Option<Cancel>,
    /// When the job's time is up.
    pub deadline: Deadline,
}

impl Stop {
    /// `Err(Error::Cancelled)` once the token is tripped.
    pub fn check(&self) -> Result<()> {
        if self.cancel.as_ref().is_some_and(Cancel::is_cancelled) {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }

    /// Whether the time is up: `Err(Error::Cancelled)` once the token is tripped (cancellation
    /// wins over the time), else whether the deadline has passed.
    pub fn out_of_time(&self) -> Result<bool> {
        self.check()?;
        Ok(self.deadline.expired())
    }
}

/// The state of a running MILP, as HiGHS reports it through its callback: the best objective
/// found (the incumbent, if any) and the proven bound, in the problem's own units and sense
/// (a maximisation: incumbent <= bound).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MilpProgress {
    /// The objective of the best feasible point found so far, if one was.
    pub incumbent: Option<f64>,
    /// The proven bound on the optimum.
    pub bound: Option<f64>,
    /// Seconds since this MILP started.
    pub seconds: f64,
}

/// What a scope offers the kernels: the token and the deadline, and the observer of MILP
/// progress.
pub struct Scope<'a> {
    stop: Stop,
    /// Opened by a job ([`scoped`]), not only for a deadline ([`within`] outside any job).
    job: bool,
    on_milp: Option<&'a mut (dyn FnMut(&MilpProgress) + 'a)>,
    /// The factor from the solver's objective to the user's units (set by the unit wrappers,
    /// `optimal::units`, around a solve in internal units).
    objective_scale: f64,
}

thread_local! {
    static CURRENT: Cell<Option<NonNull<Scope<'static>>>> = const { Cell::new(None) };
}

/// Restores the previous scope when the closure returns or unwinds.
struct Restore(Option<NonNull<Scope<'static>>>);

impl Drop for Restore {
    fn drop(&mut self) {
        CURRENT.with(|c| c.set(self.0));
    }
}

/// Runs `f` with a scope of `cancel` and `on_milp` on this thread (no deadline: a job's time
/// limit is set by [`within`] where its work starts).
pub fn scoped<'a, R>(
    cancel: Option<&'a Cancel>,
    on_milp: Option<&'a mut (dyn FnMut(&MilpProgress) + 'a)>,
    f: impl FnOnce() -> R,
) -> R {
    let mut scope = Scope {
        stop: Stop {
            cancel: cancel.cloned(),
            deadline: Deadline::NONE,
        },
        job: true,
        on_milp,
        objective_scale: 1.0,
    };
    enter(&mut scope, f)
}

/// Runs `f` with `scope` as this thread's current scope.
fn enter<'a, R>(scope: &mut Scope<'a>, f: impl FnOnce() -> R) -> R {
    // SAFETY: the pointer is only dereferenced on this thread while `f` runs (the guard puts
    // the previous value back before `scope` is dropped, also on unwinding), so the erased
    // lifetime never outlives the borrow.
    let ptr = NonNull::from(scope).cast::<Scope<'static>>();
    let _restore = Restore(CURRENT.with(|c| c.replace(Some(ptr))));
    f()
}

/// Runs `g` on the current scope, taken out of the thread-local while `g` runs (so that a
/// nested use sees none); `None` without a scope.
fn with_current<R>(g: impl FnOnce(&mut Scope<'_>) -> R) -> Option<R> {
    let ptr = CURRENT.with(|c| c.take())?;
    let _restore = Restore(Some(ptr));
    // SAFETY: see `scoped`; taken out of the cell, so no other reference exists meanwhile.
    Some(g(unsafe { &mut *ptr.as_ptr() }))
}

/// Whether this thread runs inside a [`scoped`] job (the kernels then install their hooks, such
/// as HiGHS's callback; outside one they run exactly as without this module).
pub fn in_scope() -> bool {
    with_current(|s| s.job).unwrap_or(false)
}

/// Whether this thread's job was cancelled.
pub fn cancelled() -> bool {
    with_current(|s| s.stop.check().is_err()).unwrap_or(false)
}

/// `Err(Error::Cancelled)` once this thread's job was cancelled: called between units of work.
pub fn check() -> Result<()> {
    if cancelled() {
        Err(Error::Cancelled)
    } else {
        Ok(())
    }
}

/// This thread's deadline ([`Deadline::NONE`] outside any).
pub fn deadline() -> Deadline {
    with_current(|s| s.stop.deadline).unwrap_or_default()
}

/// Seconds left of this thread's deadline; `None` without one.
pub fn remaining() -> Option<f64> {
    deadline().remaining()
}

/// Whether this thread's deadline has passed.
pub fn expired() -> bool {
    deadline().expired()
}

/// [`Stop::out_of_time`] of this thread's job: `Err(Cancelled)` once cancelled (cancellation
/// wins), else whether its deadline has passed. Asked between units of work by the loops that
/// stop at the time limit with their best answer so far.
pub fn out_of_time() -> Result<bool> {
    check()?;
    Ok(expired())
}

/// Runs `f` under a time limit of `seconds` from now ([`Deadline::child`] of the current
/// deadline: never later than it); `None` runs `f` under the current deadline. This is where a
/// job's `time_limit` setting becomes its deadline (outside any scope, `f` runs in one of its
/// own that holds only the deadline).
pub fn within<R>(seconds: Option<f64>, f: impl FnOnce() -> R) -> R {
    if seconds.is_none() {
        return f();
    }
    narrowed(|d| d.child(seconds), f)
}

/// Runs `f` within `fraction` of the time left ([`Deadline::share`]; without a deadline, `f`
/// runs without one): a part of a job given its share of the budget.
pub fn share<R>(fraction: f64, f: impl FnOnce() -> R) -> R {
    narrowed(|d| d.share(fraction), f)
}

/// Puts a deadline back when the closure that narrowed it returns or unwinds.
struct RestoreDeadline(Deadline);

impl Drop for RestoreDeadline {
    fn drop(&mut self) {
        with_current(|s| s.stop.deadline = self.0);
    }
}

/// Runs `f` with the current deadline replaced by `to(deadline)`.
fn narrowed<R>(to: impl FnOnce(Deadline) -> Deadline, f: impl FnOnce() -> R) -> R {
    let mut to = Some(to);
    let narrow = |s: &mut Scope<'_>| {
        let old = s.stop.deadline;
        if let Some(to) = to.take() {
            s.stop.deadline = to(old);
        }
        old
    };
    match with_current(narrow) {
        Some(old) => {
            let _restore = RestoreDeadline(old);
            f()
        }
        None => {
            let deadline = to.map_or(Deadline::NONE, |to| to(Deadline::NONE));
            let mut scope = Scope {
                stop: Stop {
                    cancel: None,
                    deadline,
                },
                job: false,
                on_milp: None,
                objective_scale: 1.0,
            };
            enter(&mut scope, f)
        }
    }
}

/// Reports a running MILP's state (objective values in the solver's units; they are scaled to
/// the user's by the current objective scale).
pub fn report_milp(p: MilpProgress) {
    with_current(|s| {
        let k = s.objective_scale;
        if let Some(f) = s.on_milp.as_mut() {
            f(&MilpProgress {
                incumbent: p.incumbent.map(|v| v * k),
                bound: p.bound.map(|v| v * k),
                seconds: p.seconds,
            });
        }
    });
}

/// Runs `f` with MILP objectives reported multiplied by `scale` (a solve in internal units).
pub fn with_objective_scale<R>(scale: f64, f: impl FnOnce() -> R) -> R {
    let old = with_current(|s| std::mem::replace(&mut s.objective_scale, scale));
    let r = f();
    if let Some(old) = old {
        with_current(|s| s.objective_scale = old);
    }
    r
}

/// Runs `f` with MILP objectives reported multiplied by `factor` on top of the current scale (a
/// solve in units of its own inside a job that may have its own, [`with_objective_scale`]).
pub fn with_objective_factor<R>(factor: f64, f: impl FnOnce() -> R) -> R {
    let current = with_current(|s| s.objective_scale).unwrap_or(1.0);
    with_objective_scale(current * factor, f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scope_sees_its_token_and_ends_with_its_closure() {
        let token = Cancel::new();
        assert!(check().is_ok());
        scoped(Some(&token), None, || {
            assert!(check().is_ok());
            token.cancel();
            assert_eq!(check(), Err(Error::Cancelled));
        });
        // Outside the scope nothing is cancelled.
        assert!(check().is_ok());
    }

    #[test]
    fn progress_is_scaled_and_nested_scopes_restore_the_outer() {
        let mut seen = Vec::new();
        let mut on = |p: &MilpProgress| seen.push(p.incumbent);
        scoped(None, Some(&mut on), || {
            with_objective_scale(2.0, || {
                report_milp(MilpProgress {
                    incumbent: Some(1.5),
                    bound: None,
                    seconds: 0.0,
                });
                // An inner scope without an observer hides the outer one, then restores it.
                scoped(None, None, || {
                    report_milp(MilpProgress {
                        incumbent: Some(9.0),
                        bound: None,
                        seconds: 0.0,
                    })
                });
                // A factor multiplies the current scale, which is restored after it.
                with_objective_factor(5.0, || {
                    report_milp(MilpProgress {
                        incumbent: Some(0.5),
                        bound: None,
                        seconds: 0.0,
                    })
                });
                report_milp(MilpProgress {
                    incumbent: Some(0.25),
                    bound: None,
                    seconds: 0.0,
                });
            });
            report_milp(MilpProgress {
                incumbent: Some(1.0),
                bound: None,
                seconds: 0.0,
            });
        });
        assert_eq!(seen, vec![Some(3.0), Some(5.0), Some(0.5), Some(1.0)]);
    }

    #[test]
    fn a_deadline_expires_and_none_never_does() {
        assert!(Deadline::after(Some(0.0)).expired());
        assert_eq!(Deadline::after(Some(0.0)).remaining(), Some(0.0));
        let hour = Deadline::after(Some(3600.0));
        assert!(!hour.expired());
        assert!(hour.remaining().is_some_and(|r| r > 0.0 && r <= 3600.0));
        for none in [
            Deadline::NONE,
            Deadline::after(None),
            Deadline::after(Some(1e300)),
        ] {
            assert!(!none.expired());
            assert_eq!(none.remaining(), None);
            assert_eq!(none.share(0.5), Deadline::NONE);
        }
        // A refused value (negative, NaN) never means "no limit".
        assert!(Deadline::after(Some(-1.0)).expired());
        assert!(Deadline::after(Some(f64::NAN)).expired());
    }

    #[test]
    fn a_sub_budget_never_ends_after_its_parent() {
        let parent = Deadline::after(Some(10.0));
        let end = parent.at().expect("a deadline");
        // A longer own limit is cut to the parent's; a shorter one is kept.
        assert_eq!(parent.child(Some(1e6)).at(), Some(end));
        assert_eq!(parent.child(None), parent);
        let short = parent.child(Some(1.0)).at().expect("a deadline");
        assert!(short < end);
        for f in [0.0, 0.25, 0.5, 1.0, 2.0] {
            assert!(parent.share(f).at().expect("a deadline") <= end);
        }
        // Nested in a scope: the inner deadline is the earlier one, and the outer comes back.
        scoped(None, None, || {
            assert_eq!(deadline(), Deadline::NONE);
            within(Some(10.0), || {
                let outer = deadline().at().expect("a deadline");
                within(Some(1e6), || assert_eq!(deadline().at(), Some(outer)));
                share(0.5, || {
                    assert!(deadline().at().expect("a deadline") < outer)
                });
                within(Some(0.0), || assert!(expired()));
                assert_eq!(deadline().at(), Some(outer));
                assert!(!expired());
            });
            assert_eq!(deadline(), Deadline::NONE);
        });
        // Outside any job a deadline still holds, in a scope of its own that is no job's.
        within(Some(0.0), || {
            assert!(expired());
            assert!(!in_scope());
            assert_eq!(out_of_time(), Ok(true));
        });
        assert!(!expired());
    }

    #[test]
    fn cancellation_wins_over_the_time() {
        let token = Cancel::new();
        let stop = Stop {
            cancel: Some(token.clone()),
            deadline: Deadline::after(Some(0.0)),
        };
        assert_eq!(stop.out_of_time(), Ok(true));
        token.cancel();
        assert_eq!(stop.out_of_time(), Err(Error::Cancelled));
        let fresh = Cancel::new();
        scoped(Some(&fresh), None, || {
            within(Some(0.0), || {
                assert_eq!(out_of_time(), Ok(true));
                fresh.cancel();
                assert_eq!(out_of_time(), Err(Error::Cancelled));
            })
        });
    }
}
