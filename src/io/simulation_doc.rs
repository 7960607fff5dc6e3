//! The document of a simulation of either kind (`crawlopt simulate --json`, the summary of
//! Python's `simulate`): one envelope, as every optimisation answer has one
//! ([`crate::optimal::envelope`]), over the kind's own fields.
//!
//! - `format` ([`SIMULATION_FORMAT`]) and `version` ([`SIMULATION_VERSION`]);
//! - `kind`: `"crawler"` or `"general"`;
//! - `objective`: `J` of one period of the periodic regime, `None` (JSON `null`) where it was
//!   not reached. For a general problem it is `int f1 - f2` over the period (paper eq. (2.3));
//!   for a crawler, its instance of (P) with no actuation cost (`f2 = 0`: `simulate` plays an
//!   actuation, not a gait problem), so it is the displacement per period;
//! - then the kind's fields, unchanged: a crawler's [`Simulation`] (its
//!   `displacement_per_period`, blocks' displacements, orbit, trajectory), a general problem's
//!   [`GeneralSimulated`] (its input and `simulation` section).

use super::GeneralSimulated;
use crate::integrate::Simulation;
use serde::Serialize;

/// `format` of a simulation's document.
pub const SIMULATION_FORMAT: &str = "crawlopt-simulation";

/// `version` of a simulation's document (1: the first with an envelope).
pub const SIMULATION_VERSION: u32 = 1;

/// A simulation's document (module docs): the envelope, then the kind's fields.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SimulationDocument<'a> {
    /// Always [`SIMULATION_FORMAT`].
    pub format: &'static str,
    /// Always [`SIMULATION_VERSION`].
    pub version: u32,
    /// The kind and its fields.
    #[serde(flatten)]
    pub body: SimulationBody<'a>,
}

/// The kind's part of a [`SimulationDocument`].
#[derive(Debug, Clone, Copy, Serialize)]
#[serde(untagged)]
pub enum SimulationBody<'a> {
    /// A crawler's simulation, with its `kind` and `objective` in front.
    Crawler {
        /// `"crawler"`.
        kind: &'static str,
        /// The displacement per period (module docs).
        objective: Option<f64>,
        /// The simulation.
        #[serde(flatten)]
        simulation: &'a Simulation,
    },
    /// A general problem's simulation (it has its `kind` and `objective`).
    General(&'a GeneralSimulated),
}

impl<'a> SimulationDocument<'a> {
    /// The document of a crawler's simulation.
    pub fn crawler(simulation: &'a Simulation) -> Self {
        Self::of(SimulationBody::Crawler {
            kind: "crawler",
            objective: simulation.displacement_per_period,
            simulation,
        })
    }

    /// The document of a general problem's simulation.
    pub fn general(answer: &'a GeneralSimulated) -> Self {
        Self::of(SimulationBody::General(answer))
    }

    fn of(body: SimulationBody<'a>) -> Self {
        SimulationDocument {
            format: SIMULATION_FORMAT,
            version: SIMULATION_VERSION,
            body,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::{Actuation, SimOptions, Waveform};
    use crate::model::Crawler;

    /// The envelope comes first, the crawler's fields follow unchanged, and `objective` is the
    /// displacement per period: `max(0, 2A - 2) = 4` for one link of `k = 1`, `mu+ = 1`,
    /// `mu- = 2` under a sine of amplitude 3 (theory §10).
    #[test]
    fn a_crawlers_document_has_the_envelope_and_its_fields() {
        let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
        let a = Actuation::wave(Waveform::Sine, 1.0, vec![0.0], vec![3.0], vec![0.0]).unwrap();
        let s = crate::integrate::simulate(&c, &a, &SimOptions::DEFAULT).unwrap();
        let text = serde_json::to_string(&SimulationDocument::crawler(&s)).unwrap();
        assert!(
            text.starts_with(r#"{"format":"crawlopt-simulation","version":1,"kind":"crawler","#),
            "{}",
            &text[..80]
        );
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let d = v["displacement_per_period"].as_f64().unwrap();
        assert_eq!(v["objective"].as_f64(), Some(d));
        assert!((d - 4.0).abs() < 1e-9, "{d}");
        assert_eq!(v["method"], "exact");
    }
}
