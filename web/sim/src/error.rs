//! [`Error`]: every way the module refuses a call. Its `Display` is one line naming the problem;
//! JavaScript receives it as the error's message, and the simulation is left as it was.

use grove_systems::limits::MAX_TICKS;

/// Why a call was refused.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The text handed over is not what the call takes (not UTF-8, not JSON of the right shape).
    #[error("{what}: {message}")]
    Input {
        /// What was being read ("options", "event", "replay options").
        what: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The scene could not be used.
    #[error("scene {name:?}: {message}")]
    Scene {
        /// The scene's name, as the options or the header give it.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The header line handed over is not a recording's header.
    #[error("header line: {0}")]
    HeaderLine(String),
    /// The header's simulation could not be built.
    #[error("{0}")]
    Header(#[from] grove_systems::replay::HeaderError),
    /// A `set` override was refused.
    #[error("set: {0}")]
    Config(#[from] grove_systems::resources::ConfigError),
    /// An event's kind, numbers or names were refused.
    #[error("event: {0}")]
    Event(String),
    /// An event stamped before one pushed earlier, or before the simulation's tick.
    #[error("event stamped tick {tick} is out of tick order: {reason}")]
    OutOfOrder {
        /// The event's tick.
        tick: u64,
        /// Why: what it comes before.
        reason: String,
    },
    /// A tick beyond what a recording may hold.
    #[error("tick {tick} is beyond the limit of {MAX_TICKS} ticks a recording may hold")]
    TickLimit {
        /// The tick asked for.
        tick: u64,
    },
    /// Too many events waiting for later ticks.
    #[error("more than {0} events wait for later ticks; push them nearer the tick they apply at")]
    Backlog(usize),
    /// The recording was finished: the simulation takes no more events or steps.
    #[error("the recording is finished (its footer is written); start a new simulation")]
    Finished,
    /// No simulation has this handle (it was freed, or never made).
    #[error("no simulation with handle {0}")]
    Handle(u32),
    /// A room's scene could not be built.
    #[error("room: {0}")]
    Room(#[from] grove_systems::room::RoomError),
    /// The recording replayed is unreadable or invalid (its file name and line number first).
    #[error("{0}")]
    Replay(#[from] grove_systems::replay::ReplayError),
}

impl Error {
    /// An input error: `what` was being read, `message` is what is wrong.
    pub fn input(what: &'static str, message: impl ToString) -> Error {
        Error::Input { what, message: message.to_string() }
    }
}
