//! (P) in units of order one, for its MILPs. HiGHS holds rows to an absolute tolerance
//! (`1e-9`), which in the problem's own units is a relative error of `1e-9 / T` on times and
//! `1e-9 / |C|` on states: on one link of half-width `1e-4`, the phase MILP's durations came out
//! `2e-7` of `T` off and its control's mean `4e-7` of its bound (which a reader refuses), and
//! P_7 with `T = 1e-2` claimed a global optimum `J = 0.0047219` with a gap of `8e-11`, below the
//! `0.0048` that the same grid reaches (the problem scaled to half-width 1 gives it).
//!
//! The units ([`Units::of`]): C's scale `s_x` (its largest offset) for states and the
//! projection's multipliers, U's largest bound `s_u` for controls, and for time the time
//! `t_0 = s_x / v` in which the largest speed `v = max_i (s_u sum_k |B_ik| + |b_i|)` crosses C,
//! or `T` where that is shorter (so durations are of order one either way). With
//! `x = s_x x'`, `u = s_u u'` and `t = t_0 t'`, the sweeping process `x' in -N_C(x) + A x + B u + b`
//! is the same process of ([`Units::problem`])
//!
//! ```text
//! C' = {x' : <x*_j, x'> <= c_j / s_x},   A' = t_0 A,   B' = (t_0 s_u / s_x) B,   b' = (t_0 / s_x) b,
//! U' = U / s_u,   T' = T / t_0,   f2' = (t_0 s_u^2 / s_x) f2,   x'(0) = x(0) / s_x (Cauchy),
//! ```
//!
//! the normal cone being a cone, and `J = s_x J'` with `f1`'s weights unchanged (a reaction's
//! integral is a length). So an optimum of one is the optimum of the other, a bound a bound,
//! and a grid's `h' = h / t_0` makes P_m of one P_m of the other: only the numbers change. The
//! phase MILP measures its columns in these units; the local method's branch LPs are solved on
//! the problem in these units ([`super::local`]); P_m is solved on the problem in these units,
//! where the problem's own are not these already ([`Units::needed`]) and its caller has
//! not chosen the units itself (a crawler's instance), and its answer converted back
//! ([`super::pm_milp`]). Either is then re-verified in the problem's own units,
//! as every answer is.

use crate::model::general::{Boundary, ControlSet, GeneralCost, GeneralProblem};
use crate::optimal::units::{scale_all, scale_rows};

/// A unit system of (P) (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Units {
    /// `t_0`.
    pub time: f64,
    /// `s_x`.
    pub state: f64,
    /// `s_u`.
    pub control: f64,
    /// `T / t_0`.
    pub period: f64,
}

/// U's largest scale (1 where it has none) and the fastest rate of a state under it,
/// `max_i (sum_j |B_ij| u + |b_i|)`: the sizes of a control and of a velocity in `p`'s units
/// (the units of order one; a certificate's residual units, `certify::general_kkt`).
pub fn control_and_speed(p: &GeneralProblem) -> (f64, f64) {
    let control = crate::optimal::process::control_scales(&p.control)
        .iter()
        .fold(0.0_f64, |m, v| m.max(*v));
    let control = if control > 0.0 { control } else { 1.0 };
    let speed = (0..p.states())
        .map(|i| {
            let b: f64 = p.dynamics.b[i].iter().map(|v| v.abs()).sum();
            control * b + p.dynamics.drift[i].abs()
        })
        .fold(0.0_f64, f64::max);
    (control, speed)
}

impl Units {
    /// The units of order one (module docs).
    pub fn of(p: &GeneralProblem) -> Self {
        let (control, speed) = control_and_speed(p);
        let state = p.c.scale();
        // A period shorter than the crossing is its own unit: durations then stay of order one.
        let time = if speed > 0.0 {
            (state / speed).min(p.period)
        } else {
            p.period
        };
        Units {
            time,
            state,
            control,
            period: p.period / time,
        }
    }

    /// The problem's own units (all 1).
    pub fn own(p: &GeneralProblem) -> Self {
        Units {
            time: 1.0,
            state: 1.0,
            control: 1.0,
            period: p.period,
        }
    }

