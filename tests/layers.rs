//! The layers of `src/` as the folders show them (the map in `src/lib.rs`'s documentation):
//! no file imports from a layer above its own, and no files import each other in a cycle.
//!
//! Each source file is a module (`a/b.rs` and `a/b/mod.rs` are `a::b`; `cli/main.rs` is the
//! binary's root `cli`). Its dependencies are the paths it names through `crate::`, `super::`,
//! `self::` or a child module declared in it, in `use` items and inline, outside comments,
//! strings and its `#[cfg(test)] mod tests`. A path resolves to the longest module prefix; a
//! name that prefix re-exports (`pub use child::Name`) resolves to where it comes from, and a
//! re-export is not a dependency of the module that makes it (a facade, not a user) unless
//! the module's own code uses the name bare.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Layers, lowest first; a module of the library is in the layer of its top-level module.
const LAYERS: &[&[&str]] = &[
    &["error", "progress", "number", "linalg"],
    &["model"],
    &["sweep"],
    &["integrate"],
    &["optimal"],
    &["certify", "fit"],
    &["io", "present"],
    &["api"],
    &["study"],
    &["cli"],
];

/// Known exceptions, each with its way out: `(from, to)`. None today; an entry needs a reason
/// and the change that will remove it.
const ALLOWED: &[(&str, &str)] = &[];

type Module = Vec<String>;

fn name(m: &[String]) -> String {
    if m.is_empty() {
        "crate".into()
    } else {
        m.join("::")
    }
}

