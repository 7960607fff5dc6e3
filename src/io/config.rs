//! The TOML model file (see the module docs of [`crate::io`]).

use super::csv_io::read_input_file;
use crate::error::{Error, Result};
use crate::integrate::{Actuation, Waveform};
use crate::model::Crawler;
use crate::optimal::{Cost, GaitProblem};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Largest model file read (bytes): model files are a few hundred bytes; this bounds what a
/// wrong path (a log, a disk image) makes the reader allocate.
pub const MAX_MODEL_BYTES: u64 = 16 << 20;

/// Most blocks of a crawler in a model file.
pub const MAX_BLOCKS: i64 = 10_000_000;

/// A line of the input quoted in a message: at most 80 characters, control characters escaped.
fn quote_line(line: &str) -> String {
    let line = line.trim();
    match line.char_indices().nth(80) {
        Some((cut, _)) => format!("{}...", escape_controls(&line[..cut])),
        None => escape_controls(line),
    }
}

/// `s` with control characters (and the invisible ones that reorder or hide text) escaped, so
/// that a message quoting input stays one visible line.
pub(crate) fn escape_controls(s: &str) -> String {
    let hidden = |c: char| {
        c.is_control()
            || c == '\u{feff}'
            || ('\u{200b}'..='\u{200f}').contains(&c)
            || ('\u{202a}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c)
    };
    s.chars()
        .flat_map(|c| {
            let e: Vec<char> = if hidden(c) {
                c.escape_default().collect()
            } else {
                vec![c]
            };
            e
        })
        .collect()
}

/// A number for every entry, or one per entry.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum NumberOrList {
    /// The same value everywhere.
    One(f64),
    /// One value per entry.
    Many(Vec<f64>),
}

impl NumberOrList {
    /// Expands to `len` values; a list of another length is an error naming `field`.
    pub fn expand(&self, field: &str, len: usize, what: &str) -> Result<Vec<f64>> {
        match self {
            NumberOrList::One(v) => Ok(vec![*v; len]),
            NumberOrList::Many(v) if v.len() == len => Ok(v.clone()),
            NumberOrList::Many(v) => Err(Error::invalid(
                field,
                format!("{} values", v.len()),
                format!("needs a number or one value per {what} ({len})"),
            )),
        }
    }
}

/// `[crawler]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CrawlerSpec {
    /// Number of blocks `N >= 2`.
    pub blocks: i64,
    /// `k`, per link.
    pub stiffness: NumberOrList,
    /// `mu^+`, per block.
    pub mu_forward: NumberOrList,
    /// `mu^-`, per block.
    pub mu_backward: NumberOrList,
}

/// `[actuation]`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ActuationSpec {
    /// `sine | triangle | piecewise_linear | csv`.
    pub kind: String,
    /// Period `T`.
    pub period: f64,
    /// Wave amplitude (sine, triangle).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<NumberOrList>,
    /// Wave phase lag in degrees (sine, triangle); default 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phase_deg: Option<NumberOrList>,
    /// Wave mean length (sine, triangle); default 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean: Option<NumberOrList>,
    /// Knot times (piecewise_linear).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub times: Option<Vec<f64>>,
    /// Knot lengths (piecewise_linear): one row per knot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lengths: Option<Vec<NumberOrList>>,
    /// CSV file (csv), relative to the model file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path: Option<String>,
}

/// `cost = { kind = "none" }` or `{ kind = "quadratic", weight = c }`.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CostSpec {
    /// `none | quadratic`.
    pub kind: String,
    /// `c` of the quadratic cost.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight: Option<f64>,
}

/// `[gait]`: the gait problem (P).
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct GaitSpec {
    /// Period `T`.
    pub period: f64,
    /// Bound on `|L_l'|`, a number or one per link (`a_l = k_l * speed`).
    pub max_actuator_speed: NumberOrList,
    /// Actuation cost (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost: Option<CostSpec>,
    /// Optional bound on the total variation of `u` over a period.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_total_variation: Option<f64>,
}

/// `[simulation]` (optional).
#[derive(Debug, Clone, Default, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// Initial state `x(0)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub initial_state: Option<Vec<f64>>,
}

/// The whole model file.
#[derive(Debug, Clone, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModelFile {
    /// `[crawler]`.
    pub crawler: CrawlerSpec,
    /// `[actuation]`, needed by `simulate`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub actuation: Option<ActuationSpec>,
    /// `[simulation]`.
    #[serde(default, skip_serializing_if = "SimulationSpec::is_empty")]
    pub simulation: SimulationSpec,
    /// `[gait]`, the optimal-gait problem.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gait: Option<GaitSpec>,
    /// Folder of the file, for relative paths.
    #[serde(skip)]
    pub base_dir: PathBuf,
}

