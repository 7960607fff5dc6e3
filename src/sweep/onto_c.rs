//! The Euclidean projection onto the C of a general problem (P) (theory §11), chosen by the
//! structure of C: the one operation of the catching-up step, behind one type.
//!
//! - **Dense** ([`PolyProjector`]): the exact active-set method for any polyhedron, a dense
//!   `k x k` solve per iteration (`k` the faces held).
//! - **Chain** ([`ChainOntoC`]): where (P) is a crawler's chain
//!   ([`GeneralProblem::as_chain`](crate::model::general::GeneralProblem::as_chain)), the
//!   crawler's own `O(N)` projection ([`Projector`], warm method) through the change of
//!   variables of [`crate::model::crawler_as_general`]: with `x = K^(1/2) x~`,
//!   `Proj_{C~}(v~) = K^(-1/2) Proj^(K^-1)_C(K^(1/2) v~)`, and the block displacements `D_b` of
//!   the crawler's step are the multipliers of the unit rows, `mu_(b+) = s_b D_b` for `D_b > 0`,
//!   `mu_(b-) = -s_b D_b` for `D_b < 0` (`s_b = sqrt(k_(b-1) + k_b)`, module docs of
//!   `model::general_crawler`).
//!
//! Both answer with a [`Projection`] in the problem's own variables and faces, and both
//! residuals are the KKT residual of that answer computed from the problem's rows (the chain's
//! sparsely, each row having at most two entries), so the chain's answer is checked against
//! the polyhedron the user wrote, not against the crawler it was recognised as.

use super::polyhedron::{PolyProjector, Projection};
use super::{Bound, Projector};
use crate::error::Result;
use crate::model::general::Polyhedron;
use crate::model::ChainView;

/// The projector onto C of a general problem, by structure (module docs).
#[derive(Debug, Clone)]
pub enum OntoC {
    /// Any polyhedron: the dense active-set method.
    Dense(PolyProjector),
    /// A crawler's chain: its `O(N)` projection.
    Chain(Box<ChainOntoC>),
}

impl OntoC {
    /// The projector for `c`: the chain's where `chain` (the problem's [`ChainView`]) is given
    /// and the crawler's projection accepts it, else the dense one (the crawler's own check of
    /// the uniqueness condition, relative `1e-9`, is stricter than the vertex enumeration
    /// that accepted the problem: a nearly balanced chain is projected densely).
    pub fn new(c: &Polyhedron, chain: Option<&ChainView>) -> Self {
        match chain.map(|view| ChainOntoC::new(c, view)) {
            Some(Ok(p)) => OntoC::Chain(Box::new(p)),
            _ => OntoC::Dense(PolyProjector::new(c.clone())),
        }
    }

    /// `Proj_C(v)` from `start`, a point of C (within rounding), warm-started from the previous
    /// call (see [`PolyProjector::project`]).
    pub fn project(&mut self, start: &[f64], v: &[f64]) -> Result<Projection> {
        match self {
            OntoC::Dense(p) => p.project(start, v),
            OntoC::Chain(p) => {
                let mut out = Projection::default();
                p.project_into(start, v, &mut out)?;
                Ok(out)
            }
        }
    }

    /// [`OntoC::project`] into `out`, whose vectors the chain's projection reuses (no
    /// allocation per step once they have their sizes; the dense one replaces them).
    pub fn project_into(&mut self, start: &[f64], v: &[f64], out: &mut Projection) -> Result<()> {
        match self {
            OntoC::Dense(p) => {
                *out = p.project(start, v)?;
                Ok(())
            }
            OntoC::Chain(p) => p.project_into(start, v, out),
        }
    }

    /// `"dense"` or `"chain"`: which projection this is (results say it).
    pub fn kind(&self) -> &'static str {
        match self {
            OntoC::Dense(_) => "dense",
            OntoC::Chain(_) => "chain",
        }
    }
}

/// The crawler's projection answering for the C of a general problem that is its chain (module
/// docs).
#[derive(Debug, Clone)]
pub struct ChainOntoC {
    proj: Projector,
    /// `sqrt(k_l)`: `x_l = sqrt(k_l) x~_l`.
    sqrt_k: Vec<f64>,
    /// `s_b`, the length of `K^(1/2) nu_b`.
    s: Vec<f64>,
    /// Per block, its forward and backward faces (0-based).
    faces: Vec<[usize; 2]>,
    /// The problem's rows, sparse: `(component, value)` of each non-zero.
    rows: Vec<Vec<(usize, f64)>>,
    offsets: Vec<f64>,
    x: Vec<f64>,
    delta: Vec<f64>,
    d: Vec<f64>,
    /// The stationarity residual's buffer.
    stat: Vec<f64>,
}

