//! The world hash: a checkpoint of the whole simulation state.
//!
//! Every simulation component listed in [`HASHED`] and the hashed resources are serialized
//! with postcard (floats as their exact bits, little-endian) and fed to XXH3 in a stable order:
//! component types in list order, entities sorted by their id bits. Besides the total, the hash
//! reports one value per component type and one per entity, so that a replay that diverges can
//! say which component and which entity differ.

use hecs::{Entity, World};
use serde::Serialize;

use crate::aerial::AerialCrown;
pub use crate::components::plane_hash;
use crate::components::*;
use crate::resource_hash::ResourceBytes;
use crate::resources::Resources;
use crate::water::Water;

/// The world hash's table, declared once: every hashed component type in hashing order, each
/// `required` (always hashed, even when no entity has it) or `optional` (hashed only in a world
/// that has one, so that adding the type left the hash of every world without it unchanged),
/// and the place of the hashed resources among them (`resources`: the types after it were added
/// after the resources entry). From this one table come the names ([`HASHED`]), the hashing
/// ([`world_hash`]), the presence check ([`has_component`]) and the replay reader's list of what
/// to compare. It calls `$m` with any leading arguments, a `;`, and the entries.
macro_rules! hash_table {
    ($m:ident $(, $arg:expr)*) => {
        $m!($($arg),* ;
            Transform: required, Scale: required, Tree: required, Grounded: required, WindState: required,
            Plane: required, Sun: required, Wind: required, Controller: required, Head: required,
            HitMarker: required, AnchorBall: required, Selection: required, Water: optional;
            resources;
            Grass: optional, AerialCrown: optional, ScalePad: optional
        )
    };
}

/// One entry of the world hash's table ([`HASHED`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hashed {
    /// The component type's name, or `resources` for the hashed resources.
    pub name: &'static str,
    /// Hashed only in a world that has at least one entity with it; then absent from
    /// [`WorldHash::components`].
    pub optional: bool,
}

macro_rules! is_optional {
    (required) => {
        false
    };
    (optional) => {
        true
    };
}

macro_rules! table_entries {
    (; $($t:ident: $o:ident),* ; resources ; $($late:ident: $lo:ident),*) => {
        &[
            $(Hashed { name: stringify!($t), optional: is_optional!($o) },)*
            Hashed { name: "resources", optional: false },
            $(Hashed { name: stringify!($late), optional: is_optional!($lo) },)*
        ]
    };
}

/// The world hash's table in hashing order, the hashed resources in their place. `resources`
/// covers the hashed resources ([`crate::resource_hash::FIELDS`]: tick, step, seed, RNG
/// position, config, mode, menu, interaction state, event log, task state). Registered techniques' components follow, in a world that has them
/// ([`crate::known_techniques`]).
pub const HASHED: &[Hashed] = hash_table!(table_entries);

/// Whether `name` is an optional entry of the table ([`Hashed::optional`]).
pub fn is_optional(name: &str) -> bool {
    HASHED.iter().any(|h| h.name == name && h.optional)
}

/// A checkpoint: the total hash, one hash per component type and one per entity.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WorldHash {
    /// The hash of everything.
    pub total: u64,
    /// `(component name, hash)` in [`HASHED`] order, then the techniques' components.
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
        ($r:expr, $name:expr ; $($t:ident: $o:ident),* ; resources ; $($late:ident: $lo:ident),*) => {
            match $name {
                $(stringify!($t) => $r.has::<$t>(),)*
                $(stringify!($late) => $r.has::<$late>(),)*
                _ => false,
            }
        };
    }
    hash_table!(has, r, name)
}

/// Formats a hash as 16 lowercase hex digits.
pub fn hex(h: u64) -> String {
    format!("{h:016x}")
}

