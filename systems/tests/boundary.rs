//! The simulation's boundary (issue #33): a crate that depends only on grove-systems — as this
//! test does, seeing only its public API — builds a `Sim` from a scene, scripts it through input
//! events, steps it and reads everything a test needs through `Sim`'s typed getters (the world
//! and the resources are private to grove-systems); `Sim::set_up` is its only other way in.

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::components::Pose;
use grove_systems::events::Happening;
use grove_systems::input::Button;
use grove_systems::scene::Scene;
use grove_systems::script::Script;

fn scripted(seed: u64) -> Script {
    let mut scene = Scene::builtin("study").unwrap();
    scene.sun.time_rate = 60.0;
    let mut s = Script::new(Sim::from_scene(&scene, seed).unwrap());
    let eye = s.head().pose.position;
    s.move_head(Pose::looking_at(eye, Vec3::new(1.0, 0.0, -4.0)));
    s.point_at(Vec3::new(1.0, 0.0, -4.0)).press(Button::Trigger).wait(30);
    s
}

#[test]
fn a_script_steps_the_sim_and_reads_it_through_the_read_only_view() {
    let s = scripted(3);
    let sim = s.sim();
    // Read through the view: the tick, the trees, the head, the sun, the log.
    assert!(sim.tick() > 30);
    let mut trees = 0;
    sim.for_each_tree(|_| trees += 1);
    assert_eq!(trees, sim.counts().trees);
    assert_eq!(sim.tree_ids().len(), trees);
    assert!(sim.head().pose.forward().y < 0.0, "the head looks down at the ground");
    assert!(sim.sun().unwrap().time_rate == 60.0);
    let planted = sim.log().entries.iter().filter(|e| matches!(e.what, Happening::Planted { .. })).count();
    assert_eq!(planted, 1, "Trigger on the ground planted one tree");
    // The same script on the same seed reaches the same state.
    assert_eq!(scripted(3).sim().hash(), sim.hash());
}

#[test]
fn set_up_changes_the_camera_without_a_tick() {
    let mut sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 1).unwrap();
    let tick = sim.tick();
    let pose = Pose::looking_at(Vec3::new(0.0, 5.0, 5.0), Vec3::ZERO);
    sim.set_up().camera_pose(pose).sun_angles(45.0, 135.0);
    assert_eq!(sim.head().pose, pose);
    assert_eq!(sim.sun().unwrap().elevation_deg, 45.0);
    assert_eq!(sim.tick(), tick);
    let trees: Vec<hecs::Entity> = sim.tree_ids().into_iter().filter_map(hecs::Entity::from_bits).collect();
    let n = trees.len();
    if let Some(&e) = trees.first() {
        sim.set_up().despawn(e).unwrap();
        assert_eq!(sim.counts().trees, n - 1);
        assert!(sim.set_up().despawn(e).is_err(), "a second despawn is a typed error");
    }
}
