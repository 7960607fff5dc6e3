//! The process a general certificate is about ([`crate::certify::general`]): a periodic P_m
//! process of the general problem, from an optimum or from controls by simulation, or an exact
//! phase gait (`A = 0`, theory §7 generalised), checked for consistency before any multiplier
//! is computed (a certificate of something that is not a process would be a silent wrong
//! number), every message naming the field.

use super::process::Process;
use crate::error::{Error, Result};
use crate::integrate::{simulate_general, ControlInput, GeneralSimOptions, InputKind};
use crate::model::general::{Boundary, GeneralProblem};
use crate::optimal::general::{GeneralLocal, GeneralPhaseGait, GeneralPm, PmPath};
pub use crate::optimal::process::ProcessKind;
use crate::optimal::process::{FieldNames, ProcessRows};

/// Phases of a phase gait at most this fraction of the period long are dropped before the gait
/// is certified ([`GeneralProcess::without_empty_phases`]): at the MILP's resolution such a phase
/// has duration 0, where the phase LP's bound `tau >= 0` is active and neither the weak
/// maximality of its control (`U = tau u = 0`) nor the equality of its Hamiltonian is asked.
pub const EMPTY_PHASE: f64 = 1e-9;

/// A periodic process of the general problem on `P` pieces: `x^0..x^P` (`x^P = x^0`),
/// `u^0..u^(P-1)` and the reaction rates `lambda^i` per face. A P_m process has `P = 2^m`
/// steps of `h = T / 2^m` (`lambda^i = mu^i / h`, the projection's multipliers); a phase gait
/// has pieces of their own durations, each a straight segment with its held faces active at
/// both ends (theory §7).
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralProcess {
    /// P_m or phase gait.
    pub kind: ProcessKind,
    /// Piece durations `tau_i` (`h` for every step of P_m).
    pub durations: Vec<f64>,
    /// States at the knots (`P + 1` rows).
    pub x: Vec<Vec<f64>>,
    /// Controls per piece.
    pub u: Vec<Vec<f64>>,
    /// Reaction rates per piece and face.
    pub lambda: Vec<Vec<f64>>,
}

impl GeneralProcess {
    /// A P_m process `path` on `2^m` steps of a problem of period `period`.
    pub fn pm(m: u32, period: f64, path: PmPath) -> Self {
        let steps = 1usize << m.min(crate::optimal::general::MAX_GENERAL_LOCAL_M + 1);
        GeneralProcess {
            kind: ProcessKind::Discrete { m },
            durations: vec![period / steps as f64; steps],
            x: path.x,
            u: path.u,
            lambda: path.lambda,
        }
    }

    /// The process of a P_m optimum of `p`.
    pub fn from_pm(p: &GeneralProblem, s: &GeneralPm) -> Self {
        Self::pm(s.m, p.period, s.path.clone())
    }

    /// The process of a local P_m answer of `p`.
    pub fn from_local(p: &GeneralProblem, s: &GeneralLocal) -> Self {
        Self::pm(s.m, p.period, s.path.clone())
    }

    /// The process of an exact phase gait (general or chain formulation): its phases as
    /// pieces, with the states the exact simulator replayed and the reaction rates.
    pub fn from_phase(s: &GeneralPhaseGait) -> Self {
        GeneralProcess {
            kind: ProcessKind::Phase,
            durations: s.durations.clone(),
            x: s.states.clone(),
            u: s.controls.clone(),
            lambda: s.reactions.clone(),
        }
    }

    /// The process without the phases of a phase gait at most [`EMPTY_PHASE`] `T` long (a
    /// P_m process, or a gait without such phases, as it is): each dropped phase's start knot
    /// goes with it, so the phase before it now ends where the dropped one ended (the two knots
    /// differ by at most its duration times the speed, within the checks' tolerance).
    pub fn without_empty_phases(&self, period: f64) -> GeneralProcess {
        let keep: Vec<usize> = (0..self.durations.len())
            .filter(|&i| self.durations[i] > EMPTY_PHASE * period)
            .collect();
        if self.kind != ProcessKind::Phase
            || keep.len() == self.durations.len()
            || keep.is_empty()
            || self.x.len() != self.durations.len() + 1
            || self.u.len() != self.durations.len()
            || self.lambda.len() != self.durations.len()
        {
            return self.clone();
        }
        let pick = |rows: &[Vec<f64>]| keep.iter().map(|&i| rows[i].clone()).collect::<Vec<_>>();
        let mut x = pick(&self.x);
        x.push(self.x[self.durations.len()].clone());
        GeneralProcess {
            kind: ProcessKind::Phase,
            durations: keep.iter().map(|&i| self.durations[i]).collect(),
            x,
            u: pick(&self.u),
            lambda: pick(&self.lambda),
        }
    }

