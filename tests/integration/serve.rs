//! `grove serve`: recordings pushed come out byte for byte and give the same study; two sessions
//! at once; the token on a network address; TLS; the files it serves; Ctrl-C.

use std::path::Path;
use std::time::Duration;

use crate::common::{grove, scratch};
use crate::serve_fixture::{append, open, push, request, study_files, study_lines, Server};

/// The recording's name as the server makes it: `P01-manual-7.jsonl` -> `P01-manual-7-1.jsonl`.
fn served_name(original: &Path) -> String {
    format!("{}-1.jsonl", original.file_stem().unwrap().to_string_lossy())
}

#[test]
fn every_study_recording_pushed_at_full_speed_comes_out_byte_for_byte_and_gives_the_same_study() {
    let dir = scratch("serve-study");
    let sessions = dir.join("sessions");
    let server = Server::start(&sessions, 0, &[]);
    let files = study_files();
    assert!(files.len() >= 24);
    // Four pushes at a time.
    for group in files.chunks(4) {
        let running: Vec<_> = group.iter().map(|f| (f.clone(), crate::serve_fixture::spawn_push(f, &server.url, &["--json"]))).collect();
        for (f, child) in running {
            let out = child.wait_with_output().unwrap();
            assert!(out.status.success(), "{}: {}", f.display(), String::from_utf8_lossy(&out.stderr));
            let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            assert_eq!(report["ended"]["verification"]["status"], "verified", "{report}");
        }
    }
    for f in &files {
        let pushed = std::fs::read(sessions.join(served_name(f))).unwrap();
        assert!(pushed == std::fs::read(f).unwrap(), "{} differs from the original", served_name(f));
    }
    let listed: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(sessions.join("sessions.json")).unwrap()).unwrap();
    let entries = listed["sessions"].as_array().unwrap();
    assert_eq!(entries.len(), files.len());
    assert!(entries.iter().all(|e| e["state"] == "ended" && e["verification"]["status"] == "verified"), "{listed}");

    let (a, b) = (dir.join("study-served"), dir.join("study-original"));
    for (replays, out) in [(sessions.as_path(), &a), (Path::new("replays/study"), &b)] {
        let o = grove(&["study", "--replays", &replays.display().to_string(), "--out", &out.display().to_string()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let read = |p: &Path| std::fs::read(p).unwrap();
    assert!(read(&a.join("trees.csv")) == read(&b.join("trees.csv")));
    assert!(read(&a.join("ablation.png")) == read(&b.join("ablation.png")));
    // The trial table names each file: the server's names end in -1.
    let trials = String::from_utf8(read(&a.join("trial_results.csv"))).unwrap().replace("-1.jsonl", ".jsonl");
    assert_eq!(trials, String::from_utf8(read(&b.join("trial_results.csv"))).unwrap());
    // The summary is the same but for the file names and the time the run took.
    let summary = |p: &Path| {
        let text = String::from_utf8(read(&p.join("summary.json"))).unwrap().replace("-1.jsonl", ".jsonl");
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["summary"].as_object_mut().unwrap().remove("wall_seconds").expect("a wall time");
        v
    };
    assert_eq!(summary(&a), summary(&b));
}

#[test]
fn two_sessions_at_once_write_two_files() {
    let dir = scratch("serve-two");
    let server = Server::start(&dir, 0, &[]);
    let (a, b) = (study_lines("P06-manual-7.jsonl"), study_lines("P06-ray-casting-7.jsonl"));
    // The same participant and task twice: two files, numbered.
    let (ida, fa) = open(&server.addr, "wa", &a[0], None);
    let (idb, fb) = open(&server.addr, "wb", &a[0], None);
    let (idc, fc) = open(&server.addr, "wc", &b[0], None);
    assert_eq!([fa.as_str(), fb.as_str(), fc.as_str()], ["P06-manual-7-1.jsonl", "P06-manual-7-2.jsonl", "P06-ray-casting-7-1.jsonl"]);
    // Batches of the three interleaved.
    let (mut na, mut nc) = (1usize, 1usize);
    while na < a.len() || nc < b.len() {
        for (id, w, lines, n) in [(&ida, "wa", &a, &mut na), (&idc, "wc", &b, &mut nc)] {
            if *n < lines.len() {
                let end = (*n + 37).min(lines.len());
                let r = append(&server.addr, w, id, *n as u64 + 1, &lines[*n..end]);
                assert_eq!((r.status, r.json["acked"].as_u64()), (200, Some(end as u64)), "{}", r.body);
                *n = end;
            }
        }
        // The second session of the same name stays at its header: an empty request is fine.
        let r = append(&server.addr, "wb", &idb, 2, &[]);
        assert_eq!((r.status, r.json["acked"].as_u64()), (200, Some(1)), "{}", r.body);
    }
    let whole = |l: &[String]| l.iter().map(|x| format!("{x}\n")).collect::<String>();
    assert_eq!(std::fs::read_to_string(dir.join(&fa)).unwrap(), whole(&a));
    assert_eq!(std::fs::read_to_string(dir.join(&fc)).unwrap(), whole(&b));
    assert_eq!(std::fs::read_to_string(dir.join(&fb)).unwrap(), whole(&a[..1]), "the second session has only its header");
    // The session with only its header has no checkpoint to compare: unverified, as grove replay says.
    for (id, w, status) in [(&ida, "wa", "verified"), (&idc, "wc", "verified"), (&idb, "wb", "unverified")] {
        let r = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", w)], b"");
        assert_eq!(r.json["verification"]["status"], status, "{}", r.body);
    }
}

#[test]
fn on_a_network_address_every_request_needs_the_token() {
    let dir = scratch("serve-token");
    let server = Server::start(&dir, 0, &["--host", "0.0.0.0"]);
    let token = server.url.split("?token=").nth(1).expect("the URL carries the token").to_string();
    assert_eq!(token.len(), 32);
    // The QR code follows the URL line in the log.
    assert!(server.wait_log("█", Duration::from_secs(10)), "a QR code is printed: {}", server.log());
    let header = &study_lines("P07-manual-7.jsonl")[0];
    let open_body = serde_json::json!({ "header": header }).to_string();
    for (method, path, body) in [("GET", "/api/status", ""), ("GET", "/scenes/study.ron", ""), ("GET", "/", ""), ("POST", "/api/sessions", open_body.as_str())] {
        for auth in [None, Some("Bearer 00000000000000000000000000000000"), Some("Bearer ")] {
            let h: Vec<(&str, &str)> = auth.map(|a| vec![("authorization", a)]).unwrap_or_default();
            let r = request(&server.addr, method, path, &h, body.as_bytes());
            assert_eq!(r.status, 401, "{method} {path} with {auth:?}");
            assert!(r.body.contains("token") && !r.body.contains("sessions"), "only the refusal: {}", r.body);
        }
    }
    let mut written: Vec<String> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    written.sort();
    assert_eq!(written, ["sessions.json", "token"], "nothing but the sessions' list and the kept token was written");
    // With the token: in the URL once (a cookie is set), then the cookie or a bearer header.
    let r = request(&server.addr, "GET", &format!("/api/status?token={token}"), &[], b"");
    assert_eq!(r.status, 200);
    let cookie = r.head.lines().find_map(|l| l.strip_prefix("set-cookie: ")).expect("a cookie").to_string();
    assert!(cookie.contains("HttpOnly") && cookie.contains("SameSite=Strict"), "{cookie}");
    let pair = cookie.split(';').next().unwrap();
    assert_eq!(request(&server.addr, "GET", "/scenes/study.ron", &[("cookie", pair)], b"").status, 200);
    let out = push(Path::new("replays/study/P07-manual-7.jsonl"), &server.url.replace("0.0.0.0", "127.0.0.1"), &[]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let url = format!("http://{}/", server.addr);
    let out = push(Path::new("replays/study/P07-manual-7.jsonl"), &url, &["--give-up", "1"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("401"), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn with_tls_auto_a_client_that_trusts_the_certificate_pushes_over_https() {
    let dir = scratch("serve-tls");
    let server = Server::start(&dir, 0, &["--tls", "auto"]);
    assert!(server.url.starts_with("https://127.0.0.1:"), "{}", server.url);
    let cert = dir.join("tls/cert.pem");
    assert!(std::fs::read_to_string(&cert).unwrap().starts_with("-----BEGIN CERTIFICATE-----"));
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        assert_eq!(std::fs::metadata(dir.join("tls/key.pem")).unwrap().permissions().mode() & 0o077, 0, "the key is its owner's alone");
    }
    let f = Path::new("replays/study/P08-manual-7.jsonl");
    let out = push(f, &server.url, &["--ca", &cert.display().to_string()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::read(dir.join("P08-manual-7-1.jsonl")).unwrap() == std::fs::read(f).unwrap());
    // Plain HTTP on the TLS port gets nothing; without the certificate the push is refused.
    assert_eq!(request(&server.addr, "GET", "/api/status", &[], b"").status, 0);
    let out = push(f, &server.url, &[]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("--ca"), "{}", String::from_utf8_lossy(&out.stderr));
    // The same certificate after a restart.
    let before = std::fs::read(&cert).unwrap();
    drop(server);
    let _again = Server::start(&dir, 0, &["--tls", "auto"]);
    assert_eq!(std::fs::read(&cert).unwrap(), before);
}

#[test]
fn scenes_tasks_and_models_are_served_as_they_are() {
    let dir = scratch("serve-static");
    let server = Server::start(&dir, 0, &[]);
    for (url, file, kind) in [
        ("/scenes/study.ron", "assets/scenes/study.ron", "text/plain"),
        ("/tasks/manual-7.ron", "assets/tasks/manual-7.ron", "text/plain"),
        ("/models/shipped/birch-mesh.gltf", "assets/trees/birch-mesh.gltf", "model/gltf+json"),
        ("/models/shipped/catalogue.ron", "assets/trees/catalogue.ron", "text/plain"),
        ("/models/banks/species/catalogue.ron", "assets/banks/species/catalogue.ron", "text/plain"),
        ("/client/grove-client.mjs", "web/client/grove-client.mjs", "text/javascript"),
        ("/sim/grove-sim.mjs", "web/sim/grove-sim.mjs", "text/javascript"),
    ] {
        let r = request(&server.addr, "GET", url, &[], b"");
        assert_eq!(r.status, 200, "{url}: {}", r.body);
        assert!(r.head.contains(&format!("content-type: {kind}")), "{url}: {}", r.head);
        assert_eq!(r.body, std::fs::read_to_string(crate::common::root().join(file)).unwrap(), "{url}");
    }
    let bin = request(&server.addr, "HEAD", "/models/shipped/birch-mesh.bin", &[], b"");
    let len = std::fs::metadata(crate::common::root().join("assets/trees/birch-mesh.bin")).unwrap().len();
    assert!(bin.head.contains(&format!("content-length: {len}")), "{}", bin.head);
    // With a built page (web/dist, `node web/page/build.mjs`), / is the page; without one, the
    // server's own index of sessions and files.
    let index = request(&server.addr, "GET", "/", &[], b"");
    match std::fs::read_to_string(crate::common::root().join("web/dist/index.html")) {
        Ok(page) => assert_eq!(index.body, page),
        Err(_) => assert!(index.body.contains("grove serve") && index.body.contains("/scenes/study.ron"), "{}", index.body),
    }
    let index = request(&server.addr, "GET", "/api/index", &[], b"");
    assert_eq!(index.json["tasks"], serde_json::json!(["/tasks/manual-7.ron", "/tasks/ray-casting-7.ron"]));
}

#[test]
fn ctrl_c_flushes_every_open_session_and_a_restart_continues_it() {
    let dir = scratch("serve-ctrl-c");
    let mut server = Server::start(&dir, 0, &[]);
    let lines = study_lines("P09-manual-7.jsonl");
    let (id, file) = open(&server.addr, "w1", &lines[0], None);
    let half = lines.len() / 2;
    assert_eq!(append(&server.addr, "w1", &id, 2, &lines[1..half]).json["acked"], half as u64);
    let status = server.signal(libc::SIGINT);
    assert!(status.success(), "{status}: {}", server.log());
    assert!(server.log().contains("1 sessions left open"), "{}", server.log());
    let listed: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(dir.join("sessions.json")).unwrap()).unwrap();
    assert_eq!((listed["sessions"][0]["state"].as_str(), listed["sessions"][0]["lines"].as_u64()), (Some("open"), Some(half as u64)));
    let whole = |l: &[String]| l.iter().map(|x| format!("{x}\n")).collect::<String>();
    assert_eq!(std::fs::read_to_string(dir.join(&file)).unwrap(), whole(&lines[..half]));
    let server = Server::start(&dir, 0, &[]);
    assert!(server.wait_log(&format!("continuing {file} ({half} lines)"), Duration::from_secs(5)), "{}", server.log());
    let r = request(&server.addr, "GET", &format!("/api/sessions/{id}"), &[], b"");
    assert_eq!(r.json["acked"], half as u64);
    assert_eq!(append(&server.addr, "w2", &id, half as u64 + 1, &lines[half..]).status, 200);
    let r = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "w2")], b"");
    assert_eq!(r.json["verification"]["status"], "verified", "{}", r.body);
    assert_eq!(std::fs::read_to_string(dir.join(&file)).unwrap(), whole(&lines));
}
