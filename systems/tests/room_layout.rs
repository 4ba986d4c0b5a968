//! A task started with `layout: room` (`grove_systems::room_layout`): its targets lie within the
//! floor the event carries, the task is done on them and reports the layout; without a layout the
//! event is written and hashed as before.

use glam::Vec2;
use glam::Vec3;
use grove_systems::Sim;
use grove_systems::input::{Button, InputEvent, InvalidEvent};
use grove_systems::room_layout::{EDGE_MARGIN_M, FloorError, TaskLayout, place};
use grove_systems::scene::{PlaneDef, PlaneShape, Scene};
use grove_systems::script::Script;
use grove_systems::task::TaskReport;

/// A 4 × 4 m room around the study's start (0, 6).
fn room() -> Vec<[f32; 2]> {
    vec![[-2.0, 3.0], [2.0, 3.0], [2.0, 7.0], [-2.0, 7.0]]
}

/// The study scene with a flat floor in place of its ground and no trees: a room as a headset's
/// page sends it.
fn room_scene() -> Scene {
    let mut scene = Scene::builtin("study").unwrap();
    let floor = PlaneShape::Grid {
        min: Vec2::new(-20.0, -14.0),
        size: Vec2::new(40.0, 40.0),
        cell: 2.0,
        elevation: 0.0,
        unevenness: 0.0,
        noise_seed: 0,
        holes: Vec::new(),
    };
    scene.planes = vec![PlaneDef { name: "floor".into(), shape: floor }];
    scene.trees.clear();
    scene
}

fn started(layout: Option<TaskLayout>) -> Script {
    let mut s = Script::new(Sim::from_scene(&room_scene(), 3).unwrap());
    s.push(InputEvent::StartTask { task: "ray-casting-7".into(), layout }).wait(1);
    s
}

fn report(s: &Script) -> TaskReport {
    let sim = s.sim();
    TaskReport::new(sim.task().unwrap(), sim.dt(), sim.tick(), sim.catalogue())
}

#[test]
fn the_task_is_done_on_the_targets_laid_out_in_the_room() {
    let mut s = started(Some(TaskLayout::Room { floor: room(), keep_out: vec![] }));
    let targets: Vec<(Vec3, String)> =
        s.sim().task().unwrap().def.targets.iter().map(|t| (t.position, t.model.clone())).collect();
    let file: Vec<Vec3> =
        grove_systems::task::TaskDef::builtin("ray-casting-7").unwrap().targets.iter().map(|t| t.position).collect();
    let (placed, placement) = place(&file, &room(), &[]).unwrap();
    assert_eq!(targets.iter().map(|t| t.0).collect::<Vec<_>>(), placed);
    for (p, _) in &targets {
        assert!(
            p.x >= -2.0 + EDGE_MARGIN_M as f32
                && p.x <= 2.0 - EDGE_MARGIN_M as f32
                && p.z >= 3.5
                && p.z <= 6.5
                && p.y == 0.0,
            "{p}"
        );
    }
    // Plant each target's model on it from where the participant stands, the farthest first:
    // the trees are made at the layout's scale, so none covers another's target.
    let start = Vec3::new(0.0, 0.0, 6.0);
    let mut order: Vec<usize> = (0..targets.len()).collect();
    order.sort_by(|a, b| targets[*b].0.distance(start).total_cmp(&targets[*a].0.distance(start)));
    for i in order {
        s.choose_model(targets[i].1.as_str()).point_at(targets[i].0).press(Button::Trigger).wait(2);
    }
    let r = report(&s);
    assert!(r.completed, "{r:?}");
    let mut scales = Vec::new();
    s.sim().for_each_tree(|t| scales.push(t.scale));
    assert_eq!(
        scales.iter().filter(|x| **x == placement.scale).count(),
        7,
        "{scales:?}: the planted trees at the layout's scale"
    );
    assert_eq!(s.sim().task().unwrap().def.tolerance, 0.5 * placement.scale);
    assert_eq!(r.trees.len(), 7);
    assert_eq!(r.layout, Some(placement));
    assert!(r.moved_targets.is_empty(), "every target lies on the floor");
}

