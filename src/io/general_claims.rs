//! The claims of a general result read back ([`super::general_consistency`] checks the gait
//! itself first): the envelope's claim by the one check of both kinds of result
//! ([`check_claim`]: kind, bound and gap against `J`, a claim over `K` phases against the gait),
//! and what only a general record states: the status and bound against the solution's
//! certificate, `dominates_k_phases` only for the chain's kept structured start, a
//! free-transition gait within its slots, a local answer's record, the tables of `K` and of
//! `m`, and an upper bound only on a chain. A claim that does not follow is refused naming its
//! field.

use super::GeneralAnswer;
use crate::error::{Error, Result};
use crate::model::general::GeneralProblem;
use crate::optimal::consistency::{check_claim, Claim, INPUT_TOL};
use crate::optimal::general::GeneralPhaseGait;
use crate::optimal::{Certificate, MilpStatus, ResultCertificate, ResultRecords};

/// An error naming `field` of the result `what`.
pub(super) fn bad(what: &str, field: &str, got: impl ToString, reason: impl Into<String>) -> Error {
    Error::invalid(format!("{what}: {field}"), got, reason)
}

/// The phases of a free-transition answer fit its `K` slots: each phase that holds a face takes
/// a slot, with at most one free phase before it; a free phase not followed by one that holds
/// a face takes a slot of its own (the fewest slots, counted greedily in time order).
pub(super) fn check_slots(s: &GeneralPhaseGait, what: &str) -> Result<()> {
    let mut slots = 0;
    let mut j = 0;
    while j < s.held.len() {
        slots += 1;
        // A free phase is a slot's transition, and the next phase (of any kind) its phase.
        j += if s.held[j].is_empty() { 2 } else { 1 };
    }
    if slots > s.max_phases {
        return Err(bad(
            what,
            "solution.held",
            format!("{slots} slots"),
            format!(
                "the gait needs {slots} slots of a free transition and a phase; the formulation \
                 \"transitions\" claims {} (solution.max_phases)",
                s.max_phases
            ),
        ));
    }
    Ok(())
}

/// A claim that the gait beats every gait of at most `K` phases without being one
/// (`dominates_k_phases`, its class and gap are [`check_claim`]'s): only the chain's
/// formulation makes it, keeping its structured start (`structured`) when that start is
/// outside the class.
pub(super) fn check_dominates(r: &GeneralAnswer, chain: bool, what: &str) -> Result<()> {
    let reason = if !chain {
        "is claimed only by the chain's formulation (formulation \"chain\")"
    } else if r.records.structured.is_none() {
        "is claimed only for the chain's structured start, recorded as `structured`"
    } else {
        return Ok(());
    };
    Err(bad(what, "status", r.head.status.as_str(), reason))
}

/// The closeness of two objectives of a general result whose replayed `J` is `j`: relative
/// [`INPUT_TOL`] of `J`, below the problem's floor of `J` (`floor`,
/// [`GeneralProblem::j_floor`]) in units of it. The one tolerance of a claim against `J`, for
/// global and local answers alike.
fn close_to_j(j: f64, floor: f64) -> impl Fn(f64, f64) -> bool {
    let tol = INPUT_TOL * j.abs().max(floor);
    move |a, b| (a - b).abs() <= tol
}

/// A local answer's certificate (P_m's local method, the crawler's on a chain): `local`,
/// without bound, gap or phases; the chain's upper bound over all periodic gaits may be
/// recorded with it, checked as a global answer's is: only on a chain
/// ([`check_upper_bound`]), and not below the replayed `j`.
pub(super) fn check_local_claim(
    what: &str,
    p: &GeneralProblem,
    cert: &ResultCertificate,
    j: f64,
) -> Result<()> {
    let mut own = cert.clone();
    if let Some(ub) = own.upper_bound.take() {
        check_upper_bound(what, p, cert)?;
        ub.check_recorded(what, j, close_to_j(j, p.j_floor()))?;
    }
    check_local_certificate(what, &own)
}

/// A local answer's certificate without its upper bound ([`check_local_claim`] takes it
/// apart): `local`, without bound, gap or phases.
fn check_local_certificate(what: &str, cert: &ResultCertificate) -> Result<()> {
    let why = "a local answer's certificate is \"local\", without bound, gap or phases";
    if cert.kind != "local" {
        return Err(bad(what, "certificate.kind", &cert.kind, why));
    }
    let extra = [
        ("certificate.bound", cert.bound.map(|v| v.to_string())),
        ("certificate.gap", cert.gap.map(|v| v.to_string())),
        ("certificate.phases", cert.phases.map(|k| k.to_string())),
    ];
    if let Some((field, Some(v))) = extra.into_iter().find(|(_, v)| v.is_some()) {
        return Err(bad(what, field, v, why));
    }
    debug_assert_eq!(*cert, ResultCertificate::local(None));
    Ok(())
}

