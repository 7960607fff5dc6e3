//! A crawler's multipliers found by the general problem's multiplier LPs
//! ([`crate::certify::general`]) on its exact instance of (P)
//! ([`crate::model::crawler_as_general`]), and read back in the crawler's own names: one
//! formulation of the branch LP's KKT system for both certificates.
//!
//! The change of variables `x~ = K^(-1/2) x` leaves the Lagrangian term `<q, dynamics>`
//! invariant, so (module docs of [`crate::certify::general`]) the general multipliers map back
//! as `p = K^(-1/2) p~` (componentwise by `sqrt(k_l)`), `omega` unchanged, and
//! `xi_(b+-) = xi~_(b+-) / s_b` with `s_b = sqrt(k_(b-1) + k_b)` (the crawler's `xi` is in the
//! units of the unnormalised `+-nu_b`); the general face of block `b` (0-based) and side `+` is
//! `2 b`, of side `-` is `2 b + 1` (0-based).

use super::crawler_structure::{FaceId, Raw, Structure};
use super::crawler_words::crawler_words;
use super::general::certify_structured;
use super::general_conditions::GeneralNecessaryConditions;
use super::general_kkt::{face_weights, GeneralRaw, GeneralStructure};
use super::general_process::{control_rows, GeneralProcess};
use super::general_report::Words;
use super::process::{Process, ProcessKind};
use super::CertifyOptions;
use crate::error::Result;
use crate::model::general::GeneralProblem;
use crate::model::{crawler_as_general, CrawlerInstance};

/// The crawler process `pr` as (P): its instance, its process there and that process's
/// structure, with the crawler's structure to read the multipliers back into.
pub(crate) struct AsGeneral<'a> {
    inst: CrawlerInstance,
    st: &'a Structure,
    gst: GeneralStructure,
    /// The process on the instance ([`GeneralProcess::of_crawler`]).
    process: GeneralProcess,
    s_b: Vec<f64>,
}

impl<'a> AsGeneral<'a> {
    /// The instance of `pr`'s crawler and gait problem (cost `f2` unchanged: the control is the
    /// crawler's), with the crawler's structure `st` in its terms.
    pub fn of(pr: &Process, st: &'a Structure) -> Result<Self> {
        let cost = pr.problem.cost.into();
        let inst =
            crawler_as_general(&pr.crawler, pr.problem.period, &pr.problem.rate_bound, cost)?;
        let s_b = crate::model::crawler_row_norms(pr.crawler.stiffness());
        let gst = structure_of(&inst.problem, pr, st, &s_b);
        let process = GeneralProcess::of_crawler(pr);
        Ok(AsGeneral {
            s_b,
            inst,
            st,
            gst,
            process,
        })
    }

    /// The one certificate ([`certify_structured`]) of the process on its instance, with the
    /// crawler's structure, units and words ([`crawler_words`]): (P)'s report, and the
    /// multipliers it states read back in the crawler's names ([`Self::back`]).
    pub fn certify(&self, opts: &CertifyOptions) -> Result<(GeneralNecessaryConditions, Raw)> {
        let words = Words {
            switching: "p + omega",
            component: "link",
            condition: crawler_words,
            hamiltonian: "H_k = sum_l a_l |psi_{k,l}| over the rates at their bound + lambda \
                          (Df2(u_k).u_k - f2(u_k))",
        };
        let (rep, raw) = certify_structured(
            &self.inst.problem,
            &self.process,
            &self.gst,
            &words,
            opts,
            true,
        )?;
        Ok((rep, self.back(raw)))
    }

    /// General multipliers in the crawler's units: `p = K^(-1/2) p~`, `omega`, and `xi = xi~ / s_b`
    /// (the instance's active faces are the crawler's, in the same order: [`structure_of`]).
    fn back(&self, g: GeneralRaw) -> Raw {
        let p =
            g.p.iter()
                .map(|p| {
                    p.iter()
                        .zip(&self.inst.sqrt_k)
                        .map(|(v, s)| v / s)
                        .collect()
                })
                .collect();
        let xi = self
            .st
            .active
            .iter()
            .zip(&g.xi)
            .map(|(faces, xs)| {
                faces
                    .iter()
                    .zip(xs)
                    .map(|(f, x)| x / self.s_b[f.b])
                    .collect()
            })
            .collect();
        Raw {
            lambda: g.lambda,
            p,
            xi,
            omega: g.omega,
        }
    }
}

/// The general face of a crawler's face: block `b`'s side `+` is `2 b`, side `-` is `2 b + 1`.
fn face_of(f: FaceId) -> usize {
    2 * f.b + usize::from(f.s < 0)
}

