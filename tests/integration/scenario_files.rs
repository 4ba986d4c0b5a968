//! Scenario files and `grove test` (docs/scenarios.md): the Rust scenarios of `scenarios.rs` as
//! files, mutated files, JUnit read by an independent consumer, `--update`, `--set`, drafts
//! from recordings, and the name-based targeting of the Rust `Script` API.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{assert_one_line_error, grove, root};
use glam::Vec3;
use grove_systems::Sim;
use grove_systems::expect::{Ball, Expect};
use grove_systems::hash::hex;
use grove_systems::input::Button;
use grove_systems::replay::{ReplayOptions, replay_file};
use grove_systems::scenario::run::{RunOptions, run};
use grove_systems::scenario::{Loaded, Step};
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::targets::TreeRef;

/// The scenarios of tests/integration/scenarios.rs, each also a file under tests/scenarios/.
const RUST_SCENARIOS: &[&str] = &["plant-two", "plant-remove", "manual-drag", "task-start"];

fn text(out: &Output) -> (String, String) {
    (String::from_utf8_lossy(&out.stdout).into_owned(), String::from_utf8_lossy(&out.stderr).into_owned())
}

fn grove_args(args: &[&str], paths: &[&Path]) -> Output {
    let mut all: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    all.extend(paths.iter().map(|p| p.display().to_string()));
    let refs: Vec<&str> = all.iter().map(String::as_str).collect();
    grove(&refs)
}

fn shipped(name: &str) -> PathBuf {
    root().join("tests/scenarios").join(format!("{name}.ron"))
}

fn shipped_text(name: &str) -> String {
    std::fs::read_to_string(shipped(name)).unwrap()
}

/// Writes `text` as `name.ron` in `dir`, checking that the mutation changed something.
fn mutant(dir: &Path, name: &str, base: &str, from: &str, to: &str) -> PathBuf {
    assert!(base.contains(from), "the base text holds {from:?}");
    let path = dir.join(format!("{name}.ron"));
    std::fs::write(&path, base.replacen(from, to, 1)).unwrap();
    path
}

#[test]
fn every_shipped_scenario_passes_in_grove_test() {
    let keep = tempfile::tempdir().unwrap();
    let out = grove_args(&["test", "tests/scenarios", "--keep"], &[keep.path()]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(0), "stdout: {stdout}\nstderr: {stderr}");
    let files = std::fs::read_dir(root().join("tests/scenarios"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "ron"))
        .count();
    assert!(files >= RUST_SCENARIOS.len() + 1, "the Rust scenarios and drag-snap are files");
    let passed: Vec<&str> = stdout.lines().filter(|l| l.starts_with("pass  ")).collect();
    assert_eq!(passed.len(), files, "one pass line per file: {stdout}");
    for name in RUST_SCENARIOS.iter().chain(&["drag-snap"]) {
        assert!(passed.iter().any(|l| l.split_whitespace().nth(1) == Some(name)), "{name} passed: {stdout}");
    }
    assert_eq!(std::fs::read_dir(keep.path()).unwrap().count(), 0, "nothing is kept when everything passes");
    // One at a time, the same results in the same order.
    let serial = grove_args(&["test", "tests/scenarios", "--jobs", "1", "--keep"], &[keep.path()]);
    let verdicts =
        |s: &str| s.lines().map(|l| l.split_whitespace().take(2).collect::<Vec<_>>().join(" ")).collect::<Vec<_>>();
    assert_eq!(verdicts(&text(&serial).0), verdicts(&stdout));
}

#[test]
fn a_target_that_cannot_be_found_fails_the_step_saying_why() {
    let dir = tempfile::tempdir().unwrap();
    let keep = dir.path().join("kept").display().to_string();
    let cases = [
        (
            "unnamed",
            "at: Tree(tree: Named(\"young birch\"), offset",
            "at: Tree(tree: Named(\"old oak\"), offset",
            "step 5 Mark(name: \"grab\", at: Tree(tree: Named(\"old oak\"), offset: (0.0, 2.0, 0.0))): cannot find the target: no tree is named \"old oak\"",
        ),
        (
            "unplanted",
            "Name(name: \"young birch\", tree: Last)",
            "Name(name: \"young birch\", tree: Planted(2))",
            "step 4 Name(name: \"young birch\", tree: Planted(2)): cannot find the target: tree Planted(2) does not exist: 1 trees have been planted so far",
        ),
        (
            "no-task",
            "PointAt(Mark(name: \"grab\"))",
            "PointAt(Target(1))",
            "step 6 PointAt(Target(1)): cannot find the target: no task is running",
        ),
    ];
    for (name, from, to, needle) in cases {
        let path = mutant(dir.path(), name, &shipped_text("drag-snap"), from, to);
        let out = grove_args(&["test", "--keep", &keep], &[&path]);
        assert_eq!(out.status.code(), Some(1), "{name}: {:?}", text(&out));
        assert!(text(&out).0.contains(needle), "{name}: {}", text(&out).0);
    }
}

