//! Clipmaps of aerial photographs (Tanner et al. 1998; Ropinski et al. 2007), issue #22.
//!
//! A clipmap is a stack of `levels` square textures of `size` × `size` texels. Level 0 holds
//! the finest texels around the place the camera looks at; each level above covers twice the
//! ground at half the resolution. As the camera moves, each level's window slides over its
//! level of a tiled mip pyramid on disk, and only the newly exposed rows and columns are
//! written: a texel of the window at pyramid texel `(u, v)` is stored at `(u mod size,
//! v mod size)` (toroidal addressing), so a repeating sampler reads the window as it is.
//!
//! The work is split in two halves that meet in the types of this file:
//!
//! - the CPU half (the pyramid reader in `src/aerial/tiles/`, the placement of the levels,
//!   the toroidal bookkeeping and the background loader thread) implements
//!   [`ClipmapSource`]: each frame it says where every level lies and which texels to write,
//!   and never waits on disk;
//! - the GPU half (a texture array of `levels` layers, the uniform of placements, the WGSL
//!   that samples the finest loaded level at a ground point) applies a [`ClipmapFrame`].
//!
//! Axes: world X is east and world Z is south (image x and image y), metres, Y up. The
//! pyramid's texel `(0, 0)` of mip 0 has its top-left corner at [`AerialPlacement::origin_m`].

pub mod loader;
pub mod place;
pub mod stream;
pub mod toroid;

#[cfg(test)]
mod stream_tests;

pub use stream::{Clipmap, ClipmapStats};

use glam::{DVec2, DVec3, IVec2};

/// How many levels a clipmap has and how many texels a level's side holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClipmapConfig {
    /// The number of levels, 1..=16.
    pub levels: u32,
    /// Texels per level side: a power of two, 16..=4096.
    pub size: u32,
}

/// Where a photograph lies on the ground.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AerialPlacement {
    /// World (X, Z) of the top-left corner of the photograph's texel (0, 0), metres.
    pub origin_m: DVec2,
    /// Ground sample distance of mip 0: metres per texel.
    pub gsd_m: f64,
}

/// The camera as the clipmap sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipCamera {
    /// The eye, world metres.
    pub eye: DVec3,
    /// The view direction, a unit vector.
    pub forward: DVec3,
    /// The vertical field of view, radians.
    pub fov_y: f64,
    /// Width over height of the view.
    pub aspect: f64,
}

/// Where one clipmap level lies this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelPlacement {
    /// The pyramid mip this level shows: its texels are `gsd_m · 2^mip` metres wide.
    pub mip: u32,
    /// The window's top-left texel in that mip's texel coordinates (it may lie partly
    /// outside the photograph; texels outside it are written transparent).
    pub origin: IVec2,
}

/// Texels to write into one level's toroidal texture.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Upload {
    /// The clipmap level (the texture array layer).
    pub level: u32,
    /// The rectangle's top-left texel in the level's texture (already wrapped: `x + w` and
    /// `y + h` are at most the level size).
    pub x: u32,
    /// See `x`.
    pub y: u32,
    /// The rectangle's width, texels.
    pub w: u32,
    /// The rectangle's height, texels.
    pub h: u32,
    /// `w · h` texels, rows top to bottom, RGBA8. Alpha 0 marks a texel not loaded yet (or
    /// outside the photograph): the sampler falls back to the next coarser level there.
    pub rgba: Vec<u8>,
}

/// What one frame of a clipmap gives the GPU.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ClipmapFrame {
    /// Every level's placement, finest first.
    pub placements: Vec<LevelPlacement>,
    /// The texels to write before drawing, in order.
    pub uploads: Vec<Upload>,
}

/// A source of clipmap contents: the CPU half.
pub trait ClipmapSource: Send {
    /// The levels and their size.
    fn config(&self) -> ClipmapConfig;

    /// Where the photograph lies.
    fn placement(&self) -> AerialPlacement;

    /// Moves the levels for `camera` and returns what changed. Never blocks on disk: tiles
    /// not loaded yet are requested and written by a later call, with alpha 0 until then.
    fn update(&mut self, camera: &ClipCamera) -> ClipmapFrame;

    /// Tiles the current windows need that have not arrived (their texels show a coarser
    /// level); 0 for a source that holds its photograph in memory.
    fn missing_tiles(&self) -> usize {
        0
    }
}

pub mod fed;
pub mod gpu;
pub mod image_source;

pub(crate) use fed::{FedClipmap, clip_camera};
pub use gpu::GpuClipmap;
pub use image_source::ImageSource;
