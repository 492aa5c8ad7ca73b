//! The library's modules in layers, read bottom up, with no import circle.
//!
//! Every top-level module of the library (`src/X.rs` or `src/X/`) belongs to one layer of
//! [`LAYERS`]; a module may use (`crate::...`, or `super::...` up to the crate root) only
//! modules of its own layer or of a layer below, and the modules of one layer may not
//! import each other in a circle. Doc comments and other comments are left out: a doc link
//! upwards is fine, code is not. Files inside one folder may refer to each other freely.
//!
//! docs/design.md explains the layers and where a new object kind, light kind or number
//! type goes.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The layers, lowest first: a module may use its own layer and those before it.
const LAYERS: &[(&str, &[&str])] = &[
    (
        "numbers, vectors and the error kinds",
        &[
            "error", "name", "decimal", "interval", "scalar", "lanes", "ray", "write",
        ],
    ),
    (
        "materials, textures, lights, objects, camera",
        &["material", "texture", "light", "object", "camera"],
    ),
    (
        "scene, render plan, tree, compiled scenes",
        &[
            "range",
            "scene",
            "capacity",
            "bvh",
            "hits",
            "plan",
            "compiled",
            "warning",
            "region",
            "animation",
        ],
    ),
    ("shading", &["shade"]),
    ("rendering", &["dither", "render"]),
    ("parser and printer", &["parse", "print"]),
    ("host", &["host"]),
];

