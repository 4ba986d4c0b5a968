//! The systems, one per file. Each file's header lists what it reads and writes.
//! [`crate::schedule::step`] runs them in order.

pub mod input;
pub mod sun;
pub mod wind;
pub mod task;
pub mod raycast;
pub mod spawn;
pub mod plant_remove;
pub mod select;
pub mod handles;
pub mod touchpad;
pub mod drag;
pub mod selection_box;
