//! Select system: a Trigger press on a tree selects it and grabs it for dragging; on a
//! bounding-box handle it grabs the handle; on empty ground it clears the selection.
//!
//! Reads: `Resources::edges` (Trigger going down), `Resources::mode`, `HitMarker`, `Selection`,
//! `Tree`, `Transform`, `Scale`.
//! Writes: `Selection` (which tree), `Resources::interaction` (drag, handle drag),
//! `Resources::log` (selected, deselected).
//!
//! - On a tree: the tree becomes the selection (Selected is logged when the selection changes)
//!   and a drag starts at the hit distance, keeping the offset from the hit point to the tree's
//!   origin. The drag system moves the tree only once the ray moves, so a click selects without
//!   moving.
//! - On a handle of the selected tree: a handle drag starts at the hit distance, remembering
//!   the tree's scale and yaw and the hit point's horizontal distance and angle around the
//!   tree's vertical axis (through its origin).
//! - On nothing, or on a plane in manual mode: the selection is cleared (Deselected is logged
//!   if there was one). In ray-casting mode a plane hit plants instead (plant_remove system) and
//!   leaves the selection as it is.

use hecs::World;

use crate::components::{HitMarker, HitTarget, Scale, Transform, Tree};
use crate::events::Happening;
use crate::interact;
use crate::mode::Mode;
use crate::resources::{Drag, HandleDrag, Resources};
use crate::single;

/// Runs the select system.
pub fn run(world: &mut World, res: &mut Resources) {
    if !res.edges.down.trigger || res.interaction.drag.is_some() || res.interaction.handle_drag.is_some() {
        return;
    }
    let Some(hit) = single::get::<HitMarker>(world, &res.singles) else { return };
    let tick = res.tick;
    let selected = interact::selected_tree(world, &res.singles);
    let empty = match hit.target {
        _ if !hit.visible => true,
        HitTarget::None => true,
        // Water counts as ground here: in ray-casting mode the refusal (plant_remove system)
        // leaves the selection as it is.
        HitTarget::Plane(_) | HitTarget::Water(_) => res.mode == Mode::Manual,
        HitTarget::Tree(id) => {
            let Some(e) = interact::entity(id).filter(|&e| world.satisfies::<&Tree>(e)) else { return };
            let Ok(t) = world.get::<&Transform>(e).map(|t| *t) else { return };
            if selected != Some(id) {
                interact::set_selected(world, &res.singles, Some(id));
                res.log.push(tick, Happening::Selected { tree: id });
            }
            res.interaction.drag = Some(Drag {
                tree: id,
                grab_distance: hit.distance,
                offset: t.translation - hit.position,
                moved: false,
            });
            false
        }
        HitTarget::Handle(handle) => {
            let Some(e) = selected.and_then(interact::entity) else { return };
            let (Ok(t), Ok(s)) = (world.get::<&Transform>(e).map(|t| *t), world.get::<&Scale>(e).map(|s| *s)) else {
                return;
            };
            res.interaction.handle_drag = Some(HandleDrag {
                handle,
                start_scale: s.0,
                start_yaw: t.yaw,
                start_radius: interact::horizontal_radius(hit.position, t.translation),
                start_angle: interact::angle_around(hit.position, t.translation),
                grab_distance: hit.distance,
            });
            false
        }
    };
    if empty && selected.is_some() {
        interact::set_selected(world, &res.singles, None);
        res.log.push(tick, Happening::Deselected);
    }
}
