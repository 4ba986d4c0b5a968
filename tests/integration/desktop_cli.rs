//! `grove play` and `grove view` argument and file errors: one line on stderr, exit code 2,
//! before any window opens (so these run without a display).

use std::process::Command;

const GROVE: &str = env!("CARGO_BIN_EXE_grove");

fn run(args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(GROVE).args(args).env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY").output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn play_refuses_to_overwrite_a_recording() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("kept.jsonl");
    std::fs::write(&path, "precious").unwrap();
    let (code, err) = run(&["play", "--record", path.to_str().unwrap()]);
    assert_eq!(code, Some(2));
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("already exists"), "{err}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "precious");
}

#[test]
fn play_rejects_an_unknown_task() {
    let (code, err) = run(&["play", "--task", "juggling-3"]);
    assert_eq!(code, Some(2));
    assert!(err.starts_with("error: ") && err.contains("unknown task"), "{err}");
}

#[test]
fn view_of_an_unreadable_file_is_one_line_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.jsonl");
    let (code, err) = run(&["view", missing.to_str().unwrap()]);
    assert_eq!(code, Some(2));
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: ") && err.contains("missing.jsonl"), "{err}");

    let garbage = dir.path().join("garbage.jsonl");
    std::fs::write(&garbage, "{\"hello\": 1}\n").unwrap();
    let (code, err) = run(&["view", garbage.to_str().unwrap()]);
    assert_eq!(code, Some(2));
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(err.contains("garbage.jsonl:1"), "{err}");
}

#[test]
fn play_rejects_a_bad_quality_or_measure_before_opening_a_window() {
    for args in [
        ["play", "--quality", "0.1"],
        ["play", "--quality", "fast"],
        ["play", "--measure", "nan"],
        ["play", "--measure", "1"],
    ] {
        let (code, err) = run(&args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.starts_with("error: ") && err.contains(args[1]), "{args:?}: {err}");
    }
}
