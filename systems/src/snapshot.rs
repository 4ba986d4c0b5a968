//! [`Snapshot`]: a typed, serializable copy of what a renderer and a task panel need from the
//! world at one tick (the WebAssembly module hands it to JavaScript as JSON, `web/sim`).
//!
//! Reads: trees (`Tree`, `Transform`, `Scale`, `Grounded`), `Controller`, `HitMarker`,
//! `AnchorBall`, `Selection`, `Head`, `Sun`, `Wind`, `WindState`, and the resources' tick, step,
//! time, mode, technique, menu, catalogue, task and config. Writes nothing.

use glam::{Quat, Vec3};
use serde::Serialize;

use crate::components::{AnchorBall, Controller, Grounded, Handle, HitMarker, HitTarget, Scale, Selection, Transform, Tree, WindState};
use crate::light::{sun_light, HAZE_DEPTH, HAZE_FULL_AT, HAZE_FULL_FROM, HAZE_START, NO_SUN};
use crate::wind_model::{Wind, WindParams};
use crate::hash::hex;
use crate::sim::Sim;

/// The world at one tick, as a renderer and a task panel read it. Positions are metres,
/// angles radians (names ending in `_deg` are degrees), rotations unit quaternions `[x, y, z, w]`;
/// entity ids are the entity's id bits, as recordings' checkpoints and the event log name them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Snapshot {
    /// Completed steps.
    pub tick: u64,
    /// The fixed step, seconds.
    pub dt: f32,
    /// The world hash (16 hex digits), as a checkpoint holds it.
    pub hash: String,
    /// The interaction mode of the active technique: "ray-casting" or "manual".
    pub mode: &'static str,
    /// The active technique's name (a built-in one's is its mode's).
    pub technique: String,
    /// Every tree, by ascending id.
    pub trees: Vec<TreeSnapshot>,
    /// The hand controller and its ray.
    pub controller: ControllerSnapshot,
    /// The head (the camera).
    pub head: PoseSnapshot,
    /// The head camera's vertical field of view, radians.
    pub fov_y: f32,
    /// The ball under a dragged tree.
    pub anchor_ball: AnchorSnapshot,
    /// The selected tree's bounding box, if a tree is selected.
    pub bounding_box: Option<BoxSnapshot>,
    /// The model menu.
    pub menu: MenuSnapshot,
    /// The task, if one was started.
    pub task: Option<TaskSnapshot>,
    /// The unit vector towards the sun, if the world has one.
    pub sun_direction: Option<[f32; 3]>,
    /// The light every drawing of this tick shares (the native renderer's and the page's).
    pub light: LightSnapshot,
    /// The per-vertex wind's parameters at this tick, as the native renderer's uniform holds
    /// them (`src/render/trees/wind.wgsl`; a calm wind where the world has none).
    pub wind: WindParams,
}

/// The sun's light as every drawing takes it: its direction (light from high in the south-east
/// where the world has no sun, [`crate::light::NO_SUN`]) and [`crate::light::sun_light`] of its
/// elevation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LightSnapshot {
    /// The unit vector towards the sun.
    pub sun_direction: [f32; 3],
    /// The sun's elevation, degrees.
    pub elevation_deg: f64,
    /// Direct sunlight, linear RGB times intensity (zero below the horizon).
    pub direct: [f32; 3],
    /// The sky's ambient light, linear RGB times strength.
    pub ambient: [f32; 3],
    /// The sky's brightness, 0..1.
    pub sky: f32,
    /// The aerial perspective's haze by distance, metres: start, depth, full from, full at
    /// ([`crate::light::HAZE_START`] and the others).
    pub haze: [f32; 4],
}

/// A tree's own state in the wind ([`crate::components::WindState`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TreeWindSnapshot {
    /// The trunk's lean: horizontal displacement per metre of height, world X and Z.
    pub bend: [f32; 2],
    /// The wind's gain at the tree.
    pub gain: f32,
    /// Its wind phase, radians.
    pub phase: f32,
}

