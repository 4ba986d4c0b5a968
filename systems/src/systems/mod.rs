//! The systems, one per file. Each file's header lists what it reads and writes.
//! [`crate::schedule::step`] runs them in order.

pub mod drag;
pub mod handles;
pub mod input;
pub mod plant_remove;
pub mod raycast;
pub mod scale_pad;
pub mod select;
pub mod selection_box;
pub mod spawn;
pub mod sun;
pub mod task;
pub mod touchpad;
pub mod wind;