/// The files are read into the same `Script` calls the Rust scenarios make: each reaches the
/// world hash of the recording tests/integration/scenarios.rs wrote, at the same tick, and its pinned hash
/// is that recording's final hash.
#[test]
fn the_scenario_files_reach_the_rust_scenarios_recorded_worlds() {
    for name in RUST_SCENARIOS {
        let loaded = Loaded::load(&shipped(name)).unwrap_or_else(|e| panic!("{e}"));
        let outcome = run(&loaded, &RunOptions::default()).unwrap();
        assert!(outcome.failure.is_none(), "{name}: {:?}", outcome.failure);
        let recorded =
            replay_file(&root().join("replays/scenarios").join(format!("{name}.jsonl")), &ReplayOptions::default())
                .unwrap();
        assert_eq!(outcome.ticks, recorded.sim.tick(), "{name}: the same number of ticks");
        let want = hex(recorded.sim.hash().total);
        assert_eq!(hex(outcome.sim.hash().total), want, "{name}: the world of the Rust scenario's recording");
        let pinned: Vec<&String> = loaded
            .scenario
            .expect
            .iter()
            .filter_map(|e| if let Expect::Hash(h) = e { Some(h) } else { None })
            .collect();
        assert_eq!(pinned, vec![&want], "{name}: the pinned hash is the recording's final hash");
    }
}

#[test]
fn mutated_files_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let base = shipped_text("plant-two");
    let cases = [
        ("bad-step", "Press(Trigger),", "Jump(Trigger),", "Jump"),
        ("unknown-model", "ChooseModel(\"birch-mesh\")", "ChooseModel(\"birch-mush\")", "birch-mush"),
        ("unknown-field", "seed: 1,", "seed: 1,\n    colour: \"red\",", "colour"),
        ("unknown-field-in-expectation", "within: 0.5)", "within: 0.5, radius: 2.0)", "radius"),
        ("unknown-technique", "Wait(30),", "SwitchTechnique(\"teleport\"),", "teleport"),
        ("unknown-log-kind", "kind: \"planted\"", "kind: \"plated\"", "plated"),
        ("huge-wait", "Wait(30),", "Wait(100000000),", "limit"),
    ];
    for (name, from, to, needle) in cases {
        let path = mutant(dir.path(), name, &base, from, to);
        let out = grove_args(&["test"], &[&path]);
        assert_one_line_error(&out, 2, needle);
        let (stdout, stderr) = text(&out);
        assert!(stdout.is_empty(), "{name}: nothing runs: {stdout}");
        assert!(stderr.contains(&format!("{name}.ron")), "{name}: the line names the file: {stderr}");
    }
}

#[test]
fn an_expectation_that_cannot_hold_fails_naming_the_step_and_keeps_the_recording() {
    let dir = tempfile::tempdir().unwrap();
    let keep = dir.path().join("kept");
    let path =
        mutant(dir.path(), "five-trees", &shipped_text("plant-two"), "Expect(TreeCount(4))", "Expect(TreeCount(5))");
    let out = grove_args(&["test", "--keep", &keep.display().to_string()], &[&path]);
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "stdout: {stdout}\nstderr: {stderr}");
    let line =
        stdout.lines().find(|l| l.starts_with("FAIL  five-trees")).unwrap_or_else(|| panic!("a FAIL line: {stdout}"));
    assert!(line.contains("step 8 Expect(TreeCount(5))"), "names the step: {line}");
    assert!(line.contains("expected 5, actual 4"), "expected and actual: {line}");
    let kept = keep.join("five-trees.jsonl");
    assert!(line.contains(&format!("recording: {}", kept.display())), "names the recording: {line}");
    // The kept recording replays and verifies, and ends where the run stopped: 8 steps in.
    let replayed = grove_args(&["replay", "--json"], &[&kept]);
    assert_eq!(replayed.status.code(), Some(0), "{}", text(&replayed).1);
    let report: serde_json::Value = serde_json::from_slice(&replayed.stdout).unwrap();
    assert_eq!(report["status"], "verified");
    assert_eq!(report["events"]["choose_model"], 2);
    assert_eq!(report["events"]["button_down"], 2);
}

