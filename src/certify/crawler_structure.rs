//! A crawler process's combinatorial structure (active, held and biactive faces, slips, rates
//! at their bounds) and its multipliers in its own units (module docs of [`crate::certify`] for
//! the mathematics). The multiplier LPs and the branch LPs are the general problem's
//! (`certify::general_kkt`, `certify::branch`), solved on the crawler's instance of (P) with
//! this structure mapped onto it (`certify::crawler_general`).

use crate::certify::process::{d_tol, slip, Process, ProcessKind};
use crate::optimal::Cost;

/// A face of C: block `b` (0-based) and side `s` (`+1`: `F_b <= mu_b^+`, outer normal `nu_b`;
/// `-1`: `-F_b <= mu_b^-`, outer normal `-nu_b`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FaceId {
    pub b: usize,
    pub s: i8,
}

/// The combinatorial data of a process: active faces, held faces, slips, biactive faces and
/// control bounds. Everything the KKT system needs besides the numbers.
pub(crate) struct Structure {
    pub n: usize,
    pub nb: usize,
    pub np: usize,
    /// Faces active at knot `j` (`j = 0..P`, knot `P` is knot 0).
    pub active: Vec<Vec<FaceId>>,
    /// Whether the face is held as an equality by a slipping block (then its multiplier in the
    /// branch LP has no sign).
    pub held: Vec<Vec<bool>>,
    /// Slack `c_f - <x*_f, x_j>` of each active face (for the complementarity residual).
    pub slack: Vec<Vec<f64>>,
    /// Slip direction of each block on each piece.
    pub slips: Vec<Vec<i8>>,
    /// Biactive (block, direction) pairs per piece: the block sticks but its face is active
    /// where slipping would need it (strong stationarity asks the relaxed sign condition).
    pub biactive: Vec<Vec<(usize, i8)>>,
    /// Control at its bound: `+1` upper, `-1` lower, `0` interior, per piece and link.
    pub bound: Vec<Vec<i8>>,
    /// `Df2(u_j)` per piece.
    pub grad_f2: Vec<Vec<f64>>,
    /// `k_l`.
    pub k: Vec<f64>,
    /// `Df2(u_j).u_j - f2(u_j)` per piece (the cost's part of the maximised Hamiltonian).
    pub cost_h: Vec<f64>,
}

impl Structure {
    /// The structure of `p` at relative tolerance `tol` (faces relative to the crawler's state
    /// scale, displacements to [`d_tol`], controls to their bounds).
    pub fn of(p: &Process, tol: f64) -> Self {
        let c = &p.crawler;
        let (n, nb, np) = (c.links(), c.blocks(), p.durations.len());
        let dtol = d_tol(c, tol);
        let slips: Vec<Vec<i8>> = p
            .block_displacements
            .iter()
            .map(|d| d.iter().map(|&v| slip(v, dtol)).collect())
            .collect();
        let ActiveFaces {
            active,
            held,
            slack,
        } = active_faces(p, &slips, tol);
        let biactive = biactive_pairs(p.kind, &slips, &active, nb, np);
        let a = &p.problem.rate_bound;
        let bound = p
            .controls
            .iter()
            .map(|u| {
                (0..n)
                    .map(|l| {
                        if u[l] >= a[l] * (1.0 - tol) {
                            1
                        } else if u[l] <= -a[l] * (1.0 - tol) {
                            -1
                        } else {
                            0
                        }
                    })
                    .collect()
            })
            .collect();
        let (grad_f2, cost_h) = cost_terms(p, n);
        Structure {
            cost_h,
            n,
            nb,
            np,
            active,
            held,
            slack,
            slips,
            biactive,
            bound,
            grad_f2,
            k: c.stiffness().to_vec(),
        }
    }
}

/// The faces active at every knot with their held flags and slacks, as [`active_faces`] finds
/// them (the fields of [`Structure`] of the same names).
struct ActiveFaces {
    active: Vec<Vec<FaceId>>,
    held: Vec<Vec<bool>>,
    slack: Vec<Vec<f64>>,
}

