//! Picking hits the tree, not its padded box: a ray to the ground under a crown's rim, beside
//! the trunk, reaches the ground; rays at the trunk and into the crown still hit the tree.

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::catalogue::Catalogue;
use grove_systems::scene::Scene;

/// The study scene with its trees removed and one broadleaf-mesh tree at (-7, ground, -1.5),
/// with the given catalogue. Returns the sim, the tree's entity and its base position.
fn one_tree(catalogue: Catalogue) -> (Sim, hecs::Entity, Vec3) {
    let mut sim = Sim::from_scene_with(&Scene::builtin("study").unwrap(), 1, catalogue).unwrap();
    let old: Vec<hecs::Entity> = sim.tree_ids().into_iter().filter_map(hecs::Entity::from_bits).collect();
    for e in old {
        sim.set_up().despawn(e).unwrap();
    }
    sim.set_up().refresh_spatial();
    let model = sim.catalogue().by_name("broadleaf-mesh").unwrap().id;
    let e = sim.spawn_tree(model, Vec3::new(-7.0, 0.0, -1.5), 0.0, 1.0, true);
    let base = sim.tree(e.to_bits().get()).unwrap().transform.translation;
    sim.set_up().refresh_spatial();
    (sim, e, base)
}

/// The entity a ray from `from` towards `to` hits first.
fn first_hit(sim: &Sim, from: Vec3, to: Vec3) -> Option<hecs::Entity> {
    let dir = (to - from).normalize();
    sim.spatial().cast(from, dir, 100.0, None).map(|h| h.entity)
}

#[test]
fn the_ground_beside_the_trunk_under_the_crown_can_be_pointed_at() {
    let cat = Catalogue::builtin();
    let m = cat.by_name("broadleaf-mesh").unwrap().clone();
    let pick = m.pick.expect("the model has a pick shape");
    // Up to 2 m a broadleaf is only its trunk.
    let below_2m = ((2.0 - pick.bottom) / pick.band_height()) as usize;
    assert!(below_2m >= 2 && pick.radii[..below_2m].iter().all(|r| *r < 0.5), "{pick:?}");
    let (sim, tree, base) = one_tree(cat.clone());
    // A ground point halfway out under the crown, and an eye 1 m above the ground 6 m away in
    // the same direction: the ray stays below about 0.6 m near the tree, under the crown and
    // well clear of the trunk.
    let reach = 0.5 * m.bounds_max.x;
    let ground = base + Vec3::new(reach, 0.0, 0.0);
    let eye = ground + Vec3::new(6.0, 1.0, 0.0);
    let hit = first_hit(&sim, eye, ground).expect("the ray hits something");
    assert_ne!(hit, tree, "the ground under the crown is not the tree");

    // The same ray against the padded box (a catalogue without pick shapes) hits the tree, as
    // it did before.
    let mut boxed = cat.clone();
    for m in &mut boxed.models {
        m.pick = None;
    }
    let (sim_box, tree_box, _) = one_tree(boxed);
    assert_eq!(first_hit(&sim_box, eye, ground), Some(tree_box), "the box covers that ground");

    // The trunk and the crown are still hit.
    let trunk = base + Vec3::Y * 1.0;
    assert_eq!(first_hit(&sim, trunk + Vec3::new(5.0, 0.0, 0.3), trunk), Some(tree), "the trunk");
    let crown = base + Vec3::Y * (0.5 * (pick.bottom + pick.top));
    assert_eq!(first_hit(&sim, crown + Vec3::new(0.0, 0.0, 12.0), crown), Some(tree), "the crown");
    // Past the crown's side, the ray goes by.
    let widest = pick.radii.iter().fold(0.0f32, |a, r| a.max(*r));
    let beside = crown + Vec3::new(widest + 1.5, 0.0, 0.0);
    assert_ne!(first_hit(&sim, beside + Vec3::new(0.0, 0.0, 12.0), beside), Some(tree));
}

#[test]
fn a_ray_starting_inside_the_crown_hits_at_distance_zero_but_not_inside_the_box_corner() {
    let cat = Catalogue::builtin();
    let m = cat.by_name("broadleaf-mesh").unwrap().clone();
    let pick = m.pick.unwrap();
    let (sim, tree, base) = one_tree(cat);
    let inside = base + Vec3::Y * (0.5 * (pick.bottom + pick.top));
    let h = sim.spatial().cast_trees(inside, Vec3::X, 50.0, None).unwrap();
    assert_eq!((h.entity, h.distance), (tree, 0.0));
    // Low beside the trunk, inside the tree's box but outside its shape: looking up at the
    // crown's underside, the tree is hit above, not at the start.
    let low = base + Vec3::new(0.5 * m.bounds_max.x, 0.3, 0.0);
    let h = sim.spatial().cast_trees(low, Vec3::Y, 50.0, None).expect("the crown above");
    assert_eq!(h.entity, tree);
    assert!(h.distance > 0.3, "{}", h.distance);
}