#[test]
fn a_wait_until_timeout_names_the_condition() {
    let dir = tempfile::tempdir().unwrap();
    let path = mutant(
        dir.path(),
        "wait-nine",
        &shipped_text("plant-two"),
        "Wait(30),",
        "WaitUntil(until: TreeCount(9), timeout: 20),",
    );
    let out = grove_args(&["test", "--keep", &dir.path().join("kept").display().to_string()], &[&path]);
    let (stdout, _) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("step 7 WaitUntil("), "names the step: {stdout}");
    assert!(stdout.contains("timed out after 20 ticks waiting until TreeCount(9)"), "names the condition: {stdout}");
    assert!(stdout.contains("expected 9, actual 4"), "{stdout}");
    // A condition that comes true in time passes the step.
    let unpinned = shipped_text("plant-two").lines().filter(|l| !l.contains("Hash(")).collect::<Vec<_>>().join("\n");
    let path = mutant(
        dir.path(),
        "wait-four",
        &unpinned,
        "Wait(30),",
        "WaitUntil(until: TreeCount(4), timeout: 20), Wait(30),",
    );
    let out = grove_args(&["test"], &[&path]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out).0);
}

#[test]
fn drag_and_snap_fails_at_the_anchor_ball_under_a_tiny_snap_threshold() {
    let dir = tempfile::tempdir().unwrap();
    let keep = dir.path().display().to_string();
    let ok = grove_args(&["test", "--keep", &keep], &[&shipped("drag-snap")]);
    assert_eq!(ok.status.code(), Some(0), "{}", text(&ok).0);
    let out = grove_args(&["test", "--set", "snap_threshold=0.01", "--keep", &keep], &[&shipped("drag-snap")]);
    let (stdout, _) = text(&out);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let line = stdout.lines().find(|l| l.starts_with("FAIL  drag-snap")).unwrap_or_else(|| panic!("{stdout}"));
    assert!(
        line.contains("Expect(AnchorBall(White))") && line.contains("the anchor ball: expected white, actual green"),
        "{line}"
    );
    // The kept recording carries the override, so it replays as it ran.
    let rec = std::fs::read_to_string(dir.path().join("drag-snap.jsonl")).unwrap();
    assert!(rec.lines().next().unwrap().contains("\"snap_threshold\":\"0.01\""), "{}", rec.lines().next().unwrap());
    assert_eq!(grove_args(&["replay"], &[&dir.path().join("drag-snap.jsonl")]).status.code(), Some(0));
}

fn python() -> String {
    std::env::var("GROVE_PYTHON").unwrap_or_else(|_| "python3".into())
}

/// The JUnit file as Python's junitparser reads it: counts, and each case's time and result.
#[test]
fn junit_output_is_read_by_junitparser_with_the_right_counts_and_times() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["plant-two", "task-start"] {
        std::fs::copy(shipped(name), dir.path().join(format!("{name}.ron"))).unwrap();
    }
    mutant(dir.path(), "broken", &shipped_text("plant-remove"), "TreeCount(2)", "TreeCount(7)");
    let xml = dir.path().join("out").join("results.xml");
    std::fs::create_dir(xml.parent().unwrap()).unwrap();
    let out = grove_args(
        &["test", "--keep", &dir.path().join("kept").display().to_string(), "--junit", &xml.display().to_string()],
        &[dir.path()],
    );
    let (stdout, stderr) = text(&out);
    assert_eq!(out.status.code(), Some(1), "stdout: {stdout}\nstderr: {stderr}");
    let script = r#"
import json, sys
try:
    from junitparser import JUnitXml, TestSuite, Failure
except ImportError:
    sys.exit("the Python module junitparser is missing: pip install junitparser (scripts/requirements-test.txt)")
