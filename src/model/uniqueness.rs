//! The uniqueness condition (theory §2, paper eq. 3.6):
//! `sum_{b in J} mu_b^+ != sum_{b not in J} mu_b^-` for every subset `J` of blocks.
//!
//! Writing `w_b = mu_b^+ + mu_b^-` and `theta = sum_b mu_b^-`, the condition reads
//! `w(J) != theta` for every `J`: a subset-sum question. Blocks with identical friction are
//! interchangeable, so subsets are enumerated as count vectors over groups of identical blocks
//! (a crawler with uniform friction has `N + 1` of them); beyond [`DIRECT_LIMIT`] count vectors
//! the search meets in the middle over two halves of the groups.
//!
//! Decimal inputs such as `0.1` are not exact in binary floating point, so a subset is taken as
//! violating when its two sums agree to a relative [`REL_TOL`]:
//! `|sum_J mu^+ - sum_{J^c} mu^-| <= REL_TOL * (sum_J mu^+ + sum_{J^c} mu^-)`. The tolerance is
//! relative to the two sums compared, not to the sum of all thresholds: with `mu^+ = 1e300` on
//! three blocks and `mu^- = 3`, `J = {}` compares 0 with 9, which no rounding makes equal
//! (a tolerance of `1e-9 * 3e300` called them equal). A crawler whose sums agree that closely
//! has no well-conditioned motion anyway. The test is meaningful in double precision as long as
//! the thresholds are normal numbers (relative precision 1e-16, summed by groups); a subnormal
//! threshold (below 2.2e-308) is refused as undecidable.

/// Relative tolerance below which a subset counts as violating the condition.
pub const REL_TOL: f64 = 1e-9;
/// Largest work (count vectors times groups) of a direct enumeration: a uniform crawler of
/// 10^8 blocks, or 22 distinct friction pairs.
pub const DIRECT_LIMIT: f64 = (1u64 << 27) as f64;
/// Largest number of count vectors in each half of the meet-in-the-middle search.
pub const HALF_LIMIT: f64 = (1u64 << 22) as f64;

/// Outcome of the uniqueness check.
#[derive(Debug, Clone, PartialEq)]
pub enum Uniqueness {
    /// The condition holds; `margin = min_J |sum_J mu^+ - sum_{J^c} mu^-|`, reached at
    /// `closest_subset` (0-based blocks).
    Holds {
        /// The smallest distance to a violation.
        margin: f64,
        /// A subset where it is reached.
        closest_subset: Vec<usize>,
    },
    /// The condition fails for `subset` (0-based blocks).
    Fails {
        /// The violating subset `J`.
        subset: Vec<usize>,
    },
    /// Too many distinct friction values to enumerate.
    Undecided {
        /// Why.
        reason: String,
    },
}

/// Blocks grouped by identical `(mu^+, mu^-)`: a subset is described by how many blocks of each
/// group it takes, which makes uniform or few-valued friction cheap to enumerate exactly.
#[derive(Debug, Clone)]
pub struct SubsetSearch {
    /// `w_g = mu^+ + mu^-` of each group.
    pub weight: Vec<f64>,
    /// Block indices of each group.
    pub members: Vec<Vec<usize>>,
    /// `theta = sum_b mu_b^-`.
    pub theta: f64,
    /// `sum_b w_b`.
    pub total: f64,
}

impl SubsetSearch {
    /// Groups the blocks by identical friction pair.
    pub fn new(mu_forward: &[f64], mu_backward: &[f64]) -> Self {
        let mut keys: Vec<(f64, f64)> = Vec::new();
        let mut members: Vec<Vec<usize>> = Vec::new();
        for (b, (&p, &m)) in mu_forward.iter().zip(mu_backward).enumerate() {
            match keys.iter().position(|&(kp, km)| kp == p && km == m) {
                Some(g) => members[g].push(b),
                None => {
                    keys.push((p, m));
                    members.push(vec![b]);
                }
            }
        }
        let weight: Vec<f64> = keys.iter().map(|&(p, m)| p + m).collect();
        SubsetSearch {
            theta: mu_backward.iter().sum(),
            total: weight
                .iter()
                .zip(&members)
                .map(|(w, m)| w * m.len() as f64)
                .sum(),
            weight,
            members,
        }
    }