#[test]
fn in_the_manual_task_a_small_tree_is_grabbed_by_itself_not_its_handles_and_snaps_on_its_target() {
    let mut s = Script::new(Sim::from_scene(&room_scene(), 4).unwrap());
    s.push(InputEvent::SwitchMode { mode: grove_systems::mode::Mode::Manual });
    s.push(InputEvent::StartTask {
        task: "manual-7".into(),
        layout: Some(TaskLayout::Room { floor: room(), keep_out: vec![] }),
    })
    .wait(1);
    let target = s.sim().task().unwrap().def.targets[2].clone();
    s.choose_model(target.model.as_str());
    let snap = s.sim().snapshot();
    let b = snap.bounding_box.clone().expect("the new tree is selected");
    let tree = snap.trees.iter().find(|t| t.id == b.tree).unwrap().clone();
    assert!(tree.scale < 0.2 && !tree.grounded, "{tree:?}");
    s.point_at(Vec3::from(b.center));
    let hit = s.sim().snapshot().controller.hit.unwrap();
    assert_eq!(
        (hit.kind, hit.entity),
        ("tree", Some(b.tree)),
        "the handles, picked at the layout's scale, leave the tree's box free"
    );
    // Grab it and carry the controller so that the tree's base comes just above the target.
    s.hold(Button::Trigger);
    let from = s.controller().pose;
    let d = Vec3::new(target.position.x, 0.02, target.position.z) - Vec3::from(tree.position);
    for k in 1..=10 {
        s.move_controller(grove_systems::components::Pose {
            position: from.position + d * (k as f32 / 10.0),
            rotation: from.rotation,
        });
    }
    assert_eq!(s.sim().snapshot().anchor_ball.state, "white");
    s.release(Button::Trigger).wait(2);
    let after = s.sim().snapshot();
    assert!(after.trees.iter().find(|t| t.id == b.tree).unwrap().grounded);
    let task = after.task.unwrap();
    assert!(task.targets[2].satisfied);
    // The Scale pad (a phone's) grows and shrinks it within the bounds times the layout's scale,
    // never jumping to the full-size `min_scale`.
    assert_eq!(after.bounding_box.map(|b| b.tree), Some(b.tree), "still selected");
    let scale_of = |s: &Script| s.sim().snapshot().trees.iter().find(|t| t.id == b.tree).unwrap().scale;
    let cfg = s.sim().config().clone();
    s.scale_pad(0.5, 60);
    let want = tree.scale * 0.5f32.exp2();
    assert!((scale_of(&s) - want).abs() < 1e-5, "{} against {want}", scale_of(&s));
    s.scale_pad(1.0, 600);
    assert_eq!(scale_of(&s), cfg.max_scale * task.layout_scale);
    s.scale_pad(-1.0, 900);
    assert_eq!(scale_of(&s), cfg.min_scale * task.layout_scale);
    assert!(s.sim().snapshot().trees.iter().find(|t| t.id == b.tree).unwrap().grounded, "on the floor throughout");
}

#[test]
fn without_a_layout_the_task_file_holds_and_the_event_is_written_as_before() {
    let file = started(None);
    let laid = started(Some(TaskLayout::Room { floor: room(), keep_out: vec![] }));
    assert_eq!(report(&file).layout, None);
    assert_eq!(file.sim().task().unwrap().def, grove_systems::task::TaskDef::builtin("ray-casting-7").unwrap());
    assert_ne!(file.sim().hash().total, laid.sim().hash().total, "the layout is part of the task's state");
    let plain = serde_json::to_string(&InputEvent::StartTask { task: "manual-7".into(), layout: None }).unwrap();
    assert_eq!(plain, r#"{"kind":"start_task","task":"manual-7"}"#);
    let event = InputEvent::StartTask {
        task: "manual-7".into(),
        layout: Some(TaskLayout::Room { floor: vec![[0.0, 0.0], [1.5, 0.0], [1.5, 2.0]], keep_out: vec![] }),
    };
    let text = serde_json::to_string(&event).unwrap();
    assert_eq!(
        text,
        r#"{"kind":"start_task","task":"manual-7","layout":{"room":{"floor":[[0.0,0.0],[1.5,0.0],[1.5,2.0]]}}}"#
    );
    assert_eq!(serde_json::from_str::<InputEvent>(&text).unwrap(), event);
    let bad: InputEvent =
        serde_json::from_str(r#"{"kind":"start_task","task":"manual-7","layout":{"room":{"floor":[[0,0],[1,0]]}}}"#)
            .unwrap();
    assert_eq!(bad.validate(), Err(InvalidEvent::Layout(FloorError::Points(2))));
}

#[test]
fn a_floor_without_room_for_the_margin_keeps_the_task_file() {
    let s = started(Some(TaskLayout::Room {
        floor: vec![[0.0, 0.0], [0.8, 0.0], [0.8, 3.0], [0.0, 3.0]],
        keep_out: vec![],
    }));
    assert_eq!(report(&s).layout, None);
    assert_eq!(s.sim().task().unwrap().def, grove_systems::task::TaskDef::builtin("ray-casting-7").unwrap());
}
