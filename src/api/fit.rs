//! The identification job: a measured trajectory in, the fitted crawler with its intervals out
//! ([`crate::fit`]).

use super::events::{run_with, Hooks};
use crate::error::Result;
use crate::fit::{FitData, FitResult, FitSettings};

/// Fits a crawler to `data` under `settings` ([`crate::fit::fit`]: least absolute deviations
/// for the estimate, LPs for the exact intervals, the fitted crawler re-simulated against the
/// data). Stages go to the hooks' observer; the token stops the job between (and inside) its
/// LPs with [`crate::Error::Cancelled`].
pub fn fit(data: &FitData, settings: &FitSettings, hooks: Hooks<'_>) -> Result<FitResult> {
    run_with(hooks, |em| {
        crate::progress::check()?;
        em.stage(format!(
            "fitting {} blocks to {} samples",
            data.blocks(),
            data.samples()
        ));
        let r = crate::fit::fit(data, settings)?;
        for w in &r.warnings {
            em.send(super::Event::Note(w.clone()));
        }
        Ok(r)
    })
}
