//! The schedule: the one place that says which systems run, and in which order.
//!
//! One call of [`step`] is one fixed step of `Resources::dt` seconds:
//!
//! 1. `input`: apply this tick's input events to the controller, head, buttons and UI state.
//! 2. `sun`: advance the sun's clock and direction.
//! 3. `wind`: advance the gust and every tree's bend.
//! 4. `raycast`: cast the controller ray; move the hit marker to the nearest hit.
//! 5. `spawn`: in manual mode, a model chosen from the menu appears in front of the head.
//! 6. `plant_remove`: Trigger on a plane plants (ray-casting mode); Bumper on a tree removes it.
//! 7. `select`: Trigger on a tree selects and grabs it, on a handle grabs the handle, on empty
//!    ground deselects.
//! 8. `handles`: a grabbed corner handle scales, an edge handle rotates the selected tree.
//! 9. `touchpad`: moves and turns the selected tree.
//! 10. `drag`: a grabbed tree follows the ray; the anchor ball; snap on release.
//! 11. `selection_box`: keep the selection box on the selected tree.
//! 12. `task`: check targets and measure the running task.
//!
//! Then the tick counter advances. Systems run one after another on one thread; nothing in a
//! tick depends on thread timing or the wall clock.

use hecs::World;

use crate::resources::Resources;
use crate::systems;

/// Runs one fixed step: every system in order, then `tick += 1`.
pub fn step(world: &mut World, res: &mut Resources) {
    systems::input::run(world, res);
    systems::sun::run(world, res);
    systems::wind::run(world, res);
    systems::raycast::run(world, res);
    systems::spawn::run(world, res);
    systems::plant_remove::run(world, res);
    systems::select::run(world, res);
    systems::handles::run(world, res);
    systems::touchpad::run(world, res);
    systems::drag::run(world, res);
    systems::selection_box::run(world, res);
    systems::task::run(world, res);
    res.tick += 1;
}
