//! The process a general certificate is about ([`crate::certify::general`]): a periodic P_m
//! process of the general problem, from an optimum or from controls by simulation, checked for
//! consistency before any multiplier is computed (a certificate of something that is not a
//! process would be a silent wrong number), every message naming the field.

use crate::error::{Error, Result};
use crate::integrate::{simulate_general, ControlInput, GeneralSimOptions, InputKind};
use crate::model::general::{Boundary, ControlSet, GeneralProblem};
use crate::optimal::general::GeneralPm;
use serde::Serialize;

/// The rows `(G_k, h_k)` of U: a box as `e_l <= upper_l`, `-e_l <= -lower_l` (in this order per
/// component), a polytope's unit rows as given.
pub(crate) fn control_rows(u: &ControlSet) -> Vec<(Vec<f64>, f64)> {
    match u {
        ControlSet::Box { lower, upper } => {
            let m = lower.len();
            let unit = |l: usize, s: f64| (0..m).map(|k| if k == l { s } else { 0.0 }).collect();
            (0..m)
                .flat_map(|l| [(unit(l, 1.0), upper[l]), (unit(l, -1.0), -lower[l])])
                .collect()
        }
        ControlSet::Polytope(p) => p.normals.iter().cloned().zip(p.offsets.clone()).collect(),
    }
}

/// A periodic P_m process of the general problem: `x^0..x^M` (`x^M = x^0`), `u^0..u^(M-1)`
/// and the reactions `lambda^i = mu^i / h` per face.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralProcess {
    /// `m` (`M = 2^m` steps).
    pub m: u32,
    /// States at the knots (`M + 1` rows).
    pub x: Vec<Vec<f64>>,
    /// Controls per step.
    pub u: Vec<Vec<f64>>,
    /// Reactions per step and face.
    pub lambda: Vec<Vec<f64>>,
}

impl GeneralProcess {
    /// The process of a P_m optimum.
    pub fn from_pm(s: &GeneralPm) -> Self {
        GeneralProcess {
            m: s.m,
            x: s.x.clone(),
            u: s.u.clone(),
            lambda: s.lambda.clone(),
        }
    }

    /// The process of a local P_m answer.
    pub fn from_local(s: &crate::optimal::general::GeneralLocal) -> Self {
        GeneralProcess {
            m: s.m,
            x: s.x.clone(),
            u: s.u.clone(),
            lambda: s.lambda.clone(),
        }
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
        Ok(GeneralProcess {
            m,
            x: sim.x,
            u: sim.u,
            lambda: sim.lambda,
        })
    }

    /// Checks that this is a periodic P_m process of `p` within the relative tolerance `tol`:
    /// shapes, `x^M = x^0`, `x^k in C`, `u^i in U`, zero mean, `lambda >= 0`, the catching-up
    /// step and complementarity. Every message names the field of `process`.
    pub fn check(&self, p: &GeneralProblem, tol: f64) -> Result<()> {
        if p.boundary != Boundary::Periodic {
            return Err(Error::invalid(
                "problem.periodic",
                false,
                "the necessary conditions are certified for periodic problems only",
            ));
        }
        if self.m > crate::optimal::general::MAX_GENERAL_M {
            return Err(Error::invalid(
                "process.m",
                self.m,
                "too many steps to certify",
            ));
        }
        self.check_as(p, tol, "process")
    }

