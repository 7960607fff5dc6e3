//! Is a crawler's gait a process of its problem? The check every reader of a gait runs first
//! ([`super::GaitResult::check_consistent`], and so `certify`, `plot`, `report` and `--start`;
//! the certificate's own [`Process`](crate::certify::Process)): the shapes of its rows and its
//! grid, then (P)'s conditions on the crawler's instance ([`ProcessRows::fault`]), a failure
//! named in the crawler's words.

use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::process::{max_diff, Fault, ProcessKind, ProcessRows};
use crate::optimal::GaitProblem;

/// A periodic state–control pair on its own knots `t_0 = 0 < ... < t_P = T`, borrowed.
#[derive(Debug, Clone, Copy)]
pub struct ProcessView<'a> {
    /// The crawler.
    pub crawler: &'a Crawler,
    /// The gait problem (period, rate bounds, cost).
    pub problem: &'a GaitProblem,
    /// Discrete (P_m) or phase gait.
    pub kind: ProcessKind,
    /// Piece durations `tau_j` (`P` values, summing to `T`).
    pub durations: &'a [f64],
    /// Controls `u_j` per piece (force per time).
    pub controls: &'a [Vec<f64>],
    /// States at the knots (`P + 1` rows, last = first).
    pub states: &'a [Vec<f64>],
    /// Block displacements `D_{j,b}` per piece.
    pub block_displacements: &'a [Vec<f64>],
}

/// An invalid field `{what}: {field}`.
pub(crate) fn bad(what: &str, field: &str, got: impl ToString, reason: impl Into<String>) -> Error {
    Error::invalid(format!("{what}: {field}"), got, reason)
}

