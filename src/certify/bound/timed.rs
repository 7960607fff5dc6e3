//! The time-dependent storage function `V(t, x, l)`, built to measure what the module doc of
//! [`super`] proves: on the same spatial grid it gives exactly the bound of the
//! time-independent `V(x, l)`, so it is not offered as an option.
//!
//! `V_k(x, l)`, `k = 0..nt-1` (periodic: `V_nt = V_0`), each piecewise linear on the spatial
//! grid, `V(t, p) = (1 - theta) V_k(p) + theta V_{k+1}(p)` at `t = (k + theta) dt`,
//! `dt = T / nt`. Along a motion `d/dt V = (V_{k+1}(p) - V_k(p)) / dt + <(1 - theta) g_k +
//! theta g_{k+1}, d(u)>`, so the rows are, per row `(S, F, u)` of the time-independent LP, per
//! slab `k`, per `theta in {0, 1}` and per vertex `v` of `S`:
//!
//! ```text
//! rho + (V_{k+1}(v) - V_k(v)) / dt + <g_{k+theta, S}, d(u)> >= y'(u).
//! ```

use super::{prepare, solve_storage_lp, BoundSettings, RowSink, UpperBound};
use crate::error::Result;
use crate::model::Crawler;
use crate::optimal::GaitProblem;
use std::time::Instant;

/// Name of the method in the results of [`time_dependent_bound`].
pub(crate) const TIME_METHOD: &str = "pl-storage-time";

/// The bound from a time-dependent storage function with `nt` time steps per period on the
/// spatial grid of `settings` (module doc); `nt >= 1`.
pub(crate) fn time_dependent_bound(
    crawler: &Crawler,
    problem: &GaitProblem,
    settings: &BoundSettings,
    nt: usize,
) -> Result<UpperBound> {
    let started = Instant::now();
    let level = settings.resolve(crawler)?;
    let pre = prepare(crawler, problem, &level)?;
    let np = pre.grid.nodes();
    let nt = nt.max(1);
    let inv_dt = nt as f64 / problem.period;
    let rows = |sink: &mut RowSink| {
        let mut cols = Vec::new();
        let mut cs = Vec::new();
        pre.grid
            .for_each_row(crawler, &pre.motions, pre.tol, |nodes, coefs, y| {
                for k in 0..nt {
                    let next = (k + 1) % nt;
                    for slab in [k, next] {
                        for &v in nodes {
                            cols.clear();
                            cs.clear();
                            cols.extend(nodes.iter().map(|&p| p + slab * np));
                            cs.extend_from_slice(coefs);
                            cols.extend([v + next * np, v + k * np]);
                            cs.extend([inv_dt, -inv_dt]);
                            sink(&cols, &cs, y);
                        }
                    }
                }
            });
    };
    let lp = crate::progress::within(Some(level.time_limit), || {
        solve_storage_lp(nt * np, &rows, &|n| level.too_many_rows(n))
    })?;
    Ok(UpperBound {
        method: TIME_METHOD.to_string(),
        resolution: level.resolution,
        box_resolution: level.box_resolution,
        cost_tangents: super::cost_tangents(problem, &level),
        value: lp.rate * problem.period,
        status: lp.status,
        aligned: pre.aligned,
        rows: lp.rows,
        columns: lp.columns,
        seconds: started.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certify::bound::{upper_bound_on_grid as upper_bound, BoundStatus};
    use crate::optimal::Cost;

    fn settings(resolution: usize, box_resolution: usize) -> BoundSettings {
        BoundSettings {
            resolution: Some(resolution),
            box_resolution: Some(box_resolution),
            time_limit: Some(600.0),
            ..BoundSettings::default()
        }
    }

    fn problem(c: &Crawler, period: f64, rate: f64) -> GaitProblem {
        GaitProblem::new(c, period, &vec![rate; c.links()], Cost::None, None).unwrap()
    }

    /// The module doc of `certify::bound`: time dependence cannot lower the bound of an
    /// autonomous problem on the same spatial grid. Were the telescoping argument wrong, the
    /// time-dependent LP (a different LP, more columns, other rows) would come out lower.
    #[test]
    fn time_dependence_gives_the_same_bound() {
        let cases = [
            (Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap(), 1.0, 8, 8, 4),
            // C = [-1, 0.75] is not tiled by the grid, k = 2.
            (
                Crawler::new(vec![2.0], vec![1.0, 0.75], vec![2.0, 1.5]).unwrap(),
                1.5,
                8,
                4,
                3,
            ),
            (Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap(), 1.0, 5, 1, 2),
        ];
        for (c, rate, r, rb, nt) in cases {
            let p = problem(&c, 10.0, rate);
            let s = settings(r, rb);
            let plain = upper_bound(&c, &p, &s).unwrap();
            let timed = time_dependent_bound(&c, &p, &s, nt).unwrap();
            assert_eq!(plain.status, BoundStatus::Optimal);
            assert_eq!(timed.status, BoundStatus::Optimal);
            assert_eq!(timed.rows, plain.rows * nt * 2 * (2 * c.links() + 1));
            assert!(
                (timed.value - plain.value).abs() <= 1e-5 * plain.value,
                "N = {}, {r} x {rb}, nt = {nt}: time-dependent {} against {}",
                c.blocks(),
                timed.value,
                plain.value
            );
        }
    }

    /// The table of the README: `BOUND_TIME_CASES="2:8:8:4 3:5:2:2"` (blocks:R:box R:time
    /// steps) on the reference crawlers, `cargo test --release --lib certify::bound::timed --
    /// --ignored --nocapture`.
    #[test]
    #[ignore]
    fn measure_time_dependent() {
        let cases = std::env::var("BOUND_TIME_CASES").unwrap_or_else(|_| "2:8:8:2".into());
        for case in cases.split_whitespace() {
            let v: Vec<usize> = case.split(':').map(|s| s.parse().unwrap()).collect();
            let (nb, r, rb, nt) = (v[0], v[1], v[2], v[3]);
            let mu_back = if nb == 2 { 2.0 } else { 1.5 };
            let c = Crawler::uniform(nb, 1.0, 1.0, mu_back).unwrap();
            let p = problem(&c, 10.0, 1.0);
            let s = settings(r, rb);
            let plain = upper_bound(&c, &p, &s).unwrap();
            let timed = time_dependent_bound(&c, &p, &s, nt).unwrap();
            println!(
                "N={nb} r={r} rb={rb} nt={nt}: time-independent {:.6} ({} rows, {:.2} s, \
                 {:?}); time-dependent {:.6} ({} rows, {:.2} s, {:?})",
                plain.value,
                plain.rows,
                plain.seconds,
                plain.status,
                timed.value,
                timed.rows,
                timed.seconds,
                timed.status
            );
        }
    }
}
