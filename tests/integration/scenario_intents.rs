//! The intent steps `Plant`, `Remove` and `Drag` (docs/scenarios.md): they complete the shipped
//! study tasks, fail naming why when what they mean does not come of it, and are refused in one
//! line when misspelt.

use crate::common;

use std::path::Path;

use common::{assert_one_line_error, grove};
use grove_systems::task::TaskDef;

/// Writes a scenario file and runs `grove test` on it; returns the exit code and the scenario's
/// line.
fn run_file(dir: &Path, name: &str, text: &str) -> (Option<i32>, String) {
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(&path, text).unwrap();
    let keep = dir.join("kept");
    let out = grove(&["test", "--keep", &keep.display().to_string(), &path.display().to_string()]);
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let line = stdout
        .lines()
        .find(|l| l.split_whitespace().nth(1) == Some(name))
        .map(str::to_string)
        .unwrap_or_else(|| panic!("{name}: no result line: {out:?}"));
    (out.status.code(), line)
}

fn scenario(scene: &str, steps: &[String], expect: &str) -> String {
    format!("Scenario(scene: \"{scene}\", seed: 1, steps: [\n    {},\n], expect: [{expect}])\n", steps.join(",\n    "))
}

/// A study task becomes seven `Plant` lines; the manual task seven menu choices and `Drag`s.
/// Both complete without errors.
#[test]
fn the_study_tasks_written_as_intent_steps_complete() {
    let dir = tempfile::tempdir().unwrap();
    let task = TaskDef::builtin("ray-casting-7").unwrap();
    let mut steps = vec!["StartTask(\"ray-casting-7\")".to_string()];
    steps.extend(
        task.targets.iter().enumerate().map(|(i, t)| format!("Plant(model: \"{}\", at: Target({}))", t.model, i + 1)),
    );
    let (code, line) = run_file(
        dir.path(),
        "plant-seven",
        &scenario("study", &steps, "TaskCompleted(within_s: 30.0), NoErrors, TreeCount(9)"),
    );
    assert_eq!(code, Some(0), "{line}");

    let task = TaskDef::builtin("manual-7").unwrap();
    let mut steps = vec!["SwitchTechnique(\"manual\")".to_string(), "StartTask(\"manual-7\")".to_string()];
    for (i, t) in task.targets.iter().enumerate() {
        steps.push(format!("ChooseModel(\"{}\")", t.model));
        steps.push(format!("Drag(tree: Last, to: Target({}))", i + 1));
    }
    let (code, line) = run_file(
        dir.path(),
        "drag-seven",
        &scenario("study", &steps, "TaskCompleted(within_s: 60.0), NoErrors, Logged(kind: \"snapped\", count: 7)"),
    );
    assert_eq!(code, Some(0), "{line}");

    // Plant, then Remove by name.
    let steps = [
        "Plant(model: \"shrub-billboard\", at: Point(1.0, 0.0, -3.0))",
        "Name(name: \"bush\", tree: Last)",
        "Remove(Named(\"bush\"))",
    ]
    .map(String::from);
    let (code, line) =
        run_file(dir.path(), "remove", &scenario("study", &steps, "TreeCount(2), Logged(kind: \"removed\", count: 1)"));
    assert_eq!(code, Some(0), "{line}");
}

