//! The noise of a trajectory and the slips of its blocks.
//!
//! A block slides forward only while its spring force equals `mu^+` (theory §2, the flow
//! rule). From positions alone, a block is seen moving over a sample interval when it moves by
//! more than the slip threshold, which no noise within the bound can fake; a sample is taken as
//! *sliding* when the block moves the same way over both intervals around it. That survives the
//! three defects of real data: noise (a still block never crosses the threshold), coarse
//! sampling (a slide that begins or ends inside an interval leaves the sample at its edge out,
//! where the force may still be below the threshold) and isolated outliers (a jump of one
//! sample moves the block one way then back, which is never the same way on both sides).

use super::data::FitData;
use super::result::SlipEpisode;

/// `sigma`, estimated from the data: each position is compared with the linear interpolation
/// of its two neighbours, the difference scaled to unit variance for unit noise, and the
/// median of its absolute value over every block and interior sample turned into a standard
/// deviation (`1.4826 * median`, exact for Gaussian noise). Where the motion is piecewise
/// linear, the differences vanish except at kinks, which the median ignores; curvature between
/// frames counts as noise (conservative: larger intervals).
pub fn estimate_noise(data: &FitData) -> f64 {
    let m = data.samples();
    let mut r = Vec::with_capacity(m * data.blocks());
    for i in 1..m - 1 {
        let (t0, t1, t2) = (data.t[i - 1], data.t[i], data.t[i + 1]);
        let w = (t2 - t1) / (t2 - t0);
        let scale = (1.0 + w * w + (1.0 - w) * (1.0 - w)).sqrt();
        for b in 0..data.blocks() {
            let (x0, x1, x2) = (
                data.positions[i - 1][b],
                data.positions[i][b],
                data.positions[i + 1][b],
            );
            r.push((x1 - (w * x0 + (1.0 - w) * x2)).abs() / scale);
        }
    }
    if r.is_empty() {
        return 0.0;
    }
    r.sort_by(f64::total_cmp);
    1.4826 * r[r.len() / 2]
}

/// Slips per block.
#[derive(Debug, Clone)]
pub struct Slips {
    /// `sliding[i][b]`: 1 when block `b` slides forward at sample `i`, -1 backward, 0 when
    /// nothing is known (stuck, or at the edge of a slide).
    pub sliding: Vec<Vec<i8>>,
    /// Per block, the runs of moving intervals.
    pub episodes: Vec<Vec<SlipEpisode>>,
}

/// The slips of every block with the threshold `threshold` (length units).
pub fn detect(data: &FitData, threshold: f64) -> Slips {
    let (m, nb) = (data.samples(), data.blocks());
    let mut sliding = vec![vec![0i8; nb]; m];
    let mut episodes = vec![Vec::new(); nb];
    for (b, eps) in episodes.iter_mut().enumerate() {
        let dir: Vec<i8> = (0..m - 1)
            .map(|i| {
                let dx = data.positions[i + 1][b] - data.positions[i][b];
                if dx > threshold {
                    1
                } else if dx < -threshold {
                    -1
                } else {
                    0
                }
            })
            .collect();
        for i in 1..m - 1 {
            if dir[i - 1] != 0 && dir[i - 1] == dir[i] {
                sliding[i][b] = dir[i];
            }
        }
        // Runs of intervals moving the same way: intervals j..k span rows j..k+1.
        let mut j = 0;
        while j < m - 1 {
            if dir[j] == 0 {
                j += 1;
                continue;
            }
            let mut k = j;
            while k + 1 < m - 1 && dir[k + 1] == dir[j] {
                k += 1;
            }
            eps.push(SlipEpisode {
                direction: if dir[j] > 0 { "forward" } else { "backward" },
                rows: [j + 1, k + 2],
                times: [data.t[j], data.t[k + 1]],
                samples_used: k - j,
            });
            j = k + 1;
        }
    }
    Slips { sliding, episodes }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data(x: &[f64]) -> FitData {
        let m = x.len();
        FitData::new(
            2,
            (0..m).map(|i| i as f64).collect(),
            vec![vec![0.0]; m],
            x.iter().map(|&v| vec![0.0, v]).collect(),
        )
        .unwrap()
    }

    #[test]
    fn a_single_outlier_makes_no_sliding_sample() {
        let d = data(&[0.0, 0.0, 0.0, 5.0, 0.0, 0.0, 0.0]);
        let s = detect(&d, 0.1);
        assert!(s.sliding.iter().all(|r| r[1] == 0), "{:?}", s.sliding);
        assert_eq!(s.episodes[1].len(), 2);
    }

    #[test]
    fn interior_samples_of_a_slide_are_sliding_and_its_edges_are_not() {
        let d = data(&[0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]);
        let s = detect(&d, 0.1);
        let col: Vec<i8> = s.sliding.iter().map(|r| r[1]).collect();
        assert_eq!(col, vec![0, 0, 1, 1, 0, 0, 0]);
        assert_eq!(s.episodes[1][0].rows, [2, 5]);
        assert_eq!(s.episodes[1][0].samples_used, 2);
    }

    #[test]
    fn the_noise_of_a_still_block_is_estimated() {
        // Alternating +-s around 0: each residual is 2s / sqrt(1.5).
        let s = 1e-3;
        let x: Vec<f64> = (0..201).map(|i| if i % 2 == 0 { s } else { -s }).collect();
        let est = estimate_noise(&data(&x));
        assert!(
            (est - 1.4826 * 2.0 * s / 1.5f64.sqrt()).abs() < 1e-12,
            "{est}"
        );
    }
}
