//! A given start of (P)'s local method and of its global P_m: a general result read and
//! checked, its control averaged on the grid of `2^m` steps (one start reader for both).

use crate::error::{Error, Result};
use crate::model::general::GeneralProblem;
use crate::optimal::general::phase_grid;

/// A given start on `2^m` steps: a general result (read and checked as `certify` reads it, for
/// a file) of the same numbers of states and controls and the same period as `p`, its control
/// averaged over each step and moved to an exact zero mean within U where `p` asks it
/// ([`phase_grid`]); a crawler's gait result, a result of another shape, or one whose control
/// leaves this problem's U (a result of a problem with a larger U), is refused naming `start`.
/// Returns the grid's controls and where they came from, named as a crawler's given start is
/// ([`crate::optimal::StartGait::from_result`]): the start's method, then its name
/// (`"local (start.json)"`).
pub(super) fn given_start(
    start: &super::Start,
    p: &GeneralProblem,
    m: u32,
) -> Result<(Vec<Vec<f64>>, String)> {
    let refuse = |name: &str, why: String| Err(Error::invalid("start", name, why));
    let (answer, name) = match start.read()? {
        (crate::io::ResultFile::General(answer), name) => (answer, name),
        (crate::io::ResultFile::Crawler(_), name) => {
            return refuse(
                &name,
                "is a crawler's gait result; a general problem starts from a general result".into(),
            )
        }
    };
    let q = answer.problem.problem()?;
    if (q.states(), q.controls()) != (p.states(), p.controls()) || q.period != p.period {
        return refuse(
            &name,
            format!(
                "is a result of a problem with {} states, {} controls and period {}; this one \
                 has {}, {} and {}",
                q.states(),
                q.controls(),
                q.period,
                p.states(),
                p.controls(),
                p.period
            ),
        );
    }
    let (durations, controls) = answer.pieces();
    let field = "solution.controls";
    // Each component to its own bound, as a result is read back.
    let scales = crate::optimal::process::control_scales(&p.control);
    let tol = crate::optimal::consistency::INPUT_TOL;
    let inside = |u: &[f64]| crate::optimal::process::in_u(&p.control, &scales, u, tol);
    if let Some((j, u)) = controls.iter().enumerate().find(|(_, u)| !inside(u)) {
        return refuse(
            &name,
            format!("its control {field}[{j}] = {u:?} lies outside this problem's U"),
        );
    }
    let origin = format!("{} ({name})", answer.head.method);
    Ok((phase_grid(p, &durations, controls, m)?, origin))
}
