//! `optimize` on a general problem file, decided here and not in the front ends: which of the
//! [`OptimizeSettings`] apply to a general problem (P) and with which method, the defaults
//! filled in ([`OptimizeSettings::plan_general`]), and one call that runs the plan
//! ([`optimize_general_plan`]). The command line and Python build the same settings struct
//! for both kinds of problem file and only render the answer; messages name the options as
//! the caller spelled them ([`Naming`]).

use super::events::Hooks;
use super::general::optimize_general;
use super::general::GeneralPmSettings;
use super::general_chain::{optimize_general_on_chain, GeneralChainSettings};
use super::general_local::optimize_general_local;
use super::general_phase::{optimize_general_phase, GeneralPhaseSettings};
use super::settings::{GaitMethod, Naming, OptimizeSettings};
use super::GeneralLocalSettings;
use crate::error::{Error, Result};
pub use crate::io::GeneralAnswer;
use crate::io::GeneralFile;

/// What [`OptimizeSettings::plan_general`] decides: the method that runs on a general problem
/// and its settings, defaults filled in.
#[derive(Debug, Clone, PartialEq)]
pub enum GeneralPlan {
    /// P_m globally (`method` auto or discrete).
    Discrete(GeneralPmSettings),
    /// P_m locally.
    Local(GeneralLocalSettings),
    /// Exact gaits of at most `K` phases (where `A = 0`), globally.
    Phase(GeneralPhaseSettings),
    /// The crawler's sequence or chain method, where the problem is a crawler's gait problem
    /// (checked when it runs).
    OnChain(GeneralChainSettings),
}

impl OptimizeSettings {
    /// The plan of `optimize` on a general problem file: the method (`auto` is P_m globally)
    /// and its settings with the defaults filled in, or an error naming the first setting
    /// that does not apply to it (the crawler's own settings: phases grown, patience,
    /// convergence, start gaits, bounds; and those of the other methods). `front_end` lists
    /// a front end's own options that apply to crawler results only, each with whether it was
    /// given; they are refused alike (the command line's `--plot` and `--report` apply to both
    /// kinds of file and are not listed).
    pub fn plan_general(&self, front_end: &[(&str, bool)]) -> Result<GeneralPlan> {
        let n = self.naming;
        let method = self.method;
        if method == GaitMethod::Sequence || method == GaitMethod::Chain {
            return self.plan_on_chain(front_end);
        }
        let local = method == GaitMethod::Local;
        let phase = method == GaitMethod::Phase;
        self.check_fixed_k(phase)?;
        // Every setting of a crawler's optimisation that a general problem does not take, in
        // the order the messages check them (the first one given is named).
        let refused = match n {
            Naming::Flags => self.refused_flags(phase, local, front_end),
            Naming::Keywords => self.refused_keywords(phase, local, front_end),
        };
        if let Some((name, _, reason)) = refused.into_iter().find(|(_, g, _)| *g) {
            let value = if name == "certify" && n == Naming::Keywords && local {
                "true"
            } else {
                "given"
            };
            return Err(Error::invalid(n.setting(name), value, reason));
        }
        Ok(self.general_settings(phase, local))
    }