    /// A crawler's process as a process of its instance of (P)
    /// ([`crate::model::crawler_as_general`]): the states `x~ = K^(-1/2) x` and the reaction
    /// rates of the unit rows, `lambda_(b+-) = s_b max(+-D_b, 0) / tau_j` with
    /// `s_b = |K^(1/2) nu_b|` (the block displacements `D_b = (mu_(b+) - mu_(b-)) / s_b` of
    /// that module's docs, per unit time); controls, durations and the kind are the crawler's.
    pub fn of_crawler(pr: &Process) -> Self {
        let (x, lambda) = pr.view().instance_rows();
        GeneralProcess {
            kind: pr.kind,
            durations: pr.durations.clone(),
            x,
            u: pr.controls.clone(),
            lambda,
        }
    }

    /// `m` of a P_m process (`None` for a phase gait).
    pub fn m(&self) -> Option<u32> {
        match self.kind {
            ProcessKind::Discrete { m } => Some(m),
            ProcessKind::Phase => None,
        }
    }

    /// Knot times `t_0 = 0, ..., t_P = T`.
    pub fn times(&self) -> Vec<f64> {
        let mut t = vec![0.0];
        for d in &self.durations {
            t.push(t[t.len() - 1] + d);
        }
        t
    }

    /// The catching-up process of the controls (`2^m` rows) on its periodic orbit, reached from
    /// `x0` by the general simulator. Used to certify processes no optimizer produced.
    pub fn from_controls(
        p: &GeneralProblem,
        m: u32,
        controls: &[Vec<f64>],
        x0: &[f64],
    ) -> Result<Self> {
        let steps = 1usize << m.min(20);
        if controls.len() != steps {
            return Err(Error::invalid(
                "controls",
                format!("{} rows", controls.len()),
                format!("needs 2^m = {steps} rows"),
            ));
        }
        let h = p.period / steps as f64;
        let times = (0..steps).map(|i| i as f64 * h).collect();
        let input = ControlInput::new(
            InputKind::PiecewiseConstant,
            p.period,
            times,
            controls.to_vec(),
            &p.control,
            "controls",
        )?;
        let opts = GeneralSimOptions {
            steps_per_period: steps,
            drift: crate::integrate::DriftStep::Explicit,
            ..GeneralSimOptions::DEFAULT
        };
        let sim = simulate_general(p, &input, x0, &opts)?;
        if !sim.converged {
            return Err(Error::invalid(
                "controls",
                "a control",
                "its catching-up process reached no periodic regime",
            ));
        }
        Ok(Self::pm(
            m,
            p.period,
            PmPath {
                x: sim.x,
                u: sim.u,
                lambda: sim.lambda,
            },
        ))
    }

    /// Checks that this is a periodic process of `p` within the relative tolerance `tol`:
    /// shapes, the pieces (P_m's grid, or positive durations summing to `T`), `x^P = x^0`,
    /// `x^k in C`, `u^i in U`, zero mean, `lambda >= 0`, the step (catching-up for P_m, the
    /// exact segment for a phase, which needs `A = 0`) and complementarity. Every message names
    /// the field of `process`.
    pub fn check(&self, p: &GeneralProblem, tol: f64) -> Result<()> {
        if p.boundary != Boundary::Periodic {
            return Err(Error::invalid(
                "problem.periodic",
                false,
                "the necessary conditions are certified for periodic problems only",
            ));
        }
        match self.kind {
            ProcessKind::Discrete { m } if m > crate::optimal::general::MAX_GENERAL_M => {
                return Err(Error::invalid("process.m", m, "too many steps to certify"));
            }
            ProcessKind::Phase if !p.dynamics.is_state_independent() => {
                return Err(Error::invalid(
                    "dynamics.A",
                    "non-zero",
                    "a phase gait is a chain of straight segments only where A = 0",
                ));
            }
            _ => {}
        }
        self.check_as(p, tol, &FieldNames::process("process"))
    }

