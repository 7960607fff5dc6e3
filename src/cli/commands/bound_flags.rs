//! The flags of `optimize --bound`: an upper bound over all periodic gaits
//! (`crawlopt::certify::bound`), its grid and time limit; defaults are the library's.

use crate::parse::count;
use clap::Args;
use crawlopt::certify::bound::BoundSettings;
use crawlopt::Error;

/// Each argument has an id of its own (`bound_*`): flattened into `optimize`, whose own
/// `--time-limit` is the field `time_limit`, a shared id let `--bound-time-limit` set the
/// optimiser's time limit (and go unchecked without `--bound`).
#[derive(Args, Debug)]
pub struct BoundArgs {
    /// Also prove an upper bound on J over all periodic gaits (no limit on slip phases;
    /// N <= 4), recorded as "certificate.upper_bound" with the method and grid.
    #[arg(long)]
    pub bound: bool,
    /// Grid steps across C's widest link-force range [default: 8 up to three
    /// blocks, 2 on four].
    #[arg(id = "bound_resolution", long = "bound-resolution", value_name = "R", allow_negative_numbers = true, value_parser = count)]
    pub resolution: Option<usize>,
    /// Grid steps across each actuator-length range [default: 8 up to three
    /// blocks, 1 on four].
    #[arg(id = "bound_box_resolution", long = "bound-box-resolution", value_name = "R", allow_negative_numbers = true, value_parser = count)]
    pub box_resolution: Option<usize>,
    /// Time limit of the bound's LP, seconds [default: 60].
    #[arg(
        id = "bound_time_limit",
        long = "bound-time-limit",
        value_name = "S",
        allow_hyphen_values = true
    )]
    pub time_limit: Option<f64>,
    /// With a quadratic cost: tangents per link of its piecewise-linear under-estimator
    /// [default: 4 up to three blocks, 2 on four].
    #[arg(id = "bound_cost_tangents", long = "bound-cost-tangents", value_name = "M", allow_negative_numbers = true, value_parser = count)]
    pub cost_tangents: Option<usize>,
}

impl BoundArgs {
    /// The library's settings, or `None` without `--bound` (the grid flags need it).
    pub fn settings(&self) -> Result<Option<BoundSettings>, Error> {
        if !self.bound {
            if self.resolution.is_some()
                || self.box_resolution.is_some()
                || self.time_limit.is_some()
                || self.cost_tangents.is_some()
            {
                let flag = [
                    (self.resolution.is_some(), "--bound-resolution"),
                    (self.box_resolution.is_some(), "--bound-box-resolution"),
                    (self.time_limit.is_some(), "--bound-time-limit"),
                    (self.cost_tangents.is_some(), "--bound-cost-tangents"),
                ]
                .into_iter()
                .find_map(|(given, flag)| given.then_some(flag))
                .expect("one is given");
                return Err(Error::invalid(
                    flag,
                    "given",
                    "the --bound-* flags need --bound",
                ));
            }
            return Ok(None);
        }
        Ok(Some(BoundSettings {
            resolution: self.resolution,
            box_resolution: self.box_resolution,
            time_limit: self.time_limit,
            cost_tangents: self.cost_tangents,
        }))
    }
}
