//! The machinery of the fuzz/property harness (`tests/fuzz_readers.rs`): mutators of files,
//! runners that tell a typed error from a panic, an abort or a hang, outcome counts, and the
//! driver that runs a property either once with a fixed seed (CI) or in batches with fresh seeds
//! until a duration has passed (`scripts/fuzz`).
//!
//! Environment (read by [`drive`]):
//! - `CRAWLOPT_FUZZ_SECONDS`: run each property for this many seconds, in batches of fresh
//!   random seeds, recording failures instead of stopping at the first (the long run);
//! - `CRAWLOPT_FUZZ_SEED`: the seed (a number) of the first batch, instead of the fixed CI seed
//!   or a random one;
//! - `CRAWLOPT_FUZZ_CASES`: cases per batch, instead of the property's CI count.
//!
//! Failing inputs are saved, shrunk, under `target/fuzz-findings/PROPERTY/` with a `.txt`
//! beside each saying what was run and what happened; counts by outcome go to
//! `target/fuzz-findings/stats/PROPERTY.json` and to stdout.
#![allow(dead_code)]

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestError, TestRng, TestRunner};
use serde_json::Value;
use std::cell::RefCell;
use std::collections::hash_map::DefaultHasher;
use std::collections::{BTreeMap, HashSet};
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{mpsc, Arc, Mutex, Once};
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------------------------
// Where things go.

/// The cargo target directory (the parent of `CARGO_TARGET_TMPDIR`).
pub fn target_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("CARGO_TARGET_TMPDIR has a parent")
        .to_path_buf()
}

/// `target/fuzz-findings`.
pub fn findings_dir() -> PathBuf {
    target_dir().join("fuzz-findings")
}

/// The repository root.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The binary under test.
pub fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_crawlopt"))
}

// ---------------------------------------------------------------------------------------------
// Mutations.

