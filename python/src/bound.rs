//! The upper bound's settings as Python passes them (`bound=`), for both kinds of problem.

use crawlopt::certify::bound::BoundSettings;

/// `optimize`'s bound settings as Python passes them: resolution, box resolution, time limit,
/// cost tangents (each `None` takes the library's default).
pub(crate) type BoundTuple = (Option<usize>, Option<usize>, Option<f64>, Option<usize>);

/// The library's bound settings of Python's tuple, each `None` taking the library's default.
pub(crate) fn bound_settings(bound: Option<BoundTuple>) -> Option<BoundSettings> {
    bound.map(
        |(resolution, box_resolution, time_limit, cost_tangents)| BoundSettings {
            resolution,
            box_resolution,
            time_limit,
            cost_tangents,
        },
    )
}
