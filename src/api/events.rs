//! Progress of a job as typed events, and the hooks a caller passes: an observer of events and
//! a cancellation token.

use crate::optimal::chain::ChainStep;
use crate::optimal::{ConvergenceRow, PhaseStep, StartEvent};
use crate::progress::{self, Cancel, MilpProgress};
use std::cell::{Cell, RefCell};
use std::time::Instant;

/// One thing that happened in a job, in the order it happened.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// A stage begins (e.g. `solving the 3-phase MILP`, `local LPCC method on P_10 (1024
    /// steps)`).
    Stage(String),
    /// One K of a growth of K was solved: of the certified growth, or of a start gait's
    /// (`start: true`).
    PhaseSolved {
        /// The K, its verified J_K, the MILP's bound, gap, status and seconds.
        step: PhaseStep,
        /// Whether it belongs to the computation of a start gait.
        start: bool,
    },
    /// One P_m of a convergence table was solved.
    DiscreteSolved(ConvergenceRow),
    /// One sweep of the chain method's pattern search ended: its step, the best `J` so far
    /// over the starts searched, the simulations so far.
    ChainSweep(ChainStep),
    /// A running MILP's incumbent and bound (user's units; a maximisation), reported by HiGHS
    /// while it solves, at most a few times a second.
    Milp(MilpProgress),
    /// A note on how the job goes on (e.g. without a start gait, and why). A job that ends in
    /// an error may have sent notes; the error is what explains it.
    Note(String),
}

impl Event {
    /// This event with its values of `J` (objectives, bounds, incumbents) multiplied by
    /// `factor`, for a job run in other units of `J` than its caller's (the crawler's job on a
    /// general problem's chain, whose `J` is `factor` times the crawler's). Gaps are relative
    /// and stay; stages and notes are text and stay.
    fn scaled(mut self, factor: f64) -> Self {
        match &mut self {
            Event::PhaseSolved { step, .. } => {
                step.objective *= factor;
                step.bound *= factor;
            }
            Event::DiscreteSolved(row) => {
                row.objective *= factor;
                row.bound *= factor;
            }
            Event::ChainSweep(s) => s.objective *= factor,
            Event::Milp(p) => {
                p.incumbent = p.incumbent.map(|v| v * factor);
                p.bound = p.bound.map(|v| v * factor);
            }
            Event::Stage(_) | Event::Note(_) => {}
        }
        self
    }
}

/// An observer of a job's events: called with each [`Event`] and the seconds since the job
/// began, on the job's thread.
pub type Observer<'a> = &'a mut dyn FnMut(&Event, f64);

/// What a caller hands a job: an observer of its [`Event`]s and a [`Cancel`] token. Both are
/// optional (`Hooks::default()`: no progress, not cancellable).
#[derive(Default)]
pub struct Hooks<'a> {
    /// Called with each event, on the job's thread, with the seconds since the job began.
    pub events: Option<Observer<'a>>,
    /// Tripped by the caller to stop the job ([`crate::Error::Cancelled`]).
    pub cancel: Option<&'a Cancel>,
}

/// A job's side of its [`Hooks`]: sends events stamped with the elapsed time and keeps the
/// notes for the result. Shared (`&self`) by the job and the MILP progress of the kernels.
pub(crate) struct Emitter<'a> {
    events: RefCell<Option<Observer<'a>>>,
    began: Instant,
    notes: RefCell<Vec<String>>,
    /// The factor of the values of `J` in the events sent ([`Emitter::scaled`]; 1 outside).
    scale: Cell<f64>,
}

impl<'a> Emitter<'a> {
    pub fn new(events: Option<Observer<'a>>) -> Self {
        Emitter {
            events: RefCell::new(events),
            began: Instant::now(),
            notes: RefCell::new(Vec::new()),
            scale: Cell::new(1.0),
        }
    }

    /// Runs `f` with the values of `J` in the events it sends multiplied by `factor` (on top of
    /// the current factor, restored after): a job inside another that states `J` in other
    /// units, so that the caller sees every event in its own.
    pub fn scaled<R>(&self, factor: f64, f: impl FnOnce() -> R) -> R {
        let outer = self.scale.replace(self.scale.get() * factor);
        let r = f();
        self.scale.set(outer);
        r
    }

    /// Sends `e` (and keeps it if it is a note). An event sent from inside the observer itself
    /// is dropped rather than aliased.
    pub fn send(&self, e: Event) {
        let factor = self.scale.get();
        let e = if factor == 1.0 { e } else { e.scaled(factor) };
        if let Event::Note(n) = &e {
            self.notes.borrow_mut().push(n.clone());
        }
        let t = self.began.elapsed().as_secs_f64();
        if let Ok(mut events) = self.events.try_borrow_mut() {
            if let Some(f) = events.as_mut() {
                f(&e, t);
            }
        }
    }

    /// Sends a stage.
    pub fn stage(&self, s: impl Into<String>) {
        self.send(Event::Stage(s.into()));
    }

    /// Translates a start policy's event.
    pub fn start_event(&self, e: StartEvent) {
        self.send(match e {
            StartEvent::Stage(s) => Event::Stage(s.to_string()),
            StartEvent::Phase(st) => Event::PhaseSolved {
                step: st.clone(),
                start: true,
            },
            StartEvent::Note(s) => Event::Note(s.to_string()),
        });
    }

    /// The notes sent so far.
    pub fn notes(&self) -> Vec<String> {
        self.notes.borrow().clone()
    }
}

/// Runs `job` with `hooks`: the cancellation token and the MILP progress reach the kernels
/// through a [`progress`] scope, the rest through the [`Emitter`] the job is given.
pub(crate) fn run_with<R>(hooks: Hooks<'_>, job: impl FnOnce(&Emitter<'_>) -> R) -> R {
    let Hooks { events, cancel } = hooks;
    let em = Emitter::new(events);
    let mut on_milp = |p: &MilpProgress| em.send(Event::Milp(*p));
    progress::scoped(cancel, Some(&mut on_milp), || job(&em))
}
