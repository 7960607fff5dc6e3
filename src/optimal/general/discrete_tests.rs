//! Tests of [`super`]: the paired form of a branch LP against the form with a slack per face.

use super::*;
use crate::model::{crawler_as_general, Crawler};

/// A branch LP gives two opposite faces one value column and one signed multiplier column
/// ([`Form::Branches`]); it is the same LP as with a multiplier and a slack column per face: on the three-block crawler's instance (three
/// pairs), the branch sets read off square waves' processes and their random switches (a
/// face on or off, never both of a pair) have the same optimum either way, or are
/// infeasible either way.
#[test]
fn paired_faces_make_the_same_branch_lp() {
    let crawler = Crawler::new(vec![1.0, 1.0], vec![1.0; 3], vec![1.5; 3]).unwrap();
    let inst = crawler_as_general(&crawler, 10.0, &[1.0, 1.0], GeneralCost::None).unwrap();
    let p = &inst.problem;
    let partner = opposite_faces(p);
    assert_eq!(
        partner,
        [Some(1), Some(0), Some(3), Some(2), Some(5), Some(4)]
    );
    let m = 3;
    let mm = 1usize << m;
    let solve = |active: &[Vec<bool>], paired: bool| {
        let none = vec![None; p.c.faces()];
        let pairs = if paired { &partner[..] } else { &none[..] };
        let (pb, _) = build_paired(p, m, Form::Branches(active), &[], pairs);
        let mut lp = Highs::new(pb, Sense::Maximise, "a branch LP").unwrap();
        let a = lp.solve().unwrap();
        matches!(a.status, SolveStatus::Optimal).then_some(a.objective)
    };
    let mut seed = 7u64;
    let mut rng = move |n: usize| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) as usize % n
    };
    let (mut feasible, mut cases) = (0, 0);
    for k in 0..2 {
        for shift in 0..mm {
            let mut wave: Vec<Vec<f64>> = (0..mm)
                .map(|i| {
                    let mut u = vec![0.0; 2];
                    u[k] = if i < mm / 2 { 1.0 } else { -1.0 };
                    u
                })
                .collect();
            wave.rotate_right(shift);
            let sim = run_on_grid(p, &[0.0, 0.0], &wave, "start").unwrap();
            let read: Vec<Vec<bool>> = sim
                .lambda
                .iter()
                .map(|l| l.iter().map(|&l| l > 0.0).collect())
                .collect();
            for flips in 0..4 {
                let mut active = read.clone();
                for _ in 0..flips {
                    let (i, j) = (rng(mm), rng(6));
                    let k = partner[j].unwrap();
                    active[i][j] = !active[i][j];
                    active[i][k] &= !active[i][j];
                }
                let (a, b) = (solve(&active, true), solve(&active, false));
                cases += 1;
                match (a, b) {
                    (Some(a), Some(b)) => {
                        feasible += 1;
                        assert!((a - b).abs() < 1e-9, "{a} vs {b} on {active:?}");
                    }
                    (None, None) => {}
                    _ => panic!("{a:?} vs {b:?} on {active:?}"),
                }
            }
        }
    }
    assert!(feasible * 4 >= cases, "{feasible} of {cases} feasible");
    // Both faces of a pair held: no point of C is on both, so no LP is built.
    let mut both = vec![vec![false; 6]; mm];
    both[2][2] = true;
    both[2][3] = true;
    assert_eq!(solve_general_branch(p, m, &both).unwrap(), None);
    // A branch set of the wrong shape is refused, naming it.
    let e = solve_general_branch(p, m, &both[1..]).unwrap_err();
    assert!(e.to_string().starts_with("active:"), "{e}");
    both[0].pop();
    let e = solve_general_branch(p, m, &both).unwrap_err();
    assert!(e.to_string().starts_with("active:"), "{e}");
}
