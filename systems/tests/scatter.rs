//! Scenes with scattered trees: the garden builds, every scattered tree is an ordinary tree
//! entity standing on the ground, and the result depends only on the scene.

use grove_systems::Sim;
use grove_systems::components::Transform;
use grove_systems::scene::Scene;

fn garden() -> Scene {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/garden.ron");
    Scene::load(std::path::Path::new(path)).expect("garden scene loads")
}

#[test]
fn the_garden_scatters_ordinary_grounded_trees() {
    let scene = garden();
    let scattered: usize = scene.scatter.iter().map(|s| s.trees().unwrap().len()).sum();
    assert!(scattered > 60, "{scattered} scattered trees");
    let sim = Sim::from_scene(&scene, scene.seed).unwrap();
    let mut trees: Vec<(Transform, bool)> = Vec::new();
    sim.for_each_tree(|t| trees.push((t.transform, t.grounded)));
    // Positions over the pond (a hole in the lawn) get no tree; all others do.
    assert!(
        trees.len() <= scene.trees.len() + scattered && trees.len() + 10 >= scene.trees.len() + scattered,
        "{} trees of {}",
        trees.len(),
        scene.trees.len() + scattered
    );
    // Every tree stands on the lawn (within its ±5 cm unevenness and the models' roots), except
    // that none may stand in the pond.
    for (t, grounded) in &trees {
        assert!(*grounded, "a tree at {} is not on the ground", t.translation);
        assert!(t.translation.y.abs() < 0.3, "a tree at {}", t.translation);
        let pond = glam::Vec2::new(t.translation.x + 4.0, t.translation.z - 2.0).length();
        assert!(pond > 2.0, "a tree in the pond at {}", t.translation);
    }
    // The same scene gives the same world.
    let again = Sim::from_scene(&scene, scene.seed).unwrap();
    assert_eq!(sim.hash().total, again.hash().total);
}

#[test]
fn bad_scatters_are_refused_with_a_message() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/garden.ron")).unwrap();
    let bad = text.replacen("spacing: 1.1,", "spacing: 0.0,", 1);
    let scene = Scene::parse(&bad, "garden.ron");
    let msg = match scene {
        Ok(s) => s.validate().unwrap_err().to_string(),
        Err(e) => e.message,
    };
    assert!(msg.contains("scatter 0") && msg.contains("spacing"), "{msg}");
}
