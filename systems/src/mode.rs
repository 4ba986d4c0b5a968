//! The interaction mode of the study app: a leaf module that imports nothing else from the
//! crate, so that input events, the event log, tasks and resources can all name it.

use serde::{Deserialize, Serialize};

/// The interaction mode of the study app.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Trigger on a plane plants the selected model; Bumper on a tree removes it.
    #[default]
    RayCasting,
    /// New trees come only from the menu and must be moved into place.
    Manual,
}

impl Mode {
    /// The name used in files and reports: "ray-casting" or "manual".
    pub fn name(self) -> &'static str {
        match self {
            Mode::RayCasting => "ray-casting",
            Mode::Manual => "manual",
        }
    }
}
