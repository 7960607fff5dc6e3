//! Slip modes (which are faces of C), and local search over sequences of them
//! ([`search_sequences`]).

use super::check_phase_args;
use super::layout::ExtraRows;
use super::solve::{gain_tolerance, solve_steps};
use super::PhaseSolution;
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::{GaitProblem, LocalStop};

/// Whether a slip mode (per block `-1`, `0`, `1`) names a nonempty face of C on which some
/// block slips.
///
/// The forces `F_b` sum to zero and determine `x` (`x_l = -sum_{b <= l} F_b`). The face holds
/// `F_b = mu_b^+` on the blocks `S+` slipping forward, `F_b = -mu_b^-` on `S-`, and leaves the
/// others free in `[-mu_b^-, mu_b^+]`; it is nonempty iff
/// `-sum_free mu^+ <= sum_{S+} mu^+ - sum_{S-} mu^- <= sum_free mu^-` with some block free (with
/// none, equality would violate the uniqueness condition).
pub fn slip_mode_is_valid(crawler: &Crawler, mode: &[i8]) -> bool {
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    if mode.len() != mp.len() || mode.iter().any(|&m| !(-1..=1).contains(&m)) {
        return false;
    }
    let (mut held, mut free_p, mut free_m, mut slipping) = (0.0, 0.0, 0.0, 0);
    for (b, &m) in mode.iter().enumerate() {
        match m {
            1 => held += mp[b],
            -1 => held -= mm[b],
            _ => {
                free_p += mp[b];
                free_m += mm[b];
            }
        }
        slipping += usize::from(m != 0);
    }
    slipping > 0 && slipping < mode.len() && -free_p <= held && held <= free_m
}

/// The valid slip modes that differ from `mode` in one or two blocks.
pub(super) fn neighbours(crawler: &Crawler, mode: &[i8]) -> Vec<Vec<i8>> {
    let nb = mode.len();
    let mut out: Vec<Vec<i8>> = Vec::new();
    let mut push = |m: Vec<i8>| {
        if slip_mode_is_valid(crawler, &m) && !out.contains(&m) {
            out.push(m);
        }
    };
    for b in 0..nb {
        for vb in [-1i8, 0, 1] {
            if vb == mode[b] {
                continue;
            }
            let mut m = mode.to_vec();
            m[b] = vb;
            push(m.clone());
            for c in b + 1..nb {
                for vc in [-1i8, 0, 1] {
                    if vc != mode[c] {
                        let mut m2 = m.clone();
                        m2[c] = vc;
                        push(m2);
                    }
                }
            }
        }
    }
    out
}

/// The result of [`search_sequences`].
#[derive(Debug, Clone, PartialEq)]
pub struct SequenceSearch {
    /// The best gait found: optimal for its sequence of slip modes (an LP), no global claim.
    pub best: PhaseSolution,
    /// Its sequence of slip modes, one per step (some steps may be empty in the gait).
    pub sequence: Vec<Vec<i8>>,
    /// `J` of the start sequence (its LP optimum, at least the start gait's `J`).
    pub start_objective: f64,
    /// LPs solved.
    pub lp_solves: usize,
    /// Improving moves made.
    pub moves: usize,
    /// Why it stopped: [`LocalStop::Stationary`] when no single move improves, or the time
    /// limit.
    pub stop: LocalStop,
}

