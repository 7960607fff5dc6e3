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
//! A scope is per thread and nests (the innermost wins). Its observer is taken out while it
//! runs, so an observer that calls back into the library sees no scope (and cannot alias it).

use crate::error::{Error, Result};
use std::cell::Cell;
use std::ptr::NonNull;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

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

/// What a scope offers the kernels: the token and the observer of MILP progress.
pub struct Scope<'a> {
    cancel: Option<&'a Cancel>,
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

/// Runs `f` with a scope of `cancel` and `on_milp` on this thread.
pub fn scoped<'a, R>(
    cancel: Option<&'a Cancel>,
    on_milp: Option<&'a mut (dyn FnMut(&MilpProgress) + 'a)>,
    f: impl FnOnce() -> R,
) -> R {
    let mut scope = Scope {
        cancel,
        on_milp,
        objective_scale: 1.0,
    };
    // SAFETY: the pointer is only dereferenced on this thread while `f` runs (the guard puts
    // the previous value back before `scope` is dropped, also on unwinding), so the erased
    // lifetime never outlives the borrow.
    let ptr = NonNull::from(&mut scope).cast::<Scope<'static>>();
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
    CURRENT.with(|c| c.get().is_some())
}

/// Whether this thread's job was cancelled.
pub fn cancelled() -> bool {
    with_current(|s| s.cancel.is_some_and(Cancel::is_cancelled)).unwrap_or(false)
}

/// `Err(Error::Cancelled)` once this thread's job was cancelled: called between units of work.
pub fn check() -> Result<()> {
    if cancelled() {
        Err(Error::Cancelled)
    } else {
        Ok(())
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
            });
            report_milp(MilpProgress {
                incumbent: Some(1.0),
                bound: None,
                seconds: 0.0,
            });
        });
        assert_eq!(seen, vec![Some(3.0), Some(1.0)]);
    }
}
