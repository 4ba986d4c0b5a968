//! [`RenderError`]: why the renderer could not open a device, load an asset, build a pipeline,
//! stream a clipmap or read a frame back. Its `Display` is one line, worded as the CLI prints
//! it; the errors it wraps are shown in that line rather than as a `source()`, since the CLI
//! prints an error's whole chain.
//!
//! A leaf of `src/render`: it names no feature module (features import it), only the pipeline
//! key ([`super::key`]) and the models' glTF errors ([`crate::models::GltfError`]).

use std::path::PathBuf;

use glam::DVec2;
use grove_systems::files::FileError;

use super::key::PipelineKey;
pub use crate::models::{GltfError, GltfProblem};

/// Why the renderer failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No GPU adapter could be requested.
    #[error("no GPU adapter available ({0}); install a Vulkan driver such as mesa-vulkan-drivers (lavapipe)")]
    Adapter(wgpu::RequestAdapterError),
    /// The adapter refused to open a device.
    #[error("cannot open the GPU device ({0})")]
    Device(wgpu::RequestDeviceError),
    /// Waiting for the GPU failed.
    #[error("GPU poll failed ({0})")]
    Poll(wgpu::PollError),
    /// The offscreen target's map callback never answered.
    #[error("GPU readback was dropped")]
    ReadbackDropped,
    /// Mapping the offscreen target's readback buffer failed.
    #[error("GPU readback failed ({0})")]
    Readback(wgpu::BufferAsyncError),
    /// The mapped readback buffer could not be viewed.
    #[error("GPU readback failed ({0:?})")]
    ReadbackRange(wgpu::MapRangeError),
    /// The pixels read back do not fill the image.
    #[error("readback size mismatch")]
    ReadbackSize,
    /// Pass timing was asked of a device without timestamp queries.
    #[error("this GPU device has no timestamp queries (Features::TIMESTAMP_QUERY)")]
    NoTimestamps,
    /// The timestamps' map callback never answered.
    #[error("GPU timestamp readback was dropped")]
    TimestampsDropped,
    /// Mapping the timestamps' readback buffer failed.
    #[error("GPU timestamp readback failed ({0})")]
    Timestamps(wgpu::BufferAsyncError),
    /// The mapped timestamps could not be viewed.
    #[error("GPU timestamp readback failed ({0:?})")]
    TimestampsRange(wgpu::MapRangeError),
    /// Waiting for the grass counts failed.
    #[error("grass counts: {0}")]
    GrassCountsPoll(wgpu::PollError),
    /// The grass counts could not be mapped.
    #[error("grass counts: {0}")]
    GrassCountsRange(wgpu::MapRangeError),
    /// The far grass blades' image is larger than one storage binding of the device.
    #[error(
        "grass blades cannot be drawn at {width}x{height} pixels: their image needs {bytes} bytes, over the device's limit of {limit}"
    )]
    GrassImage {
        /// Target width, pixels.
        width: u32,
        /// Target height, pixels.
        height: u32,
        /// The image's size, bytes.
        bytes: u64,
        /// The device's `max_storage_buffer_binding_size`.
        limit: u64,
    },
    /// An asset file that `grove_systems::files` refused to read (the message names the path).
    #[error("{0}")]
    File(FileError),
    /// An image file that does not decode.
    #[error("{}: {}", path.display(), one_line_image_error(error))]
    Image {
        /// The file.
        path: PathBuf,
        /// The decoder's error.
        error: image::ImageError,
    },
    /// An image that could not be written as PNG.
    #[error("{}: cannot write PNG ({})", path.display(), one_line_image_error(error))]
    SavePng {
        /// The file.
        path: PathBuf,
        /// The encoder's error.
        error: image::ImageError,
    },
    /// A cube face that is not square or not the size of the others.
    #[error("{}: cube faces must be square and all the same size", .0.display())]
    CubeFaces(PathBuf),
    /// The stage a model is rendered on could not be built.
    #[error("{0}")]
    Stage(grove_systems::sim::SimError),
    /// A feature has no pipeline for a key.
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// A glTF model could not be read or is refused.
    #[error(transparent)]
    Gltf(#[from] GltfError),
    /// A clipmap could not be made or fed.
    #[error(transparent)]
    Clipmap(#[from] ClipmapError),
}

/// Why a feature has no pipeline for a key.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The feature draws from the main view only; the name is how the message starts ("the
    /// sky", "grass").
    #[error("{0} is drawn from the main view only")]
    MainViewOnly(&'static str),
    /// Building the pipelines of a key was refused.
    #[error("{feature}: no pipeline for {key:?}: {reason}")]
    Refused {
        /// The feature.
        feature: &'static str,
        /// The key.
        key: PipelineKey,
        /// Why its build refused the key.
        reason: Box<PipelineError>,
    },
    /// The pipelines of a key were never prepared.
    #[error("{feature}: no pipeline prepared for {key:?}")]
    NotPrepared {
        /// The feature.
        feature: &'static str,
        /// The key.
        key: PipelineKey,
    },
    /// A main-view key where the sun's was expected.
    #[error("{feature}: {key:?} is not a shadow key")]
    NotShadowKey {
        /// The feature.
        feature: &'static str,
        /// The key.
        key: PipelineKey,
    },
    /// The sun's key where a main-view key was expected.
    #[error("{feature}: {key:?} is not a main-view key")]
    NotMainKey {
        /// The feature.
        feature: &'static str,
        /// The key.
        key: PipelineKey,
    },
    /// The sun's key holds a main-view pipeline (the feature's name).
    #[error("{0}: the sun's key has no shadow pipeline")]
    NoShadowPipeline(&'static str),
    /// A main-view key holds a shadow pipeline (the feature's name).
    #[error("{0}: the main key has no main pipeline")]
    NoMainPipeline(&'static str),
}

/// Why a clipmap could not be made or fed.
#[derive(Debug, thiserror::Error)]
pub enum ClipmapError {
    /// A level count the GPU clipmap does not hold.
    #[error("a clipmap has 1 to {max} levels, not {levels}")]
    GpuLevels {
        /// The levels asked for.
        levels: u32,
        /// The most levels.
        max: usize,
    },
    /// A level side the GPU clipmap does not hold.
    #[error("a clipmap level's side must be a power of two from 16 to 4096 texels, not {0}")]
    GpuSide(u32),
    /// Level textures larger than the device allows.
    #[error("the GPU allows textures of at most {max_side} texels and {max_layers} layers")]
    TextureLimits {
        /// The device's `max_texture_dimension_2d`.
        max_side: u32,
        /// The device's `max_texture_array_layers`.
        max_layers: u32,
    },
    /// A GPU clipmap (named by its label) placed with a bad ground sample distance or origin.
    #[error("{label}: the ground sample distance must be positive and the origin finite")]
    GpuPlacement {
        /// The clipmap's label.
        label: String,
    },
    /// A frame with another number of level placements than the clipmap has levels.
    #[error("a clipmap frame has {placements} placements for {levels} levels")]
    FramePlacements {
        /// The placements in the frame.
        placements: usize,
        /// The clipmap's levels.
        levels: u32,
    },
    /// An upload that does not fit its level.
    #[error("a clipmap upload of {w}x{h} texels at ({x}, {y}) of level {level} does not fit a {side}-texel level")]
    UploadOutside {
        /// Width, texels.
        w: u32,
        /// Height, texels.
        h: u32,
        /// Column of its corner.
        x: u32,
        /// Row of its corner.
        y: u32,
        /// The level.
        level: u32,
        /// The level's side, texels.
        side: u32,
    },
    /// A photograph too large (or empty) to be held in memory.
    #[error(
        "a photograph held in memory must be 1 to {max} texels a side, not {width}x{height}; tile it with `grove aerial tile`"
    )]
    MemorySide {
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
        /// The largest side.
        max: u32,
    },
    /// RGBA texels of the wrong length for their size.
    #[error("{width}x{height} RGBA texels need {expected} bytes, not {found}")]
    RgbaLength {
        /// Width, texels.
        width: u32,
        /// Height, texels.
        height: u32,
        /// The bytes such an image has.
        expected: u64,
        /// The bytes given.
        found: usize,
    },
    /// A streamed clipmap's level count out of range.
    #[error("{0} clipmap levels; between 1 and 16 are allowed")]
    Levels(u32),
    /// A streamed clipmap's level size out of range.
    #[error("clipmap level size {0} must be a power of two from 16 to 4096")]
    LevelSize(u32),
    /// A photograph's placement that is not finite or has no positive ground sample distance.
    #[error(
        "the photograph's placement (origin {origin}, {gsd} m per texel) must be finite with a positive ground sample distance"
    )]
    Placement {
        /// The origin, metres.
        origin: DVec2,
        /// The ground sample distance, metres per texel.
        gsd: f64,
    },
    /// The loader thread could not be started.
    #[error("cannot start the clipmap's loader thread: {0}")]
    LoaderThread(std::io::Error),
    /// A photograph, layer mask or tile pyramid that could not be read or does not fit.
    #[error(transparent)]
    Aerial(#[from] crate::aerial::AerialError),
    /// An error about a named photograph: `name` is how the message names it ("winter
    /// photograph").
    #[error("{name}: {error}")]
    In {
        /// The photograph, as the message names it.
        name: String,
        /// What went wrong with it.
        error: Box<ClipmapError>,
    },
}

impl ClipmapError {
    /// This error about the photograph named `name`: "`name`: error".
    pub fn named(self, name: impl std::fmt::Display) -> ClipmapError {
        ClipmapError::In { name: name.to_string(), error: Box::new(self) }
    }
}

/// A short description of an image error, on one line.
pub fn one_line_image_error(e: &image::ImageError) -> String {
    match e {
        image::ImageError::IoError(io) => grove_systems::scene::io_message(io),
        other => other.to_string().replace('\n', " "),
    }
}
