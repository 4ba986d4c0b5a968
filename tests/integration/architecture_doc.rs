//! ARCHITECTURE.md and docs/codemap.md stay true to the code: every path they name in backticks
//! exists in the repository, and every type, function, constant or `Type::item` they name in
//! backticks is defined in the source (`struct|enum|trait|type|fn|const|static|mod|macro_rules!
//! NAME` in a `.rs` or `.wgsl` file). ARCHITECTURE.md stays short, and its codemap stays whole:
//! every folder of `src/` and `systems/src/` that holds Rust files, and every `grove` command
//! and subcommand that `grove --help` lists, has its row.

use crate::common;

use std::collections::BTreeSet;
use std::path::Path;

use common::root;

/// External crates a name may start with; their items are not looked up.
const EXTERNAL: &[&str] = &[
    "grove",
    "hecs",
    "glam",
    "wgpu",
    "parry3d",
    "serde",
    "rayon",
    "statrs",
    "plotters",
    "egui",
    "winit",
    "std",
    "clap",
    "postcard",
    "thiserror",
    "gltf",
    "naga",
    "naga_oil",
];

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
        !s.is_empty()
            && s.chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
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
            let module =
                repo.paths.iter().any(|p| p.ends_with(&format!("/{last}.rs")) || p.ends_with(&format!("/{last}/")));
            let field = repo
                .source
                .iter()
                .any(|(_, t)| t.contains(&format!("pub {last}:")) || t.contains(&format!("pub(crate) {last}:")));
            return module || field || EXTERNAL.contains(&last) || defined(repo, last);
        }
        return defined(repo, last);
    }
    let owner = segs[segs.len() - 2];
    if owner.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
        // module::Item: the module is a file or folder, the item is defined.
        let module =
            repo.paths.iter().any(|p| p.ends_with(&format!("/{owner}.rs")) || p.ends_with(&format!("/{owner}/")));
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

/// Checks that every path and name `file` holds exists, and that it holds at least `least`.
fn check_doc(repo: &Repo, file: &str, least: usize) {
    let doc = std::fs::read_to_string(root().join(file)).unwrap();
    let checked = spans(&doc).iter().filter(|s| is_path(s) || item_name(s).is_some()).count();
    assert!(checked >= least, "only {checked} paths and names found in {file}");
    let gone = missing(repo, &doc);
    assert!(gone.is_empty(), "{file} names what does not exist:\n{}", gone.join("\n"));
}

#[test]
fn every_path_and_name_in_architecture_md_exists() {
    check_doc(&repo(), "ARCHITECTURE.md", 100);
}

