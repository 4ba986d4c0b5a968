//! Hostile clients of `grove serve`: each is refused with a reason, nothing is written past the
//! last good line, and the server goes on serving the others.

use std::io::Write;
use std::net::TcpStream;
use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::scratch;
use crate::serve_fixture::{append, open, push, read_answer, request, study_lines, Server};

fn whole(lines: &[String]) -> String {
    lines.iter().map(|l| format!("{l}\n")).collect()
}

/// The server still serves: its status, and a whole recording pushed and verified.
fn still_serving(server: &Server) {
    assert_eq!(request(&server.addr, "GET", "/api/status", &[], b"").status, 200, "{}", server.log());
    let out = push(Path::new("replays/study/P12-ray-casting-7.jsonl"), &server.url, &[]);
    assert!(out.status.success() && String::from_utf8_lossy(&out.stdout).contains("verified"), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A session with its first `n` lines written; returns (id, file, lines).
fn session_with(server: &Server, name: &str, n: usize) -> (String, String, Vec<String>) {
    let lines = study_lines(name);
    let (id, file) = open(&server.addr, "w", &lines[0], None);
    let r = append(&server.addr, "w", &id, 2, &lines[1..n]);
    assert_eq!(r.json["acked"].as_u64(), Some(n as u64), "{}", r.body);
    (id, file, lines)
}

#[test]
fn bad_lines_are_refused_with_their_reason_and_the_session_goes_on_from_the_last_good_one() {
    let dir = scratch("serve-bad-lines");
    let server = Server::start(&dir, 0, &[]);
    let (id, file, lines) = session_with(&server, "P01-ray-casting-7.jsonl", 30);
    let mut changed = lines[30].clone();
    let at = changed.find("\"tick\":").unwrap() + 7;
    changed.replace_range(at..at + 1, if &changed[at..at + 1] == "9" { "8" } else { "9" });
    let out_of_order = {
        // A line with an earlier tick and a right checksum chained on the last good line.
        let earlier = lines[2].clone();
        let prev = u32::from_str_radix(&lines[29][lines[29].len() - 10..lines[29].len() - 2], 16).unwrap();
        let (body, _) = grove_systems::replay::split_sum(&earlier).unwrap();
        grove_systems::replay::sign_body(&body, prev).0
    };
    let unknown_model = {
        let prev = u32::from_str_radix(&lines[29][lines[29].len() - 10..lines[29].len() - 2], 16).unwrap();
        let tick: u64 = serde_json::from_str::<serde_json::Value>(&lines[29]).unwrap()["tick"].as_u64().unwrap();
        let body = format!("{{\"type\":\"event\",\"tick\":{tick},\"ms\":0,\"frame\":0,\"event\":{{\"kind\":\"choose_model\",\"model\":\"no-such-tree\"}}}}");
        grove_systems::replay::sign_body(&body, prev).0
    };
    for (bad, status, reason) in [
        (changed, 422, "line 31: checksum mismatch"),
        (out_of_order, 422, "ticks out of order"),
        (unknown_model, 422, "unknown model 'no-such-tree'"),
        (lines[0].clone(), 422, "line 31:"),
        ("not json".to_string(), 422, "line 31:"),
    ] {
        let r = append(&server.addr, "w", &id, 31, &[bad, lines[30].clone()]);
        assert_eq!(r.status, status, "{}", r.body);
        assert!(r.json["error"].as_str().unwrap().contains(reason), "{}", r.body);
        assert_eq!(r.json["acked"], 30);
        assert_eq!(std::fs::read_to_string(dir.join(&file)).unwrap(), whole(&lines[..30]), "nothing past the last good line");
    }
    // A line without its newline is not taken either.
    let r = request(&server.addr, "POST", &format!("/api/sessions/{id}/lines?from=31"), &[("grove-writer", "w")], lines[30].as_bytes());
    assert_eq!((r.status, r.json["acked"].as_u64()), (400, Some(30)), "{}", r.body);
    // A batch that does not start at the next line is refused with the count.
    let r = append(&server.addr, "w", &id, 40, &lines[39..41]);
    assert_eq!((r.status, r.json["code"].as_str(), r.json["acked"].as_u64()), (409, Some("gap"), Some(30)), "{}", r.body);
    // The session goes on from the last good line.
    assert_eq!(append(&server.addr, "w", &id, 31, &lines[30..]).json["acked"].as_u64(), Some(lines.len() as u64));
    let r = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "w")], b"");
    assert_eq!(r.json["verification"]["status"], "verified", "{}", r.body);
    assert!(server.log().contains("refused a line of P01-ray-casting-7-1.jsonl: line 31: checksum mismatch"), "{}", server.log());
    still_serving(&server);
}

