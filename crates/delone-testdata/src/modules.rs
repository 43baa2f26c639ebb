//! Import cycles between the modules (files) of a crate's `src` folder.
//!
//! A module is a source file (`a/mod.rs` is module `a`, `lib.rs`/`main.rs`
//! the crate root). Module A *uses* module B when A's code (outside inline
//! `#[cfg(test)]` modules) names an item defined in B: through a `use`
//! declaration or a path (`crate::b::x`, `super::x`, `self::b::x`, or a
//! path that starts with one of A's child modules). Re-exports are followed
//! to the file that defines the item (`crate::Error` re-exported by
//! `lib.rs` from `error.rs` counts as a use of `error.rs`), and `mod b;`
//! declarations are not uses. A cycle is a strongly connected component of
//! two or more modules in this graph.
//!
//! The check reads the files as text (comments, strings and character
//! literals removed first); it does not expand macros, and a glob import
//! (`use x::*`) counts as a use of `x` itself.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Module = Vec<String>;

/// The import cycles among the modules of the crate whose sources are in
/// `src` (see the [module documentation](self)): each cycle as the sorted
/// names of its modules (`a/b` for `src/a/b.rs` or `src/a/b/mod.rs`,
/// `crate` for the root). Empty when the module graph has no cycle.
///
/// # Panics
/// When `src` or a file below it cannot be read (this is a test helper).
///
/// ```
/// let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
/// assert!(delone_testdata::modules::import_cycles(&src).is_empty());
/// ```
pub fn import_cycles(src: &Path) -> Vec<Vec<String>> {
    let files = read_modules(src);
    let graph = uses(&files);
    cycles(&graph)
        .into_iter()
        .map(|c| c.into_iter().map(|m| name(&m)).collect())
        .collect()
}

/// The module graph of the crate in `src`: each module's name and the
/// names of the modules it uses (see the [module documentation](self)).
///
/// # Panics
/// When `src` or a file below it cannot be read.
///
/// ```
/// let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
/// let g = delone_testdata::modules::module_graph(&src);
/// assert!(g.contains_key("crate") && g.contains_key("modules"));
/// ```
pub fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let files = read_modules(src);
    uses(&files)
        .into_iter()
        .map(|(m, to)| (name(&m), to.iter().map(name).collect()))
        .collect()
}

/// A failure message for [`import_cycles`]: each cycle with the uses
/// between its modules; empty when there is no cycle.
///
/// # Panics
/// When `src` or a file below it cannot be read.
///
/// ```
/// let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
/// assert_eq!(delone_testdata::modules::cycle_report(&src), "");
/// ```
pub fn cycle_report(src: &Path) -> String {
    let graph = module_graph(src);
    let mut out = String::new();
    for cycle in import_cycles(src) {
        out.push_str(&format!("import cycle among {} modules:\n", cycle.len()));
        for m in &cycle {
            let to: Vec<&str> = graph[m]
                .iter()
                .filter(|t| cycle.contains(t))
                .map(String::as_str)
                .collect();
            out.push_str(&format!("  {m} uses {}\n", to.join(", ")));
        }
    }
    out
}

fn name(m: &Module) -> String {
    if m.is_empty() {
        "crate".to_string()
    } else {
        m.join("/")
    }
}

/// Every `.rs` file below `src` by module path, with its code cleaned.
fn read_modules(src: &Path) -> BTreeMap<Module, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()));
        for entry in entries {
            let path = entry.expect("directory entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = path.strip_prefix(src).expect("below src");
            let mut parts: Module = rel
                .with_extension("")
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            if matches!(
                parts.last().map(String::as_str),
                Some("mod" | "lib" | "main")
            ) {
                parts.pop();
            }
            let text = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
            out.insert(parts, drop_test_modules(&clean(&text)));
        }
    }
    // `#[path = "x.rs"] mod y;` makes file `x.rs` the module `parent::y`.
    let renames: Vec<(Module, Module)> = out
        .iter()
        .flat_map(|(m, text)| {
            path_attributes(text)
                .into_iter()
                .map(move |(file, module)| {
                    let mut from = m[..m.len().saturating_sub(1)].to_vec();
                    from.push(file);
                    let mut to = m.clone();
                    to.push(module);
                    (from, to)
                })
        })
        .collect();
    for (from, to) in renames {
        if let Some(text) = out.remove(&from) {
            out.insert(to, text);
        }
    }
    out
}

