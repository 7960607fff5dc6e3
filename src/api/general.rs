//! The general problem (P) (theory §11) as jobs: a problem file analysed (C's geometry and every
//! check of the problem) and simulated for a given control.

use crate::certify::bound::BoundSettings;
use crate::error::{Error, Result};
use crate::integrate::{simulate_general_on as integrate_general, GeneralSimOptions, SimOptions};
pub use crate::io::{Check, CheckStatus, GeneralAnalysis, GeneralSimulated};
use crate::io::{GeneralAnswer, GeneralFile};
use crate::model::general::{Boundary, ControlSet, GeneralProblem, Reward};
use crate::model::ChainView;
use crate::optimal::general::{analyze_polyhedron, check_with, Geometry};

/// The problem of a file with every check: those of [`GeneralFile::problem`] and those that
/// need C's geometry ([`crate::optimal::general::check_problem`]). Returns C's geometry too.
pub fn general_problem(file: &GeneralFile) -> Result<(GeneralProblem, Geometry)> {
    let p = file.problem()?;
    let g = geometry_of(&p)?;
    check_with(&p, &g)?;
    Ok((p, g))
}

/// What `bound` and `certify` add to an answer of `p`, the same for every method on (P) and
/// after its time limit: the chain's upper bound over all periodic gaits (`bound`: the chain
/// the settings were checked against, [`check_additions`], and the bound's settings), then the
/// necessary conditions on its process ([`attach_conditions`]), each announced as a stage.
pub(super) fn add_bound_and_conditions(
    p: &GeneralProblem,
    r: &mut GeneralAnswer,
    bound: Option<(&ChainView, &BoundSettings)>,
    certify: bool,
    em: &super::events::Emitter<'_>,
) -> Result<()> {
    if let Some((view, b)) = bound {
        em.stage("proving an upper bound over all periodic gaits (the chain's)");
        r.head.certificate.upper_bound = Some(chain_upper_bound(p, view, b, r.head.objective)?);
    }
    if certify {
        em.stage("checking the necessary conditions (Theorem 2.2)");
        attach_conditions(p, r)?;
    }
    Ok(())
}

/// Attaches to an answer of `p` (of any method) the necessary conditions of Theorem 2.2 on its
/// process ([`crate::certify::certify_general`]; discrete form Theorems 6.1–6.2): what
/// `--certify` adds to every method on (P), as `crawlopt certify` does to its result file.
fn attach_conditions(p: &GeneralProblem, r: &mut GeneralAnswer) -> Result<()> {
    let pr = r.solution.process(p);
    r.necessary_conditions = Some(crate::certify::certify_general(
        p,
        &pr,
        &crate::certify::CertifyOptions::default(),
    )?);
    Ok(())
}

/// C's geometry; an empty C is an error naming `sweeping_process`.
fn geometry_of(p: &GeneralProblem) -> Result<Geometry> {
    analyze_polyhedron(&p.c).map_err(|e| match e {
        Error::Infeasible(_) => Error::invalid(
            "sweeping_process",
            format!("{} faces", p.c.faces()),
            "C is empty: no x satisfies every face",
        ),
        other => other,
    })
}

/// Analyses a problem file: C's faces, redundant faces, vertices, Chebyshev centre, and the
/// checks. Errors only where no analysis can be made (a malformed file, an empty C); a
/// failed check is reported in the answer and as [`GeneralAnalysis::failure`].
pub fn analyze_general(file: &GeneralFile) -> Result<GeneralAnalysis> {
    let p = file.problem()?;
    let g = geometry_of(&p)?;
    let failure = check_with(&p, &g).err();
    let mut checks = Vec::new();
    sets_checks(&p, &g, failure.as_ref(), &mut checks);
    face_weights_check(&p, &g, &mut checks);
    structure_checks(&p, &mut checks);
    Ok(GeneralAnalysis {
        kind: "general",
        problem: p,
        geometry: g,
        checks,
        failure,
    })
}

/// The checks of C (interior, boundedness) and of U (convex, with an interior), given the
/// failure of the problem's own check, if any.
fn sets_checks(p: &GeneralProblem, g: &Geometry, failure: Option<&Error>, checks: &mut Vec<Check>) {
    let mut add = |name: &str, status, detail: String| {
        checks.push(Check {
            name: name.into(),
            status,
            detail,
        })
    };
    let interior = g.has_interior(p.c.scale());
    add(
        "C has a non-empty interior (PLICQ)",
        if interior {
            CheckStatus::Pass
        } else {
            CheckStatus::Fail
        },
        format!(
            "Chebyshev radius {}{}",
            g.chebyshev_radius,
            if g.radius_capped { " or more" } else { "" }
        ),
    );
    add(
        "C is bounded",
        CheckStatus::Info,
        if g.bounded {
            "yes".into()
        } else {
            "no (P_m's global method needs a bounded C)".into()
        },
    );
    let u = match &p.control {
        ControlSet::Box { .. } => "a box".to_string(),
        ControlSet::Polytope(u) => format!("a polytope of {} faces", u.faces()),
    };
    let u_failed =
        matches!(failure, Some(Error::InvalidParameter { field, .. }) if field == "control");
    add(
        "U is convex with a non-empty interior",
        if u_failed {
            CheckStatus::Fail
        } else {
            CheckStatus::Pass
        },
        if p.zero_mean {
            format!("{u}, 0 in its interior (zero_mean)")
        } else {
            u
        },
    );
}

