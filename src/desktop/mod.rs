//! The desktop app: `grove play` (a live session) and `grove view` (a replay viewer).
//!
//! - [`input_map`]: mouse, keyboard and gamepad → [`grove_systems::input::InputEvent`]s (pure).
//! - [`session`]: the fixed-step clock, per-tick input batches and the crash-safe recording.
//! - [`play_ui`]: the play UI (start menu, trees, mode switch, debug panel, help, task panel).
//! - [`viewer`]: the replay viewer's model (seeking re-simulates) and UI.
//! - [`world_view`]: a painter-drawn 3D view of the world, from the same camera as the ray.
//! - [`window`]: the winit + wgpu + egui window that runs a [`window::Frontend`].
//! - [`play`]: the play frontend.
//! - [`gpu`]: the wgpu renderer as the 3D view, and the tree thumbnails.
//! - [`egui_pass`]: the window's egui pass with a shader cheap on software rasterisers.
//!
//! Everything a user does reaches the world as input events, stamped with the tick they apply
//! at, so a recording of a live session replays to the same world hashes.

pub mod budget;
pub mod egui_pass;
mod error;
pub mod gpu;
pub mod input_map;
pub mod play;
pub mod play_ui;
pub mod scaled;
pub mod session;
pub mod stats;
mod surface;
pub mod viewer;
pub mod window;
pub mod world_view;

pub use error::DesktopError;