impl ModelFile {
    /// Reads and parses a model file (a regular file of at most `MAX_MODEL_BYTES`).
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = read_input_file(path, MAX_MODEL_BYTES).map_err(|reason| Error::Io {
            path: path.display().to_string(),
            reason,
        })?;
        let text = String::from_utf8(bytes).map_err(|e| Error::Io {
            path: path.display().to_string(),
            reason: format!(
                "not a text file: invalid UTF-8 at byte {}",
                e.utf8_error().valid_up_to()
            ),
        })?;
        let mut m = Self::parse(&text).map_err(|e| match e {
            Error::Io { reason, .. } => Error::Io {
                path: path.display().to_string(),
                reason,
            },
            other => other,
        })?;
        m.base_dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok(m)
    }

    /// Parses the TOML text of a model file.
    pub fn parse(text: &str) -> Result<Self> {
        parse_toml(text)
    }

    /// The crawler of `[crawler]`.
    pub fn crawler(&self) -> Result<Crawler> {
        self.crawler.crawler()
    }

    /// The gait problem of `[gait]`, if the file has one.
    pub fn gait(&self, crawler: &Crawler) -> Result<Option<GaitProblem>> {
        self.gait.as_ref().map(|g| g.problem(crawler)).transpose()
    }

    /// The actuation of `[actuation]` for a crawler with `links` links.
    pub fn actuation(&self, links: usize) -> Result<Actuation> {
        let a = self.actuation.as_ref().ok_or_else(|| {
            Error::invalid(
                "actuation",
                "nothing",
                "the model file has no [actuation] section",
            )
        })?;
        a.actuation(links, &self.base_dir)
    }

    /// The file as TOML text, which [`ModelFile::parse`] reads back to the same model (numbers
    /// are written in their shortest form that reads back exactly).
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string(self).map_err(|e| Error::Io {
            path: "<model>".into(),
            reason: format!("cannot write the model as TOML: {e}"),
        })
    }
}

impl ModelFile {
    /// Checks every section as the commands would (the crawler, its gait problem and its
    /// actuation for its links), so that a file written by [`ModelFile::to_toml`] is one that
    /// reads back and runs.
    pub fn check(&self) -> Result<()> {
        let crawler = self.crawler()?;
        self.gait(&crawler)?;
        if self.actuation.is_some() {
            self.actuation(crawler.links())?;
        }
        Ok(())
    }
}

impl SimulationSpec {
    /// Whether the section says nothing (it is then left out of the file).
    pub fn is_empty(&self) -> bool {
        self.initial_state.is_none()
    }
}

impl NumberOrList {
    /// `values` as a single number when they are all the same (and there is at least one),
    /// else as the list: the file form that expands back to `values`.
    pub fn of(values: &[f64]) -> NumberOrList {
        match values.split_first() {
            Some((v, rest)) if rest.iter().all(|w| w.to_bits() == v.to_bits()) => {
                NumberOrList::One(*v)
            }
            _ => NumberOrList::Many(values.to_vec()),
        }
    }

    /// The number of entries of a list (None for a single number, which fits any count).
    pub fn list_len(&self) -> Option<usize> {
        match self {
            NumberOrList::One(_) => None,
            NumberOrList::Many(v) => Some(v.len()),
        }
    }
}

impl CrawlerSpec {
    /// The crawler of `[crawler]`.
    pub fn crawler(&self) -> Result<Crawler> {
        let c = self;
        if c.blocks < 2 {
            return Err(Error::invalid(
                "crawler.blocks",
                c.blocks,
                "a crawler needs at least 2 blocks",
            ));
        }
        if c.blocks > MAX_BLOCKS {
            return Err(Error::invalid(
                "crawler.blocks",
                c.blocks,
                format!("must be at most {MAX_BLOCKS}"),
            ));
        }
        let nb = c.blocks as usize;
        Crawler::new(
            c.stiffness.expand("crawler.stiffness", nb - 1, "link")?,
            c.mu_forward.expand("crawler.mu_forward", nb, "block")?,
            c.mu_backward.expand("crawler.mu_backward", nb, "block")?,
        )
    }

