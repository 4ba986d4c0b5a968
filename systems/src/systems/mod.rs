//! The systems, one per file. Each file's header lists what it reads and writes.
//! [`crate::schedule::step`] runs them in order.

pub mod input;
pub mod sun;
pub mod wind;
pub mod task;
