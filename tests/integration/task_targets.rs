//! The study tasks' promise (assets/tasks/*.ron): "a planted tree's crown (with its wind sway)
//! never covers another target or the ray towards it from the start position". For each task
//! and each target, with a tree of its model planted at every other target, the controller's
//! ray from where it starts, aimed at the target, meets the ground there first.

use grove_systems::catalogue::Catalogue;
use grove_systems::components::HitTarget;
use grove_systems::scenario::aims::{self, Aimed, Intent};
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::targets::ground_distance;
use grove_systems::task::{TaskDef, BUILTIN_TASKS};
use grove_systems::Sim;

/// Where each target's ray meets something other than the ground at the target, in words.
fn blocked(task: &TaskDef) -> Vec<String> {
    let scene = Scene::builtin(&task.scene).expect("the task's scene is built in");
    let catalogue = Catalogue::builtin();
    let mut found = Vec::new();
    for (i, target) in task.targets.iter().enumerate() {
        let mut sim = Sim::from_scene(&scene, scene.seed).unwrap();
        sim.step();
        for (j, other) in task.targets.iter().enumerate().filter(|(j, _)| *j != i) {
            let model = catalogue.by_name(&other.model).unwrap_or_else(|| panic!("target {}: model {}", j + 1, other.model)).id;
            // Planted as the plant system plants: the model's origin on the ground point.
            sim.spawn_tree(model, other.position, 0.0, 1.0, true);
        }
        let mut script = Script::new(sim);
        script.wait(1).point_at(target.position);
        let hit = script.sim().hit_marker();
        let on_ground = matches!(hit.target, HitTarget::Plane(_)) && ground_distance(hit.position, target.position) <= task.tolerance;
        if !on_ground {
            let aimed = Aimed { label: format!("Target({})", i + 1), point: target.position, intent: Intent::Ground { point: target.position, within: task.tolerance, plane: None } };
            let why = aims::check(script.sim(), script.names(), &aimed, false).err().map(|e| e.to_string()).unwrap_or_default();
            found.push(format!("{} target {} ({}): {why}", task.id, i + 1, target.model));
        }
    }
    found
}

#[test]
fn the_ray_from_the_start_to_each_target_is_clear_with_every_other_target_planted() {
    let mut all = Vec::new();
    for (id, _) in BUILTIN_TASKS {
        all.extend(blocked(&TaskDef::builtin(id).unwrap()));
    }
    assert!(all.is_empty(), "rays that do not reach their target:\n{}", all.join("\n"));
}

/// The check can fail: a tree planted on the line from the start to a target blocks its ray.
#[test]
fn a_tree_between_the_start_and_a_target_blocks_its_ray() {
    let mut task = TaskDef::builtin("ray-casting-7").unwrap();
    let scene = Scene::builtin(&task.scene).unwrap();
    let mut sim = Sim::from_scene(&scene, scene.seed).unwrap();
    sim.step();
    let start = Script::new(sim).controller().pose.position;
    let target = task.targets[1].position;
    let mut between = task.targets[0].clone();
    between.position = start + (target - start) * 0.5;
    between.position.y = 0.0;
    task.targets.push(between);
    let found = blocked(&task);
    assert!(found.iter().any(|f| f.contains("target 2 (") && f.contains("the ray meets broadleaf-mesh")), "{found:?}");
}