    /// The section of `crawler` (each quantity a single number where it is the same
    /// everywhere); [`CrawlerSpec::crawler`] builds it back exactly.
    pub fn of(crawler: &Crawler) -> CrawlerSpec {
        CrawlerSpec {
            blocks: crawler.blocks() as i64,
            stiffness: NumberOrList::of(crawler.stiffness()),
            mu_forward: NumberOrList::of(crawler.mu_forward()),
            mu_backward: NumberOrList::of(crawler.mu_backward()),
        }
    }
}

impl GaitSpec {
    /// The gait problem this section poses for `crawler` (`max_actuator_speed` expanded to
    /// its links).
    pub fn problem(&self, crawler: &Crawler) -> Result<GaitProblem> {
        let g = self;
        let cost = match &g.cost {
            None => Cost::None,
            Some(c) => match (c.kind.as_str(), c.weight) {
                ("none", None) => Cost::None,
                ("none", Some(_)) => {
                    return Err(Error::invalid(
                        "gait.cost.weight",
                        "a value",
                        "is not used by kind = \"none\"",
                    ))
                }
                ("quadratic", Some(weight)) => Cost::Quadratic { weight },
                ("quadratic", None) => {
                    return Err(Error::invalid(
                        "gait.cost.weight",
                        "nothing",
                        "is required for kind = \"quadratic\"",
                    ))
                }
                (other, _) => {
                    return Err(Error::invalid(
                        "gait.cost.kind",
                        format!("\"{other}\""),
                        "must be none or quadratic",
                    ))
                }
            },
        };
        GaitProblem::new(
            crawler,
            g.period,
            &g.max_actuator_speed
                .expand("gait.max_actuator_speed", crawler.links(), "link")?,
            cost,
            g.max_total_variation,
        )
    }
}

impl ActuationSpec {
    /// The actuation this section describes for a crawler with `links` links: a single
    /// number stands for every link (as everywhere in the file); a CSV path is relative to
    /// `base_dir`.
    pub fn actuation(&self, links: usize, base_dir: &Path) -> Result<Actuation> {
        let a = self;
        let unused = |name: &str, present: bool| -> Result<()> {
            if present {
                Err(Error::invalid(
                    format!("actuation.{name}"),
                    "a value",
                    format!("is not used by kind = \"{}\"", a.kind),
                ))
            } else {
                Ok(())
            }
        };
        let wave = match a.kind.as_str() {
            "sine" => Some(Waveform::Sine),
            "triangle" => Some(Waveform::Triangle),
            "piecewise_linear" | "csv" => None,
            other => {
                return Err(Error::invalid(
                    "actuation.kind",
                    format!("\"{other}\""),
                    "must be one of sine, triangle, piecewise_linear, csv",
                ))
            }
        };
        if let Some(wave) = wave {
            unused("times", a.times.is_some())?;
            unused("lengths", a.lengths.is_some())?;
            unused("path", a.path.is_some())?;
            let amp = a.amplitude.as_ref().ok_or_else(|| {
                Error::invalid("actuation.amplitude", "nothing", "is required for a wave")
            })?;
            let zero = NumberOrList::One(0.0);
            return Actuation::wave(
                wave,
                a.period,
                a.mean
                    .as_ref()
                    .unwrap_or(&zero)
                    .expand("actuation.mean", links, "link")?,
                amp.expand("actuation.amplitude", links, "link")?,
                a.phase_deg.as_ref().unwrap_or(&zero).expand(
                    "actuation.phase_deg",
                    links,
                    "link",
                )?,
            );
        }
        unused("amplitude", a.amplitude.is_some())?;
        unused("phase_deg", a.phase_deg.is_some())?;
        unused("mean", a.mean.is_some())?;
        let (times, lengths) = if a.kind == "csv" {
            unused("times", a.times.is_some())?;
            unused("lengths", a.lengths.is_some())?;
            let p = a.path.as_ref().ok_or_else(|| {
                Error::invalid(
                    "actuation.path",
                    "nothing",
                    "is required for kind = \"csv\"",
                )
            })?;
            if p.trim().is_empty() {
                return Err(Error::invalid(
                    "actuation.path",
                    format!("{p:?}"),
                    "is empty: name the CSV file of the actuation (relative to the model file)",
                ));
            }
            super::read_actuation_csv(&base_dir.join(p), links)?
        } else {
            unused("path", a.path.is_some())?;
            let times = a.times.clone().ok_or_else(|| {
                Error::invalid(
                    "actuation.times",
                    "nothing",
                    "is required for piecewise_linear",
                )
            })?;
            let rows = a.lengths.as_ref().ok_or_else(|| {
                Error::invalid(
                    "actuation.lengths",
                    "nothing",
                    "is required for piecewise_linear",
                )
            })?;
            let lengths = rows
                .iter()
                .enumerate()
                .map(|(j, r)| r.expand(&format!("actuation.lengths[{}]", j + 1), links, "link"))
                .collect::<Result<Vec<_>>>()?;
            (times, lengths)
        };
        Actuation::piecewise_linear(a.period, times, lengths)
    }