/// The source with comments removed and string and character literals emptied.
fn strip(s: &str) -> String {
    let b: Vec<char> = s.chars().collect();
    let (mut out, mut i, n) = (String::with_capacity(s.len()), 0, b.len());
    let at = |i: usize, p: &str| p.chars().enumerate().all(|(k, c)| b.get(i + k) == Some(&c));
    while i < n {
        if at(i, "//") {
            while i < n && b[i] != '\n' {
                i += 1;
            }
        } else if at(i, "/*") {
            let mut depth = 0;
            while i < n {
                if at(i, "/*") {
                    depth += 1;
                    i += 2;
                } else if at(i, "*/") {
                    depth -= 1;
                    i += 2;
                } else {
                    i += 1;
                }
                if depth == 0 {
                    break;
                }
            }
        } else if (b[i] == 'r' || (b[i] == 'b' && b.get(i + 1) == Some(&'r')))
            && (i == 0 || !(b[i - 1].is_alphanumeric() || b[i - 1] == '_'))
            && {
                let mut j = i + if b[i] == 'b' { 2 } else { 1 };
                while b.get(j) == Some(&'#') {
                    j += 1;
                }
                b.get(j) == Some(&'"')
            }
        {
            // A raw string r#"..."#: find the quote followed by as many hashes.
            let mut j = i + if b[i] == 'b' { 2 } else { 1 };
            let mut hashes = 0;
            while b[j] == '#' {
                hashes += 1;
                j += 1;
            }
            j += 1;
            loop {
                if b[j] == '"' && (1..=hashes).all(|k| b.get(j + k) == Some(&'#')) {
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j + 1 + hashes;
        } else if b[i] == '"' {
            let mut j = i + 1;
            while b[j] != '"' {
                j += if b[j] == '\\' { 2 } else { 1 };
            }
            out.push_str("\"\"");
            i = j + 1;
        } else if b[i] == '\'' {
            // A character literal ('a', '\n', '\u{1F}'), else a lifetime.
            let close = if b.get(i + 1) == Some(&'\\') {
                (i + 2..(i + 12).min(n)).find(|&j| b[j] == '\'')
            } else if b.get(i + 2) == Some(&'\'') {
                Some(i + 2)
            } else {
                None
            };
            match close {
                Some(j) => {
                    out.push_str("' '");
                    i = j + 1;
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    out
}

/// A path a `use` item imports, and the name it binds in the module.
type Bound = (Vec<String>, String);

/// The paths of a use tree `body` under `prefix` (`a::{b, c::{d, e as f}}`), each with the
/// name it binds (its last segment, or its alias: `f` for `c::e as f`).
fn expand(prefix: &[String], body: &str, out: &mut Vec<Bound>) {
    let body = body.trim();
    let split = |s: &str| -> Vec<String> {
        s.split("::")
            .map(str::trim)
            .filter(|x| !x.is_empty())
            .map(String::from)
            .collect()
    };
    match body.find('{') {
        Some(open) => {
            let mut pre = prefix.to_vec();
            pre.extend(split(&body[..open]));
            let inner = &body[open + 1..body.rfind('}').unwrap_or(body.len())];
            let (mut depth, mut cur) = (0, String::new());
            for c in inner.chars().chain(std::iter::once(',')) {
                match c {
                    '{' => depth += 1,
                    '}' => depth -= 1,
                    _ => {}
                }
                if c == ',' && depth == 0 {
                    if !cur.trim().is_empty() {
                        expand(&pre, &cur, out);
                    }
                    cur.clear();
                } else {
                    cur.push(c);
                }
            }
        }
        None => {
            let mut parts = body.split(" as ");
            let path = parts.next().unwrap_or(body);
            let mut p = prefix.to_vec();
            p.extend(split(path));
            let name = parts
                .next()
                .map(|a| a.trim().to_string())
                .or_else(|| p.last().cloned())
                .unwrap_or_default();
            out.push((p, name));
        }
    }
}

/// A path as written in module `m` made absolute (`None`: not into this crate).
fn absolute(m: &[String], path: &[String]) -> Option<Vec<String>> {
    let (head, rest) = path.split_first()?;
    match head.as_str() {
        "crate" => {
            let mut full: Vec<String> = if m.first().is_some_and(|s| s == "cli") {
                vec!["cli".into()]
            } else {
                vec![]
            };
            full.extend(rest.iter().cloned());
            Some(full)
        }
        "self" => Some(m.iter().chain(rest).cloned().collect()),
        "super" => {
            let mut cur = m.to_vec();
            let mut p = path;
            while p.first().is_some_and(|s| s == "super") {
                cur.pop();
                p = &p[1..];
            }
            cur.extend(p.iter().cloned());
            Some(cur)
        }
        _ => None,
    }
}

struct Crate {
    modules: BTreeMap<Module, String>,
    reexports: BTreeMap<(Module, String), Vec<String>>,
}

impl Crate {
    fn resolve(&self, path: &[String], depth: usize) -> Option<Module> {
        (1..=path.len()).rev().find_map(|k| {
            let m = path[..k].to_vec();
            if !self.modules.contains_key(&m) {
                return None;
            }
            if k < path.len() && depth < 10 {
                if let Some(to) = self.reexports.get(&(m.clone(), path[k].clone())) {
                    let mut to = to.clone();
                    to.extend(path[k + 1..].iter().cloned());
                    return Some(self.resolve(&to, depth + 1).unwrap_or(m));
                }
            }
            Some(m)
        })
    }
}

/// The code of a file without its tests, with `use child::` written `use self::child::`;
/// and the paths of its `pub use` items and of its other `use` items.
fn uses(m: &[String], text: &str) -> (String, Vec<Bound>, Vec<Vec<String>>) {
    let mut code = strip(text);
    if let Some(t) = code.find("#[cfg(test)]\nmod tests") {
        code.truncate(t);
    }
    let children: Vec<String> = code
        .lines()
        .filter_map(|l| {
            let l = l.trim();
            let l = l.strip_prefix("pub(crate) ").unwrap_or(l);
            let l = l.strip_prefix("pub ").unwrap_or(l);
            let l = l.strip_prefix("mod ")?.strip_suffix(';')?;
            Some(l.trim().to_string())
        })
        .collect();
    for c in &children {
        code = code.replace(&format!("use {c}::"), &format!("use self::{c}::"));
    }
    let (mut public, mut private) = (vec![], vec![]);
    let mut rest = code.as_str();
    while let Some(at) = rest.find("use ") {
        let before = &rest[..at];
        let word_start =
            at == 0 || !rest[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_');
        let end = rest[at..].find(';').map_or(rest.len(), |e| at + e);
        let item = &rest[at + 4..end];
        if word_start
            && ["crate::", "super::", "self::"]
                .iter()
                .any(|p| item.trim_start().starts_with(p))
        {
            let line_head = before.rsplit('\n').next().unwrap_or("").trim();
            let is_pub = line_head.starts_with("pub");
            let mut paths = vec![];
            expand(&[], item, &mut paths);
            let paths = paths
                .into_iter()
                .filter_map(|(p, name)| Some((absolute(m, &p)?, name)));
            if is_pub {
                public.extend(paths);
            } else {
                private.extend(paths.map(|(p, _)| p));
            }
        }
        rest = &rest[end.min(rest.len())..];
        if rest.is_empty() {
            break;
        }
        rest = &rest[1..];
    }
    (code, public, private)
}

/// Whether a `use` item's last segment binds a name of its own: a glob, `self` and `_` do not.
fn binds(last: &str) -> bool {
    !["*", "self", "_"].contains(&last)
}

/// The paths of `public` (a module's `pub use` items) whose name its own `code` (outside `use`
/// items) uses bare: a facade that also uses what it re-exports depends on it
/// (`pub use result::result_text;` then `result_text(r)` in the same file is an import of
/// `result`). Globs and `self` are skipped, and so are the places where the file declares a
/// name of its own that is spelled the same ([`declares`]); a renamed re-export (`x as y`) is
/// seen under the name it binds (`y`).
fn reexports_used(public: &[Bound], code: &str) -> Vec<Vec<String>> {
    let word = |c: char| c.is_alphanumeric() || c == '_';
    let variants = variant_places(code);
    public
        .iter()
        .filter(|(_, last)| {
            if !binds(last) {
                return false;
            }
            code.match_indices(last.as_str()).any(|(i, _)| {
                let before = code[..i].chars().next_back();
                let after = code[i + last.len()..].chars().next();
                !before.is_some_and(|c| word(c) || c == '.' || c == ':')
                    && !after.is_some_and(word)
                    && !declares(code, i, last.len())
                    && !variants.contains(&i)
            })
        })
        .map(|(p, _)| p.clone())
        .collect()
}

/// Whether the name at `code[i..i + len]` is declared there, not used: after `mod`, `fn`,
/// `let`, `mut`, `struct`, `enum`, `trait`, `type`, `const` or `static`, or followed by one `:`
/// (a field, a parameter or a binding with its type; a field set in a struct literal).
fn declares(code: &str, i: usize, len: usize) -> bool {
    let head = code[..i].trim_end();
    let keyword = [
        "mod", "fn", "let", "mut", "struct", "enum", "trait", "type", "const", "static",
    ]
    .iter()
    .any(|k| {
        head.ends_with(k)
            && !head[..head.len() - k.len()].ends_with(|c: char| c.is_alphanumeric() || c == '_')
    });
    let rest = code[i + len..].trim_start();
    keyword || rest.starts_with(':') && !rest.starts_with("::")
}

/// The byte offsets where the enums of `code` name their variants: the first word of each
/// item directly inside an enum's braces (after its attributes), not the types its variants
/// hold.
fn variant_places(code: &str) -> Vec<usize> {
    let mut out = vec![];
    for (at, _) in code.match_indices("enum ") {
        if code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
            continue;
        }
        let Some(open) = code[at..].find('{').map(|o| at + o) else {
            continue;
        };
        let (mut depth, mut item_start) = (0, true);
        for (k, c) in code[open..].char_indices() {
            match c {
                '{' | '(' | '[' | '<' => depth += 1,
                '}' | ')' | ']' | '>' => depth -= 1,
                ',' if depth == 1 => item_start = true,
                c if depth == 1 && item_start && (c.is_alphabetic() || c == '_') => {
                    out.push(open + k);
                    item_start = false;
                }
                _ => {}
            }
            if depth == 0 {
                break;
            }
        }
    }
    out
}

/// Inline paths `crate::a::b` and `super::a` outside `use` items.
fn inline_paths(m: &[String], code: &str) -> Vec<Vec<String>> {
    let mut out = vec![];
    let chars: Vec<char> = code.chars().collect();
    let s: String = chars.iter().collect();
    for head in ["crate::", "super::"] {
        let mut from = 0;
        while let Some(i) = s[from..].find(head) {
            let at = from + i;
            from = at + head.len();
            let prev = s[..at].chars().next_back();
            if prev.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let tail: String = s[at..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            let path: Vec<String> = tail
                .split("::")
                .filter(|x| !x.is_empty())
                .map(String::from)
                .collect();
            out.extend(absolute(m, &path));
        }
    }
    out
}

fn modules(root: &Path) -> BTreeMap<Module, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).expect("reads src/") {
            let p = e.expect("an entry").path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p.strip_prefix(root).unwrap().with_extension("");
                let mut parts: Vec<String> = rel
                    .iter()
                    .map(|c| c.to_string_lossy().into_owned())
                    .collect();
                if parts.last().is_some_and(|s| s == "mod") || parts == ["cli", "main"] {
                    parts.pop();
                }
                if parts == ["lib"] {
                    parts.clear();
                }
                out.insert(
                    parts,
                    std::fs::read_to_string(&p).expect("reads a source file"),
                );
            }
        }
    }
    out
}

/// The modules each module depends on (re-exports followed), and the top-level modules its
/// paths name as written (a re-export from a higher layer is still an import from it).
fn edges() -> (
    BTreeMap<Module, BTreeSet<Module>>,
    BTreeMap<Module, BTreeSet<Module>>,
) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut krate = Crate {
        modules: modules(&root),
        reexports: BTreeMap::new(),
    };
    let mut parsed = vec![];
    for (m, text) in &krate.modules {
        let (code, public, private) = uses(m, text);
        parsed.push((m.clone(), code, public, private));
    }
    for (m, _, public, _) in &parsed {
        for (p, name) in public {
            if binds(name) {
                krate.reexports.insert((m.clone(), name.clone()), p.clone());
            }
        }
    }
    let mut edges: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    let mut written: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (m, code, public, private) in &parsed {
        // Inline paths in the code outside `pub use` items (and outside all `use` items: those
        // are `private` already).
        let mut outside_uses = String::new();
        for piece in code.split(';') {
            let cut = piece
                .match_indices("use ")
                .find(|(i, _)| {
                    let head = piece[..*i].rsplit('\n').next().unwrap_or("").trim();
                    head.is_empty() || head.starts_with("pub")
                })
                .map_or(piece.len(), |(i, _)| i);
            outside_uses.push_str(&piece[..cut]);
            outside_uses.push(';');
        }
        let targets = private
            .iter()
            .chain(&inline_paths(m, &outside_uses))
            .chain(&reexports_used(public, &outside_uses))
            .cloned()
            .collect::<Vec<_>>();
        for p in targets {
            let top = p.iter().take(if m.first().is_some_and(|s| s == "cli") {
                2
            } else {
                1
            });
            written
                .entry(m.clone())
                .or_default()
                .insert(top.cloned().collect());
            if let Some(t) = krate.resolve(&p, 0) {
                if &t != m && !t.is_empty() {
                    edges.entry(m.clone()).or_default().insert(t);
                }
            }
        }
    }
    for (a, b) in ALLOWED {
        let split = |s: &str| s.split("::").map(String::from).collect::<Vec<_>>();
        if let Some(set) = edges.get_mut(&split(a)) {
            set.remove(&split(b));
        }
        if let Some(set) = written.get_mut(&split(a)) {
            set.remove(&split(b)[..1].to_vec());
        }
    }
    (edges, written)
}

fn layer(m: &[String]) -> Option<usize> {
    let top = m.first()?;
    LAYERS.iter().position(|l| l.contains(&top.as_str()))
}

#[test]
fn no_import_points_up_a_layer() {
    let mut up = vec![];
    let (edges, written) = edges();
    for (a, targets) in edges.into_iter().chain(written) {
        for b in targets {
            if let (Some(la), Some(lb)) = (layer(&a), layer(&b)) {
                if lb > la {
                    let edge = format!("{} -> {}", name(&a), name(&b));
                    if !up.contains(&edge) {
                        up.push(edge);
                    }
                }
            }
        }
    }
    assert!(
        up.is_empty(),
        "imports pointing up a layer:\n{}",
        up.join("\n")
    );
}

#[test]
fn no_modules_import_each_other_in_a_cycle() {
    let (edges, _) = edges();
    // Tarjan's strongly connected components.
    struct State<'a> {
        edges: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, usize>,
        low: BTreeMap<&'a Module, usize>,
        stack: Vec<&'a Module>,
        on: BTreeSet<&'a Module>,
        cycles: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Module) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on.insert(v);
        if let Some(ws) = s.edges.get(v) {
            for w in ws {
                if !s.index.contains_key(w) {
                    visit(s, w);
                    let low = s.low[v].min(s.low[w]);
                    s.low.insert(v, low);
                } else if s.on.contains(w) {
                    let low = s.low[v].min(s.index[w]);
                    s.low.insert(v, low);
                }
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = vec![];
            while let Some(w) = s.stack.pop() {
                s.on.remove(w);
                comp.push(name(w));
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.cycles.push(comp);
            }
        }
    }
    let mut s = State {
        edges: &edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        on: BTreeSet::new(),
        cycles: vec![],
    };
    for v in edges.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    let text: Vec<String> = s.cycles.iter().map(|c| c.join(", ")).collect();
    assert!(
        text.is_empty(),
        "modules importing each other in a cycle:\n{}",
        text.join("\n")
    );
}

/// The checker sees what it must: the parse of a use tree, a re-export followed through, an
/// up-pointing inline path.
#[test]
fn the_checker_reads_use_trees_and_inline_paths() {
    let m: Module = vec!["optimal".into(), "x".into()];
    let (_, public, private) = uses(
        &m,
        "pub use super::y::Z;\nuse crate::{a::{b, c::D as E}, f};\n// use crate::g;\nfn h() { \"crate::s\"; crate::i::j(); }\n",
    );
    let names = |v: &[Vec<String>]| v.iter().map(|p| p.join("::")).collect::<Vec<_>>();
    assert_eq!(
        public,
        [(vec!["optimal".into(), "y".into(), "Z".into()], "Z".into())]
    );
    assert_eq!(names(&private), ["a::b", "a::c::D", "f"]);
    let code = strip("fn h() { \"crate::s\"; crate::i::j(); } // crate::k");
    assert_eq!(names(&inline_paths(&m, &code)), ["i::j"]);
    // A facade calling what it re-exports depends on it; a method or a longer name does not.
    let public = [(
        vec!["p".to_string(), "r".into(), "text".into()],
        "text".to_string(),
    )];
    for used in [
        "fn f() { text(1) }",
        "fn f() -> Vec<text> { vec![] }",
        "enum E { A(u8, text), B { x: Vec<text> } }",
    ] {
        assert_eq!(
            names(&reexports_used(&public, used)),
            ["p::r::text"],
            "{used}"
        );
    }
    assert!(reexports_used(
        &public,
        &strip(
            "mod text;\nenum E { A, #[x] text, B(u8) }\nstruct S { text: u8 }\n\
             fn text(text: u8) { let text = S { text: 1 }; x.text(); q::text(); text_of(); } // text"
        )
    )
    .is_empty());
    // A renamed re-export is seen under the name it binds, not its original one.
    let (_, public, _) = uses(
        &m,
        "pub use self::check::{run as check_run};
",
    );
    assert_eq!(
        public,
        [(
            vec!["optimal".into(), "x".into(), "check".into(), "run".into()],
            "check_run".into()
        )]
    );
    let code = strip("fn f() { check_run(1); run(2) }");
    assert_eq!(
        names(&reexports_used(&public, &code)),
        ["optimal::x::check::run"]
    );
    assert!(reexports_used(&public, &strip("fn f() { run(2) }")).is_empty());
}

/// Every top-level module of `src/` has a layer, so that a new module cannot escape the checks
/// above by being absent from [`LAYERS`].
#[test]
fn every_module_has_a_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut missing = vec![];
    for entry in std::fs::read_dir(&src).expect("src/ is readable") {
        let path = entry.expect("a directory entry").path();
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default();
        let is_module = path.is_dir() || path.extension().is_some_and(|e| e == "rs");
        if is_module && stem != "lib" && layer(&[stem.to_string()]).is_none() {
            missing.push(stem.to_string());
        }
    }
    assert!(missing.is_empty(), "modules without a layer: {missing:?}");
}
