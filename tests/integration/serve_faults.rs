//! `grove serve` under faults: the client killed mid-session, the server killed (SIGKILL) and
//! restarted, the network gone for 10 s. The pushes run at a multiple of real time so that each
//! fault falls in the middle of a session.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::{grove, scratch};
use crate::serve_fixture::{push, spawn_push, study_lines, wait_lines, Proxy, Server};

fn sessions_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("sessions.json")).unwrap()).unwrap()
}

#[test]
fn a_client_killed_mid_session_leaves_every_acknowledged_line_verified_to_its_last_checkpoint() {
    let dir = scratch("serve-client-killed");
    // The recording's longest pause between events is 11 s: 0.55 s at 20 times real time.
    let server = Server::start(&dir, 0, &["--abandon-after", "3"]);
    let name = "P10-manual-7.jsonl";
    let original = study_lines(name);
    let mut client = spawn_push(&Path::new("replays/study").join(name), &server.url, &["--rate", "20"]);
    let file = "P10-manual-7-1.jsonl";
    // 20 times real time: the session's 85 s take about 4 s; kill it a quarter in.
    wait_lines(&dir.join(file), original.len() / 4, Duration::from_secs(30));
    client.kill().unwrap();
    client.wait().unwrap();
    assert!(server.wait_log(&format!("abandoned {file}"), Duration::from_secs(20)), "{}", server.log());
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let kept: Vec<&str> = text.lines().collect();
    assert!(text.ends_with('\n'), "whole lines only");
    assert!(kept.len() > 10 && kept.len() < original.len(), "{} of {} lines", kept.len(), original.len());
    assert_eq!(kept, original[..kept.len()].iter().map(String::as_str).collect::<Vec<_>>(), "a prefix of the recording");
    let last_checkpoint = kept.iter().rev().find(|l| l.contains("\"type\":\"checkpoint\"")).map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap()["tick"].as_u64().unwrap()).unwrap();
    let listed = sessions_json(&dir);
    let v = &listed["sessions"][0]["verification"];
    assert_eq!((listed["sessions"][0]["state"].as_str(), v["status"].as_str()), (Some("abandoned"), Some("incomplete")), "{listed}");
    assert_eq!(v["verified_to_tick"].as_u64(), Some(last_checkpoint));
    let out = grove(&["replay", &dir.join(file).display().to_string(), "--json"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!((r["complete"].as_bool(), r["verified"].as_bool()), (Some(false), Some(true)), "{r}");
    assert_eq!(r["status"], v["status"], "grove replay --json classifies the file as the server does: {r}");
}

#[test]
fn the_abandon_clock_goes_on_across_a_restart() {
    let dir = scratch("serve-abandon-clock");
    let mut server = Server::start(&dir, 0, &["--abandon-after", "600"]);
    let lines = study_lines("P03-ray-casting-7.jsonl");
    let (id, file) = crate::serve_fixture::open(&server.addr, "w", &lines[0], None);
    assert_eq!(crate::serve_fixture::append(&server.addr, "w", &id, 2, &lines[1..40]).json["acked"], 40);
    server.signal(libc::SIGKILL);
    // The session's last request was an hour ago: its file was last written then.
    let touched = std::process::Command::new("touch").args(["-m", "-d", "1 hour ago"]).arg(dir.join(&file)).status().unwrap();
    assert!(touched.success());
    let server = Server::start(&dir, 0, &["--abandon-after", "600"]);
    assert!(server.log().contains(&format!("continuing {file} (40 lines)")), "{}", server.log());
    // Ten minutes without a request were up before the restart: it is abandoned at the first look
    // (every 5 s), not ten minutes after the restart.
    assert!(server.wait_log(&format!("abandoned {file}"), Duration::from_secs(30)), "{}", server.log());
    let listed = sessions_json(&dir);
    assert_eq!(listed["sessions"][0]["state"], "abandoned", "{listed}");
}

#[test]
fn a_server_killed_mid_session_and_restarted_continues_the_file_where_the_client_left_it() {
    let dir = scratch("serve-server-killed");
    let mut server = Server::start(&dir, 0, &[]);
    let port = server.port();
    let name = "P11-ray-casting-7.jsonl";
    let path = Path::new("replays/study").join(name);
    let client = spawn_push(&path, &server.url, &["--rate", "10", "--timeout", "1", "--give-up", "60", "--json"]);
    let file = dir.join("P11-ray-casting-7-1.jsonl");
    wait_lines(&file, study_lines(name).len() / 4, Duration::from_secs(30));
    server.signal(libc::SIGKILL);
    let at_kill = std::fs::read_to_string(&file).unwrap();
    assert!(at_kill.lines().count() > 10 && at_kill.lines().count() < study_lines(name).len(), "killed mid-session: {} lines", at_kill.lines().count());
    std::thread::sleep(Duration::from_millis(800));
    let server = Server::start(&dir, port, &[]);
    assert!(server.log().contains("continuing P11-ray-casting-7-1.jsonl"), "{}", server.log());
    let out = client.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["reconnects"].as_u64().unwrap() >= 1, "{report}");
    assert_eq!(report["ended"]["verification"]["status"], "verified", "{report}");
    assert!(std::fs::read(&file).unwrap() == std::fs::read(&path).unwrap(), "the same file, nothing lost or twice");
}

#[test]
fn a_network_gone_for_ten_seconds_loses_nothing_and_duplicates_nothing() {
    let dir = scratch("serve-network");
    let server = Server::start(&dir, 0, &["--read-timeout", "2"]);
    let proxy = Proxy::start(&server.addr);
    let name = "P12-manual-7.jsonl";
    let path = Path::new("replays/study").join(name);
    // At 5 times real time the session takes about 18 s; the network goes an eighth in, for 10 s.
    let start = Instant::now();
    let client = spawn_push(&path, &format!("http://{}/", proxy.addr), &["--rate", "5", "--timeout", "1", "--give-up", "60", "--json"]);
    let file = dir.join("P12-manual-7-1.jsonl");
    wait_lines(&file, study_lines(name).len() / 8, Duration::from_secs(30));
    proxy.drop_network();
    // What was forwarded before the drop may still be being written.
    std::thread::sleep(Duration::from_millis(300));
    let at_drop = std::fs::read(&file).unwrap().len();
    std::thread::sleep(Duration::from_millis(9700));
    let before_restore = std::fs::read(&file).unwrap().len();
    assert_eq!(at_drop, before_restore, "nothing arrives while the network is gone");
    proxy.restore();
    let out = client.wait_with_output().unwrap();
    assert!(start.elapsed() > Duration::from_secs(12));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["reconnects"].as_u64().unwrap() >= 1, "{report}");
    assert_eq!(report["ended"]["verification"]["status"], "verified", "{report}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("connection lost"), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read(&file).unwrap() == std::fs::read(&path).unwrap(), "every line once, in order");
}

#[test]
fn a_push_to_no_server_gives_up_with_one_line() {
    let dir = scratch("serve-none");
    let out = push(Path::new("replays/study/P01-manual-7.jsonl"), "http://127.0.0.1:9/", &["--give-up", "1", "--timeout", "0.5"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.lines().last().unwrap().starts_with("error: gave up after"), "{err}");
    drop(dir);
}
