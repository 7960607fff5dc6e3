//! The settings of an optimisation ([`OptimizeSettings`]) and what they decide ([`Plan`]):
//! which method runs, which options apply to it, their defaults, and what is checked before any
//! solve.

use crate::certify::bound::BoundSettings;
use crate::error::{Error, Result};
use crate::model::Crawler;
use crate::optimal::{
    check_local, check_shifts, check_size, check_time_limit, Cost, GaitProblem, GrowOptions,
    MAX_LOCAL_M, MAX_M, MAX_PHASES,
};
pub use crate::optimal::{DEFAULT_MAX_PHASES, DEFAULT_PATIENCE};
use serde::{Deserialize, Deserializer, Serialize};
use std::path::PathBuf;

/// `m` of the discrete method unless given (8 steps).
pub const DEFAULT_M_DISCRETE: u32 = 3;

/// `m` of the local method unless given (1024 steps).
pub const DEFAULT_M_LOCAL: u32 = 10;

/// Time shifts of the start tried by the local method unless given.
pub const DEFAULT_SHIFTS: usize = 8;

/// The method of an optimisation, read by its [name](GaitMethod::name) (serde reads it through
/// [`GaitMethod::from_name`], so that a table of keys and a front end refuse an unknown name in
/// one wording).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", try_from = "String")]
pub enum GaitMethod {
    /// Phase gaits with K grown until no gain; the discrete P_m when the problem bounds TV(u),
    /// which phase gaits cannot express.
    #[default]
    Auto,
    /// The paper's discrete problem P_m on 2^m steps (§6), solved globally (MILP).
    Discrete,
    /// P_m on 2^m steps by the local LPCC active-set method, from a phase gait or a start.
    Local,
    /// Exact continuous-time gaits of at most K slip phases (theory §7), solved globally (MILP).
    Phase,
    /// Local search over the slip-mode sequences of phase gaits (each optimal for its
    /// sequence; no global claim), from a phase gait or a start.
    Sequence,
    /// Long chains: the best structured gait ([`crate::optimal::structured`]) improved by a
    /// pattern search over per-link ramp gaits ([`crate::optimal::chain`]), every trial
    /// simulated exactly; never below its start, no global claim. Runs without a time limit
    /// until the smallest step gains nothing.
    Chain,
}

impl GaitMethod {
    /// Its name, as the command line and Python spell it (`"discrete"`).
    pub fn name(self) -> &'static str {
        match self {
            GaitMethod::Auto => "auto",
            GaitMethod::Discrete => "discrete",
            GaitMethod::Local => "local",
            GaitMethod::Phase => "phase",
            GaitMethod::Sequence => "sequence",
            GaitMethod::Chain => "chain",
        }
    }

    /// One line on what the method does, for a front end's list of methods (the command
    /// line's `--help`); both kinds of problem run it, where it applies.
    pub fn summary(self) -> &'static str {
        match self {
            GaitMethod::Auto => {
                "A crawler: phase gaits with K grown until no gain (the discrete P_m when the \
                 problem bounds TV(u)); a general problem: the discrete P_m"
            }
            GaitMethod::Discrete => {
                "The paper's discrete problem P_m on 2^m steps, solved globally (MILP)"
            }
            GaitMethod::Local => {
                "P_m on 2^m steps by the local LPCC active-set method, from a phase gait or a \
                 start"
            }
            GaitMethod::Phase => {
                "Exact continuous-time gaits of at most K slip phases, solved globally (MILP)"
            }
            GaitMethod::Sequence => {
                "Local search over the slip-mode sequences of phase gaits (each optimal for its \
                 sequence; no global claim), from a phase gait or a start, for K where the MILP \
                 is too slow (crawlers, and (P) where it is a crawler's)"
            }
            GaitMethod::Chain => {
                "Long chains: the best structured gait (travelling, alternating, grouped waves) \
                 improved by a pattern search over per-link ramp gaits, simulated exactly (no \
                 global claim; never below its start; crawlers, and (P) where it is a crawler's)"
            }
        }
    }

    /// Every method, in the order front ends list them.
    pub const ALL: [GaitMethod; 6] = [
        Self::Auto,
        Self::Discrete,
        Self::Local,
        Self::Phase,
        Self::Sequence,
        Self::Chain,
    ];

    /// The method of a name ([`GaitMethod::name`]).
    pub fn from_name(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| Error::invalid("method", name, method_names()))
    }
}