    /// Work of enumerating every count vector over all groups (vectors times groups).
    pub fn enumeration_work(&self) -> f64 {
        let all: Vec<usize> = (0..self.weight.len()).collect();
        self.state_count(&all) * self.weight.len() as f64
    }

    /// Number of count vectors over the groups `groups`.
    pub fn state_count(&self, groups: &[usize]) -> f64 {
        groups
            .iter()
            .map(|&g| (self.members[g].len() + 1) as f64)
            .product()
    }

    /// Calls `f(counts, w)` for every count vector over all groups (mixed-radix order), with
    /// `w = sum_g counts[g] w_g`. The caller checks [`Self::state_count`] first.
    pub fn for_each_state(&self, mut f: impl FnMut(&[usize], f64)) {
        let g = self.weight.len();
        let mut counts = vec![0usize; g];
        loop {
            let w: f64 = counts
                .iter()
                .zip(&self.weight)
                .map(|(&c, &w)| c as f64 * w)
                .sum();
            f(&counts, w);
            let mut d = 0;
            loop {
                if d == g {
                    return;
                }
                if counts[d] < self.members[d].len() {
                    counts[d] += 1;
                    break;
                }
                counts[d] = 0;
                d += 1;
            }
        }
    }

    /// The subset of blocks (sorted, 0-based) taking the first `counts[g]` members of group `g`.
    pub fn subset_of(&self, counts: &[usize]) -> Vec<usize> {
        let mut s: Vec<usize> = counts
            .iter()
            .zip(&self.members)
            .flat_map(|(&c, m)| m[..c].iter().copied())
            .collect();
        s.sort_unstable();
        s
    }

    /// The count vectors minimising `|w(J) - theta|` (absolutely) and `|w(J) - theta| / s(J)`
    /// (relatively), where `s(J) = theta + sum_g counts[g] diff[g]` and `diff[g]` is
    /// `mu^+ - mu^-` of group `g`, so that `s(J) = sum_J mu^+ + sum_{J^c} mu^-`, the scale of the
    /// comparison the uniqueness condition makes. Exact for a direct enumeration; the
    /// meet-in-the-middle search finds the relative minimum among the sums adjacent to `theta`
    /// (the same as the absolute one unless friction sums of different subsets differ by
    /// orders of magnitude). `None` when it cannot be enumerated.
    fn closest_pair(&self, diff: &[f64]) -> Option<Closest> {
        if self.enumeration_work() <= DIRECT_LIMIT {
            let mut abs = (f64::INFINITY, Vec::new());
            let mut rel = (f64::INFINITY, Vec::new());
            self.for_each_state(|c, w| {
                let d = (w - self.theta).abs();
                if d < abs.0 {
                    abs = (d, c.to_vec());
                }
                let s = self.theta
                    + c.iter()
                        .zip(diff)
                        .map(|(&c, &dg)| c as f64 * dg)
                        .sum::<f64>();
                let r = d / s.max(f64::MIN_POSITIVE);
                if r < rel.0 {
                    rel = (r, c.to_vec());
                }
            });
            return Some(Closest {
                absolute: abs.1,
                relative: rel.1,
            });
        }
        self.meet_in_the_middle(diff)
    }

