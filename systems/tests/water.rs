//! Water in the simulation: the pond scene (`assets/scenes/pond.ron`) builds a `Water` entity
//! that the world hash covers; the controller ray hits the surface; Trigger on water plants
//! nothing and logs a refused planting; a tree dragged over water never arms its anchor ball
//! and cannot snap onto the pond's bed. Each test builds a world, drives it with a `Script` as a
//! participant would, and asserts the outcome.

use std::path::Path;

use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{HitTarget, Pose};
use grove_systems::events::Happening;
use grove_systems::input::Button;
use grove_systems::interact;
use grove_systems::scene::Scene;
use grove_systems::script::Script;
use grove_systems::water::WaterDef;

const SHRUB: ModelId = ModelId(3);
/// The pond's surface height and centre, as `scripts/pond-scene.py` writes them.
const SURFACE_Y: f32 = -0.15;
const CENTRE: Vec2 = Vec2::new(0.0, -6.0);

fn pond_scene() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes/pond.ron");
    Scene::load(&path).expect("the pond scene loads")
}

fn pond() -> Script {
    let scene = pond_scene();
    Script::new(Sim::from_scene(&scene, scene.seed).expect("the pond scene builds"))
}

fn water_entity(s: &Script) -> u64 {
    let ids: Vec<u64> = s.sim().water_bodies().iter().map(|(id, _)| *id).collect();
    assert_eq!(ids.len(), 1, "one pond");
    ids[0]
}

fn shift_controller(s: &mut Script, by: Vec3) {
    let c = s.controller().pose;
    s.move_controller(Pose { position: c.position + by, rotation: c.rotation });
}

#[test]
fn the_pond_is_an_entity_in_the_world_hash() {
    let s = pond();
    let id = water_entity(&s);
    let w = s.sim().water_bodies().into_iter().find(|(e, _)| *e == id).unwrap().1;
    assert_eq!(w.height, SURFACE_Y);
    assert!(w.covers_xz(Vec3::new(CENTRE.x, 0.0, CENTRE.y)));
    let h = s.sim().hash();
    assert!(h.component("Water").is_some(), "the Water component is hashed");
    assert!(h.entities.iter().any(|(e, _)| *e == id), "the pond has an entity hash");

    // The same scene with a different colour hashes differently: the component is covered.
    let mut scene = pond_scene();
    scene.water[0].colour = [0.5, 0.5, 0.5];
    let other = Sim::from_scene(&scene, scene.seed).unwrap().hash();
    assert_ne!(other.component("Water"), h.component("Water"));
    assert_ne!(other.total, h.total);

    // Without water, the type takes no part in the hash at all.
    scene.water.clear();
    let dry = Sim::from_scene(&scene, scene.seed).unwrap().hash();
    assert!(dry.component("Water").is_none());
}

#[test]
fn the_ray_hits_the_surface_not_the_bed_below() {
    let mut s = pond();
    let id = water_entity(&s);
    let target = Vec3::new(0.5, SURFACE_Y, -4.0);
    s.point_at(target);
    let m = s.sim().hit_marker();
    assert!(m.visible);
    assert_eq!(m.target, HitTarget::Water(id));
    assert!((m.position - target).length() < 1e-3, "hit at {} instead of {target}", m.position);
    let from = s.controller().ray_origin();
    assert!((m.distance - from.distance(target)).abs() < 1e-3);
    assert_eq!(m.normal, Vec3::Y, "the surface faces up, towards the controller");
}

#[test]
fn trigger_on_water_plants_nothing_and_logs_a_refusal() {
    let mut s = pond();
    let id = water_entity(&s);
    let trees = s.sim().tree_ids();
    let target = Vec3::new(-0.5, SURFACE_Y, -3.5);
    s.choose_model(SHRUB).point_at(target);
    let from = s.sim().log().entries.len();
    s.press(Button::Trigger);
    assert_eq!(s.sim().tree_ids(), trees, "no tree was planted");
    let new: Vec<&Happening> = s.sim().log().entries[from..].iter().map(|e| &e.what).collect();
    assert_eq!(new.len(), 1, "{new:?}");
    let Happening::PlantingRefused { water, position } = new[0] else { panic!("{new:?}") };
    assert_eq!(*water, id);
    assert!((*position - target).length() < 1e-3);

    // On the shore, outside the pond, the same press plants.
    s.point_at(Vec3::new(-0.5, 0.0, 2.0)).press(Button::Trigger);
    assert_eq!(s.sim().tree_ids().len(), trees.len() + 1, "the shore is ground");
}

