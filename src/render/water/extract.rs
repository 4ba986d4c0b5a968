//! The water's extract: a copy of each `Water` component, sorted by entity.

use glam::Vec2;
use grove_systems::water::Water;
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
    let mut w: Vec<(u64, WaterDraw)> = sim
        .world()
        .query::<(hecs::Entity, &Water)>()
        .iter()
        .map(|(e, w)| {
            let draw = WaterDraw { polygon: w.polygon.clone(), height: w.height, depth: w.depth, colour: w.colour, ripples: w.ripples, ripple_speed: w.ripple_speed };
            (e.to_bits().get(), draw)
        })
        .collect();
    w.sort_by_key(|(e, _)| *e);
    w.into_iter().map(|(_, d)| d).collect()
}

