//! The world hash: a checkpoint of the whole simulation state.
//!
//! Every simulation component listed in [`COMPONENTS`] and the hashed resources are serialized
//! with postcard (floats as their exact bits, little-endian) and fed to XXH3 in a stable order:
//! component types in list order, entities sorted by their id bits. Besides the total, the hash
//! reports one value per component type and one per entity, so that a replay that diverges can
//! say which component and which entity differ.

use std::collections::BTreeMap;

use hecs::{Entity, World};
use serde::Serialize;
use xxhash_rust::xxh3::Xxh3;

use crate::components::*;
use crate::resources::Resources;
use crate::aerial::AerialCrown;
use crate::water::Water;

/// The hashed component types, in hashing order: the one list from which the names
/// ([`COMPONENTS`]), the hashing ([`world_hash`]) and the presence check ([`has_component`]) are
/// made, so that a component can never be named but not hashed, or the reverse. It calls `$m`
/// with any leading arguments, a `;`, and the type names.
macro_rules! hashed_components {
    ($m:ident $(, $arg:expr)*) => {
        $m!($($arg),* ; Transform, Scale, Tree, Grounded, WindState, Plane, Sun, Wind, Controller, Head, HitMarker, AnchorBall, Selection, Water)
    };
}

macro_rules! component_names {
    (; $($t:ident),*) => {
        &[$(stringify!($t),)* "resources"]
    };
}

/// The names of the hashed component types, in hashing order. `resources` covers the hashed
/// resources (tick, RNG position, mode, menu, interaction state, event log, task state, config).
pub const COMPONENTS: &[&str] = hashed_components!(component_names);

/// Component types that take part in the hash only in a world that has at least one of them,
/// so that adding such a type leaves the hash of every world without it unchanged (a scene
/// without water or grass hashes as it did before they existed). Such a type is then absent
/// from [`WorldHash::components`]. `Water` is hashed in its place among [`COMPONENTS`], before
/// the resources; the others, added later, after the resources ([`LATE_COMPONENTS`]). The
/// rule is the same for all: no entity with it, nothing hashed.
pub const OPTIONAL: &[&str] = &["Water", "Grass", "AerialCrown"];

/// A checkpoint: the total hash, one hash per component type and one per entity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorldHash {
    /// The hash of everything.
    pub total: u64,
    /// `(component name, hash)` in [`COMPONENTS`] order.
    pub components: Vec<(&'static str, u64)>,
    /// `(entity id bits, hash of all its components)`, sorted by entity.
    pub entities: Vec<(u64, u64)>,
}

impl WorldHash {
    /// The hash of one component type, if it is known.
    pub fn component(&self, name: &str) -> Option<u64> {
        self.components.iter().find(|(n, _)| *n == name).map(|(_, h)| *h)
    }
}

/// Whether the entity with these id bits has the hashed component called `name`.
pub fn has_component(world: &World, entity_bits: u64, name: &str) -> bool {
    let Some(e) = Entity::from_bits(entity_bits) else { return false };
    let Ok(r) = world.entity(e) else { return false };
    macro_rules! has {
        ($r:expr, $name:expr ; $($t:ident),*) => {
            match $name {
                $(stringify!($t) => $r.has::<$t>(),)*
                _ => false,
            }
        };
    }
    hashed_components!(has, r, name) || (name == "Grass" && r.has::<Grass>()) || (name == "AerialCrown" && r.has::<AerialCrown>())
}

/// The [`OPTIONAL`] components hashed after the resources, in this order. Each is hashed from
/// its postcard bytes like the others.
pub const LATE_COMPONENTS: &[&str] = &["Grass", "AerialCrown"];

/// Formats a hash as 16 lowercase hex digits.
pub fn hex(h: u64) -> String {
    format!("{h:016x}")
}

struct Acc {
    buf: Vec<u8>,
    entities: BTreeMap<u64, Xxh3>,
    components: Vec<(&'static str, u64)>,
}

impl Acc {
    fn value_hash<T: Serialize>(&mut self, value: &T) -> u64 {
        self.buf.clear();
        // Serializing plain data into a Vec cannot fail.
        let buf = std::mem::take(&mut self.buf);
        self.buf = postcard::to_extend(value, buf).unwrap_or_default();
        xxhash_rust::xxh3::xxh3_64(&self.buf)
    }

    /// Hashes every entity's `T`; nothing at all for an [`OPTIONAL`] type that no entity has.
    fn component<T: HashValue + hecs::Component>(&mut self, world: &World, name: &'static str) {
        let mut rows: Vec<(u64, u64)> = Vec::new();
        for (e, c) in world.query::<(Entity, &T)>().iter() {
            let h = c.hash_value(self);
            rows.push((e.to_bits().get(), h));
        }
        self.rows(name, rows, OPTIONAL.contains(&name));
    }

