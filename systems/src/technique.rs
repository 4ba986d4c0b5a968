//! Interaction techniques as plug-ins (`docs/techniques.md`).
//!
//! A [`Technique`] is one registration: its name and version (for menus, recordings and
//! reports), the built-in behaviour it runs on ([`Technique::base`]), its systems and the
//! [`Stage`] of the schedule each runs in, its components (hashed through the same table as the
//! built-in ones, [`crate::hash`]), the controller buttons it uses and how the desktop maps them,
//! and its synthetic participant model as keystroke-level and Fitts operators ([`Operator`]).
//!
//! The two built-in techniques, ray-casting and manual modification, are registrations like any
//! other ([`Technique::ray_casting`], [`Technique::manual`]): they add no systems of their own,
//! because the built-in systems of [`crate::schedule`] already read [`crate::mode::Mode`].
//!
//! The app registers its techniques once at start-up ([`install`]); every simulation built
//! afterwards knows them ([`installed`]): the [`crate::Sim`] holds the registry (whose systems
//! the schedule runs), its resources what the world knows of it ([`crate::known_techniques`]). A simulation switches technique with the input event
//! [`crate::input::InputEvent::SwitchTechnique`]; a recording that names a technique that is not
//! registered is invalid input.

use std::sync::{Arc, OnceLock};

use hecs::World;

pub use crate::known_techniques::{HashedComponent, Known, KnownTechniques, Registered, Registry};

use crate::input::Button;
use crate::mode::Mode;
use crate::resources::Resources;

/// A system: reads and writes the world and the resources for one fixed step.
pub type System = fn(&mut World, &mut Resources);

/// The named stages of the schedule, in the order they run. Each built-in system belongs to one
/// ([`crate::schedule::BUILTIN`]); a technique's systems run after the built-in systems of their
/// stage, in registration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// Input events applied to the controller, head, buttons and menu.
    Input,
    /// The sun and the wind.
    Environment,
    /// The controller ray and the hit marker.
    Ray,
    /// Spawning, planting, removing, selecting, handles and the touchpad.
    Interaction,
    /// Dragging with the anchor ball and snapping, and the selection box.
    Constraints,
    /// The running study task.
    Task,
}

impl Stage {
    /// Every stage, in schedule order.
    pub const ALL: [Stage; 6] =
        [Stage::Input, Stage::Environment, Stage::Ray, Stage::Interaction, Stage::Constraints, Stage::Task];

    /// The stage's name as documentation and `--help` use it.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Input => "input",
            Stage::Environment => "environment",
            Stage::Ray => "ray",
            Stage::Interaction => "interaction",
            Stage::Constraints => "constraints",
            Stage::Task => "task",
        }
    }
}

/// A controller event a technique uses, and the desktop key or button that produces it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Control {
    /// The controller button.
    pub button: Button,
    /// The desktop's key or mouse button for it (`src/desktop/input_map.rs`).
    pub desktop: &'static str,
    /// What it does in this technique.
    pub action: &'static str,
}

/// One step of a synthetic participant, as the keystroke-level model (Card, Moran & Newell
/// 1980) and Fitts' law (`docs/participants.md`) name them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Operator {
    /// M: mental preparation.
    Mental,
    /// Choosing a model from the menu: a Fitts movement over the menu geometry and a press.
    Menu,
    /// P with the controller ray: a Fitts movement of the hand to the target, then corrections.
    AimRay,
    /// P with the head: a Fitts movement of the gaze to the target, then corrections.
    AimHead,
    /// K: a button press and release.
    Press(Button),
    /// A button held down (the start of a drag).
    Hold(Button),
    /// A held button released.
    Release(Button),
    /// A drag of the held tree to the target (Fitts for the ray, rate control on the touchpad).
    Drag,
    /// Holding still for this many seconds (a dwell).
    Dwell(f32),
}

/// One interaction technique.
#[derive(Clone)]
pub struct Technique {
    /// The name used in files, menus, recordings and reports, e.g. "gaze-dwell".
    pub name: &'static str,
    /// The technique's version; a recording names it and a replay refuses another.
    pub version: u32,
    /// One line for menus and `--help`.
    pub about: &'static str,
    /// The built-in behaviour the shared systems apply while this technique is active.
    pub base: Mode,
    /// The technique's own systems, each with its stage and a name.
    pub systems: Vec<(Stage, &'static str, System)>,
    /// The technique's component types.
    pub components: Vec<HashedComponent>,
    /// The controller events it uses.
    pub controls: Vec<Control>,
    /// The synthetic participant's steps for one target.
    pub participant: Vec<Operator>,
}

impl Technique {
    /// Ray-casting: Trigger on a plane plants the current model; Bumper on a tree removes it.
    pub fn ray_casting() -> Technique {
        Technique {
            name: Mode::RayCasting.name(),
            version: 1,
            about: crate::known_techniques::RAY_CASTING_ABOUT,
            base: Mode::RayCasting,
            systems: Vec::new(),
            components: Vec::new(),
            controls: vec![
                Control {
                    button: Button::Trigger,
                    desktop: "left mouse button",
                    action: "plant on the ground, select a tree",
                },
                Control {
                    button: Button::Bumper,
                    desktop: "right mouse button",
                    action: "remove the tree under the ray",
                },
                Control { button: Button::Menu, desktop: "Tab or M", action: "open the model menu" },
            ],
            participant: vec![Operator::Mental, Operator::Menu, Operator::AimRay, Operator::Press(Button::Trigger)],
        }
    }

