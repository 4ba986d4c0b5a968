//! The water's extract: a copy of each `Water` component, sorted by entity.

use glam::Vec2;
use grove_systems::Sim;

/// One water body as the frame draws it (a copy of its `Water` component).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct WaterDraw {
    /// The outline, (X, Z) metres.
    pub polygon: Vec<Vec2>,
    /// The surface height, metres.
    pub height: f32,
    /// The deepest point below the surface, metres.
    pub depth: f32,
    /// The deep colour, linear RGB.
    pub colour: [f32; 3],
    /// Ripple strength, 0 = still.
    pub ripples: f32,
    /// Ripple drift, metres per second.
    pub ripple_speed: f32,
}

/// The world's water bodies, sorted by entity.
pub(crate) fn water_bodies(sim: &Sim) -> Vec<WaterDraw> {
    sim.water_bodies()
        .into_iter()
        .map(|(_, w)| WaterDraw {
            polygon: w.polygon,
            height: w.height,
            depth: w.depth,
            colour: w.colour,
            ripples: w.ripples,
            ripple_speed: w.ripple_speed,
        })
        .collect()
}