    /// The section as TOML text (`[actuation]` and its fields).
    pub fn to_toml(&self) -> Result<String> {
        #[derive(Serialize)]
        struct Section<'a> {
            actuation: &'a ActuationSpec,
        }
        toml::to_string(&Section { actuation: self }).map_err(|e| Error::Io {
            path: "<model>".into(),
            reason: format!("cannot write the actuation as TOML: {e}"),
        })
    }

    /// The number of links the section's lists imply (the length of the first list among
    /// `amplitude`, `mean`, `phase_deg` and the rows of `lengths`); None when every value is a
    /// single number, which fits a crawler of any size (the file form binds it to the
    /// crawler's links). Lists of other lengths are refused by [`ActuationSpec::actuation`].
    pub fn implied_links(&self) -> Option<usize> {
        [&self.amplitude, &self.mean, &self.phase_deg]
            .into_iter()
            .flatten()
            .chain(self.lengths.iter().flatten())
            .find_map(NumberOrList::list_len)
    }

    /// The section without reference to another file: a `csv` actuation becomes the
    /// `piecewise_linear` one through the knots it read (`actuation`, built from this
    /// section); other kinds are returned as they are.
    pub fn self_contained(&self, actuation: &Actuation) -> ActuationSpec {
        match actuation {
            Actuation::PiecewiseLinear {
                period,
                times,
                lengths,
            } if self.kind == "csv" => ActuationSpec {
                kind: "piecewise_linear".into(),
                period: *period,
                amplitude: None,
                phase_deg: None,
                mean: None,
                times: Some(times.clone()),
                lengths: Some(lengths.iter().map(|r| NumberOrList::of(r)).collect()),
                path: None,
            },
            _ => self.clone(),
        }
    }
}