/// Why a name is no [`GaitMethod`]: the names of [`GaitMethod::ALL`].
fn method_names() -> String {
    let names: Vec<&str> = GaitMethod::ALL.iter().map(|m| m.name()).collect();
    format!("must be one of {}", names.join(", "))
}

/// Why a name is no [`PhaseFormulation`].
const FORMULATION_NAMES: &str = "must be \"general\", \"transitions\" or \"chain\"";

impl TryFrom<String> for GaitMethod {
    type Error = String;

    /// [`GaitMethod::from_name`], its refusal's reason for serde to report at the key.
    fn try_from(name: String) -> std::result::Result<Self, Self::Error> {
        Self::from_name(&name).map_err(|_| method_names())
    }
}

impl TryFrom<String> for PhaseFormulation {
    type Error = &'static str;

    /// [`PhaseFormulation::from_name`], its refusal's reason for serde to report at the key.
    fn try_from(name: String) -> std::result::Result<Self, Self::Error> {
        Self::from_name(&name).map_err(|_| FORMULATION_NAMES)
    }
}

/// How messages name settings: after the front end the user typed them in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Naming {
    /// Keyword arguments and struct fields: `max_phases`, `method="local"` (Python, Rust).
    #[default]
    Keywords,
    /// Command-line flags: `--max-phases`, `--method local`.
    Flags,
}

impl Naming {
    /// A setting as the caller spelled it, in a sentence and as the field of an error alike:
    /// `max_phases` for keywords, `--max-phases` for flags (the one scheme of every refusal
    /// of both kinds of problem file). `polish` is the flag `--no-polish`.
    pub fn setting(self, name: &str) -> String {
        match (self, name) {
            (Naming::Keywords, _) => name.to_string(),
            (Naming::Flags, "polish" | "no_polish") => "--no-polish".to_string(),
            (Naming::Flags, _) => format!("--{}", name.replace('_', "-")),
        }
    }

    /// An error of an optimisation run with these settings, its field named as the caller
    /// spelled the setting (`time_limit` is `--time-limit` for flags); other fields unchanged.
    pub fn name_settings(self, e: crate::Error) -> crate::Error {
        if self == Naming::Keywords {
            return e;
        }
        // `start` is not renamed: the library names its default start gait so too.
        let mut names: Vec<(&str, String)> = [
            "method",
            "m",
            "time_limit",
            "shifts",
            "max_phases",
            "phases",
            "patience",
            "bound",
            "certify",
            "convergence",
            "polish",
            "formulation",
        ]
        .into_iter()
        .map(|f| (f, self.setting(f)))
        .collect();
        // The bound's own settings, flags of their own.
        for (field, flag) in [
            ("bound.time_limit", "--bound-time-limit"),
            ("bound.resolution", "--bound-resolution"),
            ("bound.box_resolution", "--bound-box-resolution"),
            ("bound.cost_tangents", "--bound-cost-tangents"),
        ] {
            names.push((field, flag.to_string()));
        }
        rename_fields(e, &names)
    }

    /// Methods inside a sentence: `--method local, sequence and discrete` for flags,
    /// `method="local", "sequence" and "discrete"` for keywords.
    pub fn methods(self, methods: &[GaitMethod]) -> String {
        let names: Vec<String> = methods
            .iter()
            .map(|m| match self {
                Naming::Keywords => format!("\"{}\"", m.name()),
                Naming::Flags => m.name().to_string(),
            })
            .collect();
        let list = crate::optimal::envelope::in_words(&names, "and");
        match self {
            Naming::Keywords => format!("method={list}"),
            Naming::Flags => format!("--method {list}"),
        }
    }
}

/// A start gait for the local methods and the P_m MILP: a result of the problem's kind (a
/// crawler's gait result for a crawler's problem; a general result for (P)'s local method and
/// its global P_m), from a file or in memory.
#[derive(Clone, Debug, PartialEq)]
pub enum Start {
    /// A result file of `optimize` (read only when the method takes a start).
    File(PathBuf),
    /// A result in memory, and a name for messages and the recorded origin.
    Result {
        /// The result, of either kind (the wrong one is refused naming `start`).
        result: Box<crate::io::ResultFile>,
        /// What to call it (e.g. `start.json`).
        name: String,
    },
}

