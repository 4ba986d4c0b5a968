//! A lab day that survives (`docs/serve.md`, "What a crash leaves"): the token is kept in the
//! folder, so a server killed mid-push and started again lets the push go on; a push killed and
//! run again continues the session it began; neither makes a second file or loses a line.

use std::path::Path;
use std::time::Duration;

use crate::common::scratch;
use crate::serve_fixture::{push, request, spawn_push, study_lines, wait_lines, Server};

fn token_of(url: &str) -> String {
    url.split("?token=").nth(1).expect("the URL carries a token").to_string()
}

fn jsonl_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).filter(|n| n.ends_with(".jsonl")).collect();
    names.sort();
    names
}

#[test]
fn a_server_killed_mid_push_keeps_its_token_and_the_push_goes_on_after_the_restart() {
    let dir = scratch("serve-token-kept");
    let mut server = Server::start(&dir, 0, &["--require-token"]);
    let (port, token) = (server.port(), token_of(&server.url));
    assert_eq!(std::fs::read_to_string(dir.join("token")).unwrap(), format!("{token}\n"), "the token is kept in the folder");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        assert_eq!(std::fs::metadata(dir.join("token")).unwrap().permissions().mode() & 0o077, 0, "the token file is its owner's alone");
    }
    let name = "P10-ray-casting-7.jsonl";
    let path = Path::new("replays/study").join(name);
    let client = spawn_push(&path, &server.url, &["--rate", "10", "--timeout", "1", "--give-up", "60", "--json"]);
    let file = dir.join("P10-ray-casting-7-1.jsonl");
    wait_lines(&file, study_lines(name).len() / 4, Duration::from_secs(30));
    server.signal(libc::SIGKILL);
    let at_kill = std::fs::read_to_string(&file).unwrap().lines().count();
    assert!(at_kill < study_lines(name).len(), "killed mid-push: {at_kill} lines");
    std::thread::sleep(Duration::from_millis(800));
    let server = Server::start(&dir, port, &["--require-token"]);
    assert_eq!(token_of(&server.url), token, "the same token after the restart");
    assert!(server.log().contains("the token is the one kept in"), "{}", server.log());
    let out = client.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(report["reconnects"].as_u64().unwrap() >= 1, "{report}");
    assert_eq!(report["ended"]["verification"]["status"], "verified", "{report}");
    let session = report["session"].as_str().unwrap();
    assert!(stderr.contains(&format!("session {session} opened: P10-ray-casting-7-1.jsonl")), "the push names its session: {stderr}");
    assert!(std::fs::read(&file).unwrap() == std::fs::read(&path).unwrap(), "the file is the recording: nothing lost, nothing twice");
    assert_eq!(jsonl_files(&dir), ["P10-ray-casting-7-1.jsonl"]);
}

#[test]
fn new_token_draws_another_and_the_old_one_is_refused_with_a_json_answer() {
    let dir = scratch("serve-new-token");
    let server = Server::start(&dir, 0, &["--require-token"]);
    let old = token_of(&server.url);
    drop(server);
    let server = Server::start(&dir, 0, &["--require-token", "--new-token"]);
    let new = token_of(&server.url);
    assert_ne!(old, new);
    assert!(server.log().contains("a new token, kept in"), "{}", server.log());
    assert_eq!(std::fs::read_to_string(dir.join("token")).unwrap().trim_end(), new);
    let refused = request(&server.addr, "GET", "/api/status", &[("authorization", &format!("Bearer {old}"))], b"");
    assert_eq!(refused.status, 401);
    assert!(refused.head.contains("content-type: application/json"), "{}", refused.head);
    assert!(refused.head.to_lowercase().contains("www-authenticate: bearer"), "{}", refused.head);
    assert!(refused.json["error"].as_str().unwrap().contains("a session token is needed"), "{}", refused.body);
    assert_eq!(request(&server.addr, "GET", "/api/status", &[("authorization", &format!("Bearer {new}"))], b"").status, 200);
    // On loopback without --require-token there is no token to draw.
    let out = crate::common::grove(&["serve", "--port", "0", "--new-token", "--out", &dir.join("x").display().to_string()]);
    crate::common::assert_one_line_error(&out, 2, "--new-token is for a server that asks for a token");
}

