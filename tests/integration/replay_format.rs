//! The replay format: writing, verifying, version fixtures and every kind of bad input.

use crate::common;

use std::io::Write;
use std::path::Path;

use common::{assert_one_line_error, grove_with, root};
use glam::{Quat, Vec3};
use grove_systems::catalogue::ModelId;
use grove_systems::components::Pose;
use grove_systems::input::{Button, InputEvent, StampedEvent};
use grove_systems::replay::{decode_line, encode_line, record_events, Header, Line};
use grove_systems::resources::Mode;
use grove_systems::scene::Scene;

/// A short deterministic session that uses every kind of input event.
fn session() -> (Header, Vec<StampedEvent>) {
    let scene = Scene::builtin("study").unwrap();
    let mut header = Header::new("study", 42, scene.dt);
    header.participant = Some("T01".into());
    header.synthetic = true;
    let mut events = Vec::new();
    let mut at = |tick: u64, event: InputEvent| events.push(StampedEvent { tick, event });
    at(0, InputEvent::StartTask { task: "ray-casting-7".into(), layout: None });
    for i in 0..200u64 {
        let a = i as f32 * 0.01;
        let pose = Pose { position: Vec3::new(0.25, 1.35, 5.7), rotation: Quat::from_rotation_y(a - 1.0) * Quat::from_rotation_x(-0.4) };
        at(i + 1, InputEvent::ControllerPose { pose });
        if i % 50 == 0 {
            at(i + 1, InputEvent::HeadPose { pose: Pose::looking_at(Vec3::new(a, 1.7, 6.0), Vec3::new(0.0, 0.5, -4.0)) });
        }
    }
    at(20, InputEvent::ButtonDown { button: Button::Trigger });
    at(26, InputEvent::ButtonUp { button: Button::Trigger });
    at(40, InputEvent::TouchpadAxes { axes: glam::Vec2::new(0.0, 0.8) });
    at(70, InputEvent::TouchpadAxes { axes: glam::Vec2::ZERO });
    at(90, InputEvent::OpenMenu);
    at(120, InputEvent::ChooseModel { model: ModelId(5).into() });
    at(150, InputEvent::SwitchMode { mode: Mode::Manual });
    at(160, InputEvent::ButtonDown { button: Button::Menu });
    at(162, InputEvent::ButtonUp { button: Button::Menu });
    at(170, InputEvent::CloseMenu);
    at(230, InputEvent::EndTask);
    events.sort_by_key(|e| e.tick);
    (header, events)
}

fn record(path: &Path) -> Vec<u8> {
    let (header, events) = session();
    let bytes = record_events(Vec::new(), &header, &events, 300, serde_json::json!({})).unwrap();
    std::fs::write(path, &bytes).unwrap();
    bytes
}

fn lines_of(bytes: &[u8]) -> Vec<String> {
    String::from_utf8(bytes.to_vec()).unwrap().lines().map(str::to_string).collect()
}

fn write_lines(path: &Path, lines: &[String]) {
    let mut f = std::fs::File::create(path).unwrap();
    for l in lines {
        writeln!(f, "{l}").unwrap();
    }
}

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("bad JSON ({e}): {}", String::from_utf8_lossy(&out.stdout)))
}

#[test]
fn a_recording_verifies_and_reports_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.jsonl");
    record(&path);
    let out = grove_with(&["replay", "--json"], &path);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let v = json(&out);
    assert_eq!(v["verified"], true);
    assert_eq!(v["complete"], true);
    assert_eq!(v["ticks"], 300);
    assert_eq!(v["format_version"], grove_systems::replay::FORMAT_VERSION);
    assert_eq!(v["checkpoints_checked"], 6); // 5 checkpoints (60..300) and the footer.
    assert!(v["first_divergence"].is_null());
    assert_eq!(v["events"]["controller_pose"], 200);
    assert_eq!(v["events"]["switch_mode"], 1);
    assert!((v["sim_seconds"].as_f64().unwrap() - 5.0).abs() < 1e-3);
    for key in ["file", "wall_seconds", "speedup", "final_hash", "task"] {
        assert!(v.get(key).is_some(), "missing {key}");
    }
    assert_eq!(v["task"]["id"], "ray-casting-7");
}

