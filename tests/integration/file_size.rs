//! No source file over 600 lines (ARCHITECTURE.md's invariants): Rust, WGSL and the web side's
//! JavaScript modules, installed packages and build output aside.

use crate::common;

use std::path::Path;

use common::root;

const LIMIT: usize = 600;
const SKIP_DIRS: &[&str] = &["target", ".git", "node_modules", "dist", "fuzz"];
const EXTENSIONS: &[&str] = &["rs", "wgsl", "mjs", "js", "py"];

/// The source files under `dir` (relative to the root) with more than `limit` lines.
fn over(dir: &Path, rel: &str, limit: usize, out: &mut Vec<(String, usize)>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Ok(kind) = entry.file_type() else { continue };
        let path = format!("{rel}{name}");
        if kind.is_dir() && !SKIP_DIRS.contains(&name.as_str()) {
            over(&entry.path(), &format!("{path}/"), limit, out);
        } else if kind.is_file() && EXTENSIONS.iter().any(|e| name.ends_with(&format!(".{e}"))) {
            let lines = std::fs::read_to_string(entry.path()).map(|t| t.lines().count()).unwrap_or(0);
            if lines > limit {
                out.push((path, lines));
            }
        }
    }
}

#[test]
fn no_source_file_is_over_600_lines() {
    let mut long = Vec::new();
    for dir in ["src", "systems", "techniques", "web", "tests", "scripts", "tools"] {
        over(&root().join(dir), &format!("{dir}/"), LIMIT, &mut long);
    }
    assert!(long.is_empty(), "source files over {LIMIT} lines: {long:?}");
}

/// The walk finds long files: with a limit of 300 lines some of today's files are over it.
#[test]
fn the_walk_finds_a_long_file() {
    let mut long = Vec::new();
    over(&root().join("src"), "src/", 300, &mut long);
    assert!(long.iter().any(|(p, n)| p.ends_with(".rs") && *n > 300), "{long:?}");
}