#[test]
fn a_ten_megabyte_line_is_refused_without_being_held() {
    let dir = scratch("serve-10mb");
    let server = Server::start(&dir, 0, &[]);
    let (id, file, lines) = session_with(&server, "P02-manual-7.jsonl", 12);
    let before = server.peak_kib();
    let mut body = lines[12].clone().into_bytes();
    body.push(b'\n');
    body.extend(std::iter::repeat_n(b'x', 10 << 20));
    body.push(b'\n');
    let r = request(&server.addr, "POST", &format!("/api/sessions/{id}/lines?from=13"), &[("grove-writer", "w")], &body);
    assert_eq!(r.status, 413, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains("line 14 is longer than the limit of 1048576 bytes"), "{}", r.body);
    assert_eq!(r.json["acked"], 13, "the good line before it is written");
    assert_eq!(std::fs::read_to_string(dir.join(&file)).unwrap(), whole(&lines[..13]));
    let grown = server.peak_kib().saturating_sub(before);
    assert!(grown < 8 * 1024, "the server's peak grew by {grown} KiB");
    // The same for a header line sent to open a session.
    let huge = serde_json::json!({ "header": "x".repeat(10 << 20) }).to_string();
    let r = request(&server.addr, "POST", "/api/sessions", &[("grove-writer", "w")], huge.as_bytes());
    assert_eq!(r.status, 413, "{}", r.body);
    still_serving(&server);
}

#[test]
fn a_participant_id_that_is_a_path_is_refused_and_nothing_is_made() {
    let dir = scratch("serve-ids");
    let server = Server::start(&dir.join("sessions"), 0, &[]);
    let mut header: serde_json::Value = serde_json::from_str(&study_lines("P03-manual-7.jsonl")[0]).unwrap();
    for (field, value, reason) in [("participant", "../../etc/x", "participant \"../../etc/x\" is not allowed"), ("participant", "a/b", "not allowed"), ("task", "../x", "task \"../x\" is not allowed"), ("scene", "/etc/passwd", "scene")] {
        let mut h = header.clone();
        h[field] = serde_json::json!(value);
        let body = h.as_object().unwrap().iter().filter(|(k, _)| *k != "sum").map(|(k, v)| format!("\"{k}\":{v}")).collect::<Vec<_>>().join(",");
        let line = grove_systems::replay::sign_body(&format!("{{{body}}}"), 0).0;
        let r = request(&server.addr, "POST", "/api/sessions", &[("grove-writer", "w")], serde_json::json!({ "header": line }).to_string().as_bytes());
        assert_eq!(r.status, 400, "{}", r.body);
        assert!(r.json["error"].as_str().unwrap().contains(reason), "{field}: {}", r.body);
        // The same by fields.
        let r = request(&server.addr, "POST", "/api/sessions", &[("grove-writer", "w")], serde_json::json!({ "participant": if field == "participant" { value } else { "P03" }, field: value }).to_string().as_bytes());
        assert_eq!(r.status, 400, "{}", r.body);
    }
    let names: Vec<String> = std::fs::read_dir(dir.join("sessions")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["sessions.json"]);
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "nothing beside the folder either");
    // An open request without its client's name is refused before the header is read.
    let r = request(&server.addr, "POST", "/api/sessions", &[], serde_json::json!({ "header": study_lines("P03-manual-7.jsonl")[0] }).to_string().as_bytes());
    assert_eq!(r.status, 400, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains("an open request needs the Grove-Writer header"), "{}", r.body);
    header["sum"] = serde_json::json!("00000000");
    let r = request(&server.addr, "POST", "/api/sessions", &[("grove-writer", "w")], serde_json::json!({ "header": header.to_string() }).to_string().as_bytes());
    assert_eq!(r.status, 400, "{}", r.body);
    still_serving(&server);
}

