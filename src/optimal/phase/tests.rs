//! Unit tests of the phase module's internals (the layout, the decoding, the slip modes).

use super::decode::RawGait;
use super::layout::{build, Layout};
use super::sequence::neighbours;
use super::*;
use crate::optimal::milp::{force_row, solve_max, TangentRates};
use crate::optimal::{Cost, MilpStatus};
use highs::{Col, RowProblem};

/// Every column of `lay`, in no particular order.
fn all_columns(lay: &Layout) -> Vec<Col> {
    let mut v: Vec<Col> = Vec::new();
    for c in [&lay.sigma, &lay.tau, &lay.used] {
        v.extend(c.iter().copied());
    }
    for c in [
        &lay.xs, &lay.ys, &lay.ws, &lay.us, &lay.ps, &lay.qs, &lay.sp, &lay.sq, &lay.g, &lay.h,
    ] {
        v.extend(c.iter().flatten().copied());
    }
    v
}

/// Whether `gait` written into a `phases`-step layout satisfies every row: each column is
/// pinned to its value and HiGHS must find the problem feasible.
fn start_is_feasible(c: &Crawler, p: &GaitProblem, phases: usize, gait: &RawGait) -> bool {
    let rates = match p.cost {
        Cost::Quadratic { .. } => Some(TangentRates::new(&p.rate_bound)),
        Cost::None => None,
    };
    let (mut pb, lay) = build(c, p, phases, rates.as_ref(), None, &Default::default());
    let Some(x) = gait.columns(&lay, pb.num_cols()) else {
        return false;
    };
    let cols = all_columns(&lay);
    assert_eq!(cols.len(), pb.num_cols(), "the layout holds every column");
    for col in cols {
        let v = x[col.index()];
        let tol = 1e-9 * v.abs().max(1.0);
        pb.add_row(v - tol..=v + tol, [(col, 1.0)]);
    }
    crate::progress::within(Some(30.0), || {
        solve_max(pb, "start check", None, 1e-9).is_ok()
    })
}

fn rotated(g: &RawGait, r: usize) -> RawGait {
    let p = g.durations.len();
    let rot =
        |v: &Vec<Vec<f64>>| -> Vec<Vec<f64>> { (0..p).map(|i| v[(i + r) % p].clone()).collect() };
    let mut states = rot(&g.states[..p].to_vec());
    states.push(states[0].clone());
    RawGait {
        durations: (0..p).map(|i| g.durations[(i + r) % p]).collect(),
        increments: rot(&g.increments),
        states,
        block_displacements: rot(&g.block_displacements),
        modes: (0..p).map(|i| g.modes[(i + r) % p].clone()).collect(),
    }
}

/// Whether the face of `mode` is nonempty, by an LP over `x` (independent of the closed
/// form of [`slip_mode_is_valid`]).
fn face_is_nonempty(c: &Crawler, mode: &[i8]) -> bool {
    let (mp, mm) = (c.mu_forward(), c.mu_backward());
    let mut pb = RowProblem::default();
    let x: Vec<Col> = (0..c.links())
        .map(|_| pb.add_column(0.0, f64::NEG_INFINITY..f64::INFINITY))
        .collect();
    for (b, &m) in mode.iter().enumerate() {
        let row = force_row(&x, b);
        match m {
            1 => pb.add_row(mp[b]..=mp[b], row),
            -1 => pb.add_row(-mm[b]..=-mm[b], row),
            _ => pb.add_row(-mm[b]..=mp[b], row),
        }
    }
    let mut h = crate::optimal::solver::Highs::new(pb, highs::Sense::Maximise, "test").unwrap();
    h.solve().unwrap().status == crate::optimal::solver::SolveStatus::Optimal
}

#[test]
fn valid_slip_modes_are_the_nonempty_faces_of_c() {
    let cases = [
        (vec![1.0, 1.0, 1.0], vec![1.5, 1.5, 1.5]),
        (vec![1.0, 0.7, 1.3, 0.9], vec![1.6, 2.9, 0.8, 1.1]),
        (vec![1.0, 1.0, 1.0, 1.0, 1.0], vec![1.6, 1.6, 1.6, 1.6, 1.6]),
        (vec![2.5, 2.5, 2.5], vec![1.0, 1.0, 1.0]),
    ];
    for (mp, mm) in cases {
        let nb = mp.len();
        let c = Crawler::new(vec![1.0; nb - 1], mp, mm).unwrap();
        let mut valid = 0;
        for code in 0..3usize.pow(nb as u32) {
            let mode: Vec<i8> = (0..nb)
                .map(|b| (code / 3usize.pow(b as u32) % 3) as i8 - 1)
                .collect();
            let slipping = mode.iter().any(|&m| m != 0);
            let expect = slipping && face_is_nonempty(&c, &mode);
            assert_eq!(slip_mode_is_valid(&c, &mode), expect, "{mode:?}");
            valid += usize::from(expect);
        }
        if nb == 3 && c.mu_forward()[0] == 1.0 {
            // One block forward or backward (6), or one each way (6): the hexagon's
            // edges and vertices.
            assert_eq!(valid, 12);
        }
    }
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    assert!(!slip_mode_is_valid(&c, &[0, 0, 0]));
    assert!(!slip_mode_is_valid(&c, &[1, 0]));
    assert!(!slip_mode_is_valid(&c, &[2, 0, 0]));
    for m in neighbours(&c, &[1, 0, 0]) {
        assert!(slip_mode_is_valid(&c, &m) && m != vec![1, 0, 0]);
    }
    assert!(neighbours(&c, &[1, 0, 0]).contains(&vec![0, 1, 0]));
}

