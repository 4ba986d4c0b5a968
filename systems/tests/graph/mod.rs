#![allow(dead_code)]

//! The import graph of a crate's sources and its cycles, shared by the import-graph tests of
//! grove-systems (`systems/tests/import_graph.rs`, one node per top-level module, and one per
//! folder) and of the app (`tests/integration/import_graph.rs`, one node per file, and one per
//! folder).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The top-level module a file belongs to: `sim.rs` → `sim`, `systems/wind.rs` → `systems`.
pub fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_string_lossy().into_owned();
    let name = first.strip_suffix(".rs").unwrap_or(&first).to_string();
    (name != "lib").then_some(name)
}

pub fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The modules named as `crate::NAME` in `text`, comments left out.
pub fn references(text: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            rest = &rest[i + "crate::".len()..];
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

/// The edges of the module graph of the crate under `src`.
pub fn graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in files {
        let Some(from) = module_of(src, &f) else { continue };
        let text = std::fs::read_to_string(&f).unwrap();
        let targets = edges.entry(from.clone()).or_default();
        for to in references(&text) {
            if to != from {
                targets.insert(to);
            }
        }
    }
    edges
}

/// A cycle of the graph, if it has one (depth-first search).
pub fn find_cycle(edges: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        n: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(n.to_string(), 1);
        stack.push(n.to_string());
        for m in edges.get(n).into_iter().flatten() {
            match state.get(m.as_str()).copied().unwrap_or(0) {
                1 => {
                    let start = stack.iter().position(|s| s == m).unwrap();
                    let mut cycle = stack[start..].to_vec();
                    cycle.push(m.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(m, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(n.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for n in edges.keys() {
        if state.get(n.as_str()).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(n, edges, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

/// A file's module path: `render/frame.rs` → `render::frame`, `render/mod.rs` → `render`, the
/// crate roots (`lib.rs`, `main.rs`) → the empty path.
pub fn module_path(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap_or(file).with_extension("");
    let mut parts: Vec<String> = rel.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|l| l == "mod") || (parts.len() == 1 && (parts[0] == "lib" || parts[0] == "main")) {
        parts.pop();
    }
    parts.join("::")
}

/// The paths after `prefix` (`crate::` or `super::`) in the code of `text`, comment lines left
/// out: `use crate::render::frame::Stage;` gives `render::frame::Stage`.
fn paths_after(text: &str, prefix: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
        let mut rest = line;
        while let Some(i) = rest.find(prefix) {
            let boundary = i == 0 || !rest[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_');
            rest = &rest[i + prefix.len()..];
            let path: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':').collect();
            if boundary && !path.is_empty() {
                out.push(path.trim_end_matches(':').to_string());
            }
        }
    }
    out
}

/// The graph with one node per file of the crate (or crates) under `src`: `crate::a::b::C` is
/// an edge to the longest prefix `a::b` that is a file's module, `super::x` the same from the
/// file's parent module. A file's use of itself or of the crate root is no edge.
pub fn file_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let texts: BTreeMap<String, String> =
        files.iter().map(|f| (module_path(src, f), std::fs::read_to_string(f).unwrap())).collect();
    let resolve = |from: &str, path: &str| -> Option<String> {
        let parts: Vec<&str> = path.split("::").collect();
        (1..=parts.len()).rev().map(|k| parts[..k].join("::")).find(|c| c != from && texts.contains_key(c))
    };
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, text) in &texts {
        let targets = edges.entry(module.clone()).or_default();
        let parent: Vec<&str> = module.split("::").filter(|p| !p.is_empty()).collect();
        let parent = parent[..parent.len().saturating_sub(1)].join("::");
        let up = paths_after(text, "super::")
            .into_iter()
            .map(|p| if parent.is_empty() { p } else { format!("{parent}::{p}") });
        for path in paths_after(text, "crate::").into_iter().chain(up) {
            targets.extend(resolve(module, &path));
        }
    }
    edges
}

/// The folder of a file's module: for `a/b/mod.rs` (`a::b`) the folder `a::b` itself, for
/// `a/b/c.rs` (`a::b::c`) its directory `a::b`, for the files at the top of the crate the empty
/// path.
pub fn folder_of(src: &Path, module: &str) -> String {
    let path = src.join(module.replace("::", "/"));
    if !module.is_empty() && path.is_dir() {
        return module.to_string();
    }
    module.rsplit_once("::").map_or(String::new(), |(dir, _)| dir.to_string())
}

/// Whether one folder holds the other (or they are the same): a folder and its own subfolders do
/// not count against each other, nor does the top of the crate against anything.
pub fn nested(a: &str, b: &str) -> bool {
    a.is_empty() || b.is_empty() || a == b || b.starts_with(&format!("{a}::")) || a.starts_with(&format!("{b}::"))
}

/// The graph with one node per folder of the crate under `src` (`render::canopy`), read from
/// [`file_graph`]: an edge from a folder to another when a file inside the one imports a file
/// inside the other, neither folder holding the other.
pub fn folder_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (from, targets) in file_graph(src) {
        let a = folder_of(src, &from);
        for to in targets {
            let b = folder_of(src, &to);
            if !nested(&a, &b) {
                edges.entry(a.clone()).or_default().insert(b);
            }
        }
    }
    edges
}

/// A made-up crate under a fresh folder in the temporary folder, with two folders `a` and `b`
/// whose files import each other's in a circle (`a::x` → `b::y`, `b::z` → `a::w`) while the
/// files have none: the folder check must find it where the file check does not. Returns the
/// folder; the caller removes it.
pub fn crate_with_folder_cycle(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("grove-folder-graph-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (file, text) in [
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        ("a/mod.rs", "pub mod w;\npub mod x;\n"),
        ("a/w.rs", "pub struct W;\n"),
        ("a/x.rs", "use crate::b::y::Y;\n"),
        ("b/mod.rs", "pub mod y;\npub mod z;\n"),
        ("b/y.rs", "pub struct Y;\n"),
        ("b/z.rs", "use crate::a::w::W;\n"),
    ] {
        let path = dir.join(file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}
