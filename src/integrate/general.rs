//! Simulation of the general problem (P) (theory §11) for a given control: the catching-up scheme
//! on `M` uniform steps of a period, with the exact projection of [`crate::sweep::polyhedron`];
//! the reactions `lambda^i = mu^i / h` per face (the projection's multipliers divided by `h`),
//! and the functional `J = sum_i h (f1(eta^i) - f2(u^i))` (paper eq. 2.3, discretised as in §6).
//!
//! Two steps ([`DriftStep`]), with `A = S_- + (S_+ + K)` split as in
//! [`crate::model::general::DriftSplit`]:
//! - explicit (the paper's P_m, §6): `x^(i+1) = Proj_C(x^i + h g(x^i, u^i))`; refused when
//!   `h |S_- + K|_2` exceeds [`EXPLICIT_STEP_LIMIT`] (a stiff decaying drift would oscillate
//!   between faces and give a reward wrong by orders of magnitude);
//! - semi-implicit (the default): the damping `S_-` at the new state,
//!   `x^(i+1) - x^i - h (S_- x^(i+1) + (S_+ + K) x^i + B u^i + b) in -h N_C(x^(i+1))`, i.e.
//!   `x^(i+1)` is the projection onto C of `v = M^-1 ((I + h (S_+ + K)) x^i + h (B u^i + b))`
//!   in the metric of `M = I - h S_-` (computed as a Euclidean projection in `z = L^T x`,
//!   `M = L L^T`), and `h M (v - x^(i+1)) = h sum_j lambda_j x*_j`, so the reaction on a face
//!   that holds the state is `g`'s normal component, as in the continuous problem. Stable for
//!   any step in the damped directions (backward Euler); the growing part `S_+` is explicit
//!   (forward Euler under-grows, never oscillates, and C holds it); only a rotating part `K`
//!   limits the step, `h |K|_2 <= EXPLICIT_STEP_LIMIT` and `T h |K|_2^2 / 2 <= 1` (forward Euler
//!   grows a rotation by `(1 + (h |K|)^2)^(1/2)` a step), and the precision of a state held on a
//!   face by the growing part, `h |S_+|_2 <= GROWTH_STEP_LIMIT`. With `S_- = 0` both steps are
//!   the same.
//!
//! `u^i` is the mean of the control over step `i` (exact integrals of the piecewise-constant or
//! piecewise-linear input), so that for `g = B u` the scheme sees the exact increment
//! `B int u dt` of each step, as the crawler's catching-up does with `K (L(t_(i+1)) - L(t_i))`.
//!
//! Periodic problems: the period map is iterated until the state repeats within `tol` times
//! C's scale, and `J` is the value of one period on that orbit. Cauchy problems: one horizon
//! `[0, T]` from `x(0)`.

use crate::error::{Error, Result};
use crate::model::general::{
    min_steps, Boundary, ControlSet, GeneralProblem, Polyhedron, EXPLICIT_STEP_LIMIT,
    GROWTH_STEP_LIMIT,
};
use crate::model::ChainView;
use crate::sweep::{OntoC, PolyProjector};
use serde::Serialize;

/// How the given control is interpolated between its knots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InputKind {
    /// `u(t) = u_k` on `[t_k, t_(k+1))`, the last value up to `T`.
    PiecewiseConstant,
    /// Linear between knots, from the last knot back to the first value at `t = T`.
    PiecewiseLinear,
}

/// A `T`-periodic control `u(t)` given at knots `0 = t_0 < t_1 < ... < T`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControlInput {
    /// Interpolation.
    pub kind: InputKind,
    /// Period `T`.
    pub period: f64,
    /// Knot times.
    pub times: Vec<f64>,
    /// Knot values, one row of `m` per knot.
    pub values: Vec<Vec<f64>>,
}