/// One tree.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TreeSnapshot {
    /// Its entity id bits.
    pub id: u64,
    /// Its model's catalogue name.
    pub model: String,
    /// Its model's catalogue index.
    pub model_index: u8,
    /// The base of its trunk, metres.
    pub position: [f32; 3],
    /// Its heading: rotation about +Y, radians, counter-clockwise seen from above.
    pub yaw: f32,
    /// The same rotation as a quaternion `[x, y, z, w]`.
    pub rotation: [f32; 4],
    /// Its uniform scale.
    pub scale: f32,
    /// Whether it stands on a plane.
    pub grounded: bool,
    /// Whether it is the selected tree.
    pub selected: bool,
    /// Its state in the wind; `None` for a tree that stands still.
    pub wind: Option<TreeWindSnapshot>,
}

/// A position and a rotation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PoseSnapshot {
    /// Metres.
    pub position: [f32; 3],
    /// A unit quaternion `[x, y, z, w]`.
    pub rotation: [f32; 4],
}

/// The controller, its ray and what the ray hits.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ControllerSnapshot {
    /// The controller's pose.
    pub pose: PoseSnapshot,
    /// Where the ray starts, metres.
    pub ray_origin: [f32; 3],
    /// The ray's unit direction.
    pub ray_direction: [f32; 3],
    /// Buttons held: trigger, bumper, touchpad, menu.
    pub buttons: [bool; 4],
    /// The touchpad's thumb position, each axis in [−1, 1].
    pub touchpad: [f32; 2],
    /// What the ray hits; `None` when it hits nothing.
    pub hit: Option<HitSnapshot>,
}

/// Where the controller ray hits and what.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HitSnapshot {
    /// The hit point, metres.
    pub position: [f32; 3],
    /// The surface normal there.
    pub normal: [f32; 3],
    /// The distance from the ray's origin, metres.
    pub distance: f32,
    /// "plane", "tree", "handle" or "water".
    pub kind: &'static str,
    /// The entity hit (plane, tree or water), by id bits; `None` for a handle.
    pub entity: Option<u64>,
    /// A handle of the bounding box: "corner" or "edge" and its index.
    pub handle: Option<(&'static str, u8)>,
}

/// The anchor ball.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AnchorSnapshot {
    /// "hidden", "green" (too far above the ground to snap) or "white" (a release snaps).
    pub state: &'static str,
    /// Where it sits on the ground, metres.
    pub position: [f32; 3],
    /// From the dragged tree's lowest point down to the ground, metres.
    pub distance: f32,
}

/// The selected tree's oriented bounding box.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BoxSnapshot {
    /// The selected tree's id bits.
    pub tree: u64,
    /// The box's centre, metres.
    pub center: [f32; 3],
    /// Half its extents along its own axes, metres.
    pub half_extents: [f32; 3],
    /// Its rotation about +Y, radians.
    pub yaw: f32,
    /// Its 12 handles, where the ray grabs it: the 8 corners, then the midpoints of the 4
    /// vertical edges (`crate::interact::handle_points`).
    pub handles: Vec<HandleSnapshot>,
}

/// A handle of the bounding box.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HandleSnapshot {
    /// "corner" or "edge", as a hit on it names it.
    pub kind: &'static str,
    /// Its index among its kind's: a corner's bits are +X, +Y, +Z; an edge's +X, +Z.
    pub index: u8,
    /// Where it is, metres.
    pub position: [f32; 3],
}

fn handle_name(h: Handle) -> (&'static str, u8) {
    match h {
        Handle::Corner(i) => ("corner", i),
        Handle::Edge(i) => ("edge", i),
    }
}

/// The model menu.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MenuSnapshot {
    /// Whether it is open.
    pub open: bool,
    /// The model Trigger plants in ray-casting mode, by catalogue name.
    pub current_model: String,
    /// Every model of the catalogue, by name, in index order.
    pub models: Vec<String>,
}

