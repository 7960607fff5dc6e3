//! Everything `crawlopt analyze` reports about a crawler, as one serialisable value.

use crate::model::{Crawler, Face, Uniqueness, VmClass};
use serde::Serialize;

/// Largest number of links for which the vertices of C are listed.
pub const MAX_LINKS_FOR_VERTICES: usize = 3;

/// Closed-form facts of the one-link crawler (theory §9, paper §4).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OneLink {
    /// `C = [alpha, beta]`, `alpha = max(-mu_1^+, -mu_2^-)`.
    pub alpha: f64,
    /// `beta = min(mu_1^-, mu_2^+)`.
    pub beta: f64,
    /// `w = beta - alpha`.
    pub width: f64,
    /// Extension moves the crawler forward iff `mu_2^+ < mu_1^-` (else backward).
    pub extension_moves_forward: bool,
    /// Contraction moves the crawler forward iff `mu_1^+ < mu_2^-` (else backward).
    pub contraction_moves_forward: bool,
    /// Smallest `a T` (rate bound times period, force units) above which a periodic gait moves
    /// the crawler forward: `2 w` when both hold, `None` when no periodic gait moves it forward.
    #[serde(rename = "min_aT_forward")]
    pub min_at_forward: Option<f64>,
    /// The same for backward motion (both fail).
    #[serde(rename = "min_aT_backward")]
    pub min_at_backward: Option<f64>,
}

/// The analysis of a crawler: C, the uniqueness condition, v_m.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Analysis {
    /// `N`.
    pub blocks: usize,
    /// `n = N - 1`.
    pub links: usize,
    /// Whether the uniqueness condition (paper eq. 3.6) holds.
    pub uniqueness_ok: bool,
    /// A violating subset `J` (1-based blocks), or `None`.
    pub violating_subset: Option<Vec<usize>>,
    /// `min_J |sum_J mu^+ - sum_{J^c} mu^-|` when the condition holds.
    pub uniqueness_margin: Option<f64>,
    /// Where the margin is reached (1-based blocks).
    pub closest_subset: Option<Vec<usize>>,
    /// Why the condition could not be decided, if so.
    pub uniqueness_undecided: Option<String>,
    /// Class of v_m (`None` when the motion is not unique).
    pub vm_class: Option<VmClass>,
    /// Whether some shape rate moves the crawler forward.
    pub moves_forward: Option<bool>,
    /// Whether some shape rate moves it backward.
    pub moves_backward: Option<bool>,
    /// A shape rate `z'` with `v_m(z') > 0`.
    pub forward_witness: Option<Vec<f64>>,
    /// A shape rate `z'` with `v_m(z') < 0`.
    pub backward_witness: Option<Vec<f64>>,
    /// The `2N` faces of C.
    pub faces: Vec<Face>,
    /// Range of every link force over C.
    pub link_force_ranges: Vec<[f64; 2]>,
    /// Vertices of C (for `n <= 3`).
    pub vertices: Option<Vec<Vec<f64>>>,
    /// One-link closed forms (for `N = 2`).
    pub one_link: Option<OneLink>,
}

impl Crawler {
    /// Analyses the crawler (all decisions exact; see [`Crawler::analyze_vm`]).
    pub fn analyze(&self) -> Analysis {
        let one_based = |s: &[usize]| s.iter().map(|b| b + 1).collect::<Vec<_>>();
        let (violating_subset, margin, closest, undecided) = match self.uniqueness() {
            Uniqueness::Holds {
                margin,
                closest_subset,
            } => (None, Some(*margin), Some(one_based(closest_subset)), None),
            Uniqueness::Fails { subset } => (Some(one_based(subset)), None, None, None),
            Uniqueness::Undecided { reason } => (None, None, None, Some(reason.clone())),
        };
        let ok = self.uniqueness().holds();
        let vm = ok.then(|| self.analyze_vm());
        let one_link = (self.blocks() == 2).then(|| {
            let (mp, mm) = (self.mu_forward(), self.mu_backward());
            let alpha = (-mp[0]).max(-mm[1]);
            let beta = mm[0].min(mp[1]);
            let ext = mp[1] < mm[0];
            let con = mp[0] < mm[1];
            let w = beta - alpha;
            OneLink {
                alpha,
                beta,
                width: w,
                extension_moves_forward: ext,
                contraction_moves_forward: con,
                min_at_forward: (ok && ext && con).then_some(2.0 * w),
                min_at_backward: (ok && !ext && !con).then_some(2.0 * w),
            }
        });
        Analysis {
            blocks: self.blocks(),
            links: self.links(),
            uniqueness_ok: ok,
            violating_subset,
            uniqueness_margin: margin,
            closest_subset: closest,
            uniqueness_undecided: undecided,
            vm_class: vm.as_ref().map(|v| v.class),
            moves_forward: vm.as_ref().map(|v| v.moves_forward),
            moves_backward: vm.as_ref().map(|v| v.moves_backward),
            forward_witness: vm.as_ref().and_then(|v| v.forward_witness.clone()),
            backward_witness: vm.as_ref().and_then(|v| v.backward_witness.clone()),
            faces: self.faces(),
            link_force_ranges: self.link_force_ranges(),
            vertices: (ok && self.links() <= MAX_LINKS_FOR_VERTICES).then(|| self.vertices()),
            one_link,
        }
    }
}
