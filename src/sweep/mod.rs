//! Projections for the sweeping process (SPEC §3–4): onto C and onto its tangent cones, in the
//! `K^{-1}` metric, with the block displacements read off the multipliers.
//!
//! Both are instances of one structured QP, solved by [`ChainQp`] in `O(n)` per active-set
//! iteration. [`polyhedron`] projects onto any polyhedron (the general problem (P), SPEC §11)
//! by an exact active-set method. This layer knows the crawler's parameters but nothing of time or actuation.

mod chain;
mod dp;
pub mod polyhedron;

pub use chain::{increment, tangent, Bound, ChainQp};
pub use dp::ChainDp;
pub use polyhedron::{PolyProjector, Projection};

use crate::error::Result;
use crate::model::Crawler;

/// Below this many links a catching-up step uses the warm-started active-set method
/// ([`ChainQp`]), from it on the exact dynamic programme ([`ChainDp`]), whose cost does not
/// depend on how many faces change. Measured on the travelling sine gait (mu- = 3.3, 1000 steps,
/// shared 2-core machine, `cargo bench --bench step -- projection`): per step near the orbit,
/// 1.39 against 2.37 us at N = 100, 28.0 against 18.1 us at N = 1000 (3 active-set iterations
/// per step); a timing loop gave 2.9 ms against 0.45 ms at N = 10^4 (21 iterations).
pub const DP_MIN_LINKS: usize = 512;

/// The catching-up projection onto C (SPEC §4): `x+ = argmin_{x in C} |x - v|^2_{K^{-1}}`,
/// by the active-set method warm-started from the previous active set on short chains and by
/// the exact `O(n)` dynamic programme on long ones ([`DP_MIN_LINKS`]).
#[derive(Debug, Clone)]
pub struct Projector {
    qp: ChainQp,
    dp: ChainDp,
    use_dp: bool,
    inv_k: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    v: Vec<f64>,
}

impl Projector {
    /// A projector for this crawler. The crawler must satisfy the uniqueness condition (checked).
    pub fn new(crawler: &Crawler) -> Result<Self> {
        crawler.require_unique()?;
        Ok(Projector {
            qp: ChainQp::new(crawler.stiffness()),
            dp: ChainDp::new(crawler.stiffness()),
            use_dp: crawler.links() >= DP_MIN_LINKS,
            inv_k: crawler.stiffness().iter().map(|k| 1.0 / k).collect(),
            lo: crawler.mu_forward().iter().map(|m| -m).collect(),
            hi: crawler.mu_backward().to_vec(),
            v: vec![0.0; crawler.links()],
        })
    }

    /// One catching-up step: `x <- Proj_C(x + delta)`, `delta = K (L^{i+1} - L^i)` (= `h u^i`).
    ///
    /// `x` must be in C. `d[b]` receives the displacement of block `b` over the step
    /// (`D_b = lambda_b^+ - lambda_b^-`, SPEC §4); the barycentre moves by `mean(d)`.
    /// Returns the number of active-set iterations (1 for the dynamic programme).
    pub fn step(&mut self, x: &mut [f64], delta: &[f64], d: &mut [f64]) -> Result<usize> {
        for ((vi, xi), di) in self.v.iter_mut().zip(x.iter()).zip(delta) {
            *vi = xi + di;
        }
        if self.use_dp {
            self.dp.solve(&self.lo, &self.hi, &self.v, x, d);
            Ok(1)
        } else {
            self.qp.solve(&self.lo, &self.hi, &self.v, x, d)
        }
    }

    /// Chooses the method: the dynamic programme (`true`) or the active-set method (`false`),
    /// whatever the length of the chain (for comparisons; both give the same step).
    pub fn set_dynamic_programming(&mut self, on: bool) {
        self.use_dp = on;
    }

    /// The derivative of the last step's projection on its active faces applied to `dv` in
    /// place: the tangent map of a catching-up step (see [`tangent`]).
    pub fn tangent(&self, dv: &mut [f64]) {
        tangent(self.active(), &self.inv_k, dv);
    }

    /// Projects an arbitrary point onto C, starting from the interior point 0. Used to make an
    /// initial state that passed an admissibility check with tolerance exactly feasible.
    pub fn project_from_origin(
        &mut self,
        v: &[f64],
        x: &mut [f64],
        d: &mut [f64],
    ) -> Result<usize> {
        if self.use_dp {
            self.dp.solve(&self.lo, &self.hi, v, x, d);
            return Ok(1);
        }
        x.iter_mut().for_each(|xi| *xi = 0.0);
        self.qp.reset();
        self.qp.solve(&self.lo, &self.hi, v, x, d)
    }

    /// The working set after the last step (per block: free, forward face, backward face).
    pub fn active(&self) -> &[Bound] {
        if self.use_dp {
            self.dp.working_set()
        } else {
            self.qp.working_set()
        }
    }
}

/// Projection of a control onto the tangent cone of C (SPEC §4, exact method):
/// `x' = argmin { |w - u|^2_{K^{-1}} : w in T_C(x) }`, where `T_C(x)` only constrains the faces
/// active at `x`. The multipliers are the block velocities.
#[derive(Debug, Clone)]
pub struct ConeProjector {
    qp: ChainQp,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

impl ConeProjector {
    /// A cone projector for this crawler.
    pub fn new(crawler: &Crawler) -> Result<Self> {
        crawler.require_unique()?;
        let nb = crawler.blocks();
        Ok(ConeProjector {
            qp: ChainQp::new(crawler.stiffness()),
            lo: vec![f64::NEG_INFINITY; nb],
            hi: vec![f64::INFINITY; nb],
        })
    }

    /// `w <- P_{T_C(x)}(u)` for the faces `active` (per block) at the current state; `vel[b]`
    /// receives the velocity of block `b`.
    pub fn project(
        &mut self,
        active: &[Bound],
        u: &[f64],
        w: &mut [f64],
        vel: &mut [f64],
    ) -> Result<usize> {
        for (b, a) in active.iter().enumerate() {
            (self.lo[b], self.hi[b]) = match a {
                Bound::Free => (f64::NEG_INFINITY, f64::INFINITY),
                Bound::Lower => (0.0, f64::INFINITY),
                Bound::Upper => (f64::NEG_INFINITY, 0.0),
            };
        }
        // w = 0 is feasible with every constraint active at its bound.
        w.iter_mut().for_each(|wi| *wi = 0.0);
        self.qp.set_working_set(active);
        self.qp.solve(&self.lo, &self.hi, u, w, vel)
    }
}