#[test]
fn until_stops_early_and_reports_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.jsonl");
    record(&path);
    let out = grove_with(&["replay", "--json", "--until", "130"], &path);
    let v = json(&out);
    assert_eq!(v["ticks"], 130);
    assert_eq!(v["complete"], false);
    assert_eq!(v["checkpoints_checked"], 2);
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn a_recording_cut_mid_write_replays_as_incomplete() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.jsonl");
    let bytes = record(&path);
    // Cut in the middle of a line two thirds through, as a killed writer would leave it.
    let cut = bytes.len() * 2 / 3;
    std::fs::write(&path, &bytes[..cut]).unwrap();
    let out = grove_with(&["replay", "--json"], &path);
    let v = json(&out);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(v["complete"], false);
    assert_eq!(v["verified"], true);
    assert!(v["ticks"].as_u64().unwrap() > 100 && v["ticks"].as_u64().unwrap() < 300);
}

#[test]
fn a_changed_pose_that_still_parses_diverges_at_the_next_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.jsonl");
    let mut lines = lines_of(&record(&path));
    // Change the last controller pose (tick 200) and give the line a valid checksum.
    let i = lines.iter().position(|l| l.contains("\"tick\":200,") && l.contains("controller_pose")).unwrap();
    let (body, _) = grove_systems::replay::split_sum(&lines[i]).unwrap();
    let Line::Event(mut ev) = decode_line(&grove_systems::replay::sign_body(&body, 0).0).unwrap() else { panic!("not an event") };
    if let InputEvent::ControllerPose { pose } = &mut ev.event {
        pose.position.x += 0.001;
    }
    lines[i] = encode_line(&Line::Event(ev));
    // Sign the chain again (version 2), so that only the pose is wrong.
    lines = grove_systems::replay::rechain(&lines).unwrap();
    write_lines(&path, &lines);
    let out = grove_with(&["replay", "--json"], &path);
    assert_eq!(out.status.code(), Some(1));
    let v = json(&out);
    assert_eq!(v["verified"], false);
    let d = &v["first_divergence"];
    assert_eq!(d["tick"], 240, "the next checkpoint after tick 200");
    assert_ne!(d["expected_hash"], d["actual_hash"]);
    let differing = d["differing"].as_array().unwrap();
    let controller: Vec<_> = differing.iter().filter(|x| x["component"] == "Controller").collect();
    assert_eq!(controller.len(), 1, "exactly the controller entity's Controller differs: {differing:?}");
    // Every pair names a component its entity has: no tree is blamed for the controller.
    assert!(differing.iter().all(|x| x["component"] != "Tree"), "{differing:?}");
    assert!(differing.iter().all(|x| x["entity"] != "?"), "{differing:?}");
}

/// Writes a mutated copy of the recording and checks the one-line error and exit code 2.
fn bad(name: &str, mutate: impl FnOnce(&mut Vec<String>), needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(format!("{name}.jsonl"));
    let mut lines = lines_of(&record(&path));
    mutate(&mut lines);
    write_lines(&path, &lines);
    let out = grove_with(&["replay"], &path);
    assert_one_line_error(&out, 2, needle);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains(&format!("{name}.jsonl")), "the error names the file: {stderr}");
}

#[test]
fn a_truncated_line_is_an_error_naming_the_line() {
    bad("truncated", |l| {
        let n = l[10].len() / 2;
        l[10].truncate(n);
    }, ":11:");
}

