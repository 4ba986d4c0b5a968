//! `grove serve` and a headset's page: a session opened with the scene its room gave (kept beside
//! the recordings, named by the header, found by `grove replay`), and the routes a reloaded page
//! reads its session back from.

use crate::common::{grove, scratch};
use crate::serve_fixture::{Server, append, open, request, study_lines};

/// A room as a page builds it: a flat floor at `y`, the study scene's sun, wind and camera.
fn room_text(y: f32) -> String {
    format!(
        "// a room\nScene(\n    name: \"room\",\n    dt: 0.016666668,\n    seed: 20190612,\n    planes: [\n        (name: \"floor\", shape: Grid(min: (-20.0, -20.0), size: (40.0, 40.0), cell: 2.0, elevation: {y:?})),\n    ],\n    sun: (latitude_deg: 47.3769, longitude_deg: 8.5417, utc: \"2026-06-21T09:30:00Z\", time_rate: 0.0),\n    wind: (direction: (1.0, 0.0, 0.4), strength: 0.5, density: 0.15, gust_average: 0.6, gust_strength: 0.4, gust_frequency: 0.2),\n    camera: (position: (0.0, 1.7, 6.0), look_at: (0.0, 0.5, -4.0), fov_y_deg: 60.0),\n)\n"
    )
}

fn open_fields(server: &Server, body: &serde_json::Value) -> crate::serve_fixture::Answer {
    request(&server.addr, "POST", "/api/sessions", &[("grove-writer", "page")], body.to_string().as_bytes())
}

#[test]
fn a_session_opened_with_its_room_scene_keeps_it_beside_the_recording_and_replays_on_it() {
    let dir = scratch("serve-room");
    let server = Server::start(&dir, 0, &[]);
    let text = room_text(-0.03);
    let a = open_fields(
        &server,
        &serde_json::json!({ "participant": "P40", "task": "ray-casting-7", "seed": 7, "scene_text": text }),
    );
    assert_eq!(a.status, 201, "{}", a.body);
    let header: serde_json::Value = serde_json::from_str(a.json["header"].as_str().unwrap()).unwrap();
    let scene = header["scene"].as_str().unwrap().to_string();
    assert!(scene.starts_with("room-") && scene.ends_with(".ron"), "{scene}");
    assert_eq!(std::fs::read_to_string(dir.join(&scene)).unwrap(), text, "the scene as sent, beside the recording");
    let id = a.json["session"].as_str().unwrap();
    // A reloaded page reads the scene and the file back.
    let s = request(&server.addr, "GET", &format!("/api/sessions/{id}/scene"), &[], b"");
    assert_eq!((s.status, s.body.as_str()), (200, text.as_str()));
    let l = request(&server.addr, "GET", &format!("/api/sessions/{id}/lines"), &[], b"");
    assert_eq!((l.status, l.body.clone()), (200, format!("{}\n", a.json["header"].as_str().unwrap())));
    // The same room again: the same file, a second session.
    let b =
        open_fields(&server, &serde_json::json!({ "participant": "P40", "task": "ray-casting-7", "scene_text": text }));
    assert_eq!(b.status, 201, "{}", b.body);
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(b.json["header"].as_str().unwrap()).unwrap()["scene"],
        scene.as_str()
    );
    let end = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "page")], b"");
    assert_eq!(end.status, 200, "{}", end.body);
    assert_eq!(end.json["verification"]["error"], serde_json::Value::Null, "{}", end.body);
    // grove replay finds the scene beside the recording, from any working directory.
    let file = dir.join(a.json["file"].as_str().unwrap());
    let out = grove(&["replay", file.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn a_bad_room_scene_is_refused_with_its_reason_and_nothing_is_written() {
    let dir = scratch("serve-room-bad");
    let server = Server::start(&dir, 0, &[]);
    let cases = [
        (serde_json::json!({ "participant": "P1", "scene": "study", "scene_text": room_text(0.0) }), "not both"),
        (serde_json::json!({ "participant": "P1", "scene_text": "Scene(name: \"x\"" }), "scene_text: line 1"),
        (
            serde_json::json!({ "participant": "P1", "scene_text": room_text(0.0).replacen("name: \"room\",", "name: \"room\", banks: [\"..\"],", 1) }),
            "model banks",
        ),
        (serde_json::json!({ "participant": "../P1", "scene_text": room_text(0.0) }), "participant"),
    ];
    for (body, reason) in cases {
        let a = open_fields(&server, &body);
        assert_eq!(a.status, 400, "{}", a.body);
        assert!(a.json["error"].as_str().unwrap().contains(reason), "{reason}: {}", a.body);
    }
    let files: Vec<String> = std::fs::read_dir(&*dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "sessions.json")
        .collect();
    assert!(files.is_empty(), "{files:?}");
    assert!(request(&server.addr, "GET", "/api/status", &[], b"").status == 200, "still serving");
}

#[test]
fn a_session_s_lines_read_back_are_the_acknowledged_ones_and_a_built_in_scene_is_no_file() {
    let dir = scratch("serve-readback");
    let server = Server::start(&dir, 0, &[]);
    let lines = study_lines("P03-ray-casting-7.jsonl");
    let (id, _) = open(&server.addr, "w", &lines[0], None);
    let r = append(&server.addr, "w", &id, 2, &lines[1..120]);
    assert_eq!(r.json["acked"], 120, "{}", r.body);
    let back = request(&server.addr, "GET", &format!("/api/sessions/{id}/lines"), &[("grove-writer", "another")], b"");
    assert_eq!(back.status, 200);
    assert_eq!(back.body, lines[..120].iter().map(|l| format!("{l}\n")).collect::<String>());
    let scene = request(&server.addr, "GET", &format!("/api/sessions/{id}/scene"), &[], b"");
    assert_eq!(scene.status, 404, "{}", scene.body);
    assert!(scene.json["error"].as_str().unwrap().contains("built-in scene \"study\""), "{}", scene.body);
    // Reading takes no writer lease: the writer goes on at once.
    assert_eq!(append(&server.addr, "w", &id, 121, &lines[120..130]).json["acked"], 130);
    let unknown = request(&server.addr, "GET", "/api/sessions/0123456789abcdef0123456789abcdef/lines", &[], b"");
    assert_eq!(unknown.status, 404);
    let ended = request(&server.addr, "POST", &format!("/api/sessions/{id}/end"), &[("grove-writer", "w")], b"");
    assert_eq!(ended.status, 200);
    assert_eq!(
        request(&server.addr, "GET", &format!("/api/sessions/{id}/lines"), &[], b"").status,
        410,
        "an ended session is read from its folder, not here"
    );
}
