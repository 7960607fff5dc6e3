//! `optimize` on a general problem file, decided here and not in the front ends: which of the
//! [`OptimizeSettings`] apply to a general problem (P) and with which method, the defaults
//! filled in ([`OptimizeSettings::plan_general`]), and one call that runs the plan
//! ([`optimize_general_plan`]). The command line and Python build the same settings struct
//! for both kinds of problem file and only render the answer; messages name the options as
//! the caller spelled them ([`Naming`]).

use super::events::Hooks;
use super::general_chain::{optimize_general_on_chain, GeneralChainSettings};
use super::general_local::optimize_general_local;
use super::general_phase::{optimize_general_phase, GeneralPhaseSettings};
use super::general_pm::optimize_general;
use super::general_pm::GeneralPmSettings;
use super::settings::{GaitMethod, Naming, OptimizeSettings};
use super::GeneralLocalSettings;
use crate::error::{Error, Result};
pub use crate::io::GeneralAnswer;
use crate::io::GeneralFile;
use crate::optimal::envelope::in_words;

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
        let method = self.method;
        if method == GaitMethod::Sequence || method == GaitMethod::Chain {
            return self.plan_on_chain(front_end);
        }
        let local = method == GaitMethod::Local;
        let phase = method == GaitMethod::Phase;
        self.check_fixed_k(phase)?;
        if let Some((name, value, reason)) = self.refused(phase, local, front_end) {
            return Err(Error::invalid(self.naming.setting(name), value, reason));
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

    /// The first setting given that the general method planned (P_m globally, P_m locally,
    /// or the phase method) does not take, as `(setting, value, reason)`: the rules are
    /// written once, their messages naming settings and methods as the caller spells them
    /// ([`Naming`]). A front end's own options (`front_end`) are refused alike.
    fn refused<'a>(
        &self,
        phase: bool,
        local: bool,
        front_end: &[(&'a str, bool)],
    ) -> Option<(&'a str, String, String)> {
        use GaitMethod::{Discrete, Local, Phase};
        let n = self.naming;
        let discrete = !phase && !local;
        let only = |methods: &[GaitMethod]| {
            format!(
                "applies to {} only on a general problem",
                n.methods(methods)
            )
        };
        let taken: Vec<String> = [
            "phases",
            "max_phases",
            "patience",
            "time_limit",
            "formulation",
            "certify",
            "bound",
        ]
        .iter()
        .map(|s| n.setting(s))
        .collect();
        let in_phase = format!(
            "does not apply to {} on a general problem (it takes {})",
            n.methods(&[Phase]),
            in_words(&taken, "and")
        );
        // P_m's default start (the local method's answer, as a crawler's P_m has it) runs
        // under a time limit, without a start given or a convergence table.
        let default_start = discrete && self.time_limit.is_some() && self.start.is_none();
        let default_start = default_start && !self.convergence;
        let shifts = format!(
            "applies to {} only on a general problem, or to the default start of {} (under {}, \
             without {} or {})",
            n.methods(&[Local]),
            n.methods(&[Discrete]),
            n.setting("time_limit"),
            n.setting("start"),
            n.setting("convergence")
        );
        // A phase gait is grown for a start by the local method, without a start given, and
        // by P_m's default start (where the file's problem allows it: checked when it runs).
        let phase_start = (local && self.start.is_none()) || default_start;
        let max_phases = format!(
            "applies to {} only on a general problem, or to the phase gait that starts {} \
             (without {}) or the default start of {} (under {}, without {} or {})",
            n.methods(&[Phase]),
            n.methods(&[Local]),
            n.setting("start"),
            n.methods(&[Discrete]),
            n.setting("time_limit"),
            n.setting("start"),
            n.setting("convergence")
        );
        // In the order they are checked: the first one given is named.
        let rules: [(&str, bool, String); 10] = [
            ("phases", !phase, only(&[Phase])),
            ("max_phases", !phase && !phase_start, max_phases),
            ("patience", !phase, only(&[Phase])),
            ("formulation", !phase, only(&[Phase])),
            ("m", phase, in_phase),
            ("shifts", !local && !default_start, shifts),
            ("start", phase, only(&[Local, Discrete])),
            (
                "start",
                discrete && self.convergence,
                format!(
                    "does not apply to {} (each m is solved afresh)",
                    n.setting("convergence")
                ),
            ),
            ("convergence", !discrete, only(&[Discrete])),
            ("polish", !discrete, only(&[Discrete])),
        ];
        let refused = rules.into_iter().find_map(|(name, refuses, why)| {
            let value = self.given(name).filter(|_| refuses)?;
            Some((name, value, why))
        });
        refused.or_else(|| {
            front_end.iter().find(|(_, g)| *g).map(|&(name, _)| {
                (
                    name,
                    "given".to_string(),
                    "applies to a crawler's problem only".to_string(),
                )
            })
        })
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
                max_phases: self.max_phases,
                certify: self.certify,
                bound: self.bound,
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
                start: self.start.clone(),
                shifts: self.shifts.unwrap_or(d.shifts),
                max_phases: self.max_phases,
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
        let takes: Vec<String> = ["time_limit", "certify", "bound"]
            .iter()
            .map(|s| n.setting(s))
            .collect();
        let reason = format!(
            "does not apply to the crawler's methods on a general problem ({} take {}; {} \
             and {} too with sequence, as for crawlers)",
            n.methods(&[GaitMethod::Sequence, GaitMethod::Chain]),
            in_words(&takes, "and"),
            n.setting("phases"),
            n.setting("max_phases")
        );
        let names = [
            "m",
            "convergence",
            "start",
            "shifts",
            "polish",
            "formulation",
        ];
        if let Some((name, value)) = names.iter().find_map(|&s| Some((s, self.given(s)?))) {
            return Err(Error::invalid(n.setting(name), value, reason));
        }
        if let Some((name, _)) = front_end.iter().find(|(_, g)| *g) {
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
            bound: self.bound,
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
