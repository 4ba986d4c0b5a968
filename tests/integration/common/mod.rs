//! Helpers shared by the integration tests.

#![allow(dead_code)]

pub mod bounded;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A folder under the system's temporary folder, removed with all it holds when dropped, so
/// that a test leaves nothing behind whether it passes or fails. It reads as a [`Path`].
pub struct Scratch(tempfile::TempDir);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<std::ffi::OsStr> for Scratch {
    fn as_ref(&self) -> &std::ffi::OsStr {
        self.0.path().as_os_str()
    }
}

/// A new empty [`Scratch`] folder whose name begins with `grove-TAG-`.
pub fn scratch(tag: &str) -> Scratch {
    Scratch(tempfile::Builder::new().prefix(&format!("grove-{tag}-")).tempdir().expect("a temporary folder"))
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

/// Runs the Khronos glTF validator (`tools/gltf-validate`, installed with `npm ci` when missing)
/// on every glTF file in `dir`; asserts that it ran, and returns its report.
pub fn validate_gltf_dir(dir: &Path) -> String {
    let tool = root().join("tools/gltf-validate");
    if !tool.join("node_modules").exists() {
        let ok = Command::new("npm")
            .args(["ci", "--silent", "--no-audit", "--no-fund"])
            .current_dir(&tool)
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
        assert!(ok, "npm ci in tools/gltf-validate failed; the validator is needed for this test");
    }
    let out = Command::new("node").arg(tool.join("validate.mjs")).arg(dir).output().expect("node runs");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "validator: {text}{}", String::from_utf8_lossy(&out.stderr));
    text
}

/// Chromium's headless run of a local file (Debian's `chromium`, no network: every host name
/// fails to resolve), with `args` such as `--dump-dom` or `--screenshot=…`: what it printed (the
/// DOM after the page's scripts ran, for `--dump-dom`) and what it logged.
pub fn chromium(args: &[&str], page: &Path) -> (String, String) {
    let url = format!("file://{}", page.canonicalize().unwrap().display());
    let profile = tempfile::tempdir().unwrap();
    let out = Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--virtual-time-budget=5000",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg("--host-resolver-rules=MAP * ~NOTFOUND")
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .args(args)
        .arg(&url)
        .output()
        .expect("chromium runs (scripts/test installs Debian's chromium)");
    assert!(out.status.success(), "chromium failed: {}", String::from_utf8_lossy(&out.stderr));
    (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}
