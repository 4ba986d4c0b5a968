//! The module's Rust side, tested natively (the same code runs in WebAssembly under Node in
//! `web/sim/tests/`, against the native build).

use grove_systems::hash::hex;
use grove_systems::replay::{Header, Line, ReplayOptions, encode_line, replay_reader};
use grove_systems::scene::Scene;

use crate::error::Error;
use crate::session::Session;

fn pose(x: f32, z: f32) -> String {
    // Aiming down at (x, 0, z) from 1.2 m above the origin's south, no roll.
    let rotation = look(x, z);
    format!(r#"{{"kind":"controller_pose","pose":{{"position":[0.0,1.2,0.0],"rotation":{rotation}}}}}"#)
}

/// A unit quaternion [x, y, z, w] that turns −Z towards (x, −1.2, z): yaw about +Y, then pitch.
fn look(x: f32, z: f32) -> String {
    let yaw = (-x).atan2(-z);
    let pitch = (-1.2f32).atan2((x * x + z * z).sqrt());
    let (sy, cy) = ((yaw / 2.0).sin(), (yaw / 2.0).cos());
    let (sp, cp) = ((pitch / 2.0).sin(), (pitch / 2.0).cos());
    // q = qy * qx
    let q = [cy * sp, sy * cp, -sy * sp, cy * cp];
    format!("[{},{},{},{}]", q[0], q[1], q[2], q[3])
}

/// A scripted run: start the task, aim at two places and plant at each.
fn script(session: &mut Session) -> Vec<String> {
    let mut lines = Vec::new();
    session.push(r#"{"tick":0,"event":{"kind":"start_task","task":"ray-casting-7"}}"#).unwrap();
    for (k, (x, z)) in [(0.5, -3.0), (-1.0, -4.0)].into_iter().enumerate() {
        let t = 10 + 40 * k as u64;
        session.push(&format!(r#"{{"tick":{t},"event":{}}}"#, pose(x, z))).unwrap();
        session.push(&format!(r#"{{"tick":{},"event":{{"kind":"button_down","button":"trigger"}}}}"#, t + 5)).unwrap();
        session
            .push(&format!(
                r#"{{"tick":{},"ms":{},"frame":9,"event":{{"kind":"button_up","button":"trigger"}}}}"#,
                t + 9,
                (t + 9) * 17
            ))
            .unwrap();
    }
    while session.tick() < 130 {
        lines.extend(session.step().unwrap());
    }
    lines
}

fn verify(lines: &[String]) -> grove_systems::replay::ReplayOutcome {
    let text = lines.join("\n") + "\n";
    replay_reader(text.as_bytes(), "made.jsonl", None, &ReplayOptions::default()).unwrap()
}

#[test]
fn a_recording_made_here_verifies_with_the_native_reader() {
    let (mut session, mut lines) =
        Session::new(r#"{"scene":"study","seed":11,"record":true,"participant":"W01","set":["snap_threshold=0.2"]}"#)
            .unwrap();
    assert_eq!(lines.len(), 1, "the header line");
    lines.extend(script(&mut session));
    let planted = session.snapshot().trees.len();
    lines.extend(session.finish().unwrap());
    assert!(lines.last().unwrap().starts_with(r#"{"type":"footer""#), "{:?}", lines.last());
    assert_eq!(lines.iter().filter(|l| l.contains(r#""type":"checkpoint""#)).count(), 2, "ticks 60 and 120");
    let outcome = verify(&lines);
    assert!(
        outcome.complete && outcome.first_divergence.is_none() && outcome.checkpoints_checked == 3,
        "{:?}",
        outcome.first_divergence
    );
    assert_eq!(hex(outcome.sim.hash().total), session.hash());
    assert_eq!(outcome.header.config.as_slice()[0].name, "snap_threshold");
    assert_eq!(outcome.sim.snapshot().trees.len(), planted);
    let task = outcome.sim.task_report().expect("the task ran");
    assert_eq!(task.error_kinds.off_target, 2, "two trees planted, neither on a target: {task:?}");
    // The session takes nothing more.
    assert!(matches!(session.step(), Err(Error::Finished)));
}

#[test]
fn a_recording_continues_a_header_line_made_elsewhere() {
    let mut header = Header::new("study", 3, Scene::builtin("study").unwrap().dt);
    header.participant = Some("W02".into());
    let line = encode_line(&Line::Header(header));
    let options = serde_json::json!({ "header": line }).to_string();
    let (mut session, made) = Session::new(&options).unwrap();
    assert!(made.is_empty(), "the header is the caller's");
    let mut lines = vec![line.clone()];
    lines.extend(script(&mut session));
    lines.extend(session.finish().unwrap());
    let outcome = verify(&lines);
    assert!(outcome.complete && outcome.first_divergence.is_none(), "{:?}", outcome.first_divergence);
    assert_eq!(outcome.header.participant.as_deref(), Some("W02"));
    // A header line changed by one byte is refused.
    let bad = serde_json::json!({ "header": line.replace("W02", "W03") }).to_string();
    assert!(matches!(Session::new(&bad), Err(Error::HeaderLine(m)) if m.contains("checksum")));
    // As is a header line given with fields of its own.
    let both = serde_json::json!({ "header": line, "seed": 4 }).to_string();
    assert!(Session::new(&both).unwrap_err().to_string().contains("`seed` is given with `header`"));
}

#[test]
fn bad_input_is_an_error_naming_it_and_changes_nothing() {
    let (mut a, _) = Session::new(r#"{"seed":2}"#).unwrap();
    let (mut b, _) = Session::new(r#"{"seed":2}"#).unwrap();
    for s in [&mut a, &mut b] {
        s.push(r#"{"tick":3,"event":{"kind":"open_menu"}}"#).unwrap();
        for _ in 0..5 {
            s.step().unwrap();
        }
    }
    let refusals = [
        (r#"{"kind":"jump"}"#, "unknown variant `jump`"),
        (r#"{"kind":"touchpad_axes","axes":[0.0,2.0]}"#, "outside [-1, 1]"),
        (r#"{"kind":"controller_pose","pose":{"position":[0,1,0],"rotation":[0,0,0,2]}}"#, "not a unit quaternion"),
        (r#"{"tick":4,"event":{"kind":"open_menu"}}"#, "out of tick order: the simulation is at tick 5"),
        (r#"{"tick":100000000,"event":{"kind":"end_task"}}"#, "beyond the limit of 100000000 ticks"),
        (r#"{"kind":"choose_model","model":"baobab"}"#, "baobab"),
        (r#"{"kind":"start_task","task":"juggling"}"#, "juggling"),
        (r#"{"kind":"open_menu","extra":1}"#, "unknown field `extra`"),
        (r#"{"tick":9,"event":{"kind":"open_menu"},"colour":"red"}"#, "unknown field `colour`"),
        (r#"{"type":"checkpoint","tick":9,"event":{"kind":"open_menu"}}"#, "is not \"event\""),
        (r#"[1,2]"#, "event"),
        (r#"{"kind":"#, "EOF"),
    ];
    let before = a.hash();
    for (json, says) in refusals {
        let e = a.push(json).expect_err(json);
        assert!(e.to_string().contains(says), "{json}: {e}");
        assert_eq!(a.tick(), 5);
    }
    // Out of order behind a queued event too.
    a.push(r#"{"tick":20,"event":{"kind":"close_menu"}}"#).unwrap();
    b.push(r#"{"tick":20,"event":{"kind":"close_menu"}}"#).unwrap();
    let e = a.push(r#"{"tick":12,"event":{"kind":"end_task"}}"#).unwrap_err();
    assert!(e.to_string().contains("an event stamped tick 20 was pushed before it"), "{e}");
    assert_eq!(a.hash(), before);
    for s in [&mut a, &mut b] {
        while s.tick() < 30 {
            s.step().unwrap();
        }
    }
    assert_eq!(a.hash(), b.hash(), "the refused calls changed nothing");
    assert!(a.snapshot().menu.open == b.snapshot().menu.open);
}

#[test]
fn scenes_are_built_in_or_handed_over_as_text() {
    let study = Scene::builtin("study").unwrap();
    let text = grove_systems::scene::BUILTIN_SCENES[0].1;
    let options = serde_json::json!({ "scene": "copy.ron", "scene_text": text, "seed": study.seed }).to_string();
    let (from_text, _) = Session::new(&options).unwrap();
    let (builtin, _) = Session::new(r#"{"scene":"study"}"#).unwrap();
    assert_eq!(from_text.hash(), builtin.hash());
    let broken = serde_json::json!({ "scene": "broken.ron", "scene_text": "Scene(dt: " }).to_string();
    let e = Session::new(&broken).unwrap_err().to_string();
    assert!(e.starts_with("scene \"broken.ron\": line 1"), "{e}");
    let e = Session::new(r#"{"scene":"moon"}"#).unwrap_err().to_string();
    assert!(e.contains("not a built-in scene"), "{e}");
    let e = Session::new(r#"{"set":["snap_threshold=99"]}"#).unwrap_err().to_string();
    assert!(e.contains("snap_threshold: '99' must be a number from 0 to 10"), "{e}");
    let e = Session::new(r#"{"sede":1}"#).unwrap_err().to_string();
    assert!(e.contains("unknown field `sede`"), "{e}");
    let e = Session::new(r#"{"technique":"telekinesis"}"#).unwrap_err().to_string();
    assert!(e.contains("registered: ray-casting, manual, gaze-dwell"), "{e}");
}

#[test]
fn the_c_abi_answers_errors_as_text_and_counts_handles() {
    use crate::abi::*;
    let result = || unsafe {
        String::from_utf8_lossy(std::slice::from_raw_parts(grove_result_ptr(), grove_result_len())).into_owned()
    };
    let bad = [0xffu8, 0xfe];
    assert_eq!(unsafe { grove_sim_new(bad.as_ptr(), bad.len()) }, -1);
    assert!(result().starts_with("options: invalid utf-8"), "{}", result());
    let options = br#"{"record":true}"#;
    let h = unsafe { grove_sim_new(options.as_ptr(), options.len()) };
    assert!(h >= 0, "{}", result());
    assert!(result().starts_with(r#"{"type":"header""#) && result().ends_with('\n'));
    assert_eq!(grove_sim_step(h as u32), 0);
    assert_eq!(grove_sim_tick(h as u32), 1.0);
    assert_eq!(grove_sim_free(h as u32), 0);
    assert_eq!(grove_sim_step(h as u32), -1);
    assert_eq!(result(), format!("no simulation with handle {h}"));
    assert_eq!(grove_sim_tick(9999), -1.0);
}

#[test]
fn the_ground_is_the_scene_planes_triangles_in_the_world() {
    let (session, _) = Session::new(r#"{"scene":"study"}"#).unwrap();
    let ground = session.ground();
    let names: Vec<&str> = ground.iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["ground", "terrace"]);
    for p in &ground {
        let vertices = p["vertices"].as_array().unwrap();
        let triangles = p["triangles"].as_array().unwrap();
        assert_eq!(vertices.len() % 3, 0);
        assert!(!triangles.is_empty() && triangles.len() % 3 == 0);
        let n = (vertices.len() / 3) as u64;
        assert!(triangles.iter().all(|i| i.as_u64().unwrap() < n));
    }
    // The terrace: 8 x 5 m in 0.5 m cells at 0.8 m, minus nothing: 16 x 10 cells, 2 triangles each.
    let terrace = &ground[1];
    assert_eq!(terrace["triangles"].as_array().unwrap().len(), 16 * 10 * 2 * 3);
    let ys: Vec<f64> =
        terrace["vertices"].as_array().unwrap().iter().skip(1).step_by(3).map(|v| v.as_f64().unwrap()).collect();
    assert!(ys.iter().all(|y| (y - 0.8).abs() <= 0.011), "{ys:?}");
    // The ground has its four holes: fewer triangles than 30 x 30 cells make.
    assert!(ground[0]["triangles"].as_array().unwrap().len() < 30 * 30 * 2 * 3);
}