#[test]
fn a_second_writer_on_a_live_session_is_refused() {
    let dir = scratch("serve-second-writer");
    let server = Server::start(&dir, 0, &["--writer-lease", "30"]);
    let (id, file, lines) = session_with(&server, "P04-ray-casting-7.jsonl", 20);
    for (method, path) in [("POST", format!("/api/sessions/{id}/lines?from=21")), ("POST", format!("/api/sessions/{id}/end"))] {
        let body = whole(&lines[20..25]);
        let r = request(&server.addr, method, &path, &[("grove-writer", "intruder")], body.as_bytes());
        assert_eq!((r.status, r.json["code"].as_str()), (409, Some("writer")), "{}", r.body);
        assert!(r.json["error"].as_str().unwrap().contains("being written by another client"), "{}", r.body);
    }
    // Without a writer name, or with a session id that is not one.
    assert_eq!(request(&server.addr, "POST", &format!("/api/sessions/{id}/lines?from=21"), &[], b"").status, 400);
    for bad in ["../../sessions", "0123", &id.to_uppercase()] {
        assert_eq!(request(&server.addr, "GET", &format!("/api/sessions/{bad}"), &[], b"").status, 404, "{bad}");
    }
    assert_eq!(std::fs::read_to_string(dir.join(&file)).unwrap(), whole(&lines[..20]));
    assert_eq!(append(&server.addr, "w", &id, 21, &lines[20..]).status, 200, "its own writer goes on");
    still_serving(&server);
}

#[test]
fn a_client_that_sends_one_byte_a_second_is_cut_off_and_holds_up_no_one() {
    let dir = scratch("serve-slow");
    let server = Server::start(&dir, 0, &["--read-timeout", "5"]);
    let (id, file, lines) = session_with(&server, "P05-manual-7.jsonl", 10);
    // A body one byte a second: the line before it arrives whole and is written; the rest is
    // refused when the read time is up.
    let body = format!("{}\n{}\n", lines[10], lines[11]);
    let mut slow = TcpStream::connect(&server.addr).unwrap();
    let head = format!("POST /api/sessions/{id}/lines?from=11 HTTP/1.1\r\nHost: x\r\ngrove-writer: w\r\nConnection: close\r\nContent-Length: {}\r\n\r\n", body.len());
    slow.write_all(head.as_bytes()).unwrap();
    slow.write_all(&body.as_bytes()[..lines[10].len() + 1]).unwrap();
    let writer = std::thread::spawn(move || {
        for b in body.as_bytes()[lines_len_plus_one(&body)..].iter() {
            if slow.write_all(&[*b]).is_err() {
                break;
            }
            std::thread::sleep(Duration::from_secs(1));
        }
        slow
    });
    // Meanwhile others are served, before the slow request is over.
    let start = Instant::now();
    still_serving(&server);
    assert!(!server.log().contains("did not arrive"), "served only after the slow request ended: {}", server.log());
    let mut slow = writer.join().unwrap();
    let r = read_answer(&mut slow);
    assert!(start.elapsed() < Duration::from_secs(15), "{:?}", start.elapsed());
    assert_eq!(r.status, 408, "{}", r.body);
    assert!(r.json["error"].as_str().unwrap().contains("did not arrive within 5.0 s"), "{}", r.body);
    assert_eq!(r.json["acked"], 11);
    let lines = study_lines("P05-manual-7.jsonl");
    assert_eq!(std::fs::read_to_string(dir.join(&file)).unwrap(), whole(&lines[..11]));
    // A request head one byte a second: the connection is closed when the read time is up.
    let mut slow = TcpStream::connect(&server.addr).unwrap();
    slow.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let start = Instant::now();
    for b in b"GET /api/status HTTP/1.1\r\n" {
        if slow.write_all(&[*b]).is_err() {
            break;
        }
        std::thread::sleep(Duration::from_millis(400));
        if start.elapsed() > Duration::from_secs(7) {
            break;
        }
    }
    let r = read_answer(&mut slow);
    assert_ne!(r.status, 200, "{}", r.head);
    assert!(start.elapsed() < Duration::from_secs(10), "{:?}", start.elapsed());
}

