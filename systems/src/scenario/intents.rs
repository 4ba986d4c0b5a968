//! The intent steps: `Plant`, `Remove` and `Drag` say what should come of them, play the
//! lower-level steps a participant would take, and fail, saying why, unless it did.
//!
//! Reads: what the steps' aims name ([`super::aims`]), the interaction log since the step began
//! (`planted`, `removed`, `snapped`, `released_green`, `planting_refused`), the drag in progress,
//! the anchor ball, the mode and the task's tolerance. Writes: input events only, through the
//! [`Script`], so an intent step runs the very ticks its lower-level steps would:
//!
//! | step | events | ticks |
//! |---|---|---|
//! | `Plant(model, at)` | choose the model; controller aimed at `at`; Trigger down, up | 4 |
//! | `Remove(tree)` | controller aimed at the tree's middle; Bumper down, up | 3 |
//! | `Drag(tree, to)` | controller aimed at the tree's middle; Trigger down; the controller carried, without turning, by the way from the tree's base to `to`, at most [`DRAG_STEP`] a tick; Trigger up; the controller back | 4 + the carry |

use glam::Vec3;

use crate::components::Pose;
use crate::events::Happening;
use crate::expect::{Ball, Expect};
use crate::input::{Button, InputEvent};
use crate::mode::Mode;
use crate::script::Script;
use crate::targets::{ground_distance, tree_middle, Aim, TreeRef};

use super::aims::{hold_checked, Aimed, RunState, GROUND_TOLERANCE};
use super::Btn;
use super::failed::StepFailed;

/// The farthest a dragged tree is carried in one tick, metres (a brisk arm: 12 m/s at 60 Hz).
pub const DRAG_STEP: f32 = 0.2;

/// The most ticks a drag's carry takes: longer ways are carried in bigger steps.
pub const MAX_CARRY_TICKS: u64 = 120;

/// The log entries written since `from`.
fn logged_since(s: &Script, from: usize) -> Vec<Happening> {
    s.sim().res.log.entries.get(from..).unwrap_or_default().iter().map(|e| e.what.clone()).collect()
}

fn tolerance(s: &Script) -> f32 {
    s.sim().res.task.as_ref().map_or(GROUND_TOLERANCE, |t| t.def.tolerance)
}

/// Aims at a point and notes the aim for the button step after it.
fn aim_at(s: &mut Script, state: &mut RunState, aim: &Aim, point: Vec3) {
    s.point_at(point);
    state.aimed = Some(Aimed::new(s.sim(), s.names(), aim, point));
}

/// `Plant(model: "…", at: AIM)`: choose, aim, press Trigger; fails unless a tree of that model
/// was planted within the task's tolerance (0.5 m without a task) of the aim.
pub fn plant(s: &mut Script, state: &mut RunState, model: &str, at: &Aim) -> Result<(), StepFailed> {
    if s.sim().res.mode != Mode::RayCasting {
        return Err(StepFailed::PlantInManual);
    }
    let point = s.aim_point(at)?;
    s.choose_model(model);
    aim_at(s, state, at, point);
    let from = s.sim().res.log.entries.len();
    let checked = hold_checked(s, state, Btn::Trigger);
    s.release(Button::Trigger);
    checked?;
    let within = tolerance(s);
    let planted: Vec<(u64, Vec3)> = logged_since(s, from)
        .into_iter()
        .filter_map(|h| match h {
            Happening::Planted { tree, position, .. } => Some((tree, position)),
            _ => None,
        })
        .collect();
    if logged_since(s, from).iter().any(|h| matches!(h, Happening::PlantingRefused { .. })) {
        return Err(StepFailed::OnWater(at.text()));
    }
    let Some(&(tree, position)) = planted.last() else { return Err(StepFailed::NothingPlanted) };
    let got = s.sim().tree(tree).and_then(|t| s.sim().res.catalogue.get(t.tree.model)).map(|m| m.name.clone()).unwrap_or_default();
    if got != model {
        return Err(StepFailed::WrongModel { got, model: model.to_string() });
    }
    let off = ground_distance(position, point);
    if off > within {
        return Err(StepFailed::TooFar { model: model.to_string(), off, at: at.text(), within });
    }
    Ok(())
}

/// `Remove(TREE)`: aim at the tree's middle, press Bumper; fails unless the tree is gone.
pub fn remove(s: &mut Script, state: &mut RunState, tree: &TreeRef) -> Result<(), StepFailed> {
    let id = s.tree_id(tree)?;
    let aim = Aim::Tree { tree: tree.clone(), offset: None };
    let point = tree_middle(s.sim(), id).unwrap_or_default();
    aim_at(s, state, &aim, point);
    let checked = hold_checked(s, state, Btn::Bumper);
    s.release(Button::Bumper);
    checked?;
    if s.sim().tree(id).is_some() {
        return Err(StepFailed::StillStands(tree.text()));
    }
    Ok(())
}

/// How many ticks, and how far each, a carry over `way` takes.
pub fn carry_ticks(way: Vec3) -> u64 {
    ((way.length() / DRAG_STEP).ceil() as u64).clamp(1, MAX_CARRY_TICKS)
}

/// `Drag(tree: TREE, to: AIM)`: grab the tree at its middle, carry the controller (without
/// turning it) by the way from the tree's base to the aim, so the tree's base comes to the aim,
/// release, and put the controller back; fails unless the tree snapped to the ground.
pub fn drag(s: &mut Script, state: &mut RunState, tree: &TreeRef, to: &Aim) -> Result<(), StepFailed> {
    let id = s.tree_id(tree)?;
    let goal = s.aim_point(to)?;
    let base = s.sim().tree(id).map_or(Vec3::ZERO, |t| t.transform.translation);
    let grab = tree_middle(s.sim(), id).unwrap_or(base);
    aim_at(s, state, &Aim::Tree { tree: tree.clone(), offset: None }, grab);
    let from = s.sim().res.log.entries.len();
    let start = s.controller().pose;
    hold_checked(s, state, Btn::Trigger)?;
    if s.sim().res.interaction.drag.is_none_or(|d| d.tree != id) {
        s.release(Button::Trigger);
        return Err(StepFailed::NotGrabbed(tree.text()));
    }
    let way = goal - base;
    let n = carry_ticks(way);
    for k in 1..=n {
        let pose = Pose { position: start.position + way * (k as f32 / n as f32), rotation: start.rotation };
        s.push(InputEvent::ControllerPose { pose }).wait(1);
    }
    let ball = Expect::AnchorBall(Ball::White).check(s.sim(), s.names());
    s.release(Button::Trigger);
    s.move_controller(start);
    state.aimed = None;
    let log = logged_since(s, from);
    if log.iter().any(|h| matches!(h, Happening::Snapped { tree, .. } if *tree == id)) {
        return Ok(());
    }
    let why = match ball {
        Err(m) => format!("the anchor ball was {} at the release", m.actual),
        Ok(()) => "the anchor ball was white, yet it did not snap".into(),
    };
    Err(StepFailed::NotSnapped { tree: tree.text(), to: to.text(), why })
}
