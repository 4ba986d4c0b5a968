//! Why a benchmark could not run: its scene, the device, the renderer or what it writes. Each
//! message is one line.

use std::path::PathBuf;

use crate::aerial::AerialError;
use crate::atomic_write::WriteError;
use crate::bank::BankError;
use crate::render::{ClipmapError, PipelineError, RenderError};
use crate::study::StudyError;
use crate::video::encode::VideoError;

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// The benchmark needs a GPU and wgpu picked a software adapter (named).
    #[error("the GPU benchmark needs a real GPU, but wgpu picked the software adapter {0}")]
    SoftwareAdapter(String),
    /// The benchmark needs timestamp queries and the device has none.
    #[error("the GPU benchmark needs timestamp queries: {0}")]
    NoTimestamps(RenderError),
    /// Waiting for the device failed.
    #[error("GPU poll failed ({0})")]
    Poll(#[from] wgpu::PollError),
    /// The scene of an aerial benchmark has no aerial section.
    #[error("the scene has no aerial section")]
    NoAerial,
    /// A built-in scene is missing.
    #[error("the built-in {0} scene is missing")]
    MissingScene(&'static str),
    /// A folder could not be made.
    #[error("{}: cannot create ({source})", path.display())]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A server benchmark's server or client failed.
    #[error("serve: {0}")]
    Serve(String),
    /// A figure could not be written as JSON.
    #[error("cannot write JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The simulation refused the scene or a recording.
    #[error(transparent)]
    Systems(#[from] grove_systems::Error),
    /// [`RenderError`].
    #[error(transparent)]
    Render(#[from] RenderError),
    /// [`PipelineError`].
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
    /// [`BankError`].
    #[error(transparent)]
    Bank(#[from] BankError),
    /// [`AerialError`].
    #[error(transparent)]
    Aerial(#[from] AerialError),
    /// [`ClipmapError`]: a scene's photographs could not be opened as clipmap sources.
    #[error(transparent)]
    Clipmap(#[from] ClipmapError),
    /// [`VideoError`].
    #[error(transparent)]
    Video(#[from] VideoError),
    /// [`StudyError`].
    #[error(transparent)]
    Study(#[from] StudyError),
    /// [`WriteError`].
    #[error(transparent)]
    Write(#[from] WriteError),
}
