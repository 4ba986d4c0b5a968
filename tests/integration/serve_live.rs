//! Every session verified as it streams (docs/serve.md, "Verified as it streams"): a checkpoint
//! whose hash a client got wrong is shown as a divergence on the dashboard's feed while the
//! session is still open, with the model the participant chose and the trees so far; the
//! listing of `/api/sessions` has the same live verification; the session's end answers with
//! it, as `grove replay` finds it in the file.

use std::time::{Duration, Instant};

use grove_systems::catalogue::{Catalogue, ModelId};
use grove_systems::replay::rechain;

use crate::common::{grove, scratch};
use crate::serve_fixture::{append, open, request, study_lines, Server};

const RECORDING: &str = "P01-ray-casting-7.jsonl";

/// The recording with the hash of its checkpoint at `tick` changed (the chain signed again, as a
/// client whose world diverged would send it).
fn with_wrong_checkpoint(tick: u64) -> Vec<String> {
    let mut lines = study_lines(RECORDING);
    let prefix = format!("{{\"type\":\"checkpoint\",\"tick\":{tick},\"hash\":\"");
    let at = lines.iter().position(|l| l.starts_with(&prefix)).expect("a checkpoint at the tick");
    let hash = lines[at][prefix.len()..prefix.len() + 16].to_string();
    let wrong = if hash == "0123456789abcdef" { "fedcba9876543210" } else { "0123456789abcdef" };
    lines[at] = lines[at].replacen(&format!("\"hash\":\"{hash}\""), &format!("\"hash\":\"{wrong}\""), 1);
    rechain(&lines).unwrap()
}

/// The session `file` on the dashboard's feed.
fn on_dashboard(server: &Server, file: &str) -> serde_json::Value {
    let d = request(&server.addr, "GET", "/api/dashboard", &[], b"");
    assert_eq!(d.status, 200, "{}", d.body);
    d.json["sessions"].as_array().unwrap().iter().find(|s| s["file"] == file).cloned().expect("the session is listed")
}

/// Waits until `ok` holds for the session on the dashboard; returns it.
fn wait_for(server: &Server, file: &str, what: &str, ok: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
    let start = Instant::now();
    loop {
        let s = on_dashboard(server, file);
        if ok(&s) {
            return s;
        }
        assert!(start.elapsed() < Duration::from_secs(60), "{what}: {s}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The name of the model the last `choose_model` event among `lines` chose.
fn last_chosen(lines: &[String]) -> String {
    let index = lines.iter().rev().find_map(|l| {
        let v: serde_json::Value = serde_json::from_str(l).ok()?;
        (v["event"]["kind"] == "choose_model").then(|| v["event"]["model"].as_u64()).flatten()
    });
    let index = index.expect("the recording chooses a model") as u8;
    Catalogue::builtin().get(ModelId(index)).unwrap().name.clone()
}

#[test]
fn a_divergence_injected_mid_stream_is_on_the_dashboard_before_the_session_ends() {
    let dir = scratch("serve-live");
    let server = Server::start(&dir, 0, &["--protocol", "assets/protocols/tree-planting.ron"]);
    let lines = with_wrong_checkpoint(660);
    let wrong = lines.iter().position(|l| l.starts_with("{\"type\":\"checkpoint\",\"tick\":660,")).unwrap();
    let (id, file) = open(&server.addr, "w", &lines[0], None);

    // Up to the line before the wrong checkpoint: verified to the checkpoint before it, open.
    let r = append(&server.addr, "w", &id, 2, &lines[1..wrong]);
    assert_eq!(r.json["acked"].as_u64(), Some(wrong as u64), "{}", r.body);
    let s = wait_for(&server, &file, "verified to tick 600", |s| s["live"]["verification"]["verified_to_tick"] == 600);
    assert_eq!(s["state"], "open");
    assert_eq!(s["live"]["verification"]["status"], "incomplete", "{s}");
    assert_eq!(s["live"]["lines"].as_u64(), Some(wrong as u64));
    // The model the participant chose last, and the task so far as `grove replay --until` finds
    // it at the last line's tick (the world there, before that tick's events).
    assert_eq!(s["live"]["model"], last_chosen(&lines[..wrong]).as_str());
    let tick: u64 = serde_json::from_str::<serde_json::Value>(&lines[wrong - 1]).unwrap()["tick"].as_u64().unwrap();
    assert_eq!(s["live"]["tick"].as_u64(), Some(tick));
    let original = crate::common::root().join("replays/study").join(RECORDING);
    let sofar = grove(&["replay", &original.display().to_string(), "--until", &tick.to_string(), "--json"]);
    let sofar: serde_json::Value = serde_json::from_slice(&sofar.stdout).unwrap();
    let met = sofar["task"]["trees"].as_array().unwrap().len() as u64;
    assert!(met > 0, "the cut is after the first tree");
    assert_eq!(s["live"]["targets_satisfied"].as_u64(), Some(met), "{s}");
    assert_eq!(s["live"]["errors"], sofar["task"]["errors"]);
    assert!((s["live"]["task_clock_s"].as_f64().unwrap() - sofar["task"]["time_s"].as_f64().unwrap()).abs() < 1e-9);

    // The wrong checkpoint and a few lines after it: diverged at its tick, the session still open.
    let r = append(&server.addr, "w", &id, wrong as u64 + 1, &lines[wrong..wrong + 5]);
    assert_eq!(r.status, 200, "{}", r.body);
    let s = wait_for(&server, &file, "diverged", |s| s["live"]["verification"]["status"] == "diverged");
    assert_eq!(s["state"], "open", "shown before the session ended");
    let d = &s["live"]["verification"]["first_divergence"];
    assert_eq!(d["tick"], 660);
    assert_eq!(d["expected_hash"], "0123456789abcdef");
    let listed = request(&server.addr, "GET", "/api/sessions", &[], b"");
    let entry = listed.json["sessions"].as_array().unwrap().iter().find(|e| e["file"] == file.as_str()).unwrap().clone();
    assert_eq!(entry["live"]["status"], "diverged", "the listing has it too: {entry}");
    assert!(entry.get("id").is_none(), "the listing never has an id");

    // The rest, and the end: the verification is the divergence `grove replay` finds in the file.
    let r = append(&server.addr, "w", &id, wrong as u64 + 6, &lines[wrong + 5..]);
    assert_eq!(r.json["acked"].as_u64(), Some(lines.len() as u64), "{}", r.body);
    let end = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "w")], b"");
    assert_eq!(end.status, 200, "{}", end.body);
    let replay = grove(&["replay", &dir.join(&file).display().to_string(), "--json"]);
    assert_eq!(replay.status.code(), Some(1), "grove replay finds it diverged");
    let report: serde_json::Value = serde_json::from_slice(&replay.stdout).unwrap();
    let v = &end.json["verification"];
    assert_eq!(v["status"], "diverged", "{v}");
    assert_eq!(v["first_divergence"]["tick"], report["first_divergence"]["tick"], "{report}");
    assert_eq!(v["first_divergence"]["actual_hash"], report["first_divergence"]["actual_hash"]);
    let s = wait_for(&server, &file, "ended", |s| s["state"] == "ended");
    assert_eq!(s["verification"]["status"], "diverged");
    assert_eq!(s["live"]["verification"]["status"], "diverged", "the view kept after the end");
}