/// Replacement values for a number: extremes that are finite, non-finite written as the format
/// allows (raw tokens), wrong types, and ordinary small values.
#[derive(Debug, Clone, Copy)]
pub enum Extreme {
    F(f64),
    I(i64),
    /// Written verbatim into the file (TOML `nan`, JSON `1e400`, an integer beyond i64...).
    Raw(&'static str),
    /// A string where a number belongs.
    S(&'static str),
}

pub const EXTREMES: &[Extreme] = &[
    Extreme::F(0.0),
    Extreme::F(-0.0),
    Extreme::F(-1.0),
    Extreme::F(1.0),
    Extreme::F(1e-300),
    Extreme::F(-1e-300),
    Extreme::F(1e300),
    Extreme::F(-1e300),
    Extreme::F(1e20),
    Extreme::F(1e-20),
    Extreme::F(1e-8),
    Extreme::F(1e8),
    Extreme::F(1e12),
    Extreme::F(f64::MAX),
    Extreme::F(f64::MIN_POSITIVE),
    Extreme::F(5e-324),
    Extreme::F(0.5),
    Extreme::F(2.5),
    Extreme::F(1.0 + 1e-15),
    Extreme::I(0),
    Extreme::I(-1),
    Extreme::I(1),
    Extreme::I(2),
    Extreme::I(3),
    Extreme::I(1000),
    Extreme::I(100_000),
    Extreme::I(10_000_001),
    Extreme::I(i64::MAX),
    Extreme::I(i64::MIN),
    Extreme::I(u32::MAX as i64),
    Extreme::I(u32::MAX as i64 + 1),
    Extreme::Raw("nan"),
    Extreme::Raw("inf"),
    Extreme::Raw("-inf"),
    Extreme::Raw("NaN"),
    Extreme::Raw("1e400"),
    Extreme::Raw("-1e400"),
    Extreme::Raw("1e-400"),
    Extreme::Raw("-0"),
    Extreme::Raw("18446744073709551615"),
    Extreme::Raw("99999999999999999999999999999"),
    Extreme::Raw("0x10"),
    Extreme::Raw("1_000"),
    Extreme::S("NaN"),
    Extreme::S("inf"),
    Extreme::S("1.0"),
    Extreme::S(""),
];

/// Strings a string value may become (the vocabulary of the file kinds, and nonsense).
pub const WORDS: &[&str] = &[
    "sine",
    "triangle",
    "piecewise_linear",
    "csv",
    "none",
    "quadratic",
    "phase",
    "discrete",
    "local",
    "sequence",
    "global",
    "global_k_phases",
    "optimal",
    "optimal_among_k_phases",
    "time_limit",
    "piecewise_constant",
    "crawlopt-gait-result",
    "crawlopt-jm-table",
    "exact",
    "catching_up",
    "bogus",
    "",
    "gait.csv",
    "/dev/null",
    ".",
    "\u{0}",
    "é\u{202e}x",
];

/// One structural mutation of a value tree; selectors pick a node modulo the number of
/// candidates, so that every selector is valid on every tree and shrinking stays meaningful.
#[derive(Debug, Clone)]
pub enum Op {
    /// Replace a number (a field's value when `field`, else any, array entries included).
    Number { sel: u16, field: bool, with: usize },
    /// Multiply a number by `10^exp`.
    Scale { sel: u16, exp: i32 },
    /// Delete an object's key.
    Delete { sel: u16 },
    /// Shorten, lengthen (by one, eightfold, or to about 20000 numbers), empty, truncate to one
    /// entry, duplicate or remove an entry of, or reverse an array.
    Resize { sel: u16, mode: u8, at: u16 },
    /// Change a value's type.
    Retype { sel: u16, to: u8 },
    /// Replace a value by a copy of another one of the tree.
    Copy { from: u16, to: u16 },
    /// Add an unknown key to an object.
    AddKey { sel: u16 },
    /// Replace a string.
    Word { sel: u16, word: usize },
    /// Swap two entries of an array.
    Swap { sel: u16, i: u16, j: u16 },
    /// Wrap a value in `depth` arrays.
    Nest { sel: u16, depth: u8 },
}

/// Byte-level edits of a seed's text.
#[derive(Debug, Clone)]
pub enum TextEdit {
    /// Keep the first `permille / 1000` of the text.
    Truncate {
        permille: u16,
    },
    Delete {
        at: u16,
        len: u8,
    },
    Insert {
        at: u16,
        bytes: Vec<u8>,
    },
    /// Insert a token of the formats' syntax.
    Token {
        at: u16,
        token: usize,
    },
    Replace {
        at: u16,
        byte: u8,
    },
}

/// Tokens of TOML, JSON and CSV syntax and the field names of the file kinds.
pub const TOKENS: &[&str] = &[
    "[",
    "]",
    "{",
    "}",
    "[[",
    "]]",
    "=",
    ",",
    ":",
    "\"",
    "'",
    "\n",
    "\r\n",
    "#",
    ".",
    "-",
    "+",
    "e",
    "0",
    "1",
    "2",
    "1e300",
    "nan",
    "inf",
    "true",
    "null",
    "\"\"\"",
    "\\u0000",
    "[crawler]",
    "[actuation]",
    "[gait]",
    "[simulation]",
    "[gait.cost]",
    "blocks",
    "stiffness",
    "mu_forward",
    "mu_backward",
    "kind",
    "period",
    "amplitude",
    "phase_deg",
    "mean",
    "times",
    "lengths",
    "path",
    "initial_state",
    "max_actuator_speed",
    "cost",
    "weight",
    "max_total_variation",
    "\"format\"",
    "\"version\"",
    "\"gait\"",
    "\"solution\"",
    "\"durations\"",
    "\"m\"",
    "\"values\"",
    "\"continuous\"",
    "\u{0}",
    "\u{7f}",
    "\u{feff}",
];

/// A mutation of a seed file.
#[derive(Debug, Clone)]
pub enum Mutation {
    /// Arbitrary bytes instead of the file.
    Bytes(Vec<u8>),
    /// A soup of syntax tokens instead of the file.
    Tokens(Vec<usize>),
    /// Byte-level edits of the seed text.
    Text(Vec<TextEdit>),
    /// Structural mutations of the seed's value tree.
    Tree(Vec<Op>),
    /// Structural mutations, then byte-level edits.
    Both(Vec<Op>, Vec<TextEdit>),
}

fn op_strategy() -> impl Strategy<Value = Op> {
    prop_oneof![
        8 => (any::<u16>(), any::<bool>(), 0..EXTREMES.len())
            .prop_map(|(sel, field, with)| Op::Number { sel, field, with }),
        3 => (any::<u16>(), -40i32..40).prop_map(|(sel, exp)| Op::Scale { sel, exp }),
        1 => any::<u16>().prop_map(|sel| Op::Delete { sel }),
        3 => (any::<u16>(), 0u8..9, any::<u16>()).prop_map(|(sel, mode, at)| Op::Resize { sel, mode, at }),
        1 => (any::<u16>(), 0u8..7).prop_map(|(sel, to)| Op::Retype { sel, to }),
        1 => (any::<u16>(), any::<u16>()).prop_map(|(from, to)| Op::Copy { from, to }),
        1 => (any::<u16>(), 0..WORDS.len()).prop_map(|(sel, word)| Op::Word { sel, word }),
        1 => (any::<u16>(), 0u8..4).prop_map(|(sel, k)| if k == 0 { Op::AddKey { sel } } else { Op::Scale { sel, exp: 0 } }),
        1 => (any::<u16>(), any::<u16>(), any::<u16>()).prop_map(|(sel, i, j)| Op::Swap { sel, i, j }),
        1 => (any::<u16>(), any::<u8>()).prop_map(|(sel, depth)| Op::Nest { sel, depth }),
    ]
}

fn edit_strategy() -> impl Strategy<Value = TextEdit> {
    prop_oneof![
        1 => (0u16..1000).prop_map(|permille| TextEdit::Truncate { permille }),
        2 => (any::<u16>(), 1u8..16).prop_map(|(at, len)| TextEdit::Delete { at, len }),
        2 => (any::<u16>(), proptest::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(at, bytes)| TextEdit::Insert { at, bytes }),
        3 => (any::<u16>(), 0..TOKENS.len()).prop_map(|(at, token)| TextEdit::Token { at, token }),
        2 => (any::<u16>(), any::<u8>()).prop_map(|(at, byte)| TextEdit::Replace { at, byte }),
    ]
}

/// Mutations of a seed, weighted towards the structural ones (they get past the parser).
pub fn mutation_strategy() -> impl Strategy<Value = Mutation> {
    use proptest::collection::vec;
    prop_oneof![
        1 => vec(any::<u8>(), 0..300).prop_map(Mutation::Bytes),
        1 => vec(0..TOKENS.len(), 0..40).prop_map(Mutation::Tokens),
        2 => vec(edit_strategy(), 1..4).prop_map(Mutation::Text),
        12 => vec(op_strategy(), 1..4).prop_map(Mutation::Tree),
        1 => (vec(op_strategy(), 1..3), vec(edit_strategy(), 1..2))
            .prop_map(|(o, e)| Mutation::Both(o, e)),
    ]
}

/// Mutations that mostly keep a file well-formed and its numbers within a few orders of
/// magnitude (for the solvers, which the destructive ones rarely reach), one case in four
/// from [`mutation_strategy`].
pub fn gentle_mutation_strategy() -> impl Strategy<Value = Mutation> {
    use proptest::collection::vec;
    let op = prop_oneof![
        4 => (any::<u16>(), -6i32..7).prop_map(|(sel, exp)| Op::Scale { sel, exp }),
        2 => (any::<u16>(), 0..EXTREMES.len())
            .prop_map(|(sel, with)| Op::Number { sel, field: true, with }),
        1 => (any::<u16>(), 0u8..9, any::<u16>()).prop_map(|(sel, mode, at)| Op::Resize { sel, mode, at }),
    ];
    prop_oneof![
        3 => vec(op, 1..3).prop_map(Mutation::Tree),
        1 => mutation_strategy(),
    ]
}

/// The syntax of a seed file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Syntax {
    Toml,
    Json,
    /// CSV: the tree is an array of rows, each an array of cells (numbers where they parse).
    Csv,
}

/// A seed: its text and its value tree.
#[derive(Debug, Clone)]
pub struct Seed {
    pub name: String,
    pub text: String,
    pub syntax: Syntax,
    pub tree: Value,
}

impl Seed {
    pub fn new(name: impl Into<String>, text: impl Into<String>, syntax: Syntax) -> Self {
        let text = text.into();
        let tree = match syntax {
            Syntax::Toml => toml::from_str::<toml::Value>(&text)
                .map(|v| serde_json::to_value(v).expect("a TOML value is JSON"))
                .expect("a seed parses"),
            Syntax::Json => serde_json::from_str(&text).expect("a seed parses"),
            Syntax::Csv => Value::Array(
                text.lines()
                    .map(|l| {
                        Value::Array(
                            l.split(',')
                                .map(|c| {
                                    let c = c.trim();
                                    c.parse::<i64>()
                                        .map(Value::from)
                                        .or_else(|_| c.parse::<f64>().map(Value::from))
                                        .unwrap_or_else(|_| Value::String(c.into()))
                                })
                                .collect(),
                        )
                    })
                    .collect(),
            ),
        };
        Seed {
            name: name.into(),
            text,
            syntax,
            tree,
        }
    }