#[test]
fn a_tree_dragged_over_water_never_arms_and_cannot_snap() {
    let mut s = pond();
    // Plant a shrub on the shore south of the pond and grab it.
    let base = Vec3::new(0.0, 0.0, 1.5);
    s.choose_model(SHRUB).point_at(base).press(Button::Trigger);
    let id = *s.sim().tree_ids().last().unwrap();
    s.point_at(base + Vec3::Y * 0.5).hold(Button::Trigger);
    assert!(s.sim().interaction().drag.is_some(), "grabbed");
    // On the shore the anchor ball is white: the tree stands on the ground.
    shift_controller(&mut s, Vec3::new(0.0, 0.05, 0.0));
    assert!(s.sim().anchor_ball().armed, "white over dry ground");

    let lowest = s.sim().catalogue().get(SHRUB).unwrap().lowest_point();
    // The bed, as the scene script builds it: y = −1.5 (1 − (r / 5.6)²) at r metres from the
    // centre; it lies under the surface where that is below −0.15 m, i.e. r < 5.6 √0.9 ≈ 5.31 m.
    // (Between there and the outline the bed is a shore above the surface: dry ground.)
    let bed_y = |t: Vec3| {
        let r = Vec2::new(t.x - CENTRE.x, t.z - CENTRE.y).length();
        -1.5 * (1.0 - (r / 5.6) * (r / 5.6))
    };
    // Over the water, 0.1 m at a time, 5 m north, then down to the bed 3.5 m from the centre.
    let mut over_water = 0;
    for _ in 0..50 {
        shift_controller(&mut s, Vec3::new(0.0, 0.0, -0.1));
        let t = s.sim().tree(id).unwrap().transform.translation;
        if bed_y(t) < SURFACE_Y - 1e-3 {
            over_water += 1;
            assert!(!s.sim().anchor_ball().armed, "armed over water at {t}");
        }
    }
    assert!(over_water > 20, "the drag went well over the pond ({over_water} ticks)");
    // The bed at 3.5 m from the centre: y = −1.5 (1 − (3.5 / 5.6)²), as the scene script builds it.
    let t = s.sim().tree(id).unwrap().transform.translation;
    let bed = bed_y(t);
    let low = interact::lowest_point_y(t.y, lowest, 1.0);
    // Lower the tree so that its lowest point is 5 cm above the bed: on dry ground this arms.
    let threshold = s.sim().config().snap_threshold;
    assert!(0.05 < threshold);
    shift_controller(&mut s, Vec3::new(0.0, bed + 0.05 - low, 0.0));
    let low = interact::lowest_point_y(s.sim().tree(id).unwrap().transform.translation.y, lowest, 1.0);
    assert!((low - (bed + 0.05)).abs() < 0.02, "lowest point {low}, bed {bed}");
    let ball = s.sim().anchor_ball();
    assert!(!ball.visible && !ball.armed, "no ball over water: {ball:?}");

    let from = s.sim().log().entries.len();
    let held = s.sim().tree(id).unwrap().transform;
    s.release(Button::Trigger);
    let kinds: Vec<&str> = s.sim().log().entries[from..].iter().map(|e| e.what.kind()).collect();
    assert_eq!(kinds, ["released_green", "moved"]);
    assert_eq!(s.sim().tree(id).unwrap().transform, held, "it stays where it was let go");
    assert!(!s.sim().tree(id).unwrap().grounded.0, "not grounded in the pond");
    let all: Vec<&str> = s.sim().log().entries.iter().map(|e| e.what.kind()).collect();
    assert!(!all[from..].contains(&"snapped"));
}

fn def(polygon: Vec<Vec2>) -> WaterDef {
    WaterDef {
        name: "p".into(),
        polygon,
        height: 0.0,
        depth: 1.0,
        colour: [0.1, 0.2, 0.3],
        ripples: 1.0,
        ripple_speed: 0.05,
    }
}

#[test]
fn bad_water_fields_give_one_clear_line() {
    let square = vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    let cases: Vec<(WaterDef, &str)> = vec![
        (def(vec![Vec2::ZERO, Vec2::X]), "at least 3"),
        (def(vec![Vec2::ZERO, Vec2::new(2.0, 2.0), Vec2::new(2.0, 0.0), Vec2::new(0.0, 2.0)]), "cross"),
        (def(vec![Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0)]), "no area"),
        (def(vec![Vec2::ZERO, Vec2::X, Vec2::new(f32::NAN, 1.0)]), "NaN"),
        (WaterDef { depth: 0.0, ..def(square.clone()) }, "depth"),
        (WaterDef { depth: -1.0, ..def(square.clone()) }, "depth"),
        (WaterDef { colour: [0.1, 1.5, 0.0], ..def(square.clone()) }, "colour"),
        (WaterDef { ripples: -0.1, ..def(square.clone()) }, "ripples"),
        (WaterDef { height: f32::INFINITY, ..def(square.clone()) }, "height"),
        (WaterDef { ripple_speed: 11.0, ..def(square.clone()) }, "ripple_speed"),
    ];
    for (w, needle) in cases {
        let mut scene = pond_scene();
        scene.water = vec![w];
        let e = scene.validate().expect_err(needle).to_string();
        assert!(e.contains(needle) && e.contains("water 'p'") && !e.contains('\n'), "{e}");
    }
}
