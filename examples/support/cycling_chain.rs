//! The heterogeneous long chain of `examples/bench_chains.rs`, `examples/long_chain_study.rs`
//! and `tests/chains.rs`, in one place (included by each with `#[path]`).

use crawlopt::Crawler;

/// A chain of `nb` blocks with per-link stiffness `1 + 0.5 sin(1.7 l)` and the blocks cycling
/// through the first `pairs` (1 to 3) of three friction pairs. Few distinct pairs keep the
/// uniqueness condition exact at N = 100 (it is decided by enumerating the blocks' counts per
/// distinct pair).
#[allow(dead_code)]
pub fn cycling_chain(nb: usize, pairs: usize) -> Crawler {
    let all = [
        (1.0, 1.3),
        (1.0 + 0.1 * 2f64.sqrt(), 1.3 + 0.2 * 2f64.sqrt()),
        (1.0 - 0.1 * 3f64.sqrt(), 1.3 - 0.05 * 3f64.sqrt()),
    ];
    let used = &all[..pairs.clamp(1, 3)];
    let k = (0..nb - 1)
        .map(|l| 1.0 + 0.5 * (1.7 * l as f64).sin())
        .collect();
    let mp = (0..nb).map(|b| used[b % used.len()].0).collect();
    let mm = (0..nb).map(|b| used[b % used.len()].1).collect();
    Crawler::new(k, mp, mm).expect("a valid chain")
}
