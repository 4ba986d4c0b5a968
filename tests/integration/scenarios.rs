//! Scripted scenarios saved as recordings under `replays/scenarios/`, and the check that every
//! recording under `replays/` re-simulates to its checkpoints.
//!
//! After an intended simulation change, regenerate the scenario files with
//! `UPDATE_REPLAYS=1 cargo test --test integration scenarios::` and the study with
//! `cargo run --release -- synth --force`.
//!
//! Each scenario also exists as a scenario file under `tests/scenarios/` (docs/scenarios.md)
//! whose pinned hash is its recording's final hash (`tests/integration/scenario_files.rs` checks it); after
//! regenerating the recordings, pin the files again with `grove test --update`.

use crate::common;

use std::path::{Path, PathBuf};

use common::root;
use glam::Vec3;
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::input::Button;
use grove_systems::replay::{Header, ReplayOptions, record_events, replay_file};
use grove_systems::resources::Mode;
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::targets::{Aim, TreeRef};

fn study_script(seed: u64) -> Script {
    let scene = Scene::builtin("study").unwrap();
    Script::new(Sim::from_scene(&scene, seed).unwrap())
}

/// The scenarios: name and script. Each ends with the world in a state worth checking.
fn scenarios() -> Vec<(&'static str, Script)> {
    let mut out = Vec::new();

    let mut s = study_script(1);
    s.choose_model(ModelId(2)).point_at(Vec3::new(1.0, 0.0, -3.0)).press(Button::Trigger);
    s.choose_model(ModelId(5)).point_at(Vec3::new(-5.0, 0.0, -4.0)).press(Button::Trigger).wait(30);
    out.push(("plant-two", s));

    let mut s = study_script(2);
    s.point_at(Vec3::new(2.0, 0.0, -2.0)).press(Button::Trigger).wait(10);
    s.point_at(Vec3::new(2.0, 2.0, -2.0)).press(Button::Bumper).wait(10);
    out.push(("plant-remove", s));

    let mut s = study_script(3);
    s.switch_mode(Mode::Manual).choose_model(ModelId(4)).wait(10);
    // The tree just spawned, by name rather than by searching the world.
    let spawned = s.aim_point(&Aim::Tree { tree: TreeRef::Last, offset: Some(Vec3::ZERO) }).ok();
    if let Some(p) = spawned {
        s.point_at(p + Vec3::Y * 2.0).hold(Button::Trigger);
        s.touchpad(0.0, 1.0, 90);
        for k in 0..40 {
            let y = 2.0 - k as f32 * 0.1;
            s.point_at(Vec3::new(p.x, y, p.z - 4.0));
        }
        s.release(Button::Trigger).wait(20);
    }
    out.push(("manual-drag", s));

    let mut s = study_script(4);
    s.start_task("ray-casting-7").point_at(Vec3::new(-7.0, 0.0, -1.5)).press(Button::Trigger).wait(30).end_task();
    out.push(("task-start", s));
    out
}

fn record(name: &str, script: Script) -> Vec<u8> {
    let scene = Scene::builtin("study").unwrap();
    let (sim, events) = script.into_parts();
    // Record two more simulated seconds so that every scenario crosses checkpoints.
    let end = sim.tick() + 120;
    let mut header = Header::new("study", sim.seed(), scene.dt);
    header.participant = Some(format!("scenario:{name}"));
    header.synthetic = true;
    record_events(Vec::new(), &header, &events, end, serde_json::json!({ "scenario": name })).unwrap()
}

/// With `UPDATE_REPLAYS` set, rewrites the scenario files (each through a temporary file and a
/// rename, so a test reading them at the same time never sees half a file).
fn update_scenarios() {
    if std::env::var_os("UPDATE_REPLAYS").is_none() {
        return;
    }
    let dir = root().join("replays/scenarios");
    std::fs::create_dir_all(&dir).unwrap();
    for (name, script) in scenarios() {
        let tmp = dir.join(format!("{name}.jsonl.{}.tmp", std::process::id()));
        std::fs::write(&tmp, record(name, script)).unwrap();
        std::fs::rename(&tmp, dir.join(format!("{name}.jsonl"))).unwrap();
    }
}

#[test]
fn scenario_recordings_match_their_scripts() {
    update_scenarios();
    let dir = root().join("replays/scenarios");
    for (name, script) in scenarios() {
        let bytes = record(name, script);
        let path = dir.join(format!("{name}.jsonl"));
        let committed = std::fs::read(&path).unwrap_or_else(|_| {
            panic!("{} is missing; run UPDATE_REPLAYS=1 cargo test --test integration scenarios::", path.display())
        });
        assert!(
            committed == bytes,
            "{name}: the committed recording differs from its script; if the simulation changed on purpose, run UPDATE_REPLAYS=1 cargo test --test integration scenarios::"
        );
    }
}

fn recordings(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            recordings(&p, out);
        } else if p.extension().is_some_and(|x| x == "jsonl") {
            out.push(p);
        }
    }
}

#[test]
fn every_recording_under_replays_verifies() {
    update_scenarios();
    let mut files = Vec::new();
    recordings(&root().join("replays"), &mut files);
    files.sort();
    assert!(files.len() >= 4, "expected the committed recordings, found {}", files.len());
    for f in &files {
        let o = replay_file(f, &ReplayOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        assert!(o.first_divergence.is_none(), "{} diverged: {:?}", f.display(), o.first_divergence);
        assert!(o.complete, "{} is incomplete", f.display());
        assert!(o.checkpoints_checked >= 2, "{} checked only {} checkpoints", f.display(), o.checkpoints_checked);
    }
}

#[test]
fn scenarios_do_what_they_say() {
    for (name, script) in scenarios() {
        let sim = script.sim();
        let log = sim.log();
        match name {
            "plant-two" => assert_eq!(log.count("planted"), 2, "{name}"),
            "plant-remove" => {
                assert_eq!(log.count("planted"), 1, "{name}");
                assert_eq!(log.count("removed"), 1, "{name}");
            }
            "manual-drag" => {
                assert_eq!(log.count("planted"), 1, "{name}: one tree from the menu");
                assert!(log.count("moved") >= 1, "{name}: the tree was dragged");
            }
            "task-start" => {
                assert!(sim.task().is_some_and(|t| t.satisfied[0].is_some()), "{name}: the first target is satisfied")
            }
            _ => unreachable!(),
        }
    }
}