    /// Manual modification: a model chosen from the menu appears in front of the head and is
    /// dragged into place; the anchor ball snaps it to the ground.
    pub fn manual() -> Technique {
        Technique {
            name: Mode::Manual.name(),
            version: 1,
            about: crate::known_techniques::MANUAL_ABOUT,
            base: Mode::Manual,
            systems: Vec::new(),
            components: Vec::new(),
            controls: vec![
                Control {
                    button: Button::Trigger,
                    desktop: "left mouse button",
                    action: "grab and drag a tree or a handle",
                },
                Control {
                    button: Button::Bumper,
                    desktop: "right mouse button",
                    action: "remove the tree under the ray",
                },
                Control {
                    button: Button::Touchpad,
                    desktop: "mouse wheel or Up/Down (front/back), Q/E (left/right)",
                    action: "move the selected tree along the ray and turn it",
                },
                Control { button: Button::Menu, desktop: "Tab or M", action: "open the model menu" },
            ],
            participant: vec![
                Operator::Mental,
                Operator::Menu,
                Operator::AimRay,
                Operator::Hold(Button::Trigger),
                Operator::Drag,
                Operator::Release(Button::Trigger),
            ],
        }
    }

    /// Whether this is one of the two built-in techniques.
    pub fn is_builtin(&self) -> bool {
        self.name == Mode::RayCasting.name() || self.name == Mode::Manual.name()
    }

    /// What the world knows of it (all but its systems, controls and participant model).
    pub fn known(&self) -> Known {
        Known {
            name: self.name,
            version: self.version,
            about: self.about,
            base: self.base,
            components: self.components.clone(),
        }
    }
}

/// The registered techniques with their systems, controls and participant models.
pub type Techniques = Registry<Technique>;

impl Registered for Technique {
    fn name(&self) -> &'static str {
        self.name
    }
    fn version(&self) -> u32 {
        self.version
    }
}

impl Registry<Technique> {
    /// Only the two built-in techniques.
    pub fn builtin() -> Techniques {
        Registry(Arc::new(vec![Technique::ray_casting(), Technique::manual()]))
    }

    /// The built-in techniques and these plug-ins. A name registered twice, an empty name or
    /// one with characters other than lowercase letters, digits and `-` is refused.
    pub fn with(plugins: Vec<Technique>) -> Result<Techniques, TechniqueError> {
        let mut all = vec![Technique::ray_casting(), Technique::manual()];
        for t in plugins {
            if t.name.is_empty() || !t.name.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-') {
                return Err(TechniqueError::BadName(t.name.to_string()));
            }
            if all.iter().any(|k| k.name == t.name) {
                return Err(TechniqueError::Twice(t.name.to_string()));
            }
            all.push(t);
        }
        Ok(Registry(Arc::new(all)))
    }

    /// What the world knows of them, in the same order ([`crate::resources::Resources::techniques`]).
    pub fn known(&self) -> KnownTechniques {
        KnownTechniques::from_list(self.0.iter().map(Technique::known).collect())
    }
}

/// Why a technique list or its installation was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TechniqueError {
    /// A name that is empty or has characters other than lowercase letters, digits and `-`.
    #[error("technique name '{}' must be lowercase letters, digits and '-'", .0.escape_debug())]
    BadName(String),
    /// A name registered twice.
    #[error("technique '{0}' is registered twice")]
    Twice(String),
    /// [`install`] called a second time.
    #[error("the techniques are already installed")]
    AlreadyInstalled,
}

static INSTALLED: OnceLock<Techniques> = OnceLock::new();

/// Registers the app's techniques for every simulation built afterwards. Once per process; a
/// second call is refused.
pub fn install(techniques: Techniques) -> Result<(), TechniqueError> {
    INSTALLED.set(techniques).map_err(|_| TechniqueError::AlreadyInstalled)
}

/// The installed techniques, or only the built-in ones if [`install`] was never called.
pub fn installed() -> Techniques {
    INSTALLED.get().cloned().unwrap_or_else(Techniques::builtin)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plugin(name: &'static str) -> Technique {
        Technique {
            name,
            version: 2,
            about: "",
            base: Mode::RayCasting,
            systems: Vec::new(),
            components: Vec::new(),
            controls: Vec::new(),
            participant: Vec::new(),
        }
    }

    #[test]
    fn the_built_in_techniques_come_first_and_match_their_modes() {
        let t = Techniques::with(vec![plugin("grid-snap")]).unwrap();
        assert_eq!(t.at(Techniques::of_mode(Mode::RayCasting)).base, Mode::RayCasting);
        assert_eq!(t.at(Techniques::of_mode(Mode::Manual)).name, "manual");
        assert_eq!(t.index("grid-snap"), Some(2));
        assert!(t.at(0).is_builtin() && !t.at(2).is_builtin());
        assert_eq!(t.names(), "ray-casting, manual, grid-snap");
    }

    #[test]
    fn duplicate_and_malformed_names_are_refused() {
        assert!(Techniques::with(vec![plugin("manual")]).unwrap_err().to_string().contains("twice"));
        assert!(Techniques::with(vec![plugin("a"), plugin("a")]).is_err());
        assert!(Techniques::with(vec![plugin("Gaze Dwell")]).unwrap_err().to_string().contains("lowercase"));
        assert!(Techniques::with(vec![plugin("")]).is_err());
        assert!(Techniques::builtin().unknown("x").contains("registered: ray-casting, manual"));
    }
}