#[test]
fn slip_sequence_merges_repeats_cyclically() {
    let m = |v: &[i8]| v.to_vec();
    let modes = vec![
        m(&[1, 0, 0]),
        m(&[0, 0, 0]),
        m(&[0, 1, 0]),
        m(&[0, 1, 0]),
        m(&[0, 0, 0]),
        m(&[0, 1, 0]),
        m(&[1, 0, 0]),
    ];
    // Equal modes separated by a transition are two slip phases; the last merges with the
    // first across the period's end.
    assert_eq!(
        slip_sequence(&modes),
        vec![m(&[1, 0, 0]), m(&[0, 1, 0]), m(&[0, 1, 0])]
    );
    assert!(slip_sequence(&[m(&[0, 0])]).is_empty());
}

#[test]
fn any_rotation_of_a_gait_is_a_feasible_start_for_as_many_steps_or_more() {
    for cost in [Cost::None, Cost::Quadratic { weight: 0.1 }] {
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        let p = GaitProblem::new(&c, 10.0, &[1.0, 1.0], cost, None).unwrap();
        let s = solve_phase_global(&c, &p, 4).unwrap();
        let g = RawGait::of(&s);
        let slips = g.slip_phases();
        assert!(g.durations.len() > slips, "the optimum has transitions");
        for r in 0..g.durations.len() {
            let h = rotated(&g, r);
            for k in [slips, slips + 1] {
                assert!(start_is_feasible(&c, &p, k, &h), "rotation {r}, K = {k}");
            }
            assert!(!start_is_feasible(&c, &p, slips - 1, &h), "too few steps");
        }
        // A slip phase cut in two halves, the gait rotated so that they sit at its two
        // ends: still one slip phase, so it fits as many steps.
        let j = (0..g.durations.len())
            .find(|&j| g.modes[j].iter().any(|&m| m != 0))
            .unwrap();
        let half = |v: &Vec<f64>| -> Vec<f64> { v.iter().map(|x| 0.5 * x).collect() };
        let mut cut = RawGait {
            durations: g.durations.clone(),
            increments: g.increments.clone(),
            states: g.states.clone(),
            block_displacements: g.block_displacements.clone(),
            modes: g.modes.clone(),
        };
        let mid: Vec<f64> = g.states[j]
            .iter()
            .zip(&g.states[j + 1])
            .map(|(a, b)| 0.5 * (a + b))
            .collect();
        cut.durations[j] *= 0.5;
        cut.durations.insert(j, cut.durations[j]);
        cut.increments[j] = half(&g.increments[j]);
        cut.increments.insert(j, cut.increments[j].clone());
        cut.block_displacements[j] = half(&g.block_displacements[j]);
        cut.block_displacements
            .insert(j, cut.block_displacements[j].clone());
        cut.modes.insert(j, g.modes[j].clone());
        cut.states.insert(j + 1, mid);
        let cut = rotated(&cut, j + 1);
        assert_eq!(cut.slip_phases(), slips);
        assert!(start_is_feasible(&c, &p, slips, &cut), "split slip phase");
    }
}

#[test]
fn a_start_no_milp_has_certified_keeps_the_work_bound_and_says_time_limit() {
    let c = Crawler::uniform(10, 1.0, 1.0, 1.3).unwrap();
    let p = GaitProblem::new(&c, 10.0, &[1.0; 9], Cost::None, None).unwrap();
    let sign = |l: usize| if l % 2 == 0 { 2.5 } else { -2.5 };
    let incs: Vec<Vec<f64>> = [1.0, -1.0, -1.0, 1.0]
        .iter()
        .map(|s| (0..9).map(|l| s * sign(l)).collect())
        .collect();
    let g = phase_gait_of(&c, &p, &[2.5; 4], &incs).unwrap();
    assert!(g.certificate.bound.is_nan());
    let s = start_unproven(&c, &p, &g, 1);
    assert_eq!(s.certificate.status, MilpStatus::TimeLimit);
    assert_eq!(s.phases, 1);
    // Uniform chain of 10: the force ranges sum to 56 (widths 2.3, 4.6, ..., 11.5, ..., 2.3):
    // 10 * 56 / 2 / 10 = 28.
    assert!(
        (s.certificate.bound - 28.0).abs() < 1e-9,
        "{}",
        s.certificate.bound
    );
    assert_eq!(s.durations, g.durations);
}

#[test]
fn the_dissipation_row_is_on_by_default_from_ten_blocks() {
    let chain = |nb: usize| Crawler::uniform(nb, 1.0, 1.0, 1.3).unwrap();
    let f = Formulation::default();
    assert!(!f.dissipation_row_for(&chain(DISSIPATION_ROW_BLOCKS - 1)));
    assert!(f.dissipation_row_for(&chain(DISSIPATION_ROW_BLOCKS)));
    let off = Formulation {
        dissipation_row: Some(false),
    };
    assert!(!off.dissipation_row_for(&chain(20)));
    let on = Formulation {
        dissipation_row: Some(true),
    };
    assert!(on.dissipation_row_for(&chain(3)));
}
