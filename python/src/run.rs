//! Running a job with the GIL released and cancellable by Ctrl-C, at a cost of a few
//! microseconds a call.
//!
//! The job runs on the calling thread inside `allow_threads`, so other Python threads run
//! meanwhile. Progress events are handed to the Python callable `progress` (as JSON text) by
//! taking the GIL back for the call; a callable that raises stops the job (its token is
//! tripped) and its exception is raised.
//!
//! Ctrl-C: Python only delivers KeyboardInterrupt to its main thread, and only when that
//! thread runs Python code, which it does not during the job. So, on the main thread and while
//! SIGINT is Python's `default_int_handler`, the job's duration is bracketed by a C-level SIGINT
//! handler ([`sigint`]) that only trips the job's token (async-signal-safe: one atomic store).
//! The job stops at its next check (inside a running MILP through HiGHS's callback), the
//! previous handler is restored, the signal is raised again so Python's own machinery sees it,
//! and `check_signals` raises KeyboardInterrupt as if the job had been Python code. A job on
//! another thread is not interrupted (as Python code on that thread would not be).
//!
//! The first version ran the job on a worker thread while the caller polled for signals; the
//! thread's creation and the hand-over cost about 50 us a call, 12 % of simulating three blocks
//! for one period (`scripts/bench-python`).

use crate::errors;
use crawlopt::api::{Event, Hooks};
use crawlopt::progress::Cancel;
use pyo3::prelude::*;
use pyo3::sync::GILOnceCell;
use std::sync::Mutex;

/// Runs `job` (given the hooks) on this thread with the GIL released; see the module docs.
pub fn run<T: Send>(
    py: Python<'_>,
    progress: Option<PyObject>,
    job: impl FnOnce(Hooks<'_>) -> crawlopt::Result<T> + Send,
) -> PyResult<T> {
    let cancel = Cancel::new();
    let guard = if interruptible(py)? {
        sigint::Guard::install(&cancel)
    } else {
        None
    };
    // The first exception a progress callback raised (the job is stopped by then).
    let failed: Mutex<Option<PyErr>> = Mutex::new(None);
    let answer = {
        let (cancel, failed) = (&cancel, &failed);
        py.allow_threads(move || {
            let mut send = |e: &Event, t: f64| {
                let Some(f) = &progress else { return };
                if cancel.is_cancelled() {
                    return;
                }
                let text = event_json(e, t);
                Python::with_gil(|py| {
                    if let Err(err) = f.call1(py, (text,)) {
                        cancel.cancel();
                        if let Ok(mut slot) = failed.lock() {
                            slot.get_or_insert(err);
                        }
                    }
                });
            };
            let hooks = Hooks {
                events: if progress.is_some() {
                    Some(&mut send)
                } else {
                    None
                },
                cancel: Some(cancel),
            };
            job(hooks)
        })
    };
    let interrupted = guard.is_some_and(|g| g.restore());
    if interrupted {
        // Python's handler has seen the signal again: it raises KeyboardInterrupt here.
        py.check_signals()?;
    }
    if let Some(e) = failed.into_inner().ok().flatten() {
        return Err(e);
    }
    answer.map_err(|e| errors::to_py(py, e))
}

/// Whether Ctrl-C should cancel a job on this thread: it is Python's main thread and SIGINT
/// is Python's default handler (a program that installed its own keeps its own behaviour).
fn interruptible(py: Python<'_>) -> PyResult<bool> {
    /// `threading.main_thread().ident`, `signal.getsignal`, `signal.SIGINT` and
    /// `signal.default_int_handler`, looked up once.
    static PY: GILOnceCell<(u64, [PyObject; 3])> = GILOnceCell::new();
    if !cfg!(unix) {
        return Ok(false);
    }
    let (main, [getsignal, sigint, default]) = PY.get_or_try_init(py, || {
        let threading = py.import("threading")?;
        let signal = py.import("signal")?;
        let main = threading.call_method0("main_thread")?.getattr("ident")?;
        PyResult::Ok((
            main.extract::<u64>()?,
            [
                signal.getattr("getsignal")?.unbind(),
                signal.getattr("SIGINT")?.unbind(),
                signal.getattr("default_int_handler")?.unbind(),
            ],
        ))
    })?;
    if sigint::thread_ident() != *main {
        return Ok(false);
    }
    Ok(getsignal.call1(py, (sigint,))?.is(default))
}

/// The C-level SIGINT handler for a job's duration (unix).
#[cfg(unix)]
mod sigint {
    use crawlopt::progress::Cancel;
    use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};

    /// The running job's token flag (null between jobs).
    static FLAG: AtomicPtr<AtomicBool> = AtomicPtr::new(std::ptr::null_mut());
    /// Whether a SIGINT arrived during the job.
    static SEEN: AtomicBool = AtomicBool::new(false);

    extern "C" fn on_sigint(_: libc::c_int) {
        SEEN.store(true, Ordering::SeqCst);
        let flag = FLAG.load(Ordering::SeqCst);
        if !flag.is_null() {
            // SAFETY: FLAG points into the token of the job that installed this handler, which
            // outlives it: `Guard::restore` clears FLAG before the token can be dropped.
            unsafe { (*flag).store(true, Ordering::SeqCst) };
        }
    }

    /// This thread's identity as Python's `threading.get_ident()` gives it (`pthread_self`).
    pub fn thread_ident() -> u64 {
        // SAFETY: pthread_self cannot fail.
        unsafe { libc::pthread_self() as u64 }
    }

    /// The handler installed, with what it replaced.
    pub struct Guard {
        previous: libc::sigaction,
        previous_flag: *mut AtomicBool,
        previous_seen: bool,
    }

    impl Guard {
        /// Installs the handler for `cancel`'s job; `None` if the system refused.
        pub fn install(cancel: &Cancel) -> Option<Guard> {
            let previous_flag = FLAG.swap(
                cancel.flag() as *const AtomicBool as *mut AtomicBool,
                Ordering::SeqCst,
            );
            let previous_seen = SEEN.swap(false, Ordering::SeqCst);
            // SAFETY: plain sigaction calls with zero-initialised structs; the handler only
            // does atomic stores.
            unsafe {
                let mut action: libc::sigaction = std::mem::zeroed();
                action.sa_sigaction = on_sigint as extern "C" fn(libc::c_int) as usize;
                libc::sigemptyset(&mut action.sa_mask);
                let mut previous: libc::sigaction = std::mem::zeroed();
                if libc::sigaction(libc::SIGINT, &action, &mut previous) != 0 {
                    FLAG.store(previous_flag, Ordering::SeqCst);
                    SEEN.store(previous_seen, Ordering::SeqCst);
                    return None;
                }
                Some(Guard {
                    previous,
                    previous_flag,
                    previous_seen,
                })
            }
        }

        /// Puts the previous handler back; if a SIGINT arrived meanwhile, raises it again
        /// (now for Python's handler) and says so.
        pub fn restore(self) -> bool {
            // SAFETY: restores the action saved by `install`.
            unsafe { libc::sigaction(libc::SIGINT, &self.previous, std::ptr::null_mut()) };
            FLAG.store(self.previous_flag, Ordering::SeqCst);
            let seen = SEEN.swap(self.previous_seen, Ordering::SeqCst);
            if seen {
                // SAFETY: raising a signal whose handler is Python's own.
                unsafe { libc::raise(libc::SIGINT) };
            }
            seen
        }
    }
}