    /// The mutated file.
    pub fn render(&self, m: &Mutation) -> Vec<u8> {
        match m {
            Mutation::Bytes(b) => b.clone(),
            Mutation::Tokens(t) => t.iter().flat_map(|&i| TOKENS[i].bytes()).collect(),
            Mutation::Text(edits) => apply_edits(self.text.as_bytes().to_vec(), edits),
            Mutation::Tree(ops) => self.render_tree(ops),
            Mutation::Both(ops, edits) => apply_edits(self.render_tree(ops), edits),
        }
    }

    fn render_tree(&self, ops: &[Op]) -> Vec<u8> {
        let mut tree = self.tree.clone();
        let mut raws = Vec::new();
        for op in ops {
            apply_op(&mut tree, op, &mut raws, self.syntax);
        }
        serialize(&tree, &raws, self.syntax).into_bytes()
    }
}

fn apply_edits(mut b: Vec<u8>, edits: &[TextEdit]) -> Vec<u8> {
    let pos = |at: u16, len: usize| (at as usize) % (len + 1);
    for e in edits {
        match e {
            TextEdit::Truncate { permille } => {
                let keep = b.len() * (*permille as usize) / 1000;
                b.truncate(keep);
            }
            TextEdit::Delete { at, len } => {
                let s = pos(*at, b.len());
                let e = (s + *len as usize).min(b.len());
                b.drain(s..e);
            }
            TextEdit::Insert { at, bytes } => {
                let s = pos(*at, b.len());
                b.splice(s..s, bytes.iter().copied());
            }
            TextEdit::Token { at, token } => {
                let s = pos(*at, b.len());
                b.splice(s..s, TOKENS[*token].bytes());
            }
            TextEdit::Replace { at, byte } => {
                if !b.is_empty() {
                    let s = (*at as usize) % b.len();
                    b[s] = *byte;
                }
            }
        }
    }
    b
}

#[derive(Debug, Clone)]
enum Seg {
    Key(String),
    Idx(usize),
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Number,
    String,
    Array,
    Object,
    Other,
}

fn walk(v: &Value, path: &mut Vec<Seg>, out: &mut Vec<(Vec<Seg>, Kind)>) {
    let kind = match v {
        Value::Number(_) => Kind::Number,
        Value::String(_) => Kind::String,
        Value::Array(_) => Kind::Array,
        Value::Object(_) => Kind::Object,
        _ => Kind::Other,
    };
    out.push((path.clone(), kind));
    match v {
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Seg::Idx(i));
                walk(x, path, out);
                path.pop();
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                path.push(Seg::Key(k.clone()));
                walk(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn get_mut<'a>(mut v: &'a mut Value, path: &[Seg]) -> Option<&'a mut Value> {
    for s in path {
        v = match (s, v) {
            (Seg::Key(k), Value::Object(o)) => o.get_mut(k)?,
            (Seg::Idx(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

fn get<'a>(mut v: &'a Value, path: &[Seg]) -> Option<&'a Value> {
    for s in path {
        v = match (s, v) {
            (Seg::Key(k), Value::Object(o)) => o.get(k)?,
            (Seg::Idx(i), Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

fn pick<T: Clone>(items: &[T], sel: u16) -> Option<T> {
    (!items.is_empty()).then(|| items[sel as usize % items.len()].clone())
}

const RAW_MARK: &str = "@@FUZZRAW";

fn raw(raws: &mut Vec<String>, token: &str) -> Value {
    raws.push(token.to_string());
    Value::String(format!("{RAW_MARK}{}@@", raws.len() - 1))
}

fn extreme_value(e: Extreme, raws: &mut Vec<String>, syntax: Syntax) -> Value {
    match e {
        Extreme::F(x) => serde_json::Number::from_f64(x)
            .map(Value::Number)
            .unwrap_or(Value::Null),
        Extreme::I(i) => Value::from(i),
        // JSON has no nan/inf: written raw they make the file invalid, which is a case too.
        Extreme::Raw(t) if syntax == Syntax::Json && t == "nan" => raw(raws, "NaN"),
        Extreme::Raw(t) => raw(raws, t),
        Extreme::S(s) => Value::String(s.into()),
    }
}

fn apply_op(tree: &mut Value, op: &Op, raws: &mut Vec<String>, syntax: Syntax) {
    let mut nodes = Vec::new();
    walk(tree, &mut Vec::new(), &mut nodes);
    let of_kind = |k: Kind| -> Vec<Vec<Seg>> {
        nodes
            .iter()
            .filter(|(_, kind)| *kind == k)
            .map(|(p, _)| p.clone())
            .collect()
    };
    match op {
        Op::Number { sel, field, with } => {
            let nums: Vec<Vec<Seg>> = of_kind(Kind::Number)
                .into_iter()
                .filter(|p| !field || matches!(p.last(), Some(Seg::Key(_))))
                .collect();
            if let Some(p) = pick(&nums, *sel) {
                let v = extreme_value(EXTREMES[*with], raws, syntax);
                if let Some(slot) = get_mut(tree, &p) {
                    *slot = v;
                }
            }
        }
        Op::Scale { sel, exp } => {
            if let Some(p) = pick(&of_kind(Kind::Number), *sel) {
                if let Some(slot) = get_mut(tree, &p) {
                    let x = slot.as_f64().unwrap_or(1.0);
                    let y = x * 10f64.powi(*exp);
                    if let Some(n) = serde_json::Number::from_f64(y) {
                        *slot = Value::Number(n);
                    }
                }
            }
        }
        Op::Delete { sel } => {
            let keys: Vec<Vec<Seg>> = nodes
                .iter()
                .filter(|(p, _)| matches!(p.last(), Some(Seg::Key(_))))
                .map(|(p, _)| p.clone())
                .collect();
            if let Some(p) = pick(&keys, *sel) {
                let (last, parent) = p.split_last().expect("a key path");
                if let (Some(Value::Object(o)), Seg::Key(k)) = (get_mut(tree, parent), last) {
                    o.remove(k);
                }
            }
        }
        Op::Resize { sel, mode, at } => {
            if let Some(p) = pick(&of_kind(Kind::Array), *sel) {
                if let Some(Value::Array(a)) = get_mut(tree, &p) {
                    let n = a.len();
                    match mode {
                        0 => {
                            a.pop();
                        }
                        1 => {
                            if let Some(x) = a.last().cloned() {
                                a.push(x);
                            }
                        }
                        2 => a.clear(),
                        3 if n > 0 => {
                            let i = *at as usize % n;
                            let x = a[i].clone();
                            a.insert(i, x);
                        }
                        4 => a.truncate(1),
                        5 if n > 0 => {
                            a.remove(*at as usize % n);
                        }
                        6 => {
                            let copy = a.clone();
                            for _ in 0..7 {
                                a.extend(copy.iter().cloned());
                            }
                        }
                        // Long: about 20000 scalars in all (a resource the reader must bound
                        // or afford).
                        7 if n > 0 => {
                            let width = a[0].as_array().map_or(1, |r| r.len().max(1));
                            let want = (20_000 / width).max(n);
                            let copy = a.clone();
                            while a.len() < want {
                                a.push(copy[a.len() % n].clone());
                            }
                        }
                        _ => a.reverse(),
                    }
                }
            }
        }
        Op::Retype { sel, to } => {
            let all: Vec<Vec<Seg>> = nodes.iter().map(|(p, _)| p.clone()).collect();
            if let Some(p) = pick(&all, *sel) {
                if let Some(slot) = get_mut(tree, &p) {
                    let old = slot.clone();
                    *slot = match to {
                        0 => Value::String(match &old {
                            Value::String(s) => s.clone(),
                            other => other.to_string(),
                        }),
                        1 => Value::Bool(true),
                        2 => Value::Array(vec![old]),
                        3 => Value::Object(Default::default()),
                        4 => Value::Null,
                        5 => Value::from(1),
                        _ => match old {
                            Value::Array(a) => a.into_iter().next().unwrap_or(Value::Null),
                            Value::Object(o) => o.into_iter().next().map_or(Value::Null, |x| x.1),
                            other => Value::Array(vec![other.clone(), other]),
                        },
                    };
                }
            }
        }
        Op::Copy { from, to } => {
            let all: Vec<Vec<Seg>> = nodes.iter().map(|(p, _)| p.clone()).collect();
            if let (Some(f), Some(t)) = (pick(&all, *from), pick(&all, *to)) {
                if let Some(v) = get(tree, &f).cloned() {
                    if let Some(slot) = get_mut(tree, &t) {
                        *slot = v;
                    }
                }
            }
        }
        Op::AddKey { sel } => {
            if let Some(p) = pick(&of_kind(Kind::Object), *sel) {
                if let Some(Value::Object(o)) = get_mut(tree, &p) {
                    o.insert("fuzz_unknown".into(), Value::from(1));
                }
            }
        }
        Op::Word { sel, word } => {
            if let Some(p) = pick(&of_kind(Kind::String), *sel) {
                if let Some(slot) = get_mut(tree, &p) {
                    *slot = Value::String(WORDS[*word].into());
                }
            }
        }
        Op::Nest { sel, depth } => {
            let all: Vec<Vec<Seg>> = nodes.iter().map(|(p, _)| p.clone()).collect();
            if let Some(p) = pick(&all, *sel) {
                if let Some(slot) = get_mut(tree, &p) {
                    for _ in 0..*depth {
                        *slot = Value::Array(vec![slot.take()]);
                    }
                }
            }
        }
        Op::Swap { sel, i, j } => {
            if let Some(p) = pick(&of_kind(Kind::Array), *sel) {
                if let Some(Value::Array(a)) = get_mut(tree, &p) {
                    if !a.is_empty() {
                        let n = a.len();
                        a.swap(*i as usize % n, *j as usize % n);
                    }
                }
            }
        }
    }
}

/// Nulls have no TOML form: they become an empty value (`key = `), a syntax error.
fn nulls_to_raw(v: &mut Value, raws: &mut Vec<String>) {
    match v {
        Value::Null => *v = raw(raws, ""),
        Value::Array(a) => a.iter_mut().for_each(|x| nulls_to_raw(x, raws)),
        Value::Object(o) => o.values_mut().for_each(|x| nulls_to_raw(x, raws)),
        _ => {}
    }
}

fn serialize(tree: &Value, raws: &[String], syntax: Syntax) -> String {
    let mut raws = raws.to_vec();
    let text = match syntax {
        Syntax::Json => serde_json::to_string(tree).expect("a JSON value serialises"),
        Syntax::Csv => {
            let cell = |v: &Value| match v {
                Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            match tree {
                Value::Array(rows) => rows
                    .iter()
                    .map(|r| match r {
                        Value::Array(cells) => {
                            cells.iter().map(cell).collect::<Vec<_>>().join(", ")
                        }
                        other => cell(other),
                    })
                    .map(|l| l + "\n")
                    .collect(),
                other => cell(other),
            }
        }
        Syntax::Toml => {
            let mut t = tree.clone();
            nulls_to_raw(&mut t, &mut raws);
            match &t {
                Value::Object(_) => toml::to_string(&t).unwrap_or_else(|e| format!("# {e}\n")),
                // A document that is not a table: what a user would get by pasting a value.
                other => format!("{other}\n"),
            }
        }
    };
    let mut out = text;
    for (i, r) in raws.iter().enumerate().rev() {
        let mark = format!("{RAW_MARK}{i}@@");
        out = out
            .replace(&format!("\"{mark}\""), r)
            .replace(&format!("'{mark}'"), r)
            .replace(&mark, r);
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Running things.

/// How one run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The process exited with this status.
    Exit(i32),
    /// The process was killed by this signal (an abort is 6, a stack overflow 11).
    Signal(i32),
    /// No answer before the deadline (process killed).
    Hang,
    /// In-process: the call returned `Ok`.
    Ok,
    /// In-process: the call returned a typed error.
    Err,
    /// In-process: the call panicked with this message (and location).
    Panic(String),
}

impl Outcome {
    /// The class counted in the statistics.
    pub fn class(&self) -> String {
        match self {
            Outcome::Exit(c @ (0 | 2 | 3)) => format!("exit {c}"),
            Outcome::Exit(c) => format!("other (exit {c})"),
            Outcome::Signal(s) => format!("other (signal {s})"),
            Outcome::Hang => "other (hang)".into(),
            Outcome::Ok => "ok".into(),
            Outcome::Err => "error".into(),
            Outcome::Panic(_) => "other (panic)".into(),
        }
    }
}

/// A finished run of the binary.
#[derive(Debug, Clone)]
pub struct BinRun {
    pub args: Vec<String>,
    pub outcome: Outcome,
    pub stdout: String,
    pub stderr: String,
    pub seconds: f64,
}

impl BinRun {
    /// The command as a user would type it (paths relative to the case directory).
    pub fn command(&self) -> String {
        format!("crawlopt {}", self.args.join(" "))
    }
}

/// Address-space limit of the processes spawned (KiB): an allocation without bound ends in an
/// abort rather than taking the machine's memory.
pub const MEMORY_LIMIT_KIB: u64 = 4 * 1024 * 1024;

/// Runs the binary in `dir` with `args`, killing it after `deadline`.
pub fn run_bin(dir: &Path, args: &[&str], deadline: Duration) -> BinRun {
    let out_path = dir.join(".stdout");
    let err_path = dir.join(".stderr");
    let start = Instant::now();
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_LIMIT_KIB}; exec \"$0\" \"$@\""))
        .arg(bin())
        .args(args)
        .current_dir(dir)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).expect("stdout file"))
        .stderr(std::fs::File::create(&err_path).expect("stderr file"))
        .spawn()
        .expect("the binary starts");
    let mut nap = Duration::from_millis(1);
    let outcome = loop {
        match child.try_wait().expect("wait") {
            Some(status) => {
                use std::os::unix::process::ExitStatusExt;
                break match (status.code(), status.signal()) {
                    (Some(c), _) => Outcome::Exit(c),
                    (None, Some(s)) => Outcome::Signal(s),
                    _ => Outcome::Exit(-1),
                };
            }
            None if start.elapsed() > deadline => {
                let _ = child.kill();
                let _ = child.wait();
                break Outcome::Hang;
            }
            None => {
                std::thread::sleep(nap);
                nap = (nap * 2).min(Duration::from_millis(20));
            }
        }
    };
    // All of stdout (a --json document is checked whole), the start of stderr.
    let read = |p: &Path, cut: usize| {
        let b = std::fs::read(p).unwrap_or_default();
        String::from_utf8_lossy(&b[..b.len().min(cut)]).into_owned()
    };
    let run = BinRun {
        args: args.iter().map(|s| s.to_string()).collect(),
        outcome,
        stdout: read(&out_path, usize::MAX),
        stderr: read(&err_path, 1 << 16),
        seconds: start.elapsed().as_secs_f64(),
    };
    if std::env::var_os("CRAWLOPT_FUZZ_VERBOSE").is_some() {
        println!(
            "{} -> {:?} in {:.2} s: {}",
            run.command(),
            run.outcome,
            run.seconds,
            run.stderr.lines().next().unwrap_or("")
        );
    }
    run
}

thread_local! {
    static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
}

static HOOK: Once = Once::new();

/// Panics in worker threads are recorded (message and location) instead of printed.
fn install_panic_hook() {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let worker = std::thread::current()
                .name()
                .is_some_and(|n| n.starts_with("fuzz-worker"));
            if worker {
                let msg = info
                    .payload()
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| info.payload().downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "(non-string payload)".into());
                let loc = info
                    .location()
                    .map_or(String::new(), |l| format!(" at {}:{}", l.file(), l.line()));
                LAST_PANIC.with(|p| *p.borrow_mut() = Some(format!("{msg}{loc}")));
            } else {
                default(info);
            }
        }));
    });
}

