//! The source tree's shape, read from its imports: the dependencies between top-level modules
//! (folders) and between the files of one folder form no cycle, every `mod.rs` is a face
//! (declarations and re-exports) and no file below a face imports anything the face itself
//! defines, and no source file outside tests is longer than the limit. Reads `src/` as text (no
//! compiler): `use` trees, inline `crate::`/`super::` paths, bare paths into child modules and
//! into modules a `use` names, resolved through re-exports to the file that defines the item.
//! Test code (`#[cfg(test)]` modules and files) counts for the folder graph but not for file
//! sizes.
//!
//! The test tree too: every test file is built (a stray `tests/foo.rs` fails here), and no
//! test can return early and report "ok" having run nothing.
//!
//! Run `cargo test --test architecture -- --nocapture` to print both graphs.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Longest source file allowed outside tests (lines).
const MAX_LINES: usize = 600;

/// Files still over the limit, each a few concepts to split into files of one, with the size
/// none may grow beyond. A file split below the limit must leave this list (empty now: every
/// source file is below the limit).
const OVERSIZE: &[(&str, usize)] = &[];

/// One source file: its module path (`["driver", "step"]`; the crate root is `[]`).
struct File {
    path: PathBuf,
    module: Vec<String>,
    /// Whether the module is a directory module (`mod.rs`/`lib.rs`): its children live below it.
    is_dir: bool,
    text: String,
    lines: usize,
    test_only: bool,
}

fn src_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

fn module_of(rel: &Path) -> (Vec<String>, bool) {
    let mut parts: Vec<String> = rel.iter().map(|s| s.to_string_lossy().trim_end_matches(".rs").to_string()).collect();
    let last = parts.pop().unwrap();
    match last.as_str() {
        "lib" | "main" if parts.is_empty() => (parts, true),
        "mod" => (parts, true),
        _ => {
            parts.push(last);
            (parts, false)
        }
    }
}