    /// A technique's component ([`crate::known_techniques::HashedComponent`]): each entity's postcard
    /// bytes hashed as the built-in components' are; nothing when no entity has it.
    fn technique_component(&mut self, world: &World, c: &crate::known_techniques::HashedComponent) {
        let rows = (c.rows)(world).into_iter().map(|(e, bytes)| (e, xxhash_rust::xxh3::xxh3_64(&bytes))).collect();
        self.rows(c.name, rows, true);
    }

    /// Adds one component type's rows `(entity bits, value hash)` to the component and entity
    /// hashes; an optional type without rows adds nothing.
    fn rows(&mut self, name: &'static str, mut rows: Vec<(u64, u64)>, optional: bool) {
        rows.sort_unstable_by_key(|r| r.0);
        if rows.is_empty() && optional {
            return;
        }
        let mut h = Xxh3::new();
        h.update(name.as_bytes());
        for (e, v) in &rows {
            h.update(&e.to_le_bytes());
            h.update(&v.to_le_bytes());
            let eh = self.entities.entry(*e).or_default();
            eh.update(name.as_bytes());
            eh.update(&v.to_le_bytes());
        }
        self.components.push((name, h.digest()));
    }
}

/// How one component value is hashed.
trait HashValue {
    fn hash_value(&self, acc: &mut Acc) -> u64;
}

/// Most components are hashed from their postcard bytes.
macro_rules! serde_hashed {
    ($($t:ty),*) => {
        $(impl HashValue for $t {
            fn hash_value(&self, acc: &mut Acc) -> u64 {
                acc.value_hash(self)
            }
        })*
    };
}
serde_hashed!(Transform, Scale, Tree, Grounded, WindState, Sun, Wind, Controller, Head, HitMarker, AnchorBall, Selection, Water, Grass, AerialCrown);

/// Plane meshes are large, so they are hashed from their raw little-endian bytes rather than
/// through serde (the same bits, much faster).
impl HashValue for Plane {
    fn hash_value(&self, _: &mut Acc) -> u64 {
        plane_hash(self)
    }
}

#[derive(Serialize)]
struct HashedResources<'a> {
    tick: u64,
    dt: f32,
    seed: u64,
    rng_word_pos: u128,
    config: &'a crate::resources::Config,
    mode: crate::mode::Mode,
    menu: &'a crate::resources::MenuState,
    interaction: &'a crate::resources::Interaction,
    log: &'a crate::events::EventLog,
    task: &'a Option<crate::task::TaskState>,
}

/// The hash of a plane: its name, then its vertices' and triangles' bytes, little-endian.
pub fn plane_hash(p: &Plane) -> u64 {
    let mut h = Xxh3::new();
    h.update(p.name.as_bytes());
    h.update(&(p.vertices.len() as u64).to_le_bytes());
    if cfg!(target_endian = "little") {
        h.update(bytemuck::cast_slice(&p.vertices));
        h.update(bytemuck::cast_slice(&p.triangles));
    } else {
        for v in &p.vertices {
            for x in v.to_array() {
                h.update(&x.to_le_bytes());
            }
        }
        for t in &p.triangles {
            for i in t {
                h.update(&i.to_le_bytes());
            }
        }
    }
    h.digest()
}

/// Hashes the world and the hashed resources.
pub fn world_hash(world: &World, res: &Resources) -> WorldHash {
    let mut acc = Acc { buf: Vec::with_capacity(256), entities: BTreeMap::new(), components: Vec::new() };
    macro_rules! hash_each {
        ($acc:expr, $world:expr ; $($t:ident),*) => {
            $($acc.component::<$t>($world, stringify!($t));)*
        };
    }
    hashed_components!(hash_each, acc, world);
    let r = HashedResources {
        tick: res.tick,
        dt: res.dt,
        seed: res.seed,
        rng_word_pos: res.rng.get_word_pos(),
        config: &res.config,
        mode: res.mode,
        menu: &res.menu,
        interaction: &res.interaction,
        log: &res.log,
        task: &res.task,
    };
    let rh = acc.value_hash(&r);
    acc.components.push(("resources", rh));
    debug_assert!(acc.components.len() <= COMPONENTS.len());
    // The LATE_COMPONENTS, after the resources.
    acc.component::<Grass>(world, "Grass");
    acc.component::<AerialCrown>(world, "AerialCrown");
    // The techniques' components, through the same table; then, while a plug-in technique is
    // active, its name and version. Neither exists in a world of the built-in techniques.
    for t in res.techniques.iter() {
        for c in &t.components {
            acc.technique_component(world, c);
        }
    }
    let active = res.techniques.at(res.technique);
    if !active.is_builtin() {
        let h = acc.value_hash(&(active.name, active.version));
        acc.components.push(("technique", h));
    }
    let mut total = Xxh3::new();
    for (name, h) in &acc.components {
        total.update(name.as_bytes());
        total.update(&h.to_le_bytes());
    }
    let entities: Vec<(u64, u64)> = acc.entities.into_iter().map(|(e, h)| (e, h.digest())).collect();
    WorldHash { total: total.digest(), components: acc.components, entities }
}