/// Steps of an in-process chain, each with its outcome (the last one may have panicked).
#[derive(Debug, Default, Clone)]
pub struct Steps(pub Arc<Mutex<Vec<(String, Outcome, String)>>>);

impl Steps {
    /// Runs one step; its `Err` is recorded as a typed error and returned as `None`.
    pub fn step<T, E: std::fmt::Display>(
        &self,
        name: &str,
        f: impl FnOnce() -> Result<T, E>,
    ) -> Option<T> {
        self.0
            .lock()
            .unwrap()
            .push((name.into(), Outcome::Hang, String::new()));
        let r = f();
        let mut v = self.0.lock().unwrap();
        let last = v.last_mut().expect("pushed above");
        match r {
            Ok(x) => {
                last.1 = Outcome::Ok;
                Some(x)
            }
            Err(e) => {
                last.1 = Outcome::Err;
                last.2 = e.to_string();
                None
            }
        }
    }

    pub fn list(&self) -> Vec<(String, Outcome, String)> {
        self.0.lock().unwrap().clone()
    }
}

/// Runs `f` (a chain of library calls recording its steps) in a worker thread with a deadline:
/// the steps with their outcomes; a panic marks the step it happened in, a deadline passed marks
/// the unfinished step as a hang (the thread is left behind).
pub fn in_process(
    deadline: Duration,
    f: impl FnOnce(&Steps) + Send + 'static,
) -> Vec<(String, Outcome, String)> {
    install_panic_hook();
    let steps = Steps::default();
    let s2 = steps.clone();
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("fuzz-worker".into())
        .stack_size(8 << 20)
        .spawn(move || {
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(&s2)));
            let msg = LAST_PANIC.with(|p| p.borrow_mut().take());
            let _ = tx.send(r.err().map(|_| msg.unwrap_or_else(|| "panic".into())));
        })
        .expect("a worker thread");
    match rx.recv_timeout(deadline) {
        Ok(None) => steps.list(),
        Ok(Some(panic)) => {
            let mut v = steps.list();
            match v.last_mut() {
                Some(last) if last.1 == Outcome::Hang => {
                    last.1 = Outcome::Panic(panic.clone());
                    last.2 = panic;
                }
                _ => v.push(("(chain)".into(), Outcome::Panic(panic.clone()), panic)),
            }
            v
        }
        Err(_) => steps.list(),
    }
}

