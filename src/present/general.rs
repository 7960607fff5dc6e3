//! The figures of the general problem (P) (theory §11) from the records its jobs return: a
//! simulation ([`GeneralSimulated`]), an optimum of any method ([`GeneralAnswer`]), an analysis
//! ([`GeneralAnalysis`], C alone). Each record is first read as one [`GeneralPath`] (times,
//! states, and the control and reactions of each piece between them), from which the same
//! figures are drawn whatever made it:
//!
//! - `polytope`: C with the path of the state (interval and `x(t)` in 1-D, the polygon with its
//!   vertices in 2-D, projections onto pairs of components beyond; an unbounded C within a
//!   window, [`general_state_space`]);
//! - `states` (`n >= 2`): `x_k(t)`;
//! - `controls`: `u_k(t)`, with the bounds of a box U;
//! - `reactions`: the reaction rates `lambda_j(t)` of the faces that hold the state at some time
//!   (`eta = sum_j lambda_j x*_j`);
//! - `integrand`: the objective's integrand `f1(eta(t)) - f2(u(t))` (paper eq. 2.3), whose
//!   integral over the period is the `J` the record states (with `f1` and `f2` apart when
//!   there is a cost);
//! - `adjoint`, with the necessary conditions of a P_m optimum: the adjoint `p_i` per step.

use super::figures::{
    general_polytope_figure, sub, time_series_figure, Edge, Figure, IntervalEndData, Projection,
    SeriesLine, StatePanel, StateSpace, TimeSeries,
};
use crate::error::{Error, Result};
use crate::io::{GeneralAnalysis, GeneralAnswer, GeneralSimulated, GeneralSolution};
use crate::model::general::{Boundary, ControlSet, GeneralCost, GeneralProblem, Polyhedron};
use crate::optimal::general::{analyze_polyhedron, project_polyhedron, Geometry};

/// A process of the general problem as the figures read it: `K + 1` times and states, and on
/// each of the `K` pieces between them a constant control and constant reaction rates
/// (the steps of P_m and of catching-up, the segments of the exact simulation, the phases of a
/// phase gait).
#[derive(Debug, Clone, PartialEq)]
pub struct GeneralPath {
    /// `t_0 < ... < t_K`.
    pub t: Vec<f64>,
    /// `x(t_k)`.
    pub x: Vec<Vec<f64>>,
    /// `u` on piece `k` (`K` rows).
    pub u: Vec<Vec<f64>>,
    /// `lambda_j` on piece `k` (`K` rows of `sigma`).
    pub lambda: Vec<Vec<f64>>,
    /// The `J` the record states for the path (the figures' integral is checked against it).
    pub objective: f64,
}

impl GeneralPath {
    /// The recorded period (or horizon) of a simulation; refused without the periodic regime
    /// (the recorded period is then not on the orbit, and no `J` was computed).
    pub fn of_simulation(r: &GeneralSimulated) -> Result<Self> {
        let s = &r.simulation;
        let objective = s.objective.filter(|_| s.converged).ok_or_else(|| {
            Error::Numerical(format!(
                "no figures: the periodic regime was not reached within {} periods",
                s.periods
            ))
        })?;
        Self::new(
            s.t.clone(),
            s.x.clone(),
            s.u.clone(),
            s.lambda.clone(),
            objective,
        )
    }

    /// The optimum of an answer: P_m's grid `t_i = i T / 2^m` (global or local), or the phases
    /// of a phase gait.
    pub fn of_answer(a: &GeneralAnswer) -> Result<Self> {
        let grid = |period: f64, steps: usize| -> Vec<f64> {
            (0..=steps)
                .map(|i| period * i as f64 / steps as f64)
                .collect()
        };
        // A P_m process (global or local): its states, controls and reactions on the grid.
        let pm = |period: f64, x: &[Vec<f64>], u: &[Vec<f64>], lambda: &[Vec<f64>], j: f64| {
            Self::new(
                grid(period, u.len()),
                x.to_vec(),
                u.to_vec(),
                lambda.to_vec(),
                j,
            )
        };
        match &a.solution {
            GeneralSolution::Pm(s) => {
                pm(a.period, &s.path.x, &s.path.u, &s.path.lambda, s.objective)
            }
            GeneralSolution::Local(s) => {
                pm(a.period, &s.path.x, &s.path.u, &s.path.lambda, s.objective)
            }
            GeneralSolution::Phase(s) => {
                let mut t = vec![0.0];
                for d in &s.durations {
                    t.push(t[t.len() - 1] + d);
                }
                Self::new(
                    t,
                    s.states.clone(),
                    s.controls.clone(),
                    s.reactions.clone(),
                    s.objective,
                )
            }
        }
    }

