//! Why a scenario's steps are refused, it cannot run, or a draft or a hash update fails. Each
//! `Display` is one line; the caller adds the file's name.

use glam::Vec3;

use crate::expect::InvalidExpect;
use crate::input::InvalidEvent;

use super::failed::UnknownTechnique;
use crate::limits::{MAX_COORD, MAX_SCENARIO_STEPS, MAX_SCENARIO_TICKS, RAISE};

/// Why one step is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepError {
    /// A point that is not finite, or farther than [`MAX_COORD`] from the origin.
    #[error("{what} {point} is not a finite point within {MAX_COORD} m")]
    NotFinite {
        /// Which point ("the point", "the offset", "by", "y").
        what: &'static str,
        /// Its value.
        point: Vec3,
    },
    /// `Target(0)`.
    #[error("targets count from 1")]
    TargetZero,
    /// `Planted(0)`.
    #[error("planted trees count from 1")]
    PlantedZero,
    /// A model the catalogue does not have: the catalogue's sentence naming it.
    #[error("{0}")]
    UnknownModel(String),
    /// A pose that is not finite or not a rotation.
    #[error(transparent)]
    Pose(#[from] InvalidEvent),
    /// Touchpad axes outside [−1, 1].
    #[error("touchpad x and y must lie in [-1, 1]")]
    Touchpad,
    /// A Scale pad value outside [−1, 1].
    #[error("the Scale pad's value must lie in [-1, 1]")]
    ScalePad,
    /// A `WaitUntil` a world hash.
    #[error("a world hash cannot be waited for; check it with an Expect step")]
    WaitForHash,
    /// An expectation with a wrong name or number.
    #[error(transparent)]
    Expect(#[from] InvalidExpect),
    /// A task that is not built in.
    #[error("unknown task \"{0}\"; known: {known}", known = known_tasks())]
    UnknownTask(String),
    /// A technique that is neither built in nor registered.
    #[error(transparent)]
    Technique(#[from] UnknownTechnique),
    /// The steps up to this one may take more than [`MAX_SCENARIO_TICKS`].
    #[error("the steps so far may take {0} ticks, more than the limit of {MAX_SCENARIO_TICKS} per scenario ({RAISE})")]
    TooManyTicks(u64),
}

/// The built-in tasks, comma-separated.
fn known_tasks() -> String {
    let known: Vec<&str> = crate::task::BUILTIN_TASKS.iter().map(|(n, _)| *n).collect();
    known.join(", ")
}

/// Why a scenario's steps and expectations are refused ([`super::check`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// More steps and expectations than [`MAX_SCENARIO_STEPS`].
    #[error("{0} steps and expectations are more than the limit of {MAX_SCENARIO_STEPS} ({RAISE})")]
    TooManySteps(usize),
    /// A step is refused.
    #[error("step {number} {text}: {error}")]
    Step {
        /// The step, counting from 1.
        number: usize,
        /// The step as the file writes it.
        text: String,
        /// What is wrong.
        error: StepError,
    },
    /// An end expectation is refused.
    #[error("expect {number} {text}: {error}")]
    Expect {
        /// The expectation, counting from 1.
        number: usize,
        /// The expectation as the file writes it.
        text: String,
        /// What is wrong.
        error: InvalidExpect,
    },
}

/// Why a scenario could not start ([`super::run::start`], [`super::run::run`]).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The simulation could not be built from the scene.
    #[error(transparent)]
    Sim(#[from] crate::sim::SimError),
    /// The scene's model banks could not be used.
    #[error(transparent)]
    Banks(#[from] crate::bank::BankError),
    /// A config value was refused.
    #[error(transparent)]
    Config(#[from] crate::resources::ConfigError),
}

/// Why a scenario could not be drafted from a recording ([`super::draft::draft`]).
#[derive(Debug, thiserror::Error)]
pub enum DraftError {
    /// The recording's simulation could not be built.
    #[error(transparent)]
    Header(#[from] crate::replay::HeaderError),
    /// The scene file the recording names could not be found.
    #[error("scene {}: {error}", path.display())]
    ScenePath {
        /// The path looked up.
        path: std::path::PathBuf,
        /// The I/O error (in the message, so not a `source()`: the CLI prints the chain).
        error: std::io::Error,
    },
    /// The scenario could not be written as RON.
    #[error(transparent)]
    Ron(#[from] ron::Error),
    /// The drafted scenario was refused.
    #[error(transparent)]
    Scenario(#[from] super::ScenarioError),
    /// The drafted scenario could not start.
    #[error(transparent)]
    Run(#[from] RunError),
    /// The drafted steps fail.
    #[error("the drafted steps do not run: {0}")]
    DoesNotRun(super::run::Failure),
}

/// The text's `Hash("…")` values differ in number from the hashes the run checked
/// ([`super::update::pin_hashes`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("found {found} Hash(\"…\") values in the text but the run checked {checked}; pin them by hand")]
pub struct HashCountError {
    /// The `Hash("…")` values in the text.
    pub found: usize,
    /// The hashes the run checked.
    pub checked: usize,
}
