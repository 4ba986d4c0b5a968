//! Recordings others can write: the hand-written example of `docs/authoring.md`, written from
//! the docs' own rules (XXH3-64 with seed 0, the low 32 bits as the sum), replays as
//! `unverified`, seals and then replays as `verified`; bad names are exit 2.

use crate::common;

use common::{assert_one_line_error, grove, root};

/// The lines of the first ```jsonl block of a document.
fn example_lines(doc: &str) -> Vec<String> {
    let text = std::fs::read_to_string(root().join(doc)).unwrap();
    let start = text.find("```jsonl\n").expect("a ```jsonl block") + "```jsonl\n".len();
    let end = start + text[start..].find("```").unwrap();
    text[start..end].lines().filter(|l| !l.trim().is_empty()).map(str::to_string).collect()
}

/// Appends the checksum as `docs/authoring.md` says: the low 32 bits of XXH3-64 (seed 0) of the
/// line without its sum, 8 lowercase hex digits, as a last field.
fn with_sum(body: &str) -> String {
    let sum = xxhash_rust::xxh3::xxh3_64_with_seed(body.as_bytes(), 0) & 0xffff_ffff;
    format!("{},\"sum\":\"{sum:08x}\"}}", &body[..body.len() - 1])
}

fn write_recording(path: &std::path::Path, lines: &[String]) {
    let text: String = lines.iter().map(|l| with_sum(l) + "\n").collect();
    std::fs::write(path, text).unwrap();
}

fn replay_json(path: &std::path::Path) -> (Option<i32>, serde_json::Value) {
    let out = grove(&["replay", "--json", path.to_str().unwrap()]);
    let v = serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("bad JSON ({e}); stderr: {}", String::from_utf8_lossy(&out.stderr)));
    (out.status.code(), v)
}

#[test]
fn the_documented_example_replays_unverified_then_seals_and_verifies() {
    let dir = tempfile::tempdir().unwrap();
    let lines = example_lines("docs/authoring.md");
    assert_eq!(lines.len(), 6, "a header and five events");
    let file = dir.path().join("one-tree.jsonl");
    write_recording(&file, &lines);

    let (code, v) = replay_json(&file);
    assert_eq!(code, Some(0), "an event-only file is valid input: {v}");
    assert_eq!(v["status"], "unverified");
    assert_eq!(v["verified"], false);
    assert_eq!(v["checkpoints_checked"], 0);
    // The press at tick 10 planted model 0 on target 0, 2 m below the controller.
    let task = &v["task"];
    assert_eq!(task["id"], "ray-casting-7");
    assert_eq!(task["completed"], false);
    let trees = task["trees"].as_array().unwrap();
    assert_eq!(trees.len(), 1, "{task}");
    assert_eq!(trees[0]["target"], 0);
    assert_eq!(trees[0]["model"], "broadleaf-mesh");
    let pos = trees[0]["position"].as_array().unwrap();
    assert!((pos[0].as_f64().unwrap() + 7.0).abs() < 0.01 && (pos[2].as_f64().unwrap() + 1.5).abs() < 0.01, "{pos:?}");
    // Planted at the press (tick 10) or the tick after, measured from start_task at tick 1.
    let t = trees[0]["time_s"].as_f64().unwrap();
    assert!(t == 9.0 / 60.0 || t == 10.0 / 60.0, "{t}");

    // Sealing writes checkpoints and a footer; the sealed file verifies.
    let sealed = dir.path().join("sealed.jsonl");
    let out = grove(&["replay", "--seal", file.to_str().unwrap(), "--out", sealed.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&sealed).unwrap();
    assert!(text.lines().last().unwrap().starts_with("{\"type\":\"footer\""));
    let (code, v2) = replay_json(&sealed);
    assert_eq!(code, Some(0));
    assert_eq!(v2["status"], "verified");
    assert_eq!(v2["verified"], true);
    assert_eq!(v2["task"]["trees"], v["task"]["trees"], "sealing changes no outcome");
    // Sealing never overwrites.
    let again = grove(&["replay", "--seal", file.to_str().unwrap(), "--out", sealed.to_str().unwrap()]);
    assert_one_line_error(&again, 2, "already exists");
    assert_eq!(std::fs::read_to_string(&sealed).unwrap(), text);
}

#[test]
fn unknown_tasks_and_models_are_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let lines = example_lines("docs/authoring.md");
    let bad_task: Vec<String> = lines
        .iter()
        .enumerate()
        .map(
            |(i, l)| {
                if i == 0 { l.replace("\"task\":\"ray-casting-7\"", "\"task\":\"no-such-task\"") } else { l.clone() }
            },
        )
        .collect();
    let f = dir.path().join("bad-task.jsonl");
    write_recording(&f, &bad_task);
    assert_one_line_error(&grove(&["replay", f.to_str().unwrap()]), 2, "unknown task 'no-such-task'");
    let bad_model: Vec<String> = lines.iter().map(|l| l.replace("\"model\":0", "\"model\":9")).collect();
    let f = dir.path().join("bad-model.jsonl");
    write_recording(&f, &bad_model);
    assert_one_line_error(&grove(&["replay", f.to_str().unwrap()]), 2, "unknown model 9");
    // Sealing a bad file is bad input too, and writes nothing.
    let out = dir.path().join("out.jsonl");
    assert_one_line_error(
        &grove(&["replay", "--seal", f.to_str().unwrap(), "--out", out.to_str().unwrap()]),
        2,
        "unknown model 9",
    );
    assert!(!out.exists());
}

#[test]
fn the_study_lists_an_event_only_file_as_unverified() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec");
    std::fs::create_dir(&rec).unwrap();
    write_recording(&rec.join("X01-ray-casting-7.jsonl"), &example_lines("docs/authoring.md"));
    let out = grove(&[
        "study",
        "--json",
        "--replays",
        rec.to_str().unwrap(),
        "--out",
        dir.path().join("o").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["trials"][0]["status"], "unverified");
    assert_eq!(v["summary"]["status"]["unverified"], 1);
    assert!(v["summary"]["status"].get("diverged").is_none());
    // Not synthetic, so no note.
    assert!(v["note"].is_null());
}

/// A recording that names a scene file beside it (as `grove serve` writes a headset's room)
/// seals from any working directory: the scene is read from the recording's folder, as
/// `grove replay` reads it.
#[test]
fn a_recording_naming_a_scene_beside_it_seals_from_another_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(root().join("assets/scenes/study.ron"), dir.path().join("room.ron")).unwrap();
    let mut lines = example_lines("docs/authoring.md");
    assert!(lines[0].contains("\"scene\":\"study\""), "{}", lines[0]);
    lines[0] = lines[0].replace("\"scene\":\"study\"", "\"scene\":\"room.ron\"");
    let file = dir.path().join("one-tree.jsonl");
    write_recording(&file, &lines);
    let sealed = dir.path().join("sealed.jsonl");
    // The working directory is the repository's root, which has no room.ron.
    assert!(!root().join("room.ron").exists());
    let out = grove(&["replay", "--seal", file.to_str().unwrap(), "--out", sealed.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let (code, v) = replay_json(&sealed);
    assert_eq!((code, v["status"].as_str()), (Some(0), Some("verified")), "{v}");
    assert_eq!(v["task"]["trees"].as_array().map(Vec::len), Some(1), "{v}");
}
