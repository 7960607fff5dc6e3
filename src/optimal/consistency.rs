//! Is a recorded gait a process of its problem? The checks every reader of a gait runs before
//! it shows, replays or certifies it: [`GaitResult::from_json`](super::GaitResult::from_json)
//! (and so `certify`, `plot`, `report` and `--start`) and the certificate's own
//! [`Process`](crate::certify::Process). A result file is data from elsewhere: every field that
//! repeats what others determine is checked against them here, never trusted. Whether the gait
//! is a process at all is [`ProcessView::check`]'s question: (P)'s conditions on the crawler's
//! instance, the one check of (P)'s processes ([`super::process`]).

pub(crate) use super::gait_process::bad;
pub(crate) use super::gait_process::check_durations;
pub use super::gait_process::ProcessView;
use crate::error::Result;
use crate::model::Crawler;
use crate::optimal::envelope::SolutionKind;
use crate::optimal::milp::control_knots;
use crate::optimal::process::max_diff;
pub use crate::optimal::process::ProcessKind;
use crate::optimal::{
    replay, Certificate, GaitResult, MilpStatus, ResultCertificate, ResultRecords,
};

pub use super::envelope::INPUT_TOL;

/// The largest gap of an `optimal_among_k_phases` or `dominates_k_phases` claim in a result
/// file: ten times the outer approximation's tolerance on a quadratic cost (`1e-6`, within which
/// such a MILP counts as closed); beyond it the claim is a `time_limit` or `approximation_limit`.
pub const PHASE_CLAIM_GAP: f64 = 1e-5;

/// Slip direction of a displacement with a tolerance.
pub(crate) fn slip(d: f64, tol: f64) -> i8 {
    if d > tol {
        1
    } else if d < -tol {
        -1
    } else {
        0
    }
}

impl GaitResult {
    /// Checks that a result is what it says (module docs), with relative tolerance
    /// [`INPUT_TOL`]: the method and `m`; the problem within the optimisers' range; the gait a
    /// process of the problem ([`ProcessView::check`]); every redundant field against what
    /// determines it (knot times and the initial state against durations and states, actuator
    /// lengths against the controls, slip modes against displacements and active faces); the
    /// displacement, cost and objective recomputed, the displacement replayed by the simulator
    /// that verified it; the certificate's bound and gap against the objective; the growth and
    /// convergence tables against the objective and their own invariants. `what` names the
    /// source in errors.
    pub fn check_consistent(&self, what: &str) -> Result<()> {
        let in_problem = |e| super::envelope::in_problem(e, what);
        let crawler = self.crawler.crawler().map_err(in_problem)?;
        crawler.require_unique()?;
        self.problem.check_scales(&crawler).map_err(in_problem)?;
        let kind = self.process_kind(what)?;
        let g = &self.gait;
        let view = ProcessView {
            crawler: &crawler,
            problem: &self.problem,
            kind,
            durations: &g.durations,
            controls: &g.controls,
            states: &g.states,
            block_displacements: &g.block_displacements,
        };
        view.check(what, INPUT_TOL)?;
        self.check_repeated(&crawler, what)?;
        self.check_slip_modes(&crawler, kind, what)?;
        let t = self.problem.period;
        let len_scale = self.problem.length_scale(&crawler);
        // Displacement, cost and objective: recomputed, and replayed.
        let nb = crawler.blocks() as f64;
        let moved: f64 = g
            .block_displacements
            .iter()
            .map(|d| d.iter().sum::<f64>() / nb)
            .sum();
        let cost: f64 = g
            .durations
            .iter()
            .zip(&g.controls)
            .map(|(d, u)| d * self.problem.cost.eval(u))
            .sum();
        let increments: Vec<Vec<f64>> = g
            .durations
            .iter()
            .zip(&g.controls)
            .map(|(d, u)| u.iter().map(|v| v * d).collect())
            .collect();
        let sim = replay(
            &crawler,
            t,
            &g.durations,
            &increments,
            Some(&g.states[0]),
            self.verified_with(),
            what,
        )?;
        let replayed = sim.displacement_per_period.unwrap_or(f64::NAN);
        let j_scale = len_scale.max(moved.abs()).max(cost.abs());
        let close = |a: f64, b: f64| (a - b).abs() <= INPUT_TOL * j_scale;
        for (field, got, want) in [
            (
                "solution.displacement_per_period",
                self.displacement_per_period,
                moved,
            ),
            ("solution.displacement_per_period", replayed, moved),
            ("solution.actuation_cost", self.actuation_cost, cost),
            ("objective", self.head.objective, moved - cost),
        ] {
            if !close(got, want) {
                return Err(bad(
                    what,
                    field,
                    got,
                    format!(
                        "disagrees with the gait: its block displacements, its cost and its \
                         replay by simulation give {want}"
                    ),
                ));
            }
        }
        if !self.solver_objective.is_finite() {
            return Err(bad(
                what,
                "solver_objective",
                self.solver_objective,
                "must be finite",
            ));
        }
        self.check_certificate(&crawler, what, close)?;
        check_records(
            what,
            &self.records,
            self.head.certificate.phases,
            self.m.map(|m| m as usize),
            self.head.objective,
            close,
        )
    }

