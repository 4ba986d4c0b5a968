//! A protocol's participants over HTTP (`docs/protocol.md`): one id namespace (automatic ids
//! skip every id in use, a new id in use is refused, case does not tell ids apart, an id is a
//! string), a folder that opens again after a restart, an older folder with a repeated id
//! reported by name; and a task step finished only by the participant's own session.

use std::path::Path;

use crate::common::{assert_one_line_error, grove, scratch};
use crate::serve_fixture::{append, open, push, request, study_lines, Server};

const PROTOCOL: &str = "assets/protocols/tree-planting.ron";

fn call(server: &Server, method: &str, path: &str, body: &str) -> crate::serve_fixture::Answer {
    request(&server.addr, method, path, &[], body.as_bytes())
}

fn dashboard_ids(server: &Server) -> Vec<String> {
    let d = call(server, "GET", "/api/dashboard", "");
    d.json["participants"].as_array().unwrap().iter().map(|p| p["participant"].as_str().unwrap().to_string()).collect()
}

#[test]
fn named_p03_then_automatic_ids_give_no_second_p03_and_a_restart_opens_the_folder() {
    let dir = scratch("protocol-ids");
    let mut server = Server::start(&dir, 0, &["--protocol", PROTOCOL]);
    // The lab's network test: a shipped recording of P01 pushed into the day's folder.
    let out = push(Path::new("replays/study/P01-manual-7.jsonl"), &server.url, &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let join = |body: &str| call(&server, "POST", "/api/protocol/participants", body);
    let named = join(r#"{"participant": "P03"}"#);
    assert_eq!((named.status, named.json["participant"].as_str()), (201, Some("P03")), "{}", named.body);
    // P01 is the network test's, P03 is taken: the automatic ids are P02, then P04.
    let auto: Vec<String> = (0..2).map(|_| join("{}")).map(|a| a.json["participant"].as_str().unwrap_or_default().to_string()).collect();
    assert_eq!(auto, ["P02", "P04"]);
    for (body, status, reason) in [
        (r#"{"participant": "p03"}"#, 409, "participant id p03 is in use by participant P03"),
        (r#"{"participant": "P01"}"#, 409, "participant id P01 is in use by the sessions of P01 in this folder (P01-manual-7-1.jsonl)"),
        (r#"{"participant": 7}"#, 400, "'participant' must be a participant id, a string"),
        (r#"{"participant": null}"#, 400, "the request sent null"),
        (r#"{"participant": "P05", "order": 1}"#, 400, "the request has 'order'"),
        (r#"{"participant": "../P05"}"#, 400, "a participant id is 1 to 32 letters"),
    ] {
        let r = join(body);
        assert_eq!(r.status, status, "{body}: {}", r.body);
        assert!(r.json["error"].as_str().unwrap().contains(reason), "{body}: {}", r.body);
    }
    // A participant's own id takes them back to where they are.
    let back = join(r#"{"participant": "P03"}"#);
    assert_eq!((back.status, back.json["step"].as_u64()), (200, Some(1)), "{}", back.body);
    assert_eq!(dashboard_ids(&server), ["P03", "P02", "P04"]);
    let p03 = std::fs::read_to_string(dir.join("P03.answers.jsonl")).unwrap();
    assert_eq!(p03.matches("\"line\":\"participant\"").count(), 1, "{p03}");
    assert!(server.signal(libc::SIGTERM).success());
    let server = Server::start(&dir, 0, &["--protocol", PROTOCOL]);
    assert!(server.log().contains("participant P03 resumes at step 1"), "{}", server.log());
    assert_eq!(dashboard_ids(&server), ["P03", "P02", "P04"]);
}

/// A participant's file as an older grove serve wrote it.
fn participant_line(id: &str, index: usize) -> String {
    format!("{{\"line\":\"participant\",\"participant\":\"{id}\",\"protocol\":\"tree-planting\",\"index\":{index},\"order\":[\"ray-casting\",\"manual\"],\"time\":\"2026-12-01T09:00:00.000Z\"}}\n{{\"line\":\"step\",\"step\":1,\"block\":\"instructions\",\"time\":\"2026-12-01T09:00:00.000Z\"}}\n")
}

fn start_refused(dir: &Path) -> std::process::Output {
    grove(&["serve", "--port", "0", "--protocol", PROTOCOL, "--out", &dir.display().to_string()])
}

#[test]
fn a_folder_with_a_repeated_id_is_reported_by_name_with_how_to_mend_it() {
    let dir = scratch("protocol-repeated");
    std::fs::write(dir.join("P01.answers.jsonl"), participant_line("P01", 1)).unwrap();
    std::fs::write(dir.join("P03.answers.jsonl"), participant_line("P03", 0) + &participant_line("P03", 2)).unwrap();
    let out = start_refused(&dir);
    assert_one_line_error(&out, 2, "P03.answers.jsonl: two participants have the id P03, participant 1 and participant 3 (from line 3)");
    assert!(String::from_utf8_lossy(&out.stderr).contains("To mend the folder, move the second participant's lines (from line 3 on"), "{}", String::from_utf8_lossy(&out.stderr));

    let dir = scratch("protocol-case");
    std::fs::write(dir.join("P03.answers.jsonl"), participant_line("P03", 0)).unwrap();
    std::fs::write(dir.join("p03.answers.jsonl"), participant_line("p03", 1)).unwrap();
    assert_one_line_error(&start_refused(&dir), 2, "participants P03 and p03 have ids that differ only in case");

    let dir = scratch("protocol-file-id");
    std::fs::write(dir.join("P04.answers.jsonl"), participant_line("P07", 0)).unwrap();
    assert_one_line_error(&start_refused(&dir), 2, "P04.answers.jsonl: its participant line names \"P07\"");
}

#[test]
fn a_stale_or_header_only_session_does_not_finish_a_task_step() {
    let dir = scratch("protocol-steps");
    let server = Server::start(&dir, 0, &["--protocol", PROTOCOL]);
    let joined = call(&server, "POST", "/api/protocol/participants", "{}");
    assert_eq!(joined.json["participant"], "P01", "{}", joined.body);
    assert_eq!(joined.json["steps"][2]["task"], "ray-casting-7");
    let next = |from: u64| call(&server, "POST", "/api/protocol/participants/P01/next", &format!("{{\"from\": {from}}}"));
    assert_eq!(next(1).status, 200);
    // While P01 practises, their task's recording is pushed into the folder: a session opened
    // before the task step began.
    let out = push(Path::new("replays/study/P01-ray-casting-7.jsonl"), &server.url, &[]);
    assert!(out.status.success() && String::from_utf8_lossy(&out.stdout).contains("verified"), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(next(2).status, 200, "on to the task step");
    let r = next(3);
    assert_eq!(r.status, 409, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains("its session has not ended yet; not this step's: P01-ray-casting-7-1.jsonl (opened before the step began)"), "{}", r.body);
    // After the step began: a session with only its header, ended by its client.
    let lines = study_lines("P01-ray-casting-7.jsonl");
    let (bare, bare_file) = open(&server.addr, "w", &lines[0], None);
    let ended = request(&server.addr, "POST", &format!("/api/sessions/{bare}/end"), &[("grove-writer", "w")], b"");
    assert_eq!(ended.json["state"], "ended", "{}", ended.body);
    let r = next(3);
    assert_eq!(r.status, 409, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains(&format!("{bare_file} (it has only its header)")), "{}", r.body);
    // The participant's own session finishes it.
    let (own, own_file) = open(&server.addr, "p", &lines[0], None);
    assert_eq!(append(&server.addr, "p", &own, 2, &lines[1..]).status, 200);
    let ended = request(&server.addr, "POST", &format!("/api/sessions/{own}/end"), &[("grove-writer", "p")], b"");
    assert_eq!(ended.json["verification"]["status"], "verified", "{}", ended.body);
    let r = next(3);
    assert_eq!((r.status, r.json["step"].as_u64()), (200, Some(4)), "{}", r.body);
    let d = call(&server, "GET", "/api/dashboard", "");
    let listed: Vec<(String, serde_json::Value)> = d.json["sessions"].as_array().unwrap().iter().map(|s| (s["file"].as_str().unwrap().to_string(), s["not_this_steps"].clone())).collect();
    assert_eq!(
        listed,
        [
            ("P01-ray-casting-7-1.jsonl".to_string(), serde_json::json!("opened before the step began")),
            (bare_file, serde_json::json!("it has only its header")),
            (own_file, serde_json::Value::Null),
        ]
    );
    // A step sent as something other than a whole number is named as sent.
    let r = call(&server, "POST", "/api/protocol/participants/P01/answers", r#"{"step": "four", "answers": {"mental": 5}}"#);
    assert_eq!(r.status, 400, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains("'step' must be the participant's step, a whole number from 1; the request sent \"four\""), "{}", r.body);
    let r = call(&server, "POST", "/api/protocol/participants/P01/answers", r#"{"step": 7, "answers": {"mental": 5}}"#);
    assert_eq!(r.status, 409, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains("participant P01 is at step 4; the request names step 7"), "{}", r.body);
}