    /// [`GeneralProcess::check`] for either boundary condition (a Cauchy problem's process
    /// starts at its `x(0)` instead of ending where it began), every message naming the field
    /// as `names` says (`{at}.states[k]`, `{at}.controls[i]`, ... for a result file's
    /// solution, [`FieldNames::record`]): how a result file's P_m process is checked on reading.
    pub fn check_as(&self, p: &GeneralProblem, tol: f64, names: &FieldNames) -> Result<()> {
        self.check_rows(p, tol, names)?;
        match self.rows().fault(p, tol) {
            None => Ok(()),
            Some(fault) => Err(fault.in_words(&self.rows(), names)),
        }
    }

    /// The process's rows, borrowed, for the checks of [`ProcessRows::fault`].
    pub fn rows(&self) -> ProcessRows<'_> {
        ProcessRows {
            kind: self.kind,
            durations: &self.durations,
            x: &self.x,
            u: &self.u,
            lambda: &self.lambda,
        }
    }

    /// The grid (P_m: `2^m` steps of `T / 2^m`; a phase gait: positive durations summing to
    /// `T`), the rows' shapes and finite values.
    fn check_rows(&self, p: &GeneralProblem, tol: f64, names: &FieldNames) -> Result<()> {
        let at = names.at;
        let bad = |field: String, got: String, why: &str| {
            Err(Error::invalid(format!("{at}.{field}"), got, why))
        };
        let steps = self.durations.len();
        match self.kind {
            ProcessKind::Discrete { m } => {
                if m > crate::optimal::general::MAX_GENERAL_LOCAL_M {
                    return bad("m".into(), m.to_string(), "too many steps");
                }
                let h = p.period / (1usize << m) as f64;
                let off_grid = self.durations.iter().any(|&d| (d - h).abs() > 1e-12 * h);
                if steps != 1usize << m || off_grid {
                    return bad(
                        "durations".into(),
                        format!("{steps} pieces"),
                        &format!("P_m has 2^m = {} steps of T / 2^m", 1usize << m),
                    );
                }
            }
            ProcessKind::Phase => {
                let total: f64 = self.durations.iter().sum();
                let bad_tau = self.durations.iter().any(|&d| !(d > 0.0 && d.is_finite()));
                if steps == 0 || bad_tau || (total - p.period).abs() > tol * p.period {
                    return bad(
                        "durations".into(),
                        format!("{steps} pieces summing to {total}"),
                        "needs positive durations summing to the period",
                    );
                }
            }
        }
        let (n, mc, sigma) = (p.states(), p.controls(), p.c.faces());
        let shape = |rows: &[Vec<f64>], len: usize, width: usize| {
            rows.len() == len && rows.iter().all(|r| r.len() == width)
        };
        for (name, rows, want) in [
            (names.x, &self.x, (steps + 1, n)),
            (names.u, &self.u, (steps, mc)),
            (names.lambda, &self.lambda, (steps, sigma)),
        ] {
            if !shape(rows, want.0, want.1) {
                return bad(
                    name.into(),
                    format!("{} rows", rows.len()),
                    &format!("needs {} rows of {} values", want.0, want.1),
                );
            }
        }
        let all = self.x.iter().chain(&self.u).chain(&self.lambda);
        if all.flatten().any(|v| !v.is_finite()) {
            return bad(
                "values".into(),
                "a non-finite value".into(),
                "must be finite",
            );
        }
        Ok(())
    }

    /// `J = sum_i tau_i (f1(lambda^i) - f2(u^i))`.
    pub fn objective(&self, p: &GeneralProblem) -> f64 {
        self.u
            .iter()
            .zip(&self.lambda)
            .zip(&self.durations)
            .map(|((u, l), h)| h * (p.reward.eval(&p.c.normals, l) - p.cost.eval(u)))
            .sum()
    }
}
