//! The increments of catching-up, `h u^i = K (L(t_{i+1}) - L(t_i))` at `t_i = i T / m` with
//! `L(t_m) = L(t_0)` exactly (theory §4): held as a table for the whole period, or formed step by
//! step from the actuation so that a period needs `O(N)` memory whatever `m`.
//!
//! Both give bitwise the same increments (the same samples, the same arithmetic), so the choice
//! changes the memory and the time of a step, never a result.

use super::Actuation;
use crate::error::Result;
use serde::Serialize;

/// How catching-up holds the increments of a period.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IncrementStorage {
    /// A table of the period's increments, 8 bytes per link and step, read row by row.
    Stored,
    /// Formed at every step from the actuation: one evaluation of every link's length per step,
    /// `O(N)` memory.
    Streamed,
}

impl IncrementStorage {
    /// Default of [`super::SimOptions::increment_budget`]: the table is kept when it takes at
    /// most 64 MiB (8 MB at 1000 links and 1000 steps; 10^4 links stream).
    pub const DEFAULT_BUDGET: usize = 64 << 20;

    /// `Stored` when the table of `links x steps` increments fits in `budget` bytes,
    /// `Streamed` otherwise.
    pub fn within(budget: usize, links: usize, steps: usize) -> Self {
        let bytes = (links as u128) * (steps as u128) * 8;
        if bytes <= budget as u128 {
            IncrementStorage::Stored
        } else {
            IncrementStorage::Streamed
        }
    }
}

/// The increments of one period, row `i` being step `i`.
#[derive(Debug, Clone)]
pub(super) enum Increments {
    /// Row-major `m x n`.
    Stored {
        table: Vec<f64>,
        n: usize,
    },
    Streamed(Stream),
}

/// Samples of the actuation two at a time: `lo = L(t_i)` while row `i` is next.
#[derive(Debug, Clone)]
pub(super) struct Stream {
    act: Actuation,
    k: Vec<f64>,
    m: usize,
    /// `L(t_0)`, also `L(t_m)`.
    first: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    delta: Vec<f64>,
    /// The row `lo` is the start of.
    next: usize,
}

/// `t_i = (i / m) T`, as every sampler of the period writes it.
fn sample_time(i: usize, m: usize, period: f64) -> f64 {
    (i as f64 / m as f64) * period
}

impl Increments {
    /// The increments of `act` on `m` steps with stiffness `k`, held as `storage` says.
    /// Refuses increments that overflow double precision (the streamed ones are checked by one
    /// pass over the period here).
    pub(super) fn new(
        act: &Actuation,
        k: &[f64],
        m: usize,
        storage: IncrementStorage,
    ) -> Result<Self> {
        let n = k.len();
        let mut first = vec![0.0; n];
        act.lengths_at(0.0, &mut first);
        let mut stream = Stream {
            act: act.clone(),
            k: k.to_vec(),
            m,
            lo: first.clone(),
            hi: vec![0.0; n],
            delta: vec![0.0; n],
            first,
            next: 0,
        };
        match storage {
            IncrementStorage::Stored => {
                let mut table = Vec::with_capacity(m * n);
                for i in 0..m {
                    table.extend_from_slice(stream.row(i));
                }
                super::check_increments(&table)?;
                Ok(Increments::Stored { table, n })
            }
            IncrementStorage::Streamed => {
                for i in 0..m {
                    super::check_increments(stream.row(i))?;
                }
                Ok(Increments::Streamed(stream))
            }
        }
    }

    /// Given increments (row-major `m x n`), stored.
    pub(super) fn given(table: Vec<f64>, n: usize) -> Result<Self> {
        super::check_increments(&table)?;
        Ok(Increments::Stored { table, n })
    }

    /// Steps per period.
    pub(super) fn steps(&self) -> usize {
        match self {
            Increments::Stored { table, n } => table.len() / n,
            Increments::Streamed(s) => s.m,
        }
    }

    pub(super) fn storage(&self) -> IncrementStorage {
        match self {
            Increments::Stored { .. } => IncrementStorage::Stored,
            Increments::Streamed(_) => IncrementStorage::Streamed,
        }
    }

    /// Bytes held for the increments: the table, or the stream's five vectors of `N`.
    pub(super) fn bytes(&self) -> usize {
        match self {
            Increments::Stored { table, .. } => table.len() * 8,
            Increments::Streamed(s) => 5 * s.k.len() * 8,
        }
    }

    /// The increments of step `i`; streamed rows are cheapest taken in order `0, 1, .., m - 1`.
    pub(super) fn row(&mut self, i: usize) -> &[f64] {
        match self {
            Increments::Stored { table, n } => &table[i * *n..(i + 1) * *n],
            Increments::Streamed(s) => s.row(i),
        }
    }
}

impl Stream {
    fn row(&mut self, i: usize) -> &[f64] {
        let period = self.act.period();
        if i == 0 {
            self.lo.copy_from_slice(&self.first);
        } else if i != self.next {
            self.act
                .lengths_at(sample_time(i, self.m, period), &mut self.lo);
        }
        if i + 1 == self.m {
            self.hi.copy_from_slice(&self.first);
        } else {
            self.act
                .lengths_at(sample_time(i + 1, self.m, period), &mut self.hi);
        }
        for (((d, k), hi), lo) in self
            .delta
            .iter_mut()
            .zip(&self.k)
            .zip(&self.hi)
            .zip(&self.lo)
        {
            *d = k * (hi - lo);
        }
        std::mem::swap(&mut self.lo, &mut self.hi);
        self.next = i + 1;
        &self.delta
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Waveform;

    #[test]
    fn streamed_rows_in_any_order_are_the_stored_rows() {
        let n = 7;
        let phases = (0..n).map(|l| l as f64 * 51.0).collect();
        let act = Actuation::wave(Waveform::Sine, 1.7, vec![0.2; n], vec![1.3; n], phases).unwrap();
        let k: Vec<f64> = (0..n).map(|l| 0.5 + l as f64 / 4.0).collect();
        let m = 13;
        let mut stored = Increments::new(&act, &k, m, IncrementStorage::Stored).unwrap();
        let mut streamed = Increments::new(&act, &k, m, IncrementStorage::Streamed).unwrap();
        assert_eq!((stored.steps(), streamed.steps()), (m, m));
        for i in [0, 1, 2, 12, 5, 6, 0, 12, 11, 3] {
            assert_eq!(stored.row(i), streamed.row(i), "row {i}");
        }
        // Both are the samples' differences, with L(t_m) = L(t_0) exactly.
        let mut samples = vec![vec![0.0; n]; m + 1];
        for (i, row) in samples.iter_mut().enumerate().take(m) {
            act.lengths_at((i as f64 / m as f64) * 1.7, row);
        }
        samples[m] = samples[0].clone();
        for i in (0..m).rev() {
            let want: Vec<f64> = (0..n)
                .map(|l| k[l] * (samples[i + 1][l] - samples[i][l]))
                .collect();
            assert_eq!(streamed.row(i), want, "row {i}");
        }
    }
}