    fn new(
        t: Vec<f64>,
        x: Vec<Vec<f64>>,
        u: Vec<Vec<f64>>,
        lambda: Vec<Vec<f64>>,
        objective: f64,
    ) -> Result<Self> {
        let k = u.len();
        if k == 0 || t.len() != k + 1 || x.len() != k + 1 || lambda.len() != k {
            return Err(Error::invalid(
                "process",
                format!(
                    "{} times, {} states, {} controls, {} reactions",
                    t.len(),
                    x.len(),
                    k,
                    lambda.len()
                ),
                "needs K + 1 times and states and K controls and reactions (K >= 1)",
            ));
        }
        Ok(GeneralPath {
            t,
            x,
            u,
            lambda,
            objective,
        })
    }
}

/// The legend's name of a path of `p`: the periodic orbit or the Cauchy problem's horizon.
fn path_label(p: &GeneralProblem) -> String {
    match p.boundary {
        Boundary::Periodic => "periodic orbit".into(),
        Boundary::Initial(_) => "x(t) from the given x(0), t in [0, T]".into(),
    }
}

/// Tolerance of "on a face" for the figures, relative to the scale `s`.
const ON_FACE: f64 = 1e-7;

/// Most edges of a polygon labelled with their faces (the labels of more would overlap).
pub const MAX_LABELLED_EDGES: usize = 24;

/// C of `p` (with its geometry `g`) and the path's states, as figure `polytope` draws them: in
/// 1-D the interval, beyond the projections of C onto the pairs of
/// [`super::figures::projection_pairs`], exact ([`project_polyhedron`]); an unbounded C is cut
/// by a window, the box around its vertices, its Chebyshev centre and the path, widened by half
/// its largest span on every side.
pub fn general_state_space(
    p: &GeneralProblem,
    g: &Geometry,
    path: Option<&GeneralPath>,
) -> Result<StateSpace> {
    let c = &p.c;
    let n = c.dim();
    let states: &[Vec<f64>] = path.map_or(&[], |q| &q.x);
    if states.iter().any(|x| x.len() != n) {
        return Err(Error::invalid(
            "process",
            "a state of the wrong size",
            format!("one value per state component ({n})"),
        ));
    }
    let window = (!g.bounded).then(|| window(c.scale(), g, states));
    let mut space = StateSpace {
        dim: n,
        bounded: g.bounded,
        interval: None,
        panels: Vec::new(),
        dots: Vec::new(),
        t: path.map_or_else(Vec::new, |q| q.t.clone()),
        x: states.to_vec(),
        path_label: path_label(p),
    };
    if n == 1 {
        space.interval = Some(interval_ends(c, window.as_deref()));
        return Ok(space);
    }
    for (i, j) in super::figures::projection_pairs(n) {
        space
            .panels
            .push(pair_panel(c, g, window.as_deref(), (i, j))?);
    }
    if n == 2 && g.rank == 2 {
        space.dots = g
            .vertices
            .iter()
            .flatten()
            .map(|v| (v.point[0], v.point[1]))
            .collect();
    }
    Ok(space)
}

/// The ends of a 1-D C, each with the face that makes it (the tightest), or the window's end
/// where an unbounded C has none.
fn interval_ends(c: &Polyhedron, window: Option<&[(f64, f64)]>) -> [IntervalEndData; 2] {
    let (mut lo, mut hi) = (
        IntervalEndData {
            value: f64::NEG_INFINITY,
            face: None,
        },
        IntervalEndData {
            value: f64::INFINITY,
            face: None,
        },
    );
    for j in 0..c.faces() {
        let (a, b) = (c.normals[j][0], c.offsets[j]);
        if a > 0.0 && b / a < hi.value {
            hi = IntervalEndData {
                value: b / a,
                face: Some(j + 1),
            };
        } else if a < 0.0 && b / a > lo.value {
            lo = IntervalEndData {
                value: b / a,
                face: Some(j + 1),
            };
        }
    }
    if let Some(w) = window {
        if lo.face.is_none() {
            lo.value = w[0].0;
        }
        if hi.face.is_none() {
            hi.value = w[0].1;
        }
    }
    [lo, hi]
}

