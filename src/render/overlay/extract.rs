//! The overlay's extract: the interaction visuals' inputs (the controller, the hit marker, the
//! anchor ball, the selection and the running task's targets).

use glam::Quat;
use grove_systems::Sim;
use grove_systems::components::HitTarget;

use super::geometry::{OverlayAnchor, OverlayController, OverlayHit, OverlayScene, OverlaySelection, OverlayTarget};

/// The interaction visuals' inputs: the controller, the hit marker, the anchor ball, the
/// selection and the running task's targets.
pub fn overlay_scene(sim: &Sim) -> OverlayScene {
    // A world without a hit marker, an anchor ball or a selection reads as their defaults,
    // which draw nothing (invisible, no tree).
    let h = sim.hit_marker();
    let hit = Some(OverlayHit {
        visible: h.visible,
        distance: h.distance,
        position: h.position,
        normal: h.normal,
        on_water: matches!(h.target, HitTarget::Water(_)),
    });
    let controllers = sim
        .controller()
        .into_iter()
        .map(|c| OverlayController {
            origin: c.ray_origin(),
            dir: c.ray_dir(),
            rotation: c.pose.rotation,
            trigger: c.buttons.trigger,
            bumper: c.buttons.bumper,
            touchpad_pressed: c.buttons.touchpad,
            touchpad: c.touchpad,
        })
        .collect();
    let a = sim.anchor_ball();
    let anchors =
        vec![OverlayAnchor { visible: a.visible, armed: a.armed, position: a.position, distance: a.distance }];
    let selections = Some(sim.selection())
        .into_iter()
        .filter(|s| s.tree.is_some())
        .map(|s| OverlaySelection {
            center: s.center,
            rotation: Quat::from_rotation_y(s.yaw),
            half_extents: s.half_extents,
        })
        .collect();
    let (targets, tolerance) = match sim.task() {
        Some(task) => (
            task.def
                .targets
                .iter()
                .enumerate()
                .map(|(i, t)| OverlayTarget {
                    position: t.position,
                    done: task.satisfied.get(i).is_some_and(|s| s.is_some()),
                })
                .collect(),
            task.def.tolerance,
        ),
        None => (Vec::new(), 0.0),
    };
    OverlayScene {
        controllers,
        hit,
        anchors,
        selections,
        targets,
        target_tolerance: tolerance,
        max_ray_length: sim.config().max_ray_length,
        handle_radius: sim.config().handle_radius,
        eye: sim.head().pose.position,
        ghosts: Vec::new(),
    }
}