// ---------------------------------------------------------------------------------------------
// Statistics and findings.

/// Counts by consumer and outcome class, and the distinct inputs tried.
#[derive(Debug, Default)]
pub struct Stats {
    pub inputs: HashSet<u64>,
    pub runs: u64,
    pub by: BTreeMap<String, BTreeMap<String, u64>>,
    pub findings: BTreeMap<String, u64>,
    pub seeds: Vec<u64>,
    /// The slowest run of each binary consumer: seconds and outcome class.
    pub slowest: BTreeMap<String, (f64, String)>,
}

impl Stats {
    pub fn count(&mut self, consumer: &str, class: &str) {
        *self
            .by
            .entry(consumer.into())
            .or_default()
            .entry(class.into())
            .or_default() += 1;
    }

    /// Totals by class over every consumer.
    pub fn totals(&self) -> BTreeMap<String, u64> {
        let mut t = BTreeMap::new();
        for m in self.by.values() {
            for (k, v) in m {
                *t.entry(k.clone()).or_default() += v;
            }
        }
        t
    }

    pub fn to_json(&self, property: &str) -> Value {
        serde_json::json!({
            "property": property,
            "distinct_inputs": self.inputs.len(),
            "cases_run": self.runs,
            "seeds": self.seeds,
            "totals": self.totals(),
            "by_consumer": self.by,
            "findings": self.findings,
            "slowest_seconds": self.slowest,
        })
    }
}

