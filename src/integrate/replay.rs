//! The motion of a crawler under a recorded actuation, once, from a given state: what a fitted
//! model predicts for a measured trajectory (not a periodic regime).

use super::{Actuation, ExactPwl, PeriodMap, Recorder, Trajectory};
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::sweep::Projector;

/// Block positions at `times` of `crawler` driven by the actuator lengths `lengths` (one row
/// per time, linear in between), from the state `x0` (link compressions, force units; projected
/// onto C first, so a measured state a little outside C is accepted) and the positions `start`
/// at `times[0]`. Exact: the actuation is piecewise linear, integrated by the event-driven
/// method (theory §4).
pub fn replay(
    crawler: &Crawler,
    times: &[f64],
    lengths: &[Vec<f64>],
    x0: &[f64],
    start: &[f64],
) -> Result<Vec<Vec<f64>>> {
    let (n, nb, m) = (crawler.links(), crawler.blocks(), times.len());
    if m < 2 || lengths.len() != m || x0.len() != n || start.len() != nb {
        return Err(Error::invalid(
            "replay",
            format!("{m} times"),
            "needs at least 2 times, one row of lengths per time, a state and start positions",
        ));
    }
    // One "period" covering the record; the closing phase back to L(t_0) runs after the last
    // time and is not read.
    let local: Vec<f64> = times.iter().map(|t| t - times[0]).collect();
    let period = local[m - 1] + (local[m - 1] - local[m - 2]);
    let act = Actuation::piecewise_linear(period, local.clone(), lengths.to_vec())?;
    let mut map = ExactPwl::new(crawler, &act, 0)?;
    let mut proj = Projector::new(crawler)?;
    let (mut x, mut scratch) = (vec![0.0; n], vec![0.0; nb]);
    proj.project_from_origin(x0, &mut x, &mut scratch)?;
    let mut traj = Trajectory::default();
    let mut acc = vec![0.0; nb];
    let mut rec = Recorder {
        traj: &mut traj,
        base: start.to_vec(),
        t0: 0.0,
        max_rows: 1000 * m + 100_000,
        overflow: false,
    };
    rec.push(0.0, &x, &acc, std::iter::repeat_n(0, nb));
    map.run_period(&mut x, &mut acc, Some(&mut rec))?;
    if rec.overflow {
        return Err(Error::Numerical(
            "replay: more events than 1000 per sample".into(),
        ));
    }
    // Each phase ends with a record at its knot: the last record at or before each time.
    let tol = 1e-12 * period;
    let mut out = Vec::with_capacity(m);
    let mut r = 0;
    for &tau in &local {
        while r + 1 < traj.t.len() && traj.t[r + 1] <= tau + tol {
            r += 1;
        }
        out.push(traj.positions[r].clone());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_link_replay_matches_the_closed_form() {
        // N = 2, k = 1, mu+ = 1 and mu- = 2 on both blocks: stretching L from 0 to 3 from
        // x = 0 compresses the spring, F_2 = x_1 reaches mu+_2 = 1 at L = 1 and the front block
        // slides forward by the remaining 2 while the rear one holds (F_1 = -1 > -mu-_1).
        let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
        let times = [0.0, 1.0, 2.0];
        let lengths = vec![vec![0.0], vec![3.0], vec![3.0]];
        let x = replay(&c, &times, &lengths, &[0.0], &[0.0, 0.0]).unwrap();
        assert!((x[1][1] - 2.0).abs() < 1e-12, "{x:?}");
        assert!(x[1][0].abs() < 1e-12, "{x:?}");
        assert_eq!(x[1], x[2]);
    }
}
