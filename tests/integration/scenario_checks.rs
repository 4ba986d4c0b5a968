//! Scenario steps that say why they fail (docs/scenarios.md): a button step after an aim fails
//! at the press, naming what the ray met, when it does not meet what the aim names; tree aims
//! aim at the middle of the tree's pick shape; pressing on nothing is said explicitly.

use crate::common;

use std::path::Path;
use std::process::Output;

use common::grove;
use grove_systems::Sim;
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::targets::{Aim, TreeRef};

fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Writes a scenario file and runs `grove test` on it; returns the exit code and the scenario's
/// line.
fn run_file(dir: &Path, name: &str, text: &str) -> (Option<i32>, String) {
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(&path, text).unwrap();
    let keep = dir.join("kept");
    let out = grove(&["test", "--keep", &keep.display().to_string(), &path.display().to_string()]);
    let line = stdout(&out)
        .lines()
        .find(|l| l.split_whitespace().nth(1) == Some(name))
        .map(str::to_string)
        .unwrap_or_else(|| panic!("{name}: no result line: {:?}", out));
    (out.status.code(), line)
}

/// Where the study scene's controller starts.
fn controller_start() -> glam::Vec3 {
    let scene = Scene::builtin("study").unwrap();
    Script::new(Sim::from_scene(&scene, 1).unwrap()).controller().pose.position
}

fn scenario(steps: &str, expect: &str) -> String {
    format!("Scenario(scene: \"study\", seed: 1, steps: [{steps}], expect: [{expect}])\n")
}

/// The ray to a target meets a tree planted on the way: the press fails there, naming the tree,
/// where the ray met it and the target behind it; not at the end, as a missing tree would.
#[test]
fn a_tree_in_front_of_a_target_fails_the_press_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let target = grove_systems::task::TaskDef::builtin("ray-casting-7").unwrap().targets[1].position;
    let start = controller_start();
    let mid = start + (target - start) * 0.5;
    let steps = format!(
        "StartTask(\"ray-casting-7\"), ChooseModel(\"broadleaf-mesh\"), PointAt(Point({:.2}, 0.0, {:.2})), Press(Trigger), \
         ChooseModel(\"conifer-billboard\"), PointAt(Target(2)), Press(Trigger), Wait(10)",
        mid.x, mid.z
    );
    let (code, line) = run_file(dir.path(), "blocked", &scenario(&steps, "TargetSatisfied(2)"));
    assert_eq!(code, Some(1), "{line}");
    assert!(line.contains("step 7 Press(Trigger): the ray meets broadleaf-mesh (planted 1st) at "), "{line}");
    assert!(line.contains(", before Target(2) at "), "{line}");
    // The same scenario without the tree on the way passes.
    let clear =
        steps.replace(&format!("PointAt(Point({:.2}, 0.0, {:.2}))", mid.x, mid.z), "PointAt(Point(-4.0, 0.0, 2.0))");
    let (code, line) = run_file(dir.path(), "clear", &scenario(&clear, "TargetSatisfied(2)"));
    assert_eq!(code, Some(0), "{line}");
}

/// Bumper 2 m up a 1.3 m shrub points over it at the sky: the press fails there, saying the ray
/// meets nothing and which tree it was aimed at. A tree aim without an offset aims at the middle
/// of the shrub and removes it.
#[test]
fn a_bumper_over_a_shrub_fails_at_the_press_and_a_tree_aim_hits_the_shrub() {
    let dir = tempfile::tempdir().unwrap();
    let plant = "ChooseModel(\"shrub-billboard\"), PointAt(Point(1.0, 0.0, -3.0)), Press(Trigger), Wait(5)";
    let over = format!("{plant}, PointAt(Tree(tree: Last, offset: (0.0, 2.0, 0.0))), Press(Bumper), Wait(5)");
    let (code, line) = run_file(dir.path(), "over", &scenario(&over, "TreeCount(2)"));
    assert_eq!(code, Some(1), "{line}");
    assert!(line.contains("step 6 Press(Bumper): the ray meets nothing within 100 m, not shrub-billboard (planted 1st) aimed at Tree(tree: Last, offset: (0.0, 2.0, 0.0))"), "{line}");
    assert!(line.contains("PressOnNothing"), "says how to press on nothing: {line}");
    let middle = format!("{plant}, PointAt(Tree(tree: Last)), Press(Bumper), Wait(5)");
    let (code, line) =
        run_file(dir.path(), "middle", &scenario(&middle, "TreeCount(2), Logged(kind: \"removed\", count: 1)"));
    assert_eq!(code, Some(0), "{line}");
}