pub fn hash_bytes(parts: &[&[u8]]) -> u64 {
    let mut h = DefaultHasher::new();
    for p in parts {
        p.hash(&mut h);
    }
    h.finish()
}

/// A failed case: its files, the command or call, and what happened.
#[derive(Debug, Clone)]
pub struct Failure {
    /// Short signature for deduplication, e.g. `optimize: panic at .../lib.rs:204`.
    pub signature: String,
    /// The full description.
    pub detail: String,
}

/// One case's input files (name, bytes): what a finding saves.
pub type Files = Vec<(String, Vec<u8>)>;

/// Saves a failing input under `target/fuzz-findings/PROPERTY/` (once per signature and input);
/// returns the folder.
pub fn save_finding(property: &str, files: &Files, failure: &Failure) -> PathBuf {
    let h = hash_bytes(
        &files
            .iter()
            .flat_map(|(n, b)| [n.as_bytes(), b.as_slice()])
            .collect::<Vec<_>>(),
    );
    let slug: String = failure
        .signature
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect::<String>()
        .split('-')
        .filter(|s| !s.is_empty())
        .take(8)
        .collect::<Vec<_>>()
        .join("-");
    let dir = findings_dir()
        .join(property)
        .join(format!("{slug}-{:08x}", h as u32));
    std::fs::create_dir_all(&dir).expect("findings directory");
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).expect("finding file");
    }
    std::fs::write(
        dir.join("FINDING.txt"),
        format!("{}\n\n{}\n", failure.signature, failure.detail),
    )
    .expect("finding description");
    dir
}