#[test]
fn a_session_s_status_is_answered_while_another_request_holds_it() {
    let dir = scratch("serve-status-busy");
    let server = Server::start(&dir, 0, &["--read-timeout", "10"]);
    let (id, _file, lines) = session_with(&server, "P06-manual-7.jsonl", 10);
    // A lines request whose last line never arrives holds the session for the read time.
    let body = format!("{}\n{}\n{}", lines[10], lines[11], &lines[12][..20]);
    let mut slow = TcpStream::connect(&server.addr).unwrap();
    let head = format!("POST /api/sessions/{id}/lines?from=11 HTTP/1.1\r\nHost: x\r\ngrove-writer: w\r\nContent-Length: {}\r\n\r\n", body.len() + 100);
    slow.write_all(head.as_bytes()).unwrap();
    slow.write_all(body.as_bytes()).unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let start = Instant::now();
    let r = request(&server.addr, "GET", &format!("/api/sessions/{id}"), &[], b"");
    assert!(start.elapsed() < Duration::from_secs(5), "answered without waiting for the read time: {:?}", start.elapsed());
    assert_eq!((r.status, r.json["acked"].as_u64(), r.json["state"].as_str()), (200, Some(12), Some("open")), "the two whole lines are counted: {}", r.body);
    // Writing it is refused while the request holds it, as before.
    let w = append(&server.addr, "w", &id, 13, &lines[12..14]);
    assert_eq!((w.status, w.json["code"].as_str()), (409, Some("busy")), "{}", w.body);
    drop(slow);
}

/// Where the one-byte-a-second part of the body starts: after its first line.
fn lines_len_plus_one(body: &str) -> usize {
    body.find('\n').unwrap() + 1
}

#[test]
fn path_traversal_in_static_and_model_urls_is_refused() {
    let dir = scratch("serve-traversal");
    let server = Server::start(&dir, 0, &[]);
    for url in [
        "/../Cargo.toml",
        "/scenes/../../Cargo.toml",
        "/scenes/%2e%2e/%2e%2e/Cargo.toml",
        "/models/shipped/..%2f..%2f..%2fCargo.toml",
        "/models/banks/species/%2e%2e%2f%2e%2e%2f%2e%2e%2fCargo.toml",
        "/models/shipped/%5c..%5c..%5cCargo.toml",
        "/client/.%2e/.%2e/Cargo.toml",
        "/scenes/%00study.ron",
        "/%2fetc%2fpasswd",
        "//etc/passwd",
    ] {
        let r = request(&server.addr, "GET", url, &[], b"");
        assert_eq!(r.status, 404, "{url}: {}", r.body);
        assert!(!r.body.contains("[package]") && !r.body.contains("root:"), "{url}");
        assert!(r.json["error"].is_string(), "{url}: a reason: {}", r.body);
        assert!(!r.body.contains(&*crate::common::root().to_string_lossy()), "{url}: no path of the machine: {}", r.body);
    }
    assert_eq!(request(&server.addr, "DELETE", "/scenes/study.ron", &[], b"").status, 405);
    still_serving(&server);
}
