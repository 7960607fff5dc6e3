//! The polytope C of admissible spring forces (theory §2, paper eq. 3.16):
//! `C = { x : -mu_b^- <= F_b(x) <= mu_b^+, b = 1..N }`, `F_b(x) = x_{b-1} - x_b`,
//! `x_{-1} = x_n = 0` (0-based).
//!
//! Path view used throughout: with `p_0 = 0`, `p_{l+1} = x_l`, `p_N = 0`, the increment of block
//! `b` is `p_{b+1} - p_b = -F_b`, bounded in `[-mu_b^+, mu_b^-]`. C is the set of such closed
//! paths ("bridges"), which gives its ranges, facets and vertices in closed form.

use crate::error::{Error, Result};
use crate::model::Crawler;
use serde::Serialize;

/// Largest number of links for which face normals are listed densely.
pub const MAX_LINKS_FOR_NORMALS: usize = 200;

/// Which side of block `b`'s friction constraint a face is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum FaceSign {
    /// `F_b = mu_b^+`: block `b` may slide forward.
    #[serde(rename = "+")]
    Forward,
    /// `F_b = -mu_b^-`: block `b` may slide backward.
    #[serde(rename = "-")]
    Backward,
}

/// One of the `2N` half-spaces `<normal, x> <= offset` bounding C.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Face {
    /// Block number, 1-based.
    pub block: usize,
    /// Forward (`+nu_b`, offset `mu_b^+`) or backward (`-nu_b`, offset `mu_b^-`).
    pub sign: FaceSign,
    /// Outer normal `±nu_b`, `nu_b = e_{b-1} - e_b` (in link coordinates, `e_0 = e_N = 0`);
    /// listed densely up to [`MAX_LINKS_FOR_NORMALS`] links, `None` beyond (it has at most two
    /// non-zero entries: `±1` on link `b-1` and `∓1` on link `b`, 1-based).
    pub normal: Option<Vec<f64>>,
    /// Right-hand side.
    pub offset: f64,
    /// Whether the face is a facet of C (a block alone can slide that way); otherwise the
    /// half-space is redundant and never active.
    pub facet: bool,
}

impl Crawler {
    /// Spring force on every block, `F_b = x_{b-1} - x_b`.
    pub fn block_forces(&self, x: &[f64]) -> Vec<f64> {
        let n = self.links();
        (0..self.blocks())
            .map(|b| {
                let left = if b == 0 { 0.0 } else { x[b - 1] };
                let right = if b == n { 0.0 } else { x[b] };
                left - right
            })
            .collect()
    }

    /// The `2N` faces of C, forward face of block 1 first.
    ///
    /// Face `b+` is a facet iff `mu_b^+ < sum_{c != b} mu_c^-` (the largest `F_b` on the other
    /// constraints is `sum_{c != b} mu_c^-`); likewise `b-` iff `mu_b^- < sum_{c != b} mu_c^+`.
    pub fn faces(&self) -> Vec<Face> {
        let (n, nb) = (self.links(), self.blocks());
        let sum_m: f64 = self.mu_backward().iter().sum();
        let sum_p: f64 = self.mu_forward().iter().sum();
        let mut faces = Vec::with_capacity(2 * nb);
        for b in 0..nb {
            let nu = (n <= MAX_LINKS_FOR_NORMALS).then(|| {
                let mut nu = vec![0.0; n];
                if b > 0 {
                    nu[b - 1] = 1.0;
                }
                if b < n {
                    nu[b] = -1.0;
                }
                nu
            });
            let (mp, mm) = (self.mu_forward()[b], self.mu_backward()[b]);
            faces.push(Face {
                block: b + 1,
                sign: FaceSign::Forward,
                normal: nu.clone(),
                offset: mp,
                facet: mp < sum_m - mm,
            });
            faces.push(Face {
                block: b + 1,
                sign: FaceSign::Backward,
                normal: nu.map(|nu| nu.iter().map(|v| -v).collect()),
                offset: mm,
                facet: mm < sum_p - mp,
            });
        }
        faces
    }

    /// The range `[min, max]` of each link force `x_l` over C: a bridge rises at most
    /// `sum_{b<=l} mu_b^-` from the rear and must come back within `sum_{b>l} mu_b^+`.
    pub fn link_force_ranges(&self) -> Vec<[f64; 2]> {
        let (mp, mm) = (self.mu_forward(), self.mu_backward());
        let n = self.links();
        // Front sums over blocks l+1..N by a backward pass (exact sums on both sides, O(N)).
        let mut front = vec![(0.0, 0.0); n];
        let mut acc = (0.0, 0.0);
        for l in (0..n).rev() {
            acc = (acc.0 + mp[l + 1], acc.1 + mm[l + 1]);
            front[l] = acc;
        }
        let (mut rear_p, mut rear_m) = (0.0, 0.0);
        (0..n)
            .map(|l| {
                rear_p += mp[l];
                rear_m += mm[l];
                let (front_p, front_m) = front[l];
                [-f64::min(rear_p, front_m), f64::min(rear_m, front_p)]
            })
            .collect()
    }

    /// The size of C: the widest range of a link force. Tolerances on states are relative to it
    /// (link forces of a long chain reach sums of many thresholds).
    pub fn state_scale(&self) -> f64 {
        self.link_force_ranges()
            .iter()
            .fold(0.0_f64, |m, r| m.max(r[1] - r[0]))
    }

    /// Block displacements below this are "no motion": `tol` times the size of C over the
    /// stiffest link (a displacement is a force over a stiffness). The one threshold of a
    /// gait's slip modes, where a result is written and where it is read back.
    pub fn displacement_tol(&self, tol: f64) -> f64 {
        let kmax = self.stiffness().iter().fold(0.0_f64, |m, &k| m.max(k));
        tol * self.state_scale() / kmax
    }