impl ControlInput {
    /// Checks the knots (times from 0, increasing, below the period; one row of `m` finite
    /// values per knot, each in U, so that the whole control lies in U by convexity). `field`
    /// prefixes the messages (`input`).
    pub fn new(
        kind: InputKind,
        period: f64,
        times: Vec<f64>,
        values: Vec<Vec<f64>>,
        control: &ControlSet,
        field: &str,
    ) -> Result<Self> {
        if times.is_empty() || times[0] != 0.0 {
            return Err(Error::invalid(
                format!("{field}.times"),
                format!("{times:?}"),
                "needs knots starting at t = 0",
            ));
        }
        for k in 1..times.len() {
            if !(times[k] > times[k - 1] && times[k] < period && times[k].is_finite()) {
                return Err(Error::invalid(
                    format!("{field}.times[{}]", k + 1),
                    times[k],
                    "knot times must increase and stay below the period",
                ));
            }
        }
        if values.len() != times.len() {
            return Err(Error::invalid(
                format!("{field}.values"),
                format!("{} rows", values.len()),
                format!("needs one row per knot ({})", times.len()),
            ));
        }
        let m = control.dim();
        let tol = 1e-12 * values.iter().flatten().fold(1.0_f64, |s, v| s.max(v.abs()));
        for (k, row) in values.iter().enumerate() {
            let f = format!("{field}.values[{}]", k + 1);
            if row.len() != m {
                return Err(Error::invalid(
                    &f,
                    format!("{} values", row.len()),
                    format!("needs one value per control ({m})"),
                ));
            }
            if let Some(i) = row.iter().position(|v| !v.is_finite()) {
                return Err(Error::invalid(
                    format!("{f}[{}]", i + 1),
                    row[i],
                    "must be finite",
                ));
            }
            if !control.contains(row, tol) {
                return Err(Error::invalid(&f, format!("{row:?}"), "lies outside U"));
            }
        }
        Ok(ControlInput {
            kind,
            period,
            times,
            values,
        })
    }

    /// The end of knot interval `s`: the next knot, or `T` after the last.
    fn interval_end(&self, s: usize) -> f64 {
        self.times.get(s + 1).copied().unwrap_or(self.period)
    }

    /// Adds `int_a^e u` over knot interval `s` (`[a, b)`, `a < e <= b`) to `out`.
    fn add_interval(&self, s: usize, e: f64, out: &mut [f64]) {
        let k = self.times.len();
        let (a, b) = (self.times[s], self.interval_end(s));
        let next = &self.values[(s + 1) % k];
        for (i, o) in out.iter_mut().enumerate() {
            let u0 = self.values[s][i];
            *o += match self.kind {
                InputKind::PiecewiseConstant => u0 * (e - a),
                InputKind::PiecewiseLinear => {
                    let slope = (next[i] - u0) / (b - a);
                    u0 * (e - a) + 0.5 * slope * (e - a) * (e - a)
                }
            };
        }
    }

    /// `int_0^t u` for `t` in `[0, T]`, into `out`.
    fn integral_within(&self, t: f64, out: &mut [f64]) {
        out.iter_mut().for_each(|o| *o = 0.0);
        let k = self.times.len();
        for s in 0..k {
            if t <= self.times[s] {
                break;
            }
            self.add_interval(s, t.min(self.interval_end(s)), out);
        }
    }

    /// The mean of `u` over `[t0, t1]` (`0 <= t0 < t1 <= T`), into `out`.
    pub fn mean(&self, t0: f64, t1: f64, out: &mut [f64]) {
        let mut a = vec![0.0; out.len()];
        self.integral_within(t0, &mut a);
        self.integral_within(t1, out);
        for (o, a) in out.iter_mut().zip(&a) {
            *o = (*o - a) / (t1 - t0);
        }
    }

    /// The means of `u` over the `mm` steps of the uniform grid `h = T / mm` (the last step
    /// ending at `T`), the controls a simulation or P_m steps with: [`ControlInput::mean`] of
    /// each step, the same numbers to the bit, in one sweep over the knots (`O(M + K)` for `K`
    /// knots where the means one by one cost `O(M K)`, 3 % of a crawler's
    /// `optimize --method local --m 10`).
    pub fn step_means(&self, mm: usize) -> Vec<Vec<f64>> {
        let (k, m) = (self.times.len(), self.values[0].len());
        let h = self.period / mm as f64;
        // `int_0^(t_s) u` over the whole intervals before `s`, the last that starts before `t`,
        // summed in the order `integral_within` sums them.
        let (mut whole, mut s) = (vec![0.0; m], 0);
        let mut before = vec![0.0; m];
        let mut now = vec![0.0; m];
        (0..mm)
            .map(|i| {
                let t0 = i as f64 * h;
                let t1 = if i + 1 == mm {
                    self.period
                } else {
                    (i + 1) as f64 * h
                };
                while s + 1 < k && self.times[s + 1] < t1 {
                    self.add_interval(s, self.times[s + 1], &mut whole);
                    s += 1;
                }
                now.copy_from_slice(&whole);
                self.add_interval(s, t1.min(self.interval_end(s)), &mut now);
                let row = now
                    .iter()
                    .zip(&before)
                    .map(|(n, b)| (n - b) / (t1 - t0))
                    .collect();
                std::mem::swap(&mut before, &mut now);
                row
            })
            .collect()
    }
}

