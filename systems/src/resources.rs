//! Resources: simulation state that belongs to no entity.
//!
//! [`Resources`] holds the tick counter, the fixed step, the one seeded RNG, the configuration,
//! the input events of the current tick, the interaction event log and the interaction state.
//! Everything here except the derived caches is covered by the world hash.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::catalogue::{Catalogue, ModelId};
use crate::events::EventLog;
use crate::input::InputEvent;
use crate::spatial::SpatialIndex;

pub use crate::mode::Mode;

/// One tunable parameter as [`Config::PARAMS`] lists it: what `--set`, sweeps, what-ifs and
/// recording headers check a value against, and what `grove study --help` and the reports show.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Param {
    /// The name, as `--set NAME=VALUE` writes it.
    pub name: &'static str,
    /// The default value.
    pub default: f32,
    /// The smallest accepted value.
    pub min: f32,
    /// The largest accepted value.
    pub max: f32,
    /// The unit ("m", "m/s", "deg/s"; "" for a plain number).
    pub unit: &'static str,
    /// What it does (its doc comment).
    pub doc: &'static str,
}

impl Param {
    /// " UNIT", to write after a value, or nothing for a plain number.
    pub fn unit_suffix(&self) -> String {
        if self.unit.is_empty() { String::new() } else { format!(" {}", self.unit) }
    }

    /// The parameter called `name`.
    pub fn named(name: &str) -> Option<&'static Param> {
        Config::PARAMS.iter().find(|p| p.name == name)
    }
}

/// Defines [`Config`] from one list of fields, each `name: default, [min, max], "unit"` with
/// its doc comment: the struct, its defaults, [`Config::PARAMS`], [`Config::NAMES`] and the
/// lookup by name that [`Config::apply`] uses all come from that list, so a field is written
/// once.
macro_rules! config_fields {
    ($($(#[doc = $doc:literal])* $name:ident: $default:expr, [$min:expr, $max:expr], $unit:literal,)*) => {
        /// Tunable parameters of the interaction systems. Researchers may override any of them
        /// with `grove study --set NAME=VALUE`; [`Config::PARAMS`] lists them with their ranges.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct Config {
            $($(#[doc = $doc])* pub $name: f32,)*
        }

        impl Default for Config {
            fn default() -> Self {
                Config { $($name: $default,)* }
            }
        }

        impl Config {
            /// Every parameter, in field order, with its default, range, unit and doc.
            pub const PARAMS: &'static [Param] = &[$(Param {
                name: stringify!($name),
                default: $default,
                min: $min,
                max: $max,
                unit: $unit,
                doc: concat!($($doc),*),
            },)*];

            /// The parameters' names, in field order.
            pub const NAMES: &'static [&'static str] = &[$(stringify!($name),)*];

            /// The field called `name`.
            fn field_mut(&mut self, name: &str) -> Option<&mut f32> {
                match name {
                    $(stringify!($name) => Some(&mut self.$name),)*
                    _ => None,
                }
            }
        }
    };
}

config_fields! {
    /// A dragged tree snaps when its lowest point is closer than this to the plane below, metres.
    snap_threshold: 0.3, [0.0, 10.0], "m",
    /// Touchpad front/back speed along the controller ray, metres per second at full deflection.
    touchpad_move_rate: 1.5, [0.0, 100.0], "m/s",
    /// Touchpad left/right turn rate, degrees per second at full deflection.
    touchpad_turn_rate_deg: 90.0, [0.0, 3600.0], "deg/s",
    /// Touchpad deflections smaller than this are ignored.
    touchpad_dead_zone: 0.15, [0.0, 1.0], "",
    /// Smallest allowed uniform scale.
    min_scale: 0.25, [0.0, 100.0], "",
    /// Largest allowed uniform scale.
    max_scale: 4.0, [0.0, 100.0], "",
    /// Longest ray, metres.
    max_ray_length: 100.0, [0.0, 10000.0], "m",
    /// Radius of a bounding-box handle for ray picking, metres.
    handle_radius: 0.15, [0.0, 10.0], "m",
    /// Distance in front of the head where a tree chosen from the menu appears, metres.
    spawn_distance: 1.5, [0.0, 100.0], "m",
    /// How far below head height a tree chosen from the menu appears, metres.
    spawn_drop: 0.5, [0.0, 100.0], "m",
}

