//! Remark 3.3 of the paper: N = 3 with equal friction on all blocks.

use crawlopt::model::VmClass;
use crawlopt::Crawler;

fn class(mp: f64, mm: f64) -> (VmClass, bool, bool) {
    let a = Crawler::uniform(3, 1.0, mp, mm).unwrap().analyze();
    assert!(a.uniqueness_ok);
    (
        a.vm_class.unwrap(),
        a.moves_forward.unwrap(),
        a.moves_backward.unwrap(),
    )
}

#[test]
fn classes_just_inside_each_region() {
    // mu- > 2 mu+: convex, forward only.
    assert_eq!(class(1.0, 2.0 + 1e-6), (VmClass::Convex, true, false));
    assert_eq!(class(1.0, 5.0), (VmClass::Convex, true, false));
    // mu+ > 2 mu-: concave, backward only.
    assert_eq!(class(2.0 + 1e-6, 1.0), (VmClass::Concave, false, true));
    assert_eq!(class(4.0, 1.0), (VmClass::Concave, false, true));
    // In between: neither (the monkey saddle), both directions.
    for (mp, mm) in [(1.0, 2.0 - 1e-6), (2.0 - 1e-6, 1.0), (1.0, 1.5), (1.0, 1.1)] {
        assert_eq!(class(mp, mm), (VmClass::Neither, true, true), "{mp} {mm}");
    }
}

#[test]
fn class_boundaries_are_refused_with_a_two_block_subset() {
    for (mp, mm) in [(1.0, 2.0), (2.0, 1.0), (0.7, 1.4), (0.1, 0.2)] {
        let c = Crawler::uniform(3, 1.0, mp, mm).unwrap();
        let a = c.analyze();
        assert!(!a.uniqueness_ok, "{mp} {mm}");
        let j = a.violating_subset.unwrap();
        // mu- = 2 mu+: J of two blocks slides forward against one; mu+ = 2 mu-: one against two.
        let want = if mm > mp { 2 } else { 1 };
        assert_eq!(j.len(), want, "{mp} {mm}: {j:?}");
        let err = c.require_unique().unwrap_err().to_string();
        assert!(err.contains("uniqueness condition"), "{err}");
        assert!(a.vm_class.is_none());
    }
}

#[test]
fn monkey_saddle_has_three_ridges_and_three_ravines() {
    // On the unit circle of shape rates, v_m changes sign six times in the intermediate case.
    let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
    let m = 3600;
    let signs: Vec<bool> = (0..m)
        .map(|i| {
            let th = 2.0 * std::f64::consts::PI * (i as f64 + 0.5) / m as f64;
            c.vm(&[th.cos(), th.sin()]) > 0.0
        })
        .collect();
    let changes = (0..m).filter(|&i| signs[i] != signs[(i + 1) % m]).count();
    assert_eq!(changes, 6);
}
