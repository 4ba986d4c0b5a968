//! What the world itself knows of the registered techniques: names, versions, base modes and
//! hashed components, without their systems. [`crate::resources::Resources`] holds this (the
//! input system switches technique by name, the world hash covers the components and the
//! active technique), so that resources never depend on the systems' type, which names them.
//! A leaf: it imports only [`crate::mode`]. [`crate::technique`] builds it from the full
//! registrations.

use std::sync::Arc;

use hecs::{Entity, World};
use serde::Serialize;

use crate::mode::Mode;

/// A technique's component type as the world hash sees it: a name and a function listing
/// `(entity id bits, postcard bytes)` for every entity that has it. Like the built-in optional
/// components, it takes part in the hash only in a world where some entity has it.
#[derive(Clone, Copy)]
pub struct HashedComponent {
    /// The component's name in [`crate::hash::WorldHash::components`].
    pub name: &'static str,
    /// Every entity with the component and its serialized bytes.
    pub rows: fn(&World) -> Vec<(u64, Vec<u8>)>,
}

impl HashedComponent {
    /// The hashed form of a serializable component type `T`.
    pub fn of<T: Serialize + hecs::Component>(name: &'static str) -> HashedComponent {
        HashedComponent { name, rows: rows_of::<T> }
    }
}

fn rows_of<T: Serialize + hecs::Component>(world: &World) -> Vec<(u64, Vec<u8>)> {
    // Serializing plain data into a Vec cannot fail.
    world
        .query::<(Entity, &T)>()
        .iter()
        .map(|(e, c)| (e.to_bits().get(), postcard::to_allocvec(c).unwrap_or_default()))
        .collect()
}

/// One registered technique as the world knows it.
#[derive(Clone)]
pub struct Known {
    /// Its name, e.g. "gaze-dwell".
    pub name: &'static str,
    /// Its version.
    pub version: u32,
    /// One line for menus.
    pub about: &'static str,
    /// The built-in behaviour the shared systems apply while it is active.
    pub base: Mode,
    /// Its component types.
    pub components: Vec<HashedComponent>,
}

impl Known {
    /// Whether this is one of the two built-in techniques.
    pub fn is_builtin(&self) -> bool {
        self.name == Mode::RayCasting.name() || self.name == Mode::Manual.name()
    }

    fn builtin(mode: Mode, about: &'static str) -> Known {
        Known { name: mode.name(), version: 1, about, base: mode, components: Vec::new() }
    }
}

/// A list of registered techniques: the two built-in ones first (ray-casting at 0, manual at
/// 1), then the plug-ins in registration order. Cheap to clone. The world holds one of
/// [`Known`] ([`KnownTechniques`]); the simulation one of full registrations
/// ([`crate::technique::Techniques`]).
#[derive(Clone)]
pub struct Registry<T>(pub(crate) Arc<Vec<T>>);

/// What a [`Registry`] needs of its entries.
pub trait Registered {
    /// The technique's name.
    fn name(&self) -> &'static str;
    /// Its version.
    fn version(&self) -> u32;
}

impl Registered for Known {
    fn name(&self) -> &'static str {
        self.name
    }
    fn version(&self) -> u32 {
        self.version
    }
}

/// The registered techniques as the world knows them.
pub type KnownTechniques = Registry<Known>;

impl<T: Registered> std::fmt::Debug for Registry<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.0.iter().map(|t| (t.name(), t.version()))).finish()
    }
}

/// The built-in techniques' one-line descriptions.
pub const RAY_CASTING_ABOUT: &str = "point the controller ray at the ground and pull Trigger to plant";
/// See [`RAY_CASTING_ABOUT`].
pub const MANUAL_ABOUT: &str = "choose a model from the menu, then drag it into place";

impl Registry<Known> {
    /// Only the two built-in techniques.
    pub fn builtin() -> KnownTechniques {
        Registry(Arc::new(vec![
            Known::builtin(Mode::RayCasting, RAY_CASTING_ABOUT),
            Known::builtin(Mode::Manual, MANUAL_ABOUT),
        ]))
    }
}

impl<T: Registered> Registry<T> {
    /// From a list whose first two are the built-in techniques.
    pub fn from_list(list: Vec<T>) -> Registry<T> {
        Registry(Arc::new(list))
    }

    /// The technique at an index (0 = ray-casting, 1 = manual).
    pub fn at(&self, index: usize) -> &T {
        self.0.get(index).unwrap_or(&self.0[0])
    }

    /// The index of a technique by name.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.0.iter().position(|t| t.name() == name)
    }

    /// A technique by name.
    pub fn get(&self, name: &str) -> Option<&T> {
        self.0.iter().find(|t| t.name() == name)
    }

    /// The index of the built-in technique of a mode.
    pub fn of_mode(mode: Mode) -> usize {
        match mode {
            Mode::RayCasting => 0,
            Mode::Manual => 1,
        }
    }

    /// Every registered technique, built-in ones first.
    pub fn iter(&self) -> impl Iterator<Item = &T> {
        self.0.iter()
    }

    /// The registered names, comma-separated, for error messages.
    pub fn names(&self) -> String {
        self.0.iter().map(|t| t.name()).collect::<Vec<_>>().join(", ")
    }

    /// The error for a name that is not registered.
    pub fn unknown(&self, name: &str) -> String {
        format!("technique '{}' is not registered; registered: {}", name.escape_debug(), self.names())
    }
}
