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

use super::general_kkt::{solve_general, GeneralRaw, GeneralStructure};
use super::general_process::{crawler_face_scales, GeneralProcess};
use super::kkt::{Norm, Raw, Stage, Structure};
use super::process::Process;
use crate::error::Result;
use crate::model::general::GeneralCost;
use crate::model::{crawler_as_general, CrawlerInstance};
use crate::optimal::Cost;

/// The crawler process `pr` as (P): its instance, its process there and that process's
/// structure, with the crawler's structure to read the multipliers back into.
pub(crate) struct AsGeneral<'a> {
    inst: CrawlerInstance,
    st: &'a Structure,
    gst: GeneralStructure,
    s_b: Vec<f64>,
}

impl<'a> AsGeneral<'a> {
    /// The instance of `pr`'s crawler and gait problem (cost `f2` unchanged: the control is the
    /// crawler's) and `pr` in its variables, with the structure at the relative tolerance `tol`.
    pub fn of(pr: &Process, st: &'a Structure, tol: f64) -> Result<Self> {
        let cost = match pr.problem.cost {
            Cost::None => GeneralCost::None,
            Cost::Quadratic { weight } => GeneralCost::Quadratic { weight },
        };
        let inst =
            crawler_as_general(&pr.crawler, pr.problem.period, &pr.problem.rate_bound, cost)?;
        let gp = GeneralProcess::of_crawler(pr);
        let s_b = crawler_face_scales(pr.crawler.stiffness());
        let mut gst = GeneralStructure::of(&inst.problem, &gp, tol);
        // The violations in the crawler's units: its slip stationarity <p, K nu_b> + lambda/N is
        // s_b times the unit row's, its xi is xi~ / s_b.
        gst.face_scale = s_b.iter().flat_map(|&s| [s, s]).collect();
        Ok(AsGeneral { s_b, inst, st, gst })
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

    /// General multipliers in the crawler's units: `p = K^(-1/2) p~`, `omega`, and `xi = xi~ / s_b`
    /// on each face the crawler's structure has active (a face active in one structure only
    /// carries no mass: its residuals show it).
    fn back(&self, g: GeneralRaw) -> Raw {
        let p =
            g.p.iter()
                .map(|p| {
                    p.iter()
                        .zip(&self.inst.sqrt_k)
                        .map(|(p, s)| p / s)
                        .collect()
                })
                .collect();
        let xi = self
            .st
            .active
            .iter()
            .enumerate()
            .map(|(j, faces)| {
                faces
                    .iter()
                    .map(|f| {
                        let face = 2 * f.b + usize::from(f.s < 0);
                        self.gst.active[j]
                            .iter()
                            .position(|&g| g == face)
                            .map_or(0.0, |fi| g.xi[j][fi] / self.s_b[f.b])
                    })
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