/// `(file stem, module name)` of each `#[path = "stem.rs"] mod name;`.
fn path_attributes(text: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("#[path") {
        rest = &rest[i + 6..];
        let Some(end) = rest.find(']') else { break };
        let attr = &rest[..end];
        let after = &rest[end + 1..];
        let stem = attr
            .split('"')
            .nth(1)
            .map(|s| s.trim_end_matches(".rs").to_string());
        let module = after
            .split(';')
            .next()
            .and_then(|decl| decl.split_whitespace().last())
            .map(str::to_string);
        if let (Some(stem), Some(module)) = (stem, module) {
            out.push((stem, module));
        }
    }
    out
}

/// The code without comments; string and character literals emptied
/// (their quotes kept, so `"..."` stays a token and `'a` lifetimes stay).
fn clean(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let next = b.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if c == 'r'
            && (next == Some('"') || next == Some('#'))
            && !ident_char(b.get(i.wrapping_sub(1)).copied())
        {
            // Raw string r"..." / r#"..."#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' {
            // A character literal ('x', '\n', '\u{..}') or a lifetime.
            if next == Some('\\') {
                let mut j = i + 2;
                while j < b.len() && b[j] != '\'' {
                    j += 1;
                }
                i = j + 1;
                out.push_str("' '");
            } else if b.get(i + 2) == Some(&'\'') {
                i += 3;
                out.push_str("' '");
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn ident_char(c: Option<char>) -> bool {
    c.is_some_and(|c| c.is_alphanumeric() || c == '_')
}

/// The code without inline `#[cfg(test)] mod name { ... }` blocks (their
/// `super` is the file itself, and tests may use anything).
fn drop_test_modules(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(i) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..i]);
        let after = &rest[i + "#[cfg(test)]".len()..];
        let trimmed = after.trim_start();
        let is_mod = trimmed.starts_with("mod ") || trimmed.starts_with("pub mod ");
        let brace = trimmed.find('{');
        let semi = trimmed.find(';');
        match (is_mod, brace) {
            (true, Some(open)) if semi.is_none_or(|s| s > open) => {
                let start = after.len() - trimmed.len() + open;
                let mut depth = 0usize;
                let mut end = after.len();
                for (k, ch) in after[start..].char_indices() {
                    match ch {
                        '{' => depth += 1,
                        '}' => {
                            depth -= 1;
                            if depth == 0 {
                                end = start + k + 1;
                                break;
                            }
                        }
                        _ => {}
                    }
                }
                rest = &after[end..];
            }
            _ => {
                out.push_str("#[cfg(test)]");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// The paths of a `use` tree (`a::{b, c::{d, e}}` → `a::b`, `a::c::d`,
/// `a::c::e`), each with the name it is imported as.
fn expand_use(tree: &str) -> Vec<(String, String)> {
    let tree: String = tree.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut out = Vec::new();
    expand_into("", tree.trim(), &mut out);
    out
}

fn expand_into(prefix: &str, tree: &str, out: &mut Vec<(String, String)>) {
    let join = |p: &str, s: &str| {
        if p.is_empty() {
            s.to_string()
        } else {
            format!("{p}::{s}")
        }
    };
    if let Some(open) = tree.find('{') {
        let head = tree[..open].trim().trim_end_matches("::");
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        let base = join(prefix, head);
        let mut depth = 0;
        let mut start = 0;
        let bytes: Vec<char> = inner.chars().collect();
        let mut parts = Vec::new();
        for (k, &ch) in bytes.iter().enumerate() {
            match ch {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    parts.push(bytes[start..k].iter().collect::<String>());
                    start = k + 1;
                }
                _ => {}
            }
        }
        parts.push(bytes[start..].iter().collect::<String>());
        for p in parts {
            let p = p.trim();
            if p.is_empty() {
                continue;
            }
            if p == "self" {
                let alias = base.rsplit("::").next().unwrap_or("").to_string();
                out.push((base.clone(), alias));
            } else {
                expand_into(&base, p, out);
            }
        }
    } else {
        let (path, alias) = match tree.split_once(" as ") {
            Some((p, a)) => (p.trim(), a.trim().to_string()),
            None => (tree, tree.rsplit("::").next().unwrap_or(tree).to_string()),
        };
        out.push((join(prefix, path), alias));
    }
}

/// `use` declarations of a module's code: `(is pub, tree)`.
fn use_declarations(text: &str) -> Vec<(bool, String)> {
    let mut out = Vec::new();
    let chars: Vec<char> = text.chars().collect();
    let s: String = chars.iter().collect();
    let mut from = 0;
    while let Some(k) = s[from..].find("use ") {
        let at = from + k;
        from = at + 4;
        if ident_char(s[..at].chars().last()) {
            continue;
        }
        // What precedes on the line: nothing, or a visibility.
        let line_start = s[..at].rfind(['\n', ';', '{', '}']).map_or(0, |i| i + 1);
        let before = s[line_start..at].trim();
        let is_pub = before.starts_with("pub");
        if !(before.is_empty() || is_pub || before.starts_with('#')) {
            continue;
        }
        let Some(end) = s[from..].find(';') else {
            break;
        };
        out.push((is_pub, s[from..from + end].to_string()));
        from += end;
    }
    out
}

/// Paths in code that start with `crate`, `super`, `self` or one of the
/// module's children.
fn code_paths(text: &str, children: &BTreeSet<String>) -> Vec<String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        if !ident_char(Some(chars[i]))
            || (i > 0 && (ident_char(Some(chars[i - 1])) || chars[i - 1] == ':'))
        {
            i += 1;
            continue;
        }
        // Read ident(::ident)*.
        let mut j = i;
        let mut segs = Vec::new();
        loop {
            let s = j;
            while j < chars.len() && ident_char(Some(chars[j])) {
                j += 1;
            }
            segs.push(chars[s..j].iter().collect::<String>());
            if j + 2 < chars.len()
                && chars[j] == ':'
                && chars[j + 1] == ':'
                && ident_char(Some(chars[j + 2]))
            {
                j += 2;
            } else {
                break;
            }
        }
        let first = segs[0].as_str();
        if segs.len() > 1
            && (matches!(first, "crate" | "super" | "self") || children.contains(first))
        {
            out.push(segs.join("::"));
        }
        i = j.max(i + 1);
    }
    out
}

struct Resolver<'a> {
    modules: &'a BTreeMap<Module, String>,
    /// Per module: re-exported name → path (relative to that module).
    exports: BTreeMap<Module, BTreeMap<String, String>>,
}

