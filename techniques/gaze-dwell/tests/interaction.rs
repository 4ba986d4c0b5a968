//! The scripted interaction test of gaze-dwell: a simulation of the study scene with the
//! technique registered, driven by input events only.

use glam::Vec3;
use grove_gaze_dwell::{DWELL_S, Dwell, NAME, technique};
use grove_systems::Sim;
use grove_systems::components::Pose;
use grove_systems::events::Happening;
use grove_systems::input::Button;
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::technique::Techniques;

fn script() -> Script {
    let scene = Scene::builtin("study").unwrap();
    let mut sim = Sim::from_scene(&scene, 7).unwrap();
    sim.set_techniques(Techniques::with(vec![technique()]).unwrap());
    Script::new(sim)
}

/// Turns the head to the ground below `point` (the study's ground is uneven).
fn look_at(s: &mut Script, point: Vec3) {
    let ground = s.sim().ground_below(Vec3::new(point.x, 50.0, point.z), 0.0).map_or(point.y, |h| h.point.y);
    let point = Vec3::new(point.x, ground, point.z);
    let eye = s.head().pose.position;
    s.move_head(Pose::looking_at(eye, point));
}

fn planted(s: &Script) -> Vec<Vec3> {
    s.sim()
        .log()
        .entries
        .iter()
        .filter_map(|e| match e.what {
            Happening::Planted { position, .. } => Some(position),
            _ => None,
        })
        .collect()
}

#[test]
fn a_dwell_of_0_8_s_on_the_ground_plants_there_once() {
    let mut s = script();
    s.switch_technique(NAME);
    assert_eq!(s.sim().active_technique().name, NAME);
    let target = Vec3::new(1.0, 0.0, -4.0);
    look_at(&mut s, target);
    let dt = s.sim().dt();
    // Just short of the dwell: nothing yet.
    let short = (DWELL_S / dt).floor() as u64 - 3;
    s.wait(short);
    assert!(planted(&s).is_empty(), "planted after {short} ticks, before the dwell ended");
    // The rest of the dwell and a little more: one tree where the gaze rests.
    s.wait(10);
    let p = planted(&s);
    assert_eq!(p.len(), 1, "{p:?}");
    assert!(Vec3::new(p[0].x, 0.0, p[0].z).distance(target) < 0.05, "planted at {:?}", p[0]);
    // Keeping the gaze there plants nothing more.
    s.wait(120);
    assert_eq!(planted(&s).len(), 1);
    // The ray follows the head, not the hand.
    let (c, h) = (s.controller().pose, s.head().pose);
    assert!(c.position.distance(h.position) < 1e-6 && c.forward().distance(h.forward()) < 1e-6);
}

#[test]
fn trigger_plants_at_once_and_a_moving_gaze_never_dwells() {
    let mut s = script();
    s.switch_technique(NAME);
    let a = Vec3::new(-2.0, 0.0, -5.0);
    look_at(&mut s, a);
    s.wait(2).press(Button::Trigger);
    assert_eq!(planted(&s).len(), 1, "Trigger plants before any dwell");
    // A gaze that moves 0.3 m every 20 ticks never rests long enough.
    for k in 0..12 {
        look_at(&mut s, Vec3::new(2.0 + 0.3 * k as f32, 0.0, -6.0));
        s.wait(20);
    }
    assert_eq!(planted(&s).len(), 1);
}

#[test]
fn the_dwell_component_enters_the_world_hash_only_with_the_technique() {
    let mut plain = script();
    plain.wait(5);
    let h = plain.sim().hash();
    assert!(h.component("Dwell").is_none() && h.component("technique").is_none());

    let mut s = script();
    s.switch_technique(NAME).wait(3);
    let h = s.sim().hash();
    assert!(h.component("Dwell").is_some() && h.component("technique").is_some());
    assert_eq!(s.sim().plug_in_components::<Dwell>().len(), 1);
    // Switching back to a built-in technique stops the technique's systems.
    s.switch_mode(grove_systems::mode::Mode::RayCasting);
    look_at(&mut s, Vec3::new(0.0, 0.0, -6.0));
    s.wait(120);
    assert!(planted(&s).is_empty(), "no dwell planting under ray-casting");
    let log: Vec<&str> = s.sim().log().entries.iter().map(|e| e.what.kind()).collect();
    assert_eq!(log.iter().filter(|k| **k == "technique_changed").count(), 2, "{log:?}");
}

#[test]
fn an_unregistered_technique_changes_nothing() {
    let scene = Scene::builtin("study").unwrap();
    let mut s = Script::new(Sim::from_scene(&scene, 7).unwrap());
    s.switch_technique(NAME);
    assert_eq!(s.sim().technique_index(), 0);
    assert!(s.sim().log().entries.is_empty());
}
