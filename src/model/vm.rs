//! The displacement function v_m (theory §3, paper eqs. 3.19–3.22) and its exact classification.
//!
//! For a shape rate `z'`, the block velocities are `X'_b = s + c_b` with `c_0 = 0`,
//! `c_{b+1} = c_b + z'_b`, where `s` minimises `sum_b R_b(s + c_b)`,
//! `R_b(v) = mu_b^+ max(v, 0) + mu_b^- max(-v, 0)`: a weighted median. `v_m(z') = mean_b X'_b`.
//!
//! **Exact structure.** On each cone of the braid arrangement (a fixed ordering of the `c_b`) the
//! median block is fixed, so v_m is linear there: v_m is the Lovász extension of the set function
//! `f(S) = v_m(1_S)` (with `c = 1_S`, the blocks in `S` ahead by one unit). At `c = 1_S` the
//! median is decided by the sign of `A(S) = sum_S mu^+ - sum_{S^c} mu^-`: if `A(S) < 0` the blocks
//! of `S` slide forward (`f = |S|/N`), otherwise the others slide back (`f = |S|/N - 1`). Hence
//! `f(S) = |S|/N - h(S)`, `h(S) = [w(S) > theta]` with `w_b = mu_b^+ + mu_b^-`,
//! `theta = sum mu^-`, and:
//! - v_m is convex iff `f` is submodular iff `h` is supermodular iff there is no `S` and
//!   `i != j` outside `S` with `w(S) < theta < w(S) + min(w_i, w_j)`;
//! - v_m is concave iff there is no `S`, `i != j` outside `S` with
//!   `w(S) + max(w_i, w_j) < theta < w(S) + w_i + w_j`;
//! - the crawler can move forward iff `f(S) > 0` for some proper `S`, i.e.
//!   `min_b w_b < theta`; backward iff `sum_b w_b - min_b w_b > theta`.

use crate::model::uniqueness::{SubsetSearch, DIRECT_LIMIT};
use crate::model::Crawler;
use serde::Serialize;

/// Shape of v_m.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VmClass {
    /// Convex and concave: v_m is linear (no net motion over any periodic gait).
    Linear,
    /// Convex, not linear.
    Convex,
    /// Concave, not linear.
    Concave,
    /// Neither (e.g. the monkey saddle of Remark 3.3).
    Neither,
    /// Too many distinct friction values to decide exactly (more than the direct enumeration
    /// limit of this module).
    Undetermined,
}

/// Exact facts about v_m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VmAnalysis {
    /// Convex / concave / linear / neither.
    pub class: VmClass,
    /// `v_m(z') > 0` for some `z'`.
    pub moves_forward: bool,
    /// `v_m(z') < 0` for some `z'`.
    pub moves_backward: bool,
    /// A shape rate with `v_m > 0` (the indicator of a subset that slides forward), if any.
    pub forward_witness: Option<Vec<f64>>,
    /// A shape rate with `v_m < 0`, if any.
    pub backward_witness: Option<Vec<f64>>,
}

/// Block velocities and `v_m` for the shape rate `z'` (weighted median, theory §3).
///
/// Unique under the uniqueness condition. `O(N log N)`.
pub fn block_velocities(mu_forward: &[f64], mu_backward: &[f64], zdot: &[f64]) -> (Vec<f64>, f64) {
    let nb = mu_forward.len();
    let mut c = Vec::with_capacity(nb);
    let mut acc = 0.0;
    c.push(0.0);
    for z in zdot {
        acc += z;
        c.push(acc);
    }
    // phi(s) = sum_b R_b(s + c_b) has kinks at s = -c_b; its slope left of every kink is
    // -sum mu^-, and crossing block b's kink adds w_b. The minimiser is the first kink where the
    // slope turns positive.
    let mut order: Vec<usize> = (0..nb).collect();
    order.sort_by(|&a, &b| c[b].total_cmp(&c[a]));
    let mut slope = -mu_backward.iter().sum::<f64>();
    let mut s = -c[order[nb - 1]];
    for &b in &order {
        slope += mu_forward[b] + mu_backward[b];
        if slope > 0.0 {
            s = -c[b];
            break;
        }
    }
    let v: Vec<f64> = c.iter().map(|cb| s + cb).collect();
    let mean = v.iter().sum::<f64>() / nb as f64;
    (v, mean)
}

impl Crawler {
    /// `v_m(z')`: the barycentre velocity produced by the shape rate `z'`.
    pub fn vm(&self, zdot: &[f64]) -> f64 {
        block_velocities(self.mu_forward(), self.mu_backward(), zdot).1
    }

    /// Block velocities `X'` for the shape rate `z'` (with `X'_{b+1} - X'_b = z'_b`).
    pub fn block_velocities(&self, zdot: &[f64]) -> Vec<f64> {
        block_velocities(self.mu_forward(), self.mu_backward(), zdot).0
    }

