//! The implicit catching-up scheme (theory §4): with `u` constant on each step,
//! `x^{i+1} = argmin_{x in C} |x - (x^i + h u^i)|^2_{K^{-1}}`, and the block displacements over the
//! step are the multipliers `D_b`. Here `h u^i = K (L(t_{i+1}) - L(t_i))`: the exact increment of
//! the actuation over the step, so the scheme is rate-independent.

use super::increments::{IncrementStorage, Increments};
use super::{slip_of, Actuation, PeriodMap, Recorder};
use crate::error::Result;
use crate::model::Crawler;
use crate::sweep::{rigid_mean, tangent, Bound, ProjectionMethod, Projector};

/// The active pattern of a period, for the tangent map `dx <- J dx` of the period
/// ([`PeriodMap::apply_tangent`]): the tangent of a step ([`crate::sweep::tangent`]) depends only
/// on which blocks are free (off their faces), so the log keeps the free set after the first
/// step and then, step by step, the blocks whose free/on-a-face state changed. On a settled
/// orbit a block changes a few times per period: memory `O(N + M + changes)` instead of one
/// byte per block and step (the worst case, every block changing at every step, takes 4 bytes
/// per block and step; measured on the bench gait, the storage kept from the largest period
/// since rest: 26 KB at N = 1000 and 159 KB at N = 10^4, 1000 steps).
///
/// The tangent of a step is the `K^{-1}`-orthogonal projection onto the vectors constant on
/// every segment of links between consecutive free blocks and zero on the end segments (before
/// the first free block, after the last): idempotent, so after one step a step with the same
/// free set changes nothing, and one whose free set differs at some blocks only changes the
/// segments around those blocks (a segment whose end blocks and interior did not change is a
/// segment of the previous step, on which `dx` is already constant). [`PatternLog::apply`]
/// re-averages only those: per step `O(changes + length of the touched segments)`.
#[derive(Debug, Clone, Default)]
struct PatternLog {
    /// The working set after the first step, normalised (`Free`, or `Lower` for a block on
    /// either face).
    first: Vec<Bound>,
    /// The same, after the last step recorded.
    last: Vec<Bound>,
    /// Blocks whose state changed, step after step.
    changed: Vec<u32>,
    /// `changed[starts[i - 1]..starts[i]]` changed at step `i` (`i >= 1`).
    starts: Vec<usize>,
}

impl PatternLog {
    fn clear(&mut self) {
        self.first.clear();
        self.last.clear();
        self.changed.clear();
        self.starts.clear();
    }

    /// Records the working set of the next step.
    fn push(&mut self, ws: &[Bound]) {
        let norm = |b: &Bound| {
            if *b == Bound::Free {
                Bound::Free
            } else {
                Bound::Lower
            }
        };
        if self.first.is_empty() {
            self.first.extend(ws.iter().map(norm));
            self.last.clone_from(&self.first);
            return;
        }
        for (b, (w, l)) in ws.iter().zip(self.last.iter_mut()).enumerate() {
            let w = norm(w);
            if w != *l {
                *l = w;
                // The number of blocks is at most MAX_SAMPLES + 1, below u32::MAX.
                self.changed.push(b as u32);
            }
        }
        self.starts.push(self.changed.len());
    }

    fn bytes(&self) -> usize {
        (self.first.capacity() + self.last.capacity()) * std::mem::size_of::<Bound>()
            + self.changed.capacity() * std::mem::size_of::<u32>()
            + self.starts.capacity() * std::mem::size_of::<usize>()
    }

    /// `dx <- J dx` on the recorded steps (nothing when nothing was recorded).
    fn apply(&self, inv_k: &[f64], dx: &mut [f64]) {
        if self.first.is_empty() {
            return;
        }
        let mut ws = self.first.clone();
        tangent(&ws, inv_k, dx);
        let mut from = 0;
        for &to in &self.starts {
            let changed = &self.changed[from..to];
            from = to;
            if changed.is_empty() {
                continue;
            }
            for &b in changed {
                let b = b as usize;
                ws[b] = if ws[b] == Bound::Free {
                    Bound::Lower
                } else {
                    Bound::Free
                };
            }
            // Changed blocks come in increasing order, so are their segments: a link inside
            // the last segment found is skipped, and every segment is scanned once (O(N) per
            // step at most, however many blocks changed).
            let mut last: Option<(usize, usize)> = None;
            for &b in changed {
                let b = b as usize;
                // The links beside block b: b - 1 and b.
                for l in [b.wrapping_sub(1), b] {
                    if l >= dx.len() || last.is_some_and(|(lo, hi)| (lo..hi).contains(&l)) {
                        continue;
                    }
                    let (lo, hi) = segment(&ws, l);
                    average(&ws, inv_k, dx, lo, hi);
                    last = Some((lo, hi));
                }
            }
        }
    }
}

/// The segment of link `l` under the free set `ws`: links `lo..hi` between the nearest free
/// block at or left of `l` and the nearest free block right of it (block `l + 1` on).
fn segment(ws: &[Bound], l: usize) -> (usize, usize) {
    let lo = (0..=l).rev().find(|&b| ws[b] == Bound::Free).unwrap_or(0);
    let hi = (l + 1..ws.len())
        .find(|&b| ws[b] == Bound::Free)
        .unwrap_or(ws.len() - 1);
    (lo, hi)
}

