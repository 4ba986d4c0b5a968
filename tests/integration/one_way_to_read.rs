//! Every input file is opened through `grove_systems::files` (regular files only, opened
//! without blocking, size-checked per kind, kept inside a folder): this test fails when a direct
//! `File::open`, `fs::read`, `fs::read_to_string`, `image::open` or `ImageReader::open` appears
//! in the non-test code of `src/` or `systems/src` outside that module.

use std::path::{Path, PathBuf};

/// Calls that open a file for reading without the checks.
const DIRECT: [&str; 6] =
    ["File::open(", "fs::read(", "fs::read_to_string(", "image::open(", "ImageReader::open(", "fs::File::open("];

/// The one module allowed to open input files.
const THE_MODULE: &str = "systems/src/files.rs";

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The lines of non-test code that open a file directly: everything before a file's first
/// `#[cfg(test)]` (test modules sit at the end of their file), in files that are not test
/// files themselves.
fn direct_reads(root: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for dir in ["src", "systems/src"] {
        rust_files(&root.join(dir), &mut files);
    }
    let mut found = Vec::new();
    for f in files {
        let rel = f.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
        let name = f.file_name().unwrap().to_string_lossy();
        if rel == THE_MODULE || name == "tests.rs" || name.ends_with("_tests.rs") {
            continue;
        }
        let text = std::fs::read_to_string(&f).unwrap();
        for (i, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("#[cfg(test)]") {
                break;
            }
            let code = line.split("//").next().unwrap_or("");
            if DIRECT.iter().any(|d| code.contains(d)) {
                found.push(format!("{rel}:{}: {}", i + 1, line.trim()));
            }
        }
    }
    found
}

#[test]
fn input_files_are_opened_only_through_grove_systems_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let found = direct_reads(root);
    assert!(
        found.is_empty(),
        "open input files with grove_systems::files (read, read_text, open), not directly:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_scan_sees_a_direct_read() {
    // The scan itself must be able to fail: a folder with one direct read is reported.
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(src.join("a")).unwrap();
    std::fs::create_dir_all(dir.path().join("systems/src")).unwrap();
    std::fs::write(src.join("a/b.rs"), "fn f() { let _ = std::fs::read_to_string(\"x\"); }\n#[cfg(test)]\nmod t { fn g() { std::fs::read(\"y\"); } }\n").unwrap();
    std::fs::write(dir.path().join("systems/src/files.rs"), "fn ok() { std::fs::File::open(\"z\"); }\n").unwrap();
    let found = direct_reads(dir.path());
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("src/a/b.rs:1:"), "{found:?}");
}
