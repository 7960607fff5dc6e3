//! Projections for the sweeping process (theory §3–4): onto C and onto its tangent cones, in the
//! `K^{-1}` metric, with the block displacements read off the multipliers.
//!
//! Both are instances of one structured QP over the chain: a catching-up step is solved by
//! [`ChainWarm`] (the previous faces guessed, certified by one `O(n)` pass, repaired on windows
//! by the exact dynamic programme [`ChainDp`]), a tangent-cone projection by the active-set
//! method [`ChainQp`] in `O(n)` per iteration. [`polyhedron`] projects onto any polyhedron (the general problem (P), theory §11)
//! by an exact active-set method. This layer knows the crawler's parameters but nothing of time or actuation.

mod chain;
mod dp;
mod onto_c;
pub mod polyhedron;
mod warm;

pub use chain::{increment, rigid_mean, tangent, Bound, ChainQp};
pub use dp::ChainDp;
pub use onto_c::{ChainOntoC, OntoC};
pub use polyhedron::{PolyProjector, Projection};
pub use warm::ChainWarm;

use crate::error::Result;
use crate::model::Crawler;

/// How [`Projector`] solves a catching-up projection. All three give the same step (the QP is
/// strictly convex); they differ in cost.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProjectionMethod {
    /// The previous step's faces as a guess, certified by one pass and repaired by exact
    /// windows ([`ChainWarm`]). The default at every length.
    Warm,
    /// The exact dynamic programme over the whole chain ([`ChainDp`]).
    Dp,
    /// The primal active-set method warm-started from the previous faces ([`ChainQp`]).
    ActiveSet,
}

/// From this many links a warm catching-up step forms `x + delta` inside the pass
/// ([`ChainWarm::solve_increment`]), below it in a loop of its own. Measured on the bench gait
/// (`cargo bench --bench step -- 'period_of_1000_steps/catching-up'`, idle 2-core machine):
/// fused, a step took 3.7 against 4.3 us at N = 1000 and 366 against 374 ns at N = 100, but
/// 31 against 24 ns at N = 3 and 57 against 53 ns at N = 10.
pub const FUSED_MIN_LINKS: usize = 64;

/// The catching-up projection onto C (theory §4): `x+ = argmin_{x in C} |x - v|^2_{K^{-1}}`,
/// by default guessed from the previous step's faces and certified or repaired ([`ChainWarm`]),
/// which is `O(n)` whatever the number of faces that change and faster than both other methods
/// at every length measured (`cargo bench --bench step -- projection`, N = 100 to 10^4).
#[derive(Debug, Clone)]
pub struct Projector {
    qp: ChainQp,
    dp: ChainDp,
    warm: ChainWarm,
    method: ProjectionMethod,
    inv_k: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    v: Vec<f64>,
}

impl Projector {
    /// A projector for this crawler. The crawler must satisfy the uniqueness condition (checked).
    pub fn new(crawler: &Crawler) -> Result<Self> {
        crawler.require_unique()?;
        let lo: Vec<f64> = crawler.mu_forward().iter().map(|m| -m).collect();
        let hi = crawler.mu_backward().to_vec();
        Ok(Projector {
            qp: ChainQp::new(crawler.stiffness()),
            dp: ChainDp::new(crawler.stiffness()),
            warm: ChainWarm::new(crawler.stiffness(), &lo, &hi),
            method: ProjectionMethod::Warm,
            inv_k: crawler.stiffness().iter().map(|k| 1.0 / k).collect(),
            lo,
            hi,
            v: vec![0.0; crawler.links()],
        })
    }

    /// One catching-up step: `x <- Proj_C(x + delta)`, `delta = K (L^{i+1} - L^i)` (= `h u^i`).
    ///
    /// `x` must be in C. `d[b]` receives the displacement of block `b` over the step
    /// (`D_b = lambda_b^+ - lambda_b^-`, theory §4); the barycentre moves by `mean(d)`.
    /// Returns the number of active-set iterations (1 for the dynamic programme and for the
    /// warm method: its windows are counted by [`ChainWarm::counters`]).
    pub fn step(&mut self, x: &mut [f64], delta: &[f64], d: &mut [f64]) -> Result<usize> {
        let form_v = |v: &mut [f64], x: &[f64]| {
            for ((vi, xi), di) in v.iter_mut().zip(x).zip(delta) {
                *vi = xi + di;
            }
        };
        match self.method {
            ProjectionMethod::Warm if x.len() >= FUSED_MIN_LINKS => {
                self.warm.solve_increment(x, delta, d);
                Ok(1)
            }
            ProjectionMethod::Warm => {
                form_v(&mut self.v, x);
                self.warm.solve(&self.v, x, d);
                Ok(1)
            }
            ProjectionMethod::Dp => {
                form_v(&mut self.v, x);
                self.dp.solve(&self.lo, &self.hi, &self.v, x, d);
                Ok(1)
            }
            ProjectionMethod::ActiveSet => {
                form_v(&mut self.v, x);
                self.qp.solve(&self.lo, &self.hi, &self.v, x, d)
            }
        }
    }

    /// Chooses the method whatever the length of the chain (for comparisons; all give the same
    /// step). The next step of the warm and active-set methods starts from an empty working set
    /// if the method changed.
    pub fn set_method(&mut self, method: ProjectionMethod) {
        if method != self.method {
            self.qp.reset();
            self.warm.set_working_set(&vec![Bound::Free; self.lo.len()]);
        }
        self.method = method;
    }

    /// The method in use.
    pub fn method(&self) -> ProjectionMethod {
        self.method
    }

    /// Work counters of the warm method (see [`ChainWarm::counters`]).
    pub fn warm_counters(&self) -> (u64, u64, u64) {
        self.warm.counters()
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
        match self.method {
            ProjectionMethod::Warm => {
                self.warm.solve(v, x, d);
                return Ok(1);
            }
            ProjectionMethod::Dp => {
                self.dp.solve(&self.lo, &self.hi, v, x, d);
                return Ok(1);
            }
            ProjectionMethod::ActiveSet => {}
        }
        x.iter_mut().for_each(|xi| *xi = 0.0);
        self.qp.reset();
        self.qp.solve(&self.lo, &self.hi, v, x, d)
    }

    /// The working set after the last step (per block: free, forward face, backward face).
    pub fn active(&self) -> &[Bound] {
        match self.method {
            ProjectionMethod::Warm => self.warm.working_set(),
            ProjectionMethod::Dp => self.dp.working_set(),
            ProjectionMethod::ActiveSet => self.qp.working_set(),
        }
    }
}

/// Projection of a control onto the tangent cone of C (theory §4, exact method):
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