xml = JUnitXml.fromfile(sys.argv[1])
suites = [xml] if isinstance(xml, TestSuite) else list(xml)
cases = {}
for s in suites:
    for c in s:
        cases[c.name] = {"time": c.time, "failed": any(isinstance(r, Failure) for r in c.result),
                         "message": next((r.message for r in c.result if isinstance(r, Failure)), None)}
print(json.dumps({"suites": len(suites), "tests": sum(s.tests for s in suites),
                  "failures": sum(s.failures for s in suites), "errors": sum(s.errors for s in suites),
                  "time": sum(s.time for s in suites), "cases": cases}))
"#;
    let py = std::process::Command::new(python())
        .arg("-c")
        .arg(script)
        .arg(&xml)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {} ({e}); set GROVE_PYTHON", python()));
    assert!(py.status.success(), "junitparser: {}", String::from_utf8_lossy(&py.stderr));
    let got: serde_json::Value = serde_json::from_slice(&py.stdout).unwrap();
    assert_eq!(got["suites"], 1);
    assert_eq!(got["tests"], 3);
    assert_eq!(got["failures"], 1);
    assert_eq!(got["errors"], 0);
    // Each case's time is the one `grove test` printed, and the suite's is their sum.
    let mut sum = 0.0;
    for line in stdout.lines().filter(|l| l.starts_with("pass") || l.starts_with("FAIL")) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let (name, printed): (&str, f64) = (words[1], words[2].parse().unwrap());
        let case = &got["cases"][name];
        assert!((case["time"].as_f64().unwrap() - printed).abs() < 1e-9, "{name}: {case} vs {line}");
        assert_eq!(case["failed"], words[0] == "FAIL", "{name}");
        sum += printed;
    }
    assert!((got["time"].as_f64().unwrap() - sum).abs() < 1e-6, "suite time {} vs {sum}", got["time"]);
    let message = got["cases"]["broken"]["message"].as_str().unwrap();
    assert!(message.contains("TreeCount(7)") && message.contains("expected 7, actual 2"), "{message}");
    // An existing file is not replaced without --force.
    let again = grove_args(&["test", "--junit", &xml.display().to_string()], &[&shipped("plant-two")]);
    assert_one_line_error(&again, 2, "already exists");
}

#[test]
fn update_pins_the_hash_and_keeps_the_rest_of_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let base = shipped_text("plant-two");
    let start = base.find("Hash(\"").unwrap() + 6;
    let old = &base[start..start + 16];
    let path = mutant(dir.path(), "unpinned", &base, &format!("Hash(\"{old}\")"), "Hash(\"\")");
    let out = grove_args(&["test", "--keep", &dir.path().join("kept").display().to_string()], &[&path]);
    assert_eq!(out.status.code(), Some(1), "an unpinned hash fails");
    assert!(text(&out).0.contains("run grove test --update"), "{}", text(&out).0);
    let out = grove_args(&["test", "--update"], &[&path]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out).0);
    let recorded = replay_file(&root().join("replays/scenarios/plant-two.jsonl"), &ReplayOptions::default()).unwrap();
    let pinned = std::fs::read_to_string(&path).unwrap();
    assert_eq!(pinned, base.replace(old, &hex(recorded.sim.hash().total)), "only the hash changed, to the recording's");
    assert_eq!(grove_args(&["test"], &[&path]).status.code(), Some(0));
}

