//! Input events: the only way anything outside the simulation reaches the systems.
//!
//! Events are semantic (what the user did, not which device key was pressed), so recordings
//! survive changes to device mappings. A live session, a test script and a replay all feed the
//! same events into [`crate::resources::Resources::input`].

use glam::Vec2;
use serde::{Deserialize, Serialize};

use crate::catalogue::ModelRef;
use crate::components::Pose;
use crate::mode::Mode;

/// A controller button (Magic Leap One names; WebXR calls Bumper "squeeze").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Button {
    /// Plants, selects, drags.
    Trigger,
    /// Removes.
    Bumper,
    /// The touchpad press.
    Touchpad,
    /// Opens the model menu.
    Menu,
}

/// One input event. It applies at the start of the tick it is stamped with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum InputEvent {
    /// The controller moved to a new pose.
    ControllerPose {
        /// The new controller pose.
        pose: Pose,
    },
    /// The head (camera) moved to a new pose.
    HeadPose {
        /// The new head pose.
        pose: Pose,
    },
    /// A button went down.
    ButtonDown {
        /// Which button.
        button: Button,
    },
    /// A button went up.
    ButtonUp {
        /// Which button.
        button: Button,
    },
    /// The thumb position on the touchpad changed; (0, 0) when released.
    TouchpadAxes {
        /// Each axis in [−1, 1]; +Y is front, +X is right.
        axes: Vec2,
    },
    /// The Scale pad moved (a phone's touch bar, `docs/headset.md`): the selected tree grows while
    /// the value is above 0 and shrinks while it is below, faster the further; 0 when released.
    ScaleAxis {
        /// In [−1, 1]; +1 doubles the tree's scale each second.
        value: f32,
    },
    /// The user opened the model menu.
    OpenMenu,
    /// The user closed the model menu without choosing.
    CloseMenu,
    /// The user chose a model (from the menu in manual mode, or as the current model to plant).
    ChooseModel {
        /// The chosen model, by name (or, in older recordings, by the index of a shipped model).
        model: ModelRef,
    },
    /// The user switched the interaction mode.
    SwitchMode {
        /// The new mode.
        mode: Mode,
    },
    /// The user switched to a registered technique by name (a plug-in, or a built-in one).
    SwitchTechnique {
        /// The technique's name, e.g. "gaze-dwell".
        technique: String,
    },
    /// A study task starts now.
    StartTask {
        /// The task id, e.g. "ray-casting-7".
        task: String,
        /// Where its targets lie, when not as the task file puts them (`layout: room`: within a
        /// room's detected floor, `crate::room_layout`); absent for the task file's layout.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        layout: Option<crate::room_layout::TaskLayout>,
    },
    /// The user declared the task finished.
    EndTask,
}

impl InputEvent {
    /// A short, stable name for the event's kind, as used in the replay format and reports.
    pub fn kind(&self) -> &'static str {
        match self {
            InputEvent::ControllerPose { .. } => "controller_pose",
            InputEvent::HeadPose { .. } => "head_pose",
            InputEvent::ButtonDown { .. } => "button_down",
            InputEvent::ButtonUp { .. } => "button_up",
            InputEvent::TouchpadAxes { .. } => "touchpad_axes",
            InputEvent::ScaleAxis { .. } => "scale_axis",
            InputEvent::OpenMenu => "open_menu",
            InputEvent::CloseMenu => "close_menu",
            InputEvent::ChooseModel { .. } => "choose_model",
            InputEvent::SwitchMode { .. } => "switch_mode",
            InputEvent::SwitchTechnique { .. } => "switch_technique",
            InputEvent::StartTask { .. } => "start_task",
            InputEvent::EndTask => "end_task",
        }
    }

    /// Checks the numbers an event carries: poses and axes must be finite, axes within [−1, 1],
    /// and rotations close to unit length.
    pub fn validate(&self) -> Result<(), InvalidEvent> {
        match self {
            InputEvent::ControllerPose { pose } | InputEvent::HeadPose { pose } => {
                if !pose.is_finite() {
                    return Err(InvalidEvent::PoseNotFinite);
                }
                let len = pose.rotation.length();
                if (len - 1.0).abs() > 1e-3 {
                    return Err(InvalidEvent::RotationNotUnit(len));
                }
                if pose.position.abs().max_element() > 1.0e5 {
                    return Err(InvalidEvent::PoseTooFar);
                }
                Ok(())
            }
            InputEvent::TouchpadAxes { axes } => {
                if !axes.is_finite() {
                    Err(InvalidEvent::AxesNotFinite)
                } else if axes.abs().max_element() > 1.0 {
                    Err(InvalidEvent::AxesOutOfRange)
                } else {
                    Ok(())
                }
            }
            InputEvent::ScaleAxis { value } if !value.is_finite() => Err(InvalidEvent::AxesNotFinite),
            InputEvent::ScaleAxis { value } if value.abs() > 1.0 => Err(InvalidEvent::AxesOutOfRange),
            InputEvent::StartTask { task, .. } if task.is_empty() => Err(InvalidEvent::EmptyTask),
            InputEvent::StartTask { layout: Some(l), .. } => l.validate().map_err(InvalidEvent::Layout),
            InputEvent::SwitchTechnique { technique } if technique.is_empty() || technique.len() > 64 => {
                Err(InvalidEvent::TechniqueName)
            }
            _ => Ok(()),
        }
    }
}

/// Why an input event's numbers or names are refused ([`InputEvent::validate`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InvalidEvent {
    /// A pose with a NaN or infinite number.
    #[error("pose has a NaN or infinite number")]
    PoseNotFinite,
    /// A rotation that is not a unit quaternion; its length.
    #[error("pose rotation is not a unit quaternion (length {0})")]
    RotationNotUnit(f32),
    /// A pose more than 100 km from the origin.
    #[error("pose position is more than 100 km from the origin")]
    PoseTooFar,
    /// Touchpad axes with a NaN or infinite number.
    #[error("touchpad axes have a NaN or infinite number")]
    AxesNotFinite,
    /// Touchpad axes outside [−1, 1].
    #[error("touchpad axes outside [-1, 1]")]
    AxesOutOfRange,
    /// A task start with an empty id.
    #[error("empty task id")]
    EmptyTask,
    /// A technique name that is empty or longer than 64 characters.
    #[error("technique name must have 1 to 64 characters")]
    TechniqueName,
    /// A task layout whose floor is not an outline.
    #[error("{0}")]
    Layout(crate::room_layout::FloorError),
}

/// An input event stamped with the tick at which it applies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StampedEvent {
    /// The tick at whose start the event applies.
    pub tick: u64,
    /// The event.
    pub event: InputEvent,
}