/// The task.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TaskSnapshot {
    /// Its id, e.g. "ray-casting-7".
    pub id: String,
    /// The mode it is done in.
    pub mode: &'static str,
    /// How far a tree may stand from its target, metres.
    pub tolerance: f32,
    /// The scale of a room layout (`crate::room_layout`: the study as a scale model, new trees
    /// and handles at it), 1 for the task file's layout: what a page draws targets and handles at.
    pub layout_scale: f32,
    /// Its targets, in the task file's order.
    pub targets: Vec<TargetSnapshot>,
    /// How many targets are satisfied.
    pub satisfied: usize,
    /// Seconds on the task's clock: from its start to its end, or to now while it runs.
    pub clock_s: f64,
    /// Every target is satisfied.
    pub completed: bool,
    /// The clock has stopped (every target satisfied, or the task ended).
    pub done: bool,
}

/// One target of the task.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TargetSnapshot {
    /// Where a tree must stand, metres.
    pub position: [f32; 3],
    /// The required model's name.
    pub model: String,
    /// Whether a tree has satisfied it.
    pub satisfied: bool,
    /// The tree that satisfied it first, by id bits.
    pub tree: Option<u64>,
    /// Where it lies when the scene's ground has no plane at its height (a room without the
    /// study scene's terrace): the point on the plane below (`crate::task_layout`).
    pub moved_to: Option<[f32; 3]>,
}

fn quat(q: Quat) -> [f32; 4] {
    q.to_array()
}

fn v3(v: Vec3) -> [f32; 3] {
    v.to_array()
}

fn hit(m: &HitMarker) -> Option<HitSnapshot> {
    let (kind, entity, handle) = match m.target {
        HitTarget::None => return None,
        HitTarget::Plane(e) => ("plane", Some(e), None),
        HitTarget::Tree(e) => ("tree", Some(e), None),
        HitTarget::Water(e) => ("water", Some(e), None),
        HitTarget::Handle(h) => ("handle", None, Some(handle_name(h))),
    };
    if !m.visible {
        return None;
    }
    Some(HitSnapshot { position: v3(m.position), normal: v3(m.normal), distance: m.distance, kind, entity, handle })
}