/// Parses the TOML text of a model file of either kind into `T`; errors quote the line.
pub(crate) fn parse_toml<T: serde::de::DeserializeOwned>(text: &str) -> Result<T> {
    toml::from_str(text).map_err(|e| {
        let msg = escape_controls(&e.message().trim().replace('\n', "; ")).replace(
            "data did not match any variant of untagged enum NumberOrList",
            "expected a number or a list of numbers",
        );
        let at = e.span().map_or(String::new(), |span| {
            // Bytes, not a string slice: a span need not fall on a character boundary.
            let start = span.start.min(text.len());
            let line = text.as_bytes()[..start]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1;
            let src = quote_line(text.split('\n').nth(line - 1).unwrap_or(""));
            format!(" at line {line} (`{src}`)")
        });
        Error::Io {
            path: "<model>".into(),
            reason: format!("invalid model file{at}: {msg}"),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_and_lists_parse() {
        let m = ModelFile::parse(
            "[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = [1, 2, 3]\nmu_backward = 3.0\n",
        )
        .unwrap();
        let c = m.crawler().unwrap();
        assert_eq!(c.stiffness(), &[1.0, 1.0]);
        assert_eq!(c.mu_forward(), &[1.0, 2.0, 3.0]);
    }

    #[test]
    fn errors_name_the_field() {
        let e = ModelFile::parse(
            "[crawler]\nblocks = 3\nstiffness = 1\nmu_forward = [1, 2]\nmu_backward = 3.0\n",
        )
        .unwrap()
        .crawler()
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("crawler.mu_forward: needs a number or one value per block (3)"),
            "{e}"
        );
        let e = ModelFile::parse(
            "[crawler]\nblocks = 3\nstifness = 1\nmu_forward = 1\nmu_backward = 3.0\n",
        )
        .unwrap_err();
        assert!(e.to_string().contains("unknown field `stifness`"), "{e}");
        let e = ModelFile::parse(
            "[crawler]\nblocks = 1\nstiffness = 1\nmu_forward = 1\nmu_backward = 3.0\n",
        )
        .unwrap()
        .crawler()
        .unwrap_err();
        assert!(e.to_string().starts_with("crawler.blocks"), "{e}");
        let e = ModelFile::parse(
            "[crawler]\nblocks = 2\nstiffness = -1\nmu_forward = 1\nmu_backward = 3.0\n",
        )
        .unwrap()
        .crawler()
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "crawler.stiffness[1]: must be positive and finite (got -1)"
        );
        let e = ModelFile::parse(
            "[crawler]\nblocks = 2\nstiffness = nan\nmu_forward = 1\nmu_backward = 3.0\n",
        )
        .unwrap()
        .crawler()
        .unwrap_err();
        assert!(
            e.to_string()
                .starts_with("crawler.stiffness[1]: must be positive and finite"),
            "{e}"
        );
    }

    #[test]
    fn to_toml_reads_back_to_the_same_model() {
        let text = "[crawler]\nblocks = 3\nstiffness = [1.5, 0.1]\nmu_forward = 1\n\
                    mu_backward = [3.0, 0.3, 2]\n[actuation]\nkind = \"sine\"\nperiod = 0.7\n\
                    amplitude = 0.1\nphase_deg = [0, 33.3]\n[simulation]\n\
                    initial_state = [0.1, -0.2]\n[gait]\nperiod = 1\n\
                    max_actuator_speed = [1, 0.3]\n\
                    cost = { kind = \"quadratic\", weight = 0.1 }\nmax_total_variation = 3\n";
        let m = ModelFile::parse(text).unwrap();
        let written = m.to_toml().unwrap();
        assert_eq!(ModelFile::parse(&written).unwrap(), m, "{written}");
        assert_eq!(m.actuation.as_ref().unwrap().implied_links(), Some(2));
        // A crawler's section builds it back bit for bit; a single number where all agree.
        let c = m.crawler().unwrap();
        let spec = CrawlerSpec::of(&c);
        assert_eq!(spec.mu_forward, NumberOrList::One(1.0));
        assert_eq!(spec.crawler().unwrap(), c);
        // Without [actuation], [simulation] and [gait]: none written.
        let bare = ModelFile {
            actuation: None,
            simulation: SimulationSpec::default(),
            gait: None,
            ..m
        };
        let written = bare.to_toml().unwrap();
        assert!(!written.contains("[simulation]"), "{written}");
        assert_eq!(ModelFile::parse(&written).unwrap(), bare);
    }

    const CSV_MODEL: &str =
        "[crawler]\nblocks = 2\nstiffness = 1\nmu_forward = 1\nmu_backward = 3\n\
                             [actuation]\nkind = \"csv\"\nperiod = 1\npath = ";

    #[test]
    fn an_empty_csv_path_is_named_as_such() {
        for p in ["\"\"", "\"  \""] {
            let e = ModelFile::parse(&format!("{CSV_MODEL}{p}\n"))
                .unwrap()
                .actuation(1)
                .unwrap_err()
                .to_string();
            assert!(
                e.starts_with("actuation.path: is empty: name the CSV file"),
                "{e}"
            );
        }
    }

    #[test]
    fn only_regular_files_are_read() {
        let dir = std::env::temp_dir().join(format!("crawlopt-config-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let mut m = ModelFile::parse(&format!("{CSV_MODEL}\"sub\"\n")).unwrap();
        m.base_dir = dir.clone();
        let e = m.actuation(1).unwrap_err().to_string();
        assert!(e.ends_with("is a directory, not a file"), "{e}");
        let e = ModelFile::load(&dir).unwrap_err().to_string();
        assert!(e.ends_with("is a directory, not a file"), "{e}");
        // A device would be read without end (/dev/zero) or block (a FIFO): refused unopened.
        #[cfg(unix)]
        for dev in ["/dev/zero", "/dev/null"] {
            let e = ModelFile::load(Path::new(dev)).unwrap_err().to_string();
            assert!(e.contains("is not a regular file"), "{e}");
            m.actuation.as_mut().unwrap().path = Some(dev.into());
            let e = m.actuation(1).unwrap_err().to_string();
            assert!(e.contains("is not a regular file"), "{e}");
        }
        // Larger than the limit: refused after reading limit + 1 bytes.
        let big = dir.join("big.toml");
        std::fs::write(&big, vec![b'#'; 2000]).unwrap();
        let e = read_input_file(&big, 1000).unwrap_err();
        assert!(e.starts_with("larger than"), "{e}");
        assert_eq!(read_input_file(&big, 2000).unwrap().len(), 2000);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn parse_errors_quote_one_visible_line() {
        // A multi-byte character before the error, a control character and a long line.
        let text = format!("[crawler]\nblocks = \"é\u{1b}[31m{}\" x\n", "a".repeat(200));
        let e = ModelFile::parse(&text).unwrap_err().to_string();
        assert!(!e.contains('\u{1b}') && !e.contains('\n'), "{e}");
        assert!(e.contains("\\u{1b}") && e.contains("..."), "{e}");
        assert!(e.len() < 400, "{e}");
    }
}