/// Text of an input for a message: lossy UTF-8, cut after 3000 bytes.
pub fn show(bytes: &[u8]) -> String {
    let s = String::from_utf8_lossy(&bytes[..bytes.len().min(3000)]).into_owned();
    if bytes.len() > 3000 {
        format!("{s}... ({} bytes)", bytes.len())
    } else {
        s
    }
}

// ---------------------------------------------------------------------------------------------
// The driver.

/// How long to run and with which seeds.
#[derive(Debug, Clone)]
pub struct Plan {
    /// `Some(seconds)`: the long run.
    pub seconds: Option<f64>,
    pub first_seed: Option<u64>,
    pub cases: u32,
}

impl Plan {
    pub fn from_env(ci_cases: u32) -> Self {
        let num = |k: &str| {
            std::env::var(k)
                .ok()
                .and_then(|v| v.trim().parse::<f64>().ok())
        };
        Plan {
            seconds: num("CRAWLOPT_FUZZ_SECONDS").filter(|s| *s > 0.0),
            first_seed: std::env::var("CRAWLOPT_FUZZ_SEED")
                .ok()
                .and_then(|v| v.trim().parse().ok()),
            cases: num("CRAWLOPT_FUZZ_CASES").map_or(ci_cases, |c| c.max(1.0) as u32),
        }
    }
}

/// The seed of the CI run: fixed, so that CI is reproducible.
pub const CI_SEED: u64 = 0x00c0_ffee_2018;

fn rng_of(seed: u64) -> TestRng {
    let mut bytes = [0u8; 32];
    for (i, chunk) in bytes.chunks_mut(8).enumerate() {
        chunk.copy_from_slice(
            &(seed ^ (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)).to_le_bytes(),
        );
    }
    TestRng::from_seed(RngAlgorithm::ChaCha, &bytes)
}

fn fresh_seed(n: u64) -> u64 {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    hash_bytes(&[
        &t.to_le_bytes(),
        &n.to_le_bytes(),
        &std::process::id().to_le_bytes(),
    ])
}

/// Runs the property `check` over cases of `strategy`. `check` renders a case into files, runs
/// every consumer and counts outcomes in the stats; it returns the files and the failure, if
/// any. CI (no `CRAWLOPT_FUZZ_SECONDS`): one batch with the fixed seed, panicking with the
/// shrunk input on a failure. Long run: batches with fresh seeds until the time is up, every
/// failure saved and the run continued.
pub fn drive<S>(
    property: &str,
    ci_cases: u32,
    strategy: S,
    check: impl Fn(&S::Value, &mut Stats) -> (Files, Option<Failure>),
) where
    S: Strategy,
    S::Value: std::fmt::Debug,
{
    let plan = Plan::from_env(ci_cases);
    let long = plan.seconds.is_some();
    let started = Instant::now();
    let stats = Mutex::new(Stats::default());
    // Long run: signatures already found (and shrunk) count as repeats and are not shrunk again.
    let known: Mutex<HashSet<String>> = Mutex::new(HashSet::new());
    let mut failures: Vec<(PathBuf, Failure, String)> = Vec::new();
    let mut batch = 0u64;
    let mut next_report = Duration::from_secs(30);
    loop {
        let seed = match (batch, plan.first_seed, long) {
            (0, Some(s), _) => s,
            (0, None, false) => CI_SEED,
            _ => fresh_seed(batch),
        };
        stats.lock().unwrap().seeds.push(seed);
        let config = Config {
            cases: plan.cases,
            failure_persistence: None,
            max_shrink_iters: if long { 400 } else { 150 },
            max_shrink_time: if long { 120_000 } else { 30_000 },
            max_global_rejects: 100_000,
            ..Config::default()
        };
        let mut runner = TestRunner::new_with_rng(config, rng_of(seed));
        let result = runner.run(&strategy, |case| {
            let mut st = stats.lock().unwrap();
            let (files, failure) = check(&case, &mut st);
            let parts: Vec<&[u8]> = files
                .iter()
                .flat_map(|(n, b)| [n.as_bytes(), b.as_slice()])
                .collect();
            st.inputs.insert(hash_bytes(&parts));
            st.runs += 1;
            match failure {
                None => Ok(()),
                Some(f) if long && known.lock().unwrap().contains(&f.signature) => {
                    *st.findings.entry(f.signature).or_default() += 1;
                    Ok(())
                }
                Some(f) => Err(TestCaseError::fail(format!(
                    "{}\n{}",
                    f.signature, f.detail
                ))),
            }
        });
        if let Err(e) = result {
            let minimal = match e {
                TestError::Fail(_, v) => v,
                TestError::Abort(why) => panic!("{property}: the runner gave up: {why}"),
            };
            // Run the minimal case again to save its files and its own failure.
            let mut st = stats.lock().unwrap();
            let (files, failure) = check(&minimal, &mut st);
            let failure = failure.unwrap_or_else(|| Failure {
                signature: "flaky (did not fail again)".into(),
                detail: format!("{minimal:?}"),
            });
            *st.findings.entry(failure.signature.clone()).or_default() += 1;
            known.lock().unwrap().insert(failure.signature.clone());
            drop(st);
            let dir = save_finding(property, &files, &failure);
            let inputs = files
                .iter()
                .map(|(n, b)| format!("--- {n} ---\n{}", show(b)))
                .collect::<Vec<_>>()
                .join("\n");
            println!(
                "{property}: FINDING (seed {seed}) saved in {}: {}",
                dir.display(),
                failure.signature
            );
            failures.push((dir, failure, inputs));
            if !long {
                break;
            }
        }
        batch += 1;
        if long && started.elapsed() >= next_report {
            next_report += Duration::from_secs(30);
            let st = stats.lock().unwrap();
            println!(
                "{property}: {batch} batches (last seed {seed}) at {:.0} s: {} distinct inputs, {} findings",
                started.elapsed().as_secs_f64(),
                st.inputs.len(),
                st.findings.values().sum::<u64>()
            );
        }
        match plan.seconds {
            Some(s) if started.elapsed().as_secs_f64() < s => continue,
            _ => break,
        }
    }
    let st = stats.into_inner().unwrap();
    let summary = st.to_json(property);
    let stats_dir = findings_dir().join("stats");
    std::fs::create_dir_all(&stats_dir).expect("stats directory");
    std::fs::write(
        stats_dir.join(format!("{property}.json")),
        serde_json::to_string_pretty(&summary).unwrap(),
    )
    .expect("stats file");
    println!(
        "{property}: {} distinct inputs, {} cases in {:.1} s; outcomes {}",
        st.inputs.len(),
        st.runs,
        started.elapsed().as_secs_f64(),
        serde_json::to_string(&summary["totals"]).unwrap()
    );
    if !long {
        if let Some((dir, f, inputs)) = failures.first() {
            panic!(
                "{property}: {}\n{}\n\ninput (saved in {}):\n{inputs}",
                f.signature,
                f.detail,
                dir.display()
            );
        }
    }
}