    /// The records that repeat the gait: knot times (the durations summed), the initial state
    /// (the first state) and the actuator lengths (`L(0) = 0`, `L' = u / k` on each piece).
    fn check_repeated(&self, crawler: &Crawler, what: &str) -> Result<()> {
        let g = &self.gait;
        let t = self.problem.period;
        // Knot times and the initial state repeat the durations and the states.
        let mut knot = 0.0;
        for (j, &tj) in g.times.iter().enumerate() {
            if (tj - knot).abs() > 1e-9 * t {
                return Err(bad(
                    what,
                    &format!("solution.times[{j}]"),
                    tj,
                    format!("disagrees with the sum of the durations before it ({knot})"),
                ));
            }
            knot += g.durations.get(j).copied().unwrap_or(0.0);
        }
        let scale = crawler.state_scale();
        let d0 = max_diff(&g.states[0], &g.initial_state);
        if d0 > INPUT_TOL * scale {
            return Err(bad(
                what,
                "solution.initial_state",
                format!("{:?}", g.initial_state),
                format!("differs from solution.states[0] by {d0:.3e}"),
            ));
        }
        // Actuator lengths: L(0) = 0 and L' = u / k on each piece.
        let (_, lengths) = control_knots(&g.durations, &g.controls, crawler.stiffness());
        let len_scale = self.problem.length_scale(crawler);
        for (j, (got, want)) in g.lengths.iter().zip(&lengths).enumerate() {
            let d = max_diff(got, want);
            let sweep = (0..crawler.links())
                .map(|l| self.problem.rate_bound[l] * t / crawler.stiffness()[l])
                .fold(len_scale, f64::max);
            if d > INPUT_TOL * sweep {
                return Err(bad(
                    what,
                    &format!("solution.lengths[{j}]"),
                    format!("{got:?}"),
                    format!("disagrees with the lengths the controls give ({want:?})"),
                ));
            }
        }
        Ok(())
    }