#[test]
fn every_path_and_name_in_the_detailed_codemap_exists() {
    check_doc(&repo(), "docs/codemap.md", 300);
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

// The codemap's coverage.

/// The most lines ARCHITECTURE.md may have: the detail lives in docs/codemap.md.
const MOST_LINES: usize = 150;

/// The codemap of `doc`: the lines from its `## Codemap` heading to the next `## ` heading.
fn codemap(doc: &str) -> String {
    let mut lines = doc.lines().skip_while(|l| l.trim() != "## Codemap");
    let heading = lines.next().unwrap_or_default();
    let body: Vec<&str> = lines.take_while(|l| !l.starts_with("## ")).collect();
    format!("{heading}\n{}", body.join("\n"))
}

/// The folders of the two crates' sources that hold `.rs` files, each as a path from the root
/// ending in `/` (`src/`, `src/render/trees/`, `systems/src/replay/`, …).
fn source_folders(repo: &Repo) -> BTreeSet<String> {
    repo.paths
        .iter()
        .filter(|p| (p.starts_with("src/") || p.starts_with("systems/src/")) && p.ends_with(".rs"))
        .map(|p| p[..=p.rfind('/').unwrap()].to_string())
        .collect()
}

/// The backticked spans of the table rows of `codemap` (lines that begin with `|`), each with
/// the root of the `###` section it sits in: that heading's first backticked folder (`src/`,
/// `systems/src/`), or the repository root under any other heading.
fn row_spans(codemap: &str) -> Vec<(String, String)> {
    let mut root = String::new();
    let mut out = Vec::new();
    for line in codemap.lines() {
        if let Some(heading) = line.strip_prefix("### ") {
            root = spans(heading).into_iter().find(|s| s.ends_with('/')).unwrap_or_default();
        } else if line.trim_start().starts_with('|') {
            out.extend(spans(line).into_iter().map(|s| (root.clone(), s)));
        }
    }
    out
}

/// The folders the rows of `codemap` name: each backticked path ending in `/`, from the root
/// when it starts with `src/` or `systems/`, else from its section's root (`cli/` under
/// `src/` is `src/cli/`).
fn codemap_folders(codemap: &str) -> BTreeSet<String> {
    row_spans(codemap)
        .into_iter()
        .filter(|(_, s)| s.ends_with('/') && !s.contains(char::is_whitespace))
        .map(|(root, s)| if s.starts_with("src/") || s.starts_with("systems/") { s } else { format!("{root}{s}") })
        .collect()
}

/// The commands the rows of `codemap` name, without `grove` (`aerial tile`): a backticked span
/// `grove A B …` names each word up to the first that is not a command's name (an option, a
/// FILE); a word may give alternatives, `derive|model` (written `derive\|model` in a table).
/// A command names its parents too: `grove aerial tile` names `aerial`.
fn codemap_commands(codemap: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (_, span) in row_spans(codemap) {
        let Some(rest) = span.strip_prefix("grove ") else { continue };
        let mut paths = vec![String::new()];
        for word in rest.replace("\\|", "|").split_whitespace() {
            let names: Vec<&str> = word.split('|').collect();
            let is_name = |n: &&str| {
                !n.is_empty()
                    && n.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
                    && !n.starts_with('-')
            };
            if !names.iter().all(is_name) {
                break;
            }
            paths = paths
                .iter()
                .flat_map(|p| names.iter().map(move |n| if p.is_empty() { n.to_string() } else { format!("{p} {n}") }))
                .collect();
            out.extend(paths.iter().cloned());
        }
    }
    out
}

/// The subcommands of `text`, a clap `--help` page: the names in its `Commands:` list, without
/// clap's own `help`.
fn help_commands(text: &str) -> Vec<String> {
    text.lines()
        .skip_while(|l| l.trim() != "Commands:")
        .skip(1)
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect()
}

/// Every command of the `grove` binary, top level and nested, as its `--help` pages list them
/// (`sim`, `aerial`, `aerial tile`, …).
fn grove_commands() -> Vec<String> {
    let mut out = Vec::new();
    let mut todo = vec![String::new()];
    while let Some(parent) = todo.pop() {
        let mut args: Vec<&str> = parent.split_whitespace().collect();
        args.push("--help");
        let help = common::grove(&args);
        assert!(help.status.success(), "grove {} failed: {}", args.join(" "), String::from_utf8_lossy(&help.stderr));
        for name in help_commands(&String::from_utf8_lossy(&help.stdout)) {
            let path = if parent.is_empty() { name } else { format!("{parent} {name}") };
            todo.push(path.clone());
            out.push(path);
        }
    }
    out.sort();
    out
}

/// What `codemap` leaves out of `folders` and `commands`, one line each.
fn left_out(codemap: &str, folders: &BTreeSet<String>, commands: &[String]) -> Vec<String> {
    let named_folders = codemap_folders(codemap);
    let named_commands = codemap_commands(codemap);
    let folders = folders.iter().filter(|f| !named_folders.contains(*f)).map(|f| format!("folder `{f}`"));
    let commands = commands.iter().filter(|c| !named_commands.contains(*c)).map(|c| format!("command `grove {c}`"));
    folders.chain(commands).collect()
}

#[test]
fn architecture_md_is_short() {
    let doc = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let lines = doc.lines().count();
    assert!(
        lines <= MOST_LINES,
        "ARCHITECTURE.md has {lines} lines, more than {MOST_LINES}: move detail to docs/codemap.md"
    );
}

#[test]
fn every_source_folder_and_grove_command_has_a_codemap_row() {
    let repo = repo();
    let folders = source_folders(&repo);
    assert!(
        folders.len() > 30 && folders.contains("src/render/trees/impostor/") && folders.contains("systems/src/"),
        "the walk found {folders:?}"
    );
    let commands = grove_commands();
    assert!(
        commands.len() > 30 && commands.contains(&"aerial tile".to_string()) && commands.contains(&"sim".to_string()),
        "grove --help listed {commands:?}"
    );
    let doc = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let gone = left_out(&codemap(&doc), &folders, &commands);
    assert!(gone.is_empty(), "ARCHITECTURE.md's codemap has no row for:\n{}", gone.join("\n"));
}

#[test]
fn a_folder_or_command_without_a_row_is_reported() {
    let doc = "# A\n\n## Codemap\n\n### `systems/src/` — the simulation\n\n| folder | what |\n|---|---|\n\
               | `systems/src/` | the root |\n| `replay/` | recordings; `grove replay` |\n\n\
               ### `src/` — the app\n\n| folder | what |\n|---|---|\n| `render/`, `render/trees/` | drawing |\n\
               | `cli/aerial/` | `grove aerial tile\\|flight --out DIR`, `grove lsystem derive` |\n\n\
               Outside a row `render/water/` and `grove sun` do not count.\n\n\
               ### Other folders\n\n| `src/study/` | from the root |\n\n## Invariants\n\n| `src/video/` | `grove video` |\n";
    let folders: BTreeSet<String> = [
        "systems/src/",
        "systems/src/replay/",
        "systems/src/scenario/",
        "src/render/",
        "src/render/trees/",
        "src/render/water/",
        "src/cli/aerial/",
        "src/study/",
        "src/video/",
    ]
    .map(String::from)
    .into();
    let commands: Vec<String> = [
        "replay",
        "aerial",
        "aerial tile",
        "aerial flight",
        "aerial eval",
        "lsystem",
        "lsystem derive",
        "sun",
        "video",
    ]
    .map(String::from)
    .into();
    assert_eq!(
        left_out(&codemap(doc), &folders, &commands),
        [
            "folder `src/render/water/`",
            "folder `src/video/`",
            "folder `systems/src/scenario/`",
            "command `grove aerial eval`",
            "command `grove sun`",
            "command `grove video`",
        ]
    );
    assert_eq!(
        help_commands(
            "Usage: grove <COMMAND>\n\nCommands:\n  sim    Run\n  scene  Work\n  help   Print\n\nOptions:\n  -h\n"
        ),
        ["sim", "scene"]
    );
}