/// The faces active at every knot (slack within `tol` of the state scale), whether each is held
/// (by the piece ending there, or for a phase gait starting there, slipping on it) and its
/// slack: [`Structure::active`], [`Structure::held`], [`Structure::slack`].
fn active_faces(p: &Process, slips: &[Vec<i8>], tol: f64) -> ActiveFaces {
    let c = &p.crawler;
    let (nb, np) = (c.blocks(), p.durations.len());
    let scale = c.state_scale();
    let mut active = Vec::with_capacity(np);
    let mut held = Vec::with_capacity(np);
    let mut slack = Vec::with_capacity(np);
    let is_active = |j: usize, f: FaceId| -> Option<f64> {
        let force = c.block_forces(&p.states[j])[f.b];
        let s = if f.s > 0 {
            c.mu_forward()[f.b] - force
        } else {
            c.mu_backward()[f.b] + force
        };
        (s <= tol * scale).then_some(s)
    };
    for j in 0..np {
        let prev = (j + np - 1) % np;
        let (mut a, mut h, mut sl) = (Vec::new(), Vec::new(), Vec::new());
        for b in 0..nb {
            for s in [1i8, -1] {
                let f = FaceId { b, s };
                if let Some(v) = is_active(j, f) {
                    // Held by the piece ending here (both kinds) or starting here (phase).
                    let by_prev = slips[prev][b] == s;
                    let by_next = p.kind == ProcessKind::Phase && slips[j][b] == s;
                    a.push(f);
                    h.push(by_prev || by_next);
                    sl.push(v);
                }
            }
        }
        active.push(a);
        held.push(h);
        slack.push(sl);
    }
    ActiveFaces {
        active,
        held,
        slack,
    }
}

/// The biactive (block, direction) pairs of every piece ([`Structure::biactive`]): a sticking
/// block whose face is active where a slip on it would need it (P_m: at the piece's end; a
/// phase: at both ends).
fn biactive_pairs(
    kind: ProcessKind,
    slips: &[Vec<i8>],
    active: &[Vec<FaceId>],
    nb: usize,
    np: usize,
) -> Vec<Vec<(usize, i8)>> {
    let mut biactive = Vec::with_capacity(np);
    for j in 0..np {
        let mut v = Vec::new();
        for b in 0..nb {
            if slips[j][b] != 0 {
                continue;
            }
            for s in [1i8, -1] {
                let f = FaceId { b, s };
                let end = active[(j + 1) % np].contains(&f);
                let start = active[j].contains(&f);
                let avail = match kind {
                    ProcessKind::Discrete { .. } => end,
                    ProcessKind::Phase => end && start,
                };
                if avail {
                    v.push((b, s));
                }
            }
        }
        biactive.push(v);
    }
    biactive
}

/// The cost's terms per piece: `Df2(u_j)` and `Df2(u_j).u_j - f2(u_j)`
/// ([`Structure::grad_f2`], [`Structure::cost_h`]).
fn cost_terms(p: &Process, n: usize) -> (Vec<Vec<f64>>, Vec<f64>) {
    let grad_f2: Vec<Vec<f64>> = p
        .controls
        .iter()
        .map(|u| match p.problem.cost {
            Cost::None => vec![0.0; n],
            Cost::Quadratic { weight } => u.iter().map(|v| weight * v).collect(),
        })
        .collect();
    let cost_h = p
        .controls
        .iter()
        .zip(&grad_f2)
        .map(|(u, g)| u.iter().zip(g).map(|(u, g)| u * g).sum::<f64>() - p.problem.cost.eval(u))
        .collect();
    (grad_f2, cost_h)
}

/// Raw multipliers: `p_j` per piece, `xi` per active face of every knot (same layout as
/// [`Structure::active`]), `omega`, at the given `lambda`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Raw {
    pub lambda: f64,
    pub p: Vec<Vec<f64>>,
    pub xi: Vec<Vec<f64>>,
    pub omega: Vec<f64>,
}