/// The projection of C (within `window` when unbounded) onto the components `(i, j)`: its
/// polygon, the sides that are the window's, and in the plane (`n = 2`) its sides labelled
/// with their faces (none beyond [`MAX_LABELLED_EDGES`]).
fn pair_panel(
    c: &Polyhedron,
    g: &Geometry,
    window: Option<&[(f64, f64)]>,
    (i, j): (usize, usize),
) -> Result<StatePanel> {
    let n = c.dim();
    let tol = ON_FACE * c.scale();
    let ring = project_polyhedron(c, window, i, j)?;
    let vertices: Vec<(f64, f64)> = ring.iter().map(|v| v.point).collect();
    let mut edges = Vec::new();
    let mut open_sides = Vec::new();
    for k in 0..ring.len() {
        let (a, b) = (&ring[k], &ring[(k + 1) % ring.len()]);
        if let Some(w) = window {
            let on_window = (0..n).any(|d| {
                let at = |v: f64, e: f64| (v - e).abs() <= tol.max(1e-9 * e.abs());
                (at(a.lifted[d], w[d].0) && at(b.lifted[d], w[d].0))
                    || (at(a.lifted[d], w[d].1) && at(b.lifted[d], w[d].1))
            });
            if on_window {
                open_sides.push(k);
                continue;
            }
        }
        if n != 2 {
            continue;
        }
        // In the plane the side is a face: the first (not redundant) face both ends hold.
        let holds = |f: usize| c.slack(f, &a.lifted) >= -tol && c.slack(f, &b.lifted) >= -tol;
        let face = (0..c.faces())
            .filter(|f| holds(*f))
            .min_by_key(|f| g.redundant_faces.contains(&(f + 1)));
        if let Some(f) = face {
            edges.push(Edge {
                label: format!("{}", f + 1),
                from: a.point,
                to: b.point,
                normal: (c.normals[f][0], c.normals[f][1]),
            });
        }
    }
    if edges.len() > MAX_LABELLED_EDGES {
        edges.clear();
    }
    Ok(StatePanel {
        pair: (i, j),
        projection: Projection {
            vertices,
            edges,
            open_sides,
        },
    })
}

/// The window of an unbounded C: the box around its vertices, its centre and `states`, widened
/// by half its largest span (at least C's scale) on every side.
fn window(scale: f64, g: &Geometry, states: &[Vec<f64>]) -> Vec<(f64, f64)> {
    let n = g.dim;
    let mut b = vec![(f64::INFINITY, f64::NEG_INFINITY); n];
    let points = g
        .vertices
        .iter()
        .flatten()
        .map(|v| &v.point)
        .chain(std::iter::once(&g.chebyshev_centre))
        .chain(states);
    for x in points {
        for (k, v) in x.iter().enumerate() {
            if v.is_finite() {
                b[k] = (b[k].0.min(*v), b[k].1.max(*v));
            }
        }
    }
    let span = b.iter().map(|(lo, hi)| hi - lo).fold(scale, f64::max);
    b.iter()
        .map(|&(lo, hi)| (lo - 0.5 * span, hi + 0.5 * span))
        .collect()
}

/// A piecewise-constant curve: `v_k` on `[t_k, t_(k+1)]`.
fn steps(t: &[f64], v: impl Iterator<Item = f64>) -> Vec<(f64, f64)> {
    let mut pts = Vec::new();
    for (k, y) in v.enumerate() {
        pts.push((t[k], y));
        pts.push((t[k + 1], y));
    }
    pts
}

/// The curves of a path over time: `states` (`n >= 2`), `controls`, `reactions`, `integrand`
/// (module docs). The integral of the `integrand` curve is the objective `J` of the path.
pub fn general_series(p: &GeneralProblem, path: &GeneralPath) -> Vec<TimeSeries> {
    let mut out = Vec::new();
    if p.states() >= 2 {
        out.push(states_series(p, path));
    }
    out.push(controls_series(p, path));
    out.push(reactions_series(p, path));
    out.push(integrand_series(p, path));
    out
}

