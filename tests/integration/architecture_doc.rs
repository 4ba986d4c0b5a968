//! ARCHITECTURE.md stays true to the code: every path it names in backticks exists in the
//! repository, and every type, function, constant or `Type::item` it names in backticks is
//! defined in the source (`struct|enum|trait|type|fn|const|static|mod|macro_rules! NAME` in a
//! `.rs` or `.wgsl` file).

use crate::common;

use std::collections::BTreeSet;
use std::path::Path;

use common::root;

/// External crates a name may start with; their items are not looked up.
const EXTERNAL: &[&str] = &["grove", "hecs", "glam", "wgpu", "parry3d", "serde", "rayon", "statrs", "plotters", "egui", "winit", "std", "clap", "postcard", "thiserror", "gltf", "naga", "naga_oil"];

/// Directories never walked: build output, version control, installed packages.
const SKIP_DIRS: &[&str] = &["target", ".git", "node_modules"];

/// The repository's files and folders, as paths relative to the root with `/` separators
/// (folders end with `/`), and the text of every `.rs` and `.wgsl` file.
struct Repo {
    paths: Vec<String>,
    source: Vec<(String, String)>,
}

fn walk(dir: &Path, rel: &str, repo: &mut Repo) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Ok(kind) = entry.file_type() else { continue };
        let path = format!("{rel}{name}");
        if kind.is_dir() {
            if SKIP_DIRS.contains(&name.as_str()) {
                continue;
            }
            repo.paths.push(format!("{path}/"));
            walk(&entry.path(), &format!("{path}/"), repo);
        } else if kind.is_file() {
            if name.ends_with(".rs") || name.ends_with(".wgsl") {
                let text = std::fs::read_to_string(entry.path()).unwrap_or_default();
                repo.source.push((path.clone(), text));
            }
            repo.paths.push(path);
        }
    }
}

fn repo() -> Repo {
    let mut repo = Repo { paths: Vec::new(), source: Vec::new() };
    walk(&root(), "", &mut repo);
    assert!(repo.source.len() > 50, "the walk found too few source files: {}", repo.source.len());
    repo
}

/// The backticked spans of `doc` outside fenced code blocks.
fn spans(doc: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut fenced = false;
    for line in doc.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        let parts: Vec<&str> = line.split('`').collect();
        // Odd-numbered parts lie between a pair of backticks.
        for (i, part) in parts.iter().enumerate() {
            if i % 2 == 1 && i + 1 < parts.len() {
                out.push(part.to_string());
            }
        }
    }
    out
}

const PATH_EXTENSIONS: &[&str] = &[".rs", ".wgsl", ".md", ".toml", ".py"];

/// Whether a span names a path: it has a `/` (or a source or doc extension) and no spaces.
fn is_path(span: &str) -> bool {
    !span.contains(char::is_whitespace)
        && !span.starts_with(['$', '~', '-'])
        && !(span.starts_with('.') && !span.contains('/'))
        && !span.contains("://")
        && (span.contains('/') || PATH_EXTENSIONS.iter().any(|e| span.ends_with(e)))
        && span.chars().all(|c| c.is_ascii_alphanumeric() || "/._-*".contains(c))
}

/// Whether `pattern` (with `*` matching within one path segment) matches the end of `path` at
/// a segment boundary.
fn matches_tail(pattern: &str, path: &str) -> bool {
    let pat: Vec<&str> = pattern.trim_end_matches('/').split('/').collect();
    let segs: Vec<&str> = path.trim_end_matches('/').split('/').collect();
    if pattern.ends_with('/') != path.ends_with('/') || segs.len() < pat.len() {
        return false;
    }
    segs[segs.len() - pat.len()..].iter().zip(&pat).all(|(s, p)| glob_segment(p, s))
}

fn glob_segment(pattern: &str, seg: &str) -> bool {
    match pattern.split_once('*') {
        None => pattern == seg,
        Some((head, tail)) => {
            seg.len() >= head.len() + tail.len() && seg.starts_with(head) && glob_segment_rest(tail, &seg[head.len()..])
        }
    }
}

fn glob_segment_rest(pattern: &str, rest: &str) -> bool {
    (0..=rest.len()).filter(|&i| rest.is_char_boundary(i)).any(|i| glob_segment(pattern, &rest[i..]))
}

fn path_exists(repo: &Repo, span: &str) -> bool {
    let span = span.trim_start_matches("./");
    // A path from the root must exist as written; a shorter one (`cli/`, `trees/lod.rs`) names
    // a file or folder of the part of the codemap it sits in, so it must end some real path.
    if ["systems/", "src/", "tests/", "docs/", "assets/", "scripts/"].iter().any(|r| span.starts_with(r)) {
        if !span.contains('*') {
            return repo.paths.iter().any(|p| p == span || p.strip_suffix('/') == Some(span));
        }
    }
    // A folder may be named without its trailing `/`.
    let as_folder = format!("{span}/");
    repo.paths.iter().any(|p| matches_tail(span, p) || (!span.ends_with('/') && matches_tail(&as_folder, p)))
}