impl Start {
    /// What messages and records call the start: the file's path, or the name given with a
    /// result in memory.
    pub fn name(&self) -> String {
        match self {
            Start::File(path) => path.display().to_string(),
            Start::Result { name, .. } => name.clone(),
        }
    }

    /// The start's result and its name: a file read and checked as `certify` reads it, or the
    /// result in memory checked alike (the one reader of starts of both kinds).
    pub(crate) fn read(&self) -> Result<(crate::io::ResultFile, String)> {
        let name = self.name();
        match self {
            Start::File(path) => {
                let text = crate::io::read_input_text(path, crate::io::MAX_RESULT_BYTES)?;
                Ok((crate::io::ResultFile::from_json(&text, &name)?, name))
            }
            Start::Result { result, .. } => {
                result.check_consistent(&name)?;
                Ok(((**result).clone(), name))
            }
        }
    }
}

/// Everything an optimisation can be told. Every field has a default (`None`: the method's
/// own, documented at the field); [`OptimizeSettings::plan`] checks them against the method and
/// the problem before any solve.
///
/// ```
/// use crawlopt::api::{GaitMethod, OptimizeSettings};
/// let s = OptimizeSettings { method: GaitMethod::Discrete, m: Some(4), ..Default::default() };
/// assert_eq!(s.time_limit, None);
/// ```
///
/// The settings read from a table of keys ([`OptimizeSettings::from_keys`]: a sweep file's
/// `[settings]`, Python's keyword arguments) are these fields by their names; `start` and
/// `naming` are the caller's to set.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OptimizeSettings {
    /// The method (default [`GaitMethod::Auto`]).
    pub method: GaitMethod,
    /// Slip phases allowed in a phase gait (phase, auto); the sequence method's number of slip
    /// modes (default: the start's plus 2; given, its default start gait grows K no further,
    /// stopping earlier at the first K without a gain, and the best structured gait starts it
    /// only when it fits). Without it K grows from 1 until the value has not improved for
    /// `patience` K (or `max_phases`, or the time limit).
    pub phases: Option<usize>,
    /// Consecutive K without a gain that end a certified growth of K (default
    /// [`DEFAULT_PATIENCE`]).
    pub patience: Option<usize>,
    /// Largest K tried when K grows (default [`DEFAULT_MAX_PHASES`]; checked by
    /// [`OptimizeSettings::check_values`], in `1..=MAX_PHASES` and not below the first K). The
    /// sequence method's default start grows K to at most `phases` when that is given.
    #[serde(alias = "max-phases")]
    pub max_phases: Option<usize>,
    /// The grid of P_m has 2^m steps (discrete: default [`DEFAULT_M_DISCRETE`]; local: default
    /// [`DEFAULT_M_LOCAL`]).
    pub m: Option<u32>,
    /// Solve P_m for m = 1..=M and record the table of J_m (discrete).
    pub convergence: bool,
    /// A start gait (local, sequence, discrete). Default: the phase optimum with K grown to the
    /// first K without a gain (local, sequence), or under a time limit the local method's gait
    /// on the same grid (discrete).
    #[serde(skip)]
    pub start: Option<Start>,
    /// Time shifts of the start tried by the local method (default [`DEFAULT_SHIFTS`]).
    pub shifts: Option<usize>,
    /// Wall-clock limit, seconds: the best gait found is returned with its gap.
    #[serde(alias = "time-limit")]
    pub time_limit: Option<f64>,
    /// Also check the necessary conditions (Theorem 2.2) on the answer.
    pub certify: bool,
    /// Polish a P_m answer of a quadratic cost on its fixed slip pattern, a QP solved to the
    /// solvers' resolution ([`crate::optimal::polish`]; discrete). Default (`None`):
    /// [`crate::optimal::polish::POLISH_DEFAULT`], on; without it a rate off its bounds is
    /// only as accurate as the MILP's outer approximation (about 1e-3).
    pub polish: Option<bool>,
    /// The phase MILP's formulation on a general problem file (default `None`: the chain's
    /// where the problem is a crawler's, free transitions elsewhere;
    /// [`super::GeneralPhaseSettings::formulation`]). Refused elsewhere, naming it: a crawler's
    /// phase MILP has its own.
    pub formulation: Option<PhaseFormulation>,
    /// How messages name the settings.
    #[serde(skip)]
    pub naming: Naming,
    /// Also prove an upper bound over all periodic gaits ([`crate::certify::bound`]), recorded
    /// as `certificate.upper_bound` (default: none). As a key: `true` (the bound's defaults),
    /// `false` (none) or a table of [`BoundSettings`]' fields (`bound = { resolution = 16 }`).
    #[serde(deserialize_with = "bound_key")]
    pub bound: Option<BoundSettings>,
}

