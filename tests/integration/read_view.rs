//! Outside grove-systems the simulation is read through `Sim`'s typed getters
//! (`systems/src/view.rs`), never through its world or resources: this test fails when a call of
//! the crate's private accessors (a dot, `world` or `res`, and `()`) appears in any Rust file of
//! `src/`, `techniques/`, `tests/`, `examples/`, `fuzz/`, `tools/`, `systems/tests/` or
//! `systems/examples/`, comments included (the compiler already refuses the call; this keeps the
//! words out of examples and comments that would teach it).

use std::path::{Path, PathBuf};

/// The folders outside the simulation's own sources.
const READERS: [&str; 8] =
    ["src", "techniques", "tests", "examples", "fuzz", "tools", "systems/tests", "systems/examples"];

/// The accessors, written so that this file does not contain them.
fn accessors() -> [String; 2] {
    [format!(".{}()", "world"), format!(".{}()", "res")]
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries {
        let p = entry.unwrap().path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n == "target" || n == "node_modules") {
                continue;
            }
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// Every line under `root`'s reader folders that calls an accessor, as `path:line: text`.
fn accessor_reads(root: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for dir in READERS {
        rust_files(&root.join(dir), &mut files);
    }
    files.sort();
    let needles = accessors();
    let mut found = Vec::new();
    for f in files {
        let rel = f.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        let text = std::fs::read_to_string(&f).unwrap();
        for (i, line) in text.lines().enumerate() {
            // A chain broken over lines puts the accessor at the start of one.
            let code: String = line.chars().filter(|c| !c.is_whitespace()).collect();
            if needles.iter().any(|n| code.contains(n.as_str())) {
                found.push(format!("{rel}:{}: {}", i + 1, line.trim()));
            }
        }
    }
    found
}

#[test]
fn readers_use_the_typed_view() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    assert!(root.join("systems/src/view.rs").is_file(), "the typed view is where this test says");
    let found = accessor_reads(root);
    assert!(
        found.is_empty(),
        "read the simulation through Sim's getters (systems/src/view.rs), not its world or resources:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_scan_sees_an_accessor() {
    // The scan itself must be able to fail: each accessor, on one line or at the start of a
    // continued chain, in a reader folder, is reported; the simulation's own sources are not
    // scanned.
    let dir = tempfile::tempdir().unwrap();
    for d in ["src/a", "tests/integration", "systems/src"] {
        std::fs::create_dir_all(dir.path().join(d)).unwrap();
    }
    let [world, res] = accessors();
    std::fs::write(dir.path().join("src/a/b.rs"), format!("fn f(sim: &Sim) {{ let t = sim{res}.tick; }}\n")).unwrap();
    std::fs::write(
        dir.path().join("tests/integration/c.rs"),
        format!("fn g(sim: &Sim) {{\n    sim\n        {world}\n        .len();\n}}\n"),
    )
    .unwrap();
    std::fs::write(dir.path().join("systems/src/view.rs"), format!("fn tick(&self) -> u64 {{ self{res}.tick }}\n"))
        .unwrap();
    let found = accessor_reads(dir.path());
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].starts_with("src/a/b.rs:1:") && found[1].starts_with("tests/integration/c.rs:3:"), "{found:?}");
}