/// The claims of a local method's phase gait on a chain (`sequence`, `chain`) whose replayed
/// `J` is `j`: a local status (`stationary`, `stalled`, `time_limit`) that is the solution's,
/// the certificate `local` without bound or gap but perhaps the chain's upper bound
/// ([`check_local_claim`]), no bound in the solution and no growth table.
pub(super) fn check_local_phase(
    what: &str,
    r: &GeneralAnswer,
    s: &GeneralPhaseGait,
    p: &GeneralProblem,
    j: f64,
) -> Result<()> {
    let allowed = [
        MilpStatus::Stationary,
        MilpStatus::Stalled,
        MilpStatus::TimeLimit,
    ];
    if r.head.status != s.certificate.status || !allowed.contains(&r.head.status) {
        return Err(bad(
            what,
            "status",
            r.head.status.as_str(),
            format!(
                "must be one of stationary, stalled, time_limit (a local method), and \
                 solution.certificate.status ({}) where a version 2 file repeats it",
                s.certificate.status.as_str()
            ),
        ));
    }
    check_local_claim(what, p, &r.head.certificate, j)?;
    if !(s.certificate.bound.is_nan() && s.certificate.gap.is_nan()) {
        return Err(bad(
            what,
            "certificate.bound",
            s.certificate.bound,
            "a local method proves no bound (null)",
        ));
    }
    if r.records.phase_growth.is_some() {
        return Err(bad(
            what,
            "phase_growth",
            "a table",
            "a local method grows no K",
        ));
    }
    Ok(())
}

/// [`crate::optimal::consistency::check_records`] with a general reader's equality of
/// objectives (relative [`INPUT_TOL`], below the problem's floor of `J` `floor` in units of it).
pub(super) fn check_records(
    what: &str,
    records: &ResultRecords,
    phases: Option<usize>,
    m: Option<usize>,
    j: f64,
    floor: f64,
) -> Result<()> {
    let close = |a: f64, b: f64| (a - b).abs() <= INPUT_TOL * a.abs().max(b.abs()).max(floor);
    crate::optimal::consistency::check_records(what, records, phases, m, j, close)
}

/// An upper bound recorded with an answer of any method: only for a problem that is a
/// crawler's gait problem, whose bound it is. Its value against `J` is checked apart (a global
/// answer's by [`check_claim`], a local one's by [`check_local_claim`]), taken as recorded, as
/// for crawlers: its LP is not re-solved.
fn check_upper_bound(what: &str, p: &GeneralProblem, cert: &ResultCertificate) -> Result<()> {
    match &cert.upper_bound {
        Some(ub) if p.as_chain().is_none() => Err(bad(
            what,
            "certificate.upper_bound",
            ub.value,
            "a general problem carries the crawler's upper bound only when it is a crawler's \
             gait problem",
        )),
        _ => Ok(()),
    }
}

/// The envelope's status and certificate of a MILP's answer against the solution's
/// certificate and its replayed objective `j`: the status one the method may have and the
/// solution's; the claim itself ([`check_claim`]: the kind and `K` the MILP's, its bound and gap
/// against `j`, a phase claim against the gait's `phases` (`K` and the phases that hold a face));
/// the MILP's incumbent under its bound; the envelope's bound and gap the solution's.
/// An upper bound recorded only where `p` is a chain ([`check_upper_bound`]). `(p, j)` is the
/// problem and the replayed `J`; gaps are stated and numbers compared over the problem's floor
/// of `J` ([`GeneralProblem::j_floor`]).
pub(super) fn check_global(
    what: &str,
    method: &str,
    status: MilpStatus,
    cert: &ResultCertificate,
    c: &Certificate,
    phases: Option<(usize, usize)>,
    (p, j): (&GeneralProblem, f64),
) -> Result<()> {
    check_upper_bound(what, p, cert)?;
    let floor = p.j_floor();
    let allowed: &[MilpStatus] = match phases {
        None => &[
            MilpStatus::Optimal,
            MilpStatus::TimeLimit,
            MilpStatus::ApproximationLimit,
        ],
        Some(_) => &[
            MilpStatus::OptimalAmongKPhases,
            MilpStatus::DominatesKPhases,
            MilpStatus::TimeLimit,
            MilpStatus::ApproximationLimit,
        ],
    };
    if c.status != status || !allowed.contains(&status) {
        return Err(bad(
            what,
            "status",
            status.as_str(),
            format!(
                "must be one of {:?}, and solution.certificate.status ({}) where a version 2 \
                 file repeats it",
                allowed.iter().map(|s| s.as_str()).collect::<Vec<_>>(),
                c.status.as_str()
            ),
        ));
    }
    let want = ResultCertificate::of_milp(c, phases.map(|(k, _)| k));
    if cert.phases != want.phases {
        return Err(bad(
            what,
            "certificate.phases",
            format!("{:?}", cert.phases),
            format!("must be {:?}", want.phases),
        ));
    }
    let claim = Claim {
        status,
        certificate: cert,
        bound: Some(c.bound),
        gap: Some(c.gap),
        record: "certificate",
        objective: j,
        method,
        kinds: &[want.kind.as_str()],
        phases: (phases.map_or(0, |(_, held)| held), "phases holding a face"),
        j_floor: floor,
    };
    check_claim(what, &claim, close_to_j(j, floor))?;
    // The MILP's incumbent lies under its own bound.
    if !(c.milp_objective.is_finite()
        && c.milp_objective <= c.bound + INPUT_TOL * c.bound.abs().max(floor))
    {
        return Err(bad(
            what,
            "solver_objective",
            c.milp_objective,
            format!("must be finite and at most the bound ({})", c.bound),
        ));
    }
    for (field, got, want) in [
        ("certificate.bound", cert.bound, c.bound),
        ("certificate.gap", cert.gap, c.gap),
    ] {
        if got != Some(want) {
            return Err(bad(
                what,
                field,
                format!("{got:?}"),
                format!("must be the solution's ({want})"),
            ));
        }
    }
    Ok(())
}