#[test]
fn a_recording_becomes_a_scenario_that_passes() {
    let dir = tempfile::tempdir().unwrap();
    let out_path = dir.path().join("draft.ron");
    let rec = root().join("replays/scenarios/plant-two.jsonl");
    let out = grove_args(&["scenario", "from-recording", &rec.display().to_string(), "--out"], &[&out_path]);
    assert_eq!(out.status.code(), Some(0), "{:?}", text(&out));
    let loaded = Loaded::load(&out_path).unwrap_or_else(|e| panic!("{e}"));
    // The Rust script chose models 2 and 5 by index and aimed at (1, 0, −3) and (−5, 0, −4).
    let chosen: Vec<&str> = loaded
        .scenario
        .steps
        .iter()
        .filter_map(|s| if let Step::ChooseModel(m) = s { Some(m.as_str()) } else { None })
        .collect();
    assert_eq!(chosen, ["birch-mesh", "conifer-billboard"]);
    let near = |model: &str, p: Vec3| {
        loaded.scenario.expect.iter().any(|e| matches!(e, Expect::TreeNear { model: m, point, .. } if m == model && (point.x - p.x).hypot(point.z - p.z) < 0.5))
    };
    assert!(
        near("birch-mesh", Vec3::new(1.0, 0.0, -3.0)) && near("conifer-billboard", Vec3::new(-5.0, 0.0, -4.0)),
        "{:?}",
        loaded.scenario.expect
    );
    assert!(loaded.scenario.expect.contains(&Expect::TreeCount(4)));
    let ran = grove_args(&["test"], &[&out_path]);
    assert_eq!(ran.status.code(), Some(0), "{}", text(&ran).0);
    // A draft of a manual-mode session with a touchpad push and a drag also runs as written.
    let drag = dir.path().join("drag.ron");
    let rec = root().join("replays/scenarios/manual-drag.jsonl");
    assert_eq!(
        grove_args(&["scenario", "from-recording", &rec.display().to_string(), "--out"], &[&drag]).status.code(),
        Some(0)
    );
    let ran = grove_args(&["test"], &[&drag]);
    assert_eq!(ran.status.code(), Some(0), "{}", text(&ran).0);
    // A synthetic participant's whole task: the draft plants every target's model at its
    // place (tolerance 0.5 m, as in the task file) and completes the task.
    let task = dir.path().join("task.ron");
    let rec = root().join("replays/study/P01-ray-casting-7.jsonl");
    assert_eq!(
        grove_args(&["scenario", "from-recording", &rec.display().to_string(), "--out"], &[&task]).status.code(),
        Some(0)
    );
    let drafted = Loaded::load(&task).unwrap_or_else(|e| panic!("{e}"));
    let def = grove_systems::task::TaskDef::builtin("ray-casting-7").unwrap();
    for t in &def.targets {
        let hit = drafted.scenario.expect.iter().any(|e| matches!(e, Expect::TreeNear { model, point, .. } if *model == t.model && (point.x - t.position.x).hypot(point.z - t.position.z) <= 0.5));
        assert!(hit, "a {} near {}: {:?}", t.model, t.position, drafted.scenario.expect);
    }
    assert!(
        drafted.scenario.expect.iter().any(|e| matches!(e, Expect::TaskCompleted { .. })),
        "{:?}",
        drafted.scenario.expect
    );
    assert_eq!(grove_args(&["test"], &[&task]).status.code(), Some(0));
    // An existing file is not overwritten.
    let again = grove_args(&["scenario", "from-recording", &rec.display().to_string(), "--out"], &[&out_path]);
    assert_one_line_error(&again, 2, "already exists");
}

fn study(seed: u64) -> Script {
    Script::new(Sim::from_scene(&Scene::builtin("study").unwrap(), seed).unwrap())
}

#[test]
fn the_rust_script_targets_trees_by_name_and_checks_expectations() {
    let mut s = study(2);
    s.choose_model("broadleaf-mesh").point_at(Vec3::new(2.0, 0.0, -2.0)).press(Button::Trigger);
    s.choose_model("birch-mesh").point_at(Vec3::new(-3.0, 0.0, -3.0)).press(Button::Trigger).wait(5);
    s.name_tree("oak", &TreeRef::Planted(1)).unwrap();
    s.expect(&Expect::TreeCount(4));
    // The first tree is removed by name, not by where it was aimed at.
    s.point_at_tree(TreeRef::Named("oak".into())).unwrap().press(Button::Bumper).wait(5);
    s.expect(&Expect::TreeCount(3));
    let err = s.tree_id(&TreeRef::Named("oak".into())).unwrap_err();
    assert!(err.to_string().contains("has been removed"), "{err}");
    assert!(s.tree_id(&TreeRef::Planted(3)).unwrap_err().to_string().contains("2 trees have been planted"));
    assert_eq!(s.tree_id(&TreeRef::Last).unwrap(), s.planted()[1]);
    // The scene's own conifer stands at (-11, 0, -13).
    let conifer = s.tree_id(&TreeRef::Nearest(-10.0, 0.0, -12.0)).unwrap();
    assert_eq!(s.sim().catalogue().get(s.sim().tree(conifer).unwrap().tree.model).unwrap().name, "conifer-mesh");
    assert!(
        s.check(&Expect::TreeNear { model: "birch-mesh".into(), point: Vec3::new(-3.0, 0.0, -3.0), within: 0.5 })
            .is_ok()
    );
    let m = s
        .check(&Expect::TreeNear { model: "broadleaf-mesh".into(), point: Vec3::new(2.0, 0.0, -2.0), within: 0.5 })
        .unwrap_err();
    assert_eq!(m.actual, "no broadleaf-mesh tree");
    let tick = s.sim().tick();
    let m = s.wait_until(&Expect::AnchorBall(Ball::White), 15).unwrap_err();
    assert_eq!(s.sim().tick(), tick + 15, "waited exactly the timeout");
    assert!(
        m.what.contains("timed out after 15 ticks waiting until AnchorBall(White)")
            && m.expected == "white"
            && m.actual == "hidden",
        "{m}"
    );
}

