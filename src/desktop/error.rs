//! [`DesktopError`]: why `grove play` or `grove view` could not open, record or run. Its
//! `Display` is one line; wrapped errors are shown in it rather than as a `source()`, since the
//! CLI prints an error's whole chain.

use std::path::PathBuf;

use grove_systems::input::InvalidEvent;

/// Why the desktop app failed.
#[derive(Debug, thiserror::Error)]
pub enum DesktopError {
    /// The event loop could not be created.
    #[error("cannot open the display ({0}); is DISPLAY set?")]
    Display(winit::error::EventLoopError),
    /// The window, its GPU set-up or the frontend failed while it ran (their one-line message).
    #[error("{0}")]
    Window(String),
    /// A panic inside the window that is not the windowing system's: its message.
    #[error("internal error in the window: {0}; please report this")]
    Internal(String),
    /// The renderer failed.
    #[error(transparent)]
    Renderer(#[from] grove::render::RenderError),
    /// The scene's aerial photographs could not be opened.
    #[error(transparent)]
    Aerial(#[from] grove::render::ClipmapError),
    /// The session's model banks could not be opened or loaded.
    #[error(transparent)]
    Bank(#[from] grove::bank::BankError),
    /// A thumbnail's stage could not be built.
    #[error("{0}")]
    Stage(grove_systems::sim::SimError),
    /// The recording file exists already.
    #[error("{}: already exists; choose another --record file (grove never overwrites a recording)", .0.display())]
    RecordingExists(PathBuf),
    /// The recording file could not be created.
    #[error("{}: {}", path.display(), grove_systems::scene::io_message(error))]
    CreateRecording {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// The recording's header could not be written.
    #[error("{}: {error}", path.display())]
    RecordingHeader {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A line of the recording could not be written.
    #[error("recording: {0}")]
    Recording(std::io::Error),
    /// An input event with invalid numbers or names.
    #[error(transparent)]
    Event(#[from] InvalidEvent),
    /// A recording that does not replay.
    #[error(transparent)]
    Replay(#[from] grove_systems::replay::ReplayError),
    /// The simulation a recording's header describes could not be built.
    #[error("{}: {error}", path.display())]
    Header {
        /// The recording.
        path: PathBuf,
        /// Why.
        error: grove_systems::replay::HeaderError,
    },
}

impl From<DesktopError> for String {
    fn from(e: DesktopError) -> String {
        e.to_string()
    }
}
