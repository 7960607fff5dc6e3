//! Resource limits of the optimisers: a model whose size would exhaust memory (or that HiGHS
//! could not even build and presolve in minutes) is refused before anything is allocated,
//! naming the limit.
//!
//! Every optimiser builds one LP or MILP whose columns and rows grow with blocks x steps
//! (`2^m` grid steps of P_m, or `K` slip phases of a phase gait): measured, HiGHS holds about
//! 6-15 KB per block-step once the model is built and presolved (three blocks on 2^16 steps:
//! 1.45 GB; 100 blocks on 2^10 steps: 0.63 GB; 1000 blocks and 64 phases: 0.94 GB), and more
//! as branch and bound proceeds. A model of 10^4 blocks and one phase took 47 s to build and
//! presolve, whatever the time limit (5 s), and 10^6 blocks ended in `std::bad_alloc`.

use crate::error::{Error, Result};
use crate::model::Crawler;

/// Most blocks an optimiser accepts. Beyond it the MILPs find no feasible gait within
/// minutes (1000 blocks: none after 2 s for one phase), and building and presolving the model
/// alone outlasts a time limit (10^4 blocks: 47 s).
pub const MAX_OPT_BLOCKS: usize = 1000;

/// Most block-steps (blocks x grid steps `2^m`, or blocks x slip phases `K`) of one
/// optimisation model: at the measured 6-15 KB per block-step, 2 to 4 GB. It admits P_16 up
/// to four blocks, the local method's P_14 up to 16 blocks, and 64 phases up to 1000 blocks.
pub const MAX_BLOCK_STEPS: usize = 1 << 18;

/// Most time shifts of the local method's start (`--shifts`): each shift is a whole local
/// solve (the default is 8).
pub const MAX_SHIFTS: usize = 256;

/// Refuses an optimisation model of `crawler` over `steps` grid steps or slip phases that
/// exceeds [`MAX_OPT_BLOCKS`] or [`MAX_BLOCK_STEPS`]; `field` and `value` name what sets
/// `steps` (e.g. `m` and `16`, or `phases` and `64`).
pub fn check_size(
    crawler: &Crawler,
    steps: usize,
    field: &str,
    value: impl ToString,
) -> Result<()> {
    let nb = crawler.blocks();
    if nb > MAX_OPT_BLOCKS {
        return Err(Error::invalid(
            "crawler.blocks",
            nb,
            format!(
                "the optimisers accept at most {MAX_OPT_BLOCKS} blocks (their models of more \
                 cannot be built and presolved within minutes, or exhaust memory)"
            ),
        ));
    }
    if nb.saturating_mul(steps) > MAX_BLOCK_STEPS {
        return Err(Error::invalid(
            field,
            value,
            format!(
                "{nb} blocks x {steps} steps exceed the optimisers' limit of {MAX_BLOCK_STEPS} \
                 block-steps (memory: their models take 6-15 KB per block-step)"
            ),
        ));
    }
    Ok(())
}

/// Refuses a number of time shifts of the local method's start outside `1..=MAX_SHIFTS`.
pub fn check_shifts(shifts: usize) -> Result<()> {
    if !(1..=MAX_SHIFTS).contains(&shifts) {
        return Err(Error::invalid(
            "shifts",
            shifts,
            format!("must be in 1..={MAX_SHIFTS} (each shift is one local solve)"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_refused_by_name() {
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        assert!(check_size(&c, 1 << 16, "m", 16).is_ok());
        let c5 = Crawler::uniform(5, 1.0, 1.0, 1.6).unwrap();
        let e = check_size(&c5, 1 << 16, "m", 16).unwrap_err().to_string();
        assert!(e.starts_with("m: ") && e.contains("262144"), "{e}");
        let big = Crawler::uniform(MAX_OPT_BLOCKS + 1, 1.0, 1.0, 3.3).unwrap();
        let e = check_size(&big, 1, "phases", 1).unwrap_err().to_string();
        assert!(
            e.starts_with("crawler.blocks: ") && e.contains("1000"),
            "{e}"
        );
        assert!(check_shifts(MAX_SHIFTS).is_ok());
        for s in [0, MAX_SHIFTS + 1, usize::MAX] {
            let e = check_shifts(s).unwrap_err().to_string();
            assert!(e.starts_with("shifts: "), "{e}");
        }
    }
}
