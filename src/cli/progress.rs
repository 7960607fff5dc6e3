//! Progress of a job on stderr: the library's events on an indicatif spinner with the elapsed
//! time (hidden when stderr is not a terminal); its notes printed once the job has succeeded.

use crawlopt::api::Event;
use crawlopt::present::text::{num, phase_step};

/// A spinner showing a job's events.
pub struct Spinner {
    bar: indicatif::ProgressBar,
    /// The current stage, to which a running MILP's incumbent and bound are appended.
    stage: String,
    /// The length scale of the problem, for the values shown.
    length: f64,
}

impl Spinner {
    /// A spinner for a problem whose lengths have the scale `length`.
    pub fn new(length: f64) -> Self {
        let bar = indicatif::ProgressBar::new_spinner();
        bar.set_style(
            indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .expect("valid template"),
        );
        bar.enable_steady_tick(std::time::Duration::from_millis(200));
        Spinner {
            bar,
            stage: String::new(),
            length,
        }
    }

    /// Shows one event.
    pub fn show(&mut self, e: &Event) {
        let n = |v: f64| num(v, self.length);
        let stage = match e {
            Event::Stage(s) => s.clone(),
            Event::PhaseSolved { step, start: false } => phase_step(step, self.length),
            Event::PhaseSolved { step, start: true } => {
                format!("start: phase gait, {}", phase_step(step, self.length))
            }
            Event::DiscreteSolved(row) => format!(
                "m = {}: J = {} (gap {:.1e}, {:.2} s); m = {} next",
                row.m,
                n(row.objective),
                row.gap,
                row.seconds,
                row.m + 1
            ),
            Event::ChainSweep(st) => format!(
                "chain pattern search: sweep {}, step {}, best J = {} ({} simulations)",
                st.sweep,
                st.step,
                n(st.objective),
                st.evaluations
            ),
            Event::Note(s) => format!("note: {s}"),
            Event::Milp(p) => {
                let incumbent = p.incumbent.map_or("none".into(), n);
                let bound = p.bound.map_or("none".into(), n);
                let msg = format!("{} (incumbent J = {incumbent}, bound {bound})", self.stage);
                self.bar.set_message(msg);
                return;
            }
        };
        self.bar.set_message(stage.clone());
        self.stage = stage;
    }

    /// Clears the spinner and prints the job's notes.
    pub fn finish(&self, notes: &[String]) {
        self.bar.finish_and_clear();
        for msg in notes {
            eprintln!("note: {msg}");
        }
    }
}
