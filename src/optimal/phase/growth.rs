//! Raising `K` until the value stops improving ([`grow_phases`]): the crawler's phase gaits as
//! a [`PhaseFamily`] of the growth written once for every family ([`crate::optimal::growth`]).

use super::solve::{gain_tolerance, solve_phase_with};
use super::{start_unproven, Formulation, PhaseOptions, PhaseSolution, MAX_PHASES};
use crate::error::Result;
use crate::model::Crawler;
use crate::optimal::growth::{GrowthRange, PhaseFamily};
pub use crate::optimal::growth::{GrowthStop, PhaseStep};
use crate::optimal::milp::check_time_limit;
use crate::optimal::{Certificate, GaitProblem};

/// The last `K` a growth tries unless told ([`GrowOptions::max_phases`]; the one definition
/// of this default: the CLI's `--max-phases`, Python's `max_phases=` and a sweep's
/// `max_phases` leave it to the library).
pub const DEFAULT_MAX_PHASES: usize = 8;

/// Consecutive `K` without a gain that end a growth unless told ([`GrowOptions::patience`]).
pub const DEFAULT_PATIENCE: usize = 2;

/// How [`grow_phases`] raises `K`.
#[derive(Debug, Clone, PartialEq)]
pub struct GrowOptions {
    /// First `K`.
    pub min_phases: usize,
    /// Last `K` tried.
    pub max_phases: usize,
    /// Stop after this many consecutive `K` without a gain, counted once `J_K` moves the crawler
    /// (above [`MOVE_RESOLUTION`](crate::optimal::growth::MOVE_RESOLUTION) times the length scale;
    /// before, `K` is too small for any gait to move the crawler, e.g. one link needs 2 slip
    /// phases). The default is 2: plateaus `J_K = J_{K+1} < J_{K+2}` occur (a 4-block crawler with
    /// per-block friction had `J_3 = J_4 = 6.575 < J_5 = 6.600`).
    pub patience: usize,
    /// Wall-clock limit for the whole growth, seconds (from its start, within the job's
    /// deadline: [`crate::progress::within`]).
    pub time_limit: Option<f64>,
    /// A known gait to start from (e.g. the best structured gait, through
    /// [`phase_gait_of`](super::phase_gait_of)): the best gait before the first `K`, so every
    /// MILP takes it as its incumbent where it fits and as a cutoff where it has more slip
    /// phases than `K` ([`PhaseOptions::start`]). A `K` whose MILP proves that nothing of at
    /// most `K` slip phases beats it does not count towards `patience`. Default: none.
    pub start: Option<PhaseSolution>,
    /// Optional valid rows of every MILP.
    pub formulation: Formulation,
}

impl Default for GrowOptions {
    fn default() -> Self {
        GrowOptions {
            min_phases: 1,
            max_phases: DEFAULT_MAX_PHASES,
            patience: DEFAULT_PATIENCE,
            time_limit: None,
            start: None,
            formulation: Formulation::default(),
        }
    }
}

impl GrowOptions {
    /// Refuses options no growth can run with: `1 <= min_phases <= max_phases <= MAX_PHASES`,
    /// `patience >= 1`, a positive finite time limit.
    pub fn check(&self) -> Result<()> {
        check_time_limit(self.time_limit)?;
        self.range().check(MAX_PHASES)
    }

    /// The range of `K` and the patience.
    fn range(&self) -> GrowthRange {
        GrowthRange {
            min_phases: self.min_phases,
            max_phases: self.max_phases,
            patience: self.patience,
        }
    }
}

/// The result of [`grow_phases`].
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseGrowth {
    /// The best gait, certified for the last `K` solved to optimality (`best.phases`).
    pub best: PhaseSolution,
    /// Every `K` solved.
    pub table: Vec<PhaseStep>,
    /// Why it stopped.
    pub stop: GrowthStop,
}

/// Raises `K` from `min_phases` until `J_K` has not improved (by more than a relative `1e-7`,
/// or the outer-approximation tolerance `1e-6` with a quadratic cost, whose values are only
/// that accurate) for `patience` consecutive `K`, or `max_phases` or the time limit is reached
/// (module docs). The returned gait is the best found, and its certificate is that of the largest
/// `K` solved: `optimal_among_k_phases` when that `K` was solved to optimality (the gait has at
/// most that many slip phases, and no gait of that many does better than the bound),
/// `dominates_k_phases` when the gait is the start, of more slip phases than that `K`, and no gait
/// of at most `K` beats it, `time_limit` with that `K`'s bound and gap when the limit cut its MILP
/// short. `progress` sees each `K` as it
/// is solved.
pub fn grow_phases(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &GrowOptions,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<PhaseGrowth> {
    opts.check()?;
    crate::progress::within(opts.time_limit, || grow(crawler, problem, opts, progress))
}

/// The crawler's phase gaits as a [`PhaseFamily`]: one `K` is [`solve_phase_with`], started
/// from the best gait so far.
struct ChainPhases<'a> {
    crawler: &'a Crawler,
    problem: &'a GaitProblem,
    formulation: Formulation,
}

impl PhaseFamily for ChainPhases<'_> {
    type Gait = PhaseSolution;

    fn solve(&self, k: usize, best: Option<&PhaseSolution>) -> Result<PhaseSolution> {
        let opts = PhaseOptions {
            start: best.cloned(),
            cutoff: None,
            formulation: self.formulation,
        };
        solve_phase_with(self.crawler, self.problem, k, &opts)
    }
    fn objective(g: &PhaseSolution) -> f64 {
        g.objective()
    }
    fn claim(g: &mut PhaseSolution) -> (&mut usize, &mut Certificate) {
        (&mut g.phases, &mut g.certificate)
    }
    fn length_scale(&self) -> f64 {
        self.problem.length_scale(self.crawler)
    }
    fn j_floor(&self) -> f64 {
        self.problem.j_floor(self.crawler)
    }
    fn gain_tolerance(&self) -> f64 {
        gain_tolerance(self.problem)
    }
    // y' = v_m(z') (theory §3): when v_m <= 0 everywhere, J <= 0 for every gait.
    fn idle(&self) -> bool {
        self.crawler.analyze().moves_forward == Some(false)
    }
    fn same(a: &PhaseSolution, b: &PhaseSolution) -> bool {
        a.durations == b.durations && a.states == b.states
    }
    fn unproven(&self, g: &PhaseSolution, phases: usize) -> PhaseSolution {
        start_unproven(self.crawler, self.problem, g, phases)
    }
}

/// [`grow_phases`], options checked, within the current deadline.
fn grow(
    crawler: &Crawler,
    problem: &GaitProblem,
    opts: &GrowOptions,
    progress: &mut dyn FnMut(&PhaseStep),
) -> Result<PhaseGrowth> {
    let family = ChainPhases {
        crawler,
        problem,
        formulation: opts.formulation,
    };
    let mut g = crate::optimal::growth::grow(&family, opts.range(), opts.start.clone(), progress)?;
    // A start kept over a larger K's in-class optimum took that K's claim.
    g.best.settle_claim();
    Ok(PhaseGrowth {
        best: g.best,
        table: g.table,
        stop: g.stop,
    })
}