/// Why a config parameter or a set of overrides was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// The name is not one of [`Config::NAMES`].
    #[error("unknown parameter '{name}'; known: {}", Config::NAMES.join(", "))]
    Unknown {
        /// The name as written.
        name: String,
    },
    /// The value does not parse as a number.
    #[error("{name}: '{text}' is not a number")]
    NotANumber {
        /// The parameter.
        name: &'static str,
        /// The value as written.
        text: String,
    },
    /// The value is infinite, NaN or outside the parameter's range.
    #[error("{}: '{text}' must be a number from {} to {}{}", param.name, param.min, param.max, param.unit_suffix())]
    OutOfRange {
        /// The parameter.
        param: &'static Param,
        /// The value as written.
        text: String,
    },
    /// An argument without `=`.
    #[error("{0}: expected NAME=VALUE")]
    NotNameValue(String),
    /// A list of values with an empty one (`NAME=1,,2`).
    #[error("{0}: an empty value in the list")]
    EmptyValue(String),
    /// A second swept parameter (a run sweeps one at most).
    #[error("{0}: only one parameter can be swept at a time")]
    TwoSweeps(String),
    /// A list of values where nothing is swept.
    #[error("{0}: one value only here (a list of values sweeps the parameter, which grove study does)")]
    NoSweepHere(String),
    /// Together the overrides put `min_scale` above `max_scale`.
    #[error("min_scale {min} is above max_scale {max}")]
    ScaleOrder {
        /// The resulting `min_scale`.
        min: f32,
        /// The resulting `max_scale`.
        max: f32,
    },
}

/// One value of a parameter, checked once: a known parameter and its value (`--set` reads them
/// through [`crate::set_arg::SetArg`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    /// The parameter, one of [`Config::NAMES`].
    pub name: &'static str,
    /// Its value.
    pub value: f32,
    /// The value as it was written (for reports).
    pub text: String,
}

impl Override {
    /// The one place a parameter's text is read: `name` must be one of [`Config::PARAMS`] and
    /// `text` a finite number within its range.
    pub fn new(name: &str, text: &str) -> Result<Override, ConfigError> {
        let (name, text) = (name.trim(), text.trim());
        let param = Param::named(name).ok_or_else(|| ConfigError::Unknown { name: name.to_string() })?;
        let value: f32 =
            text.parse().map_err(|_| ConfigError::NotANumber { name: param.name, text: text.to_string() })?;
        if !value.is_finite() || value < param.min || value > param.max {
            return Err(ConfigError::OutOfRange { param, text: text.to_string() });
        }
        Ok(Override { name: param.name, value, text: text.to_string() })
    }
}

/// Overrides, at most one per parameter, in name order: what a recording header's `config`
/// holds. Written as a JSON object of name → value text (as `--set` took it) and read back
/// through [`Override::new`], so a header's parameters are checked once, when it is read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides(Vec<Override>);

impl Overrides {
    /// Sets `o`, replacing an earlier value of the same parameter.
    pub fn set(&mut self, o: Override) {
        match self.0.binary_search_by(|p| p.name.cmp(o.name)) {
            Ok(i) => self.0[i] = o,
            Err(i) => self.0.insert(i, o),
        }
    }

    /// The overrides, in name order.
    pub fn as_slice(&self) -> &[Override] {
        &self.0
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The defaults with these applied ([`Config::apply`]).
    pub fn config(&self) -> Result<Config, ConfigError> {
        let mut config = Config::default();
        config.apply(&self.0)?;
        Ok(config)
    }
}

impl FromIterator<Override> for Overrides {
    fn from_iter<I: IntoIterator<Item = Override>>(iter: I) -> Self {
        let mut all = Overrides::default();
        for o in iter {
            all.set(o);
        }
        all
    }
}

impl Serialize for Overrides {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.0.iter().map(|o| (o.name, o.text.as_str())))
    }
}

impl<'de> Deserialize<'de> for Overrides {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = std::collections::BTreeMap::<String, String>::deserialize(d)?;
        text.iter().map(|(k, v)| Override::new(k, v).map_err(serde::de::Error::custom)).collect()
    }
}

impl Config {
    /// Applies parsed overrides in order.
    pub fn apply(&mut self, overrides: &[Override]) -> Result<(), ConfigError> {
        for o in overrides {
            if let Some(field) = self.field_mut(o.name) {
                *field = o.value;
            }
        }
        if self.min_scale > self.max_scale {
            return Err(ConfigError::ScaleOrder { min: self.min_scale, max: self.max_scale });
        }
        Ok(())
    }

    /// The scales a tree can be given, `[min_scale, max_scale]` times `layout` (a room layout's
    /// scale, `crate::task::layout_scale`): its trees stand at that scale, and so do their bounds
    /// (a corner handle's, the Scale pad's).
    pub fn scale_bounds(&self, layout: f32) -> (f32, f32) {
        (self.min_scale * layout, self.max_scale * layout)
    }
}

/// The state of the model menu.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct MenuState {
    /// Whether the menu is open.
    pub open: bool,
    /// The model that Trigger plants in ray-casting mode.
    pub current_model: ModelId,
}

