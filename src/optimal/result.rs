//! The result of an optimal-gait computation as one self-describing record: the crawler and the
//! problem it was computed for, the method, the certificate, the re-verified value and the gait
//! itself. This is what `crawlopt optimize --json` prints and what `certify`, `plot` and `report`
//! read back, so it carries a format name and version, and reading it checks both and the
//! consistency of every array.

use crate::error::{Error, Result};
use crate::integrate::{slip_of, Method};
use crate::model::Crawler;
use crate::optimal::milp::control_knots;
use crate::optimal::{
    DiscreteSolution, GaitProblem, LocalSolution, LocalStop, MilpStatus, PhaseGrowth,
    PhaseSolution, SequenceSearch,
};
use serde::{Deserialize, Serialize};

use super::envelope::{
    in_problem, local_status, read_envelope, ResultCertificate, ResultHead, ResultKind,
};
pub use super::envelope::{RESULT_FORMAT, RESULT_VERSION};
use super::records::{PhaseGrowthRecord, ResultRecords, StructuredRecord};

/// The crawler's parameters, as stored in a result (per link / per block, expanded).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CrawlerParams {
    /// Number of blocks `N`.
    pub blocks: usize,
    /// `k_l`, one per link.
    pub stiffness: Vec<f64>,
    /// `mu_b^+`, one per block.
    pub mu_forward: Vec<f64>,
    /// `mu_b^-`, one per block.
    pub mu_backward: Vec<f64>,
}

impl CrawlerParams {
    /// The parameters of `crawler`.
    pub fn of(crawler: &Crawler) -> Self {
        CrawlerParams {
            blocks: crawler.blocks(),
            stiffness: crawler.stiffness().to_vec(),
            mu_forward: crawler.mu_forward().to_vec(),
            mu_backward: crawler.mu_backward().to_vec(),
        }
    }

    /// The crawler (validated again: a result file is input like any other).
    pub fn crawler(&self) -> Result<Crawler> {
        let c = Crawler::new(
            self.stiffness.clone(),
            self.mu_forward.clone(),
            self.mu_backward.clone(),
        )?;
        if c.blocks() != self.blocks {
            return Err(Error::invalid(
                "crawler.blocks",
                self.blocks,
                format!("does not match the {} friction values", c.blocks()),
            ));
        }
        Ok(c)
    }
}

/// The gait over one period, on its own knots: `times` has one entry more than the pieces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GaitData {
    /// Knot times `t_0 = 0 < ... < t_P = T` (phase boundaries or grid times).
    pub times: Vec<f64>,
    /// Piece durations `t_{j+1} - t_j`.
    pub durations: Vec<f64>,
    /// Actuator lengths `L(t_j)` at the knots, from `L(0) = 0` (`P + 1` rows; last = first).
    pub lengths: Vec<Vec<f64>>,
    /// Controls `u_j = k L'` on each piece (force per time).
    pub controls: Vec<Vec<f64>>,
    /// States `x(t_j)` at the knots (`P + 1` rows; last = first: a limit cycle).
    pub states: Vec<Vec<f64>>,
    /// Block displacements on each piece.
    pub block_displacements: Vec<Vec<f64>>,
    /// Slip mode of each block on each piece: -1, 0, 1.
    pub slip: Vec<Vec<i8>>,
    /// `x(0)`.
    pub initial_state: Vec<f64>,
}

impl GaitData {
    /// Its number of slip phases, runs of one slip mode merged cyclically (what a phase
    /// certificate's `K` counts; [`crate::optimal::slip_sequence`]).
    pub fn slip_phases(&self) -> usize {
        super::slip_sequence(&self.slip).len()
    }

    /// A gait on a uniform grid of step `step` (P_m), slip modes read off the displacements.
    fn on_grid(
        crawler: &Crawler,
        step: f64,
        controls: &[Vec<f64>],
        states: &[Vec<f64>],
        block_displacements: &[Vec<f64>],
        initial_state: &[f64],
    ) -> Self {
        let durations = vec![step; controls.len()];
        let (times, lengths) = knots(crawler, &durations, controls);
        // A length, as the reader's threshold is (`1e-9 * step` was a time: at a period of
        // 1e-5 a block moving by 3e-16 was written as slipping, off its face, and at a period
        // of 1e7 a block moving by 1.25e-6 as sticking; the reader refused both files).
        let no_motion = crawler.displacement_tol(1e-9);
        GaitData {
            times,
            durations,
            lengths,
            controls: controls.to_vec(),
            states: states.to_vec(),
            block_displacements: block_displacements.to_vec(),
            slip: block_displacements
                .iter()
                .map(|d| d.iter().map(|&v| slip_of(v, no_motion)).collect())
                .collect(),
            initial_state: initial_state.to_vec(),
        }
    }
}