/// A tree aim without an offset is the middle of the tree's pick shape: halfway up a shrub, far
/// higher up a broadleaf, always above the base.
#[test]
fn a_tree_aim_is_the_middle_of_its_pick_shape() {
    let scene = Scene::builtin("study").unwrap();
    let mut s = Script::new(Sim::from_scene(&scene, 1).unwrap());
    let mut heights = Vec::new();
    for (model, x) in [("shrub-billboard", -2.0), ("broadleaf-mesh", 2.0)] {
        s.choose_model(model).point_at(glam::Vec3::new(x, 0.0, -3.0)).press(grove_systems::input::Button::Trigger);
        let base = s.aim_point(&Aim::Tree { tree: TreeRef::Last, offset: Some(glam::Vec3::ZERO) }).unwrap();
        let middle = s.aim_point(&Aim::Tree { tree: TreeRef::Last, offset: None }).unwrap();
        assert_eq!((middle.x, middle.z), (base.x, base.z), "{model}: on its axis");
        heights.push(middle.y - base.y);
    }
    assert!(heights[0] > 0.3 && heights[0] < 1.0, "the shrub's middle, m above its base: {}", heights[0]);
    assert!(heights[1] > 2.0 * heights[0], "the broadleaf's middle is far higher: {heights:?}");
}

/// Pressing on nothing is said: `PressOnNothing(…)` passes where the ray meets nothing and fails,
/// naming what it meets, where it meets something; `press_on_nothing: true` lets any press after
/// an aim at the sky pass.
#[test]
fn pressing_on_nothing_is_said_explicitly() {
    let dir = tempfile::tempdir().unwrap();
    let sky = "PointAt(Point(0.0, 40.0, -10.0))";
    let (code, line) = run_file(dir.path(), "unsaid", &scenario(&format!("{sky}, Press(Trigger)"), "TreeCount(2)"));
    assert_eq!(code, Some(1), "{line}");
    assert!(line.contains("step 2 Press(Trigger): the ray meets nothing within 100 m"), "{line}");
    let (code, line) =
        run_file(dir.path(), "said", &scenario(&format!("{sky}, PressOnNothing(Trigger)"), "TreeCount(2)"));
    assert_eq!(code, Some(0), "{line}");
    let text = scenario(&format!("{sky}, Press(Trigger)"), "TreeCount(2)")
        .replace("seed: 1,", "seed: 1, press_on_nothing: true,");
    let (code, line) = run_file(dir.path(), "switch", &text);
    assert_eq!(code, Some(0), "{line}");
    let (code, line) =
        run_file(dir.path(), "ground", &scenario("PointAt(Point(1.0, 0.0, -3.0)), PressOnNothing(Trigger)", ""));
    assert_eq!(code, Some(1), "{line}");
    assert!(line.contains("step 2 PressOnNothing(Trigger): the ray meets the plane \"ground\" at "), "{line}");
    // The switch does not excuse a press that meets the wrong thing.
    // 1.5 m behind the tree as seen from the start: the ray passes its trunk near the ground.
    let base = glam::Vec3::new(-10.0, 0.0, -5.0);
    let away = (base - controller_start()).with_y(0.0).normalize() * 1.5;
    let steps = format!(
        "ChooseModel(\"broadleaf-mesh\"), PointAt(Point(-10.0, 0.0, -5.0)), Press(Trigger), PointAt(Point({:.2}, 0.0, {:.2})), Press(Trigger)",
        base.x + away.x,
        base.z + away.z
    );
    let text = scenario(&steps, "").replace("seed: 1,", "seed: 1, press_on_nothing: true,");
    let (code, line) = run_file(dir.path(), "behind", &text);
    assert_eq!(code, Some(1), "{line}");
    assert!(line.contains("step 5 Press(Trigger): the ray meets broadleaf-mesh (planted 1st)"), "{line}");
}
