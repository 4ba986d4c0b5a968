//! The library's errors are its own types: a public function of the folders listed here returns
//! their module's error type (thiserror), never `anyhow::Result`, which stays in main.rs and
//! cli/. The check reads the sources: a `pub fn` whose signature names `anyhow::Result`.

use std::path::Path;

/// The folders of src/ whose public functions return typed errors.
const TYPED: &[&str] = &["bank", "lsystem", "models"];

/// The public functions in `text` whose signature (up to its body's `{`) names
/// `anyhow::Result`: their first lines.
fn anyhow_signatures(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let lines: Vec<&str> = text.lines().collect();
    for (i, line) in lines.iter().enumerate() {
        let code = line.trim_start();
        if !(code.starts_with("pub fn ") || code.starts_with("pub(crate) fn ")) {
            continue;
        }
        let mut signature = String::new();
        for l in &lines[i..] {
            signature.push_str(l.split('{').next().unwrap_or(""));
            if l.contains('{') || l.trim_end().ends_with(';') {
                break;
            }
        }
        if signature.contains("anyhow::Result") || signature.contains("anyhow::Error") {
            out.push(code.to_string());
        }
    }
    out
}

#[test]
fn the_checker_sees_an_anyhow_signature() {
    let text = "pub fn a() -> anyhow::Result<()> {\n}\npub fn b(\n    x: u32,\n) -> anyhow::Result<u32> {\n}\npub fn c() -> Result<(), E> {\n    let r: anyhow::Result<()> = Ok(());\n}\n";
    assert_eq!(anyhow_signatures(text), ["pub fn a() -> anyhow::Result<()> {", "pub fn b("]);
}

#[test]
fn the_typed_folders_return_their_own_errors() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    let mut files = 0;
    for folder in TYPED {
        let mut paths = Vec::new();
        crate::graph::rust_files(&src.join(folder), &mut paths);
        for p in paths {
            files += 1;
            for s in anyhow_signatures(&std::fs::read_to_string(&p).unwrap()) {
                found.push(format!("{}: {s}", p.display()));
            }
        }
    }
    assert!(files >= 20, "the folders were read ({files} files)");
    assert!(found.is_empty(), "public functions returning anyhow: {found:#?}");
}