/// One optimal-gait result (module docs). Written and read in the shape of
/// `crate::optimal::result_wire` (result version 4: the crawler and its gait problem under
/// `problem`, the gait's own numbers, `m`, `local` and `polish` in `solution`), in
/// `result_wire`.
#[derive(Debug, Clone, PartialEq)]
pub struct GaitResult {
    /// The envelope every result opens with ([`ResultHead`]): format, version, kind
    /// (`"crawler"`), method (`"phase"`, `"sequence"` or `"chain"`, an exact phase gait, for
    /// which version 1 files wrote `"phase"` alike; `"discrete"` or `"local"`, a P_m process on
    /// the grid of `m`), `J` (displacement per period minus actuation cost, from the verified
    /// displacement), status (`"optimal"` for P_m, `"optimal_among_k_phases"` for phase gaits,
    /// `K` being `certificate.phases`, `"dominates_k_phases"` for a phase gait of more than `K`
    /// slip phases that none of at most `K` beats, `"time_limit"` (see the gap and bound),
    /// `"approximation_limit"`, or the local methods' `"stationary"` / `"stalled"`) and the
    /// certificate.
    pub head: ResultHead,
    /// The crawler (`problem.crawler`).
    pub crawler: CrawlerParams,
    /// The gait problem (`problem.gait`).
    pub problem: GaitProblem,
    /// `m` of P_m (`solution.m`; P_m answers only).
    pub m: Option<u32>,
    /// Displacement per period, found by replaying the gait in the simulator that verifies it
    /// (`solution.displacement_per_period`; versions 1 to 3 wrote it twice, also as
    /// `verified_displacement`).
    pub displacement_per_period: f64,
    /// `int_0^T f2(u) dt` of the gait (`solution.actuation_cost`).
    pub actuation_cost: f64,
    /// The solver's own objective (before re-verification).
    pub solver_objective: f64,
    /// The gait: the envelope's `solution` (`gait` in version 1 files, read as well).
    pub gait: GaitData,
    /// The records beside the solution ([`ResultRecords`]): the growth of `K` that led to a
    /// phase gait, the table of `J_m` when asked (`--convergence`), the structured gait kept
    /// as the answer.
    pub records: ResultRecords,
    /// How the local method ran (methods `local` and `sequence`; `solution.local`).
    pub local: Option<LocalRecord>,
    /// The start a P_m MILP took as its first incumbent, when it had one.
    pub discrete_start: Option<StartRecord>,
    /// What polishing on the fixed slip pattern did to a P_m answer of a quadratic cost
    /// ([`crate::optimal::polish`]; `solution.polish`).
    pub polish: Option<crate::optimal::polish::PolishRecord>,
}

/// The methods whose answer is an exact phase gait.
pub const PHASE_GAIT_METHODS: [&str; 3] = ["phase", "sequence", "chain"];

/// A gait on the exact simulator's pieces (one control and one slip pattern per piece):
/// the record of a structured gait ([`GaitResult::from_structured`]).
#[derive(Debug, Clone, PartialEq)]
pub struct StructuredPieces {
    /// Piece durations, summing to `T`.
    pub durations: Vec<f64>,
    /// Controls `u` per piece.
    pub controls: Vec<Vec<f64>>,
    /// States at the piece ends (`P + 1` rows, last = first).
    pub states: Vec<Vec<f64>>,
    /// Block displacements per piece.
    pub block_displacements: Vec<Vec<f64>>,
    /// Slip modes per piece.
    pub slip: Vec<Vec<i8>>,
    /// The displacement per period on the orbit, from the simulator.
    pub verified_displacement: f64,
}

/// The start gait of a P_m MILP
/// ([`solve_discrete_global_from`](crate::optimal::solve_discrete_global_from)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StartRecord {
    /// Where it came from (e.g. `"local (start.json)"`).
    pub start: String,
    /// Its `J` on the grid (catching-up on its periodic orbit).
    pub start_objective: f64,
}