impl Default for ModelId {
    fn default() -> Self {
        ModelId(0)
    }
}

/// A tree being dragged by the controller ray.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Drag {
    /// The dragged tree, by entity id bits.
    pub tree: u64,
    /// Distance along the ray at which the tree is held, metres.
    pub grab_distance: f32,
    /// Offset from the grab point to the tree origin, metres.
    pub offset: glam::Vec3,
    /// Whether the tree has moved since the grab. A Trigger click on a tree (down and up with
    /// the ray still) selects it without moving, ungrounding, snapping or logging a move.
    pub moved: bool,
}

/// A touchpad gesture on the selected tree: from the first tick an axis is beyond the dead zone
/// until both are back inside it. Moved and Rotated are logged once, when it ends.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TouchpadGesture {
    /// The tree, by entity id bits.
    pub tree: u64,
    /// Whether the gesture moved the tree (not counting grab-distance changes during a drag).
    pub moved: bool,
    /// Whether the gesture turned the tree.
    pub rotated: bool,
}

/// A bounding-box handle being dragged.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HandleDrag {
    /// The handle.
    pub handle: crate::components::Handle,
    /// Scale of the tree when the drag started.
    pub start_scale: f32,
    /// Yaw of the tree when the drag started, radians.
    pub start_yaw: f32,
    /// Horizontal distance from the tree axis to the ray's grab point when the drag started.
    pub start_radius: f32,
    /// Angle of the grab point around the tree axis when the drag started, radians.
    pub start_angle: f32,
    /// Distance along the ray at which the handle was grabbed, metres.
    pub grab_distance: f32,
}

/// What the trigger is doing, tracked across ticks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Interaction {
    /// Tick at which the trigger went down, while it is held.
    pub trigger_down_tick: Option<u64>,
    /// The tree being dragged, if any.
    pub drag: Option<Drag>,
    /// The handle being dragged, if any.
    pub handle_drag: Option<HandleDrag>,
    /// A model chosen from the menu in manual mode, waiting to be spawned in front of the head.
    pub pending_spawn: Option<ModelId>,
    /// The touchpad gesture in progress, if any.
    pub touchpad: Option<TouchpadGesture>,
}

/// Buttons that went down or up during the current tick (from this tick's input events).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ButtonEdges {
    /// Buttons that went down this tick.
    pub down: crate::components::Buttons,
    /// Buttons that went up this tick.
    pub up: crate::components::Buttons,
}

/// All resources of a simulation.
pub struct Resources {
    /// Ticks completed since the start.
    pub tick: u64,
    /// The fixed step, seconds.
    pub dt: f32,
    /// The seed the RNG started from.
    pub seed: u64,
    /// The one random number generator; every random draw in a tick comes from here.
    pub rng: ChaCha8Rng,
    /// Tunable parameters.
    pub config: Config,
    /// The model catalogue.
    pub catalogue: Catalogue,
    /// The interaction mode: the built-in behaviour of the active technique.
    pub mode: Mode,
    /// The registered techniques as the world knows them (set with [`crate::Sim::set_techniques`]).
    pub techniques: crate::known_techniques::KnownTechniques,
    /// The active technique, an index into `techniques`; always one whose `base` is `mode`.
    pub technique: usize,
    /// The menu state.
    pub menu: MenuState,
    /// Ongoing trigger, drag and handle interactions.
    pub interaction: Interaction,
    /// Input events that apply at the start of the next tick, in arrival order.
    pub input: Vec<InputEvent>,
    /// Button edges of the current tick, set by the input system.
    pub edges: ButtonEdges,
    /// Everything the interaction systems did, with ticks.
    pub log: EventLog,
    /// The task being run, if any.
    pub task: Option<crate::task::TaskState>,
    /// Derived acceleration structure for ray queries; rebuilt from the world when trees or
    /// planes change. Not hashed: it is a cache of hashed state.
    pub spatial: SpatialIndex,
    /// The entities of the world's one controller, head, hit marker, anchor ball, selection, sun
    /// and wind ([`crate::single`]). Not hashed: it is a cache of the world's own entities.
    pub singles: crate::single::Singles,
    /// The selected tree's box and handle points as last computed ([`crate::interact::BoxMemo`]).
    /// Not hashed: it is a cache of values computed from hashed state.
    pub boxes: crate::interact::BoxMemo,
    /// What the task system's last search for trees on targets saw ([`crate::systems::task`]):
    /// the spatial index's tree changes, the dragged tree and the task's start tick. Not hashed:
    /// it only lets the search be skipped when it would find what it found before.
    pub task_search: Option<(u64, Option<u64>, u64)>,
    /// Each plane's hash ([`crate::components::plane_hash`]), noted when the world is built: a
    /// plane never changes afterwards, so the world hash does not hash its mesh again at every
    /// checkpoint. Not hashed: it is a cache of hashed state.
    pub plane_hashes: Vec<(hecs::Entity, u64)>,
    /// The event log's entries as the world hash serializes them, each serialized once (the log
    /// only grows). Not hashed: it is a cache of hashed state.
    pub log_bytes: crate::events::LogBytes,
}