    /// [`GeneralProcess::check`] for either boundary condition (a Cauchy problem's process
    /// starts at its `x(0)` instead of ending where it began), every message naming the field
    /// as `{at}.x[k]`, `{at}.u[i]`, ...: how a result file's P_m process is checked on reading.
    pub fn check_as(&self, p: &GeneralProblem, tol: f64, at: &str) -> Result<()> {
        let bad = |field: String, got: String, why: &str| {
            Err(Error::invalid(format!("{at}.{field}"), got, why))
        };
        if self.m > crate::optimal::general::MAX_GENERAL_LOCAL_M {
            return bad("m".into(), self.m.to_string(), "too many steps");
        }
        let (n, mc, sigma, steps) = (p.states(), p.controls(), p.c.faces(), 1usize << self.m);
        let shape = |rows: &[Vec<f64>], len: usize, width: usize| {
            rows.len() == len && rows.iter().all(|r| r.len() == width)
        };
        for (name, rows, want) in [
            ("x", &self.x, (steps + 1, n)),
            ("u", &self.u, (steps, mc)),
            ("lambda", &self.lambda, (steps, sigma)),
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
        let scale = p.c.scale();
        let h = p.period / steps as f64;
        match &p.boundary {
            Boundary::Periodic => {
                let gap = max_diff(&self.x[steps], &self.x[0]);
                if gap > tol * scale {
                    return bad(
                        format!("x[{steps}]"),
                        format!("{gap:e} from x[0]"),
                        "not periodic",
                    );
                }
            }
            Boundary::Initial(x0) => {
                let gap = max_diff(&self.x[0], x0);
                if gap > tol * scale {
                    return bad(
                        "x[0]".into(),
                        format!("{gap:e} from problem.initial_state"),
                        "must be the initial state",
                    );
                }
            }
        }
        for (k, x) in self.x.iter().enumerate() {
            if let Some((j, s)) = p.c.violation(x, tol * scale) {
                return bad(
                    format!("x[{k}]"),
                    format!("{s:e}"),
                    &format!("outside face {}", j + 1),
                );
            }
        }
        let uscale = control_rows(&p.control)
            .iter()
            .fold(0.0_f64, |s, (_, h)| s.max(h.abs()));
        let mut mean = vec![0.0; mc];
        for (i, u) in self.u.iter().enumerate() {
            if !p.control.contains(u, tol * uscale) {
                return bad(format!("u[{i}]"), format!("{u:?}"), "outside U");
            }
            for (m, v) in mean.iter_mut().zip(u) {
                *m += v / steps as f64;
            }
        }
        if p.zero_mean && mean.iter().any(|v| v.abs() > tol * uscale) {
            return bad("u".into(), format!("mean {mean:?}"), "must have zero mean");
        }
        let mut g = vec![0.0; n];
        for i in 0..steps {
            let lam = &self.lambda[i];
            if let Some(j) = lam.iter().position(|&l| h * l < -tol * scale) {
                return bad(format!("lambda[{i}][{j}]"), lam[j].to_string(), "negative");
            }
            p.dynamics.eval(&self.x[i], &self.u[i], &mut g);
            let mut res = 0.0_f64;
            for l in 0..n {
                let react: f64 = (0..sigma).map(|j| lam[j] * p.c.normals[j][l]).sum();
                let v = self.x[i][l] + h * (g[l] - react) - self.x[i + 1][l];
                res = res.max(v.abs());
            }
            if res > tol * scale {
                return bad(
                    format!("x[{}]", i + 1),
                    format!("{res:e}"),
                    &format!(
                        "does not follow from {s}.x[{i}], {s}.u[{i}] and {s}.lambda[{i}] by the \
                         catching-up step x^(i+1) = x^i + h (g - sum lambda x*)",
                        s = at.rsplit(": ").next().unwrap_or(at)
                    ),
                );
            }
            for j in 0..sigma {
                let c = h * lam[j] * (-p.c.slack(j, &self.x[i + 1]));
                if c > tol * scale * scale {
                    return bad(
                        format!("lambda[{i}][{}]", j + 1),
                        lam[j].to_string(),
                        "reaction on an inactive face",
                    );
                }
            }
        }
        Ok(())
    }

    /// `J = sum_i h (f1(lambda^i) - f2(u^i))`.
    pub fn objective(&self, p: &GeneralProblem) -> f64 {
        let h = p.period / self.u.len() as f64;
        self.u
            .iter()
            .zip(&self.lambda)
            .map(|(u, l)| h * (p.reward.eval(&p.c.normals, l) - p.cost.eval(u)))
            .sum()
    }
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |d, (x, y)| d.max((x - y).abs()))
}