/// Which integrator `crate::api::simulate_general` uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GeneralMethod {
    /// Exact where it applies (`A = 0` and a piecewise-constant input), else catching-up.
    Auto,
    /// Catching-up ([`simulate_general`]).
    CatchingUp,
}

impl From<super::Method> for GeneralMethod {
    /// The crawler's method's name on (P): exact where it applies, else catching-up.
    fn from(m: super::Method) -> Self {
        match m {
            super::Method::Exact => GeneralMethod::Auto,
            super::Method::CatchingUp => GeneralMethod::CatchingUp,
        }
    }
}

/// How [`simulate_general`] steps the drift `A x` (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DriftStep {
    /// Damping implicit, the rest explicit: stable for any step unless `A` rotates.
    SemiImplicit,
    /// All explicit: the paper's P_m, whose answers the optimisers replay with it.
    Explicit,
}

/// Options of [`simulate_general`].
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralSimOptions {
    /// The integrator chosen by `crate::api::simulate_general` (default auto);
    /// [`simulate_general`] itself is catching-up.
    pub method: GeneralMethod,
    /// Steps `M` per period.
    pub steps_per_period: usize,
    /// Give up the search for the periodic regime after this many periods.
    pub max_periods: usize,
    /// The state repeats when it changes by at most `tol` times C's scale over a period.
    pub tol: f64,
    /// The step of the drift (default semi-implicit; P_m's replays are explicit).
    pub drift: DriftStep,
}

impl GeneralSimOptions {
    /// The defaults.
    pub const DEFAULT: GeneralSimOptions = GeneralSimOptions {
        method: GeneralMethod::Auto,
        steps_per_period: 1000,
        max_periods: 5000,
        tol: 1e-12,
        drift: DriftStep::SemiImplicit,
    };

    /// Checks the options for a problem whose recorded period holds `per_step` values a step
    /// (states, controls, reactions): at most `super::periodic::MAX_RECORDED` in all.
    /// Both general methods are held to it, so that no setting is accepted by one and refused
    /// by the other.
    pub fn check(&self, per_step: usize) -> Result<()> {
        if (self.steps_per_period as f64) * (per_step as f64) > super::periodic::MAX_RECORDED {
            return Err(Error::invalid(
                "steps_per_period",
                self.steps_per_period,
                format!(
                    "the recorded period would hold more than {:e} values",
                    super::periodic::MAX_RECORDED
                ),
            ));
        }
        if self.steps_per_period == 0
            || self.steps_per_period > super::periodic::MAX_STEPS_PER_PERIOD
        {
            return Err(Error::invalid(
                "steps_per_period",
                self.steps_per_period,
                format!(
                    "must be between 1 and {}",
                    super::periodic::MAX_STEPS_PER_PERIOD
                ),
            ));
        }
        if self.max_periods == 0 {
            return Err(Error::invalid("max_periods", 0, "must be at least 1"));
        }
        super::periodic::check_tol(self.tol)
    }
}