/// What a local method did ([`solve_discrete_local`](crate::optimal::solve_discrete_local) on
/// P_m, or [`search_sequences`](crate::optimal::search_sequences) on phase gaits).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LocalRecord {
    /// `J` of the start: the start gait sampled on the grid (P_m), or the LP optimum of the
    /// start sequence (phase gaits).
    pub start_objective: f64,
    /// Where the start came from (e.g. `"phase (K = 5)"`).
    pub start: String,
    /// LP solves.
    pub lp_solves: usize,
    /// Mode switches (P_m) or improving moves (phase gaits).
    pub switches: usize,
    /// Why it stopped.
    pub stop: LocalStop,
}

fn knots(crawler: &Crawler, durations: &[f64], controls: &[Vec<f64>]) -> GaitKnots {
    control_knots(durations, controls, crawler.stiffness())
}

type GaitKnots = (Vec<f64>, Vec<Vec<f64>>);

fn actuation_cost(problem: &GaitProblem, durations: &[f64], controls: &[Vec<f64>]) -> f64 {
    durations
        .iter()
        .zip(controls)
        .map(|(d, u)| d * problem.cost.eval(u))
        .sum()
}

impl GaitResult {
    /// A record of `method` with its header filled in: format, version, crawler, problem and
    /// the objective from the verified displacement and the cost; no optional records.
    #[allow(clippy::too_many_arguments)]
    fn record(
        crawler: &Crawler,
        problem: &GaitProblem,
        method: &str,
        m: Option<u32>,
        status: MilpStatus,
        (verified, cost, solver_objective): (f64, f64, f64),
        certificate: ResultCertificate,
        gait: GaitData,
    ) -> Self {
        GaitResult {
            head: ResultHead::new(
                ResultKind::Crawler,
                method,
                verified - cost,
                status,
                certificate,
            ),
            crawler: CrawlerParams::of(crawler),
            problem: problem.clone(),
            m,
            displacement_per_period: verified,
            actuation_cost: cost,
            solver_objective,
            gait,
            records: ResultRecords::default(),
            local: None,
            discrete_start: None,
            polish: None,
        }
    }

    /// The record of a structured gait ([`crate::optimal::structured`]) on the exact
    /// simulator's pieces: a continuous-time gait of constant controls per piece, replayed
    /// exactly like a phase gait (method `"phase"`), with no claim of optimality (certificate
    /// `"local"` without bound or gap, status `"stalled"`: nothing improved on it) and its
    /// origin in [`ResultRecords::structured`].
    pub fn from_structured(
        crawler: &Crawler,
        problem: &GaitProblem,
        p: StructuredPieces,
        origin: &str,
    ) -> Self {
        let (times, lengths) = knots(crawler, &p.durations, &p.controls);
        let cost = actuation_cost(problem, &p.durations, &p.controls);
        let gait = GaitData {
            times,
            durations: p.durations,
            lengths,
            controls: p.controls,
            initial_state: p.states.first().cloned().unwrap_or_default(),
            states: p.states,
            block_displacements: p.block_displacements,
            slip: p.slip,
        };
        let certificate = ResultCertificate::local(None);
        let mut r = GaitResult::record(
            crawler,
            problem,
            "phase",
            None,
            MilpStatus::Stalled,
            (
                p.verified_displacement,
                cost,
                p.verified_displacement - cost,
            ),
            certificate,
            gait,
        );
        r.records.structured = Some(StructuredRecord {
            origin: origin.into(),
            replaced: None,
        });
        r
    }

    /// The record of a phase-formulation answer.
    pub fn from_phase(crawler: &Crawler, problem: &GaitProblem, s: &PhaseSolution) -> Self {
        let (times, lengths) = knots(crawler, &s.durations, &s.controls);
        let cost = actuation_cost(problem, &s.durations, &s.controls);
        let gait = GaitData {
            times,
            durations: s.durations.clone(),
            lengths,
            controls: s.controls.clone(),
            states: s.states.clone(),
            block_displacements: s.block_displacements.clone(),
            slip: s.modes.clone(),
            initial_state: s.states.first().cloned().unwrap_or_default(),
        };
        let certificate = ResultCertificate::of_milp(&s.certificate, Some(s.phases));
        GaitResult::record(
            crawler,
            problem,
            "phase",
            None,
            s.certificate.status,
            (s.verified_displacement, cost, s.certificate.milp_objective),
            certificate,
            gait,
        )
    }

