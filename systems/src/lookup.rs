//! One entity's components looked up through a prepared hecs query, kept per thread.
//!
//! `World::query_one_mut` finds each component type of the query in the entity's archetype by a
//! binary search over its type ids: for the three components of a tree's box, about 250
//! instructions a call, twice a tick while a tree is selected. A `hecs::PreparedQuery` keeps each
//! matching archetype's columns from one call to the next and finds the entity's row directly;
//! it prepares itself again whenever the world it is given is another one or has gained an
//! archetype (hecs's own check), so the answer is always `query_one_mut`'s.
//!
//! A prepared query cannot move between threads (its columns are raw pointers), while a `Sim`
//! may, so it is kept in a thread-local slot rather than in `Resources`; two worlds used in turn
//! on one thread only make it prepare itself more often.

use std::cell::RefCell;

use hecs::{Entity, PreparedQuery, World};

use crate::catalogue::ModelId;
use crate::components::{Scale, Transform, Tree};

thread_local! {
    static TREE_PARTS: RefCell<PreparedQuery<(&'static Tree, &'static Transform, &'static Scale)>> = RefCell::new(PreparedQuery::new());
}

/// A tree's model, transform and scale: what `query_one_mut::<(&Tree, &Transform, &Scale)>`
/// gives, or `None` where it gives an error (no such entity, or not a tree).
pub fn tree_parts(world: &mut World, e: Entity) -> Option<(ModelId, Transform, f32)> {
    TREE_PARTS.with_borrow_mut(|q| q.view_mut(world).get_mut(e).map(|(tree, t, s)| (tree.model, *t, s.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_prepared_look_up_answers_as_query_one_mut_across_worlds_and_new_archetypes() {
        let tree = |m: u8| Tree { model: ModelId(m) };
        let t = |x: f32| Transform { translation: glam::Vec3::new(x, 0.0, 0.0), yaw: x };
        let direct = |world: &mut World, e: Entity| {
            world.query_one_mut::<(&Tree, &Transform, &Scale)>(e).ok().map(|(tree, t, s)| (tree.model, *t, s.0))
        };
        let mut a = World::new();
        let mut b = World::new();
        let a1 = a.spawn((tree(1), t(1.0), Scale(1.5)));
        let b1 = b.spawn((tree(2), t(2.0), Scale(2.5)));
        let not_a_tree = a.spawn((t(3.0), Scale(3.0)));
        for _ in 0..2 {
            // Two worlds in turn on one thread.
            assert_eq!(tree_parts(&mut a, a1), direct(&mut a, a1));
            assert_eq!(tree_parts(&mut b, b1), direct(&mut b, b1));
            assert_eq!(tree_parts(&mut a, not_a_tree), direct(&mut a, not_a_tree));
        }
        assert_eq!(tree_parts(&mut a, a1), Some((ModelId(1), t(1.0), 1.5)));
        assert_eq!(tree_parts(&mut a, not_a_tree), None);
        // A new archetype (a tree with one more component), a moved tree, a despawned one.
        let a2 = a.spawn((tree(4), t(4.0), Scale(4.0), crate::components::Grounded::default()));
        a.query_one_mut::<&mut Transform>(a1).unwrap().yaw = 0.25;
        assert_eq!(tree_parts(&mut a, a2), Some((ModelId(4), t(4.0), 4.0)));
        assert_eq!(tree_parts(&mut a, a1), direct(&mut a, a1));
        a.despawn(a1).unwrap();
        assert_eq!(tree_parts(&mut a, a1), None);
        // Its slot reused by another entity (another generation): still none for the old one.
        let reused = a.spawn((tree(5), t(5.0), Scale(5.0)));
        assert_eq!(tree_parts(&mut a, a1), None);
        assert_eq!(tree_parts(&mut a, reused), Some((ModelId(5), t(5.0), 5.0)));
    }
}