struct Acc<'a> {
    buf: Vec<u8>,
    /// `(entity bits, component name, value hash)` of every hashed component, in the order the
    /// types are hashed; the entity hashes are made from them at the end.
    rows: Vec<(u64, &'static str, u64)>,
    /// One component type's rows `(entity bits, value hash)`, reused from type to type.
    type_rows: Vec<(u64, u64)>,
    components: Vec<(&'static str, u64)>,
    /// The planes' hashes, computed when the world was built ([`Resources::plane_hashes`]).
    plane_hashes: &'a [(Entity, u64)],
}

impl Acc<'_> {
    fn value_hash<T: Serialize>(&mut self, value: &T) -> u64 {
        self.buf.clear();
        // Serializing plain data into a Vec cannot fail.
        let buf = std::mem::take(&mut self.buf);
        self.buf = postcard::to_extend(value, buf).unwrap_or_default();
        xxhash_rust::xxh3::xxh3_64(&self.buf)
    }

    /// Hashes every entity's `T`; nothing at all for an optional type that no entity has.
    fn component<T: HashValue + hecs::Component>(&mut self, world: &World, name: &'static str, optional: bool) {
        let mut rows = std::mem::take(&mut self.type_rows);
        rows.clear();
        for (e, c) in world.query::<(Entity, &T)>().iter() {
            let h = c.hash_value(e, self);
            rows.push((e.to_bits().get(), h));
        }
        self.rows(name, &mut rows, optional);
        self.type_rows = rows;
    }

    /// A technique's component ([`crate::known_techniques::HashedComponent`]): each entity's postcard
    /// bytes hashed as the built-in components' are; nothing when no entity has it.
    fn technique_component(&mut self, world: &World, c: &crate::known_techniques::HashedComponent) {
        let mut rows: Vec<(u64, u64)> =
            (c.rows)(world).into_iter().map(|(e, bytes)| (e, xxhash_rust::xxh3::xxh3_64(&bytes))).collect();
        self.rows(c.name, &mut rows, true);
    }

    /// Adds one component type's rows `(entity bits, value hash)` to the component and entity
    /// hashes; an optional type without rows adds nothing.
    ///
    /// A component type's hash is the XXH3 of its name, then each row's entity bits and value
    /// hash, little-endian, in entity order: the bytes are gathered and hashed at once (XXH3
    /// of bytes fed in pieces is the XXH3 of the whole).
    fn rows(&mut self, name: &'static str, rows: &mut [(u64, u64)], optional: bool) {
        rows.sort_unstable_by_key(|r| r.0);
        if rows.is_empty() && optional {
            return;
        }
        self.buf.clear();
        self.buf.extend_from_slice(name.as_bytes());
        for (e, v) in rows.iter() {
            self.buf.extend_from_slice(&e.to_le_bytes());
            self.buf.extend_from_slice(&v.to_le_bytes());
            self.rows.push((*e, name, *v));
        }
        self.components.push((name, xxhash_rust::xxh3::xxh3_64(&self.buf)));
    }

    /// Each entity's hash: the XXH3 of its components' names and value hashes (little-endian),
    /// in the order the types were hashed; sorted by entity.
    fn entities(&mut self) -> Vec<(u64, u64)> {
        // Each entity's components in the order they were hashed: sorted by entity, then by
        // their place in `rows` (the same order as a stable sort by entity).
        let mut order: Vec<(u64, u32)> = self.rows.iter().enumerate().map(|(i, r)| (r.0, i as u32)).collect();
        order.sort_unstable();
        let mut out = Vec::with_capacity(order.len());
        for group in order.chunk_by(|a, b| a.0 == b.0) {
            self.buf.clear();
            for &(_, i) in group {
                let (_, name, v) = self.rows[i as usize];
                self.buf.extend_from_slice(name.as_bytes());
                self.buf.extend_from_slice(&v.to_le_bytes());
            }
            out.push((group[0].0, xxhash_rust::xxh3::xxh3_64(&self.buf)));
        }
        out
    }
}

/// How one component value is hashed.
trait HashValue {
    fn hash_value(&self, entity: Entity, acc: &mut Acc) -> u64;
}

/// Most components are hashed from their postcard bytes.
macro_rules! serde_hashed {
    ($($t:ty),*) => {
        $(impl HashValue for $t {
            fn hash_value(&self, _: Entity, acc: &mut Acc) -> u64 {
                acc.value_hash(self)
            }
        })*
    };
}
serde_hashed!(
    Transform,
    Scale,
    Tree,
    Grounded,
    WindState,
    Sun,
    Wind,
    Controller,
    Head,
    HitMarker,
    AnchorBall,
    Selection,
    Water,
    Grass,
    AerialCrown,
    ScalePad
);

/// Plane meshes are large, so they are hashed from their raw little-endian bytes rather than
/// through serde (the same bits, much faster), and only once: a plane never changes after the
/// world is built, so its hash is the one [`Resources::plane_hashes`] noted then (a plane it
/// does not list is hashed here).
impl HashValue for Plane {
    fn hash_value(&self, entity: Entity, acc: &mut Acc) -> u64 {
        match acc.plane_hashes.iter().find(|(e, _)| *e == entity) {
            Some(&(_, h)) => {
                debug_assert_eq!(h, plane_hash(self), "a plane changed after the world was built");
                h
            }
            None => plane_hash(self),
        }
    }
}

/// Hashes the world and the hashed resources.
pub fn world_hash(world: &World, res: &Resources) -> WorldHash {
    world_hash_keeping(world, res, None)
}

/// [`world_hash`], and with `keep` the hashed resources' bytes and their fields' ends
/// ([`crate::resource_hash`]) as they were hashed, for a reader that may have to say later which
/// field differs.
pub(crate) fn world_hash_keeping(world: &World, res: &Resources, mut keep: Option<&mut ResourceBytes>) -> WorldHash {
    // Room for every row at once (most entities have a few hashed components), so the vectors
    // do not grow a step at a time at every checkpoint.
    let entities = world.len() as usize;
    let mut acc = Acc {
        buf: Vec::with_capacity(256),
        rows: Vec::with_capacity(4 * entities),
        type_rows: Vec::with_capacity(entities),
        components: Vec::with_capacity(HASHED.len() + 4),
        plane_hashes: &res.plane_hashes,
    };
    macro_rules! hash_each {
        ($acc:expr, $world:expr ; $($t:ident: $o:ident),* ; resources ; $($late:ident: $lo:ident),*) => {
            $($acc.component::<$t>($world, stringify!($t), is_optional!($o));)*
            let ends = crate::resource_hash::write(res, &mut $acc.buf);
            let rh = xxhash_rust::xxh3::xxh3_64(&$acc.buf);
            if let Some(k) = keep.as_deref_mut() {
                k.bytes.clear();
                k.bytes.extend_from_slice(&$acc.buf);
                k.ends = ends;
            }
            $acc.components.push(("resources", rh));
            $($acc.component::<$late>($world, stringify!($late), is_optional!($lo));)*
        };
    }
    hash_table!(hash_each, acc, world);
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
    // The total: the XXH3 of every component type's name and hash, little-endian, in order.
    acc.buf.clear();
    for (name, h) in &acc.components {
        acc.buf.extend_from_slice(name.as_bytes());
        acc.buf.extend_from_slice(&h.to_le_bytes());
    }
    let total = xxhash_rust::xxh3::xxh3_64(&acc.buf);
    let entities = acc.entities();
    WorldHash { total, components: acc.components, entities }
}