/// Checks a binary run: exit 0, 2 (with a message) or one of `also` (3 for simulate); with
/// `--json` and exit 0, stdout must be one JSON document.
pub fn judge_bin(consumer: &str, run: &BinRun, also: &[i32], stats: &mut Stats) -> Option<Failure> {
    stats.count(consumer, &run.outcome.class());
    let slot = stats
        .slowest
        .entry(consumer.into())
        .or_insert((0.0, String::new()));
    if run.seconds > slot.0 {
        *slot = (run.seconds, run.outcome.class());
    }
    let bad = |why: &str| {
        let tail: String = run
            .stderr
            .lines()
            .filter(|l| !l.trim().is_empty())
            .take(6)
            .collect::<Vec<_>>()
            .join("\n");
        Some(Failure {
            signature: format!("{consumer}: {why}"),
            detail: format!(
                "command: {}\noutcome: {:?} after {:.1} s\nstderr:\n{tail}",
                run.command(),
                run.outcome,
                run.seconds
            ),
        })
    };
    match &run.outcome {
        Outcome::Exit(0) => {
            if run.args.iter().any(|a| a == "--json")
                && serde_json::from_str::<Value>(&run.stdout).is_err()
            {
                return bad("exit 0 but --json output is not one JSON document");
            }
            None
        }
        Outcome::Exit(2) => {
            if run.stderr.trim().is_empty() {
                return bad("exit 2 without a message");
            }
            None
        }
        Outcome::Exit(c) if also.contains(c) => None,
        Outcome::Exit(101) => bad(&format!("panic {}", panic_site(&run.stderr))),
        Outcome::Exit(c) => bad(&format!("exit {c}")),
        Outcome::Signal(s) => bad(&format!("signal {s}{}", abort_reason(&run.stderr))),
        Outcome::Hang => bad("hang"),
        other => bad(&format!("{other:?}")),
    }
}

/// Checks the steps of an in-process chain: each counted; a panic or a hang fails.
pub fn judge_steps(
    consumer: &str,
    steps: &[(String, Outcome, String)],
    stats: &mut Stats,
) -> Option<Failure> {
    let mut failure = None;
    if std::env::var_os("CRAWLOPT_FUZZ_VERBOSE").is_some() {
        for (name, outcome, msg) in steps {
            println!("  {consumer}: {name} -> {}: {msg}", outcome.class());
        }
    }
    for (name, outcome, msg) in steps {
        stats.count(&format!("{consumer}: {name}"), &outcome.class());
        if failure.is_none() && matches!(outcome, Outcome::Panic(_) | Outcome::Hang) {
            let what = match outcome {
                Outcome::Hang => "hang".to_string(),
                _ => format!("panic {}", panic_location(msg)),
            };
            failure = Some(Failure {
                signature: format!("{consumer}: {name}: {what}"),
                detail: format!("in-process call `{name}`: {outcome:?}\n{msg}"),
            });
        }
    }
    failure
}

/// `file:line` of a panic message recorded by the hook.
fn panic_location(msg: &str) -> String {
    msg.rsplit_once(" at ")
        .map_or_else(|| msg.chars().take(80).collect(), |(_, l)| strip_home(l))
}

/// `file:line` of the panic printed by a process (`thread 'main' panicked at FILE:LINE:COL:`).
fn panic_site(stderr: &str) -> String {
    stderr
        .lines()
        .find_map(|l| {
            l.split_once("panicked at ")
                .map(|(_, r)| r.trim_end_matches(':'))
        })
        .map(|s| {
            let s = strip_home(s);
            // Drop the column: the line is the site.
            match s.rsplit_once(':') {
                Some((a, c)) if c.chars().all(|ch| ch.is_ascii_digit()) => a.to_string(),
                _ => s,
            }
        })
        .unwrap_or_else(|| "(no location)".into())
}

fn abort_reason(stderr: &str) -> String {
    stderr
        .lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .map_or(String::new(), |l| {
            format!(" ({})", l.chars().take(80).collect::<String>())
        })
}

/// Paths of the cargo registry shortened to the crate's name and version.
fn strip_home(s: &str) -> String {
    match s.find("/registry/src/") {
        Some(i) => {
            let rest = &s[i + "/registry/src/".len()..];
            rest.split_once('/').map_or(rest, |(_, r)| r).to_string()
        }
        None => s.to_string(),
    }
}