/// The key `bound` of [`OptimizeSettings`]: `true` is the bound with its defaults, `false` no
/// bound, a table its settings (each key of the table reached by its path, `bound.resolution`,
/// so that a refusal names it).
fn bound_key<'de, D: Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<BoundSettings>, D::Error> {
    struct Key;
    impl<'de> serde::de::Visitor<'de> for Key {
        type Value = Option<BoundSettings>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("true, false or a table of the bound's settings")
        }

        fn visit_bool<E: serde::de::Error>(self, on: bool) -> std::result::Result<Self::Value, E> {
            Ok(on.then(BoundSettings::default))
        }

        fn visit_map<A: serde::de::MapAccess<'de>>(
            self,
            map: A,
        ) -> std::result::Result<Self::Value, A::Error> {
            let table = serde::de::value::MapAccessDeserializer::new(map);
            BoundSettings::deserialize(table).map(Some)
        }
    }
    d.deserialize_any(Key)
}

/// A formulation of the phase MILP of a general problem
/// ([`GeneralPhaseSettings::formulation`](super::GeneralPhaseSettings::formulation)), read by
/// its [name](PhaseFormulation::name) (serde reads it through [`PhaseFormulation::from_name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(try_from = "String")]
pub enum PhaseFormulation {
    /// `K` phases of constant control and held faces (`optimal::general::phase`): any (P)
    /// with `A = 0`.
    General,
    /// `K` slots of a free transition (no face held, no binaries) and a phase
    /// (`optimal::general::solve_general_transitions`): any (P) with `A = 0`, as strong as the
    /// chain's formulation on the chains measured (the same `J_K`), with the general one's
    /// binaries at `K`: at least the general formulation's value at `K`, at most its value at
    /// `2K`.
    Transitions,
    /// `K` slip phases with transitions free (`optimal::general::chain_phase`): a crawler's
    /// gait problem only; every general gait of at most `K` phases is among its gaits.
    Chain,
}

impl PhaseFormulation {
    /// The formulation's name: `general`, `transitions` or `chain` (the result's
    /// `formulation`, the CLI's `--formulation`, Python's `formulation=`).
    pub fn name(self) -> &'static str {
        match self {
            PhaseFormulation::General => "general",
            PhaseFormulation::Transitions => "transitions",
            PhaseFormulation::Chain => "chain",
        }
    }

    /// The formulation of a name ([`PhaseFormulation::name`]); an error naming `formulation`.
    pub fn from_name(name: &str) -> crate::Result<Self> {
        [Self::General, Self::Transitions, Self::Chain]
            .into_iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| crate::Error::invalid("formulation", name, FORMULATION_NAMES))
    }
}

/// What [`OptimizeSettings`] decide for a problem: the method that runs and every value it
/// runs with, defaults filled in.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// The method that runs (auto resolved).
    pub method: GaitMethod,
    /// The options of a growth of K (certified, or a start's).
    pub growth: GrowOptions,
    /// Whether the certified growth of K runs (phase without `phases`).
    pub certified_growth: bool,
    /// `m` of the P_m methods.
    pub m: u32,
    /// Shifts of the local method.
    pub shifts: usize,
}