/// Curve `states`: each component `x_k(t)`, linear between the recorded times.
fn states_series(p: &GeneralProblem, path: &GeneralPath) -> TimeSeries {
    let t = &path.t;
    let label = path_label(p);
    TimeSeries {
        name: "states".into(),
        caption: format!(
            "The state x(t) of the sweeping process over time ({label}; linear between the \
             recorded times)."
        ),
        title: "The state x(t)".into(),
        ylabel: "state x".into(),
        lines: (0..p.states())
            .map(|k| SeriesLine {
                label: format!("x{}(t)", sub(k + 1)),
                points: t.iter().zip(&path.x).map(|(&t, x)| (t, x[k])).collect(),
                thick: true,
            })
            .collect(),
        levels: Vec::new(),
    }
}

/// Curve `controls`: each `u_k(t)`, constant on each piece, with the bounds of a box U of at
/// most three controls as levels.
fn controls_series(p: &GeneralProblem, path: &GeneralPath) -> TimeSeries {
    let m = p.controls();
    let levels = match &p.control {
        ControlSet::Box { lower, upper } if m <= 3 => {
            let mut l: Vec<(f64, String)> = Vec::new();
            for v in lower.iter().chain(upper) {
                if !l.iter().any(|(w, _)| w == v) {
                    l.push((*v, "bounds of U".into()));
                }
            }
            l
        }
        _ => Vec::new(),
    };
    TimeSeries {
        name: "controls".into(),
        caption: format!(
            "The control u(t), constant on each piece{}.",
            if levels.is_empty() {
                String::new()
            } else {
                ", with the bounds of the box U (dashed)".to_string()
            }
        ),
        title: "The control u(t)".into(),
        ylabel: "control u".into(),
        lines: (0..m)
            .map(|k| SeriesLine {
                label: format!("u{}(t)", sub(k + 1)),
                points: steps(&path.t, path.u.iter().map(|u| u[k])),
                thick: true,
            })
            .collect(),
        levels,
    }
}

/// Curve `reactions`: the rates `lambda_j(t)` of the faces that are active at some time (a
/// flat line at 0 when none is).
fn reactions_series(p: &GeneralProblem, path: &GeneralPath) -> TimeSeries {
    let t = &path.t;
    let sigma = p.c.faces();
    let biggest = path
        .lambda
        .iter()
        .flatten()
        .fold(0.0_f64, |a, v| a.max(v.abs()));
    let active: Vec<usize> = (0..sigma)
        .filter(|&j| {
            path.lambda
                .iter()
                .any(|l| l[j].abs() > 1e-12 * biggest && l[j] != 0.0)
        })
        .collect();
    let lines: Vec<SeriesLine> = if active.is_empty() {
        vec![SeriesLine {
            label: "λ = 0: no face holds the state".into(),
            points: vec![(t[0], 0.0), (t[t.len() - 1], 0.0)],
            thick: true,
        }]
    } else {
        active
            .iter()
            .map(|&j| SeriesLine {
                label: format!("λ{}(t), face {}", sub(j + 1), j + 1),
                points: steps(t, path.lambda.iter().map(|l| l[j])),
                thick: true,
            })
            .collect()
    };
    TimeSeries {
        name: "reactions".into(),
        caption: format!(
            "The reactions: the rates λ_j(t) of the faces that hold the state at some time \
             ({} of the {sigma} faces), constant on each piece; the reaction is η = g − x′ = \
             Σ_j λ_j x*_j.",
            active.len()
        ),
        title: "The reaction rates λⱼ(t) of the active faces".into(),
        ylabel: "reaction rate λ".into(),
        lines,
        levels: Vec::new(),
    }
}

/// Curve `integrand`: `f1(eta(t)) - f2(u(t))`, with `f1` and `f2` apart when there is a cost;
/// its integral is the path's `J`.
fn integrand_series(p: &GeneralProblem, path: &GeneralPath) -> TimeSeries {
    let t = &path.t;
    let f1: Vec<f64> = path
        .lambda
        .iter()
        .map(|l| p.reward.eval(&p.c.normals, l))
        .collect();
    let f2: Vec<f64> = path.u.iter().map(|u| p.cost.eval(u)).collect();
    let mut lines = vec![SeriesLine {
        label: "f₁(η(t)) − f₂(u(t))".into(),
        points: steps(t, f1.iter().zip(&f2).map(|(a, b)| a - b)),
        thick: true,
    }];
    if p.cost != GeneralCost::None {
        lines.push(SeriesLine {
            label: "f₁(η(t))".into(),
            points: steps(t, f1.iter().copied()),
            thick: false,
        });
        lines.push(SeriesLine {
            label: "f₂(u(t))".into(),
            points: steps(t, f2.iter().copied()),
            thick: false,
        });
    }
    TimeSeries {
        name: "integrand".into(),
        caption: format!(
            "The objective's integrand f₁(η(t)) − f₂(u(t)) (paper eq. 2.3), constant on each \
             piece; its integral over [0, T] is J = {}.",
            crate::number::num(path.objective, 0.0)
        ),
        title: "The integrand of J".into(),
        ylabel: "integrand of J".into(),
        lines,
        levels: Vec::new(),
    }
}