/// Local search over the sequences of slip modes of phase gaits with `phases` steps, for crawlers
/// or `K` where the MILP is too slow (theory §7: "local search over sequences scales further").
///
/// For a fixed cyclic sequence, the best gait following it is an LP (the MILP of the module docs
/// with its binaries fixed), so every candidate is an exact continuous-time gait, solved to
/// optimality for its sequence and re-verified by the exact simulator. A move replaces the mode of
/// one step by a valid mode differing in one or two blocks ([`slip_mode_is_valid`]); the first
/// improving move is taken, scanning the steps cyclically, until a whole cycle brings none (a local
/// optimum for these moves) or the time limit. The start sequence is `start_modes` (e.g. the
/// [`slip_sequence`](super::slip_sequence) of a gait), each mode repeated in turn until there are
/// `phases` steps: a repeated mode is a slip phase that may stay empty, so the start's value is
/// kept. An empty start (an idle gait) is seeded with each block slipping forward in turn, from the
/// front (where that is a face of C; else one block slipping).
pub fn search_sequences(
    crawler: &Crawler,
    problem: &GaitProblem,
    start_modes: &[Vec<i8>],
    phases: usize,
) -> Result<SequenceSearch> {
    check_phase_args(crawler, problem, phases)?;
    // An idle start has no slip phase: seed it with each block slipping forward in turn, from
    // the front (a peristaltic wave), or one block slipping; the LP may leave them all empty
    // (the idle gait held on a face), so nothing is lost.
    let seed: Vec<Vec<i8>>;
    let start_modes = if start_modes.is_empty() {
        let nb = crawler.blocks();
        let single = (0..nb).rev().flat_map(|b| {
            [1i8, -1].map(|s| {
                let mut m = vec![0i8; nb];
                m[b] = s;
                m
            })
        });
        let forward: Vec<Vec<i8>> = single
            .clone()
            .filter(|m| m.contains(&1) && slip_mode_is_valid(crawler, m))
            .take(phases)
            .collect();
        seed = if forward.is_empty() {
            single
                .filter(|m| slip_mode_is_valid(crawler, m))
                .take(1)
                .collect()
        } else {
            forward
        };
        &seed[..]
    } else {
        start_modes
    };
    if start_modes.is_empty() || start_modes.len() > phases {
        return Err(Error::invalid(
            "start",
            format!("{} slip phases", start_modes.len()),
            format!("needs 1 to {phases} slip phases, the length of the sequences searched"),
        ));
    }
    if let Some(m) = start_modes.iter().find(|m| !slip_mode_is_valid(crawler, m)) {
        return Err(Error::invalid(
            "start",
            format!("{m:?}"),
            "is not a slip mode of a face of C",
        ));
    }
    let mut seq: Vec<Vec<i8>> = Vec::with_capacity(phases);
    for (i, m) in start_modes.iter().enumerate() {
        seq.push(m.clone());
        let extra = (phases - start_modes.len()) / start_modes.len()
            + usize::from(i < (phases - start_modes.len()) % start_modes.len());
        seq.extend(std::iter::repeat_n(m.clone(), extra));
    }
    search_from(crawler, problem, start_modes, seq)
}

/// [`search_sequences`] from the sequence `seq` (grown from `start_modes`, checked), within
/// the current deadline.
fn search_from(
    crawler: &Crawler,
    problem: &GaitProblem,
    start_modes: &[Vec<i8>],
    mut seq: Vec<Vec<i8>>,
) -> Result<SequenceSearch> {
    let phases = seq.len();
    let mut lp_solves = 1;
    if crate::progress::out_of_time()? {
        return Err(Error::TimeLimit(
            "sequence search: the time limit was reached before any gait was found".into(),
        ));
    }
    let mut best = solve_steps(
        crawler,
        problem,
        phases,
        None,
        Some(&seq),
        &ExtraRows::default(),
    )
    .map_err(|e| match e {
        Error::Infeasible(_) => Error::invalid(
            "start",
            format!("{} slip phases", start_modes.len()),
            "no gait of the period follows this sequence of slip modes",
        ),
        e => e,
    })?;
    let start_objective = best.objective();
    let (mut moves, mut quiet, mut j) = (0, 0, 0);
    let stop = 'search: loop {
        let mut improved = false;
        for cand in neighbours(crawler, &seq[j]) {
            if crate::progress::out_of_time()? {
                break 'search LocalStop::TimeLimit;
            }
            let mut next = seq.clone();
            next[j] = cand;
            lp_solves += 1;
            match solve_steps(
                crawler,
                problem,
                phases,
                None,
                Some(&next),
                &ExtraRows::default(),
            ) {
                Ok(s)
                    if s.objective()
                        > best.objective()
                            + gain_tolerance(problem)
                                * best.objective().abs().max(problem.length_scale(crawler)) =>
                {
                    best = s;
                    seq = next;
                    improved = true;
                    break;
                }
                // A sequence no gait can follow, or whose LP answer the simulator does not
                // reproduce, is no candidate; the search goes on.
                Ok(_) | Err(Error::Infeasible(_) | Error::Numerical(_)) => {}
                Err(Error::TimeLimit(_)) => break 'search LocalStop::TimeLimit,
                Err(e) => return Err(e),
            }
        }
        if improved {
            moves += 1;
            quiet = 0;
        } else {
            quiet += 1;
            if quiet >= phases {
                break LocalStop::Stationary;
            }
        }
        j = (j + 1) % phases;
    };
    Ok(SequenceSearch {
        best,
        sequence: seq,
        start_objective,
        lp_solves,
        moves,
        stop,
    })
}
