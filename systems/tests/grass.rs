//! Grass patches: the park's patches become `Grass` entities in the world hash, blade placement
//! is a pure function of the patch that never stands a blade over a hole, and bad grass fields
//! are refused with one line.

use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::grass::{Blade, GrassKind, place_blades};
use grove_systems::scene::Scene;

fn park_text() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/park.ron")).expect("park scene")
}

fn park() -> Scene {
    // Loaded from its file, so that the species bank it names is found beside it.
    Scene::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../assets/scenes/park.ron")))
        .expect("the park scene loads")
}

/// The blades of every blade patch of a world, patch by patch in entity order.
fn blades_of(sim: &Sim) -> Vec<Vec<Blade>> {
    let mut planes: Vec<(String, Vec<Vec3>, Vec<[u32; 3]>)> = Vec::new();
    sim.for_each_plane(|_, p| planes.push((p.name.clone(), p.vertices.clone(), p.triangles.clone())));
    let views: Vec<(&str, &[Vec3], &[[u32; 3]])> =
        planes.iter().map(|(n, v, t)| (n.as_str(), v.as_slice(), t.as_slice())).collect();
    sim.grass_patches().iter().map(|(_, g)| place_blades(g, &views)).collect()
}

#[test]
fn every_patch_is_a_grass_entity_in_the_hash() {
    let scene = park();
    let sim = Sim::from_scene(&scene, scene.seed).unwrap();
    let kinds: Vec<GrassKind> = sim.grass_patches().iter().map(|(_, g)| g.def.kind).collect();
    assert_eq!(kinds.len(), 2);
    assert!(kinds.contains(&GrassKind::Shells) && kinds.contains(&GrassKind::Blades));
    let h = sim.hash();
    assert!(h.component("Grass").is_some(), "the grass is hashed");

    // A denser lawn is another world: its hash differs in the grass and nowhere else.
    let mut denser = scene.clone();
    denser.grass[1].density = 301.0;
    let h2 = Sim::from_scene(&denser, denser.seed).unwrap().hash();
    assert_ne!(h.total, h2.total);
    for (name, v) in &h.components {
        if *name != "Grass" {
            assert_eq!(Some(*v), h2.component(name), "{name} changed with the grass density");
        }
    }

    // The same scene without grass has no grass in its hash, and everything else (the RNG's
    // position included, in "resources") is the same: grass takes nothing from the sim's RNG.
    let mut bare = scene.clone();
    bare.grass.clear();
    let h3 = Sim::from_scene(&bare, bare.seed).unwrap().hash();
    assert!(h3.component("Grass").is_none());
    for (name, v) in &h3.components {
        assert_eq!(Some(*v), h.component(name), "{name} differs between the park with and without grass");
    }
}

#[test]
fn placement_is_deterministic_and_fills_the_lawn() {
    let scene = park();
    let a = blades_of(&Sim::from_scene(&scene, scene.seed).unwrap());
    let b = blades_of(&Sim::from_scene(&scene, 12345).unwrap());
    // The placement follows the scene's seed, not the simulation's.
    assert_eq!(a, b);
    let blades: Vec<&Blade> = a.iter().flatten().collect();
    // The east lawn: 10 x 8 m at 300 blades per m², less a hole of radius 0.8 m (about
    // 2 m²): about 23,400 blades.
    let expected = (80.0 - std::f32::consts::PI * 0.64) * 300.0;
    let n = blades.len() as f32;
    assert!((n - expected).abs() < 0.03 * expected, "{n} blades, about {expected} expected");
    for bl in &blades {
        let p = bl.position;
        assert!((1.0..=11.0).contains(&p.x) && (0.0..=8.0).contains(&p.z), "a blade outside its polygon at {p}");
        assert!((0.12..=0.3).contains(&bl.height), "height {}", bl.height);
    }
    // Another scene seed moves the blades.
    let mut other = scene.clone();
    other.seed += 1;
    let c = blades_of(&Sim::from_scene(&other, other.seed).unwrap());
    assert_ne!(a, c);
}