impl Default for GeneralSimOptions {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A simulated period (or horizon) of the general problem.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeneralSimulation {
    /// Periodic problems: whether the state repeated (the values below are then on the
    /// orbit); Cauchy problems: always true.
    pub converged: bool,
    /// Periods integrated (the transient included).
    pub periods: usize,
    /// `J = int f1(eta) - f2(u)` over the recorded period (`None` without a periodic regime).
    pub objective: Option<f64>,
    /// `int f1(eta)` over it.
    pub reward: f64,
    /// `int f2(u)` over it.
    pub cost: f64,
    /// The mean of the control over a period (0 under the zero-mean constraint).
    pub mean_control: Vec<f64>,
    /// Times `t_i = i h`, `i = 0..M`.
    pub t: Vec<f64>,
    /// States `x^i` (`M + 1` rows).
    pub x: Vec<Vec<f64>>,
    /// Controls `u^i` (`M` rows: the mean over each step).
    pub u: Vec<Vec<f64>>,
    /// Reactions per face `lambda^i = mu^i / h` (`M` rows of `sigma`).
    pub lambda: Vec<Vec<f64>>,
    /// The projection of the catching-up steps ([`crate::sweep::OntoC`]): `"chain"` (the
    /// crawler's O(N) projection, where (P) is a crawler's chain) or `"dense"` (the general
    /// active-set method; also the exact method's tangent cones).
    pub projection: &'static str,
    /// The largest KKT residual of a projection of the recorded period (for the semi-implicit
    /// step with a damping, of the Euclidean projection in `z = L^T x`).
    pub max_kkt_residual: f64,
}

/// Simulates `p` under `input` from `x0` (a point of C; the problem's `x(0)` for a Cauchy
/// problem). See the module docs.
pub fn simulate_general(
    p: &GeneralProblem,
    input: &ControlInput,
    x0: &[f64],
    opts: &GeneralSimOptions,
) -> Result<GeneralSimulation> {
    simulate_general_on(p, p.as_chain().as_ref(), input, x0, opts)
}

/// [`simulate_general`] with the problem's structure already recognised: `chain` is
/// `p.as_chain()` (a caller that simulates one problem several times recognises it once; crate
/// only, since a view of another problem would project onto the wrong set).
pub(crate) fn simulate_general_on(
    p: &GeneralProblem,
    chain: Option<&ChainView>,
    input: &ControlInput,
    x0: &[f64],
    opts: &GeneralSimOptions,
) -> Result<GeneralSimulation> {
    opts.check(p.states() + p.controls() + p.c.faces())?;
    if (input.period - p.period).abs() > 1e-12 * p.period {
        return Err(Error::invalid(
            "input.period",
            input.period,
            format!("must be the problem's period ({})", p.period),
        ));
    }
    let (n, mm) = (p.states(), opts.steps_per_period);
    let h = p.period / mm as f64;
    let split = p.dynamics.split();
    check_drift_step(p, mm, opts.drift, &split)?;
    let implicit = opts.drift == DriftStep::SemiImplicit && !split.undamped();
    let metric = if implicit {
        Some(Metric::new(&split.damping, &p.c, h)?)
    } else {
        None
    };
    // The explicit part of the drift: all of A, or A - S_-.
    let a_exp = if implicit { &split.rest } else { &p.dynamics.a };
    // The controls of the steps, the same every period.
    let us = input.step_means(mm);
    // The projection by structure: a chain's O(N) one where (P) is a crawler's chain (the
    // metric step is for a damped drift, which a chain has not).
    let mut proj = match &metric {
        Some(mt) => OntoC::Dense(PolyProjector::new(mt.c.clone())),
        None => OntoC::new(&p.c, chain),
    };
    let projection = proj.kind();
    let x = x0.to_vec();
    // `B u^i + b` of each step, the same every period; `A x` only where `A` has entries.
    let forcing: Vec<Vec<f64>> = us
        .iter()
        .map(|u| {
            (0..n)
                .map(|k| crate::model::general::dot(&p.dynamics.b[k], u) + p.dynamics.drift[k])
                .collect()
        })
        .collect();
    let drift_rows: Vec<usize> = (0..n)
        .filter(|&k| a_exp[k].iter().any(|v| *v != 0.0))
        .collect();
    let mut g = vec![0.0; n];
    let mut v = vec![0.0; n];
    // Each step's projection, its vectors reused from step to step.
    let mut a = crate::sweep::Projection::default();
    // One period from `x`; with `record`, the trajectory.
    let period = |x: &mut Vec<f64>, record: Option<&mut GeneralSimulation>| -> Result<()> {
        let mut rec = record;
        for (i, u) in us.iter().enumerate() {
            g.copy_from_slice(&forcing[i]);
            for &k in &drift_rows {
                g[k] += crate::model::general::dot(&a_exp[k], x);
            }
            for k in 0..n {
                v[k] = x[k] + h * g[k];
            }
            match &metric {
                None => proj.project_into(x, &v, &mut a)?,
                Some(mt) => a = mt.project(&mut proj, x, &v)?,
            };
            x.copy_from_slice(&a.x);
            if let Some(r) = rec.as_deref_mut() {
                let lambda: Vec<f64> = a.mu.iter().map(|mu| mu / h).collect();
                r.reward += h * p.reward.eval(&p.c.normals, &lambda);
                r.cost += h * p.cost.eval(u);
                r.max_kkt_residual = r.max_kkt_residual.max(a.residual);
                r.t.push((i + 1) as f64 * h);
                r.x.push(x.clone());
                r.u.push(u.clone());
                r.lambda.push(lambda);
            }
        }
        Ok(())
    };
    let mut sim = periodic_regime(p, input, x, opts.max_periods, opts.tol, period)?;
    sim.projection = projection;
    Ok(sim)
}

/// Refuses `steps_per_period = mm` where the drift's explicit part is beyond its limit (module
/// docs): forward Euler's stability limit `h rate <= EXPLICIT_STEP_LIMIT` on the part stepped
/// explicitly (all of `A` but its growing part for [`DriftStep::Explicit`], the rotating part
/// `K` for [`DriftStep::SemiImplicit`]); for the semi-implicit step also the spurious growth of
/// an explicit rotation over a period, `prod (1 + (h |K|)^2)^(1/2) ~ exp(T h |K|^2 / 2) <= e`,
/// and the precision of a state held by the growing part, `h |S_+|_2 <= GROWTH_STEP_LIMIT`.
/// The message names the steps needed (or says that no grid of at most
/// `MAX_STEPS_PER_PERIOD` steps has them).
fn check_drift_step(
    p: &GeneralProblem,
    mm: usize,
    drift: DriftStep,
    split: &crate::model::general::DriftSplit,
) -> Result<()> {
    let t = p.period;
    let h = t / mm as f64;
    let refuse = |why: String, need: f64| {
        let max = super::periodic::MAX_STEPS_PER_PERIOD;
        let need = if need <= max as f64 {
            format!("needs at least {need:e} steps")
        } else {
            format!(
                "no grid of at most {max} steps is fine enough: scale dynamics.A down (or the \
                 period)"
            )
        };
        Err(Error::invalid(
            "steps_per_period",
            mm,
            format!("is too coarse for the drift: {why}; {need}"),
        ))
    };
    let (rate, what) = match drift {
        DriftStep::Explicit => (split.stiff_rate, "decaying and rotating part |S_- + K|_2"),
        DriftStep::SemiImplicit => (split.skew_rate, "rotating part |K|_2"),
    };
    if !within(h * rate, EXPLICIT_STEP_LIMIT) {
        return refuse(
            format!(
                "the step h = {h:e} times the {what} of dynamics.A ({rate:e}) exceeds the \
                 explicit stability limit {EXPLICIT_STEP_LIMIT}"
            ),
            min_steps(t, rate),
        );
    }
    if drift == DriftStep::Explicit {
        return Ok(());
    }
    let k = split.skew_rate;
    if !within(t * h * k * k / 2.0, 1.0) {
        return refuse(
            format!(
                "the explicit step of the rotating part |K|_2 = {k:e} of dynamics.A grows the \
                 state spuriously by exp(T h |K|^2 / 2) = exp({:e}) over a period (at most e)",
                t * h * k * k / 2.0
            ),
            (t * t * k * k / 2.0).ceil(),
        );
    }
    let g = split.growth_rate;
    if !within(h * g, GROWTH_STEP_LIMIT) {
        return refuse(
            format!(
                "the step h = {h:e} times the growing rate |S_+|_2 of dynamics.A ({g:e}) \
                 exceeds {GROWTH_STEP_LIMIT:e}, beyond which a state held on a face loses its \
                 precision in the projection"
            ),
            (t * g / GROWTH_STEP_LIMIT).ceil(),
        );
    }
    Ok(())
}

/// `v <= limit`, false for NaN.
fn within(v: f64, limit: f64) -> bool {
    v <= limit
}

/// The semi-implicit step's metric `M = I - h S_-` (module docs): `M = L L^T`, and C in
/// `z = L^T x` as `{z : <L^-1 x*_j, z> <= c_j}` (rows scaled to unit length `nu_j`).
struct Metric {
    /// `L^-1` (rows).
    l_inv: nalgebra::DMatrix<f64>,
    /// `L^-T`.
    l_inv_t: nalgebra::DMatrix<f64>,
    /// `L^T`.
    l_t: nalgebra::DMatrix<f64>,
    /// C in `z`.
    c: Polyhedron,
}

impl Metric {
    fn new(damping: &[Vec<f64>], c: &Polyhedron, h: f64) -> Result<Metric> {
        let n = damping.len();
        let m = nalgebra::DMatrix::from_fn(n, n, |i, k| {
            (if i == k { 1.0 } else { 0.0 }) - h * damping[i][k]
        });
        let chol = m.cholesky().ok_or_else(|| {
            Error::Numerical(format!(
                "semi-implicit step: I - h S_- is not positive definite at h = {h:e} (A's \
                 damping out of the floating-point range)"
            ))
        })?;
        let l = chol.l();
        let l_inv = l
            .clone()
            .try_inverse()
            .ok_or_else(|| Error::Numerical("semi-implicit step: L is singular".into()))?;
        let rows: Vec<Vec<f64>> = c
            .normals
            .iter()
            .map(|nj| {
                (&l_inv * nalgebra::DVector::from_column_slice(nj))
                    .iter()
                    .copied()
                    .collect()
            })
            .collect();
        let cz = Polyhedron::new(
            rows,
            c.offsets.clone(),
            "sweeping_process (in the metric of I - h S_-)",
        )?;
        Ok(Metric {
            l_inv_t: l_inv.transpose(),
            l_inv,
            l_t: l.transpose(),
            c: cz,
        })
    }

