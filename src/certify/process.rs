//! The process to certify: a periodic state–control pair on its own knots, read from a
//! [`GaitResult`] (or built from controls by simulation) and checked for consistency before any
//! multiplier is computed. A certificate of a process that is not a process would be a silent
//! wrong number, so every check here names what is wrong.

use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::consistency::{bad, ProcessView};
pub use crate::optimal::consistency::{ProcessKind, INPUT_TOL};
use crate::optimal::{replay, GaitProblem, GaitResult};

/// A periodic process `(x, u)` with block displacements, on knots `t_0 = 0 < ... < t_P = T`.
#[derive(Debug, Clone, PartialEq)]
pub struct Process {
    /// The crawler.
    pub crawler: Crawler,
    /// The gait problem (period, rate bounds, cost).
    pub problem: GaitProblem,
    /// Discrete (P_m) or phase gait.
    pub kind: ProcessKind,
    /// Piece durations `tau_j` (`P` values, summing to `T`).
    pub durations: Vec<f64>,
    /// Controls `u_j` per piece (force per time).
    pub controls: Vec<Vec<f64>>,
    /// States at the knots (`P + 1` rows, last = first).
    pub states: Vec<Vec<f64>>,
    /// Block displacements `D_{j,b}` per piece.
    pub block_displacements: Vec<Vec<f64>>,
}

impl Process {
    /// Knot times `t_0 = 0, ..., t_P = T`.
    pub fn times(&self) -> Vec<f64> {
        let mut t = vec![0.0];
        for d in &self.durations {
            t.push(t[t.len() - 1] + d);
        }
        t
    }

    /// The process recorded in an optimizer result, checked (see [`Process::check`]); `what`
    /// names the source in errors. A phase gait of one piece (an idle optimum: with zero mean
    /// its control is 0) is certified as its two halves, the same process on knots the
    /// conditions can be stated on.
    pub fn from_result(r: &GaitResult, what: &str) -> Result<Self> {
        r.check_consistent(what)?;
        let mut p = Process {
            crawler: r.crawler.crawler()?,
            problem: r.problem.clone(),
            kind: r.process_kind(what)?,
            durations: r.gait.durations.clone(),
            controls: r.gait.controls.clone(),
            states: r.gait.states.clone(),
            block_displacements: r.gait.block_displacements.clone(),
        };
        if p.kind == ProcessKind::Phase && p.durations.len() == 1 && p.states.len() == 2 {
            p = p.halved();
        }
        p.check(what, INPUT_TOL)?;
        Ok(p)
    }

    /// A one-piece phase gait as two halves: the piece's motion is linear, so its midpoint
    /// state is the mean of its ends and each half carries half its block displacements.
    fn halved(self) -> Self {
        let mid: Vec<f64> = self.states[0]
            .iter()
            .zip(&self.states[1])
            .map(|(a, b)| 0.5 * (a + b))
            .collect();
        let half: Vec<f64> = self.block_displacements[0]
            .iter()
            .map(|d| 0.5 * d)
            .collect();
        Process {
            durations: vec![0.5 * self.durations[0]; 2],
            controls: vec![self.controls[0].clone(); 2],
            states: vec![self.states[0].clone(), mid, self.states[1].clone()],
            block_displacements: vec![half.clone(), half],
            ..self
        }
    }

    /// A P_m process from its controls (`2^m` rows): the catching-up trajectory on its periodic
    /// orbit, found by simulation. Used to certify gaits that did not come from an optimizer
    /// (e.g. a perturbed optimum).
    pub fn discrete_from_controls(
        crawler: &Crawler,
        problem: &GaitProblem,
        m: u32,
        controls: &[Vec<f64>],
    ) -> Result<Self> {
        let steps = 1usize << m;
        if controls.len() != steps {
            return Err(Error::invalid(
                "controls",
                format!("{} rows", controls.len()),
                format!("needs 2^m = {steps} rows"),
            ));
        }
        let h = problem.period / steps as f64;
        Self::from_controls(
            crawler,
            problem,
            ProcessKind::Discrete { m },
            &vec![h; steps],
            controls,
        )
    }

    /// A phase process from durations and controls, simulated exactly on its periodic orbit; the
    /// pieces are split at the events (a face reached, a block starting to slip) so that each
    /// has one slip mode.
    pub fn phase_from_controls(
        crawler: &Crawler,
        problem: &GaitProblem,
        durations: &[f64],
        controls: &[Vec<f64>],
    ) -> Result<Self> {
        Self::from_controls(crawler, problem, ProcessKind::Phase, durations, controls)
    }