impl Resolver<'_> {
    /// The module defining the item `path` names, seen from module `at`.
    fn resolve(&self, at: &Module, path: &str, depth: usize) -> Option<Module> {
        let segs: Vec<&str> = path.split("::").collect();
        let mut cur: Module = match segs[0] {
            "crate" => Vec::new(),
            _ => at.clone(),
        };
        let mut k = 0;
        while k < segs.len() {
            match segs[k] {
                "crate" if k == 0 => {}
                "self" => {}
                "super" => {
                    cur.pop();
                }
                _ => break,
            }
            k += 1;
        }
        while k < segs.len() {
            let mut next = cur.clone();
            next.push(segs[k].to_string());
            if self.modules.contains_key(&next) {
                cur = next;
                k += 1;
            } else {
                break;
            }
        }
        if !self.modules.contains_key(&cur) {
            return None;
        }
        if let Some(item) = segs.get(k) {
            if depth < 16 {
                if let Some(target) = self.exports.get(&cur).and_then(|e| e.get(*item)) {
                    return self.resolve(&cur, target, depth + 1).or(Some(cur));
                }
            }
        }
        Some(cur)
    }
}

fn uses(modules: &BTreeMap<Module, String>) -> BTreeMap<Module, BTreeSet<Module>> {
    let mut exports = BTreeMap::new();
    let mut decls = BTreeMap::new();
    for (m, text) in modules {
        let mut ex = BTreeMap::new();
        let mut all = Vec::new();
        for (is_pub, tree) in use_declarations(text) {
            for (path, alias) in expand_use(&tree) {
                if is_pub && alias != "*" {
                    ex.insert(alias, path.clone());
                }
                all.push(path);
            }
        }
        exports.insert(m.clone(), ex);
        decls.insert(m.clone(), all);
    }
    let r = Resolver { modules, exports };
    let mut graph = BTreeMap::new();
    for (m, text) in modules {
        let children: BTreeSet<String> = modules
            .keys()
            .filter(|c| c.len() == m.len() + 1 && c.starts_with(m))
            .map(|c| c[m.len()].clone())
            .collect();
        let mut to = BTreeSet::new();
        let paths = decls[m]
            .iter()
            .filter(|p| {
                let first = p.split("::").next().unwrap_or("");
                matches!(first, "crate" | "super" | "self") || children.contains(first)
            })
            .cloned()
            .chain(code_paths(text, &children));
        for p in paths {
            let p = p.trim_end_matches("::*");
            if let Some(t) = r.resolve(m, p, 0) {
                if &t != m {
                    to.insert(t);
                }
            }
        }
        graph.insert(m.clone(), to);
    }
    graph
}