    /// Whether the gait is an exact phase gait (methods phase, sequence and chain), not a P_m
    /// process.
    pub fn is_phase_gait(&self) -> bool {
        PHASE_GAIT_METHODS.contains(&self.head.method.as_str())
    }

    /// The simulator that verified this result's gait, and so replays it: catching-up on the grid
    /// for P_m answers (global or local), exact for phase gaits.
    pub fn verified_with(&self) -> Method {
        match self.head.method.as_str() {
            "discrete" | "local" => Method::CatchingUp,
            _ => Method::Exact,
        }
    }

    /// The record of a phase gait found by [`search_sequences`](crate::optimal::search_sequences):
    /// an exact continuous-time gait (method `"sequence"`, replayed exactly as a phase gait),
    /// optimal for its sequence of slip modes only, so its certificate is `"local"` (no gap, no
    /// bound); `start` says where the start sequence came from.
    pub fn from_sequence(
        crawler: &Crawler,
        problem: &GaitProblem,
        s: &SequenceSearch,
        start: &str,
    ) -> Self {
        let mut r = GaitResult::from_phase(crawler, problem, &s.best);
        r.head.method = "sequence".into();
        r.head.status = local_status(s.stop);
        r.head.certificate = ResultCertificate::local(Some(s.best.phases));
        r.local = Some(LocalRecord {
            start_objective: s.start_objective,
            start: start.into(),
            lp_solves: s.lp_solves,
            switches: s.moves,
            stop: s.stop,
        });
        r
    }

    /// The record of a phase gait found by growing `K`, with the growth's table.
    pub fn from_growth(crawler: &Crawler, problem: &GaitProblem, g: &PhaseGrowth) -> Self {
        let mut r = GaitResult::from_phase(crawler, problem, &g.best);
        r.records.phase_growth = Some(PhaseGrowthRecord {
            table: g.table.clone(),
            stop: g.stop,
        });
        r
    }

    /// The record of a local P_m answer; `start` says where its start gait came from.
    pub fn from_local(
        crawler: &Crawler,
        problem: &GaitProblem,
        s: &LocalSolution,
        start: &str,
    ) -> Self {
        let gait = GaitData::on_grid(
            crawler,
            s.step,
            &s.controls,
            &s.states,
            &s.block_displacements,
            &s.initial_state,
        );
        let certificate = ResultCertificate::local(None);
        let mut r = GaitResult::record(
            crawler,
            problem,
            "local",
            Some(s.m),
            local_status(s.stop),
            (s.verified_displacement, s.actuation_cost, s.lp_objective),
            certificate,
            gait,
        );
        r.local = Some(LocalRecord {
            start_objective: s.start_objective,
            start: start.into(),
            lp_solves: s.lp_solves,
            switches: s.switches,
            stop: s.stop,
        });
        r
    }

    /// The record of a P_m answer.
    pub fn from_discrete(crawler: &Crawler, problem: &GaitProblem, s: &DiscreteSolution) -> Self {
        let gait = GaitData::on_grid(
            crawler,
            s.step,
            &s.controls,
            &s.states,
            &s.block_displacements,
            &s.initial_state,
        );
        let cost = actuation_cost(problem, &gait.durations, &s.controls);
        let certificate = ResultCertificate::of_milp(&s.certificate, None);
        let mut r = GaitResult::record(
            crawler,
            problem,
            "discrete",
            Some(s.m),
            s.certificate.status,
            (s.verified_displacement, cost, s.certificate.milp_objective),
            certificate,
            gait,
        );
        r.polish = s.polish.clone();
        r
    }

    /// Reads a result from JSON text, checking the envelope (format name, version and kind:
    /// a general problem's result is refused naming `kind`, see `crate::io::ResultFile` for
    /// either), the shape of every array against the crawler, and that the result is what it
    /// says ([`GaitResult::check_consistent`]); `what` names the source in errors.
    pub fn from_json(text: &str, what: &str) -> Result<Self> {
        let (v, kind, label) = read_envelope(text, what)?;
        if kind != ResultKind::Crawler {
            return Err(Error::invalid(
                format!("{what}: kind"),
                kind.as_str(),
                "is a general problem's result, not a crawler's gait (certify reads both)",
            ));
        }
        Self::from_checked_envelope(v, &label)
    }

    /// [`GaitResult::from_json`] of a document whose envelope [`read_envelope`] has checked
    /// (kind crawler).
    pub fn from_checked_envelope(v: serde_json::Value, what: &str) -> Result<Self> {
        let r: GaitResult = serde_json::from_value(v).map_err(|e| Error::Io {
            path: what.into(),
            reason: format!("malformed gait result: {e}"),
        })?;
        r.check_shape(what)?;
        r.check_consistent(what)?;
        Ok(r)
    }