#[test]
fn a_flipped_byte_is_caught_even_inside_a_number() {
    bad(
        "flipped",
        |l| {
            let i = l.iter().position(|x| x.contains("\"tick\":50,") && x.contains("controller_pose")).unwrap();
            let pos = l[i].find("\"position\":[").unwrap() + 13;
            let mut bytes = l[i].clone().into_bytes();
            bytes[pos] = if bytes[pos] == b'3' { b'4' } else { b'3' };
            l[i] = String::from_utf8(bytes).unwrap();
        },
        "checksum mismatch",
    );
}

fn replace_event(lines: &mut [String], find: &str, f: impl FnOnce(&str) -> String) {
    let i = lines.iter().position(|x| x.contains(find)).unwrap();
    let body = lines[i][..lines[i].rfind(",\"sum\":\"").unwrap()].to_string() + "}";
    let new_body = f(&body);
    lines[i] = grove_systems::replay::sign_body(&new_body, 0).0;
    // Version 2 chains each checksum on the previous one: sign the whole chain again, as a
    // forger would, so that only the changed content is wrong.
    let chained = grove_systems::replay::rechain(lines).unwrap();
    lines.clone_from_slice(&chained);
}

#[test]
fn an_unknown_event_kind_is_an_error() {
    bad("unknown", |l| replace_event(l, "open_menu", |b| b.replace("open_menu", "open_portal")), "unknown variant");
}

#[test]
fn a_future_format_version_is_an_error() {
    bad("future", |l| replace_event(l, "\"header\"", |b| b.replace("\"format_version\":2", "\"format_version\":99")), "format version 99");
}

#[test]
fn nan_and_infinite_poses_are_errors() {
    bad("nan", |l| replace_event(l, "\"tick\":60,\"ms\"", |b| b.replacen("\"position\":[0.25", "\"position\":[NaN", 1)), "expected value");
    bad("huge", |l| replace_event(l, "\"tick\":60,\"ms\"", |b| b.replacen("\"position\":[0.25", "\"position\":[1e999", 1)), "out of range");
    // Finite as a JSON number, but infinite as an f32.
    bad("inf", |l| replace_event(l, "\"tick\":60,\"ms\"", |b| b.replacen("\"position\":[0.25", "\"position\":[1e39", 1)), "NaN or infinite");
}

#[test]
fn ticks_out_of_order_are_an_error() {
    // With the chain signed again, so that the order itself is what is caught.
    bad("order", |l| {
        l.swap(30, 32);
        let chained = grove_systems::replay::rechain(l).unwrap();
        *l = chained;
    }, "out of order");
    // Without, the chain breaks at the first moved line.
    bad("moved", |l| l.swap(30, 80), ":31: checksum mismatch");
}

#[test]
fn a_missing_header_is_an_error() {
    bad("noheader", |l| {
        l.remove(0);
    }, "missing header");
}

#[test]
fn an_empty_file_and_a_directory_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let empty = dir.path().join("empty.jsonl");
    std::fs::write(&empty, b"").unwrap();
    assert_one_line_error(&grove_with(&["replay"], &empty), 2, "empty file");
    assert_one_line_error(&grove_with(&["replay"], dir.path()), 2, "is a directory");
    assert_one_line_error(&grove_with(&["replay"], &dir.path().join("missing.jsonl")), 2, "no such file");
}

#[test]
fn a_gigabyte_of_garbage_is_rejected_without_reading_it_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("garbage.jsonl");
    let mut f = std::fs::File::create(&path).unwrap();
    // A megabyte of pseudo-random bytes without newlines, then a sparse tail up to 1 GiB.
    let mut x: u32 = 12345;
    let chunk: Vec<u8> = (0..(1 << 20))
        .map(|_| {
            x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
            let b = (x >> 16) as u8;
            if b == b'\n' { b'x' } else { b }
        })
        .collect();
    f.write_all(&chunk).unwrap();
    f.set_len(1 << 30).unwrap();
    drop(f);
    let out = grove_with(&["replay"], &path);
    assert_one_line_error(&out, 2, "garbage.jsonl:1");
}

