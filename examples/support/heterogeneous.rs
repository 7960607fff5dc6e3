//! The heterogeneous chains of `tests/orbit.rs` and `examples/heterogeneous_chains.rs`, in one
//! place (included by both with `#[path]`).

use crawlopt::integrate::{Actuation, Waveform};
use crawlopt::Crawler;

/// A heterogeneous chain of `nb` blocks: per-link stiffness in [0.5, 2], four friction pairs
/// (mu+ in {0.75, 1}, mu- in {2.5, 3.5}; the uniqueness check enumerates distinct pairs, and
/// mu- off the grid of mu+ by 1/(8 N) keeps the uniqueness condition with a margin), drawn
/// from `seed`, under a sine wave of amplitude 1.5 and 60 degrees per link.
pub fn heterogeneous_chain(nb: usize, seed: u64) -> Result<(Crawler, Actuation), crawlopt::Error> {
    let n = nb - 1;
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let k: Vec<f64> = (0..n).map(|_| 0.5 + 1.5 * next()).collect();
    let mp: Vec<f64> = (0..nb)
        .map(|_| if next() < 0.5 { 0.75 } else { 1.0 })
        .collect();
    let mm: Vec<f64> = (0..nb)
        .map(|_| if next() < 0.5 { 2.5 } else { 3.5 } + 1.0 / (8.0 * nb as f64))
        .collect();
    let c = Crawler::new(k, mp, mm)?;
    let phases = (0..n).map(|l| l as f64 * 60.0).collect();
    let a = Actuation::wave(Waveform::Sine, 1.0, vec![0.0; n], vec![1.5; n], phases)?;
    Ok((c, a))
}
