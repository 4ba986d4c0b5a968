//! Plant and remove system: Trigger on a plane plants (ray-casting mode); Bumper on a tree
//! removes it. Trigger on water plants nothing and logs a refused planting.
//!
//! Reads: `Resources::edges` (Trigger and Bumper going down), `Resources::mode`, `Resources::task`
//! (a room layout's scale),
//! `Resources::menu.current_model`, `HitMarker`, `Tree`, `Wind`, `Selection`.
//! Writes: new and despawned tree entities (through a command buffer), `Resources::rng` (the
//! new tree's wind phase), `Selection` (cleared if its tree is removed),
//! `Resources::interaction` (drag, handle drag or touchpad gesture on a removed tree ends),
//! `Resources::spatial` (marked dirty), `Resources::log` (planted, planting_refused, removed,
//! deselected).
//!
//! Planting happens only in ray-casting mode: the current model is placed upright (yaw 0,
//! scale 1, or a room layout's scale: `task::layout_scale`) with its base, the model origin,
//! exactly at the hit point, and is grounded. In
//! manual mode a Trigger on a plane does nothing here (the select system treats it as a click on
//! empty ground). Removal works in both modes, because manual mode has no other way to take a
//! tree away; Bumper on a plane, on a handle or on nothing does nothing.

use hecs::{CommandBuffer, World};

use crate::components::tree_components;
use crate::components::{HitMarker, HitTarget, Tree, Wind};
use crate::events::Happening;
use crate::interact;
use crate::mode::Mode;
use crate::resources::Resources;
use crate::single;

/// Runs the plant and remove system.
pub fn run(world: &mut World, res: &mut Resources) {
    if !res.edges.down.trigger && !res.edges.down.bumper {
        return;
    }
    let Some(hit) = single::get::<HitMarker>(world, &res.singles) else { return };
    if !hit.visible {
        return;
    }
    let tick = res.tick;
    let mut cmd = CommandBuffer::new();
    let mut changed = false;

    if res.edges.down.trigger && res.mode == Mode::RayCasting && matches!(hit.target, HitTarget::Plane(_)) {
        let model = res.menu.current_model;
        if res.catalogue.get(model).is_some() {
            let wind = single::get::<Wind>(world, &res.singles);
            let e = world.reserve_entity();
            cmd.insert(e, tree_components(&mut res.rng, wind.as_ref(), model, hit.position, 0.0, crate::task::layout_scale(res.task.as_ref()), true));
            res.log.push(tick, Happening::Planted { tree: e.to_bits().get(), model, position: hit.position });
            changed = true;
        }
    }

    if let (true, Mode::RayCasting, HitTarget::Water(water)) = (res.edges.down.trigger, res.mode, hit.target) {
        res.log.push(tick, Happening::PlantingRefused { water, position: hit.position });
    }

    if let (true, HitTarget::Tree(id)) = (res.edges.down.bumper, hit.target) {
        let model = interact::entity(id).and_then(|e| world.get::<&Tree>(e).ok().map(|t| (e, t.model)));
        if let Some((e, model)) = model {
            cmd.despawn(e);
            changed = true;
            res.log.push(tick, Happening::Removed { tree: id, model });
            let i = &mut res.interaction;
            if i.drag.is_some_and(|d| d.tree == id) {
                i.drag = None;
            }
            if i.touchpad.is_some_and(|g| g.tree == id) {
                i.touchpad = None;
            }
            if interact::selected_tree(world, &res.singles) == Some(id) {
                i.handle_drag = None;
                interact::set_selected(world, &res.singles, None);
                res.log.push(tick, Happening::Deselected);
            }
        }
    }

    if changed {
        cmd.run_on(world);
        res.spatial.mark_trees_dirty();
    }
}
