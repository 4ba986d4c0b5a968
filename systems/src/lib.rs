//! grove-systems: the headless, deterministic simulation of the grove tree-planting study.
//!
//! Trees, ground planes, the sun, the wind, the controller, the head, the hit marker, the anchor
//! ball and the selection are hecs entities ([`components`]). Everything else lives in
//! [`resources::Resources`]. Input reaches the simulation only as [`input::InputEvent`]s; the
//! [`schedule`] runs the [`systems`] in a fixed order once per fixed step; [`hash::world_hash`]
//! checkpoints the state.
//!
//! Units and axes for the whole crate: metres, radians (unless a name ends in `_deg`), seconds;
//! right-handed, +Y up, −Z north, +X east; azimuths clockwise from north.
//!
//! This crate knows nothing about GPUs, windows or UI toolkits, and reads no clock: the same
//! input gives the same world hash in debug and release builds and on any machine.

#![warn(missing_docs)]

pub mod aerial;
pub mod bank;
pub mod catalogue;
pub mod components;
pub mod error;
pub mod events;
pub mod expect;
pub mod files;
pub mod grass;
pub mod hash;
pub mod holes;
pub mod input;
pub mod interact;
pub mod known_techniques;
pub mod light;
pub mod limits;
pub mod lookup;
mod message_error;
pub mod mode;
mod plane_geometry;
pub mod plane_grid;
pub mod replay;
pub mod scatter;
pub mod resource_hash;
pub mod resources;
pub mod room;
pub mod room_layout;
pub mod scenario;
pub mod scene;
pub mod scene_text;
pub mod set_arg;
pub mod setup;
pub mod schedule;
pub mod script;
pub mod sim;
pub mod single;
pub mod snapshot;
pub mod spatial;
pub mod stage;
pub mod systems;
pub mod targets;
pub mod task;
pub mod task_layout;
pub mod technique;
pub mod tree_def;
pub mod view;
pub mod water;
pub mod wind_model;
pub mod wgsl_struct;

pub use error::Error;
pub use sim::Sim;
