//! Selection box system: keeps the `Selection` box on the selected tree.
//!
//! Reads: `Selection` (which tree), `Tree`, `Transform`, `Scale`, `Resources::catalogue`.
//! Writes: `Selection` (centre, half extents, yaw; cleared if the tree is gone),
//! `Resources::interaction.handle_drag` (ends if the tree is gone), `Resources::log`
//! (deselected, if the tree is gone).
//!
//! The box is the tree's catalogue bounds, scaled and turned with the tree: the same box the
//! spatial index and the handles use. Only the one selected tree is looked at.

use glam::Vec3;
use hecs::World;

use crate::components::Selection;
use crate::events::Happening;
use crate::interact;
use crate::resources::Resources;
use crate::single;

/// Runs the selection box system.
pub fn run(world: &mut World, res: &mut Resources) {
    let Some(id) = interact::selected_tree(world, &res.singles) else { return };
    let b = interact::entity(id).and_then(|e| interact::tree_box_of(world, &res.catalogue, &res.boxes, e));
    // Most ticks the tree has not moved: the selection holds this very box already (bit for
    // bit), and writing it again would change nothing.
    let bits =
        |c: Vec3, h: Vec3, yaw: f32| (c.to_array().map(f32::to_bits), h.to_array().map(f32::to_bits), yaw.to_bits());
    if let Some(b) = b
        && single::get_single::<Selection>(world, &res.singles)
            .is_some_and(|s| bits(s.center, s.half_extents, s.yaw) == bits(b.center, b.half_extents, b.yaw))
    {
        return;
    }
    single::for_each_mut::<Selection>(world, &res.singles, |s| match b {
        Some(b) => {
            s.center = b.center;
            s.half_extents = b.half_extents;
            s.yaw = b.yaw;
        }
        None => *s = Selection::default(),
    });
    if b.is_none() {
        res.interaction.handle_drag = None;
        res.log.push(res.tick, Happening::Deselected);
    }
}