#[test]
fn no_blade_stands_over_a_hole() {
    // A lawn of blades over the whole of a plane with three holes, one of them at a corner.
    let text = park_text()
        .replace("polygon: [(1.0, 0.0), (11.0, 0.0), (11.0, 8.0), (1.0, 8.0)],", "")
        .replace("density: 300.0,", "density: 40.0,")
        .replace(
            "(center: (6.0, 4.0), radius: 0.8),",
            "(center: (6.0, 4.0), radius: 0.8), (center: (-12.0, -10.0), radius: 2.3),",
        );
    let mut scene = Scene::parse(&text, "holes.ron").unwrap();
    // The pond's bed (a separate plane whose rim overlaps the ground by a few millimetres) and
    // its water are not part of this test; the ground's hole under the pond stays.
    scene.planes.retain(|p| p.name != "pond bed");
    scene.water.clear();
    // Nor are its trees, from a bank beside the scene's file (this text has no folder).
    scene.trees.clear();
    scene.banks.clear();
    let sim = Sim::from_scene(&scene, scene.seed).unwrap();
    let holes = [
        (Vec2::new(-6.0, -3.0), 1.0),
        (Vec2::new(6.0, 4.0), 0.8),
        (Vec2::new(-12.0, -10.0), 2.3),
        (Vec2::new(6.0, -6.0), 2.7857),
    ];
    let blades: Vec<Blade> = blades_of(&sim).into_iter().flatten().collect();
    assert!(blades.len() > 15_000, "{} blades", blades.len());
    let mut near_hole = 0;
    for bl in &blades {
        let p = bl.position;
        for (c, r) in holes {
            let d = Vec2::new(p.x, p.z).distance(c);
            assert!(d >= r, "a blade at {p} stands in the hole at {c} (radius {r})");
            near_hole += usize::from(d < r + 0.3);
        }
        // There is ground under the blade's root, at its height.
        let hit = sim.ground_below(p, 0.5).unwrap_or_else(|| panic!("no ground below the blade at {p}"));
        assert!((hit.point.y - p.y).abs() < 1e-3, "a blade at {p} floats over ground at {}", hit.point.y);
    }
    // The holes' rims are grassed right up to the edge.
    assert!(near_hole > 50, "{near_hole} blades near the holes' rims");
}

fn refused(from: &str, to: &str) -> String {
    let text = park_text();
    assert!(text.contains(from), "{from}");
    let bad = text.replacen(from, to, 1);
    match Scene::parse(&bad, "park.ron") {
        Ok(_) => panic!("a park with '{to}' was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_grass_fields_are_refused_with_one_line() {
    let cases = [
        ("density: 4000.0,", "density: -3.0,", "density -3 must be positive"),
        ("shells: 20,", "shells: 0,", "shells 0 must be between 1"),
        ("height: (0.04, 0.09),", "height: (0.09, 0.04),", "height (0.09, 0.04)"),
        ("planes: [\"ground\"],", "planes: [\"lawn\"],", "names plane 'lawn'"),
        (
            "polygon: [(-11.0, -9.0), (-1.0, -9.0), (-1.0, 3.0), (-11.0, 3.0)],",
            "polygon: [(100.0, 100.0), (110.0, 100.0), (110.0, 110.0)],",
            "lies off every plane",
        ),
        ("tip_color: (0.10, 0.22, 0.03),", "tip_color: (3.0, 0.22, 0.03),", "every channel in 0..=1"),
        ("density: 300.0,", "density: 1.0e9,", "more than the limit"),
        ("kind: Shells,", "kind: Moss,", "Moss"),
    ];
    for (from, to, want) in cases {
        let msg = refused(from, to);
        assert!(msg.contains(want), "'{to}': {msg}");
        assert!(!msg.contains('\n'), "'{to}': more than one line: {msg}");
        if want != "Moss" {
            assert!(msg.contains("grass patch"), "'{to}': the message does not name the patch: {msg}");
        }
    }
}