#[test]
fn a_push_killed_and_run_again_continues_its_session_and_makes_one_file() {
    let dir = scratch("serve-push-again");
    let server = Server::start(&dir, 0, &[]);
    let name = "P09-ray-casting-7.jsonl";
    let path = Path::new("replays/study").join(name);
    let file = dir.join("P09-ray-casting-7-1.jsonl");
    let mut first = spawn_push(&path, &server.url, &["--rate", "10"]);
    wait_lines(&file, study_lines(name).len() / 4, Duration::from_secs(30));
    first.kill().unwrap();
    let first = first.wait_with_output().unwrap();
    let first_err = String::from_utf8_lossy(&first.stderr).into_owned();
    let session = first_err.split("session ").nth(1).and_then(|r| r.split_whitespace().next()).expect("the first push printed its session").to_string();
    let at_kill = std::fs::read_to_string(&file).unwrap().lines().count();
    assert!(at_kill > 1 && at_kill < study_lines(name).len(), "killed mid-push: {at_kill} lines");

    let again = push(&path, &server.url, &["--json"]);
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{err}");
    let report: serde_json::Value = serde_json::from_slice(&again.stdout).unwrap();
    assert_eq!(report["session"], session.as_str(), "the same session: {report}");
    assert_eq!(report["server_file"], "P09-ray-casting-7-1.jsonl");
    assert!(report["continued_from"].as_u64().unwrap() >= at_kill as u64, "{report}");
    assert!(err.contains(&format!("session {session} continued")), "{err}");
    assert_eq!(report["ended"]["verification"]["status"], "verified", "{report}");
    assert!(std::fs::read(&file).unwrap() == std::fs::read(&path).unwrap(), "one file, equal to the recording");
    assert_eq!(jsonl_files(&dir), ["P09-ray-casting-7-1.jsonl"], "no second file for the same recording");

    // Once more after the end: nothing is sent, the session's verification is reported.
    let third = push(&path, &server.url, &[]);
    assert!(third.status.success(), "{}", String::from_utf8_lossy(&third.stderr));
    assert!(String::from_utf8_lossy(&third.stderr).contains("has ended already: nothing sent"), "{}", String::from_utf8_lossy(&third.stderr));
    assert!(String::from_utf8_lossy(&third.stdout).contains(&format!("(session {session}): verified")), "{}", String::from_utf8_lossy(&third.stdout));
    assert_eq!(jsonl_files(&dir), ["P09-ray-casting-7-1.jsonl"]);
    let listed: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("sessions.json")).unwrap()).unwrap();
    assert_eq!(listed["sessions"].as_array().unwrap().len(), 1, "{listed}");
}

#[test]
fn a_push_whose_start_differs_from_the_server_s_is_refused() {
    let dir = scratch("serve-push-differs");
    let server = Server::start(&dir, 0, &["--writer-lease", "0.2"]);
    let lines = study_lines("P08-ray-casting-7.jsonl");
    // The server has the recording's first 20 lines; the file pushed has the same header line
    // but another line 10.
    let a = request(&server.addr, "POST", "/api/sessions", &[("grove-writer", "w")], serde_json::json!({ "header": lines[0], "continue": true }).to_string().as_bytes());
    assert_eq!(a.status, 201, "{}", a.body);
    let id = a.json["session"].as_str().unwrap();
    let r = crate::serve_fixture::append(&server.addr, "w", id, 2, &lines[1..20]);
    assert_eq!(r.json["acked"], 20, "{}", r.body);
    std::thread::sleep(Duration::from_millis(300));
    let scratch_dir = scratch("serve-push-differs-file");
    let changed = scratch_dir.join("P08-ray-casting-7.jsonl");
    let mut text: Vec<String> = lines.clone();
    text[9] = text[9].replace("\"sum\":\"", "\"sum\":\"0");
    std::fs::write(&changed, text.iter().map(|l| format!("{l}\n")).collect::<String>()).unwrap();
    let out = push(&changed, &server.url, &["--give-up", "5"]);
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("line 10 of P08-ray-casting-7-1.jsonl on the server differs"), "{err}");
    assert_eq!(std::fs::read_to_string(dir.join("P08-ray-casting-7-1.jsonl")).unwrap().lines().count(), 20, "nothing written by the refused push");
}