    /// Splits the groups in two halves of balanced size, lists the sums of one half sorted and
    /// looks up `theta - s` for every sum `s` of the other ([`Self::closest_pair`]).
    fn meet_in_the_middle(&self, diff: &[f64]) -> Option<Closest> {
        let g = self.weight.len();
        let mut order: Vec<usize> = (0..g).collect();
        order.sort_by_key(|&i| std::cmp::Reverse(self.members[i].len()));
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let (mut ca, mut cb) = (1.0, 1.0);
        for i in order {
            let s = (self.members[i].len() + 1) as f64;
            if ca <= cb {
                a.push(i);
                ca *= s;
            } else {
                b.push(i);
                cb *= s;
            }
        }
        if ca > HALF_LIMIT || cb > HALF_LIMIT {
            return None;
        }
        // Sums of every count vector of a half (w and the sum of diff), with its mixed-radix
        // index (decoded at the end).
        let half = |groups: &[usize]| -> Vec<(f64, f64, u64)> {
            let sub = SubsetSearch {
                weight: groups.iter().map(|&i| self.weight[i]).collect(),
                members: groups.iter().map(|&i| self.members[i].clone()).collect(),
                theta: 0.0,
                total: 0.0,
            };
            let sub_diff: Vec<f64> = groups.iter().map(|&i| diff[i]).collect();
            let mut out = Vec::new();
            sub.for_each_state(|c, w| {
                let idx = out.len() as u64;
                let d = c.iter().zip(&sub_diff).map(|(&c, &dg)| c as f64 * dg).sum();
                out.push((w, d, idx));
            });
            out
        };
        let decode = |groups: &[usize], mut idx: u64, counts: &mut [usize]| {
            for &g in groups {
                let radix = self.members[g].len() as u64 + 1;
                counts[g] = (idx % radix) as usize;
                idx /= radix;
            }
        };
        let mut left = half(&a);
        left.sort_by(|x, y| x.0.total_cmp(&y.0));
        let right = half(&b);
        let mut best: (f64, u64, u64) = (f64::INFINITY, 0, 0);
        let mut best_rel: (f64, u64, u64) = (f64::INFINITY, 0, 0);
        for &(wb, db, jb) in &right {
            let target = self.theta - wb;
            let i = left.partition_point(|(w, _, _)| *w < target);
            for k in [i.saturating_sub(1), i.min(left.len() - 1)] {
                let d = (left[k].0 + wb - self.theta).abs();
                if d < best.0 {
                    best = (d, left[k].2, jb);
                }
                let r = d / (self.theta + left[k].1 + db).max(f64::MIN_POSITIVE);
                if r < best_rel.0 {
                    best_rel = (r, left[k].2, jb);
                }
            }
        }
        let counts = |(_, ia, ib): (f64, u64, u64)| {
            let mut counts = vec![0; g];
            decode(&a, ia, &mut counts);
            decode(&b, ib, &mut counts);
            counts
        };
        Some(Closest {
            absolute: counts(best),
            relative: counts(best_rel),
        })
    }

    /// `(sum_J mu^+, sum_{J^c} mu^-)` of the count vector `counts`, summed by groups (a count
    /// times a threshold is one rounding, so the sums keep their relative precision).
    fn sums_of(&self, counts: &[usize], mu_forward: &[f64], mu_backward: &[f64]) -> (f64, f64) {
        let mut sums = (0.0, 0.0);
        for (g, &c) in counts.iter().enumerate() {
            let first = self.members[g][0];
            let out = self.members[g].len() - c;
            sums.0 += c as f64 * mu_forward[first];
            sums.1 += out as f64 * mu_backward[first];
        }
        sums
    }
}

/// The subsets nearest to a violation of the condition ([`SubsetSearch::closest_pair`]).
struct Closest {
    /// Minimising `|sum_J mu^+ - sum_{J^c} mu^-|`.
    absolute: Vec<usize>,
    /// Minimising that difference relative to `sum_J mu^+ + sum_{J^c} mu^-`.
    relative: Vec<usize>,
}

