//! The world's one-of-a-kind entities (the controller, the head, the hit marker, the anchor ball,
//! the selection, the sun and the wind), found by entity rather than by a query.
//!
//! A scene spawns exactly one of each ([`crate::Sim::from_scene`]) and no system spawns another,
//! so the systems read and write "the" controller. Looking it up through a hecs query each time
//! walked every archetype of the world, about twenty times a tick; [`Singles`] keeps each one's
//! entity, found once when the world is built. A slot is filled only when the world has exactly
//! one entity of that kind; an empty slot, or an entity that no longer has the component, falls
//! back to the query, so a world built another way (tests, a world without a controller) reads as
//! before.
//!
//! During a step it also keeps a copy of each single component as a system last read or wrote
//! it ([`Copies`]), so that the next system that reads it does not look it up again: the
//! controller, for one, is read by half the systems every tick. Within the built-in systems every
//! read and write of a single component goes through [`get`] and [`for_each_mut`], which keep the
//! copies true; the schedule starts each step with none, forgets them after every system of a
//! plug-in technique (which may write any component), and ends the step with none, so outside a
//! step (set-up, tests) every read looks the world up.
//!
//! It also notes whether the world has no water body at all: no system spawns one, so the
//! systems that cast rays or look for ground skip the query for water in a world without any.
//!
//! Not hashed: it is a cache of the world's own entities.

use std::cell::Cell;

use hecs::{Component, Entity, World};

use crate::components::{AnchorBall, Controller, Head, HitMarker, Selection, Sun, Wind};
use crate::water::Water;

/// A component of which a world has one entity.
pub trait Single: Component + Copy {
    /// Its slot in [`Singles`].
    const SLOT: usize;
    /// Its copy in [`Copies`].
    fn copy(copies: &Copies) -> &Cell<Option<Self>>;
    /// Whether a copy is kept during a step: for the components that several systems read each
    /// tick (for the others, keeping one would cost more than it saves).
    const KEPT: bool;
}

macro_rules! singles {
    ($($t:ident = $i:expr, $field:ident, $kept:expr),* $(,)?) => {
        $(impl Single for $t {
            const SLOT: usize = $i;
            const KEPT: bool = $kept;
            fn copy(copies: &Copies) -> &Cell<Option<Self>> {
                &copies.$field
            }
        })*
        /// How many kinds of single entity there are.
        const KINDS: usize = [$($i),*].len();
        impl Singles {
            /// Finds each kind's entity in `world`: filled when the world has exactly one.
            pub fn find(world: &World) -> Singles {
                let mut s = Singles::default();
                $(s.slots[$i] = only::<$t>(world);)*
                s.dry = world.query::<&Water>().iter().next().is_none();
                s
            }
        }
        /// Copies of the single components as the running step last read or wrote them
        /// through this module; none outside a step.
        #[derive(Clone, Debug, Default)]
        pub struct Copies {
            /// Whether a step is running (copies are kept only then).
            active: Cell<bool>,
            $($field: Cell<Option<$t>>,)*
        }
        impl Copies {
            fn clear(&self) {
                $(self.$field.set(None);)*
            }
        }
    };
}
singles!(
    Controller = 0,
    controller,
    true,
    Head = 1,
    head,
    false,
    HitMarker = 2,
    hit_marker,
    true,
    AnchorBall = 3,
    anchor_ball,
    false,
    Selection = 4,
    selection,
    true,
    Sun = 5,
    sun,
    false,
    Wind = 6,
    wind,
    false,
);

/// The entity of each single kind, where the world has exactly one, and the copies of their
/// components during a step.
#[derive(Clone, Debug, Default)]
pub struct Singles {
    slots: [Option<Entity>; KINDS],
    /// The world had no water body when it was built (false: it had one, or it is not known).
    dry: bool,
    copies: Copies,
}

fn only<T: Component>(world: &World) -> Option<Entity> {
    let mut q = world.query::<(Entity, &T)>();
    let mut it = q.iter().map(|(e, _)| e);
    let first = it.next()?;
    it.next().is_none().then_some(first)
}

impl Singles {
    /// The kind's entity, when the world had exactly one.
    pub fn entity<T: Single>(&self) -> Option<Entity> {
        self.slots[T::SLOT]
    }

    /// A step begins: from now on, the components read and written through [`get`] and
    /// [`for_each_mut`] are kept.
    pub fn begin_step(&self) {
        self.copies.clear();
        self.copies.active.set(true);
    }

    /// Forgets the kept components: after a system that may have written single components
    /// other than through this module (a plug-in technique's).
    pub fn forget(&self) {
        self.copies.clear();
    }

    /// The step is over: nothing is kept until the next one begins.
    pub fn end_step(&self) {
        self.copies.clear();
        self.copies.active.set(false);
    }
}

/// A copy of the world's `T`: its one entity's, else the first a query finds, else `None`.
/// During a step, the copy kept from the last read or write of it in this step, if any.
///
/// It takes the world mutably only to read it through `query_one_mut`, which skips the runtime
/// borrow flags that `World::get` sets and clears (the systems, its callers, hold the world
/// mutably anyway).
pub fn get<T: Single>(world: &mut World, singles: &Singles) -> Option<T> {
    get_single(world, singles).or_else(|| world.query_mut::<&T>().into_iter().next().copied())
}

