//! Helpers shared by the integration tests.

#![allow(dead_code)]

pub mod bounded;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Runs the built `grove` binary in the repository root.
pub fn grove(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_grove")).args(args).current_dir(root()).output().expect("the grove binary runs")
}

/// Runs `grove` with a path argument appended.
pub fn grove_with(args: &[&str], path: &Path) -> Output {
    let mut all: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    all.push(path.display().to_string());
    Command::new(env!("CARGO_BIN_EXE_grove")).args(&all).current_dir(root()).output().expect("the grove binary runs")
}

/// Asserts that a run failed with exit code `code`, printed exactly one non-empty line on
/// stderr that contains `needle`, and did not panic.
pub fn assert_one_line_error(out: &Output, code: i32, needle: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(code), "exit code; stderr: {stderr}");
    assert!(!stderr.contains("panicked"), "panicked: {stderr}");
    assert!(!stderr.contains("internal error"), "internal error: {stderr}");
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "expected one error line, got: {stderr}");
    assert!(lines[0].contains(needle), "error line {:?} should contain {:?}", lines[0], needle);
}
