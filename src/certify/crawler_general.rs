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

use super::crawler_words::crawler_words;
use super::general_conditions::residuals;
use super::general_conditions::GeneralNecessaryConditions;
use super::general_kkt::{face_weights, psi_of, solve_general, GeneralRaw, GeneralStructure};
use super::general_process::{control_rows, GeneralProcess};
use super::general_report::{report, Words};
use super::kkt::{FaceId, Norm, Raw, Stage, Structure};
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

    /// One general multiplier LP (the crawler's instance has no drift: `A = 0`), its solution
    /// read back in the crawler's names.
    pub fn solve(
        &self,
        lambda: f64,
        stage: Stage,
        norm: Option<Norm>,
        durations_free: bool,
    ) -> Result<Option<Raw>> {
        let raw = solve_general(
            &self.inst.problem,
            &self.gst,
            lambda,
            stage,
            norm,
            true,
            durations_free,
        )?;
        Ok(raw.map(|g| self.back(g)))
    }

    /// The branch LP of the process on its instance ([`super::branch::branch_lp`]: the
    /// slipping blocks' faces reacting, and the biactive pairs `choice` picks, in the order of
    /// [`Structure::biactive`]), its optimum and duals read back in the crawler's names.
    pub(crate) fn branch_lp(&self, choice: &[bool]) -> Option<(f64, Raw)> {
        super::branch::branch_lp(&self.inst.problem, &self.gst, choice)
            .map(|(optimum, raw)| (optimum, self.back(raw)))
    }

    /// The size of the largest branch LP ([`super::branch::columns`]), for the budget.
    pub(crate) fn branch_columns(&self) -> usize {
        super::branch::columns(&self.gst)
    }

    /// The discrete residuals of the crawler's multipliers `raw`, recomputed by (P)'s
    /// residuals ([`residuals`]) on the instance, each in the crawler's units
    /// ([`GeneralStructure::state_scale`], [`GeneralStructure::face_scale`]), in (P)'s names:
    /// adjoint, complementarity, reaction stationarity, branch face sign, weak maximality,
    /// sign and, with `durations_free`, the duration stationarity.
    pub fn residuals(&self, raw: &Raw, durations_free: bool) -> Vec<(&'static str, f64)> {
        residuals(
            &self.inst.problem,
            &self.gst,
            &self.forward(raw),
            true,
            durations_free,
        )
        .into_iter()
        .map(|(name, _, r)| (name, r))
        .collect()
    }

    /// (P)'s certificate report ([`report`]) of the crawler's multipliers `raw` on the
    /// instance: every residual in the crawler's units (the structure's scales), every
    /// condition in the crawler's words ([`crawler_words`]); read back into the crawler's
    /// names by `certify::report`.
    pub fn report(
        &self,
        raw: &Raw,
        scaled_by: String,
        opts: &CertifyOptions,
    ) -> GeneralNecessaryConditions {
        let words = Words {
            switching: "p + omega",
            component: "link",
            condition: crawler_words,
        };
        let g = self.forward(raw);
        report(
            &self.inst.problem,
            &self.process,
            &self.gst,
            &g,
            scaled_by,
            opts,
            true,
            &words,
        )
    }

    /// The crawler's multipliers in the instance's units, the inverse of [`Self::back`]:
    /// `p~ = K^(1/2) p`, `omega`, `xi~ = s_b xi`, and each rate at its bound weighted by `psi`
    /// (`rho = sign(v) psi_l`, clipped at 0: every active row of the crawler's box is an axis row,
    /// [`GeneralStructure::axis_rows`]).
    fn forward(&self, raw: &Raw) -> GeneralRaw {
        let (p, xi) = self.rescaled(&raw.p, &raw.xi, |v, s| v * s);
        let mut g = GeneralRaw {
            lambda: raw.lambda,
            p,
            xi,
            omega: raw.omega.clone(),
            rho: Vec::new(),
        };
        g.rho = (0..self.gst.steps)
            .map(|i| {
                let psi = psi_of(&self.inst.problem, &self.gst, &g, i);
                self.gst
                    .axis_rows(i)
                    .iter()
                    .map(|ax| ax.map_or(0.0, |(l, v)| (psi[l] / v).max(0.0)))
                    .collect()
            })
            .collect();
        g
    }

    /// General multipliers in the crawler's units: `p = K^(-1/2) p~`, `omega`, and `xi = xi~ / s_b`
    /// (the instance's active faces are the crawler's, in the same order: [`structure_of`]).
    fn back(&self, g: GeneralRaw) -> Raw {
        let (p, xi) = self.rescaled(&g.p, &g.xi, |v, s| v / s);
        Raw {
            lambda: g.lambda,
            p,
            xi,
            omega: g.omega,
        }
    }

    /// `p` per link by `sqrt(k_l)` and `xi` per face by `s_b`, each through `by(value, scale)`
    /// (a product one way, a quotient the other).
    fn rescaled(
        &self,
        p: &[Vec<f64>],
        xi: &[Vec<f64>],
        by: impl Fn(f64, f64) -> f64,
    ) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let p = p
            .iter()
            .map(|p| {
                p.iter()
                    .zip(&self.inst.sqrt_k)
                    .map(|(&v, &s)| by(v, s))
                    .collect()
            })
            .collect();
        let xi = self
            .st
            .active
            .iter()
            .zip(xi)
            .map(|(faces, xs)| {
                faces
                    .iter()
                    .zip(xs)
                    .map(|(f, &x)| by(x, self.s_b[f.b]))
                    .collect()
            })
            .collect();
        (p, xi)
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
    }
}
