//! A gait read off the phase MILP's columns, and a known gait written back into them (a start).

use super::layout::Layout;
use super::PhaseSolution;
use crate::error::{Error, Result};
use crate::integrate::{Method, Trajectory};
use crate::model::Crawler;
use crate::optimal::milp::{check_verified, gait_knots, replay};
use crate::optimal::units::{scale_all, scale_rows, Units};
use crate::optimal::{Certificate, GaitProblem, MilpStatus};
use highs::Col;

/// A gait read off the MILP's columns, empty phases removed.
#[derive(Default)]
pub(super) struct RawGait {
    pub(super) durations: Vec<f64>,
    pub(super) increments: Vec<Vec<f64>>,
    pub(super) states: Vec<Vec<f64>>,
    pub(super) block_displacements: Vec<Vec<f64>>,
    pub(super) modes: Vec<Vec<i8>>,
}

impl RawGait {
    /// Reads the gait: each used phase gives its transition and its slip segment, those of
    /// positive duration, in order. Each increment is clipped to the rate bound `|U_l| <= a_l d`
    /// that the MILP imposes: HiGHS meets it only to its feasibility tolerance, and on a piece
    /// of a few 1e-12 of the period that excess, divided by the duration, would give a rate far
    /// beyond `a_l` (a gait `certify` then refuses).
    pub(super) fn read(lay: &Layout, cols: &[f64], t: f64, a: &[f64]) -> Self {
        let val = |c: &Col| cols[c.index()];
        let vals = |cs: &[Col]| -> Vec<f64> { cs.iter().map(val).collect() };
        let clipped = |cs: &[Col], d: f64| -> Vec<f64> {
            cs.iter()
                .zip(a)
                .map(|(c, &al)| val(c).clamp(-al * d, al * d))
                .collect()
        };
        let nb = lay.ps.first().map_or(0, Vec::len);
        let mut g = RawGait::default();
        for j in 0..lay.tau.len() {
            let sigma = val(&lay.sigma[j]);
            if sigma > 1e-12 * t {
                g.durations.push(sigma);
                g.increments.push(clipped(&lay.ws[j], sigma));
                g.states.push(vals(&lay.xs[j]));
                g.block_displacements.push(vec![0.0; nb]);
                g.modes.push(vec![0; nb]);
            }
            let tau = val(&lay.tau[j]);
            if tau > 1e-12 * t {
                g.durations.push(tau);
                g.increments.push(clipped(&lay.us[j], tau));
                g.states.push(vals(&lay.ys[j]));
                g.block_displacements.push(
                    lay.ps[j]
                        .iter()
                        .zip(&lay.qs[j])
                        .map(|(p, q)| val(p) - val(q))
                        .collect(),
                );
                g.modes.push(
                    lay.sp[j]
                        .iter()
                        .zip(&lay.sq[j])
                        .map(|(p, q)| match (val(p) > 0.5, val(q) > 0.5) {
                            (true, _) => 1,
                            (_, true) => -1,
                            _ => 0,
                        })
                        .collect(),
                );
            }
        }
        let x0 = g
            .states
            .first()
            .cloned()
            .unwrap_or_else(|| vals(&lay.xs[0]));
        g.states.push(x0);
        g
    }

    /// Number of slip phases, runs of one mode merged cyclically (what `K` counts).
    pub(super) fn slip_phases(&self) -> usize {
        slip_sequence(&self.modes).len()
    }

    /// The same gait with each run of consecutive phases of one mode (all-stick runs included)
    /// merged into one phase, cyclically: the run's duration, increment and displacements are
    /// summed and `x` goes straight from the run's first state to its last. For an all-stick
    /// run that is a straight move inside the convex C with every block sticking; for a slip
    /// run the faces are held at both ends, hence on the segment. Displacements are unchanged
    /// and, by convexity, so is or drops the cost.
    fn merged(&self) -> RawGait {
        let p = self.durations.len();
        let first = (0..p)
            .find(|&j| self.modes[j] != self.modes[(j + p - 1) % p])
            .unwrap_or(0);
        let mut g = RawGait::default();
        for i in 0..p {
            let j = (first + i) % p;
            if i > 0 && g.modes.last() == Some(&self.modes[j]) {
                let last = g.durations.len() - 1;
                g.durations[last] += self.durations[j];
                for (a, b) in g.increments[last].iter_mut().zip(&self.increments[j]) {
                    *a += b;
                }
                for (a, b) in g.block_displacements[last]
                    .iter_mut()
                    .zip(&self.block_displacements[j])
                {
                    *a += b;
                }
            } else {
                g.durations.push(self.durations[j]);
                g.increments.push(self.increments[j].clone());
                g.states.push(self.states[j].clone());
                g.block_displacements
                    .push(self.block_displacements[j].clone());
                g.modes.push(self.modes[j].clone());
            }
        }
        if let Some(x0) = g.states.first().cloned() {
            g.states.push(x0);
        }
        g
    }