impl ProcessView<'_> {
    /// Checks that the data is a process of the problem (relative tolerance `tol`): the shapes
    /// of its rows and its grid (`2^m` equal steps `T / 2^m` for P_m; positive durations
    /// summing to `T`), then (P)'s conditions on the crawler's instance
    /// ([`ProcessRows::fault`]): periodicity `x(T) = x(0)`, states in C, `|u_l| <= a_l`, zero
    /// mean `int u = 0`, the dynamics `x_{j+1} = x_j + tau_j u_j - K sum_b D_{j,b} nu_b`, and
    /// the flow rule (a block moves only against an active face: at the step's end for P_m, at
    /// both ends for a phase). A failure is named in the crawler's words: the field of the
    /// gait, the block and its friction threshold, the link.
    pub fn check(&self, what: &str, tol: f64) -> Result<()> {
        self.check_shapes(what)?;
        let inst = self.problem.instance(self.crawler)?;
        let (x, lambda) = self.instance_rows();
        let rows = ProcessRows {
            kind: self.kind,
            durations: self.durations,
            x: &x,
            u: self.controls,
            lambda: &lambda,
        };
        match rows.fault(&inst.problem, tol) {
            None => Ok(()),
            Some(fault) => Err(self.in_words(&fault, what)),
        }
    }

    /// The process on the crawler's instance of (P) ([`crate::model::crawler_as_general`]):
    /// the states `x~ = K^(-1/2) x` and the reaction rates of the unit rows,
    /// `lambda_(b+-) = s_b max(+-D_b, 0) / tau_j` with `s_b = |K^(1/2) nu_b|`, per knot and per
    /// piece (controls, durations and the kind are the crawler's).
    pub fn instance_rows(&self) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let k = self.crawler.stiffness();
        let sqrt_k: Vec<f64> = k.iter().map(|k| k.sqrt()).collect();
        let s_b = crate::model::crawler_row_norms(k);
        let x = self
            .states
            .iter()
            .map(|x| x.iter().zip(&sqrt_k).map(|(x, s)| x / s).collect())
            .collect();
        let lambda = self
            .block_displacements
            .iter()
            .zip(self.durations)
            .map(|(d, &h)| {
                d.iter()
                    .zip(&s_b)
                    .flat_map(|(&v, &s)| [s * v.max(0.0) / h, s * (-v).max(0.0) / h])
                    .collect()
            })
            .collect();
        (x, lambda)
    }

    /// A fault of the instance's process in the crawler's words: face `2 b` of the instance is
    /// block `b`'s forward threshold, `2 b + 1` its backward one; the instance's states are the
    /// crawler's `solution.states`, its reactions the block displacements.
    fn in_words(&self, fault: &Fault, what: &str) -> Error {
        let np = self.durations.len();
        let a = &self.problem.rate_bound;
        let worst = |v: &[f64]| {
            (0..v.len())
                .max_by(|&i, &j| (v[i].abs() / a[i]).total_cmp(&(v[j].abs() / a[j])))
                .unwrap_or(0)
        };
        match *fault {
            Fault::NotPeriodic { .. } => {
                let per = max_diff(&self.states[0], &self.states[np]);
                bad(
                    what,
                    &format!("solution.states[{np}]"),
                    format!("{:?}", self.states[np]),
                    format!(
                        "the process is not periodic: x(T) differs from x(0) = {:?} by {per:.3e}",
                        self.states[0]
                    ),
                )
            }
            Fault::NotInitial { .. } => bad(
                what,
                "solution.states[0]",
                format!("{:?}", self.states[0]),
                "must be the initial state",
            ),
            Fault::Outside { k, face, .. } => self.outside_words(k, face, what),
            Fault::ControlOutside { i } => {
                let l = worst(&self.controls[i]);
                bad(
                    what,
                    &format!("solution.controls[{i}][{l}]"),
                    self.controls[i][l],
                    format!("exceeds the rate bound a = {}", a[l]),
                )
            }
            Fault::Mean { ref mean } => {
                let l = worst(mean);
                bad(
                    what,
                    "solution.controls",
                    format!("int u_{} dt = {:.6e}", l + 1, mean[l] * self.problem.period),
                    "the control must have zero mean (a periodic actuation)",
                )
            }
            Fault::Negative { i, face } | Fault::Inactive { i, face } => {
                self.flow_words(i, face, matches!(fault, Fault::Negative { .. }), what)
            }
            Fault::Step { i, .. } => self.step_words(i, what),
        }
    }

    /// [`Self::in_words`] of a state outside C: the block whose force passes its threshold.
    fn outside_words(&self, k: usize, face: usize, what: &str) -> Error {
        let c = self.crawler;
        let (b, x) = (face / 2, &self.states[k]);
        let f = c.block_forces(x)[b];
        let detail = if face % 2 == 0 {
            let mu = c.mu_forward()[b];
            format!(
                "spring force on block {} is {f} > mu_forward = {mu} (by {:.3e})",
                b + 1,
                f - mu
            )
        } else {
            let mu = c.mu_backward()[b];
            format!(
                "spring force on block {} is {f} < -mu_backward = {} (by {:.3e})",
                b + 1,
                -mu,
                -mu - f
            )
        };
        Error::Inadmissible {
            what: format!("{what}: solution.states[{k}]"),
            detail,
        }
    }

    /// [`Self::in_words`] of a block displacement against the flow rule on piece `i`: of the
    /// wrong sign (`negative`), or with its threshold not reached.
    fn flow_words(&self, i: usize, face: usize, negative: bool, what: &str) -> Error {
        let b = face / 2;
        let reason = if negative {
            format!(
                "block {} has a negative displacement rate on piece {i}",
                b + 1
            )
        } else {
            format!(
                "block {} moves on piece {i} but its friction threshold is not \
                 reached{} (flow rule, theory §2)",
                b + 1,
                match self.kind {
                    ProcessKind::Discrete { .. } => " at the step's end",
                    ProcessKind::Phase => {
                        " at both ends of the phase (split phases where a face is \
                         reached or left)"
                    }
                }
            )
        };
        bad(
            what,
            &format!("solution.block_displacements[{i}][{b}]"),
            self.block_displacements[i][b],
            reason,
        )
    }

    /// [`Self::in_words`] of a state that does not follow from the previous one, the control
    /// and the block displacements of piece `i`: the link of the largest residual.
    fn step_words(&self, i: usize, what: &str) -> Error {
        let c = self.crawler;
        // x1 - x0 - tau u + k_l (D_{l+1} - D_l) (K sum_b D_b nu_b, nu_b = e_{b-1} - e_b).
        let (x0, x1) = (&self.states[i], &self.states[i + 1]);
        let (u, d, k) = (
            &self.controls[i],
            &self.block_displacements[i],
            c.stiffness(),
        );
        let r: Vec<f64> = (0..c.links())
            .map(|l| x1[l] - x0[l] - self.durations[i] * u[l] + k[l] * (d[l + 1] - d[l]))
            .collect();
        let l = (0..r.len())
            .max_by(|&p, &q| r[p].abs().total_cmp(&r[q].abs()))
            .unwrap_or(0);
        bad(
            what,
            &format!("solution.states[{}]", i + 1),
            format!("{:?}", x1),
            format!(
                "does not follow from solution.states[{i}], the control and the block \
                 displacements of piece {i} (link {}: residual {:.3e})",
                l + 1,
                r[l]
            ),
        )
    }

    /// The shapes of the process's rows, finite values, and its grid: positive durations
    /// summing to `T`, for P_m `2^m` equal steps `T / 2^m` (`m` in `1..=MAX_M`).
    fn check_shapes(&self, what: &str) -> Result<()> {
        let (n, nb) = (self.crawler.links(), self.crawler.blocks());
        let t = self.problem.period;
        let np = self.durations.len();
        for (field, rows, want, width) in [
            ("solution.controls", self.controls, np, n),
            ("solution.states", self.states, np + 1, n),
            (
                "solution.block_displacements",
                self.block_displacements,
                np,
                nb,
            ),
        ] {
            if rows.len() != want {
                return Err(bad(
                    what,
                    field,
                    format!("{} rows", rows.len()),
                    format!("needs {want} rows"),
                ));
            }
            if let Some(j) = rows.iter().position(|r| r.len() != width) {
                return Err(bad(
                    what,
                    &format!("{field}[{j}]"),
                    format!("{} values", rows[j].len()),
                    format!("needs {width} values"),
                ));
            }
            if rows.iter().flatten().any(|v| !v.is_finite()) {
                return Err(bad(what, field, "a non-finite value", "must be finite"));
            }
        }
        check_durations(what, "solution.durations", self.durations, t)?;
        if let ProcessKind::Discrete { m } = self.kind {
            if m == 0 || m > super::MAX_M {
                return Err(bad(
                    what,
                    "m",
                    m,
                    format!("must be in 1..={}", super::MAX_M),
                ));
            }
            let steps = 1usize << m;
            if np != steps {
                return Err(bad(
                    what,
                    "solution.durations",
                    format!("{np} steps"),
                    format!("a P_{m} gait lives on the dyadic grid of 2^{m} = {steps} steps"),
                ));
            }
            let h = t / steps as f64;
            if let Some(j) = self.durations.iter().position(|d| (d - h).abs() > 1e-9 * h) {
                return Err(bad(
                    what,
                    &format!("solution.durations[{j}]"),
                    self.durations[j],
                    format!("a P_{m} step must be h = T / 2^{m} = {h}"),
                ));
            }
        }
        Ok(())
    }
}

/// Phase durations read back (`field` names them): each positive and finite, summing to the
/// period `t` within `1e-9` relative; crawler and general results alike.
pub(crate) fn check_durations(what: &str, field: &str, durations: &[f64], t: f64) -> Result<()> {
    if let Some(j) = durations.iter().position(|d| !(d.is_finite() && *d > 0.0)) {
        return Err(bad(
            what,
            &format!("{field}[{j}]"),
            durations[j],
            "must be positive and finite",
        ));
    }
    let total: f64 = durations.iter().sum();
    if (total - t).abs() > 1e-9 * t {
        return Err(bad(
            what,
            field,
            format!("a sum of {total}"),
            format!("must sum to the period {t}"),
        ));
    }
    Ok(())
}