/// Each intent step fails at its own line, saying why, when what it means does not happen.
#[test]
fn intent_steps_fail_naming_why() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, Vec<&str>, &str); 5] = [
        // A tree is planted only in ray-casting mode.
        (
            "plant-manual",
            "study",
            vec!["SwitchTechnique(\"manual\")", "Plant(model: \"birch-mesh\", at: Point(1.0, 0.0, -3.0))"],
            "step 2 Plant(model: \"birch-mesh\", at: Point(1.0, 0.0, -3.0)): Plant plants in ray-casting mode",
        ),
        // Nothing is planted on water.
        (
            "plant-water",
            "assets/scenes/pond.ron",
            vec!["Plant(model: \"birch-mesh\", at: Point(0.0, -0.15, -6.0))"],
            "step 1 Plant(model: \"birch-mesh\", at: Point(0.0, -0.15, -6.0)): nothing was planted: the ray met water",
        ),
        // A tree behind another is not the tree the Bumper meets.
        (
            "remove-hidden",
            "study",
            vec![
                "Plant(model: \"shrub-billboard\", at: Point(0.0, 0.0, -6.0))",
                "Name(name: \"small\", tree: Last)",
                "Plant(model: \"broadleaf-mesh\", at: Point(0.0, 0.0, -2.0))",
                "Remove(Named(\"small\"))",
            ],
            "step 4 Remove(Named(\"small\")): the ray meets broadleaf-mesh (planted 2nd, removed by this press) at ",
        ),
        // Carried to a point 1.5 m above the ground, the tree is released green.
        (
            "drag-air",
            "study",
            vec![
                "SwitchTechnique(\"manual\")",
                "ChooseModel(\"birch-mesh\")",
                "Drag(tree: Last, to: Point(2.0, 1.5, -3.0))",
            ],
            "step 3 Drag(tree: Last, to: Point(2.0, 1.5, -3.0)): the tree Last did not snap to the ground at Point(2.0, 1.5, -3.0): the anchor ball was green (",
        ),
        // Carried over a hole, there is no ground under it.
        (
            "drag-hole",
            "study",
            vec![
                "SwitchTechnique(\"manual\")",
                "ChooseModel(\"birch-mesh\")",
                "Drag(tree: Last, to: Point(-7.5, 0.0, -9.0))",
            ],
            "did not snap to the ground at Point(-7.5, 0.0, -9.0): the anchor ball was hidden",
        ),
    ];
    for (name, scene, steps, needle) in cases {
        let steps: Vec<String> = steps.into_iter().map(String::from).collect();
        let (code, line) = run_file(dir.path(), name, &scenario(scene, &steps, ""));
        assert_eq!(code, Some(1), "{name}: {line}");
        assert!(line.contains(needle), "{name}: {line}\nwants: {needle}");
    }
}

/// A misspelt intent step is refused before anything runs, in one line naming it.
#[test]
fn misspelt_intent_steps_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for (name, step, needle) in [
        ("plnt", "Plnt(model: \"birch-mesh\", at: Point(1.0, 0.0, -3.0))", "Plnt"),
        ("remvoe", "Remvoe(Last)", "Remvoe"),
        ("darg", "Darg(tree: Last, to: Target(1))", "Darg"),
        ("plant-field", "Plant(modle: \"birch-mesh\", at: Point(1.0, 0.0, -3.0))", "modle"),
        ("drag-field", "Drag(tree: Last, onto: Target(1))", "onto"),
        ("plant-model", "Plant(model: \"birch-mush\", at: Point(1.0, 0.0, -3.0))", "birch-mush"),
    ] {
        let path = dir.path().join(format!("{name}.ron"));
        std::fs::write(&path, scenario("study", &[step.to_string()], "")).unwrap();
        let out = grove(&["test", &path.display().to_string()]);
        assert_one_line_error(&out, 2, needle);
        assert!(out.stdout.is_empty(), "{name}: nothing runs");
    }
}

/// Every scenario docs/scenarios.md shows in a `ron` block runs and passes as written (the
/// first is also checked, with its failing variant, by scenario_files).
#[test]
fn every_scenario_in_the_documentation_passes() {
    let doc = std::fs::read_to_string(common::root().join("docs/scenarios.md")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let blocks: Vec<&str> = doc.split("```ron\n").skip(1).map(|b| &b[..b.find("```").unwrap()]).collect();
    assert!(blocks.len() >= 2, "the first scenario and the study task in intent steps");
    assert!(blocks.iter().any(|b| b.matches("Plant(").count() == 7), "a study task as seven Plant lines");
    for (i, text) in blocks.iter().enumerate() {
        let (code, line) = run_file(dir.path(), &format!("doc-{}", i + 1), text);
        assert_eq!(code, Some(0), "block {}: {line}", i + 1);
    }
}
