//! Wind system: advances the gust function and every tree's bend.
//!
//! Reads: `Resources::tick`, `Resources::dt`, `Wind`, `Transform`, `WindState` (phase, gain).
//! Writes: `Wind::current`, `WindState::bend`, and `WindState::gain` / `gain_at` for trees that
//! moved (or all trees when the wind's density changed).
//!
//! The per-tree work is a few multiplies and one polynomial sine, with no allocation, so that
//! a million trees take a few milliseconds. The sine is a fixed polynomial rather than the
//! platform's `sin`, so the result is the same bit pattern everywhere.

use glam::{Vec2, Vec3};
use hecs::World;

use crate::components::{Transform, Wind, WindState};
use crate::resources::Resources;
use crate::single;

pub use crate::wind_model::{det_sin, gust_at, gust_shape, max_bend, position_gain, tree_bend};

/// Runs the wind system.
pub fn run(world: &mut World, res: &mut Resources) {
    let t = res.time();
    let mut wind = None;
    single::for_each_mut::<Wind>(world, &res.singles, |w| {
        w.current = gust_at(&w.gust, t);
        wind = Some(*w);
    });
    let Some(w) = wind else { return };
    let dir = Vec2::new(w.direction.x, w.direction.z);
    // Reduce time to one period of the 0.5 Hz oscillation (2 s) in f64 first, so f32 keeps
    // its precision however long the session runs.
    let tf = crate::wind_model::exact::rem_2(t) as f32;
    for (tr, ws) in world.query_mut::<(Option<&Transform>, &mut WindState)>() {
        if let Some(tr) = tr {
            // The gain is a function of position: recompute it only when the tree has moved
            // or the wind's density has changed, so the per-tick cost stays a few multiplies.
            let key = Vec3::new(tr.translation.x, tr.translation.z, w.density);
            if key != ws.gain_at {
                ws.gain = position_gain(tr.translation, w.density);
                ws.gain_at = key;
            }
        }
        ws.bend = tree_bend(dir, w.strength, w.current, ws.gain, ws.phase, tf);
    }
}