    /// Whether a unit differs from the problem's own (P_m converts then). Converting only
    /// where a unit was off by more than a factor of 100 was not enough: with C's scale
    /// `0.01` to `0.03` (units inside that band), HiGHS proved P_3 of a 2-D problem with a box U
    /// optimal at `J = 0.0365` (`0.0410` for P_4) where the same grid reaches `0.0649` (its
    /// exact twin at scale 1, and the local method from that gait, give it), while the problem
    /// in units of one gives `0.0649` at every scale. Since every problem is solved in units of
    /// one, exact twins (the same problem in other units) give one MILP. A crawler's instance is
    /// exempt ([`super::pm_milp`]'s `keep_units`).
    pub fn needed(&self) -> bool {
        [self.time, self.state, self.control]
            .iter()
            .any(|&u| u != 1.0)
    }

    /// `p` in these units (module docs): the same problem, its numbers divided by their units.
    pub fn problem(&self, p: &GeneralProblem) -> GeneralProblem {
        let Units {
            time,
            state,
            control,
            period,
        } = *self;
        let mut c = p.c.clone();
        c.offsets = scale_all(&c.offsets, 1.0 / state);
        let mut dynamics = p.dynamics.clone();
        dynamics.a = scale_rows(&dynamics.a, time);
        dynamics.b = scale_rows(&dynamics.b, time * control / state);
        dynamics.drift = scale_all(&dynamics.drift, time / state);
        let u = match &p.control {
            ControlSet::Box { lower, upper } => ControlSet::Box {
                lower: scale_all(lower, 1.0 / control),
                upper: scale_all(upper, 1.0 / control),
            },
            ControlSet::Polytope(q) => {
                let mut q = q.clone();
                q.offsets = scale_all(&q.offsets, 1.0 / control);
                ControlSet::Polytope(q)
            }
        };
        let f = time * control * control / state;
        let cost = match &p.cost {
            GeneralCost::None => GeneralCost::None,
            GeneralCost::Quadratic { weight } => GeneralCost::Quadratic { weight: weight * f },
            GeneralCost::Matrix { matrix } => GeneralCost::Matrix {
                matrix: scale_rows(matrix, f),
            },
        };
        let boundary = match &p.boundary {
            Boundary::Periodic => Boundary::Periodic,
            Boundary::Initial(x0) => Boundary::Initial(scale_all(x0, 1.0 / state)),
        };
        GeneralProblem {
            c,
            dynamics,
            control: u,
            zero_mean: p.zero_mean,
            reward: p.reward.clone(),
            cost,
            period,
            boundary,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::general::GeneralParts;

    /// One link of half-width `a` driven at rates up to 2, a quadratic cost, period `t`.
    fn link(a: f64, t: f64) -> GeneralProblem {
        GeneralProblem::new(GeneralParts {
            normals: vec![vec![1.0], vec![-1.0]],
            offsets: vec![a, a],
            b: vec![vec![1.0]],
            lower: Some(vec![-2.0]),
            upper: Some(vec![2.0]),
            zero_mean: true,
            face_weights: Some(vec![0.5, 0.5]),
            cost: Some(GeneralCost::Quadratic { weight: 0.1 }),
            period: t,
            periodic: true,
            ..Default::default()
        })
        .expect("a valid problem")
    }

    #[test]
    fn a_small_link_in_its_units_is_the_link_of_half_width_one() {
        // s_x = 1e-4, s_u = 2, v = 2: t_0 = 5e-5, T' = 1e-2 / 5e-5 = 200.
        let p = link(1e-4, 1e-2);
        let u = Units::of(&p);
        assert!((u.time - 5e-5).abs() < 1e-18 && (u.period - 200.0).abs() < 1e-9);
        let q = u.problem(&p);
        assert!(q.c.offsets.iter().all(|c| (c - 1.0).abs() < 1e-15));
        assert!((q.dynamics.b[0][0] - 1.0).abs() < 1e-12);
        assert_eq!(q.control.dim(), 1);
        assert!(q.control.contains(&[1.0], 1e-15) && !q.control.contains(&[1.0 + 1e-9], 0.0));
        // f2' = t_0 s_u^2 / s_x f2 = 5e-5 * 4 / 1e-4 f2 = 2 f2.
        let GeneralCost::Quadratic { weight } = q.cost else {
            panic!("a quadratic cost stays quadratic")
        };
        assert!((weight - 0.2).abs() < 1e-15);
        assert!((q.period - 200.0).abs() < 1e-9);
    }

    #[test]
    fn a_period_shorter_than_the_crossing_is_the_unit_of_time() {
        let p = link(1.0, 0.1);
        let u = Units::of(&p);
        assert_eq!((u.time, u.period), (0.1, 1.0));
        assert!(u.needed() && Units::of(&link(1e-4, 1e-2)).needed());
        assert!(!Units::own(&p).needed());
        assert_eq!(Units::own(&p).problem(&p), p);
    }
}