/// The first example of docs/scenarios.md, as a reader would save it, passes; with the tree
/// count changed as the document suggests, it fails with the line the document shows.
#[test]
fn the_example_in_the_documentation_runs_as_documented() {
    let doc = std::fs::read_to_string(root().join("docs/scenarios.md")).unwrap();
    let start = doc.find("```ron\n").expect("a ron example") + 7;
    let example = &doc[start..start + doc[start..].find("```").unwrap()];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plant.ron");
    std::fs::write(&path, example).unwrap();
    let out = grove_args(&["test"], &[&path]);
    assert_eq!(out.status.code(), Some(0), "{:?}", text(&out));
    assert!(text(&out).0.starts_with("pass  plant  "), "{}", text(&out).0);
    std::fs::write(&path, example.replace("TreeCount(3)", "TreeCount(4)")).unwrap();
    let keep = dir.path().join("kept");
    let out = grove_args(&["test", "--keep", &keep.display().to_string()], &[&path]);
    assert_eq!(out.status.code(), Some(1));
    let line = format!(
        "end expectation TreeCount(4): the number of trees: expected 4, actual 3; recording: {}",
        keep.join("plant.jsonl").display()
    );
    assert!(text(&out).0.contains(&line), "{}", text(&out).0);
    assert!(doc.contains("end expectation TreeCount(4): the number of trees: expected 4, actual 3; recording: target/grove-test/plant.jsonl"), "the document shows that line");
}

/// Files that are not scenarios, or ask for too much, are refused with one line before anything
/// runs, in bounded time.
#[test]
fn hostile_scenario_files_are_refused_quickly() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe.ron");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let huge = dir.path().join("huge.ron");
    std::fs::write(&huge, " ".repeat(5 << 20)).unwrap();
    let many = dir.path().join("many.ron");
    std::fs::write(&many, format!("Scenario(scene: \"study\", steps: [{}])", "Wait(1),".repeat(100_001))).unwrap();
    let deep = dir.path().join("deep.ron");
    std::fs::write(&deep, format!("Scenario(scene: \"study\", steps: [{}])", "Expect(".repeat(50_000))).unwrap();
    let sweep = dir.path().join("sweep.ron");
    std::fs::write(&sweep, "Scenario(scene: \"study\", steps: [Sweep(from: Point(0.0, 0.0, 0.0), by: (0.0, 0.0, 0.0), count: 18446744073709551615)])").unwrap();
    let nan = dir.path().join("nan.ron");
    std::fs::write(&nan, "Scenario(scene: \"study\", steps: [PointAt(Point(NaN, 0.0, 0.0))])").unwrap();
    let outside = dir.path().join("outside.ron");
    std::fs::write(&outside, "Scenario(scene: \"../../../../../../etc/passwd\", steps: [])").unwrap();
    let cases: [(&Path, &str); 8] = [
        (&fifo, "not a regular file"),
        (Path::new("/dev/zero"), "not a regular file"),
        (&huge, "larger than the limit"),
        (&many, "more than the limit of 100000"),
        (&deep, "line 1"),
        (&sweep, "more than the limit of 360000"),
        (&nan, "not a finite point"),
        (&outside, "does not end in .ron"),
    ];
    for (path, needle) in cases {
        let start = std::time::Instant::now();
        let out = grove_args(&["test"], &[path]);
        assert_one_line_error(&out, 2, needle);
        assert!(start.elapsed().as_secs_f64() < 2.0, "{}: refused in {:?}", path.display(), start.elapsed());
    }
}