#[test]
fn a_session_that_verifies_is_verified_as_it_streams_and_at_its_end() {
    let dir = scratch("serve-live-ok");
    let server = Server::start(&dir, 0, &[]);
    let lines = study_lines(RECORDING);
    let (id, file) = open(&server.addr, "w", &lines[0], None);
    let half = lines.len() / 2;
    let r = append(&server.addr, "w", &id, 2, &lines[1..half]);
    assert_eq!(r.status, 200, "{}", r.body);
    // The last checkpoint among the lines sent, as the file has it.
    let last_checkpoint = lines[1..half].iter().rev().find_map(|l| l.strip_prefix("{\"type\":\"checkpoint\",\"tick\":").and_then(|r| r.split(',').next()?.parse::<u64>().ok())).unwrap();
    let start = Instant::now();
    let live = loop {
        let listed = request(&server.addr, "GET", "/api/sessions", &[], b"");
        let entry = listed.json["sessions"].as_array().unwrap().iter().find(|e| e["file"] == file.as_str()).unwrap().clone();
        if entry["live"]["verified_to_tick"] == last_checkpoint {
            break entry["live"].clone();
        }
        assert!(start.elapsed() < Duration::from_secs(60), "{entry}");
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(live["status"], "incomplete", "no footer yet: verified to its last checkpoint; {live}");
    assert_eq!(live["checkpoints_checked"].as_u64(), Some(last_checkpoint / 60));
    let r = append(&server.addr, "w", &id, half as u64 + 1, &lines[half..]);
    assert_eq!(r.json["acked"].as_u64(), Some(lines.len() as u64), "{}", r.body);
    let end = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "w")], b"");
    assert_eq!(end.json["verification"]["status"], "verified", "{}", end.body);
    let report: serde_json::Value = serde_json::from_slice(&grove(&["replay", &dir.join(&file).display().to_string(), "--json"]).stdout).unwrap();
    assert_eq!(end.json["verification"]["checkpoints_checked"], report["checkpoints_checked"], "{report}");
    assert_eq!(end.json["verification"]["last_tick"], report["ticks"]);
}

#[test]
fn with_live_off_a_session_is_verified_at_its_end_only() {
    let dir = scratch("serve-live-off");
    let server = Server::start(&dir, 0, &["--live", "off"]);
    let lines = with_wrong_checkpoint(1200);
    let (id, file) = open(&server.addr, "w", &lines[0], None);
    let r = append(&server.addr, "w", &id, 2, &lines[1..]);
    assert_eq!(r.json["acked"].as_u64(), Some(lines.len() as u64), "{}", r.body);
    let listed = request(&server.addr, "GET", "/api/sessions", &[], b"");
    let entry = listed.json["sessions"].as_array().unwrap().iter().find(|e| e["file"] == file.as_str()).unwrap().clone();
    assert!(entry["live"].is_null(), "nothing watched: {entry}");
    let end = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "w")], b"");
    assert_eq!(end.status, 200, "{}", end.body);
    let report: serde_json::Value = serde_json::from_slice(&grove(&["replay", &dir.join(&file).display().to_string(), "--json"]).stdout).unwrap();
    assert_eq!(end.json["verification"]["status"], "diverged", "its file re-simulated at the end: {}", end.body);
    assert_eq!(end.json["verification"]["first_divergence"]["tick"], report["first_divergence"]["tick"], "{report}");
}
