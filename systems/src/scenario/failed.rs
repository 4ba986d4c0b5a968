//! Why a step did not do what it says when it ran (`StepFailed`), and a technique name that is
//! neither built in nor registered (`UnknownTechnique`). Each `Display` is one line; the run's
//! failure names the step before it.

use crate::input::InvalidEvent;

/// A technique name that is neither built in nor registered ([`super::technique`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown technique \"{name}\"; known: {known}")]
pub struct UnknownTechnique {
    /// The name as written.
    pub name: String,
    /// The known names, comma-separated.
    pub known: String,
}

/// Why a step did not do what it says when it ran (a scenario's failure names the step, then
/// this; [`super::run::apply`]). Each `Display` is one line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum StepFailed {
    /// The tree or point a step names cannot be found.
    #[error("cannot find the target: {0}")]
    NoTarget(#[from] crate::targets::TargetError),
    /// The ray met something else than the aim when an aimed button went down.
    #[error("the ray meets {met}, {} {aimed} at {distance:.1} m{}", if *.before { "before" } else { "not" }, if *.met_nothing { " (to press where the ray meets nothing, write PressOnNothing(…) or press_on_nothing: true)" } else { "" })]
    Missed {
        /// What the ray met, in words.
        met: String,
        /// Whether it met that before the aim (nearer).
        before: bool,
        /// The aim, in words.
        aimed: String,
        /// The aim's distance from the ray's origin, metres.
        distance: f32,
        /// Whether the ray met nothing.
        met_nothing: bool,
    },
    /// A `PressOnNothing` whose ray met something.
    #[error("the ray meets {0}, not nothing")]
    NotNothing(String),
    /// `Plant` in manual mode.
    #[error("Plant plants in ray-casting mode; in manual mode a tree comes from the menu: ChooseModel(\"…\"), then Drag(tree: Last, to: …)")]
    PlantInManual,
    /// The press met water, where nothing is planted.
    #[error("nothing was planted: the ray met water at {0}, where nothing is planted")]
    OnWater(String),
    /// The press planted nothing.
    #[error("nothing was planted")]
    NothingPlanted,
    /// A tree of another model was planted.
    #[error("a {got} tree was planted, not a {model} tree")]
    WrongModel {
        /// The model planted.
        got: String,
        /// The model the step names.
        model: String,
    },
    /// The tree stands farther from the aim than the tolerance.
    #[error("the {model} tree stands {off:.2} m from {at}, more than the tolerance of {within} m")]
    TooFar {
        /// The model.
        model: String,
        /// How far from the aim, along the ground, metres.
        off: f32,
        /// The aim as written.
        at: String,
        /// The tolerance, metres.
        within: f32,
    },
    /// `Remove` left the tree standing.
    #[error("the tree {0} still stands")]
    StillStands(String),
    /// `Drag`'s Trigger did not grab the tree.
    #[error("the Trigger did not grab the tree {0}")]
    NotGrabbed(String),
    /// `Drag` did not snap the tree to the ground.
    #[error("the tree {tree} did not snap to the ground at {to}: {why}")]
    NotSnapped {
        /// The tree as written.
        tree: String,
        /// The aim as written.
        to: String,
        /// What the anchor ball showed.
        why: String,
    },
    /// A pose that is not finite or not a rotation.
    #[error(transparent)]
    Pose(#[from] InvalidEvent),
    /// An expectation that does not hold (an `Expect` step, a `WaitUntil` that timed out).
    #[error(transparent)]
    Mismatch(#[from] crate::expect::Mismatch),
    /// A technique that is neither built in nor registered.
    #[error(transparent)]
    Technique(#[from] UnknownTechnique),
}