/// Without unix signals a job is not interrupted by Ctrl-C.
#[cfg(not(unix))]
mod sigint {
    use crawlopt::progress::Cancel;

    pub struct Guard;

    pub fn thread_ident() -> u64 {
        0
    }

    impl Guard {
        pub fn install(_: &Cancel) -> Option<Guard> {
            None
        }
        pub fn restore(self) -> bool {
            false
        }
    }
}

/// An event as a JSON object for Python: `kind` and its fields, `seconds` since the job began.
fn event_json(e: &Event, seconds: f64) -> String {
    use serde_json::json;
    let v = match e {
        Event::Stage(s) => json!({"kind": "stage", "text": s}),
        Event::Note(s) => json!({"kind": "note", "text": s}),
        Event::PhaseSolved { step, start } => json!({
            "kind": "phase", "start": start, "K": step.phases, "objective": step.objective,
            "bound": step.bound, "gap": step.gap, "seconds_of_step": step.seconds,
        }),
        Event::DiscreteSolved(row) => json!({
            "kind": "discrete", "m": row.m, "objective": row.objective, "bound": row.bound,
            "gap": row.gap, "seconds_of_step": row.seconds,
        }),
        Event::ChainSweep(st) => json!({
            "kind": "chain", "sweep": st.sweep, "step": st.step, "objective": st.objective,
            "simulations": st.evaluations, "seconds_of_step": st.seconds,
        }),
        Event::Milp(p) => json!({
            "kind": "milp", "incumbent": p.incumbent, "bound": p.bound,
            "seconds_of_step": p.seconds,
        }),
    };
    let mut v = v;
    v["seconds"] = json!(seconds);
    crawlopt::io::json::to_string(&v).expect("serialisable")
}