/// Like [`get`], but only the value of the kind's one entity (kept or looked up), `None` where
/// the world has no single entity of the kind or it no longer has the component: where it is
/// `Some`, [`for_each_mut`] writes that one entity alone.
pub fn get_single<T: Single>(world: &mut World, singles: &Singles) -> Option<T> {
    let e = singles.entity::<T>()?;
    let copy = T::copy(&singles.copies);
    if let Some(c) = copy.get() {
        return Some(c);
    }
    let c = *world.query_one_mut::<&T>(e).ok()?;
    if T::KEPT && singles.copies.active.get() {
        copy.set(Some(c));
    }
    Some(c)
}

/// The world's water bodies ([`crate::water::bodies`]); none, without a query, in a world that
/// had none when it was built.
pub fn water(world: &World, singles: &Singles) -> Vec<(Entity, Water)> {
    if singles.dry {
        return Vec::new();
    }
    crate::water::bodies(world)
}

/// Calls `f` on every `T` of the world: on its one entity's directly when there is one.
pub fn for_each_mut<T: Single>(world: &mut World, singles: &Singles, mut f: impl FnMut(&mut T)) {
    // `query_one_mut` borrows through `&mut World`, without the runtime borrow flags.
    if let Some(e) = singles.entity::<T>()
        && let Ok(c) = world.query_one_mut::<&mut T>(e)
    {
        f(c);
        if T::KEPT && singles.copies.active.get() {
            T::copy(&singles.copies).set(Some(*c));
        }
        return;
    }
    for c in world.query_mut::<&mut T>() {
        f(c);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_kind_with_one_entity_is_found_by_entity_and_others_by_query() {
        let mut world = World::new();
        let c = world.spawn((Controller::default(),));
        world.spawn((HitMarker::default(),));
        world.spawn((HitMarker { visible: true, ..Default::default() },));
        let singles = Singles::find(&world);
        assert_eq!(singles.entity::<Controller>(), Some(c));
        // Two hit markers: no slot, and every one of them is written.
        assert_eq!(singles.entity::<HitMarker>(), None);
        assert_eq!(singles.entity::<Head>(), None);
        assert!(get::<Head>(&mut world, &singles).is_none());
        for_each_mut::<HitMarker>(&mut world, &singles, |m| m.visible = false);
        assert_eq!(world.query::<&HitMarker>().iter().filter(|m| m.visible).count(), 0);
        // Only the one entity's value is its single value: none for the two hit markers.
        assert_eq!(get_single::<Controller>(&mut world, &singles).map(|c| c.touchpad), Some(glam::Vec2::ZERO));
        assert!(get_single::<HitMarker>(&mut world, &singles).is_none());
        assert!(get::<HitMarker>(&mut world, &singles).is_some());
        // A despawned single falls back to the query: none left.
        world.despawn(c).unwrap();
        assert!(get::<Controller>(&mut world, &singles).is_none());
        let c2 = world.spawn((Controller { touchpad: glam::Vec2::ONE, ..Default::default() },));
        assert_eq!(get::<Controller>(&mut world, &singles).map(|c| c.touchpad), Some(glam::Vec2::ONE));
        // Another controller than the one found at first is no single value.
        assert!(get_single::<Controller>(&mut world, &singles).is_none());
        assert_ne!(Some(c2), singles.entity::<Controller>());
    }

    #[test]
    fn copies_are_kept_within_a_step_and_forgotten_when_something_else_may_write() {
        let mut world = World::new();
        let c = world.spawn((Controller::default(),));
        let singles = Singles::find(&world);
        let touchpad = |world: &mut World| get::<Controller>(world, &singles).map(|c| c.touchpad.x);
        // A write behind the module's back (as a plug-in or the set-up may make).
        let behind = |world: &mut World, x: f32| world.query_one_mut::<&mut Controller>(c).unwrap().touchpad.x = x;
        // Outside a step nothing is kept: every read sees the world.
        assert_eq!(touchpad(&mut world), Some(0.0));
        behind(&mut world, 1.0);
        assert_eq!(touchpad(&mut world), Some(1.0));
        // Within a step, a write through the module is what the next read gets.
        singles.begin_step();
        for_each_mut::<Controller>(&mut world, &singles, |c| c.touchpad.x = 2.0);
        assert_eq!(touchpad(&mut world), Some(2.0));
        assert_eq!(world.query_one_mut::<&Controller>(c).unwrap().touchpad.x, 2.0);
        // The schedule forgets the copies after a plug-in system, which may write anything.
        behind(&mut world, 3.0);
        singles.forget();
        assert_eq!(touchpad(&mut world), Some(3.0));
        // And keeps none once the step is over.
        singles.end_step();
        behind(&mut world, 4.0);
        assert_eq!(touchpad(&mut world), Some(4.0));
    }
}