impl OptimizeSettings {
    /// The settings given as a table of keys, the fields' own names (`max_phases`, with
    /// `max-phases` and `time-limit` also read as a flag spells them; `method = "phase"`,
    /// `formulation = "general"`), every key left out at its default: how a sweep file's
    /// `[settings]` and Python's keyword arguments reach the one settings struct, so that a
    /// setting is declared once, here. `bound` is `true`, `false` or a table of the bound's
    /// settings. `start` and `naming` are not keys (a start is a file or a result): the caller
    /// sets them.
    ///
    /// An error names the key (`m`, for `m = "a"` or `m = -3`) and shows its value (a value of
    /// the wrong type, `m = "a"`, is an [`Error::WrongType`]); a key that is not a setting is
    /// refused naming `settings`, listing the settings. Values are only read here: what they
    /// mean to a method is [`OptimizeSettings::plan`]'s to check.
    ///
    /// ```
    /// use crawlopt::api::{GaitMethod, OptimizeSettings};
    /// let keys: toml::Table = toml::from_str("method = \"phase\"\nmax_phases = 4").unwrap();
    /// let s = OptimizeSettings::from_keys(&keys).unwrap();
    /// assert_eq!((s.method, s.max_phases, s.m), (GaitMethod::Phase, Some(4), None));
    /// let bad: toml::Table = toml::from_str("m = -3").unwrap();
    /// let e = OptimizeSettings::from_keys(&bad).unwrap_err();
    /// assert!(matches!(e, crawlopt::Error::InvalidParameter { ref field, .. } if field == "m"));
    /// ```
    pub fn from_keys(keys: &toml::Table) -> Result<Self> {
        super::keys::read_keys(keys)
    }

    /// Resolves the method, checks that every option given applies to it and has a usable
    /// value, and the size of the model, before any solve: so that a bad value is not found
    /// after a start gait was computed, or turned into a note by a start policy. The bound's
    /// settings, whether it applies to `crawler` (at most four blocks) and the size of its grid
    /// are checked here too ([`crate::certify::bound::check_upper_bound`]), not after the
    /// method has run.
    pub fn plan(&self, crawler: &Crawler, problem: &GaitProblem) -> Result<Plan> {
        use GaitMethod::*;
        let plan = self.decide(problem)?;
        if let Some(b) = &self.bound {
            crate::certify::bound::check_upper_bound(crawler, problem, b)?;
        }
        // The size of the models (blocks, blocks x grid steps), before any allocation.
        match plan.method {
            Local | Discrete => {
                // An m beyond the grids was refused by `check_values`.
                check_size(crawler, 1usize << plan.m.min(MAX_M), "m", plan.m)?;
            }
            _ => {
                let k = self.phases.unwrap_or(plan.growth.max_phases);
                check_size(crawler, k, "phases", k)?;
            }
        }
        Ok(plan)
    }

    /// Refuses, whatever the problem, a value no method runs with: `m` outside `1..=MAX_M`,
    /// `phases` or `max_phases` outside `1..=MAX_PHASES`, `patience` 0, `shifts` outside
    /// `1..=MAX_SHIFTS`, a time limit that is not positive and finite (the checks of the
    /// optimisers themselves, made before any work: a sweep makes them when it reads its file).
    /// The fields are the settings' own names (`max_phases`), as the optimisers name them.
    pub fn check_values(&self) -> Result<()> {
        check_time_limit(self.time_limit)?;
        match self.m {
            Some(0) => {
                return Err(Error::invalid(
                    "m",
                    0,
                    "must be at least 1 (a periodic gait needs two steps)",
                ))
            }
            Some(m) if m > MAX_M => {
                return Err(Error::invalid(
                    "m",
                    m,
                    format!("must be in 1..={MAX_M} (grids of at most 2^{MAX_M} steps)"),
                ))
            }
            _ => {}
        }
        if let Some(k) = self.phases {
            if !(1..=MAX_PHASES).contains(&k) {
                return Err(Error::invalid(
                    "phases",
                    k,
                    format!("must be in 1..={MAX_PHASES}"),
                ));
            }
        }
        self.growth().check()?;
        if let Some(s) = self.shifts {
            check_shifts(s)?;
        }
        Ok(())
    }

    /// The options of a growth of K under these settings, the library's defaults filled in
    /// ([`DEFAULT_MAX_PHASES`], [`DEFAULT_PATIENCE`]).
    fn growth(&self) -> GrowOptions {
        GrowOptions {
            max_phases: self.max_phases.unwrap_or(DEFAULT_MAX_PHASES),
            patience: self.patience.unwrap_or(DEFAULT_PATIENCE),
            time_limit: self.time_limit,
            ..GrowOptions::default()
        }
    }