impl Uniqueness {
    /// Decides the condition for the given friction thresholds.
    ///
    /// A subset violates it when its two sums agree to a relative `REL_TOL` (module docs);
    /// `Undecided` when the subsets are too many to enumerate, or a threshold is subnormal (its
    /// sums have no relative precision to decide with).
    pub fn decide(mu_forward: &[f64], mu_backward: &[f64]) -> Self {
        for (name, mu) in [("mu_forward", mu_forward), ("mu_backward", mu_backward)] {
            if let Some(b) = mu.iter().position(|v| v.is_subnormal()) {
                return Uniqueness::Undecided {
                    reason: format!(
                        "crawler.{name}[{}] = {:e} is below the smallest normal double \
                         (about 2.2e-308), where sums of friction thresholds lose their relative \
                         precision; use larger units of force",
                        b + 1,
                        mu[b]
                    ),
                };
            }
        }
        let search = SubsetSearch::new(mu_forward, mu_backward);
        let diff: Vec<f64> = search
            .members
            .iter()
            .map(|m| mu_forward[m[0]] - mu_backward[m[0]])
            .collect();
        let Some(closest) = search.closest_pair(&diff) else {
            return Uniqueness::Undecided {
                reason: format!(
                    "{} distinct friction pairs among {} blocks exceed the exact enumeration limit; \
                     use fewer distinct (mu_forward, mu_backward) values",
                    search.weight.len(),
                    mu_forward.len()
                ),
            };
        };
        // Recompute the sums of each subset by groups, for honest values.
        let (a, b) = search.sums_of(&closest.relative, mu_forward, mu_backward);
        if (a - b).abs() <= REL_TOL * (a + b) {
            return Uniqueness::Fails {
                subset: search.subset_of(&closest.relative),
            };
        }
        let (a, b) = search.sums_of(&closest.absolute, mu_forward, mu_backward);
        Uniqueness::Holds {
            margin: (a - b).abs(),
            closest_subset: search.subset_of(&closest.absolute),
        }
    }

