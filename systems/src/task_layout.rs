//! Where a task's targets lie on the scene's ground: a target stands on a plane of the scene at
//! its own height, or, where the scene has no such plane (a room found by a headset has a floor
//! but not the study scene's terrace at 0.8 m), it is moved straight down onto the plane below.
//!
//! The task's own check is unchanged by this (a target counts its horizontal distance only, and a
//! tree on the floor below is grounded): the layout says where a page draws a target and tells
//! reports that a trial's targets were not all where the task file puts them. It is a pure
//! function of the scene's planes and the task, so a replay of a recording (whose header names
//! both) finds the same layout.
//!
//! Reads: `Resources::task`, `Resources::spatial` (the planes). Writes nothing.

use glam::Vec3;

use crate::sim::Sim;
pub use crate::task::MovedTarget;

/// How far above or below a target a plane may lie and still be the plane the target stands on,
/// metres.
pub const ON_PLANE_M: f32 = 0.3;

/// Where a target at `p` lies on the ground that `below` finds (the plane hit straight down from a
/// point): `None` when a plane lies within [`ON_PLANE_M`] of its height (it stays) or no plane
/// lies below it at all (nothing to move it onto); else the point on the plane below.
pub fn moved_onto(p: Vec3, below: impl Fn(Vec3, f32) -> Option<Vec3>) -> Option<Vec3> {
    let hit = below(p, ON_PLANE_M)?;
    if hit.y >= p.y - ON_PLANE_M {
        return None;
    }
    Some(hit)
}

impl Sim {
    /// The running task's targets that the scene's ground moves ([`moved_onto`]), in target
    /// order; empty without a task or when every target lies on a plane at its height.
    pub fn moved_targets(&self) -> Vec<MovedTarget> {
        let Some(task) = self.res.task.as_ref() else { return Vec::new() };
        let spatial = &self.res.spatial;
        task.def
            .targets
            .iter()
            .enumerate()
            .filter_map(|(i, t)| {
                let to = moved_onto(t.position, |p, lift| spatial.ground_below(p, lift).map(|h| h.point))?;
                Some(MovedTarget { target: i, from: t.position.to_array(), to: to.to_array() })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::InputEvent;
    use crate::scene::{PlaneDef, PlaneShape, Scene};

    fn started(scene: &Scene) -> Sim {
        let mut sim = Sim::from_scene(scene, 1).unwrap();
        sim.step_with([InputEvent::StartTask { task: "ray-casting-7".into(), layout: None }]).unwrap();
        sim
    }

    #[test]
    fn every_target_of_the_study_lies_on_a_plane_of_the_study_scene() {
        let sim = started(&Scene::builtin("study").unwrap());
        assert_eq!(sim.task().unwrap().def.targets.len(), 7);
        assert_eq!(sim.moved_targets(), Vec::new());
    }

    #[test]
    fn a_room_with_only_a_floor_moves_the_terrace_target_onto_it() {
        let mut scene = Scene::builtin("study").unwrap();
        let floor = PlaneShape::Grid { min: glam::Vec2::new(-20.0, -20.0), size: glam::Vec2::new(40.0, 40.0), cell: 2.0, elevation: -0.05, unevenness: 0.0, noise_seed: 0, holes: Vec::new() };
        scene.planes = vec![PlaneDef { name: "floor".into(), shape: floor }];
        scene.trees.clear();
        let sim = started(&scene);
        let moved = sim.moved_targets();
        assert_eq!(moved.len(), 1, "{moved:?}");
        assert_eq!(moved[0].target, 6);
        assert_eq!(moved[0].from, [10.0, 0.8, -11.0]);
        assert!((moved[0].to[0] - 10.0).abs() < 1e-4 && (moved[0].to[2] + 11.0).abs() < 1e-4, "{moved:?}");
        assert!((moved[0].to[1] + 0.05).abs() < 1e-4, "{moved:?}");
    }

    #[test]
    fn a_target_over_no_plane_or_near_one_stays() {
        let stays = |y: f32, ground: Option<f32>| moved_onto(Vec3::new(1.0, y, 2.0), |p, lift| ground.filter(|g| *g <= p.y + lift).map(|g| Vec3::new(p.x, g, p.z)));
        assert_eq!(stays(0.8, None), None);
        assert_eq!(stays(0.8, Some(0.6)), None);
        assert_eq!(stays(0.0, Some(0.25)), None);
        assert_eq!(stays(0.8, Some(0.0)), Some(Vec3::new(1.0, 0.0, 2.0)));
    }
}