    /// The gait as a [`PhaseSolution`] of `phases` steps: its rates `u / tau` from its
    /// increments, with what was proven (`certificate`), its verified displacement, its cost
    /// and the outer approximation's `rounds`.
    pub(super) fn into_solution(
        self,
        phases: usize,
        certificate: Certificate,
        verified: f64,
        cost: f64,
        rounds: usize,
    ) -> PhaseSolution {
        PhaseSolution {
            phases,
            certificate,
            verified_displacement: verified,
            actuation_cost: cost,
            controls: self
                .increments
                .iter()
                .zip(&self.durations)
                .map(|(u, d)| u.iter().map(|v| v / d).collect())
                .collect(),
            durations: self.durations,
            states: self.states,
            block_displacements: self.block_displacements,
            modes: self.modes,
            rounds,
        }
    }

    pub(super) fn displacement(&self) -> f64 {
        self.block_displacements
            .iter()
            .map(|d| d.iter().sum::<f64>() / d.len() as f64)
            .sum()
    }

    pub(super) fn cost(&self, problem: &GaitProblem) -> f64 {
        self.durations
            .iter()
            .zip(&self.increments)
            .map(|(&d, u)| {
                let rate: Vec<f64> = u.iter().map(|v| v / d).collect();
                d * problem.cost.eval(&rate)
            })
            .sum()
    }

    /// All columns of a `K`-step layout holding this gait, with exact cost epigraphs: a
    /// feasible start for the MILP, or `None` when no block ever holds a face (an idle gait,
    /// which the layout writes differently) or the gait has too many slip phases.
    ///
    /// The gait is rotated to start just after a slip phase; each run of all-stick phases
    /// becomes one transition (a straight move of `x` inside the convex C, every block
    /// sticking, with the run's total increment and duration), followed by its slip phase.
    /// The phase of largest displacement goes first, as the symmetry rows require, and unused
    /// phases come last.
    pub(super) fn columns(&self, lay: &Layout, ncols: usize) -> Option<Vec<f64>> {
        self.merged().columns_merged(lay, ncols)
    }

    /// [`RawGait::columns`] of a gait whose runs are merged.
    fn columns_merged(&self, lay: &Layout, ncols: usize) -> Option<Vec<f64>> {
        let p = self.durations.len();
        let slips: Vec<usize> = (0..p)
            .filter(|&j| self.modes[j].iter().any(|&s| s != 0))
            .collect();
        let last = *slips.last()?;
        if slips.len() > lay.tau.len() {
            return None;
        }
        let n = self.increments[0].len();
        // (sigma, W, x, slip phase index)
        let mut macros: Vec<(f64, Vec<f64>, Vec<f64>, usize)> = Vec::new();
        let (mut sigma, mut w, mut x0): (f64, Vec<f64>, Option<&Vec<f64>>) =
            (0.0, vec![0.0; n], None);
        for i in 1..=p {
            let j = (last + i) % p;
            if self.modes[j].iter().any(|&s| s != 0) {
                let x = x0.unwrap_or(&self.states[j]).clone();
                macros.push((sigma, w, x, j));
                (sigma, w, x0) = (0.0, vec![0.0; n], None);
            } else {
                sigma += self.durations[j];
                for (wl, ul) in w.iter_mut().zip(&self.increments[j]) {
                    *wl += ul;
                }
                x0.get_or_insert(&self.states[j]);
            }
        }
        let disp = |m: &(f64, Vec<f64>, Vec<f64>, usize)| -> f64 {
            self.block_displacements[m.3].iter().sum()
        };
        let first = (0..macros.len())
            .max_by(|&i, &j| disp(&macros[i]).total_cmp(&disp(&macros[j])))
            .unwrap_or(0);
        macros.rotate_left(first);
        let mut x = vec![0.0; ncols];
        let mut set = |cols: &[Col], vals: &[f64]| {
            for (c, v) in cols.iter().zip(vals) {
                x[c.index()] = *v;
            }
        };
        let home = macros[0].2.clone();
        for j in 0..lay.tau.len() {
            let Some((sig, w, xj, s)) = macros.get(j) else {
                set(&lay.xs[j], &home);
                set(&lay.ys[j], &home);
                continue;
            };
            let d = self.durations[*s];
            set(&lay.xs[j], xj);
            set(&lay.ys[j], &self.states[*s]);
            set(&lay.ws[j], w);
            set(&lay.us[j], &self.increments[*s]);
            set(&[lay.sigma[j], lay.tau[j], lay.used[j]], &[*sig, d, 1.0]);
            if let (Some(g), Some(h)) = (lay.g.get(j), lay.h.get(j)) {
                let sq: Vec<f64> = self.increments[*s].iter().map(|u| u * u / d).collect();
                set(g, &sq);
                let sq: Vec<f64> = w
                    .iter()
                    .map(|u| if *sig > 0.0 { u * u / sig } else { 0.0 })
                    .collect();
                set(h, &sq);
            }
            let dj = &self.block_displacements[*s];
            let mj = &self.modes[*s];
            let pos: Vec<f64> = dj.iter().map(|v| v.max(0.0)).collect();
            let neg: Vec<f64> = dj.iter().map(|v| (-v).max(0.0)).collect();
            set(&lay.ps[j], &pos);
            set(&lay.qs[j], &neg);
            let bp: Vec<f64> = mj.iter().map(|&m| f64::from(u8::from(m > 0))).collect();
            let bq: Vec<f64> = mj.iter().map(|&m| f64::from(u8::from(m < 0))).collect();
            set(&lay.sp[j], &bp);
            set(&lay.sq[j], &bq);
        }
        Some(x)
    }