#[test]
fn the_version_1_fixture_is_readable() {
    let path = root().join("tests/fixtures/replay-v1.jsonl");
    if std::env::var_os("UPDATE_FIXTURES").is_some() && !path.exists() {
        record(&path);
    }
    let (header, events) = grove_systems::replay::read_events(&path).unwrap();
    assert_eq!(header.format_version, 1);
    assert_eq!(header.participant.as_deref(), Some("T01"));
    assert_eq!(events, session().1, "the fixture holds the session's events");
    // It must also replay without an input error (exit 0 or 1, never 2): a later simulation
    // change may make its checkpoints diverge, but the file stays readable.
    let out = grove_with(&["replay", "--json"], &path);
    assert_ne!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn the_version_2_fixture_is_readable() {
    let path = root().join("tests/fixtures/replay-v2.jsonl");
    if std::env::var_os("UPDATE_FIXTURES").is_some() && !path.exists() {
        record(&path);
    }
    let (header, events) = grove_systems::replay::read_events(&path).unwrap();
    assert_eq!(header.format_version, 2);
    assert_eq!(header.participant.as_deref(), Some("T01"));
    assert_eq!(events, session().1, "the fixture holds the session's events");
    let out = grove_with(&["replay", "--json"], &path);
    assert_ne!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    // Its checksums are chained: every line after the second differs from its version-1 form.
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let v1_sum = |l: &str| {
        let (body, _) = grove_systems::replay::split_sum(l).unwrap();
        grove_systems::replay::line_sum(&body)
    };
    assert!(lines[2..].iter().all(|l| !l.ends_with(&format!("\"sum\":\"{}\"}}", v1_sum(l)))));
}

#[test]
fn unknown_fields_are_refused_on_events_without_fields() {
    for kind in ["open_menu", "close_menu", "end_task"] {
        bad(kind, |l| replace_event(l, &format!("\"kind\":\"{kind}\""), |b| b.replace(&format!("{{\"kind\":\"{kind}\"}}"), &format!("{{\"kind\":\"{kind}\",\"bogus\":1}}"))), "unknown field `bogus`");
    }
}

#[test]
fn the_recorder_flushes_every_press_at_once() {
    /// A writer that counts what reached it through `flush`.
    #[derive(Default)]
    struct Spy {
        buffered: Vec<u8>,
        flushed: Vec<u8>,
    }
    impl Write for Spy {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.buffered.extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            self.flushed.append(&mut self.buffered);
            Ok(())
        }
    }
    let (header, _) = session();
    let mut rec = grove_systems::replay::Recorder::new(Spy::default(), &header).unwrap();
    let pose = Pose { position: Vec3::new(0.0, 1.0, 0.0), rotation: Quat::IDENTITY };
    rec.event(3, 50, 3, &InputEvent::ControllerPose { pose }).unwrap();
    rec.event(3, 50, 3, &InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
    let f = rec.finish(&grove_systems::Sim::from_scene(&Scene::builtin("study").unwrap(), 42).unwrap(), serde_json::json!({})).unwrap();
    let text = String::from_utf8(f.flushed).unwrap();
    assert_eq!(text.lines().count(), 4, "header, pose, press and footer");
    // Now without the footer: the press must already be out, even though the pose before it
    // waited in the buffer.
    let mut rec = grove_systems::replay::Recorder::new(Spy::default(), &header).unwrap();
    rec.event(3, 50, 3, &InputEvent::ControllerPose { pose }).unwrap();
    assert_eq!(String::from_utf8_lossy(&spy_flushed(&rec)).lines().count(), 1, "a pose waits");
    rec.event(3, 50, 3, &InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
    let flushed = String::from_utf8(spy_flushed(&rec)).unwrap();
    assert!(flushed.lines().last().unwrap().contains("button_down"), "{flushed}");

    fn spy_flushed(rec: &grove_systems::replay::Recorder<Spy>) -> Vec<u8> {
        rec.get_ref().flushed.clone()
    }
}
