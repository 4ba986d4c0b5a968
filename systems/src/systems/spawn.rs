//! Spawn system: in manual mode, a model chosen from the menu appears in front of the head.
//!
//! Reads: `Resources::interaction.pending_spawn` (taken), `Resources::mode`, `Resources::config`
//! (`spawn_distance`, `spawn_drop`), `Resources::task` (a room layout's scale), `Head`, `Wind`.
//! Writes: a new tree entity (through a command buffer), `Resources::rng` (its wind phase),
//! `Selection` (the new tree is selected), `Resources::interaction.pending_spawn`,
//! `Resources::spatial` (marked dirty), `Resources::log` (planted, selected).
//!
//! The input system sets `pending_spawn` only when a model is chosen from an open menu in manual
//! mode and closes the menu, so each new tree needs the menu opened again. The tree appears
//! `spawn_distance` metres in front of the head (horizontally), `spawn_drop` metres below head
//! height, with yaw 0 and scale 1 (a room layout's scale: `task::layout_scale`), not grounded:
//! it has to be moved into place and snapped.
//! While a drag or a handle drag is in progress the spawn waits until it ends.

use hecs::{CommandBuffer, World};

use crate::components::tree_components;
use crate::components::{Head, Wind};
use crate::events::Happening;
use crate::interact;
use crate::mode::Mode;
use crate::resources::Resources;
use crate::single;

/// Runs the spawn system.
pub fn run(world: &mut World, res: &mut Resources) {
    // A tree held by a drag or a handle drag is let go first; the new tree waits until then.
    if res.interaction.drag.is_some() || res.interaction.handle_drag.is_some() {
        return;
    }
    let Some(model) = res.interaction.pending_spawn.take() else { return };
    if res.mode != Mode::Manual || res.catalogue.get(model).is_none() {
        return;
    }
    let Some(head) = single::get::<Head>(world, &res.singles) else { return };
    let tick = res.tick;
    let position = interact::spawn_point(&head.pose, res.config.spawn_distance, res.config.spawn_drop);
    let wind = single::get::<Wind>(world, &res.singles);

    let mut cmd = CommandBuffer::new();
    let e = world.reserve_entity();
    cmd.insert(e, tree_components(&mut res.rng, wind.as_ref(), model, position, 0.0, crate::task::layout_scale(res.task.as_ref()), false));
    cmd.run_on(world);
    res.spatial.mark_trees_dirty();

    let id = e.to_bits().get();
    res.log.push(tick, Happening::Planted { tree: id, model, position });
    interact::set_selected(world, &res.singles, Some(id));
    res.log.push(tick, Happening::Selected { tree: id });
}