    /// The slip modes: each the sign of its block's displacement, a slipping block on the face
    /// of its direction (at the step's end for P_m, at both ends for a phase).
    fn check_slip_modes(&self, crawler: &Crawler, kind: ProcessKind, what: &str) -> Result<()> {
        let g = &self.gait;
        let np = g.durations.len();
        let scale = crawler.state_scale();
        // Slip modes: the sign of a displacement, and a slipping block on its face.
        let dtol = crawler.displacement_tol(INPUT_TOL);
        for j in 0..np {
            let (f0, f1) = (
                crawler.block_forces(&g.states[j]),
                crawler.block_forces(&g.states[j + 1]),
            );
            for b in 0..crawler.blocks() {
                let s = g.slip[j][b];
                let moved = slip(g.block_displacements[j][b], dtol);
                let face = |f: f64| match s {
                    1 => (f - crawler.mu_forward()[b]).abs() <= INPUT_TOL * scale,
                    -1 => (f + crawler.mu_backward()[b]).abs() <= INPUT_TOL * scale,
                    _ => true,
                };
                let on_face = match kind {
                    ProcessKind::Discrete { .. } => face(f1[b]),
                    ProcessKind::Phase => face(f0[b]) && face(f1[b]),
                };
                if !(-1..=1).contains(&s) || (moved != 0 && moved != s) || !on_face {
                    return Err(bad(
                        what,
                        &format!("solution.slip[{j}][{b}]"),
                        s,
                        format!(
                            "disagrees with the gait: block {} moves by {:.3e} on piece {j} \
                             {}",
                            b + 1,
                            g.block_displacements[j][b],
                            if on_face {
                                "in the other direction"
                            } else {
                                "and its friction threshold of that direction is not reached"
                            }
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The process kind of the method (and `m`) a result names ([`SolutionKind::of_result`]).
    pub(crate) fn process_kind(&self, what: &str) -> Result<ProcessKind> {
        let kind = SolutionKind::of_result(Some(&self.head.method), what)?;
        match (kind, self.m) {
            (SolutionKind::Discrete | SolutionKind::Local, Some(m))
                if (1..=super::MAX_M).contains(&m) =>
            {
                Ok(ProcessKind::Discrete { m })
            }
            (SolutionKind::Discrete | SolutionKind::Local, Some(m)) => Err(bad(
                what,
                "solution.m",
                m,
                format!("must be in 1..={}", super::MAX_M),
            )),
            (SolutionKind::Discrete | SolutionKind::Local, None) => Err(bad(
                what,
                "solution.m",
                "nothing",
                "a discrete (P_m) result needs m",
            )),
            (SolutionKind::Phase, None) => Ok(ProcessKind::Phase),
            (SolutionKind::Phase, Some(m)) => {
                Err(bad(what, "solution.m", m, "a phase gait has no grid m"))
            }
        }
    }

    /// The certificate's claim ([`check_claim`]): its kind one of the method's, and a phase
    /// claim against the gait's slip phases.
    fn check_certificate(
        &self,
        crawler: &Crawler,
        what: &str,
        close: impl Fn(f64, f64) -> bool,
    ) -> Result<()> {
        let kinds: &[&str] = match self.head.method.as_str() {
            "phase" => &["global_k_phases", "local"],
            "discrete" => &["global"],
            _ => &["local"],
        };
        let claim = Claim {
            status: self.head.status,
            certificate: &self.head.certificate,
            bound: self.head.certificate.bound,
            gap: self.head.certificate.gap,
            record: "certificate",
            objective: self.head.objective,
            method: &self.head.method,
            kinds,
            phases: (self.gait.slip_phases(), "slip phases"),
            j_floor: self.problem.j_floor(crawler),
        };
        check_claim(what, &claim, close)
    }
}

/// The tables a result may carry ([`ResultRecords`]), a crawler's and (P)'s alike, each
/// through [`check_table`]: a phase growth's last `K` must be `phases` (the certificate's) and
/// a convergence table's last `m` the answer's `m`, where the result has them; a result has
/// one table at most. `j` is its verified `J`; `close` its reader's equality of objectives.
pub(crate) fn check_records(
    what: &str,
    records: &ResultRecords,
    phases: Option<usize>,
    m: Option<usize>,
    j: f64,
    close: impl Fn(f64, f64) -> bool,
) -> Result<()> {
    match (&records.phase_growth, &records.convergence) {
        (Some(g), None) => {
            let rows: Vec<_> = g
                .table
                .iter()
                .map(|r| (r.phases, r.objective, r.bound))
                .collect();
            check_table(what, "phase_growth.table", &rows, phases, j, true, close)
        }
        (None, Some(c)) => {
            let rows: Vec<_> = c
                .iter()
                .map(|r| (r.m as usize, r.objective, r.bound))
                .collect();
            check_table(what, "convergence", &rows, m, j, false, close)
        }
        (None, None) => Ok(()),
        (Some(_), Some(_)) => Err(bad(
            what,
            "convergence",
            "a table",
            "a result has a phase growth or a convergence table, not both",
        )),
    }
}

/// What a result's envelope claims about its verified objective, for a crawler's result and a
/// general one alike ([`check_claim`]).
pub(crate) struct Claim<'a> {
    /// The envelope's status.
    pub status: MilpStatus,
    /// The envelope's certificate: its kind, `K` and upper bound.
    pub certificate: &'a ResultCertificate,
    /// The bound and gap claimed, and the record that states them (`certificate`; a version 2
    /// general result repeated it as its MILP's `solution.certificate`).
    pub bound: Option<f64>,
    /// (See `bound`.)
    pub gap: Option<f64>,
    /// (See `bound`.)
    pub record: &'a str,
    /// `J`, re-verified.
    pub objective: f64,
    /// The result's method, and the certificate kinds it may claim.
    pub method: &'a str,
    /// (See `method`.)
    pub kinds: &'a [&'a str],
    /// The gait's phases as `K` counts them, and what they are called in errors (a crawler's
    /// slip phases; (P)'s phases that hold a face).
    pub phases: (usize, &'a str),
    /// The problem's floor of `J`, over which the gap is stated ([`Certificate::gap_of`]).
    pub j_floor: f64,
}

/// The claim of a result read back (`close` is the reader's equality of objectives): a recorded
/// upper bound at least `J`; the certificate's kind one of the method's; a claim over gaits of
/// at most `K` phases (`optimal_among_k_phases` for a gait in that class, `dominates_k_phases`
/// for one outside it) with the phase certificate, its `K` and a gap at most
/// [`PHASE_CLAIM_GAP`]; a local certificate without bound or gap, a global one with a finite
/// bound at least `J` and the gap of the two.
pub(crate) fn check_claim(what: &str, c: &Claim, close: impl Fn(f64, f64) -> bool) -> Result<()> {
    let cert = c.certificate;
    if let Some(ub) = &cert.upper_bound {
        ub.check_recorded(what, c.objective, &close)?;
    }
    if !c.kinds.contains(&cert.kind.as_str()) {
        return Err(bad(
            what,
            "certificate.kind",
            &cert.kind,
            format!(
                "a {} result's certificate is one of {:?}",
                c.method, c.kinds
            ),
        ));
    }
    check_phase_claim(what, c)?;
    let field = |name: &str| format!("{}.{name}", c.record);
    let (bound, gap) = match (cert.kind.as_str(), c.bound, c.gap) {
        ("local", None, None) => return Ok(()),
        ("local", _, _) => {
            return Err(bad(
                what,
                &field("bound"),
                "a bound",
                "a local answer proves no bound",
            ))
        }
        (_, Some(bound), Some(gap)) => (bound, gap),
        _ => {
            return Err(bad(
                what,
                c.record,
                "no bound or no gap",
                "a global certificate states both",
            ))
        }
    };
    let j = c.objective;
    if !(bound.is_finite() && (bound >= j || close(bound, j))) {
        return Err(bad(
            what,
            &field("bound"),
            bound,
            format!("is below the verified objective {j}"),
        ));
    }
    let want = Certificate::gap_of(bound, j, c.j_floor);
    if !(gap.is_finite() && (gap - want).abs() <= INPUT_TOL * want.abs().max(1.0)) {
        return Err(bad(
            what,
            &field("gap"),
            gap,
            format!("disagrees with the bound and the objective ({want})"),
        ));
    }
    Ok(())
}

/// A claim over gaits of at most `K` phases against the gait (and its gap against
/// [`PHASE_CLAIM_GAP`]): `optimal_among_k_phases` is for a gait in that class,
/// `dominates_k_phases` for one outside it (more phases than `K`), and both need the phase
/// certificate with its `K`.
fn check_phase_claim(what: &str, claim: &Claim) -> Result<()> {
    let (c, status) = (claim.certificate, claim.status.as_str());
    let among = claim.status == MilpStatus::OptimalAmongKPhases;
    if !among && claim.status != MilpStatus::DominatesKPhases {
        return Ok(());
    }
    let k = match (c.kind.as_str(), c.phases) {
        ("global_k_phases", Some(k)) => k,
        _ => {
            return Err(bad(
                what,
                "status",
                status,
                "is the status of a phase gait's global certificate, with its K in \
                 certificate.phases",
            ))
        }
    };
    // Both claim that no gait of at most K phases beats this one: the bound is its J (up to
    // the outer approximation's tolerance of a quadratic cost).
    if let Some(gap) = claim.gap.filter(|&g| g.is_nan() || g > PHASE_CLAIM_GAP) {
        return Err(bad(
            what,
            &format!("{}.gap", claim.record),
            gap,
            format!(
                "status {status} claims no gait of at most {k} phases does better; its gap \
                 must be at most {PHASE_CLAIM_GAP:e}"
            ),
        ));
    }
    let (p, noun) = claim.phases;
    match (among, p > k) {
        (true, true) => Err(bad(
            what,
            "status",
            status,
            format!(
                "claims optimality among gaits of at most {k} {noun} (certificate.phases) for \
                 a gait of {p}; that claim is dominates_k_phases"
            ),
        )),
        (false, false) => Err(bad(
            what,
            "status",
            status,
            format!("is for a gait of more than {k} {noun} (certificate.phases); this one has {p}"),
        )),
        _ => Ok(()),
    }
}

/// A table of a growth of `K` (`growth`) or of P_m over `m` (`rows`: the `K` or `m`, its
/// verified `J`, its bound) against the answer, for a crawler's result and a general
/// one alike: at least one row, `K` or `m` increasing and ending at the answer's `last` (where
/// it has one), each `J` finite and at most its bound, and the answer's `j` the largest `J` (a
/// growth keeps its best gait) or the last one (the answer is the finest P_m). In a growth each
/// bound is at least the `J` of every earlier row: the classes of gaits of at most `K` phases
/// are nested, so an earlier gait is one of the later class. Over `m` no such order holds: a step of catching-up is not two half steps (a polytope's projection of
/// `x + v` is not in general that of its projection of `x + v/2` plus `v/2`), so P_m's
/// processes are not P_(m+1)'s, and a drift makes the explicit step differ too. `close` is the
/// reader's equality of objectives.
fn check_table(
    what: &str,
    field: &str,
    rows: &[(usize, f64, f64)],
    last: Option<usize>,
    j: f64,
    growth: bool,
    close: impl Fn(f64, f64) -> bool,
) -> Result<()> {
    let Some(&(k, jk, _)) = rows.last() else {
        return Err(bad(what, field, "[]", "has no row"));
    };
    if let Some(last) = last.filter(|&l| l != k) {
        return Err(bad(
            what,
            field,
            k,
            format!("its last row must be the answer's {last}"),
        ));
    }
    for (i, w) in rows.windows(2).enumerate() {
        if w[1].0 <= w[0].0 {
            return Err(bad(
                what,
                &format!("{field}[{}]", i + 1),
                w[1].0,
                "must increase",
            ));
        }
    }
    // In a growth every earlier row's J is that of a gait of a smaller class, hence of this
    // row's class: at most this row's optimum, so at most its bound (whatever the statuses, and
    // robust to an outer approximation's tolerance, unlike a comparison of the J's).
    let mut earlier = f64::NEG_INFINITY;
    for (i, &(_, v, b)) in rows.iter().enumerate() {
        let at = format!("{field}[{i}]");
        if !(v.is_finite() && b.is_finite()) || (v > b && !close(v, b)) {
            return Err(bad(
                what,
                &at,
                format!("J {v}, bound {b}"),
                "needs a finite J at most its finite bound",
            ));
        }
        if growth && earlier > b && !close(earlier, b) {
            return Err(bad(
                what,
                &at,
                format!("bound {b}"),
                format!(
                    "is below {earlier}, the J of a gait of a smaller class (which is one of this \
                     class)"
                ),
            ));
        }
        earlier = earlier.max(v);
    }
    let want = if growth {
        rows.iter().fold(f64::NEG_INFINITY, |m, r| m.max(r.1))
    } else {
        jk
    };
    if !close(want, j) {
        // Both fields are named: either may be the one that is wrong.
        return Err(bad(
            what,
            &format!("objective and {field}"),
            j,
            format!("the answer's objective disagrees with the table's value {want} for it"),
        ));
    }
    Ok(())
}