    /// [`OptimizeSettings::plan`] without the size of the crawler: the method, the options that
    /// apply to it and their values, which depend on the problem only through its kind (a TV
    /// bound, a quadratic cost), not on its numbers.
    pub fn decide(&self, problem: &GaitProblem) -> Result<Plan> {
        use GaitMethod::*;
        self.check_values()?;
        let method = match self.method {
            Auto if problem.max_total_variation.is_some() => Discrete,
            Auto => Phase,
            other => other,
        };
        self.check_applies(method, problem)?;
        let grows = self.grows(method, problem);
        let certified_growth = method == Phase && grows;
        let m = self.m.unwrap_or(if method == Local {
            DEFAULT_M_LOCAL
        } else {
            DEFAULT_M_DISCRETE
        });
        // The local method runs for local, and in discrete's default start unless the start is
        // the phase gait itself (a quadratic cost, grids beyond the method).
        let local_search = method == Local
            || (method == Discrete && grows && problem.cost == Cost::None && m <= MAX_LOCAL_M);
        self.check_growth_settings(grows, certified_growth, local_search)?;
        let mut growth = self.growth();
        if let (Sequence, Some(k)) = (method, self.phases) {
            // The sequence search moves among sequences of K slip modes: its default start
            // grows K no further, so that it fits.
            growth.max_phases = growth.max_phases.min(k);
        }
        if let Some(s) = self.shifts {
            check_shifts(s)?;
        }
        if method == Local {
            check_local(problem, m)?;
        }
        self.check_method_options(method, m)?;
        Ok(Plan {
            method,
            growth,
            certified_growth,
            m,
            shifts: self.shifts.unwrap_or(DEFAULT_SHIFTS),
        })
    }

    /// The start gait, polishing and the chain method are refused where `method` cannot take
    /// them.
    fn check_applies(&self, method: GaitMethod, problem: &GaitProblem) -> Result<()> {
        use GaitMethod::*;
        let n = self.naming;
        if self.start.is_some() && !matches!(method, Local | Sequence | Discrete) {
            return Err(Error::invalid(
                n.setting("start"),
                "a file",
                format!(
                    "applies to {} only",
                    n.methods(&[Local, Sequence, Discrete])
                ),
            ));
        }
        if let (Some(v), false) = (self.polish, method == Discrete) {
            // Only P_m's MILP answers are polished; the CLI's flag is --no-polish.
            return Err(Error::invalid(
                n.setting("polish"),
                v,
                format!("applies to {} only", n.methods(&[Discrete])),
            ));
        }
        if let Some(f) = self.formulation {
            return Err(Error::invalid(
                n.setting("formulation"),
                f.name(),
                "applies to the phase method on a general problem file only (a crawler's \
                 phase MILP counts slip phases, as the chain's formulation does)",
            ));
        }
        if method == Chain && problem.max_total_variation.is_some() {
            return Err(Error::invalid(
                n.setting("method"),
                "chain",
                "the chain method's gaits do not honour a bound on TV(u) (gait.max_total_variation): \
                 use the discrete method",
            ));
        }
        Ok(())
    }

    /// Whether `method` grows K: for a certified answer (phase), or for a default start gait.
    fn grows(&self, method: GaitMethod, problem: &GaitProblem) -> bool {
        use GaitMethod::*;
        let no_start = self.start.is_none();
        match method {
            Auto | Phase => self.phases.is_none(),
            Local | Sequence => no_start,
            Chain => false,
            Discrete => {
                no_start
                    && !self.convergence
                    && self.time_limit.is_some()
                    && problem.max_total_variation.is_none()
            }
        }
    }