/// Whether the face weights of `f1` are well defined: at every vertex of C (or, on a chain
/// too long to enumerate them, by the chain's uniqueness condition, paper eq. 3.6).
fn face_weights_check(p: &GeneralProblem, g: &Geometry, checks: &mut Vec<Check>) {
    let mut add = |name: &str, status, detail: String| {
        checks.push(Check {
            name: name.into(),
            status,
            detail,
        })
    };
    let (status, detail) = match &p.reward {
        Reward::ReactionWeights(_) => (CheckStatus::Info, "not needed: f1 = <q, eta>".into()),
        Reward::FaceWeights(_) => {
            let (status, detail) = match (&g.vertices, g.degenerate_vertex, p.as_chain()) {
                (None, _, Some(view)) => match view.check_face_weights() {
                    Ok(()) => (
                        CheckStatus::Pass,
                        format!(
                            "a chain of {} blocks whose uniqueness condition holds (paper eq. \
                             3.6): at most N - 1 blocks at a threshold at once, their normals \
                             independent (vertices not enumerated)",
                            view.crawler.blocks()
                        ),
                    ),
                    Err(e) => (CheckStatus::Fail, e.to_string()),
                },
                (None, _, None) => (CheckStatus::Fail, "vertices not enumerated".to_string()),
                (Some(vs), Some(k), _) => (
                    CheckStatus::Fail,
                    format!(
                        "vertex {k} = {:?}: active faces {:?} have dependent normals",
                        vs[k - 1].point,
                        vs[k - 1].active
                    ),
                ),
                (Some(vs), None, _) => (
                    CheckStatus::Pass,
                    format!(
                        "active normals independent at all {} {}",
                        vs.len(),
                        if g.rank == g.dim {
                            "vertices"
                        } else {
                            "minimal faces"
                        }
                    ),
                ),
            };
            (status, detail)
        }
    };
    add("face weights well defined", status, detail);
}

/// The dynamics (`A = 0` or a drift) and the structure recognised (a crawler's chain).
fn structure_checks(p: &GeneralProblem, checks: &mut Vec<Check>) {
    let mut add = |name: &str, status, detail: String| {
        checks.push(Check {
            name: name.into(),
            status,
            detail,
        })
    };
    add(
        "dynamics",
        CheckStatus::Info,
        if p.dynamics.is_state_independent() {
            "A = 0: piecewise-linear motion under piecewise-constant controls".into()
        } else {
            "A != 0: state-dependent drift".into()
        },
    );
    add(
        "structure",
        CheckStatus::Info,
        match p.as_chain() {
            Some(v) => format!(
                "a chain: the gait problem of a crawler of {} blocks (stiffness {:?}, mu+ {:?}, \
                 mu- {:?}, rate bounds {:?}; J = {} times its displacement{}): {}",
                v.crawler.blocks(),
                v.crawler.stiffness(),
                v.crawler.mu_forward(),
                v.crawler.mu_backward(),
                v.rate_bounds,
                v.objective_scale,
                v.cost_weight
                    .map_or(String::new(), |c| format!(" less (c/2)|u|^2, c = {c}")),
                bound_applies(&v)
            ),
            None => "no chain recognised (not a crawler's gait problem)".into(),
        },
    );
}

/// Whether the chain's upper bound applies to the crawler `v` is, as `--bound` decides it
/// ([`BoundSettings::grid`]: at most four blocks, the uniqueness condition), in words.
fn bound_applies(v: &ChainView) -> String {
    match BoundSettings::default().grid(&v.crawler) {
        Ok(_) => "the chain's upper bound applies (--bound)".into(),
        Err(Error::InvalidParameter { reason, .. }) => {
            format!("the chain's upper bound does not apply ({reason})")
        }
        Err(e) => format!("the chain's upper bound does not apply ({e})"),
    }
}