    /// The largest violation `max_b max(F_b - mu_b^+, -mu_b^- - F_b, 0)` of C at `x`, with the
    /// face where it happens.
    pub fn violation(&self, x: &[f64]) -> (f64, Option<(usize, FaceSign)>) {
        let mut worst = (0.0, None);
        for (b, f) in self.block_forces(x).into_iter().enumerate() {
            let up = f - self.mu_forward()[b];
            let down = -self.mu_backward()[b] - f;
            if up > worst.0 {
                worst = (up, Some((b, FaceSign::Forward)));
            }
            if down > worst.0 {
                worst = (down, Some((b, FaceSign::Backward)));
            }
        }
        worst
    }

    /// Checks that `x` has the right length, is finite and lies in C up to
    /// `tol * force_scale`; the error names the face.
    pub fn check_admissible(&self, what: &str, x: &[f64], tol: f64) -> Result<()> {
        if x.len() != self.links() {
            return Err(Error::invalid(
                what,
                format!("{} values", x.len()),
                format!("needs one value per link ({})", self.links()),
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("{what}[{}]", i + 1),
                x[i],
                "must be finite",
            ));
        }
        let (v, face) = self.violation(x);
        if v > tol * self.force_scale() {
            // `violation` returns a face with every positive violation (v > 0 here).
            let (b, s) = face.expect("a positive violation has a face");
            let f = self.block_forces(x)[b];
            let detail = match s {
                FaceSign::Forward => format!(
                    "spring force on block {} is {f} > mu_forward = {} (by {v:.3e})",
                    b + 1,
                    self.mu_forward()[b]
                ),
                FaceSign::Backward => format!(
                    "spring force on block {} is {f} < -mu_backward = {} (by {v:.3e})",
                    b + 1,
                    -self.mu_backward()[b]
                ),
            };
            return Err(Error::Inadmissible {
                what: what.to_string(),
                detail,
            });
        }
        Ok(())
    }

    /// All vertices of C. A vertex has `n` active faces; under the uniqueness condition exactly
    /// one block is free, so vertices are enumerated as (free block, bound of every other block)
    /// with the free increment fixed by closing the bridge; those inside its bounds are the
    /// vertices, each met once. Cost `N 2^n`: call it for small `n` only.
    pub fn vertices(&self) -> Vec<Vec<f64>> {
        let (n, nb) = (self.links(), self.blocks());
        let (mp, mm) = (self.mu_forward(), self.mu_backward());
        let mut out = Vec::new();
        for free in 0..nb {
            for mask in 0u64..(1u64 << n) {
                let others = (0..nb).filter(|&b| b != free);
                let inc: Vec<(usize, f64)> = others
                    .enumerate()
                    .map(|(j, b)| (b, if mask >> j & 1 == 1 { mm[b] } else { -mp[b] }))
                    .collect();
                let closing = -inc.iter().map(|(_, d)| d).sum::<f64>();
                if closing <= -mp[free] || closing >= mm[free] {
                    continue;
                }
                let mut delta = vec![0.0; nb];
                inc.iter().for_each(|&(b, d)| delta[b] = d);
                delta[free] = closing;
                let mut x = Vec::with_capacity(n);
                let mut p = 0.0;
                for d in &delta[..n] {
                    p += d;
                    x.push(p);
                }
                out.push(x);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_link_interval() {
        // theory §9: C = [alpha, beta], alpha = max(-mu_1^+, -mu_2^-), beta = min(mu_1^-, mu_2^+).
        let c = Crawler::new(vec![1.0], vec![1.0, 0.7], vec![2.0, 0.4]).unwrap();
        assert_eq!(c.link_force_ranges(), vec![[-0.4, 0.7]]);
        let mut v = c.vertices().into_iter().map(|x| x[0]).collect::<Vec<_>>();
        v.sort_by(f64::total_cmp);
        assert_eq!(v, vec![-0.4, 0.7]);
        let facets: Vec<_> = c
            .faces()
            .into_iter()
            .filter(|f| f.facet)
            .map(|f| (f.block, f.sign))
            .collect();
        assert_eq!(
            facets,
            vec![(2, FaceSign::Forward), (2, FaceSign::Backward)]
        );
    }

    #[test]
    fn vertices_lie_on_n_facets() {
        let c = Crawler::new(
            vec![1.0, 2.0, 0.5],
            vec![1.0, 1.3, 0.8, 1.1],
            vec![2.0, 2.95, 3.1, 2.2],
        )
        .unwrap();
        assert!(c.uniqueness().holds());
        let vs = c.vertices();
        assert!(!vs.is_empty());
        for x in &vs {
            assert!(c.violation(x).0 < 1e-12);
            let active = c
                .block_forces(x)
                .iter()
                .enumerate()
                .filter(|&(b, &f)| {
                    (f - c.mu_forward()[b]).abs() < 1e-12 || (f + c.mu_backward()[b]).abs() < 1e-12
                })
                .count();
            assert_eq!(active, 3, "{x:?} {:?}", c.block_forces(x));
        }
        // Every link force range endpoint is attained at some vertex.
        for (l, r) in c.link_force_ranges().iter().enumerate() {
            let lo = vs.iter().map(|x| x[l]).fold(f64::INFINITY, f64::min);
            let hi = vs.iter().map(|x| x[l]).fold(f64::NEG_INFINITY, f64::max);
            assert!(
                (lo - r[0]).abs() < 1e-12 && (hi - r[1]).abs() < 1e-12,
                "{l}: {r:?} vs {lo} {hi}"
            );
        }
    }
}
