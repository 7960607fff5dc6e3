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
use super::general::certify_structured;
use super::general_conditions::GeneralNecessaryConditions;
use super::general_kkt::{GeneralRaw, GeneralStructure};
use super::general_process::GeneralProcess;
use super::general_report::Words;
use super::process::Process;
use super::CertifyOptions;
use crate::error::Result;
use crate::model::CrawlerInstance;
use crate::optimal::units::Units;

/// A face of C: block `b` (0-based) and side `s` (`+1`: `F_b <= mu_b^+`, outer normal `nu_b`;
/// `-1`: `-F_b <= mu_b^-`, outer normal `-nu_b`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FaceId {
    pub b: usize,
    pub s: i8,
}

impl FaceId {
    /// The crawler's face of the instance's face `f` (0-based): `2 b` is block `b`'s side `+`,
    /// `2 b + 1` its side `-`.
    fn of(f: usize) -> Self {
        FaceId {
            b: f / 2,
            s: if f % 2 == 0 { 1 } else { -1 },
        }
    }
}

/// A crawler's multipliers in its own units: `p_j` per piece, `xi` per active face of every
/// knot (the faces in `active`), `omega`, at the given `lambda`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Raw {
    pub lambda: f64,
    pub p: Vec<Vec<f64>>,
    pub active: Vec<Vec<FaceId>>,
    pub xi: Vec<Vec<f64>>,
    pub omega: Vec<f64>,
}

/// The crawler process `pr` as (P): its instance, its process there and that process's
/// structure, in the crawler's units.
pub(crate) struct AsGeneral {
    inst: CrawlerInstance,
    gst: GeneralStructure,
    /// The process on the instance ([`GeneralProcess::of_crawler`]).
    process: GeneralProcess,
    s_b: Vec<f64>,
    /// The switching function as a reason quotes it: `k_max (p + omega)` where `pr` is in units
    /// whose stiffest spring has `k = 1` and the user's did not (`super::crawler_units`).
    switching: &'static str,
}

impl AsGeneral {
    /// The instance of `pr`'s crawler and gait problem (cost `f2` unchanged: the control is the
    /// crawler's), its process there and that process's structure at relative tolerance `tol`
    /// ([`GeneralStructure::of`]: faces relative to the instance's C, reactions `tau lambda =
    /// s_b |D|` to the same scale, rates to their bounds), counted in the crawler's units:
    /// - `face_scale = s_b`: its slip stationarity `<p, K nu_b> + lambda/N` is `s_b` times the
    ///   unit row's, its `xi` is `xi~ / s_b`;
    /// - `state_scale = 1 / sqrt(k_l)` (`B = K^(-1/2)`: the instance's `p~` is `K^(1/2) p`);
    /// - the margin taken on every rate at its bound, as its margin `min |p + omega|` reads;
    /// - the switching function's unit `1 / (N k_max)` (its `p` is `lambda / N` per `K nu_b`
    ///   while block `b` slips), and the margin's cap ten times `1 / (N k_min)`;
    /// - the slacks in units of the instance's C, `psi` in the crawler's own units, `p` in
    ///   units of `1 / k_max` and the Hamiltonian in units of `max_l a_l / k_max`, its value at
    ///   `|p|` of that unit ([`super::general_kkt::ResidualUnits`]).
    ///
    /// `user` is the user's units in `pr`'s (`super::crawler_units`; one each where `pr` is as
    /// the user gave it): its time, the period where `pr` is in periods, is the unit of the
    /// times a reason states, of the weak maximality and of the paper's norm; its force per
    /// length, `k_max`, the factor of the switching function a reason quotes.
    pub fn of(pr: &Process, tol: f64, user: Units) -> Result<Self> {
        let inst = pr.problem.instance(&pr.crawler)?;
        let k = pr.crawler.stiffness();
        let s_b = crate::model::crawler_row_norms(k);
        let process = GeneralProcess::of_crawler(pr);
        let mut gst = GeneralStructure::of(&inst.problem, &process, tol);
        let nb = pr.crawler.blocks() as f64;
        gst.face_scale = s_b.iter().flat_map(|&s| [s, s]).collect();
        gst.state_scale = inst.sqrt_k.iter().map(|s| 1.0 / s).collect();
        gst.margin_off_vertex = true;
        let k_max = k.iter().fold(0.0_f64, |m, &k| m.max(k));
        gst.switching_unit = 1.0 / (nb * k_max);
        gst.margin_cap = 10.0 / (nb * k.iter().fold(f64::INFINITY, |m, &k| m.min(k)));
        // The slacks in the instance's C (forces over `s_b`); `psi` in the crawler's own units,
        // as `state_scale` and `switching_unit` count them. `p` is a length per force, of unit
        // `1 / k_max`, and the Hamiltonian `sum_l a_l |psi_l|` is counted in units of
        // `max_l a_l / k_max` (both 1 for a crawler of unit stiffness and rates): with the
        // Hamiltonian counted in units of one, the three-block optimum's twin in forces times
        // 1e6, time times 1e-6 and lengths times 1e6 failed its duration stationarity at
        // 1.2e-4, the rounding of Hamiltonians of size 1e12, where the crawler in units of
        // one holds it to 4e-15.
        let a_max = pr.problem.rate_bound.iter().fold(0.0_f64, |m, &a| m.max(a));
        gst.units.psi = 1.0;
        gst.units.time = user.time;
        gst.units.p = 1.0 / k_max;
        gst.units.speed = a_max / k_max;
        Ok(AsGeneral {
            s_b,
            inst,
            gst,
            process,
            // `F / L` is `k_max`: `p` is counted in `1 / k_max` where the stiffest spring is
            // not 1.
            switching: if user.force != user.length {
                "k_max (p + omega)"
            } else {
                "p + omega"
            },
        })
    }