    /// Checks the problem data, and array lengths and finiteness against the crawler.
    fn check_shape(&self, what: &str) -> Result<()> {
        let crawler = self.crawler.crawler().map_err(|e| in_problem(e, what))?;
        self.problem
            .validate(&crawler)
            .map_err(|e| in_problem(e, what))?;
        let (n, nb) = (crawler.links(), crawler.blocks());
        let g = &self.gait;
        let p = g.durations.len();
        let bad = |field: &str, got: String, want: String| {
            Err(Error::invalid(
                format!("{what}: solution.{field}"),
                got,
                format!("needs {want}"),
            ))
        };
        if p == 0 {
            return bad("durations", "0 pieces".into(), "at least one piece".into());
        }
        for (field, len, width) in [
            ("times", p + 1, 1),
            ("lengths", p + 1, n),
            ("controls", p, n),
            ("states", p + 1, n),
            ("block_displacements", p, nb),
        ] {
            let (got_len, widths): (usize, Vec<usize>) = match field {
                "times" => (g.times.len(), vec![]),
                "lengths" => (g.lengths.len(), g.lengths.iter().map(Vec::len).collect()),
                "controls" => (g.controls.len(), g.controls.iter().map(Vec::len).collect()),
                "states" => (g.states.len(), g.states.iter().map(Vec::len).collect()),
                _ => (
                    g.block_displacements.len(),
                    g.block_displacements.iter().map(Vec::len).collect(),
                ),
            };
            if got_len != len {
                return bad(field, format!("{got_len} rows"), format!("{len} rows"));
            }
            if let Some(w) = widths.iter().find(|&&w| w != width) {
                return bad(field, format!("a row of {w}"), format!("{width} per row"));
            }
        }
        if g.slip.len() != p || g.slip.iter().any(|r| r.len() != nb) {
            return bad("slip", "a wrong shape".into(), format!("{p} rows of {nb}"));
        }
        if g.initial_state.len() != n {
            return bad(
                "initial_state",
                format!("{} values", g.initial_state.len()),
                format!("{n} values"),
            );
        }
        let all = g
            .times
            .iter()
            .chain(&g.durations)
            .chain(g.lengths.iter().flatten())
            .chain(g.controls.iter().flatten())
            .chain(g.states.iter().flatten())
            .chain(g.block_displacements.iter().flatten())
            .chain(&g.initial_state);
        if all.into_iter().any(|v| !v.is_finite()) {
            return bad("*", "a non-finite value".into(), "finite numbers".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimal::{solve_phase_global, Cost};

    fn one_link_result() -> GaitResult {
        let c = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
        let p = GaitProblem::new(&c, 10.0, &[1.0], Cost::None, None).unwrap();
        let s = solve_phase_global(&c, &p, 4).unwrap();
        GaitResult::from_phase(&c, &p, &s)
    }

    #[test]
    fn round_trips_and_refuses_other_versions_and_truncation() {
        let r = one_link_result();
        assert!((r.head.objective - 3.0).abs() < 1e-9);
        let text = serde_json::to_string(&r).unwrap();
        assert_eq!(GaitResult::from_json(&text, "r.json").unwrap(), r);
        let e = GaitResult::from_json(&text[..text.len() / 2], "r.json").unwrap_err();
        assert!(
            e.to_string().contains("not a complete JSON document"),
            "{e}"
        );
        let other = text.replace("\"version\":4", "\"version\":5");
        let e = GaitResult::from_json(&other, "r.json").unwrap_err();
        assert!(e.to_string().contains("version"), "{e}");
        let e = GaitResult::from_json("{\"objective\": 1}", "r.json").unwrap_err();
        assert!(e.to_string().contains("format"), "{e}");
        let mut short = r.clone();
        short.gait.states.pop();
        let e =
            GaitResult::from_json(&serde_json::to_string(&short).unwrap(), "r.json").unwrap_err();
        assert!(e.to_string().contains("solution.states"), "{e}");
        let mut bad = r;
        bad.problem.period = -1.0;
        let e = GaitResult::from_json(&serde_json::to_string(&bad).unwrap(), "r.json").unwrap_err();
        assert!(e.to_string().contains("gait.period"), "{e}");
    }
}
