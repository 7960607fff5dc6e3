//! Cancellation and in-solve progress through the library's hooks: a long MILP stops within a
//! HiGHS callback of the token being tripped, a simulation between periods, and a MILP reports
//! its incumbent and bound while it runs, in the user's units.

use crawlopt::api::{self, Event, GaitMethod, Hooks, OptimizeSettings};
use crawlopt::integrate::{Actuation, SimOptions, Waveform};
use crawlopt::optimal::{Cost, GaitProblem};
use crawlopt::progress::{Cancel, MilpProgress};
use crawlopt::{Crawler, Error};
use std::time::{Duration, Instant};

/// Runs `optimize` on another thread, trips the token after `after`, and returns the answer
/// and the seconds from the trip to the answer.
fn cancelled_after(
    c: &Crawler,
    p: &GaitProblem,
    s: &OptimizeSettings,
    after: Duration,
) -> (Result<api::Optimized, Error>, f64) {
    let cancel = Cancel::new();
    std::thread::scope(|scope| {
        let job = scope.spawn(|| {
            let hooks = Hooks {
                events: None,
                cancel: Some(&cancel),
            };
            let r = api::optimize(c, p, s, hooks);
            (r, Instant::now())
        });
        std::thread::sleep(after);
        let tripped = Instant::now();
        cancel.cancel();
        let (r, done) = job.join().unwrap();
        (r, done.saturating_duration_since(tripped).as_secs_f64())
    })
}

#[test]
fn a_long_milp_stops_promptly_when_cancelled() {
    // Six blocks, mu- = 1.63: the 4-phase MILP does not close within 60 s on the 2-core
    // machine (issue 16's measurement), so only the interrupt can end it within seconds.
    let c = Crawler::uniform(6, 1.0, 1.0, 1.63).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0; 5], Cost::None, None).unwrap();
    let s = OptimizeSettings {
        method: GaitMethod::Phase,
        phases: Some(4),
        time_limit: Some(120.0),
        ..Default::default()
    };
    let (r, latency) = cancelled_after(&c, &p, &s, Duration::from_secs(2));
    assert_eq!(r.err(), Some(Error::Cancelled));
    // Within a callback: well under a second on an idle machine; generous for a busy CI.
    assert!(latency < 3.0, "stopped {latency:.2} s after the trip");
}

#[test]
fn a_simulation_stops_between_periods_when_cancelled() {
    let c = Crawler::uniform(3, 1.0, 1.0, 3.0).unwrap();
    let act = Actuation::wave(
        Waveform::Sine,
        1.0,
        vec![0.0; 2],
        vec![2.0; 2],
        vec![0.0, 90.0],
    )
    .unwrap();
    let cancel = Cancel::new();
    cancel.cancel();
    let hooks = Hooks {
        events: None,
        cancel: Some(&cancel),
    };
    let r = api::simulate(&c, &act, &SimOptions::default(), hooks);
    assert_eq!(r.err(), Some(Error::Cancelled));
    // Without a token the same simulation runs (1.914213562 per period, the README's example).
    let s = api::simulate(&c, &act, &SimOptions::default(), Hooks::default()).unwrap();
    assert!((s.displacement_per_period.unwrap() - 1.914213562).abs() < 1e-9);
}

#[test]
fn a_running_milp_reports_its_incumbent_and_bound() {
    // Four blocks, mu- = 1.5, period 10, a = 1, 3 slip phases: a MILP of a few seconds, with
    // improving solutions along the way.
    let c = Crawler::uniform(4, 1.0, 1.0, 1.5).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0; 3], Cost::None, None).unwrap();
    let s = OptimizeSettings {
        method: GaitMethod::Phase,
        phases: Some(3),
        ..Default::default()
    };
    let mut seen: Vec<MilpProgress> = Vec::new();
    let mut on = |e: &Event, _: f64| {
        if let Event::Milp(m) = e {
            seen.push(*m)
        }
    };
    let hooks = Hooks {
        events: Some(&mut on),
        cancel: None,
    };
    let r = api::optimize(&c, &p, &s, hooks).unwrap().result;
    let incumbents: Vec<f64> = seen.iter().filter_map(|m| m.incumbent).collect();
    assert!(!incumbents.is_empty(), "no incumbent reported: {seen:?}");
    for m in &seen {
        if let (Some(i), Some(b)) = (m.incumbent, m.bound) {
            assert!(i <= b + 1e-9 * b.abs().max(1.0), "{m:?}");
        }
    }
    // The last incumbent is the MILP's optimum, in the user's units: the solver's objective of
    // the result (which the simulation then verifies).
    let last = *incumbents.last().unwrap();
    assert!(
        (last - r.solver_objective).abs() <= 1e-6 * r.solver_objective.abs().max(1.0),
        "last incumbent {last}, solver objective {}",
        r.solver_objective
    );
}