    /// With `phases` given, the phase method solves one MILP at a fixed K: the growth's
    /// settings have nothing to act on (as for a crawler's problem).
    fn check_fixed_k(&self, phase: bool) -> Result<()> {
        let n = self.naming;
        if phase && self.phases.is_some() {
            for (name, value) in [("patience", self.patience), ("max_phases", self.max_phases)] {
                if let Some(v) = value {
                    return Err(Error::invalid(
                        n.setting(name),
                        v,
                        format!(
                            "applies only to a growth of K, without {}",
                            n.setting("phases")
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The CLI's refusals on a general problem file: `(setting, given, reason)` in the order
    /// they are checked.
    fn refused_flags<'a>(
        &self,
        phase: bool,
        local: bool,
        front_end: &[(&'a str, bool)],
    ) -> Vec<(&'a str, bool, String)> {
        let polish = ("polish", self.polish.is_some());
        let reason = if phase {
            "does not apply to --method phase on a general problem file (--phases, \
             --max-phases, --patience, --time-limit, --certify, --bound on a crawler's \
             problem, --json)"
        } else {
            "does not apply to a general problem file with this method (--certify with \
             the global P_m or phase, --convergence with the global P_m, --shifts with \
             --method local, --bound with --method discrete or phase on a crawler's \
             problem)"
        };
        // The growth's settings name the method they belong to.
        let only_phase = "applies to --method phase only on a general problem file (--phases \
                          and --max-phases also to sequence where the problem is a crawler's)";
        let mut given = vec![
            ("phases", self.phases.is_some() && !phase, only_phase),
            ("patience", self.patience.is_some() && !phase, only_phase),
            if phase {
                ("m", self.m.is_some(), reason)
            } else {
                ("max_phases", self.max_phases.is_some(), only_phase)
            },
            ("convergence", self.convergence && (local || phase), reason),
            (
                "start",
                self.start.is_some() && !local,
                "applies to --method local only on a general problem file",
            ),
            ("shifts", self.shifts.is_some() && !local, reason),
            ("certify", self.certify && local, reason),
            ("no_polish", polish.1 && (local || phase), reason),
            ("bound", self.bound.is_some() && local, reason),
            (
                "formulation",
                self.formulation.is_some() && !phase,
                "applies to --method phase only on a general problem file",
            ),
        ];
        given.extend(front_end.iter().map(|&(name, g)| (name, g, reason)));
        given
            .into_iter()
            .map(|(name, g, why)| (name, g, why.to_string()))
            .collect()
    }

    /// Python's refusals on a general problem: `(setting, given, reason)` in the order they
    /// are checked.
    fn refused_keywords<'a>(
        &self,
        phase: bool,
        local: bool,
        front_end: &[(&'a str, bool)],
    ) -> Vec<(&'a str, bool, String)> {
        let polish = ("polish", self.polish.is_some());
        let discrete = "applies to method=\"discrete\" only (the global P_m optimum)";
        let global = "applies to the global methods (\"discrete\", \"phase\") only";
        let not_general = "does not apply to a general problem";
        let only_phase = "applies to method=\"phase\" only on a general problem";
        let in_phase = "does not apply to method=\"phase\" (phases, max_phases, patience, \
                        time_limit, certify)";
        let mut given = vec![
            ("polish", polish.1 && (local || phase), discrete.to_string()),
            (
                "max_phases",
                self.max_phases.is_some() && !phase,
                "applies to method=\"phase\" only".to_string(),
            ),
            (
                "phases",
                self.phases.is_some() && !phase,
                only_phase.to_string(),
            ),
            (
                "patience",
                self.patience.is_some() && !phase,
                only_phase.to_string(),
            ),
            (
                "formulation",
                self.formulation.is_some() && !phase,
                "applies to method=\"phase\" only on a general problem".to_string(),
            ),
            (
                "convergence",
                self.convergence && (local || phase),
                discrete.to_string(),
            ),
            (
                "start",
                self.start.is_some() && !local,
                "applies to method=\"local\" only on a general problem".to_string(),
            ),
            (
                "bound",
                self.bound.is_some() && local,
                "applies to the global methods on a general problem".to_string(),
            ),
        ];
        if phase {
            given.extend([
                ("m", self.m.is_some(), in_phase.to_string()),
                ("shifts", self.shifts.is_some(), in_phase.to_string()),
            ]);
        } else if local {
            given.push(("certify", self.certify, global.to_string()));
        } else {
            given.push((
                "shifts",
                self.shifts.is_some(),
                "applies to method=\"local\" only".to_string(),
            ));
        }
        given.extend(
            front_end
                .iter()
                .map(|&(name, g)| (name, g, not_general.to_string())),
        );
        given
    }

    /// The settings of the general method planned, each unset one the method's default.
    fn general_settings(&self, phase: bool, local: bool) -> GeneralPlan {
        if phase {
            let d = GeneralPhaseSettings::default();
            GeneralPlan::Phase(GeneralPhaseSettings {
                max_phases: self.max_phases,
                phases: self.phases,
                patience: self.patience.unwrap_or(d.patience),
                time_limit: self.time_limit,
                formulation: self.formulation,
                bound: self.bound,
                certify: self.certify,
            })
        } else if local {
            let d = GeneralLocalSettings::default();
            GeneralPlan::Local(GeneralLocalSettings {
                m: self.m.unwrap_or(d.m),
                shifts: self.shifts.unwrap_or(d.shifts),
                time_limit: self.time_limit,
                start: self.start.clone(),
            })
        } else {
            let d = GeneralPmSettings::default();
            GeneralPlan::Discrete(GeneralPmSettings {
                m: self.m.unwrap_or(d.m),
                time_limit: self.time_limit,
                certify: self.certify,
                convergence: self.convergence,
                bound: self.bound,
                polish: self.polish.unwrap_or(d.polish),
            })
        }
    }
}

impl OptimizeSettings {
    /// [`OptimizeSettings::plan_general`] for the crawler's sequence and chain methods: the
    /// crawler's settings they take pass through (checked by the crawler's job), the others
    /// are refused naming the first one given.
    fn plan_on_chain(&self, front_end: &[(&str, bool)]) -> Result<GeneralPlan> {
        let n = self.naming;
        let polish = match n {
            Naming::Flags => "no_polish",
            Naming::Keywords => "polish",
        };
        let reason = match n {
            Naming::Flags => {
                "does not apply to --method sequence or chain on a general problem file \
                 (--time-limit, --certify, --json; --phases and --max-phases with sequence, as \
                 for crawlers)"
            }
            Naming::Keywords => {
                "does not apply to method=\"sequence\" or \"chain\" on a general problem \
                 (time_limit, certify; phases and max_phases with sequence, as for crawlers)"
            }
        };
        let given = [
            ("m", self.m.is_some()),
            ("convergence", self.convergence),
            ("start", self.start.is_some()),
            ("shifts", self.shifts.is_some()),
            (polish, self.polish.is_some()),
            ("bound", self.bound.is_some()),
            ("formulation", self.formulation.is_some()),
        ];
        if let Some((name, _)) = given.iter().chain(front_end).find(|(_, g)| *g) {
            return Err(Error::invalid(n.setting(name), "given", reason));
        }
        Ok(GeneralPlan::OnChain(GeneralChainSettings {
            crawler: OptimizeSettings {
                method: self.method,
                phases: self.phases,
                max_phases: self.max_phases,
                patience: self.patience,
                time_limit: self.time_limit,
                naming: n,
                ..Default::default()
            },
            certify: self.certify,
        }))
    }
}

/// Runs a [`GeneralPlan`] on a problem file: the method's job with `hooks` (progress and
/// cancellation where the method takes them); errors name the settings as `naming` spells
/// them.
pub fn optimize_general_plan(
    file: &GeneralFile,
    plan: &GeneralPlan,
    naming: Naming,
    hooks: Hooks<'_>,
) -> Result<GeneralAnswer> {
    let named = |e| naming.name_settings(e);
    match plan {
        GeneralPlan::Discrete(s) => optimize_general(file, s, hooks),
        GeneralPlan::Local(s) => optimize_general_local(file, s, hooks),
        GeneralPlan::Phase(s) => optimize_general_phase(file, s, hooks),
        GeneralPlan::OnChain(s) => optimize_general_on_chain(file, s, hooks),
    }
    .map_err(named)
}
