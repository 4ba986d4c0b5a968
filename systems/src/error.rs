//! The crate's one error type: every error a grove-systems function returns converts into
//! [`Error`] with `?`, its one-line message unchanged, for a caller that wants a single type
//! (the specific types stay for callers that match on what went wrong).

use crate::bank::BankError;
use crate::catalogue::{CatalogueError, UnknownModel};
use crate::expect::InvalidExpect;
use crate::files::FileError;
use crate::input::InvalidEvent;
use crate::limits::InvalidScene;
use crate::replay::codec::LineFormatError;
use crate::replay::names::NameError;
use crate::replay::reader::ReplayError;
use crate::replay::scene_ref::SceneRefError;
use crate::replay::{HeaderError, RecordError};
use crate::resources::ConfigError;
use crate::scenario::{CheckError, DraftError, HashCountError, RunError, ScenarioError, StepError, UnknownTechnique};
use crate::scene::{SceneError, TimeError};
use crate::setup::SetUpError;
use crate::sim::SimError;
use crate::systems::sun::SunError;
use crate::targets::TargetError;
use crate::task::TaskError;
use crate::technique::TechniqueError;

/// Any error of grove-systems.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// [`CatalogueError`].
    #[error(transparent)]
    CatalogueError(#[from] CatalogueError),
    /// [`UnknownModel`].
    #[error(transparent)]
    UnknownModel(#[from] UnknownModel),
    /// [`ConfigError`].
    #[error(transparent)]
    ConfigError(#[from] ConfigError),
    /// [`FileError`].
    #[error(transparent)]
    FileError(#[from] FileError),
    /// [`SceneError`].
    #[error(transparent)]
    SceneError(#[from] SceneError),
    /// [`TimeError`].
    #[error(transparent)]
    TimeError(#[from] TimeError),
    /// [`InvalidScene`].
    #[error(transparent)]
    InvalidScene(#[from] InvalidScene),
    /// [`SimError`].
    #[error(transparent)]
    SimError(#[from] SimError),
    /// [`SetUpError`].
    #[error(transparent)]
    SetUpError(#[from] SetUpError),
    /// [`InvalidEvent`].
    #[error(transparent)]
    InvalidEvent(#[from] InvalidEvent),
    /// [`SunError`].
    #[error(transparent)]
    SunError(#[from] SunError),
    /// [`TargetError`].
    #[error(transparent)]
    TargetError(#[from] TargetError),
    /// [`TechniqueError`].
    #[error(transparent)]
    TechniqueError(#[from] TechniqueError),
    /// [`TaskError`].
    #[error(transparent)]
    TaskError(#[from] TaskError),
    /// [`InvalidExpect`].
    #[error(transparent)]
    InvalidExpect(#[from] InvalidExpect),
    /// [`BankError`].
    #[error(transparent)]
    BankError(#[from] BankError),
    /// [`LineFormatError`].
    #[error(transparent)]
    LineFormatError(#[from] LineFormatError),
    /// [`NameError`].
    #[error(transparent)]
    NameError(#[from] NameError),
    /// [`SceneRefError`].
    #[error(transparent)]
    SceneRefError(#[from] SceneRefError),
    /// [`HeaderError`].
    #[error(transparent)]
    HeaderError(#[from] HeaderError),
    /// [`RecordError`].
    #[error(transparent)]
    RecordError(#[from] RecordError),
    /// [`ReplayError`].
    #[error(transparent)]
    ReplayError(#[from] ReplayError),
    /// [`ScenarioError`].
    #[error(transparent)]
    ScenarioError(#[from] ScenarioError),
    /// [`CheckError`].
    #[error(transparent)]
    CheckError(#[from] CheckError),
    /// [`StepError`].
    #[error(transparent)]
    StepError(#[from] StepError),
    /// [`RunError`].
    #[error(transparent)]
    RunError(#[from] RunError),
    /// [`DraftError`].
    #[error(transparent)]
    DraftError(#[from] DraftError),
    /// [`HashCountError`].
    #[error(transparent)]
    HashCountError(#[from] HashCountError),
    /// [`UnknownTechnique`].
    #[error(transparent)]
    UnknownTechnique(#[from] UnknownTechnique),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::set_arg::SetArg;

    #[test]
    fn any_error_converts_with_its_message_unchanged() {
        fn set(arg: &str) -> Result<SetArg, Error> {
            Ok(arg.parse::<SetArg>()?)
        }
        let e = set("snap_threshold=x").unwrap_err();
        assert!(matches!(e, Error::ConfigError(_)));
        assert_eq!(e.to_string(), "snap_threshold: 'x' is not a number");
        fn decode(line: &str) -> Result<crate::replay::Line, Error> {
            Ok(crate::replay::codec::decode_line(line)?)
        }
        let e = decode("{}").unwrap_err();
        assert!(matches!(e, Error::LineFormatError(_)), "{e:?}");
        assert_eq!(e.to_string(), crate::replay::codec::decode_line("{}").unwrap_err().to_string());
    }
}