/// Strongly connected components of two or more nodes (Tarjan, iterative).
fn cycles(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    let nodes: Vec<&Module> = graph.keys().collect();
    let id: BTreeMap<&Module, usize> = nodes.iter().enumerate().map(|(i, m)| (*m, i)).collect();
    let adj: Vec<Vec<usize>> = nodes
        .iter()
        .map(|m| {
            graph[*m]
                .iter()
                .filter_map(|t| id.get(t).copied())
                .collect()
        })
        .collect();
    let n = nodes.len();
    let (mut index, mut low, mut on) = (vec![usize::MAX; n], vec![0; n], vec![false; n]);
    let (mut stack, mut out, mut counter) = (Vec::new(), Vec::new(), 0);
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        let mut call = vec![(root, 0usize)];
        index[root] = counter;
        low[root] = counter;
        counter += 1;
        stack.push(root);
        on[root] = true;
        while let Some(&mut (v, ref mut e)) = call.last_mut() {
            if *e < adj[v].len() {
                let w = adj[v][*e];
                *e += 1;
                if index[w] == usize::MAX {
                    index[w] = counter;
                    low[w] = counter;
                    counter += 1;
                    stack.push(w);
                    on[w] = true;
                    call.push((w, 0));
                } else if on[w] {
                    low[v] = low[v].min(index[w]);
                }
            } else {
                call.pop();
                if let Some(&(u, _)) = call.last() {
                    low[u] = low[u].min(low[v]);
                }
                if low[v] == index[v] {
                    let mut comp = Vec::new();
                    loop {
                        let w = stack.pop().expect("on stack");
                        on[w] = false;
                        comp.push(nodes[w].clone());
                        if w == v {
                            break;
                        }
                    }
                    if comp.len() > 1 {
                        comp.sort();
                        out.push(comp);
                    }
                }
            }
        }
    }
    out.sort();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn graph(files: &[(&str, &str)]) -> Vec<Vec<String>> {
        let modules: BTreeMap<Module, String> = files
            .iter()
            .map(|(m, t)| {
                let m: Module = if m.is_empty() {
                    Vec::new()
                } else {
                    m.split('/').map(str::to_string).collect()
                };
                (m, drop_test_modules(&clean(t)))
            })
            .collect();
        cycles(&uses(&modules))
            .into_iter()
            .map(|c| c.into_iter().map(|m| name(&m)).collect())
            .collect()
    }

    #[test]
    fn finds_a_cycle_through_a_path() {
        let c = graph(&[
            ("", "mod a; mod b;"),
            ("a", "use crate::b::X; pub struct Y;"),
            ("b", "pub struct X; fn f() { crate::a::Y; }"),
        ]);
        assert_eq!(c, vec![vec!["a".to_string(), "b".to_string()]]);
    }

    #[test]
    fn follows_reexports_to_the_defining_file() {
        // `crate::X` is re-exported by the root from `a`: `b` uses `a`,
        // not the root, so the root's `pub use` makes no cycle.
        let c = graph(&[
            ("", "mod a; mod b; pub use a::X; pub use b::f;"),
            ("a", "pub struct X;"),
            ("b", "use crate::X; pub fn f() {}"),
        ]);
        assert!(c.is_empty(), "{c:?}");
    }

    #[test]
    fn parent_and_child_using_each_other_is_a_cycle() {
        let c = graph(&[
            ("p", "mod c; pub struct Opt; fn run() { c::go(); }"),
            ("p/c", "use super::Opt; pub fn go() {}"),
        ]);
        assert_eq!(c, vec![vec!["p".to_string(), "p/c".to_string()]]);
    }

    #[test]
    fn comments_strings_and_tests_are_ignored() {
        let c = graph(&[
            ("", "mod a; mod b;"),
            (
                "a",
                "// crate::b::X\n/* crate::b::X */ const S: &str = \"crate::b::X\"; pub struct Y;",
            ),
            (
                "b",
                "pub struct X;\n#[cfg(test)]\nmod tests { use crate::a::Y; }",
            ),
        ]);
        assert!(c.is_empty(), "{c:?}");
    }

    #[test]
    fn use_trees_expand() {
        let e = expand_use("crate::a::{b, c::{d, e as f}, self}");
        let paths: Vec<&str> = e.iter().map(|(p, _)| p.as_str()).collect();
        assert_eq!(
            paths,
            [
                "crate::a::b",
                "crate::a::c::d",
                "crate::a::c::e",
                "crate::a"
            ]
        );
        assert_eq!(e[2].1, "f");
    }
}