impl Sim {
    /// The world as a renderer and a task panel read it ([`Snapshot`]).
    pub fn snapshot(&self) -> Snapshot {
        let (world, res) = (&self.world, &self.res);
        let model_name = |id: crate::catalogue::ModelId| res.catalogue.get(id).map_or_else(|| format!("#{}", id.0), |m| m.name.clone());
        let selection = world.query::<&Selection>().iter().next().copied().unwrap_or_default();
        let mut trees: Vec<TreeSnapshot> = world
            .query::<(hecs::Entity, &Tree, &Transform, &Scale, &Grounded, Option<&WindState>)>()
            .iter()
            .map(|(e, tree, t, s, g, w)| {
                let id = e.to_bits().get();
                TreeSnapshot {
                    id,
                    model: model_name(tree.model),
                    model_index: tree.model.0,
                    position: v3(t.translation),
                    yaw: t.yaw,
                    rotation: quat(t.rotation()),
                    scale: s.0,
                    grounded: g.0,
                    selected: selection.tree == Some(id),
                    wind: w.map(|w| TreeWindSnapshot { bend: w.bend.to_array(), gain: w.gain, phase: w.phase }),
                }
            })
            .collect();
        trees.sort_by_key(|t| t.id);
        let controller = world.query::<&Controller>().iter().next().copied().unwrap_or_default();
        let marker = world.query::<&HitMarker>().iter().next().copied().unwrap_or_default();
        let ball = world.query::<&AnchorBall>().iter().next().copied().unwrap_or_default();
        let head = self.head();
        let technique = res.techniques.at(res.technique);
        let moved = self.moved_targets();
        let task = res.task.as_ref().map(|t| {
            let now = t.end_tick().unwrap_or(res.tick);
            TaskSnapshot {
                id: t.def.id.clone(),
                mode: t.def.mode.name(),
                tolerance: t.def.tolerance,
                layout_scale: crate::task::layout_scale(Some(t)),
                targets: t
                    .def
                    .targets
                    .iter()
                    .zip(&t.satisfied)
                    .enumerate()
                    .map(|(i, (d, s))| TargetSnapshot {
                        position: v3(d.position),
                        model: d.model.clone(),
                        satisfied: s.is_some(),
                        tree: s.map(|h| h.tree),
                        moved_to: moved.iter().find(|m| m.target == i).map(|m| m.to),
                    })
                    .collect(),
                satisfied: t.satisfied.iter().filter(|s| s.is_some()).count(),
                clock_s: crate::task::ticks_to_seconds(now.saturating_sub(t.started_tick), res.dt),
                completed: t.is_complete(),
                done: t.end_tick().is_some(),
            }
        });
        Snapshot {
            tick: res.tick,
            dt: res.dt,
            hash: hex(self.hash().total),
            mode: res.mode.name(),
            technique: technique.name.to_string(),
            trees,
            controller: ControllerSnapshot {
                pose: PoseSnapshot { position: v3(controller.pose.position), rotation: quat(controller.pose.rotation) },
                ray_origin: v3(controller.ray_origin()),
                ray_direction: v3(controller.ray_dir()),
                buttons: [controller.buttons.trigger, controller.buttons.bumper, controller.buttons.touchpad, controller.buttons.menu],
                touchpad: controller.touchpad.to_array(),
                hit: hit(&marker),
            },
            head: PoseSnapshot { position: v3(head.pose.position), rotation: quat(head.pose.rotation) },
            fov_y: head.fov_y,
            anchor_ball: AnchorSnapshot {
                state: match (ball.visible, ball.armed) {
                    (false, _) => "hidden",
                    (true, false) => "green",
                    (true, true) => "white",
                },
                position: v3(ball.position),
                distance: ball.distance,
            },
            bounding_box: selection.tree.map(|tree| {
                let handles = crate::interact::handle_points(selection.center, selection.half_extents, selection.yaw);
                let handles = handles.iter().map(|&(h, p)| HandleSnapshot { kind: handle_name(h).0, index: handle_name(h).1, position: v3(p) }).collect();
                BoxSnapshot { tree, center: v3(selection.center), half_extents: v3(selection.half_extents), yaw: selection.yaw, handles }
            }),
            menu: MenuSnapshot {
                open: res.menu.open,
                current_model: model_name(res.menu.current_model),
                models: res.catalogue.models.iter().map(|m| m.name.clone()).collect(),
            },
            task,
            sun_direction: self.sun().map(|s| v3(s.direction)),
            light: self.light(),
            wind: WindParams::from_wind(&self.wind().unwrap_or_else(Wind::calm), self.time()),
        }
    }

    fn light(&self) -> LightSnapshot {
        let (dir, elevation_deg) = self.sun().map_or((NO_SUN.0.normalize(), NO_SUN.1), |s| (s.direction.normalize_or(Vec3::Y), s.elevation_deg));
        let l = sun_light(elevation_deg);
        let haze = [HAZE_START, HAZE_DEPTH, HAZE_FULL_FROM, HAZE_FULL_AT];
        LightSnapshot { sun_direction: v3(dir), elevation_deg, direct: v3(l.direct), ambient: v3(l.ambient), sky: l.sky, haze }
    }
}

