//! The process to certify: a periodic state–control pair on its own knots, read from a
//! [`GaitResult`] (or built from controls by simulation) and checked for consistency before any
//! multiplier is computed. A certificate of a process that is not a process would be a silent
//! wrong number, so every check here names what is wrong.

use crate::error::{Error, Result};
use crate::integrate::Method;
use crate::model::Crawler;
use crate::optimal::{replay, GaitProblem, GaitResult};

/// Default relative tolerance on the consistency of an input process (states in C, periodicity,
/// zero mean, dynamics): relative to the size of C, the rate bounds and the period. Loose enough
/// for a gait written with ten significant digits, tight enough that the first-order conditions
/// are meaningful at the `1e-9` level of the certificate.
pub const INPUT_TOL: f64 = 1e-7;

/// How the process was discretised, which fixes where a slipping block's face must be active.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProcessKind {
    /// A P_m process (SPEC §6): `2^m` equal catching-up steps; a block slipping on step `i`
    /// has its face active at the end `x^{i+1}` (implicit Euler).
    Discrete {
        /// `m`.
        m: u32,
    },
    /// A phase gait (SPEC §7): constant control per phase, exact; a block slipping on a phase
    /// has its face active at both ends (held throughout).
    Phase,
}

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

fn bad(what: &str, field: &str, got: impl ToString, reason: impl Into<String>) -> Error {
    Error::invalid(format!("{what}: {field}"), got, reason)
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
    /// names the source in errors.
    pub fn from_result(r: &GaitResult, what: &str) -> Result<Self> {
        let crawler = r.crawler.crawler()?;
        crawler.require_unique()?;
        r.problem.validate(&crawler)?;
        let g = &r.gait;
        let kind = match (r.method.as_str(), r.m) {
            // A local answer is a P_m process like a global one.
            ("discrete" | "local", Some(m)) => ProcessKind::Discrete { m },
            ("discrete" | "local", None) => {
                return Err(bad(what, "m", "nothing", "a discrete (P_m) result needs m"))
            }
            ("phase", _) => ProcessKind::Phase,
            (other, _) => {
                return Err(bad(
                    what,
                    "method",
                    other,
                    "must be \"discrete\", \"local\" or \"phase\"",
                ))
            }
        };
        let p = Process {
            crawler,
            problem: r.problem.clone(),
            kind,
            durations: g.durations.clone(),
            controls: g.controls.clone(),
            states: g.states.clone(),
            block_displacements: g.block_displacements.clone(),
        };
        // The knot times and the initial state are redundant with durations and states: they
        // must agree.
        let t = p.times();
        if g.times.len() != t.len() {
            return Err(bad(
                what,
                "gait.times",
                format!("{} knots", g.times.len()),
                format!("needs {} knots", t.len()),
            ));
        }
        for (j, (a, b)) in g.times.iter().zip(&t).enumerate() {
            if (a - b).abs() > 1e-9 * p.problem.period {
                return Err(bad(
                    what,
                    &format!("gait.times[{j}]"),
                    a,
                    format!("disagrees with the sum of the durations before it ({b})"),
                ));
            }
        }
        if let Some(x0) = p.states.first() {
            let d = max_diff(x0, &g.initial_state);
            if d > INPUT_TOL * p.crawler.state_scale() {
                return Err(bad(
                    what,
                    "gait.initial_state",
                    format!("{:?}", g.initial_state),
                    format!("differs from gait.states[0] by {d:.3e}"),
                ));
            }
        }
        p.check(what, INPUT_TOL)?;
        Ok(p)
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
        // exact method, so that every piece has one slip mode (SPEC §7).
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
        let c = &self.crawler;
        let (n, nb) = (c.links(), c.blocks());
        let t = self.problem.period;
        let a = &self.problem.rate_bound;
        let np = self.durations.len();
        if self.problem.max_total_variation.is_some() {
            return Err(bad(
                what,
                "problem.max_total_variation",
                "a bound",
                "is not covered by the necessary conditions (Theorem 2.2 has no TV bound)",
            ));
        }
        if np < 2 {
            return Err(bad(
                what,
                "gait.durations",
                format!("{np} pieces"),
                "needs at least two pieces",
            ));
        }
        for (field, rows, want, width) in [
            ("gait.controls", &self.controls, np, n),
            ("gait.states", &self.states, np + 1, n),
            (
                "gait.block_displacements",
                &self.block_displacements,
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
        if let Some(j) = self
            .durations
            .iter()
            .position(|d| !(d.is_finite() && *d > 0.0))
        {
            return Err(bad(
                what,
                &format!("gait.durations[{j}]"),
                self.durations[j],
                "must be positive and finite",
            ));
        }
        let total: f64 = self.durations.iter().sum();
        if (total - t).abs() > 1e-9 * t {
            return Err(bad(
                what,
                "gait.durations",
                format!("a sum of {total}"),
                format!("must sum to the period {t}"),
            ));
        }
        if let ProcessKind::Discrete { m } = self.kind {
            if m == 0 || m > crate::optimal::MAX_M {
                return Err(bad(
                    what,
                    "m",
                    m,
                    format!("must be in 1..={}", crate::optimal::MAX_M),
                ));
            }
            let steps = 1usize << m;
            if np != steps {
                return Err(bad(
                    what,
                    "gait.durations",
                    format!("{np} steps"),
                    format!("a P_{m} gait lives on the dyadic grid of 2^{m} = {steps} steps"),
                ));
            }
            let h = t / steps as f64;
            if let Some(j) = self.durations.iter().position(|d| (d - h).abs() > 1e-9 * h) {
                return Err(bad(
                    what,
                    &format!("gait.durations[{j}]"),
                    self.durations[j],
                    format!("a P_{m} step must be h = T / 2^{m} = {h}"),
                ));
            }
        }
        let scale = c.state_scale();
        for (j, x) in self.states.iter().enumerate() {
            c.check_admissible(&format!("{what}: gait.states[{j}]"), x, tol)?;
        }
        let per = max_diff(&self.states[0], &self.states[np]);
        if per > tol * scale {
            return Err(bad(
                what,
                &format!("gait.states[{np}]"),
                format!("{:?}", self.states[np]),
                format!(
                    "the process is not periodic: x(T) differs from x(0) = {:?} by {per:.3e}",
                    self.states[0]
                ),
            ));
        }
        for (j, u) in self.controls.iter().enumerate() {
            for l in 0..n {
                if u[l].abs() > a[l] * (1.0 + tol) {
                    return Err(bad(
                        what,
                        &format!("gait.controls[{j}][{l}]"),
                        u[l],
                        format!("exceeds the rate bound a = {}", a[l]),
                    ));
                }
            }
        }
        for l in 0..n {
            let mean: f64 = self
                .controls
                .iter()
                .zip(&self.durations)
                .map(|(u, d)| u[l] * d)
                .sum();
            if mean.abs() > tol * a[l] * t {
                return Err(bad(
                    what,
                    "gait.controls",
                    format!("int u_{} dt = {mean:.6e}", l + 1),
                    "the control must have zero mean (a periodic actuation)",
                ));
            }
        }
        let k = c.stiffness();
        let dtol = d_tol(c, tol);
        for j in 0..np {
            let (x0, x1, u, d) = (
                &self.states[j],
                &self.states[j + 1],
                &self.controls[j],
                &self.block_displacements[j],
            );
            // x1 - x0 - tau u + k_l (D_{l+1} - D_l) = 0 (K sum_b D_b nu_b, nu_b = e_{b-1} - e_b).
            for l in 0..n {
                let r = x1[l] - x0[l] - self.durations[j] * u[l] + k[l] * (d[l + 1] - d[l]);
                if r.abs() > tol * scale.max(a[l] * self.durations[j]) {
                    return Err(bad(
                        what,
                        &format!("gait.states[{}]", j + 1),
                        format!("{:?}", x1),
                        format!(
                            "does not follow from gait.states[{j}], the control and the block \
                             displacements of piece {j} (link {}: residual {r:.3e})",
                            l + 1
                        ),
                    ));
                }
            }
            let f1 = c.block_forces(x1);
            let f0 = c.block_forces(x0);
            for b in 0..nb {
                let s = slip(d[b], dtol);
                if s == 0 {
                    continue;
                }
                let on = |f: f64| {
                    if s > 0 {
                        (f - c.mu_forward()[b]).abs() <= tol * scale
                    } else {
                        (f + c.mu_backward()[b]).abs() <= tol * scale
                    }
                };
                let ends_ok = match self.kind {
                    ProcessKind::Discrete { .. } => on(f1[b]),
                    ProcessKind::Phase => on(f0[b]) && on(f1[b]),
                };
                if !ends_ok {
                    return Err(bad(
                        what,
                        &format!("gait.block_displacements[{j}][{b}]"),
                        d[b],
                        format!(
                            "block {} moves on piece {j} but its friction threshold is not \
                             reached{} (flow rule, SPEC §2)",
                            b + 1,
                            match self.kind {
                                ProcessKind::Discrete { .. } => " at the step's end",
                                ProcessKind::Phase => {
                                    " at both ends of the phase (split phases where a face is \
                                     reached or left)"
                                }
                            }
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `max_l |a_l - b_l|` (infinite when the lengths differ).
pub(crate) fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Displacements below this are "no motion": `tol` times the size of C over the stiffest link.
pub(crate) fn d_tol(c: &Crawler, tol: f64) -> f64 {
    let kmax = c.stiffness().iter().fold(0.0_f64, |m, &k| m.max(k));
    tol * c.state_scale() / kmax
}

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