    pub(super) fn of(s: &PhaseSolution) -> Self {
        RawGait {
            durations: s.durations.clone(),
            increments: s
                .controls
                .iter()
                .zip(&s.durations)
                .map(|(u, d)| u.iter().map(|v| v * d).collect())
                .collect(),
            states: s.states.clone(),
            block_displacements: s.block_displacements.clone(),
            modes: s.modes.clone(),
        }
    }
}

/// The phase gait of a piecewise-linear actuation (pieces of `durations`, increments `U_j = k
/// (L_{j+1} - L_j)` per link, summing to 0 over the period): played by the exact simulator to its
/// periodic orbit, each interval between events is a phase of constant control and slip mode, with
/// its states and block displacements. So any gait written as knots (a structured gait, a local
/// method's answer) becomes a start of the phase MILP
/// ([`PhaseOptions::start`](super::PhaseOptions::start),
/// [`GrowOptions::start`](super::GrowOptions::start)).
///
/// The result makes no claim: `phases` is its number of slip phases, its certificate has status
/// `stalled`, a NaN bound and gap; a MILP that takes it as its start certifies its own answer.
/// Refused (field `start`): pieces that do not match the links, non-positive or non-finite
/// durations, durations not summing to the period, increments that exceed the rate bounds or do not
/// sum to 0.
pub fn phase_gait_of(
    crawler: &Crawler,
    problem: &GaitProblem,
    durations: &[f64],
    increments: &[Vec<f64>],
) -> Result<PhaseSolution> {
    let t = problem.period;
    check_pieces(crawler, problem, durations, increments)?;
    let what = "start gait";
    let sim = replay(crawler, t, durations, increments, None, Method::Exact, what)?;
    let verified = sim
        .displacement_per_period
        .ok_or_else(|| Error::Numerical(format!("{what}: the replay did not converge")))?;
    let traj = sim
        .trajectory
        .as_ref()
        .filter(|tr| tr.t.len() >= 2)
        .ok_or_else(|| Error::Numerical(format!("{what}: no trajectory was recorded")))?;
    let mut g = trajectory_pieces(crawler, problem, durations, increments, traj);
    let Some(x0) = g.states.first().cloned() else {
        return Err(Error::Numerical(format!(
            "{what}: no piece of positive duration"
        )));
    };
    g.states.push(x0);
    check_verified(
        what,
        g.displacement(),
        verified,
        problem.length_scale(crawler),
    )?;
    // The gait returned is the merged one: its cost, which merging lowers where a run's rates
    // differ (the same motion at constant rates; a quadratic cost's start had reported the
    // cost of the unmerged pieces, so its J was below what it is).
    let merged = g.merged();
    let cost = merged.cost(problem);
    let certificate = Certificate {
        status: MilpStatus::Stalled,
        milp_objective: verified,
        bound: f64::NAN,
        gap: f64::NAN,
    };
    let phases = merged.slip_phases();
    Ok(merged.into_solution(phases, certificate, verified, cost, 0))
}