/// The tangent on the links `lo..hi` of one segment: zero where the segment reaches an end of
/// the chain without a free block there, else the `1/k`-weighted mean.
fn average(ws: &[Bound], inv_k: &[f64], dx: &mut [f64], lo: usize, hi: usize) {
    let pinned = ws[lo] != Bound::Free || ws[hi] != Bound::Free;
    let seg = &mut dx[lo..hi];
    if pinned {
        seg.iter_mut().for_each(|d| *d = 0.0);
        return;
    }
    rigid_mean(&inv_k[lo..hi], seg);
}

/// Catching-up on `m` uniform steps per period.
#[derive(Debug, Clone)]
pub struct CatchingUp {
    proj: Projector,
    /// `K (L^{i+1} - L^i)` of every step.
    incs: Increments,
    times: Vec<f64>,
    d: Vec<f64>,
    iterations: u64,
    /// The active pattern of the last period when recording ([`PeriodMap::record_tangent`]).
    pattern: PatternLog,
    recording: bool,
    inv_k: Vec<f64>,
}

impl CatchingUp {
    /// Samples the actuation at `t_i = i T / m`, `i = 0..=m` (with `L(t_m) = L(t_0)` exactly, so
    /// the increments sum to zero), holding the increments as a table when it fits in
    /// [`IncrementStorage::DEFAULT_BUDGET`] bytes.
    pub fn new(crawler: &Crawler, act: &Actuation, m: usize) -> Result<Self> {
        let storage =
            IncrementStorage::within(IncrementStorage::DEFAULT_BUDGET, crawler.links(), m);
        Self::with_storage(crawler, act, m, storage)
    }

    /// As [`CatchingUp::new`], the increments held as `storage` says (both give bitwise the same
    /// steps).
    pub fn with_storage(
        crawler: &Crawler,
        act: &Actuation,
        m: usize,
        storage: IncrementStorage,
    ) -> Result<Self> {
        let incs = Increments::new(act, crawler.stiffness(), m, storage)?;
        Self::build(crawler, incs, act.period())
    }

    /// Catching-up on given increments `K (L^{i+1} - L^i)` (row-major `m x n`) over a period.
    pub fn from_increments(crawler: &Crawler, deltas: Vec<f64>, period: f64) -> Result<Self> {
        Self::build(crawler, Increments::given(deltas, crawler.links())?, period)
    }

    fn build(crawler: &Crawler, incs: Increments, period: f64) -> Result<Self> {
        let m = incs.steps();
        Ok(CatchingUp {
            proj: Projector::new(crawler)?,
            incs,
            times: (0..=m).map(|i| (i as f64 / m as f64) * period).collect(),
            d: vec![0.0; crawler.blocks()],
            iterations: 0,
            pattern: PatternLog::default(),
            recording: false,
            inv_k: crawler.stiffness().iter().map(|k| 1.0 / k).collect(),
        })
    }

    /// How the increments are held.
    pub fn increment_storage(&self) -> IncrementStorage {
        self.incs.storage()
    }

    /// Bytes held for the increments: `8 N M` stored, `40 N` streamed.
    pub fn increment_bytes(&self) -> usize {
        self.incs.bytes()
    }

    /// Bytes held by the active pattern recorded in the last period
    /// ([`PeriodMap::record_tangent`]): `O(N + M + changes)`.
    pub fn recorded_pattern_bytes(&self) -> usize {
        self.pattern.bytes()
    }

    /// Total projection iterations so far (a cost measure of the projection kernel): the
    /// active-set method's iterations, one per step for the warm method (the default) and the
    /// dynamic programme, whose windows are counted by [`crate::sweep::Projector::warm_counters`].
    pub fn iterations(&self) -> u64 {
        self.iterations
    }

    /// Projects with this method whatever the length of the chain (default:
    /// [`ProjectionMethod::Warm`]; all give the same steps).
    pub fn set_method(&mut self, method: ProjectionMethod) {
        self.proj.set_method(method);
    }

    /// Work counters of the warm projection (see [`crate::sweep::ChainWarm::counters`]).
    pub fn warm_counters(&self) -> (u64, u64, u64) {
        self.proj.warm_counters()
    }
}

impl PeriodMap for CatchingUp {
    fn run_period(
        &mut self,
        x: &mut [f64],
        acc: &mut [f64],
        mut rec: Option<&mut Recorder>,
    ) -> Result<()> {
        self.pattern.clear();
        for i in 0..self.times.len() - 1 {
            let delta = self.incs.row(i);
            self.iterations += self.proj.step(x, delta, &mut self.d)? as u64;
            if self.recording {
                self.pattern.push(self.proj.active());
            }
            for (a, d) in acc.iter_mut().zip(&self.d) {
                *a += d;
            }
            if let Some(r) = rec.as_deref_mut() {
                let tol = 1e-12 * delta.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                r.push(
                    self.times[i + 1],
                    x,
                    acc,
                    self.d.iter().map(|&d| slip_of(d, tol)),
                );
            }
        }
        Ok(())
    }

    fn run_period_tangent(&mut self, x: &mut [f64], dx: &mut [f64]) -> Result<bool> {
        for i in 0..self.times.len() - 1 {
            let delta = self.incs.row(i);
            self.iterations += self.proj.step(x, delta, &mut self.d)? as u64;
            self.proj.tangent(dx);
        }
        Ok(true)
    }

    fn record_tangent(&mut self, on: bool) -> bool {
        self.recording = on;
        if !on {
            self.pattern = PatternLog::default();
        }
        true
    }

    fn apply_tangent(&self, dx: &mut [f64]) {
        self.pattern.apply(&self.inv_k, dx);
    }
}