/// Drops comments and string literals (so `"crate::x"` in a message is no dependency).
fn strip(text: &str) -> String {
    let b: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == '/' && i + 1 < b.len() && b[i + 1] == '/' {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if b[i] == '/' && i + 1 < b.len() && b[i + 1] == '*' {
            i += 2;
            while i + 1 < b.len() && !(b[i] == '*' && b[i + 1] == '/') {
                i += 1;
            }
            i += 2;
        } else if b[i] == '"' {
            // A raw string r#"..."# is rare here; plain strings with escapes suffice.
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if b[i] == '\'' && i + 2 < b.len() && (b[i + 2] == '\'' || b[i + 1] == '\\') {
            // a char literal ('{', '\n'); lifetimes ('a) have no closing quote here
            i += 1;
            while i < b.len() && b[i] != '\'' {
                if b[i] == '\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    out
}

/// Splits stripped text into (production, test) parts: an inline `#[cfg(test)] mod x { ... }`
/// block goes to the test part (brace-matched on stripped text).
fn split_tests(text: &str) -> (String, String) {
    let mut prod = String::new();
    let mut test = String::new();
    let mut rest = text;
    while let Some(at) = rest.find("#[cfg(test)]") {
        prod.push_str(&rest[..at]);
        let after = &rest[at + "#[cfg(test)]".len()..];
        let trimmed = after.trim_start();
        let is_block =
            trimmed.starts_with("mod ") && trimmed.find('{').is_some_and(|b| trimmed.find(';').is_none_or(|s| b < s));
        if !is_block {
            // an attribute on one item (`mod x;`, a fn, a use): that item is test code
            let end = after.find([';', '{']).unwrap_or(after.len());
            let end = if after[end..].starts_with('{') { block_end(after, end) } else { end + 1 };
            test.push_str(&after[..end]);
            rest = &after[end..];
            continue;
        }
        let open = after.find('{').unwrap();
        let end = block_end(after, open);
        test.push_str(&after[..end]);
        rest = &after[end..];
    }
    prod.push_str(rest);
    (prod, test)
}

fn block_end(s: &str, open: usize) -> usize {
    let mut depth = 0usize;
    for (i, c) in s[open..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    return open + i + 1;
                }
            }
            _ => {}
        }
    }
    s.len()
}

/// The code of a module and of each inline `mod name { ... }` inside it, each with its own
/// module path (a nested module's `super::` is its parent, not the file's parent).
fn units(code: &str, module: &[String]) -> Vec<(Vec<String>, String)> {
    let mut own = String::new();
    let mut out = Vec::new();
    let mut rest = code;
    while let Some((name, open)) = find_inline_mod(rest) {
        own.push_str(&rest[..open]);
        let end = block_end(rest, open);
        let mut inner = module.to_vec();
        inner.push(name);
        out.extend(units(&rest[open + 1..end - 1], &inner));
        rest = &rest[end..];
    }
    own.push_str(rest);
    out.insert(0, (module.to_vec(), own));
    out
}

/// The next `mod name {` in `code`: its name and the position of its `{`.
fn find_inline_mod(code: &str) -> Option<(String, usize)> {
    let mut from = 0;
    while let Some(i) = code[from..].find("mod ") {
        let at = from + i;
        from = at + 4;
        if at > 0 && is_ident(code[..at].chars().last().unwrap()) {
            continue;
        }
        let name: String = code[at + 4..].chars().take_while(|&c| is_ident(c)).collect();
        let after = code[at + 4 + name.len()..].trim_start();
        if !name.is_empty() && after.starts_with('{') {
            let open = code.len() - after.len();
            return Some((name, open));
        }
    }
    None
}

/// The paths a `use` tree names, expanded: `a::{b, c::d}` → `a::b`, `a::c::d` (aliases dropped).
fn expand_use(tree: &str) -> Vec<String> {
    expand_use_named(tree).into_iter().map(|(path, _)| path).collect()
}

/// The paths a `use` tree names, each with the name it binds: `a::{b as c, d::{self}}` →
/// (`a::b`, `c`), (`a::d`, `d`).
fn expand_use_named(tree: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    expand_into("", tree, &mut out);
    out
}

fn expand_into(prefix: &str, tree: &str, out: &mut Vec<(String, String)>) {
    let mut depth = 0;
    let mut start = 0;
    let mut items = Vec::new();
    for (i, c) in tree.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&tree[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    items.push(&tree[start..]);
    for item in items {
        let item = item.trim();
        if item.is_empty() {
            continue;
        }
        if let Some(b) = item.find('{') {
            let head = item[..b].trim().trim_end_matches("::");
            let inner = &item[b + 1..item.rfind('}').unwrap_or(item.len())];
            expand_into(&join(prefix, head), inner, out);
        } else {
            let mut parts = item.split(" as ");
            let path: String = parts.next().unwrap().chars().filter(|c| !c.is_whitespace()).collect();
            let path = join(prefix, &path);
            let name = match parts.next() {
                Some(alias) => alias.trim().to_string(),
                None => path.rsplit("::").next().unwrap_or_default().to_string(),
            };
            out.push((path, name));
        }
    }
}

fn join(a: &str, b: &str) -> String {
    if a.is_empty() {
        b.to_string()
    } else if b.is_empty() || b == "self" {
        a.to_string()
    } else {
        format!("{a}::{b}")
    }
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Paths in code outside `use` lines that start with `crate::` or `super::`.
fn inline_paths(code: &str) -> Vec<String> {
    ["crate", "super"]
        .iter()
        .flat_map(|start| paths_from(code, start))
        .map(|(start, rest)| join(&start, &rest))
        .collect()
}

/// The paths in `code` that start with the name `start` (`start::a::b`, not `x::start::a` nor
/// `my_start::a`), each as (`start`, the rest: `a::b`; empty for `start::{...}`).
fn paths_from(code: &str, start: &str) -> Vec<(String, String)> {
    let head = format!("{start}::");
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = code[from..].find(&head) {
        let at = from + i;
        from = at + head.len();
        if code[..at].chars().last().is_some_and(|c| is_ident(c) || c == ':') {
            continue; // inside a longer name, or a later segment of another path
        }
        let rest = &code[at + head.len()..];
        let mut len = 0;
        let mut chars = rest.char_indices().peekable();
        while let Some((k, c)) = chars.next() {
            if is_ident(c) {
                len = k + c.len_utf8();
            } else if c == ':' && chars.peek().is_some_and(|&(_, n)| n == ':') {
                chars.next();
            } else {
                break;
            }
        }
        out.push((start.to_string(), rest[..len].to_string()));
    }
    out
}

fn use_trees(code: &str) -> Vec<(bool, String)> {
    // (is a `pub use`, tree)
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = code[from..].find("use ") {
        let at = from + i;
        from = at + 4;
        let before = code[..at].trim_end();
        let line_start = before.is_empty()
            || before.ends_with(';')
            || before.ends_with('{')
            || before.ends_with('}')
            || before.ends_with(']')
            || before.ends_with("pub")
            || before.ends_with(')');
        if !line_start || (at > 0 && is_ident(code[..at].chars().last().unwrap())) {
            continue;
        }
        let is_pub = before.ends_with("pub") || before.ends_with(')') && before.contains("pub(");
        let Some(end) = code[at..].find(';') else { break };
        out.push((is_pub, code[at + 4..at + end].to_string()));
        from = at + end;
    }
    out
}

/// One path in a file's code, resolved: the file `to` that defines what it names, and the item
/// named there (None: the module itself).
struct Dep {
    from: usize,
    to: usize,
    item: Option<String>,
    is_test: bool,
}

struct Tree {
    files: Vec<File>,
    /// module path → file index
    by_module: BTreeMap<Vec<String>, usize>,
}

impl Tree {
    fn read() -> Tree {
        let src = src_dir();
        let mut paths = Vec::new();
        collect(&src, &mut paths);
        let mut sources = Vec::new();
        for path in paths {
            let rel = path.strip_prefix(&src).unwrap().to_path_buf();
            if rel == Path::new("main.rs") {
                continue; // the binary: a separate crate using `poroplast::`
            }
            sources.push((rel, std::fs::read_to_string(&path).unwrap()));
        }
        Tree::from_sources(sources)
    }

    /// The tree of these files (paths relative to `src/`, with their text).
    fn from_sources(sources: Vec<(PathBuf, String)>) -> Tree {
        let mut files = Vec::new();
        for (rel, text) in sources {
            let (module, is_dir) = module_of(&rel);
            let lines = text.lines().count();
            files.push(File { path: rel, module, is_dir, text, lines, test_only: false });
        }
        let by_module = files.iter().enumerate().map(|(i, f)| (f.module.clone(), i)).collect();
        let mut tree = Tree { files, by_module };
        tree.mark_test_files();
        tree
    }

    /// Files declared under `#[cfg(test)] mod x;` are test code.
    fn mark_test_files(&mut self) {
        let mut test_modules = Vec::new();
        for f in &self.files {
            let code = strip(&f.text);
            let mut from = 0;
            while let Some(i) = code[from..].find("#[cfg(test)]") {
                let at = from + i + "#[cfg(test)]".len();
                from = at;
                let rest = code[at..].trim_start();
                let rest = rest.strip_prefix("pub ").unwrap_or(rest);
                let rest = rest.strip_prefix("pub(crate) ").unwrap_or(rest);
                if let Some(m) = rest.strip_prefix("mod ") {
                    let name: String = m.chars().take_while(|&c| is_ident(c)).collect();
                    if m[name.len()..].trim_start().starts_with(';') {
                        let mut module = f.module.clone();
                        module.push(name);
                        test_modules.push(module);
                    }
                }
            }
        }
        for f in &mut self.files {
            if test_modules.iter().any(|m| f.module.starts_with(m)) {
                f.test_only = true;
            }
        }
    }

    /// The module (as a path) a use path refers to, from module `at`, or None for other crates.
    fn absolute(&self, at: &[String], path: &str) -> Option<Vec<String>> {
        let segs: Vec<&str> = path.split("::").filter(|s| !s.is_empty()).collect();
        let first = *segs.first()?;
        // the module that a relative path starts from: `self` is the file's module
        let mut base: Vec<String> = at.to_vec();
        let mut rest: &[&str] = &segs;
        match first {
            "crate" => {
                base.clear();
                rest = &segs[1..];
            }
            "self" => rest = &segs[1..],
            "super" => {
                let mut k = 0;
                while k < segs.len() && segs[k] == "super" {
                    base.pop()?;
                    k += 1;
                }
                rest = &segs[k..];
            }
            name => {
                // a bare path: only a child module of this one counts (2018 paths)
                let mut child = at.to_vec();
                child.push(name.to_string());
                if !self.by_module.contains_key(&child) {
                    return None;
                }
            }
        }
        let mut full = base;
        full.extend(rest.iter().map(|s| s.to_string()));
        Some(full)
    }

    /// What `full` names: the file that defines it, and the item named there (None for the
    /// module itself, `use crate::petsc;`; `*` for a glob). The longest module prefix is the
    /// file, followed through that module's `use`s (its re-exports, `pub use child::X`, and the
    /// imports its child modules see) when the next segment is a name one of them binds; a name
    /// bound from another crate is no file of this one (None). A face re-exports by name: a
    /// glob re-export (`pub use child::*`) is not followed.
    fn resolve(&self, full: &[String], depth: usize) -> Option<(usize, Option<String>)> {
        let mut k = full.len();
        while k > 0 && !self.by_module.contains_key(&full[..k]) {
            k -= 1;
        }
        let idx = *self.by_module.get(&full[..k])?;
        let Some(item) = full.get(k) else { return Some((idx, None)) };
        if depth < 8 && item != "*" {
            let f = &self.files[idx];
            let (prod, _) = split_tests(&strip(&f.text));
            let own = units(&prod, &f.module).swap_remove(0).1;
            for (_, tree) in use_trees(&own) {
                for (p, name) in expand_use_named(&tree) {
                    if name == *item {
                        match self.absolute(&f.module, &p) {
                            Some(abs) if abs != full[..k] => return self.resolve(&abs, depth + 1),
                            Some(_) => {}
                            None => return None,
                        }
                    }
                }
            }
        }
        Some((idx, Some(item.clone())))
    }

    /// (from file, to file, is test code) for every dependency between two different files.
    fn edges(&self) -> Vec<(usize, usize, bool)> {
        let set: BTreeSet<_> = self.dependencies().into_iter().map(|d| (d.from, d.to, d.is_test)).collect();
        set.into_iter().collect()
    }

    /// Every path in the code that names something in another file of the crate, resolved.
    fn dependencies(&self) -> Vec<Dep> {
        let mut out = Vec::new();
        for (i, f) in self.files.iter().enumerate() {
            let (prod, test) = split_tests(&strip(&f.text));
            for (code, is_test) in [(prod, f.test_only), (test, true)] {
                let mut paths = Vec::new();
                for (module, code) in units(&code, &f.module) {
                    let top = module == f.module;
                    // names a `use` binds to a module (`use crate::petsc::options;`), whose bare
                    // paths (`options::set`) are paths into that module
                    let mut modules = Vec::new();
                    for (is_pub, tree) in use_trees(&code) {
                        for (p, name) in expand_use_named(&tree) {
                            let abs = self.absolute(&module, &p);
                            if let Some(a) = abs.as_ref().filter(|a| self.by_module.contains_key(*a)) {
                                modules.push((name, a.clone()));
                            }
                            // a directory module's re-export of its own child is structure, not use
                            if is_pub && f.is_dir && top {
                                if let Some(a) = &abs {
                                    if a.starts_with(&f.module) && a.len() > f.module.len() {
                                        continue;
                                    }
                                }
                            }
                            paths.push(abs);
                        }
                    }
                    for p in inline_paths(&code) {
                        paths.push(self.absolute(&module, &p));
                    }
                    for (name, at) in modules {
                        for (_, rest) in paths_from(&code, &name).into_iter().filter(|(_, r)| !r.is_empty()) {
                            paths.push(Some(at.iter().cloned().chain(rest.split("::").map(String::from)).collect()));
                        }
                    }
                }
                for full in paths.into_iter().flatten() {
                    if let Some((j, item)) = self.resolve(&full, 0) {
                        // inside a test module `super::` is the file itself; the crate root only
                        // declares modules (a `super::` in a macro body lands there)
                        if j != i && !self.files[j].module.is_empty() {
                            out.push(Dep { from: i, to: j, item, is_test });
                        }
                    }
                }
            }
        }
        out
    }

    fn folder(&self, i: usize) -> String {
        self.files[i].module.first().cloned().unwrap_or_else(|| "crate".into())
    }

    fn parent(&self, i: usize) -> Vec<String> {
        let f = &self.files[i];
        let mut p = f.module.clone();
        if !f.is_dir {
            p.pop();
        }
        p
    }
}

/// The strongly connected components with more than one node (the cycles), by Tarjan.
fn cycles(nodes: &[String], edges: &BTreeSet<(String, String)>) -> Vec<Vec<String>> {
    struct S<'a> {
        adj: BTreeMap<&'a str, Vec<&'a str>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on: BTreeSet<&'a str>,
        next: usize,
        out: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut S<'a>, v: &'a str) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        s.on.insert(v);
        for w in s.adj.get(v).cloned().unwrap_or_default() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let l = s.low[v].min(s.low[w]);
                s.low.insert(v, l);
            } else if s.on.contains(w) {
                let l = s.low[v].min(s.index[w]);
                s.low.insert(v, l);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on.remove(w);
                comp.push(w.to_string());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut adj: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (a, b) in edges {
        adj.entry(a.as_str()).or_default().push(b.as_str());
    }
    let mut s = S {
        adj,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: vec![],
        on: BTreeSet::new(),
        next: 0,
        out: vec![],
    };
    for n in nodes {
        if !s.index.contains_key(n.as_str()) {
            visit(&mut s, n);
        }
    }
    s.out
}

fn report(title: &str, edges: &BTreeSet<(String, String)>) {
    println!("{title}:");
    let mut by: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for (a, b) in edges {
        by.entry(a).or_default().push(b);
    }
    for (a, bs) in by {
        println!("  {a} -> {}", bs.join(", "));
    }
}

#[test]
fn top_level_modules_form_no_cycle() {
    let tree = Tree::read();
    let mut edges = BTreeSet::new();
    let mut why: BTreeMap<(String, String), String> = BTreeMap::new();
    for (i, j, is_test) in tree.edges() {
        let (a, b) = (tree.folder(i), tree.folder(j));
        if a != b && a != "crate" {
            why.entry((a.clone(), b.clone())).or_insert_with(|| {
                format!(
                    "{} -> {}{}",
                    tree.files[i].path.display(),
                    tree.files[j].path.display(),
                    if is_test { " (test)" } else { "" }
                )
            });
            edges.insert((a, b));
        }
    }
    report("top-level modules (tests included)", &edges);
    let nodes: Vec<String> = edges.iter().flat_map(|(a, b)| [a.clone(), b.clone()]).collect();
    let found = cycles(&nodes, &edges);
    let explain: Vec<String> = found
        .iter()
        .map(|c| {
            let inside: Vec<&String> =
                why.iter().filter(|((a, b), _)| c.contains(a) && c.contains(b)).map(|(_, w)| w).collect();
            format!("{c:?} via {inside:?}")
        })
        .collect();
    assert!(found.is_empty(), "cycles between top-level modules: {explain:#?}");
}

#[test]
fn files_of_one_folder_form_no_cycle() {
    let tree = Tree::read();
    let mut edges = BTreeSet::new();
    for (i, j, is_test) in tree.edges() {
        // within one directory module: the files whose parent is the same module
        if !is_test && (tree.parent(i) == tree.parent(j) || tree.files[j].module == tree.parent(i)) {
            let name = |k: usize| tree.files[k].path.display().to_string();
            edges.insert((name(i), name(j)));
        }
    }
    let nodes: Vec<String> = edges.iter().flat_map(|(a, b)| [a.clone(), b.clone()]).collect();
    let found = cycles(&nodes, &edges);
    if !found.is_empty() {
        report("file dependencies inside folders (production code)", &edges);
    }
    assert!(found.is_empty(), "cycles between the files of one folder: {found:#?}");
}

/// What a `mod.rs` (or the crate root) holds beyond a face's declarations (`mod x;`), imports
/// and re-exports (`use`), attributes and comments: the first line of that code, or None.
fn beyond_face(text: &str) -> Option<String> {
    let code = strip(text);
    let mut rest = code.trim_start();
    while !rest.is_empty() {
        if rest.starts_with("#[") || rest.starts_with("#![") {
            let mut depth = 0;
            let end = rest.char_indices().find_map(|(k, c)| {
                match c {
                    '[' => depth += 1,
                    ']' => depth -= 1,
                    _ => return None,
                }
                (depth == 0).then_some(k + 1)
            });
            rest = rest[end.unwrap_or(rest.len())..].trim_start();
            continue;
        }
        let item = match rest.strip_prefix("pub(") {
            Some(vis) => vis[vis.find(')').map_or(vis.len(), |k| k + 1)..].trim_start(),
            None => rest.strip_prefix("pub ").unwrap_or(rest).trim_start(),
        };
        let declared = item.strip_prefix("mod ").is_some_and(|m| {
            let name = m.find(|c: char| !is_ident(c)).unwrap_or(m.len());
            m[name..].trim_start().starts_with(';')
        });
        if declared || item.starts_with("use ") {
            rest = item[item.find(';').map_or(item.len(), |k| k + 1)..].trim_start();
            continue;
        }
        return Some(rest.lines().next().unwrap_or_default().trim().to_string());
    }
    None
}

/// Every `mod.rs` (and the crate root) is a face: it declares the folder's files and re-exports
/// what others use of them; the folder's code lives in those files, each named for its concept.
#[test]
fn every_mod_rs_is_a_face_only() {
    let tree = Tree::read();
    let found: Vec<String> = tree
        .files
        .iter()
        .filter(|f| f.is_dir)
        .filter_map(|f| beyond_face(&f.text).map(|code| format!("{}: {code}", f.path.display())))
        .collect();
    assert!(
        found.is_empty(),
        "mod.rs files holding code beyond declarations and re-exports (move it to a named file of the \
         folder): {found:#?}"
    );
}

/// The imports that tie a folder's face to a file below it both ways: the face composes the files
/// below it (declares them, re-exports from them), so a file there that imports something the face
/// itself defines closes a cycle. An import through the face of a name it re-exports is followed
/// to the file defining it (`super::X` after `pub use child::X` names `child`), so it is no tie;
/// a glob import of a face (`use super::*`) is one if the face holds code. One line per tie:
/// `importer -> face::item`.
fn face_ties(tree: &Tree) -> BTreeSet<String> {
    let mut ties = BTreeSet::new();
    for d in tree.dependencies() {
        let (from, face) = (&tree.files[d.from], &tree.files[d.to]);
        let below = face.is_dir && from.module.len() > face.module.len() && from.module.starts_with(&face.module);
        let defined_there = match d.item.as_deref() {
            None => false, // the module itself: its names are read as paths into it
            Some("*") => beyond_face(&face.text).is_some(),
            Some(_) => true,
        };
        if below && defined_there {
            ties.insert(format!(
                "{} -> {}::{}{}",
                from.path.display(),
                face.path.display(),
                d.item.unwrap_or_default(),
                if d.is_test { " (test)" } else { "" }
            ));
        }
    }
    ties
}

/// No folder's face and a file below it form a two-way tie (the cycle checks above see a face's
/// re-exports as structure, not use, so they cannot see this one).
#[test]
fn no_file_imports_what_its_folders_face_defines() {
    let ties = face_ties(&Tree::read());
    assert!(
        ties.is_empty(),
        "files importing what their folder's mod.rs defines, while that mod.rs declares them (move the \
         item to a named file of the folder and re-export it): {ties:#?}"
    );
}

#[test]
fn the_reader_follows_a_faces_re_exports() {
    let tree = |files: &[(&str, &str)]| {
        Tree::from_sources(files.iter().map(|(p, t)| (PathBuf::from(p), t.to_string())).collect())
    };
    let name = |t: &Tree, i: usize| t.files[i].path.display().to_string();
    // a face only: `b` imports `X` through it, which is `a`'s
    let face = "//! doc\n#[macro_use]\nmod a;\nmod b;\npub use a::X;\npub(crate) use a::f as g;\n";
    let a = "pub struct X;\npub(crate) fn f() {}\n";
    let b = "use super::X;\nuse crate::m;\nfn h() { super::g(); m::a::f(); }\n";
    let t = tree(&[("lib.rs", "mod m;"), ("m/mod.rs", face), ("m/a.rs", a), ("m/b.rs", b)]);
    let deps: BTreeSet<(String, String, Option<String>)> =
        t.dependencies().iter().map(|d| (name(&t, d.from), name(&t, d.to), d.item.clone())).collect();
    let want = |to: &str, item: Option<&str>| ("m/b.rs".to_string(), to.to_string(), item.map(String::from));
    assert!(deps.contains(&want("m/a.rs", Some("X"))), "{deps:?}");
    assert!(deps.contains(&want("m/a.rs", Some("f"))), "through the alias g: {deps:?}");
    assert!(deps.contains(&want("m/mod.rs", None)), "`use crate::m;` names the module: {deps:?}");
    assert!(!deps.iter().any(|(_, to, item)| to == "m/mod.rs" && item.is_some()), "{deps:?}");
    assert!(face_ties(&t).is_empty());
    // the face defines `Y`, which `b` imports: a two-way tie, however it is named
    for import in ["use super::Y;", "fn h() { crate::m::Y::new(); }", "use crate::m;\nfn h() { m::Y::new(); }"] {
        let face = format!("{face}pub struct Y;\n");
        let t = tree(&[("lib.rs", "mod m;"), ("m/mod.rs", &face), ("m/a.rs", a), ("m/b.rs", import)]);
        assert_eq!(face_ties(&t), BTreeSet::from(["m/b.rs -> m/mod.rs::Y".to_string()]), "{import}");
    }
    // a grandchild, a glob of a face with code, and an item bound from another crate
    let face_y = format!("{face}pub struct Y;\nuse std::fmt::Debug;\n");
    let t = tree(&[
        ("lib.rs", "mod m;"),
        ("m/mod.rs", &face_y),
        ("m/a.rs", a),
        ("m/b/mod.rs", "mod c;"),
        ("m/b/c.rs", "use super::super::*;\nuse super::super::Debug;\n#[cfg(test)]\nmod t { use crate::m::Y; }\n"),
    ]);
    assert_eq!(
        face_ties(&t),
        BTreeSet::from(["m/b/c.rs -> m/mod.rs::*".to_string(), "m/b/c.rs -> m/mod.rs::Y (test)".to_string()])
    );
    // what a face may hold
    assert_eq!(beyond_face(face), None);
    assert_eq!(beyond_face("#![allow(x)]\n#[allow(a, b)]\npub mod ffi;\npub(in crate::x) use a::{b, c};"), None);
    assert_eq!(beyond_face("mod a;\n/// f\npub fn f() {}\n"), Some("pub fn f() {}".to_string()));
    assert_eq!(beyond_face("mod a {\n}\n"), Some("mod a {".to_string()));
    assert_eq!(beyond_face("#[cfg(test)]\nmod tests;\nconst N: usize = 1;"), Some("const N: usize = 1;".to_string()));
}

#[test]
fn no_source_file_outside_tests_exceeds_the_limit() {
    let tree = Tree::read();
    let mut problems = Vec::new();
    for f in tree.files.iter().filter(|f| !f.test_only) {
        let path = f.path.display().to_string();
        match OVERSIZE.iter().find(|(p, _)| *p == path) {
            Some((_, allowed)) if f.lines > *allowed => {
                problems.push(format!("{path} grew to {} lines (at most {allowed} until it is split)", f.lines))
            }
            Some(_) if f.lines <= MAX_LINES => {
                problems.push(format!("{path} is {} lines now: take it off OVERSIZE", f.lines))
            }
            None if f.lines > MAX_LINES => problems.push(format!("{path} ({} lines)", f.lines)),
            _ => {}
        }
    }
    for (p, _) in OVERSIZE {
        if !tree.files.iter().any(|f| f.path.display().to_string() == *p) {
            problems.push(format!("{p} (on OVERSIZE) does not exist"));
        }
    }
    assert!(problems.is_empty(), "source files over {MAX_LINES} lines: {problems:?}");
}

#[test]
fn the_reader_sees_use_trees_and_paths() {
    // the parser itself, on known shapes
    assert_eq!(expand_use("crate::{a::b, c::{d, e as f}}"), ["crate::a::b", "crate::c::d", "crate::c::e"]);
    assert_eq!(expand_use("super::x::{self, Y}"), ["super::x", "super::x::Y"]);
    assert_eq!(inline_paths("let a = crate::mesh::Mesh::new(); super::f()"), ["crate::mesh::Mesh::new", "super::f"]);
    assert_eq!(inline_paths("super::super::f(x::super::g)"), ["super::super::f"]);
    assert_eq!(
        expand_use_named("crate::{a::b as c, d::{self}, e}"),
        [("crate::a::b".into(), "c".into()), ("crate::d".into(), "d".into()), ("crate::e".into(), "e".into())]
            as [(String, String); 3]
    );
    assert_eq!(
        paths_from("options::set(1); x::options::y; my_options::z; options::{a}", "options"),
        [("options".into(), "set".into()), ("options".into(), String::new())] as [(String, String); 2]
    );
    let (p, t) =
        split_tests("fn a() {}\n#[cfg(test)]\nmod tests {\n use super::*;\n fn b() { if x { } }\n}\nfn c() {}");
    assert!(p.contains("fn a") && p.contains("fn c") && !p.contains("fn b"));
    assert!(t.contains("fn b"));
    assert_eq!(strip("let s = \"crate::x\"; // crate::y\n'{'"), "let s = \"\"; \n");
}

// The test tree: with `autotests = false` (Cargo.toml) a test file is built only if Cargo.toml
// names it as a target or a built file declares it as a module; a file nobody names is silently
// not compiled, and its tests never run. And libtest has no run-time skip: a test that returns
// early reports "ok" having checked nothing, so the slow or unavailable goes behind `#[ignore]`.

fn package_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The files under `dir` (recursively), relative to the package, sorted.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy();
            if name.starts_with('.') || name == "__pycache__" {
                continue; // an editor's or Python's, not the tree's
            } else if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(package_dir()).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// The `path`s of Cargo.toml's `[[test]]`, `[[example]]`, `[[bin]]` and `[[bench]]` targets.
fn cargo_target_paths() -> Vec<PathBuf> {
    let manifest: toml::Table = std::fs::read_to_string(package_dir().join("Cargo.toml")).unwrap().parse().unwrap();
    let mut out = Vec::new();
    for kind in ["test", "example", "bin", "bench"] {
        for target in manifest.get(kind).and_then(|t| t.as_array()).into_iter().flatten() {
            if let Some(p) = target.get("path").and_then(|p| p.as_str()) {
                out.push(PathBuf::from(p));
            }
        }
    }
    out
}

/// The module files `file` (relative to the package, with its text) declares (`mod x;`, with or
/// without `#[path = "..."]`), as rustc finds them: beside a crate root or a `mod.rs`, else in
/// the folder named after the file. Reads rustfmt's layout: one attribute or item per line.
fn declared_modules(file: &Path, text: &str, is_root: bool) -> Vec<PathBuf> {
    let dir = file.parent().unwrap();
    let own = if is_root || file.file_name().is_some_and(|n| n == "mod.rs") {
        dir.to_path_buf()
    } else {
        dir.join(file.file_stem().unwrap())
    };
    let mut out = Vec::new();
    let mut path_attr: Option<&str> = None;
    for line in text.lines().map(str::trim) {
        if let Some(p) = line.strip_prefix("#[path = \"").and_then(|l| l.strip_suffix("\"]")) {
            path_attr = Some(p);
            continue;
        }
        let item = line.strip_prefix("pub ").or_else(|| line.strip_prefix("pub(crate) ")).unwrap_or(line);
        let name = item.strip_prefix("mod ").and_then(|l| l.strip_suffix(';'));
        match (name, path_attr) {
            (Some(_), Some(p)) => out.push(dir.join(p)),
            (Some(n), None) if package_dir().join(&own).join(n).join("mod.rs").is_file() => {
                out.push(own.join(n).join("mod.rs"))
            }
            (Some(n), None) => out.push(own.join(format!("{n}.rs"))),
            _ => {}
        }
        if !line.starts_with("#[") {
            path_attr = None;
        }
    }
    out
}

/// The Rust files under `tests/` that are compiled: the Cargo targets there and the modules
/// they declare, transitively.
fn built_test_files() -> BTreeSet<PathBuf> {
    let mut built = BTreeSet::new();
    let mut todo: Vec<(PathBuf, bool)> =
        cargo_target_paths().into_iter().filter(|p| p.starts_with("tests")).map(|p| (p, true)).collect();
    while let Some((file, is_root)) = todo.pop() {
        let Ok(text) = std::fs::read_to_string(package_dir().join(&file)) else { continue };
        if built.insert(file.clone()) {
            todo.extend(declared_modules(&file, &text, is_root).into_iter().map(|m| (m, false)));
        }
    }
    built
}

/// Every Rust file under `tests/` is compiled (a Cargo target or a module of one), and every other
/// file there (the scripts of `tests/support`) is named by a compiled one. `tests/data` is left
/// out: inputs that the unit tests of `src/` read too, by names they build.
#[test]
fn every_test_file_is_built() {
    let built = built_test_files();
    let code: String = built
        .iter()
        .map(|f| std::fs::read_to_string(package_dir().join(f)).unwrap())
        .flat_map(|t| t.lines().filter(|l| !l.trim_start().starts_with("//")).map(String::from).collect::<Vec<_>>())
        .collect::<Vec<_>>()
        .join("\n");
    let mut stray = Vec::new();
    for f in files_under(&package_dir().join("tests")).into_iter().filter(|f| !f.starts_with("tests/data")) {
        let named = f.file_name().is_some_and(|n| code.contains(n.to_str().unwrap()));
        let used = if f.extension().is_some_and(|e| e == "rs") { built.contains(&f) } else { named };
        if !used {
            stray.push(f.display().to_string());
        }
    }
    assert!(
        stray.is_empty(),
        "files under tests/ that no test builds or names (with `autotests = false`, a test file is a \
         `[[test]]` of Cargo.toml or a `#[path = \"...\"] mod` of tests/integration.rs): {stray:?}"
    );
}

/// The `#[test]` functions of a file: (name, body without its braces), on stripped text.
fn test_functions(code: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("#[test]") {
        rest = &rest[at + "#[test]".len()..];
        let Some(f) = rest.find("fn ") else { break };
        let name: String = rest[f + 3..].chars().take_while(|c| is_ident(*c)).collect();
        let open = rest[f..].find('{').unwrap() + f;
        let end = block_end(rest, open);
        out.push((name, rest[open + 1..end - 1].to_string()));
        rest = &rest[end..];
    }
    out
}

/// Whether a test's body can end having checked nothing: a bare `return;`, or a body that is one
/// `if` without `else` (`if !skip() { ... }`).
fn can_return_unchecked(body: &str) -> bool {
    let b = body.trim();
    let bare_return = b.split("return").skip(1).any(|after| after.trim_start().starts_with([';', '}']));
    let one_if = b.starts_with("if ") && b.find('{').is_some_and(|open| b[block_end(b, open)..].trim().is_empty());
    bare_return || one_if
}

/// No test returns early (on an environment variable, a missing tool): it would print "ok" having
/// run nothing. Use `#[ignore = "why"]`, which libtest reports as ignored.
#[test]
fn no_test_can_pass_without_running() {
    let mut found = Vec::new();
    for f in built_test_files() {
        let code = strip(&std::fs::read_to_string(package_dir().join(&f)).unwrap());
        for (name, body) in test_functions(&code) {
            if can_return_unchecked(&body) {
                found.push(format!("{}: {name}", f.display()));
            }
        }
    }
    assert!(found.is_empty(), "tests that can return before checking anything (use #[ignore]): {found:#?}");
}

#[test]
fn the_test_tree_reader_sees_modules_and_early_returns() {
    let root = Path::new("tests/integration.rs");
    let text = "#[path = \"plates.rs\"]\nmod plates;\nmod common;\npub mod young_laplace;\nmod inline {\n}";
    assert_eq!(
        declared_modules(root, text, true),
        [Path::new("tests/plates.rs"), Path::new("tests/common/mod.rs"), Path::new("tests/young_laplace.rs")]
    );
    let code =
        strip("#[test]\n#[ignore = \"slow\"]\nfn a() {\n    if skip() {\n        return;\n    }\n    run();\n}\n");
    let tests = test_functions(&code);
    assert_eq!(tests.len(), 1);
    assert_eq!(tests[0].0, "a");
    assert!(can_return_unchecked(&tests[0].1));
    assert!(can_return_unchecked("if !skip() { run(); }"));
    assert!(can_return_unchecked("let x = f(); if x.is_none() { return }"));
    assert!(!can_return_unchecked("if a { b(); } else { c(); }"));
    assert!(!can_return_unchecked("let r = (|| { return 1; })(); assert_eq!(r, 1);"));
    assert!(!can_return_unchecked("if a { b(); }\nassert!(c());"));
}
