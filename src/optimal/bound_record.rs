//! The record of a proven upper bound on `J` (theory §12): what a gait result carries and the
//! consistency check reads. The bound itself is computed in `certify::bound`, which re-exports
//! these names; the record lives here, beside the results that hold it, so that the optimal
//! layer does not import from the certificates' layer above it.

use serde::{Deserialize, Serialize};

/// Name of the method in results.
pub const METHOD: &str = "pl-storage";

/// How the LP ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundStatus {
    /// The LP was solved: the bound is the best this grid gives.
    Optimal,
    /// The time limit stopped the LP: the bound holds but a finished solve would lower it.
    TimeLimit,
}

/// A proven upper bound on `J` over all `T`-periodic gaits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UpperBound {
    /// The method ([`METHOD`]).
    pub method: String,
    /// `x` grid steps across C's widest link-force range.
    pub resolution: usize,
    /// Grid steps across each actuator-length range.
    pub box_resolution: usize,
    /// Tangents per link of the quadratic cost's under-estimator (0: the problem has no cost).
    #[serde(default)]
    pub cost_tangents: usize,
    /// The bound on the displacement per period, `rho T`.
    pub value: f64,
    /// How the LP ended.
    pub status: BoundStatus,
    /// Whether the grid tiles C exactly (all thresholds multiples of the step).
    pub aligned: bool,
    /// LP size: rows (simplex, face, control vertex) of the primal.
    pub rows: usize,
    /// LP columns of the primal (node values and `rho`).
    pub columns: usize,
    /// Wall-clock seconds (grid, LP and re-evaluation).
    pub seconds: f64,
}

impl UpperBound {
    /// Refuses a bound just proven below the verified `j` it must bound (beyond `1e-9` of `j`
    /// or of `floor`, the problem's floor of `J`), or NaN: a defect of the bound, never an
    /// answer. The one check of every optimiser that proves a bound, crawler or (P).
    pub fn check_bounds(&self, j: f64, floor: f64) -> crate::error::Result<()> {
        if self.value.is_nan() || self.value < j - 1e-9 * j.abs().max(floor) {
            return Err(crate::Error::Numerical(format!(
                "upper bound {} below the verified J {j}: a defect of the bound",
                self.value
            )));
        }
        Ok(())
    }

    /// How far a gait of objective `j` can be from the best periodic gait, as a fraction of the
    /// bound: `(value - j) / value`, and 0 when the two agree to `1e-9` of `scale` (the
    /// problem's length scale) or of themselves: a bound of `7.5e-12` over `J = 0` (a crawler
    /// that cannot move) is the LP's rounding of 0, not a gap of 100 %.
    pub fn within(&self, j: f64, scale: f64) -> f64 {
        let close = 1e-9 * scale.abs().max(self.value.abs()).max(j.abs());
        if self.value - j <= close || self.value <= 0.0 {
            0.0
        } else {
            (self.value - j) / self.value
        }
    }

    /// Checks a recorded bound against the verified `j` it bounds, as a result file is read
    /// back (`what` names the file in errors): taken as recorded (its LP is not re-solved), but
    /// it must be by [`METHOD`] and a finite value at least `j` (or `close` to it).
    pub fn check_recorded(
        &self,
        what: &str,
        j: f64,
        close: impl Fn(f64, f64) -> bool,
    ) -> crate::error::Result<()> {
        let bad = |field: &str, got: String, reason: String| {
            crate::Error::invalid(
                format!("{what}: certificate.upper_bound.{field}"),
                got,
                reason,
            )
        };
        if self.method != METHOD {
            return Err(bad(
                "method",
                self.method.clone(),
                format!("the method is \"{METHOD}\""),
            ));
        }
        if !(self.value.is_finite() && (self.value >= j || close(self.value, j))) {
            return Err(bad(
                "value",
                self.value.to_string(),
                format!("is below the verified objective {j}"),
            ));
        }
        Ok(())
    }

    /// The resolution that gave the bound, as the text and the report print it:
    /// `"R x R'"`, with `", M cost tangents"` when a quadratic cost entered through tangents.
    pub fn resolution_text(&self) -> String {
        let mut s = format!("{} x {}", self.resolution, self.box_resolution);
        if self.cost_tangents > 0 {
            s.push_str(&format!(", {} cost tangents", self.cost_tangents));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bound(value: f64) -> UpperBound {
        UpperBound {
            method: METHOD.into(),
            resolution: 2,
            box_resolution: 2,
            cost_tangents: 0,
            value,
            status: BoundStatus::Optimal,
            aligned: true,
            rows: 1,
            columns: 1,
            seconds: 0.0,
        }
    }

    /// The gap is relative to the bound, and 0 where bound and `J` agree to rounding: a crawler
    /// that cannot move (`J = 0`) under an LP bound of 7.5e-12 is optimal, not 100 % away.
    #[test]
    fn the_gap_is_zero_where_bound_and_j_agree_to_rounding() {
        assert_eq!(bound(7.5e-12).within(0.0, 5.0), 0.0);
        assert_eq!(bound(0.0).within(0.0, 5.0), 0.0);
        assert!((bound(4.0).within(3.0, 5.0) - 0.25).abs() < 1e-15);
        assert!((bound(1e-3).within(0.0, 5.0) - 1.0).abs() < 1e-15);
    }
}
