//! Running a job off the GIL and cancellable by Ctrl-C.
//!
//! The job runs on a worker thread with a `Cancel` token and an observer that forwards its
//! events over a channel. The calling thread waits in slices of [`SLICE`] with the GIL
//! released, hands the events to the Python callable `progress` (as JSON text) with the GIL
//! held, and checks for signals between slices: on KeyboardInterrupt it trips the token, waits
//! for the worker (which stops at its next check, inside a running MILP through HiGHS's
//! callback) and raises KeyboardInterrupt.

use crate::errors;
use crawlopt::api::{Event, Hooks};
use crawlopt::progress::Cancel;
use pyo3::prelude::*;
use std::sync::mpsc;
use std::time::Duration;

/// How long the calling thread waits without the GIL before it looks for signals.
const SLICE: Duration = Duration::from_millis(50);

/// Runs `job` (given the hooks) on a worker thread; see the module docs.
pub fn run<T: Send>(
    py: Python<'_>,
    progress: Option<PyObject>,
    job: impl FnOnce(Hooks<'_>) -> crawlopt::Result<T> + Send,
) -> PyResult<T> {
    let cancel = Cancel::new();
    let watching = progress.is_some();
    let (tx, rx) = mpsc::channel::<String>();
    std::thread::scope(|scope| {
        let cancel_ref = &cancel;
        let worker = scope.spawn(move || {
            let mut send = |e: &Event, t: f64| {
                let _ = tx.send(event_json(e, t));
            };
            // Without a callback no event is sent (each would wake the waiting thread).
            let hooks = Hooks {
                events: if watching { Some(&mut send) } else { None },
                cancel: Some(cancel_ref),
            };
            job(hooks)
        });
        let mut interrupted: Option<PyErr> = None;
        let mut rx = rx;
        loop {
            // The receiver is moved into the GIL-free wait and back (it is Send, not Sync).
            let (back, got) = py.allow_threads(move || {
                let got = rx.recv_timeout(SLICE);
                (rx, got)
            });
            rx = back;
            match got {
                Ok(text) => {
                    if let Some(f) = &progress {
                        if let Err(e) = f.call1(py, (text,)) {
                            // A failing progress callback stops the job and is raised.
                            cancel.cancel();
                            interrupted.get_or_insert(e);
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    cancel.cancel();
                    interrupted = Some(e);
                }
            }
        }
        let answer = py.allow_threads(|| worker.join());
        if let Some(e) = interrupted {
            return Err(e);
        }
        match answer {
            Ok(Ok(v)) => Ok(v),
            Ok(Err(e)) => Err(errors::to_py(py, e)),
            Err(_) => Err(errors::NumericalError::new_err(
                "internal error: the job panicked (please report it)",
            )),
        }
    })
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
        Event::Milp(p) => json!({
            "kind": "milp", "incumbent": p.incumbent, "bound": p.bound,
            "seconds_of_step": p.seconds,
        }),
    };
    let mut v = v;
    v["seconds"] = json!(seconds);
    v.to_string()
}