    /// The projection of `M^-1 r` (`r` given) onto C in the metric `M`, from `x`; its
    /// multipliers are those of the unit normals of C (`M (v - x^+) = sum_j mu_j x*_j`).
    fn project(&self, proj: &mut OntoC, x: &[f64], r: &[f64]) -> Result<crate::sweep::Projection> {
        let z0 = &self.l_t * nalgebra::DVector::from_column_slice(x);
        let zv = &self.l_inv * nalgebra::DVector::from_column_slice(r);
        let mut a = proj.project(z0.as_slice(), zv.as_slice())?;
        a.x = (&self.l_inv_t * nalgebra::DVector::from_vec(a.x))
            .iter()
            .copied()
            .collect();
        for (mu, nu) in a.mu.iter_mut().zip(&self.c.row_norms) {
            *mu /= nu;
        }
        Ok(a)
    }
}

/// The regime of a simulation from `x`, given one of its `period` maps (with a recording, the
/// trajectory): for a Cauchy problem one horizon; for a periodic one, periods until the state
/// repeats within `tol` times C's scale (at most `max_periods`). Then one period recorded, with
/// `J` on it (none without the regime).
pub(super) fn periodic_regime(
    p: &GeneralProblem,
    input: &ControlInput,
    mut x: Vec<f64>,
    max_periods: usize,
    tol: f64,
    mut period: impl FnMut(&mut Vec<f64>, Option<&mut GeneralSimulation>) -> Result<()>,
) -> Result<GeneralSimulation> {
    let scale = p.c.scale();
    let mut periods = 0;
    let converged = match p.boundary {
        Boundary::Initial(_) => true,
        Boundary::Periodic => loop {
            crate::progress::check()?;
            let start = x.clone();
            period(&mut x, None)?;
            periods += 1;
            let change = x
                .iter()
                .zip(&start)
                .fold(0.0_f64, |d, (a, b)| d.max((a - b).abs()));
            if change <= tol * scale {
                break true;
            }
            if periods >= max_periods {
                break false;
            }
        },
    };
    let mut mean_control = vec![0.0; p.controls()];
    input.mean(0.0, p.period, &mut mean_control);
    let mut sim = GeneralSimulation {
        converged,
        periods,
        objective: None,
        reward: 0.0,
        cost: 0.0,
        mean_control,
        t: vec![0.0],
        x: vec![x.clone()],
        u: vec![],
        lambda: vec![],
        projection: "dense",
        max_kkt_residual: 0.0,
    };
    if converged {
        period(&mut x, Some(&mut sim))?;
        sim.periods += 1;
        let objective = sim.reward - sim.cost;
        check_finite_answer(&sim, objective)?;
        sim.objective = Some(objective);
    } else if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(Error::Numerical(format!(
            "the state's component {} is {} after {periods} periods: the simulation \
             overflowed (the dynamics' A, B or b too large for C's scale)",
            i + 1,
            x[i]
        )));
    }
    Ok(sim)
}