    /// Whether the condition holds.
    pub fn holds(&self) -> bool {
        matches!(self, Uniqueness::Holds { .. })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(mp: &[f64], mm: &[f64]) -> f64 {
        let n = mp.len();
        (0u32..(1 << n))
            .map(|mask| {
                (0..n)
                    .map(|b| if mask >> b & 1 == 1 { mp[b] } else { -mm[b] })
                    .sum::<f64>()
                    .abs()
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn peers_degenerate_case_is_refused() {
        // N = 5, mu+ = 1, mu- = 1.5: 3 * 1 = 2 * 1.5 (shared/peers/README.md).
        let u = Uniqueness::decide(&[1.0; 5], &[1.5; 5]);
        match u {
            Uniqueness::Fails { subset } => assert_eq!(subset.len(), 3),
            other => panic!("expected failure, got {other:?}"),
        }
        assert!(Uniqueness::decide(&[1.0; 5], &[1.6; 5]).holds());
    }

    #[test]
    fn large_uniform_crawlers_are_decided() {
        // One friction group: N + 1 count vectors, however large N is.
        let n = 5_000_000;
        match Uniqueness::decide(&vec![1.0; n], &vec![2.5; n]) {
            Uniqueness::Holds { margin, .. } => assert!(margin > 0.1, "{margin}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn decimal_inputs_count_as_violations() {
        // 0.1 + 0.2 != 0.3 in binary, but J = {1, 2} violates the condition mathematically.
        let u = Uniqueness::decide(&[0.1, 0.2, 5.0], &[7.0, 7.0, 0.3]);
        assert!(matches!(u, Uniqueness::Fails { .. }), "{u:?}");
    }

    #[test]
    fn margin_matches_brute_force_and_mitm() {
        // Distinct values in every block: 2^12 count vectors directly; then force the
        // meet-in-the-middle path by calling it on the same data.
        let mp: Vec<f64> = (0..12).map(|i| 1.0 + (i as f64).sqrt() * 0.37).collect();
        let mm: Vec<f64> = (0..12)
            .map(|i| 2.0 + (0.11 * i as f64 + 0.5).ln())
            .collect();
        let want = brute(&mp, &mm);
        match Uniqueness::decide(&mp, &mm) {
            Uniqueness::Holds { margin, .. } => assert!((margin - want).abs() < 1e-12),
            other => panic!("{other:?}"),
        }
        let s = SubsetSearch::new(&mp, &mm);
        let c = s.meet_in_the_middle(&[0.0; 12]).unwrap().absolute;
        let w: f64 = c.iter().zip(&s.weight).map(|(&c, &w)| c as f64 * w).sum();
        assert!(((w - s.theta).abs() - want).abs() < 1e-12);
    }

    #[test]
    fn extreme_thresholds_are_compared_at_their_own_scale() {
        // mu+ = 1e300: J = {} compares 0 with 9, far from equal, and no other J comes close.
        match Uniqueness::decide(&[1e300; 3], &[3.0; 3]) {
            Uniqueness::Holds {
                margin,
                closest_subset,
            } => {
                assert_eq!(margin, 9.0);
                assert!(closest_subset.is_empty());
            }
            other => panic!("{other:?}"),
        }
        // mu- = 1e-300: J = {} compares 0 with 3e-300, which is not 0.
        match Uniqueness::decide(&[1.0; 3], &[1e-300; 3]) {
            Uniqueness::Holds { margin, .. } => assert_eq!(margin, 3e-300),
            other => panic!("{other:?}"),
        }
        // A true violation at an extreme scale is still one: 1e300 + 1e300 = 2e300.
        let u = Uniqueness::decide(&[1e300, 1e300, 5e300], &[9e300, 9e300, 2e300]);
        assert_eq!(u, Uniqueness::Fails { subset: vec![0, 1] });
        // ... also through the meet in the middle.
        let (mp, mm) = ([1e300, 1e300, 5e300], [9e300, 9e300, 2e300]);
        let s = SubsetSearch::new(&mp, &mm);
        let diff: Vec<f64> = s.members.iter().map(|m| mp[m[0]] - mm[m[0]]).collect();
        let c = s.meet_in_the_middle(&diff).unwrap();
        assert_eq!(s.subset_of(&c.relative), vec![0, 1]);
        // Decimal inputs at a tiny scale violate as they do at scale 1.
        let u = Uniqueness::decide(&[0.1e-200, 0.2e-200, 5.0e-200], &[7e-200, 7e-200, 0.3e-200]);
        assert!(matches!(u, Uniqueness::Fails { .. }), "{u:?}");
    }

    #[test]
    fn subnormal_thresholds_are_undecided() {
        let u = Uniqueness::decide(&[1.0, 1e-310], &[2.0, 2.0]);
        match u {
            Uniqueness::Undecided { reason } => {
                assert!(
                    reason.contains("crawler.mu_forward[2] = 1e-310"),
                    "{reason}"
                )
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn relative_and_absolute_closest_agree_with_brute_force() {
        // Random-ish thresholds over six orders of magnitude: the decision equals the brute
        // force of the relative test over all subsets.
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for case in 0..300 {
            let n = 2 + case % 7;
            let pick = |r: f64| [1e-3, 0.5, 1.0, 1.5, 2.0, 1e3][(r * 6.0) as usize % 6];
            let mp: Vec<f64> = (0..n).map(|_| pick(rnd())).collect();
            let mm: Vec<f64> = (0..n).map(|_| pick(rnd())).collect();
            let violated = (0u32..(1 << n)).any(|mask| {
                let (mut a, mut b) = (0.0, 0.0);
                for i in 0..n {
                    if mask >> i & 1 == 1 {
                        a += mp[i];
                    } else {
                        b += mm[i];
                    }
                }
                (a - b).abs() <= REL_TOL * (a + b)
            });
            let u = Uniqueness::decide(&mp, &mm);
            assert_eq!(!u.holds(), violated, "{mp:?} {mm:?}: {u:?}");
            if let Uniqueness::Holds { margin, .. } = u {
                assert!((margin - brute(&mp, &mm)).abs() < 1e-9, "{mp:?} {mm:?}");
            }
        }
    }
}