/// The crawler's structure `st` of `pr` in the terms of its instance `p` of (P): the same
/// active and held faces (slacks in the unit normals' units, `/ s_b`), each slipping block's
/// face reacting and each biactive pair a face that may react without doing so, the same
/// bounds of the rates (rows `+e_l <= a_l`, `-e_l <= a_l`), one decision at one tolerance for
/// both certificates, and the margin taken on every rate at its bound as the crawler's
/// certificate reads it. The violations are counted in the crawler's units (`face_scale = s_b`:
/// its slip stationarity `<p, K nu_b> + lambda/N` is `s_b` times the unit row's, its `xi` is
/// `xi~ / s_b`).
fn structure_of(p: &GeneralProblem, pr: &Process, st: &Structure, s_b: &[f64]) -> GeneralStructure {
    let active: Vec<Vec<usize>> = st
        .active
        .iter()
        .map(|a| a.iter().map(|&f| face_of(f)).collect())
        .collect();
    let slack = st
        .active
        .iter()
        .zip(&st.slack)
        .map(|(a, sl)| a.iter().zip(sl).map(|(f, v)| v / s_b[f.b]).collect())
        .collect();
    let reacting = (0..st.np)
        .map(|i| {
            let slipping = (0..st.nb).filter(|&b| st.slips[i][b] != 0).map(|b| {
                (
                    face_of(FaceId {
                        b,
                        s: st.slips[i][b],
                    }),
                    true,
                )
            });
            let biactive = st.biactive[i]
                .iter()
                .map(|&(b, s)| (face_of(FaceId { b, s }), false));
            slipping.chain(biactive).collect()
        })
        .collect();
    let urows = control_rows(&p.control);
    let urows_active: Vec<Vec<usize>> = st
        .bound
        .iter()
        .map(|bound| {
            bound
                .iter()
                .enumerate()
                .filter(|(_, &s)| s != 0)
                .map(|(l, &s)| 2 * l + usize::from(s < 0))
                .collect()
        })
        .collect();
    let at_vertex = urows_active.iter().map(|a| a.len() == st.n).collect();
    GeneralStructure {
        n: st.n,
        m: st.n,
        steps: st.np,
        tau: pr.durations.clone(),
        phase: pr.kind == ProcessKind::Phase,
        active,
        held: st.held.clone(),
        slack,
        reacting,
        urows_active,
        at_vertex,
        grad_f2: st.grad_f2.clone(),
        cost_h: st.cost_h.clone(),
        w: face_weights(p),
        urows,
        face_scale: s_b.iter().flat_map(|&s| [s, s]).collect(),
        // B = K^(-1/2): the instance's p~ is K^(1/2) p.
        state_scale: (0..st.n).map(|l| p.dynamics.b[l][l]).collect(),
        margin_off_vertex: true,
        switching_unit: 1.0 / (st.nb as f64 * st.k.iter().fold(0.0_f64, |m, &k| m.max(k))),
        margin_cap: 10.0 / (st.nb as f64 * st.k.iter().fold(f64::INFINITY, |m, &k| m.min(k))),
    }
}

#[cfg(test)]
mod tests {
    use super::super::general_conditions::residuals;
    use super::super::general_kkt::psi_of;
    use super::super::process::INPUT_TOL;
    use super::*;
    use crate::optimal::{solve_discrete_global, Cost, GaitProblem, GaitResult};
    use crate::Crawler;

    /// The duals HiGHS returns for the branch LP on the crawler's instance
    /// ([`super::super::branch::branch_lp`]) satisfy the KKT system the certificate solves for
    /// (the independent check of the derivation and its signs), at the global optimum of P_m,
    /// every residual counted in the crawler's units.
    #[test]
    fn branch_lp_duals_satisfy_the_kkt_system() {
        for (nb, mm, m) in [(2, 2.0, 3), (3, 1.5, 3)] {
            let c = Crawler::uniform(nb, 1.0, 1.0, mm).unwrap();
            let pb = GaitProblem::new(&c, 10.0, &vec![1.0; nb - 1], Cost::None, None).unwrap();
            let s = solve_discrete_global(&c, &pb, m).unwrap();
            let r = GaitResult::from_discrete(&c, &pb, &s);
            let pr = Process::from_result(&r, "test").unwrap();
            let st = Structure::of(&pr, INPUT_TOL);
            let general = AsGeneral::of(&pr, &st).unwrap();
            let (p, gst) = (&general.inst.problem, &general.gst);
            let (opt, mut raw) = super::super::branch::branch_lp(p, gst, &[]).unwrap();
            assert!((opt - r.objective).abs() < 1e-9, "{opt} vs {}", r.objective);
            // Each rate at its bound weighted by psi (every active row of the box is an axis row).
            raw.rho = (0..gst.steps)
                .map(|i| {
                    let psi = psi_of(p, gst, &raw, i);
                    let axis = gst.axis_rows(i);
                    axis.iter()
                        .map(|ax| ax.map_or(0.0, |(l, v)| (psi[l] / v).max(0.0)))
                        .collect()
                })
                .collect();
            for (name, _, v) in residuals(p, gst, &raw, true, false) {
                println!("N = {nb}: {name} {v:.3e}");
                if name != "sign" {
                    assert!(v < 1e-9, "N = {nb}: {name} {v:.3e}");
                }
            }
        }
    }
}
