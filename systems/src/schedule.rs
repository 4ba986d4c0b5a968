//! The schedule: the one place that says which systems run, and in which order.
//!
//! One call of [`step`] is one fixed step of `Resources::dt` seconds:
//!
//! 1. `input`: apply this tick's input events to the controller, head, buttons and UI state.
//! 2. `sun`: advance the sun's clock and direction.
//! 3. `wind`: advance the gust and every tree's bend.
//! 4. `task`: check targets and measure the running task.
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
    systems::task::run(world, res);
    res.tick += 1;
}