    /// The growth's settings (`patience`, `max_phases`) and `shifts` are refused where nothing
    /// they set runs.
    fn check_growth_settings(
        &self,
        grows: bool,
        certified_growth: bool,
        local_search: bool,
    ) -> Result<()> {
        use GaitMethod::*;
        let n = self.naming;
        let (phase, auto, phases) = (n.methods(&[Phase]), "auto without a TV bound", "phases");
        let without_phases = format!("without {}", n.setting(phases));
        for (given, applies, name, scope) in [
            (
                self.patience,
                certified_growth,
                "patience",
                format!(
                    "a certified growth of K: {phase}, or {auto}, {without_phases} (start gaits \
                     stop at the first K without a gain)"
                ),
            ),
            (
                self.max_phases,
                grows,
                "max_phases",
                format!(
                    "a growth of K: {phase}, or {auto}, {without_phases}; or a default start \
                     gait (no {}; for discrete, under {} and without a TV bound)",
                    n.setting("start"),
                    n.setting("time_limit")
                ),
            ),
            (
                self.shifts,
                local_search,
                "shifts",
                format!(
                    "the local method: {}, or the default start of {} (under {}, without a TV \
                     bound or a quadratic cost, m <= {MAX_LOCAL_M})",
                    n.methods(&[Local]),
                    n.methods(&[Discrete]),
                    n.setting("time_limit")
                ),
            ),
        ] {
            if let (Some(v), false) = (given, applies) {
                return Err(Error::invalid(
                    n.setting(name),
                    v,
                    format!("applies only to {scope}"),
                ));
            }
        }
        Ok(())
    }

    /// The value of the setting `name` as a refusal shows it, when it is given (`None` when it
    /// is left at its default, or is not one of the settings a method may refuse).
    pub(super) fn given(&self, name: &str) -> Option<String> {
        match name {
            "phases" => self.phases.map(|k| k.to_string()),
            "max_phases" => self.max_phases.map(|k| k.to_string()),
            "patience" => self.patience.map(|k| k.to_string()),
            "formulation" => self.formulation.map(|f| f.name().to_string()),
            "m" => self.m.map(|m| m.to_string()),
            "shifts" => self.shifts.map(|k| k.to_string()),
            "start" => self.start.as_ref().map(Start::name),
            "convergence" => self.convergence.then(|| "set".into()),
            "polish" => self.polish.map(|v| v.to_string()),
            "certify" => self.certify.then(|| "true".into()),
            "bound" => self.bound.as_ref().map(|_| "set".into()),
            other => {
                debug_assert!(false, "{other} is not a setting a method refuses");
                None
            }
        }
    }

    /// The options that belong to one method only.
    fn check_method_options(&self, method: GaitMethod, m: u32) -> Result<()> {
        use GaitMethod::*;
        let n = self.naming;
        let set = |name: &str| n.setting(name);
        // The option given is named (a sweep renames it `settings.KEY`).
        let given = |name: &str| -> Result<()> {
            match self.given(name) {
                Some(v) => Err(Error::invalid(
                    set(name),
                    v,
                    format!("does not apply to {}", n.methods(&[method])),
                )),
                None => Ok(()),
            }
        };
        match method {
            Local if self.phases.is_some() || self.convergence => {
                given("phases")?;
                given("convergence")
            }
            Sequence if self.m.is_some() || self.convergence => {
                given("m")?;
                given("convergence")
            }
            Chain => {
                given("phases")?;
                given("m")?;
                given("convergence")
            }
            Phase | Auto => {
                let only = format!("applies to {} only", n.methods(&[Discrete]));
                if let Some(m) = self.m {
                    return Err(Error::invalid(set("m"), m, only));
                }
                if self.convergence {
                    return Err(Error::invalid(set("convergence"), "set", only));
                }
                Ok(())
            }
            Discrete => {
                if let Some(k) = self.phases {
                    return Err(Error::invalid(
                        set("phases"),
                        k,
                        format!("applies to {} only", n.methods(&[Phase])),
                    ));
                }
                if m == 0 {
                    return Err(Error::invalid(
                        set("m"),
                        0,
                        "must be at least 1 (a periodic gait needs two steps)",
                    ));
                }
                if self.convergence && self.start.is_some() {
                    return Err(Error::invalid(
                        set("start"),
                        "a file",
                        format!(
                            "does not apply to {} (each m starts from the optimum of m - 1)",
                            n.setting("convergence")
                        ),
                    ));
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

/// `e` with the field of an [`Error::InvalidParameter`] renamed by `names` (`(field, name)`; a
/// field matches itself and its indexed entries `field[i]`).
pub fn rename_fields(e: Error, names: &[(&str, String)]) -> Error {
    let rename = |field: String| {
        let to = names.iter().find(|(name, _)| {
            field
                .strip_prefix(name)
                .is_some_and(|rest| rest.is_empty() || rest.starts_with('['))
        });
        to.map_or(field, |(_, f)| f.clone())
    };
    e.map_field(rename)
}