impl Resources {
    /// Fresh resources for a simulation with this step and seed.
    pub fn new(dt: f32, seed: u64, catalogue: Catalogue) -> Resources {
        Resources {
            tick: 0,
            dt,
            seed,
            rng: ChaCha8Rng::seed_from_u64(seed),
            config: Config::default(),
            catalogue,
            mode: Mode::default(),
            techniques: crate::known_techniques::KnownTechniques::builtin(),
            technique: crate::known_techniques::KnownTechniques::of_mode(Mode::default()),
            menu: MenuState::default(),
            interaction: Interaction::default(),
            input: Vec::new(),
            edges: ButtonEdges::default(),
            log: EventLog::default(),
            task: None,
            spatial: SpatialIndex::default(),
            singles: crate::single::Singles::default(),
            boxes: crate::interact::BoxMemo::default(),
            task_search: None,
            plane_hashes: Vec::new(),
            log_bytes: crate::events::LogBytes::default(),
        }
    }

    /// Simulated time at the start of the current tick, seconds.
    pub fn time(&self) -> f64 {
        self.tick as f64 * self.dt as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_has_its_field_a_default_within_its_range_and_a_doc() {
        let defaults = Config::default();
        assert_eq!(Config::PARAMS.len(), Config::NAMES.len());
        for p in Config::PARAMS {
            let mut c = defaults.clone();
            assert_eq!(c.field_mut(p.name).map(|f| *f), Some(p.default), "{}", p.name);
            assert!(p.min <= p.default && p.default <= p.max, "{}", p.name);
            assert!(p.doc.trim().len() > 10, "{}", p.name);
        }
        assert_eq!(Param::named("snap_threshold").map(|p| (p.unit, p.max)), Some(("m", 10.0)));
    }

    #[test]
    fn a_value_is_read_once_and_checked_against_its_range() {
        let o = Override::new(" snap_threshold ", " 0.2 ").unwrap();
        assert_eq!((o.name, o.value, o.text.as_str()), ("snap_threshold", 0.2, "0.2"));
        // The ends of a range are in it; past them is refused with the range and unit.
        assert!(Override::new("touchpad_dead_zone", "1").is_ok());
        assert_eq!(
            Override::new("touchpad_dead_zone", "1.5").unwrap_err().to_string(),
            "touchpad_dead_zone: '1.5' must be a number from 0 to 1"
        );
        assert_eq!(
            Override::new("snap_threshold", "-0.1").unwrap_err().to_string(),
            "snap_threshold: '-0.1' must be a number from 0 to 10 m"
        );
        assert!(matches!(Override::new("snap_threshold", "inf"), Err(ConfigError::OutOfRange { .. })));
        assert!(matches!(Override::new("snap_threshold", "x"), Err(ConfigError::NotANumber { .. })));
        assert!(matches!(Override::new("snap", "1"), Err(ConfigError::Unknown { .. })));
        let mut config = Config::default();
        let order = [Override::new("min_scale", "5").unwrap(), Override::new("max_scale", "2").unwrap()];
        assert!(matches!(config.apply(&order), Err(ConfigError::ScaleOrder { .. })));
    }

    #[test]
    fn overrides_are_written_as_their_text_and_checked_when_read() {
        let mut all: Overrides = [("touchpad_move_rate", "3"), ("snap_threshold", "0.20")]
            .iter()
            .map(|(n, v)| Override::new(n, v).unwrap())
            .collect();
        all.set(Override::new("touchpad_move_rate", "2.5").unwrap());
        // One per parameter, in name order, each as it was written.
        let json = serde_json::to_string(&all).unwrap();
        assert_eq!(json, r#"{"snap_threshold":"0.20","touchpad_move_rate":"2.5"}"#);
        let back: Overrides = serde_json::from_str(&json).unwrap();
        assert_eq!(back, all);
        assert_eq!(back.config().unwrap().snap_threshold, 0.2);
        let bad = serde_json::from_str::<Overrides>(r#"{"snap_threshold":"20"}"#).unwrap_err().to_string();
        assert!(bad.contains("snap_threshold: '20' must be a number from 0 to 10 m"), "{bad}");
        assert!(serde_json::from_str::<Overrides>(r#"{"snap":"1"}"#).is_err());
    }
}