impl Sim {
    /// The task's outcome as `grove replay` and `grove study` report it, if a task was started:
    /// measured up to now, and under a plug-in technique's name when one is active.
    pub fn task_report(&self) -> Option<crate::task::TaskReport> {
        let res = &self.res;
        let mut report = crate::task::TaskReport::new(res.task.as_ref()?, res.dt, res.tick, &res.catalogue);
        report.moved_targets = self.moved_targets();
        let technique = res.techniques.at(res.technique);
        if !technique.is_builtin() {
            report.mode = technique.name.to_string();
        }
        Some(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::{Pose, Selection};
    use crate::input::{Button, InputEvent};
    use crate::scene::Scene;

    fn study() -> Sim {
        Sim::from_scene(&Scene::builtin("study").unwrap(), 5).unwrap()
    }

    #[test]
    fn a_planted_tree_appears_selected_with_its_box_and_the_ray_hits_the_ground() {
        let mut sim = study();
        let before = sim.snapshot();
        assert_eq!(before.tick, 0);
        assert!(before.bounding_box.is_none() && before.task.is_none());
        assert_eq!(before.anchor_ball.state, "hidden");
        assert_eq!(before.hash, hex(sim.hash().total));
        let trees_before = before.trees.len();
        // Aim 4 m ahead at the ground, plant.
        let pose = Pose::looking_at(Vec3::new(0.0, 1.2, 0.0), Vec3::new(0.0, 0.0, -4.0));
        sim.step_with([InputEvent::ControllerPose { pose }]).unwrap();
        let aimed = sim.snapshot();
        let hit = aimed.controller.hit.clone().expect("the ray hits the ground");
        assert_eq!(hit.kind, "plane");
        assert!((hit.position[2] + 4.0).abs() < 0.5, "{hit:?}");
        sim.step_with([InputEvent::ButtonDown { button: Button::Trigger }]).unwrap();
        sim.step_with([InputEvent::ButtonUp { button: Button::Trigger }]).unwrap();
        sim.run(2);
        let after = sim.snapshot();
        assert_eq!(after.trees.len(), trees_before + 1, "{:?}", after.trees);
        let new = after.trees.iter().find(|t| !before.trees.iter().any(|b| b.id == t.id)).unwrap();
        assert!((new.position[2] + 4.0).abs() < 0.5 && new.grounded, "{new:?}");
        assert_eq!(new.model, after.menu.current_model);
        assert_eq!(after.tick, 5);
        assert_ne!(after.hash, before.hash);
    }

    #[test]
    fn the_selected_tree_s_box_has_its_handles_at_its_corners_and_edges() {
        let mut sim = study();
        let tree = 12345;
        let (c, h, yaw) = ([1.0f32, 2.0, 3.0], [0.5f32, 1.0, 0.25], 0.5f32);
        sim.set_up().selection(Selection { tree: Some(tree), center: Vec3::from(c), half_extents: Vec3::from(h), yaw });
        let b = sim.snapshot().bounding_box.expect("a tree is selected");
        assert_eq!(b.tree, tree);
        assert_eq!(b.handles.len(), 12);
        // Turned by the yaw about +Y (counter-clockwise seen from above) around the centre.
        let (s, co) = (yaw.sin(), yaw.cos());
        let at = |x: f32, y: f32, z: f32| [c[0] + co * x + s * z, c[1] + y, c[2] - s * x + co * z];
        let near = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(p, q)| (p - q).abs() < 1e-5);
        assert_eq!((b.handles[0].kind, b.handles[0].index), ("corner", 0));
        assert!(near(b.handles[0].position, at(-h[0], -h[1], -h[2])), "{:?}", b.handles[0]);
        assert_eq!((b.handles[7].kind, b.handles[7].index), ("corner", 7));
        assert!(near(b.handles[7].position, at(h[0], h[1], h[2])), "{:?}", b.handles[7]);
        assert_eq!((b.handles[9].kind, b.handles[9].index), ("edge", 1));
        assert!(near(b.handles[9].position, at(h[0], 0.0, -h[2])), "the edges at the centre's height: {:?}", b.handles[9]);
    }

    #[test]
    fn the_task_panel_counts_targets_and_runs_its_clock() {
        let mut sim = study();
        sim.step_with([InputEvent::StartTask { task: "ray-casting-7".into(), layout: None }]).unwrap();
        sim.run(60);
        let s = sim.snapshot();
        let task = s.task.expect("a task");
        assert_eq!((task.id.as_str(), task.mode, task.targets.len()), ("ray-casting-7", "ray-casting", 7));
        assert_eq!(task.satisfied, 0);
        assert!(!task.done && !task.completed);
        assert!((task.clock_s - 60.0 * s.dt as f64).abs() < 0.02, "{}", task.clock_s);
        sim.step_with([InputEvent::EndTask]).unwrap();
        sim.run(30);
        let ended = sim.snapshot().task.unwrap();
        assert!(ended.done && !ended.completed);
        assert!((ended.clock_s - 61.0 * s.dt as f64).abs() < 0.02, "{}", ended.clock_s);
    }
}
