//! No import cycle among the modules of `crates/delone-cli/src`.
//!
//! A module "uses" another when its file names an item of it through
//! `crate::a::...` (in a `use` or in a path, `use crate::{a, b::c}`
//! included) or `super::a` (from a file whose parent is the crate root, or
//! from a nested module); `mod` declarations and comments do not count.
//! Each file is a module (`a/b.rs` and `a/b/mod.rs` are `a::b`; `main.rs`
//! and `lib.rs` the root); a path names the longest module it starts with.
//! The check fails on the first cycle found and prints it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The module path of `file` under `src` (`""` for the crate root).
fn module_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap_or(file).with_extension("");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "main" | "lib")
    ) {
        parts.pop();
    }
    parts.join("::")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The source without comments (line comments and doc comments).
fn strip_comments(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(k) => &l[..k],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths (`a::b::c`, relative to the crate root) that `text`, the
/// source of module `me`, names through `crate::` or `super::`.
fn named_paths(me: &str, text: &str) -> Vec<String> {
    let text = strip_comments(text);
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = Vec::new();
    // The path after a prefix: identifiers joined by `::`, with one level
    // of `{a, b::c}` expanded.
    fn path_at(s: &str, base: &str, out: &mut Vec<String>, ident: &dyn Fn(char) -> bool) {
        let end = s.find(|c: char| !(ident(c) || c == ':')).unwrap_or(s.len());
        let head = s[..end].trim_end_matches(':');
        let full = match (base.is_empty(), head.is_empty()) {
            (true, _) => head.to_string(),
            (false, true) => base.to_string(),
            (false, false) => format!("{base}::{head}"),
        };
        if s[end..].starts_with('{') {
            if let Some(close) = s[end..].find('}') {
                for item in s[end + 1..end + close].split(',') {
                    let item = item.trim();
                    if !item.is_empty() {
                        path_at(item, &full, out, ident);
                    }
                }
                return;
            }
        }
        if !full.is_empty() {
            out.push(full);
        }
    }
    let parent = me.rsplit_once("::").map_or("", |(p, _)| p);
    for (prefix, base) in [("crate::", ""), ("super::", parent)] {
        let mut from = 0;
        while let Some(k) = text[from..].find(prefix) {
            let at = from + k;
            from = at + prefix.len();
            // Only a path that starts here (not `foo_crate::`).
            if at > 0 && text[..at].chars().next_back().is_some_and(ident) {
                continue;
            }
            path_at(&text[from..], base, &mut out, &ident);
        }
    }
    out
}

/// The module graph of the crate at `src`: module → modules it uses.
fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeSet<String> = files.iter().map(|f| module_of(src, f)).collect();
    let mut g = BTreeMap::new();
    for f in &files {
        let me = module_of(src, f);
        let text = std::fs::read_to_string(f).unwrap();
        let mut uses = BTreeSet::new();
        for p in named_paths(&me, &text) {
            // The longest module the path starts with.
            let parts: Vec<&str> = p.split("::").collect();
            let target = (1..=parts.len())
                .rev()
                .map(|n| parts[..n].join("::"))
                .find(|m| modules.contains(m));
            if let Some(t) = target.filter(|t| *t != me) {
                uses.insert(t);
            }
        }
        g.insert(me, uses);
    }
    g
}

/// A cycle of `g`, if any (depth-first search), as the modules in order.
fn find_cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    let mut mark: BTreeMap<&str, Mark> = g.keys().map(|k| (k.as_str(), Mark::New)).collect();
    fn visit<'a>(
        v: &'a str,
        g: &'a BTreeMap<String, BTreeSet<String>>,
        mark: &mut BTreeMap<&'a str, Mark>,
        stack: &mut Vec<&'a str>,
    ) -> Option<Vec<String>> {
        mark.insert(v, Mark::Open);
        stack.push(v);
        for w in g.get(v).into_iter().flatten() {
            match mark.get(w.as_str()).copied().unwrap_or(Mark::Done) {
                Mark::Open => {
                    let k = stack.iter().position(|&s| s == w).unwrap_or(0);
                    let mut c: Vec<String> = stack[k..].iter().map(|s| s.to_string()).collect();
                    c.push(w.clone());
                    return Some(c);
                }
                Mark::New => {
                    if let Some(c) = visit(w, g, mark, stack) {
                        return Some(c);
                    }
                }
                Mark::Done => {}
            }
        }
        stack.pop();
        mark.insert(v, Mark::Done);
        None
    }
    let keys: Vec<&str> = g.keys().map(String::as_str).collect();
    for v in keys {
        if mark[v] == Mark::New {
            if let Some(c) = visit(v, g, &mut mark, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn the_checker_finds_a_cycle_and_reads_every_use_form() {
    let paths = named_paths(
        "a",
        "use crate::b::X;\nuse crate::{c, d::Y};\n// crate::e::Z in a comment\nfn f() { super::f2(); crate::g::h(); }",
    );
    assert_eq!(paths, ["b::X", "c", "d::Y", "g::h", "f2"]);
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    g.insert("a".into(), ["b".to_string()].into());
    g.insert("b".into(), ["c".to_string()].into());
    g.insert("c".into(), BTreeSet::new());
    assert_eq!(find_cycle(&g), None);
    g.get_mut("c").unwrap().insert("a".into());
    assert_eq!(
        find_cycle(&g),
        Some(vec!["a".into(), "b".into(), "c".into(), "a".into()])
    );
}

#[test]
fn no_import_cycle_in_the_cli() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let g = graph(&src);
    assert!(g.len() > 20, "{} modules", g.len());
    // The dispatcher uses the runs; shared helpers are used by all.
    assert!(g["run"].contains("plc") && g["plc"].contains("fail"));
    if let Some(c) = find_cycle(&g) {
        panic!("import cycle in delone-cli/src: {}", c.join(" -> "));
    }
}