impl ChainOntoC {
    /// The chain projection for `c`, recognised as `view` (the problem's own C and view).
    pub fn new(c: &Polyhedron, view: &ChainView) -> Result<Self> {
        let k = view.crawler.stiffness();
        let (n, nb) = (k.len(), k.len() + 1);
        let s = (0..nb)
            .map(|b| {
                let behind = if b > 0 { k[b - 1] } else { 0.0 };
                let ahead = if b < n { k[b] } else { 0.0 };
                (behind + ahead).sqrt()
            })
            .collect();
        let rows = c
            .normals
            .iter()
            .map(|r| {
                r.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0.0)
                    .map(|(i, v)| (i, *v))
                    .collect()
            })
            .collect();
        Ok(ChainOntoC {
            proj: Projector::new(&view.crawler)?,
            sqrt_k: k.iter().map(|v| v.sqrt()).collect(),
            s,
            faces: view.faces.clone(),
            rows,
            offsets: c.offsets.clone(),
            x: vec![0.0; n],
            delta: vec![0.0; n],
            d: vec![0.0; nb],
            stat: vec![0.0; n],
        })
    }

    /// `Proj_C(v)` from `start` (module docs) into `out`; one warm catching-up step of the
    /// crawler.
    pub fn project_into(&mut self, start: &[f64], v: &[f64], out: &mut Projection) -> Result<()> {
        for l in 0..self.sqrt_k.len() {
            self.x[l] = self.sqrt_k[l] * start[l];
            self.delta[l] = self.sqrt_k[l] * (v[l] - start[l]);
        }
        out.iterations = self.proj.step(&mut self.x, &self.delta, &mut self.d)?;
        out.x.clear();
        out.x
            .extend(self.x.iter().zip(&self.sqrt_k).map(|(xi, r)| xi / r));
        // Only the faces of the working set carry a multiplier: a free block's displacement is
        // rounding (1e-16 to 1e-12), not a reaction on a face far from the state.
        out.mu.clear();
        out.mu.resize(self.rows.len(), 0.0);
        out.active.clear();
        for (b, (a, &db)) in self.proj.active().iter().zip(&self.d).enumerate() {
            let (face, push) = match a {
                Bound::Free => continue,
                Bound::Lower => (self.faces[b][0], db),
                Bound::Upper => (self.faces[b][1], -db),
            };
            out.mu[face] = self.s[b] * push.max(0.0);
            out.active.push(face);
        }
        out.residual = self.kkt_residual(v, &out.x, &out.mu);
        Ok(())
    }

    /// [`super::polyhedron::kkt_residual`] on the sparse rows: `O(N)`, stationarity
    /// accumulated in a buffer of the projector.
    fn kkt_residual(&mut self, v: &[f64], x: &[f64], mu: &[f64]) -> f64 {
        let stat = &mut self.stat;
        stat.clear();
        stat.extend(v.iter().zip(x).map(|(a, b)| a - b));
        let mut r = 0.0_f64;
        for ((row, &c), &m) in self.rows.iter().zip(&self.offsets).zip(mu) {
            let mut dot = 0.0;
            for &(i, a) in row {
                stat[i] -= m * a;
                dot += a * x[i];
            }
            let slack = dot - c;
            r = r
                .max(slack.max(0.0))
                .max((-m).max(0.0))
                .max((m * slack).abs());
        }
        stat.iter().fold(r, |r, s| r.max(s.abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::crawler_as_general;
    use crate::model::general::GeneralCost;
    use crate::Crawler;

    /// A small deterministic generator in [0, 1).
    fn rng(seed: &mut u64) -> f64 {
        *seed ^= *seed << 13;
        *seed ^= *seed >> 7;
        *seed ^= *seed << 17;
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// On random chains of 2 to 12 blocks (uneven stiffness and thresholds) and sequences of
    /// catching-up steps, the chain's projection gives the dense method's point and multipliers
    /// (unique: the active normals are independent), faces held on C, and a residual at
    /// rounding.
    #[test]
    fn the_chains_projection_is_the_dense_one() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut chains = 0;
        for nb in 2..=12 {
            let n = nb - 1;
            let k: Vec<f64> = (0..n).map(|_| 0.3 + 3.0 * rng(&mut seed)).collect();
            let mp: Vec<f64> = (0..nb).map(|_| 0.2 + rng(&mut seed)).collect();
            let mm: Vec<f64> = (0..nb).map(|_| 0.2 + 1.5 * rng(&mut seed)).collect();
            let Ok(crawler) = Crawler::new(k, mp, mm) else {
                continue;
            };
            if crawler.require_unique().is_err() {
                continue;
            }
            let inst = crawler_as_general(&crawler, 10.0, &vec![1.0; n], GeneralCost::None)
                .expect("a crawler's general form");
            let p = &inst.problem;
            chains += 1;
            let view = p.as_chain().expect("recognised");
            let mut chain = OntoC::new(&p.c, Some(&view));
            let mut dense = OntoC::new(&p.c, None);
            assert_eq!((chain.kind(), dense.kind()), ("chain", "dense"));
            let scale = p.c.scale();
            let mut x = vec![0.0; n];
            for step in 0..60 {
                let amp = if step % 3 == 0 { 3.0 } else { 0.4 };
                let v: Vec<f64> = x
                    .iter()
                    .map(|xi| xi + amp * scale * (2.0 * rng(&mut seed) - 1.0))
                    .collect();
                let a = chain.project(&x, &v).unwrap();
                let b = dense.project(&x, &v).unwrap();
                for (i, (ai, bi)) in a.x.iter().zip(&b.x).enumerate() {
                    assert!((ai - bi).abs() <= 1e-10 * scale, "N = {nb}, x[{i}]");
                }
                for (j, (ai, bi)) in a.mu.iter().zip(&b.mu).enumerate() {
                    assert!((ai - bi).abs() <= 1e-10 * scale, "N = {nb}, mu[{j}]");
                    // A face off the state carries no reaction, not even a rounding.
                    if p.c.slack(j, &a.x) < -1e-9 * scale {
                        assert_eq!(*ai, 0.0, "N = {nb}, mu[{j}] off its face");
                    }
                }
                for &j in &a.active {
                    assert!(p.c.slack(j, &a.x).abs() <= 1e-10 * scale, "face {j} held");
                }
                let size = v.iter().fold(scale, |m, vi| m.max(vi.abs()));
                assert!(a.residual <= 1e-12 * size, "residual {:e}", a.residual);
                x = a.x;
            }
        }
        assert!(
            chains >= 8,
            "only {chains} chains met the uniqueness condition"
        );
    }
}