/// Refuses a recorded period whose numbers left the floating-point range, naming what
/// overflowed: no `J = inf` (or NaN) is reported as an answer.
fn check_finite_answer(sim: &GeneralSimulation, objective: f64) -> Result<()> {
    let overflow = |what: &str, v: f64, cause: &str| {
        Error::Numerical(format!(
            "{what} over the recorded period is {v}: it overflowed the floating-point range \
             ({cause}); scale the problem down"
        ))
    };
    if let Some(row) = sim.x.iter().find(|r| r.iter().any(|v| !v.is_finite())) {
        return Err(overflow(
            "the state",
            row.iter()
                .copied()
                .find(|v| !v.is_finite())
                .unwrap_or(f64::NAN),
            "the dynamics' A, B or b too large for C's scale",
        ));
    }
    if !sim.reward.is_finite() {
        return Err(overflow(
            "int f1(eta)",
            sim.reward,
            "the reactions times objective.face_weights or objective.reaction_weights",
        ));
    }
    if !sim.cost.is_finite() {
        return Err(overflow("int f2(u)", sim.cost, "objective.cost"));
    }
    if !objective.is_finite() {
        return Err(overflow("J = int f1 - int f2", objective, "both integrals"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sweep's step means are `mean` of each step to the bit, for knots between, on and
    /// beyond the grid's times, and are the integrals of the interpolants worked by hand.
    #[test]
    fn step_means_are_the_means_of_the_steps() {
        let u = ControlSet::Box {
            lower: vec![-5.0, -5.0],
            upper: vec![5.0, 5.0],
        };
        // Knots at 0, 1 (a grid time of 4 and 8 steps), 1.3 and 3.7, T = 4.
        let times = vec![0.0, 1.0, 1.3, 3.7];
        let values = vec![
            vec![0.0, 1.0],
            vec![2.0, -1.0],
            vec![-1.0, 0.5],
            vec![0.7, -0.2],
        ];
        for kind in [InputKind::PiecewiseConstant, InputKind::PiecewiseLinear] {
            let input =
                ControlInput::new(kind, 4.0, times.clone(), values.clone(), &u, "input").unwrap();
            for mm in [1, 3, 4, 8, 37] {
                let h = 4.0 / mm as f64;
                let swept = input.step_means(mm);
                assert_eq!(swept.len(), mm);
                for (i, row) in swept.iter().enumerate() {
                    let t1 = if i + 1 == mm { 4.0 } else { (i + 1) as f64 * h };
                    let mut one = vec![0.0; 2];
                    input.mean(i as f64 * h, t1, &mut one);
                    assert_eq!(row, &one, "{kind:?}, {mm} steps, step {i}");
                }
            }
        }
        // By hand, linear, first control: 2t on [0, 1], 2 - 10 (t - 1) on [1, 1.3],
        // -1 + a (t - 1.3) on [1.3, 3.7] and 0.7 - b (t - 3.7) on [3.7, 4] (back to 0 at T),
        // `a = 1.7 / 2.4`, `b = 0.7 / 0.3`; two steps of 2.
        let input =
            ControlInput::new(InputKind::PiecewiseLinear, 4.0, times, values, &u, "input").unwrap();
        let (a, b) = (1.7 / 2.4, 0.7 / 0.3);
        let first = 1.0 + (0.6 - 5.0 * 0.09) + (-0.7 + 0.5 * a * 0.49);
        let second = (-1.7 + 0.5 * a * (5.76 - 0.49)) + (0.21 - 0.5 * b * 0.09);
        let means = input.step_means(2);
        assert!((means[0][0] - first / 2.0).abs() < 1e-14, "{}", means[0][0]);
        assert!(
            (means[1][0] - second / 2.0).abs() < 1e-14,
            "{}",
            means[1][0]
        );
    }
}