/// The figures of a path of `p` (module docs).
pub fn general_path_figures(
    p: &GeneralProblem,
    g: &Geometry,
    path: &GeneralPath,
) -> Result<Vec<Figure>> {
    let mut figs = vec![general_polytope_figure(&general_state_space(
        p,
        g,
        Some(path),
    )?)?];
    for s in general_series(p, path) {
        figs.push(time_series_figure(&s)?);
    }
    Ok(figs)
}

/// C's geometry for the figures ([`analyze_polyhedron`]).
fn geometry(p: &GeneralProblem) -> Result<Geometry> {
    analyze_polyhedron(&p.c)
}

/// The figures of C alone (`crawlopt analyze --plot`).
pub fn general_analysis_figures(a: &GeneralAnalysis) -> Result<Vec<Figure>> {
    Ok(vec![general_polytope_figure(&general_state_space(
        &a.problem,
        &a.geometry,
        None,
    )?)?])
}

/// The figures of a simulation of `p` (`crawlopt simulate --plot`); refused without the
/// periodic regime ([`GeneralPath::of_simulation`]).
pub fn general_simulation_figures(p: &GeneralProblem, r: &GeneralSimulated) -> Result<Vec<Figure>> {
    let path = GeneralPath::of_simulation(r)?;
    general_path_figures(p, &geometry(p)?, &path)
}

/// The figures of an optimum of `p`, any method (`crawlopt optimize --plot`), with the adjoint
/// when its necessary conditions were computed.
pub fn general_answer_figures(p: &GeneralProblem, a: &GeneralAnswer) -> Result<Vec<Figure>> {
    let path = GeneralPath::of_answer(a)?;
    answer_figures_with(p, &geometry(p)?, &path, a)
}

/// [`general_answer_figures`] with C's geometry and the answer's path at hand.
pub(super) fn answer_figures_with(
    p: &GeneralProblem,
    g: &Geometry,
    path: &GeneralPath,
    a: &GeneralAnswer,
) -> Result<Vec<Figure>> {
    let mut figs = general_path_figures(p, g, path)?;
    if let Some(nc) = a.necessary_conditions.as_ref() {
        figs.extend(general_adjoint_figure(p, nc)?);
    }
    // J_m against m with a convergence table (`optimize --convergence`), as for crawlers.
    if let Some(table) = &a.records.convergence {
        figs.push(super::figures::convergence_figure(table)?);
    }
    Ok(figs)
}

/// The adjoint p(t) of necessary conditions computed on a P_m process of `p` (Theorem 2.2,
/// discrete form), constant on each step; `None` when the conditions carry no adjoint.
pub fn general_adjoint_figure(
    p: &GeneralProblem,
    nc: &crate::certify::GeneralNecessaryConditions,
) -> Result<Option<Figure>> {
    let m = &nc.multipliers;
    if m.times.len() != m.p.len() + 1 || m.p.is_empty() {
        return Ok(None);
    }
    let lines = (0..p.states())
        .map(|k| SeriesLine {
            label: format!("p{}(t)", sub(k + 1)),
            points: steps(&m.times, m.p.iter().map(|r| r[k])),
            thick: true,
        })
        .collect();
    Ok(Some(time_series_figure(&TimeSeries {
        name: "adjoint".into(),
        caption: "The adjoint p(t) of the necessary conditions (Theorem 2.2, discrete form), \
                  constant on each step of P_m."
            .into(),
        title: "The adjoint p(t)".into(),
        ylabel: "adjoint p".into(),
        lines,
        levels: Vec::new(),
    })?))
}