/// One `crate::` use: from which file and line, to which top-level module.
#[derive(Debug)]
struct Use {
    file: PathBuf,
    line: usize,
    from: String,
    to: String,
}

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The library's `.rs` files (not the binaries under `src/bin`).
fn library_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .expect("src/ is readable")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            if path != src().join("bin") {
                library_files(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The file's module path below the crate root: `src/object/mod.rs` is `[object]`,
/// `src/object/plane.rs` is `[object, plane]`, `src/lib.rs` is `[]`.
fn module_path(file: &Path) -> Vec<String> {
    let relative = file.strip_prefix(src()).expect("a file under src/");
    let mut parts: Vec<String> = relative
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().expect("a file name");
    let stem = last.trim_end_matches(".rs");
    if stem != "mod" && stem != "lib" {
        parts.push(stem.to_string());
    }
    parts
}

/// The text with comments (doc comments included) and the contents of string and char
/// literals blanked out, lines kept where they were.
fn code_only(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    // Keeps line breaks of what is blanked, so line numbers stay right.
    let blank = |c: char, out: &mut String| out.push(if c == '\n' { '\n' } else { ' ' });
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                blank(chars[i], &mut out);
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    blank(chars[i], &mut out);
                    i += 1;
                }
            }
        } else if c == 'r'
            && (next == Some('"') || next == Some('#'))
            && !ident_char(prev(&chars, i))
        {
            // A raw string: r"..." or r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            let closing: String = std::iter::once('"')
                .chain(std::iter::repeat_n('#', hashes))
                .collect();
            let rest: String = chars[j + 1..].iter().collect();
            let end = rest.find(&closing).map_or(chars.len(), |k| {
                j + 1 + rest[..k].chars().count() + closing.len()
            });
            for &ch in &chars[i..end] {
                blank(ch, &mut out);
            }
            i = end;
        } else if c == '"' {
            blank(c, &mut out);
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                if chars[i] == '\\' {
                    blank(chars[i], &mut out);
                    i += 1;
                }
                if i < chars.len() {
                    blank(chars[i], &mut out);
                    i += 1;
                }
            }
            if i < chars.len() {
                blank(chars[i], &mut out);
                i += 1;
            }
        } else if c == '\'' {
            // A char literal ('x', '\n', '\u{..}') or a lifetime ('a).
            let end = if next == Some('\\') {
                (i + 2..chars.len())
                    .find(|&k| chars[k] == '\'')
                    .map(|k| k + 1)
            } else if chars.get(i + 2) == Some(&'\'') {
                Some(i + 3)
            } else {
                None
            };
            match end {
                Some(end) => {
                    for &ch in &chars[i..end] {
                        blank(ch, &mut out);
                    }
                    i = end;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn prev(chars: &[char], i: usize) -> char {
    if i == 0 { ' ' } else { chars[i - 1] }
}

fn ident_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The identifier at the start of `s` (after white space).
fn leading_ident(s: &str) -> &str {
    let s = s.trim_start();
    let end = s.find(|c: char| !ident_char(c)).unwrap_or(s.len());
    &s[..end]
}

/// The first identifiers of the items of a `{...}` group that starts at `s` (just after
/// the `{`), at the group's own depth.
fn group_heads(s: &str) -> Vec<String> {
    let mut heads = vec![leading_ident(s).to_string()];
    let mut depth = 1;
    for (k, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            ',' if depth == 1 => heads.push(leading_ident(&s[k + 1..]).to_string()),
            _ => {}
        }
    }
    heads
        .into_iter()
        .filter(|h| !h.is_empty() && h != "self")
        .collect()
}

/// The top-level modules a path that starts at `at` (just after `crate::`, or after the
/// `super::`s that reach the crate root) names.
fn targets(code: &str, at: usize) -> Vec<String> {
    let rest = code[at..].trim_start();
    if let Some(group) = rest.strip_prefix('{') {
        group_heads(group)
    } else {
        let head = leading_ident(rest);
        if head.is_empty() {
            vec![]
        } else {
            vec![head.to_string()]
        }
    }
}

/// The top-level modules, and the names `lib.rs` re-exports from them (`crate::Scalar`
/// is a use of `scalar`).
fn names() -> BTreeMap<String, String> {
    let mut files = Vec::new();
    library_files(&src(), &mut files);
    let mut names: BTreeMap<String, String> = files
        .iter()
        .filter_map(|f| module_path(f).first().cloned())
        .map(|m| (m.clone(), m))
        .collect();
    let lib = code_only(&std::fs::read_to_string(src().join("lib.rs")).expect("src/lib.rs"));
    for (at, _) in lib.match_indices("pub use ") {
        let module = leading_ident(&lib[at + "pub use ".len()..]).to_string();
        if !names.contains_key(&module) {
            continue; // another crate's
        }
        let rest = &lib[at + "pub use ".len() + module.len()..];
        let rest = rest.trim_start().trim_start_matches("::").trim_start();
        let items = match rest.strip_prefix('{') {
            Some(group) => group_heads(group),
            None => vec![leading_ident(rest).to_string()],
        };
        for item in items {
            names.insert(item, module.clone());
        }
    }
    names
}

/// Every use of a top-level module in the library's code.
fn uses() -> Vec<Use> {
    let names = names();
    let mut files = Vec::new();
    library_files(&src(), &mut files);
    let mut found = Vec::new();
    for file in files {
        let path = module_path(&file);
        let Some(from) = path.first().cloned() else {
            continue; // lib.rs: the crate root declares every module.
        };
        let text = std::fs::read_to_string(&file).expect("a readable source file");
        let code = code_only(&text);
        let line_of = |at: usize| code[..at].matches('\n').count() + 1;
        let mut record = |at: usize, to: Vec<String>| {
            for to in to.iter().filter_map(|name| names.get(name)) {
                if *to != from {
                    found.push(Use {
                        file: file.clone(),
                        line: line_of(at),
                        from: from.clone(),
                        to: to.clone(),
                    });
                }
            }
        };
        for (at, _) in code.match_indices("crate::") {
            if at > 0 && ident_char(code[..at].chars().last().unwrap_or(' ')) {
                continue; // `$crate::` in a macro, or part of a longer name.
            }
            record(at, targets(&code, at + "crate::".len()));
        }
        // `super::` chains that climb to the crate root.
        for (at, _) in code.match_indices("super::") {
            if at > 0 && ident_char(code[..at].chars().last().unwrap_or(' ')) {
                continue;
            }
            if at >= "super::".len() && code[..at].ends_with("super::") {
                continue; // counted from the chain's start
            }
            let mut end = at;
            let mut climbs = 0;
            while code[end..].starts_with("super::") {
                climbs += 1;
                end += "super::".len();
            }
            // (Inside a file's own `mod tests` one more is needed: such a path is read as
            // the crate's only if it names a top-level module, which the tests' don't.)
            if climbs == path.len() {
                record(at, targets(&code, end));
            }
        }
    }
    found
}

fn layer_of(module: &str) -> Option<usize> {
    LAYERS
        .iter()
        .position(|(_, modules)| modules.contains(&module))
}

/// The modules of `edges` in a cycle, if any (depth-first search).
fn cycle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        done: &mut BTreeSet<String>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        if let Some(start) = path.iter().position(|n| n == node) {
            let mut cycle = path[start..].to_vec();
            cycle.push(node.to_string());
            return Some(cycle);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in edges.get(node).into_iter().flatten() {
            if let Some(cycle) = visit(next, edges, done, path) {
                return Some(cycle);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    edges
        .keys()
        .find_map(|node| visit(node, edges, &mut done, &mut Vec::new()))
}

#[test]
fn every_module_has_a_layer() {
    let mut files = Vec::new();
    library_files(&src(), &mut files);
    let unplaced: BTreeSet<String> = files
        .iter()
        .filter_map(|f| module_path(f).first().cloned())
        .filter(|m| layer_of(m).is_none())
        .collect();
    assert!(
        unplaced.is_empty(),
        "modules in no layer of tests/layers.rs: {unplaced:?}"
    );
}

#[test]
fn modules_import_only_their_own_layer_or_below() {
    let upward: Vec<String> = uses()
        .iter()
        .filter(|u| match (layer_of(&u.from), layer_of(&u.to)) {
            (Some(from), Some(to)) => to > from,
            _ => false,
        })
        .map(|u| {
            let (from, to) = (layer_of(&u.from).unwrap_or(0), layer_of(&u.to).unwrap_or(0));
            format!(
                "{}:{}: {} ({}) uses {} ({})",
                u.file.strip_prefix(src()).unwrap_or(&u.file).display(),
                u.line,
                u.from,
                LAYERS[from].0,
                u.to,
                LAYERS[to].0
            )
        })
        .collect();
    assert!(
        upward.is_empty(),
        "{} upward imports:\n{}",
        upward.len(),
        upward.join("\n")
    );
}

#[test]
fn no_import_circle() {
    let uses = uses();
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for u in &uses {
        edges
            .entry(u.from.clone())
            .or_default()
            .insert(u.to.clone());
    }
    if let Some(circle) = cycle(&edges) {
        // Where each step of the circle is written.
        let steps: Vec<String> = circle
            .windows(2)
            .filter_map(|step| {
                let u = uses.iter().find(|u| u.from == step[0] && u.to == step[1])?;
                let file = u.file.strip_prefix(src()).unwrap_or(&u.file);
                Some(format!(
                    "{}:{}: {} uses {}",
                    file.display(),
                    u.line,
                    u.from,
                    u.to
                ))
            })
            .collect();
        panic!(
            "modules that import each other in a circle:\n{}",
            steps.join("\n")
        );
    }
}

/// The checker itself: it sees a `crate::` path in code, a grouped one over several lines,
/// a `super::` that reaches the root, and not what is in a comment or a string.
#[test]
fn the_checker_reads_paths_as_rust_does() {
    let text = "use crate::{\n    a::X,\n    b::{Y, Z},\n};\n// crate::c\n/// [`crate::d`]\nlet s = \"crate::e\";\nfn f<'a>() { crate::g::h(); '\"'; }\n";
    let code = code_only(text);
    let mut seen: Vec<String> = code
        .match_indices("crate::")
        .flat_map(|(at, _)| targets(&code, at + 7))
        .collect();
    seen.sort();
    assert_eq!(seen, ["a", "b", "g"]);
    assert_eq!(code.lines().count(), text.lines().count());
}