    /// The one certificate ([`certify_structured`]) of the process on its instance, in the
    /// crawler's units and words ([`crawler_words`]): (P)'s report, and the multipliers it
    /// states read back in the crawler's names ([`Self::back`]).
    pub fn certify(&self, opts: &CertifyOptions) -> Result<(GeneralNecessaryConditions, Raw)> {
        let words = Words {
            switching: self.switching,
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

    /// General multipliers in the crawler's units: `p = K^(-1/2) p~`, `omega`, and
    /// `xi = xi~ / s_b` on the crawler's faces ([`FaceId::of`]).
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
        let active: Vec<Vec<FaceId>> = self
            .gst
            .active
            .iter()
            .map(|a| a.iter().map(|&f| FaceId::of(f)).collect())
            .collect();
        let xi = active
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
            active,
            xi,
            omega: g.omega,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::general_conditions::residuals;
    use super::super::general_kkt::psi_of;
    use super::super::process::INPUT_TOL;
    use super::*;
    use crate::model::general::GeneralProblem;
    use crate::optimal::{solve_discrete_global, Cost, GaitProblem, GaitResult};
    use crate::Crawler;

    /// The duals HiGHS returns for the branch LP on the crawler's instance
    /// ([`super::super::branch::branch_lp`]) satisfy the KKT system the certificate solves for
    /// (the independent check of the derivation and its signs), at the global optimum of P_m,
    /// every residual counted in the crawler's units. Each branch through the biactive pairs
    /// (faces active without a reaction) holds the process and lies in P_m, so at a global
    /// optimum its LP's optimum is J (asserted). On one of them the duals must satisfy every
    /// condition, the sign at the biactive pairs included: strong stationarity, which the
    /// certificate's branch search looks for and which global optimality alone does not imply;
    /// it holds at these optima (the test's own claim, checked here).
    #[test]
    fn branch_lp_duals_satisfy_the_kkt_system() {
        for (nb, mm, m) in [(2, 2.0, 3), (3, 1.5, 3)] {
            let c = Crawler::uniform(nb, 1.0, 1.0, mm).unwrap();
            let pb = GaitProblem::new(&c, 10.0, &vec![1.0; nb - 1], Cost::None, None).unwrap();
            let s = solve_discrete_global(&c, &pb, m).unwrap();
            let r = GaitResult::from_discrete(&c, &pb, &s);
            let pr = Process::from_result(&r, "test").unwrap();
            let general = AsGeneral::of(&pr, INPUT_TOL, Units::ONE).unwrap();
            let (p, gst) = (&general.inst.problem, &general.gst);
            let biactive = gst.reacting.iter().flatten().filter(|f| !f.1).count();
            assert!(biactive <= 12, "N = {nb}: {biactive} biactive pairs");
            let mut best: Option<(f64, Vec<(&str, f64)>)> = None;
            for bits in 0..1usize << biactive {
                let choice: Vec<bool> = (0..biactive).map(|k| bits >> k & 1 == 1).collect();
                let (opt, raw) = super::super::branch::branch_lp(p, gst, &choice)
                    .unwrap_or_else(|| panic!("N = {nb}: branch {bits} has no optimum"));
                assert!(
                    (opt - r.head.objective).abs() < 1e-9,
                    "N = {nb}: branch {bits}: {opt} vs {}",
                    r.head.objective
                );
                let res = kkt_residuals(p, gst, raw);
                let worst = res
                    .iter()
                    .filter(|(name, _)| *name != "sign")
                    .fold(0.0_f64, |w, (_, v)| w.max(*v));
                if best.as_ref().is_none_or(|(b, _)| worst < *b) {
                    best = Some((worst, res));
                }
            }
            let (worst, res) = best.expect("one branch at least");
            for (name, v) in res {
                println!("N = {nb}: {name} {v:.3e}");
            }
            assert!(
                worst < 1e-9,
                "N = {nb}: no branch satisfies the KKT system ({worst:.3e})"
            );
        }
    }

    /// The residuals of the branch LP's duals `raw`, each rate at its bound weighted by psi
    /// (every active row of the box is an axis row).
    fn kkt_residuals(
        p: &GeneralProblem,
        gst: &GeneralStructure,
        mut raw: GeneralRaw,
    ) -> Vec<(&'static str, f64)> {
        raw.rho = (0..gst.steps)
            .map(|i| {
                let psi = psi_of(p, gst, &raw, i);
                let axis = gst.axis_rows(i);
                axis.iter()
                    .map(|ax| ax.map_or(0.0, |(l, v)| (psi[l] / v).max(0.0)))
                    .collect()
            })
            .collect();
        residuals(p, gst, &raw, true, false)
            .into_iter()
            .map(|(name, _, v)| (name, v))
            .collect()
    }
}