/// Simulates the file's `[input]`: exactly where `A = 0` and the input is piecewise constant
/// ([`crate::integrate::general_exact`], unless `opts.method` asks for catching-up), else by
/// catching-up ([`crate::integrate::general`], the damping of `A` stepped implicitly): for a
/// periodic problem until the periodic regime, with `J` of one period on the orbit; for a Cauchy
/// problem over `[0, T]` from `x(0)`. On a crawler's chain
/// ([`GeneralProblem::as_chain`](crate::model::general::GeneralProblem::as_chain)) under a
/// zero-mean piecewise-constant input, the periodic regime is searched by the crawler's simulator
/// with the same scheme ([`crate::integrate::chain_regime`](mod@crate::integrate::chain_regime):
/// the chain's O(N) kernels and Newton steps, where the general period map is iterated plainly) and
/// the general simulator plays the period from the state it found, checking that it repeats
/// (`regime_search = "chain"`); its catching-up steps project with the chain's O(N) method too
/// (`simulation.projection = "chain"`, [`crate::sweep::OntoC`]), the exact method's tangent cones
/// with the dense one.
pub fn simulate_general(file: &GeneralFile, opts: &GeneralSimOptions) -> Result<GeneralSimulated> {
    simulate_general_problem(file, opts).map(|(_, s)| s)
}

/// [`simulate_general`] with the problem it built (for the figures of the simulation).
pub(super) fn simulate_general_problem(
    file: &GeneralFile,
    opts: &GeneralSimOptions,
) -> Result<(GeneralProblem, GeneralSimulated)> {
    let (p, g) = general_problem(file)?;
    let input = file.input(&p)?;
    opts.check(p.states() + p.controls() + p.c.faces())?;
    let (start, start_from) = match &p.boundary {
        Boundary::Initial(x0) => (x0.clone(), "initial_state"),
        Boundary::Periodic => {
            let origin = vec![0.0; p.states()];
            if p.c.violation(&origin, 0.0).is_none() {
                (origin, "origin")
            } else {
                (g.chebyshev_centre.clone(), "chebyshev_centre")
            }
        }
    };
    let exact = opts.method == crate::integrate::GeneralMethod::Auto
        && p.dynamics.is_state_independent()
        && input.kind == crate::integrate::InputKind::PiecewiseConstant;
    // A chain's periodic regime is searched by the crawler's simulator (its O(N) kernels and
    // Newton steps, with the same scheme); the general simulator then plays the period from the
    // state found.
    let catching_up = (!exact).then_some(opts.steps_per_period);
    let chain = p.as_chain();
    let regime = match &chain {
        Some(view) if start_from == "origin" => crate::integrate::chain_regime(
            &p,
            view,
            &input,
            catching_up,
            opts.max_periods,
            opts.tol,
        )?,
        _ => None,
    };
    // The crawler's state is taken when the general simulator confirms it within a few
    // periods (a tolerance below the crawler's reach is not); else the plain search.
    let confirmed = match &regime {
        Some(r) => {
            let budget = crate::integrate::chain_regime::REPLAY_PERIODS.min(opts.max_periods);
            let s = if exact {
                crate::integrate::simulate_general_exact(&p, &input, &r.state, budget, opts.tol)?
            } else {
                let replay = GeneralSimOptions {
                    max_periods: budget,
                    ..opts.clone()
                };
                integrate_general(&p, chain.as_ref(), &input, &r.state, &replay)?
            };
            s.converged.then(|| crate::integrate::GeneralSimulation {
                periods: s.periods + r.periods,
                ..s
            })
        }
        None => None,
    };
    let searched_on_chain = confirmed.is_some();
    let simulation = match (confirmed, exact) {
        (Some(s), _) => s,
        (None, true) => crate::integrate::simulate_general_exact(
            &p,
            &input,
            &start,
            opts.max_periods,
            opts.tol,
        )?,
        (None, false) => integrate_general(&p, chain.as_ref(), &input, &start, opts)?,
    };
    let simulated = GeneralSimulated {
        kind: "general",
        method: if exact { "exact" } else { "catching-up" },
        steps_per_period: opts.steps_per_period,
        start,
        start_from,
        regime_search: if searched_on_chain { "chain" } else { "plain" },
        objective: simulation.objective,
        input,
        simulation,
    };
    Ok((p, simulated))
}