    fn from_controls(
        crawler: &Crawler,
        problem: &GaitProblem,
        kind: ProcessKind,
        durations: &[f64],
        controls: &[Vec<f64>],
    ) -> Result<Self> {
        crawler.require_unique()?;
        problem.validate(crawler)?;
        if durations.len() != controls.len() || durations.len() < 2 {
            return Err(Error::invalid(
                "controls",
                format!("{} rows for {} durations", controls.len(), durations.len()),
                "needs one row per piece and at least two pieces",
            ));
        }
        let increments: Vec<Vec<f64>> = durations
            .iter()
            .zip(controls)
            .map(|(d, u)| u.iter().map(|v| v * d).collect())
            .collect();
        let method = match kind {
            ProcessKind::Discrete { .. } => Method::CatchingUp,
            ProcessKind::Phase => Method::Exact,
        };
        let sim = replay(
            crawler,
            problem.period,
            durations,
            &increments,
            None,
            method,
            "the process",
        )?;
        let tr = sim
            .trajectory
            .ok_or_else(|| Error::Numerical("the process: no period was recorded".into()))?;
        // Knots: the grid (P_m); for a phase gait also the events inside pieces recorded by the
        // exact method, so that every piece has one slip mode (theory §7).
        let mut knot_t = vec![0.0];
        for d in durations {
            knot_t.push(knot_t[knot_t.len() - 1] + d);
        }
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * problem.period;
        let mut idx: Vec<usize> = Vec::new();
        for (i, &s) in tr.t.iter().enumerate() {
            let keep = match kind {
                ProcessKind::Discrete { .. } => knot_t.iter().any(|&tk| close(s, tk)),
                ProcessKind::Phase => s >= -1e-9 * problem.period,
            };
            if keep && idx.last().is_none_or(|&l| !close(tr.t[l], s)) {
                idx.push(i);
            }
        }
        if idx.len() < knot_t.len() || !close(tr.t[idx[idx.len() - 1]], problem.period) {
            return Err(Error::Numerical(
                "the simulation did not record the knots of the gait".into(),
            ));
        }
        let times: Vec<f64> = idx.iter().map(|&i| tr.t[i]).collect();
        let piece_of = |t: f64| {
            knot_t[1..]
                .iter()
                .position(|&e| t < e)
                .unwrap_or(durations.len() - 1)
        };
        let p = Process {
            crawler: crawler.clone(),
            problem: problem.clone(),
            kind,
            durations: times.windows(2).map(|w| w[1] - w[0]).collect(),
            controls: times
                .windows(2)
                .map(|w| controls[piece_of(0.5 * (w[0] + w[1]))].clone())
                .collect(),
            states: idx.iter().map(|&i| tr.x[i].clone()).collect(),
            block_displacements: idx
                .windows(2)
                .map(|w| {
                    tr.positions[w[1]]
                        .iter()
                        .zip(&tr.positions[w[0]])
                        .map(|(a, b)| a - b)
                        .collect()
                })
                .collect(),
        };
        p.check("simulated gait", INPUT_TOL)?;
        Ok(p)
    }

    /// Checks that the data is a process of the problem (relative tolerance `tol`): shapes,
    /// grid (`2^m` equal steps `T / 2^m` for P_m; positive durations summing to `T`), states in
    /// C, periodicity `x(T) = x(0)`, `|u_l| <= a_l`, zero mean `int u = 0`, the dynamics
    /// `x_{j+1} = x_j + tau_j u_j - K sum_b D_{j,b} nu_b`, and the flow rule (a block moves only
    /// against an active face: at the step's end for P_m, at both ends for a phase).
    pub fn check(&self, what: &str, tol: f64) -> Result<()> {
        if self.problem.max_total_variation.is_some() {
            return Err(bad(
                what,
                "problem.max_total_variation",
                "a bound",
                "is not covered by the necessary conditions (Theorem 2.2 has no TV bound)",
            ));
        }
        let np = self.durations.len();
        if np < 2 {
            return Err(bad(
                what,
                "solution.durations",
                format!("{np} pieces"),
                "needs at least two pieces",
            ));
        }
        self.view().check(what, tol)
    }

    /// The process as borrowed data, for the checks shared with every reader of a gait.
    pub fn view(&self) -> ProcessView<'_> {
        ProcessView {
            crawler: &self.crawler,
            problem: &self.problem,
            kind: self.kind,
            durations: &self.durations,
            controls: &self.controls,
            states: &self.states,
            block_displacements: &self.block_displacements,
        }
    }
}