    /// Decides the class of v_m and the possible directions of motion exactly (module docs).
    pub fn analyze_vm(&self) -> VmAnalysis {
        let (mp, mm) = (self.mu_forward(), self.mu_backward());
        let nb = self.blocks();
        let w: Vec<f64> = mp.iter().zip(mm).map(|(p, m)| p + m).collect();
        let theta: f64 = mm.iter().sum();
        let total: f64 = w.iter().sum();
        // Directions: witnesses are single blocks.
        let imin = (0..nb).min_by(|&a, &b| w[a].total_cmp(&w[b])).unwrap_or(0);
        let shape_of = |set: &dyn Fn(usize) -> bool| -> Vec<f64> {
            (0..nb - 1)
                .map(|l| f64::from(set(l + 1) as u8) - f64::from(set(l) as u8))
                .collect()
        };
        let moves_forward = w[imin] < theta;
        let moves_backward = total - w[imin] > theta;
        let forward_witness = moves_forward.then(|| shape_of(&|b| b == imin));
        let backward_witness = moves_backward.then(|| shape_of(&|b| b != imin));

        let search = SubsetSearch::new(mp, mm);
        let class = if search.enumeration_work() > DIRECT_LIMIT {
            VmClass::Undetermined
        } else {
            let (mut convex, mut concave) = (true, true);
            search.for_each_state(|counts, ws| {
                // Weights available outside S, the two largest and the two largest below r.
                let r = theta - ws;
                if r <= 0.0 {
                    return;
                }
                let (mut top1, mut top2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
                let (mut low1, mut low2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
                for (g, &wg) in search.weight.iter().enumerate() {
                    let avail = (search.members[g].len() - counts[g]).min(2);
                    for _ in 0..avail {
                        if wg > top1 {
                            top2 = top1;
                            top1 = wg;
                        } else if wg > top2 {
                            top2 = wg;
                        }
                        if wg < r {
                            if wg > low1 {
                                low2 = low1;
                                low1 = wg;
                            } else if wg > low2 {
                                low2 = wg;
                            }
                        }
                    }
                }
                if top2 > r {
                    convex = false; // w(S) < theta < w(S) + min(w_i, w_j)
                }
                if low2 > f64::NEG_INFINITY && low1 + low2 > r {
                    concave = false; // w(S) + max < theta < w(S) + w_i + w_j
                }
            });
            match (convex, concave) {
                (true, true) => VmClass::Linear,
                (true, false) => VmClass::Convex,
                (false, true) => VmClass::Concave,
                (false, false) => VmClass::Neither,
            }
        };
        VmAnalysis {
            class,
            moves_forward,
            moves_backward,
            forward_witness,
            backward_witness,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force convexity test of v_m along random segments (midpoint inequality): an
    /// independent check of the subset criterion.
    fn sampled_class(c: &Crawler) -> (bool, bool) {
        let n = c.links();
        let mut seed = 12345u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let (mut convex, mut concave) = (true, true);
        for _ in 0..4000 {
            let a: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let b: Vec<f64> = (0..n).map(|_| rnd()).collect();
            let m: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 0.5 * (x + y)).collect();
            let gap = c.vm(&m) - 0.5 * (c.vm(&a) + c.vm(&b));
            if gap > 1e-12 {
                convex = false;
            }
            if gap < -1e-12 {
                concave = false;
            }
        }
        (convex, concave)
    }

    #[test]
    fn subset_criterion_agrees_with_sampling() {
        let cases = [
            (vec![1.0, 1.0, 1.0], vec![2.5, 2.5, 2.5]),
            (vec![2.5, 2.5, 2.5], vec![1.0, 1.0, 1.0]),
            (vec![1.0, 1.0, 1.0], vec![1.5, 1.5, 1.5]),
            (vec![1.0, 0.3, 2.0, 0.7], vec![3.0, 1.1, 0.4, 2.2]),
            (vec![1.0, 1.2], vec![2.0, 1.7]),
            (vec![1.0, 3.0], vec![2.0, 0.5]),
        ];
        for (mp, mm) in cases {
            let c = Crawler::new(vec![1.0; mp.len() - 1], mp.clone(), mm.clone()).unwrap();
            let a = c.analyze_vm();
            let (cv, cc) = sampled_class(&c);
            let want = match (cv, cc) {
                (true, true) => VmClass::Linear,
                (true, false) => VmClass::Convex,
                (false, true) => VmClass::Concave,
                (false, false) => VmClass::Neither,
            };
            assert_eq!(a.class, want, "{mp:?} {mm:?}");
            if let Some(z) = &a.forward_witness {
                assert!(c.vm(z) > 0.0);
            }
            if let Some(z) = &a.backward_witness {
                assert!(c.vm(z) < 0.0);
            }
        }
    }

    #[test]
    fn one_link_closed_form() {
        // theory §9: both conditions -> v_m(z') = |z'|/2.
        let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
        for z in [-3.0, -0.5, 0.0, 0.25, 4.0] {
            assert_eq!(c.vm(&[z]), 0.5 * f64::abs(z));
        }
    }
}