/// The name a span names, if it is an item name: `Name`, `path::Name`, `name()`, `name(args)`,
/// `name!` or a single lower-case word (a module, a function or a field: `input`, `prepare`).
fn item_name(span: &str) -> Option<String> {
    let core = match span.find('(') {
        Some(i) if span.ends_with(')') => &span[..i],
        Some(_) => return None,
        None => span.trim_end_matches('!'),
    };
    let ident = |s: &str| {
        !s.is_empty() && s.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_') && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    };
    if !core.split("::").all(ident) {
        return None;
    }
    if core.starts_with('_') && !core.chars().any(|c| c.is_ascii_uppercase()) {
        return None; // a name's suffix such as `_deg`, not a name
    }
    Some(core.to_string())
}

fn defined(repo: &Repo, name: &str) -> bool {
    let keywords = ["struct", "enum", "trait", "type", "fn", "const", "static", "mod", "macro_rules!"];
    repo.source.iter().any(|(_, text)| {
        keywords.iter().any(|k| {
            text.match_indices(&format!("{k} {name}")).any(|(i, m)| {
                let before_ok = i == 0 || !text[..i].ends_with(|c: char| c.is_ascii_alphanumeric() || c == '_');
                let after = text[i + m.len()..].chars().next();
                before_ok && !after.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_')
            })
        })
    })
}

/// Whether `word` occurs as a whole word in `text`.
fn has_word(text: &str, word: &str) -> bool {
    text.match_indices(word).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        let edge = |c: Option<char>| !c.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_');
        edge(before) && edge(after)
    })
}

/// Whether the item `name` (`Name`, `module::Name`, `Type::item`) exists in the source.
fn item_exists(repo: &Repo, name: &str) -> bool {
    // The workspace's own crates: `grove_systems::files` is the module `files`.
    let name = name.strip_prefix("grove_systems::").or_else(|| name.strip_prefix("grove::")).unwrap_or(name);
    let segs: Vec<&str> = name.split("::").collect();
    if EXTERNAL.contains(&segs[0]) {
        return true;
    }
    let last = *segs.last().unwrap();
    if segs.len() == 1 {
        // A SCREAMING_CASE name may be a constant or a name the code spells in a string (an
        // environment variable, a glTF attribute): it must occur in the source as a word.
        if last.chars().all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_') {
            return repo.source.iter().any(|(_, t)| has_word(t, last) || t.contains(&format!("\"{last}")));
        }
        if last.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit()) {
            // A lower-case word: a module (a file or a folder), an item, a field or a crate.
            let module = repo.paths.iter().any(|p| p.ends_with(&format!("/{last}.rs")) || p.ends_with(&format!("/{last}/")));
            let field = repo.source.iter().any(|(_, t)| t.contains(&format!("pub {last}:")) || t.contains(&format!("pub(crate) {last}:")));
            return module || field || EXTERNAL.contains(&last) || defined(repo, last);
        }
        return defined(repo, last);
    }
    let owner = segs[segs.len() - 2];
    if owner.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
        // module::Item: the module is a file or folder, the item is defined.
        let module = repo.paths.iter().any(|p| p.ends_with(&format!("/{owner}.rs")) || p.ends_with(&format!("/{owner}/")));
        return module && defined(repo, last);
    }
    // Type::item: the type is defined, and a file that defines it names the item (a method,
    // a field, a variant or an associated constant).
    if !defined(repo, owner) {
        return false;
    }
    let owners = ["struct", "enum", "trait", "type"].map(|k| format!("{k} {owner}"));
    let impls = [format!("impl {owner}"), format!("for {owner}")];
    repo.source.iter().any(|(_, text)| {
        (owners.iter().chain(&impls).any(|o| has_word(text, o.split(' ').nth(1).unwrap()) && text.contains(o.as_str())))
            && has_word(text, last)
    })
}

/// Every path and item name in `doc` that does not exist in the repository.
fn missing(repo: &Repo, doc: &str) -> Vec<String> {
    let mut out = BTreeSet::new();
    for span in spans(doc) {
        if is_path(&span) {
            if !path_exists(repo, &span) {
                out.insert(format!("path `{span}`"));
            }
        } else if let Some(name) = item_name(&span) {
            if !item_exists(repo, &name) {
                out.insert(format!("name `{span}`"));
            }
        }
    }
    out.into_iter().collect()
}

#[test]
fn every_path_and_name_in_architecture_md_exists() {
    let repo = repo();
    let doc = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let checked = spans(&doc).iter().filter(|s| is_path(s) || item_name(s).is_some()).count();
    assert!(checked > 100, "only {checked} paths and names found in ARCHITECTURE.md");
    let gone = missing(&repo, &doc);
    assert!(gone.is_empty(), "ARCHITECTURE.md names what does not exist:\n{}", gone.join("\n"));
}

#[test]
fn made_up_paths_and_names_are_reported() {
    let repo = repo();
    let doc = "The `Sim` in `systems/src/sim.rs` with `Sim::step_with`, `frame::Feature`, `cli/`, `trees/lod.rs`, \
               `systems/*.rs`, `grove_systems::files`, `touchpad`, `prepare`, `world` and `config_fields!` exist; `systems/src/warp_drive.rs`, `warp/`, `FluxCapacitor`, \
               `Sim::teleport`, `ViewKind::Reflection`, `grove_systems::warp`, `frame::Hyperdrive`, `engage_warp()`, `warpfield` and `src/render/nope/*.wgsl` \
               do not.\n\n```\n`NotCheckedInsideAFence`\n```\n";
    assert_eq!(
        missing(&repo, doc),
        [
            "name `FluxCapacitor`",
            "name `Sim::teleport`",
            "name `ViewKind::Reflection`",
            "name `engage_warp()`",
            "name `frame::Hyperdrive`",
            "name `grove_systems::warp`",
            "name `warpfield`",
            "path `src/render/nope/*.wgsl`",
            "path `systems/src/warp_drive.rs`",
            "path `warp/`",
        ]
    );
}
