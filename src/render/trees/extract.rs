//! The trees' extract: every tree as the frame draws it (its model, pose, scale and wind
//! state); the photographed crowns' trees only when the canopy does not draw them.

use glam::{Vec2, Vec3};
use grove_systems::Sim;

use crate::render::feature::ExtractContext;

/// One tree as the frame draws it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TreeDraw {
    /// The catalogue model's index.
    pub model: usize,
    /// Base position, world metres.
    pub origin: Vec3,
    /// Rotation about +Y, radians.
    pub yaw: f32,
    /// Uniform scale.
    pub scale: f32,
    /// The trunk's lean, metres per metre of height (world X and Z); zero without a wind state.
    pub bend: Vec2,
    /// The wind's gain at the tree; zero without a wind state (the tree stands still).
    pub gain: f32,
    /// The tree's wind phase, radians.
    pub phase: f32,
}

/// The trees of the frame: the others in the world's order, then the photographed crowns'
/// (sorted by entity) unless the canopy draws them.
pub(crate) fn trees(sim: &Sim, cx: &ExtractContext<'_>) -> Vec<TreeDraw> {
    let mut trees = Vec::new();
    let mut crowns = Vec::new();
    sim.for_each_tree(|v| {
        // A tree without a wind state stands still: no bend and zero gain.
        let (bend, gain, phase) = v.wind.map_or((Vec2::ZERO, 0.0, 0.0), |w| (w.bend, w.gain, w.phase));
        let t = v.transform;
        let draw = TreeDraw {
            model: usize::from(v.model.0),
            origin: t.translation,
            yaw: t.yaw,
            scale: v.scale,
            bend,
            gain,
            phase,
        };
        match v.crown {
            Some(_) if cx.canopy => {}
            Some(_) => crowns.push((v.id, draw)),
            None => trees.push(draw),
        }
    });
    crowns.sort_by_key(|c| c.0);
    trees.extend(crowns.into_iter().map(|c| c.1));
    trees
}