/// Refuses (field `start`) pieces that do not match the links, non-positive or non-finite
/// durations, durations not summing to the period, increments that exceed the rate bounds or
/// do not sum to 0 ([`phase_gait_of`]).
fn check_pieces(
    crawler: &Crawler,
    problem: &GaitProblem,
    durations: &[f64],
    increments: &[Vec<f64>],
) -> Result<()> {
    let (n, t) = (crawler.links(), problem.period);
    let a = &problem.rate_bound;
    let bad = |why: String| {
        Err(Error::invalid(
            "start",
            format!("{} pieces", durations.len()),
            why,
        ))
    };
    if durations.is_empty() || increments.len() != durations.len() {
        return bad("needs one increment row per piece, and some pieces".into());
    }
    if increments.iter().any(|u| u.len() != n) {
        return bad(format!("every increment row needs {n} links"));
    }
    if durations.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
        return bad("durations must be positive and finite".into());
    }
    let total: f64 = durations.iter().sum();
    if (total - t).abs() > 1e-9 * t {
        return bad(format!("durations sum to {total}, not the period {t}"));
    }
    for l in 0..n {
        let sum: f64 = increments.iter().map(|u| u[l]).sum();
        let scale: f64 = a[l] * t;
        if sum.abs() > 1e-9 * scale {
            return bad(format!("increments of link {} sum to {sum}, not 0", l + 1));
        }
        if let Some(j) = (0..durations.len())
            .find(|&j| increments[j][l].abs() > a[l] * durations[j] * (1.0 + 1e-9))
        {
            return bad(format!(
                "piece {} exceeds the rate bound of link {}",
                j + 1,
                l + 1
            ));
        }
    }
    Ok(())
}

/// The exact simulator's pieces of the gait's periodic regime as a raw phase gait (before
/// merging; the closing state not yet pushed): per recorded step of positive duration, its
/// spring-force increments `k (L(s1) - L(s0))` with `L` linear between the knots, its start
/// state, and the block displacements (below `1e-9` of the length scale read as 0) and modes.
fn trajectory_pieces(
    crawler: &Crawler,
    problem: &GaitProblem,
    durations: &[f64],
    increments: &[Vec<f64>],
    traj: &Trajectory,
) -> RawGait {
    let (n, t) = (crawler.links(), problem.period);
    let (times, lengths) = gait_knots(durations, increments, crawler.stiffness());
    // L at time s: linear between the knots (s in [0, T]).
    let length_at = |s: f64| -> Vec<f64> {
        let j = times.partition_point(|&k| k <= s).clamp(1, times.len() - 1);
        let (t0, t1) = (times[j - 1], times[j]);
        let w = if t1 > t0 {
            ((s - t0) / (t1 - t0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        lengths[j - 1]
            .iter()
            .zip(&lengths[j])
            .map(|(p, q)| p + w * (q - p))
            .collect()
    };
    let k = crawler.stiffness();
    let tiny = 1e-9 * problem.length_scale(crawler);
    let mut g = RawGait::default();
    for i in 0..traj.t.len() - 1 {
        let (s0, s1) = (traj.t[i], traj.t[i + 1]);
        if s1 - s0 <= 1e-12 * t {
            continue;
        }
        let (l0, l1) = (length_at(s0), length_at(s1));
        g.durations.push(s1 - s0);
        g.increments
            .push((0..n).map(|l| k[l] * (l1[l] - l0[l])).collect());
        g.states.push(traj.x[i].clone());
        let d: Vec<f64> = traj.positions[i + 1]
            .iter()
            .zip(&traj.positions[i])
            .map(|(q, p)| if (q - p).abs() > tiny { q - p } else { 0.0 })
            .collect();
        g.modes.push(
            d.iter()
                .map(|&v| (v > 0.0) as i8 - (v < 0.0) as i8)
                .collect(),
        );
        g.block_displacements.push(d);
    }
    g
}

/// The slip phases of a gait, in order: the modes of its phases where some block slips, a run
/// of consecutive phases of one mode merged (it is one slip phase), cyclically.
pub fn slip_sequence(modes: &[Vec<i8>]) -> Vec<Vec<i8>> {
    let mut runs: Vec<&Vec<i8>> = Vec::new();
    for m in modes {
        if runs.last() != Some(&m) {
            runs.push(m);
        }
    }
    if runs.len() > 1 && runs.first() == runs.last() {
        runs.pop();
    }
    runs.into_iter()
        .filter(|m| m.iter().any(|&s| s != 0))
        .cloned()
        .collect()
}

impl Units {
    /// A phase gait from internal units to the user's (`to_user`) or back.
    pub fn phase(&self, s: &PhaseSolution, to_user: bool) -> PhaseSolution {
        let (f, t, l) = self.factors(to_user);
        let mut out = PhaseSolution {
            phases: s.phases,
            certificate: s.certificate.clone(),
            verified_displacement: s.verified_displacement * l,
            actuation_cost: s.actuation_cost * l,
            durations: scale_all(&s.durations, t),
            controls: scale_rows(&s.controls, f / t),
            states: scale_rows(&s.states, f),
            block_displacements: scale_rows(&s.block_displacements, l),
            modes: s.modes.clone(),
            rounds: s.rounds,
        };
        // The target units' floor of `J`: the user's length unit, or 1 inside.
        let floor = if to_user { self.length } else { 1.0 };
        out.certificate = self.certificate_scaled(&s.certificate, out.objective(), l, floor);
        out
    }
}