/// The options of a simulation of a general problem from those a front end builds for either
/// kind of problem file (the crawler's [`SimOptions`]): `method` (exact: the exact method where
/// it applies, else catching-up), `steps_per_period`, `max_periods` and `tol` carry over, and
/// the search without acceleration (`accelerate_after: None`) is the general simulator's own.
/// Refused, naming the field: `record_periods` other than 1 (the simulation of a general
/// problem records one period of its periodic regime, or a Cauchy problem's horizon `[0, T]`:
/// its CSV, JSON and figures show that period) and a search without Newton steps (`newton:
/// None`: the general simulator iterates the period map plainly, with no Newton-Krylov or
/// Anderson acceleration to choose between), an acceleration switched off or moved
/// (`accelerate_after` other than the default: there is none to switch), and an increment
/// budget other than the default (the general simulator keeps no table of increments).
pub fn general_sim_options(o: &SimOptions) -> Result<GeneralSimOptions> {
    if o.record_periods != 1 {
        return Err(Error::invalid(
            "periods",
            o.record_periods,
            "a general problem's simulation records one period of its periodic regime (a \
             Cauchy problem's horizon [0, T]); its CSV, JSON and figures show that period",
        ));
    }
    if o.newton.is_none() {
        return Err(Error::invalid(
            "newton",
            "off",
            "the general simulator iterates the period map plainly (no Newton-Krylov or \
             Anderson acceleration), so there are no Newton steps to leave out",
        ));
    }
    if o.accelerate_after != SimOptions::DEFAULT.accelerate_after {
        return Err(Error::invalid(
            "accelerate_after",
            o.accelerate_after
                .map_or_else(|| "off".to_string(), |k| k.to_string()),
            "the general simulator iterates the period map plainly, with no acceleration to \
             start later or switch off",
        ));
    }
    if o.increment_budget != SimOptions::DEFAULT.increment_budget {
        return Err(Error::invalid(
            "increment_budget",
            o.increment_budget,
            "the general simulator keeps no table of the period's increments, so there is no \
             budget to set",
        ));
    }
    Ok(GeneralSimOptions {
        method: o.method.into(),
        steps_per_period: o.steps_per_period,
        max_periods: o.max_periods,
        tol: o.tol,
        ..GeneralSimOptions::DEFAULT
    })
}

/// What [`add_bound_and_conditions`] will add to an answer of `p`, checked before any work:
/// the bound ([`chain_for_bound`]: the chain it is proved on, returned), then the necessary
/// conditions, which are stated for periodic problems only (`certify` on a Cauchy problem is
/// refused naming `certify`, rather than after the method has run).
pub(super) fn check_additions(
    p: &GeneralProblem,
    bound: Option<&BoundSettings>,
    certify: bool,
) -> Result<Option<ChainView>> {
    let chain = chain_for_bound(p, bound)?;
    if certify && p.boundary != Boundary::Periodic {
        return Err(Error::invalid(
            "certify",
            true,
            "the necessary conditions are certified for periodic problems only (this is a \
             Cauchy problem from its initial state: periodic = false)",
        ));
    }
    Ok(chain)
}

/// The problem's chain when a bound is asked ([`GeneralProblem::as_chain`]), checked before
/// any work: a bound asked of a problem that is not a crawler's gait problem is refused naming
/// `bound`, and the bound's settings, its crawler (at most four blocks) and its grid's size as
/// [`crate::certify::bound::check_upper_bound`] checks them.
fn chain_for_bound(p: &GeneralProblem, bound: Option<&BoundSettings>) -> Result<Option<ChainView>> {
    let Some(b) = bound else {
        return Ok(None);
    };
    let view = p.as_chain().ok_or_else(|| {
        Error::invalid(
            "bound",
            "given",
            "the upper bound is the crawler's (a storage function over C): it applies to a \
             general problem only when it is a crawler's gait problem (a chain: A = 0, b = 0, \
             B diagonal, a symmetric box U with zero mean, two faces per block, the \
             barycentre's displacement as f1; see `analyze`)",
        )
    })?;
    // The crawler's fields are not the file's: a refusal of the chain itself names `bound`.
    let gp = crate::optimal::general::chain_gait_problem(p, &view)?;
    crate::certify::bound::check_upper_bound(&view.crawler, &gp, b).map_err(|e| match e {
        Error::InvalidParameter {
            field,
            value,
            reason,
        } if field.starts_with("crawler.") => Error::invalid(
            "bound",
            format!("the problem's chain, whose {field} is {value}"),
            reason,
        ),
        other => other,
    })?;
    Ok(Some(view))
}

/// The crawler's upper bound over all periodic gaits ([`crate::certify::bound`]) for a
/// general problem recognised as that crawler's gait problem, in the problem's units (`lambda`
/// times the crawler's); an error if it is below the verified `j` (a defect of the bound).
pub(super) fn chain_upper_bound(
    p: &GeneralProblem,
    view: &ChainView,
    b: &BoundSettings,
    j: f64,
) -> Result<crate::optimal::bound_record::UpperBound> {
    let gp = crate::optimal::general::chain_gait_problem(p, view)?;
    let mut ub = crate::certify::bound::upper_bound(&view.crawler, &gp, b)?;
    ub.value *= view.objective_scale;
    ub.check_bounds(j, p.j_floor())?;
    Ok(ub)
}
