//! Culling the trees per pass (`RenderOptions::cull_trees`, `src/render/trees/views.rs`) changes
//! no pixel: the park (species trees, a pond with its reflection and refraction, shadows), the
//! pond scene and the garden render byte for byte the same with culling on and off, from the
//! scenes' own cameras and from a camera that turns its back on most trees. The main view draws
//! fewer trees with culling where some stand outside it, and none of a tree behind the camera.
//!
//! Renders on whatever adapter wgpu finds (lavapipe in CI).

use std::path::PathBuf;

use glam::Vec3;
use grove::render::Renderer;
use grove::render::offscreen::{self, Gpu};
use grove_systems::Sim;
use grove_systems::components::{Head, Pose};
use grove_systems::scene::Scene;
use image::RgbaImage;

use crate::shared_gpu;
use shared_gpu::LOCK;

fn gpu() -> &'static Gpu {
    shared_gpu::shared_gpu("tree culling tests")
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scene(name: &str) -> Scene {
    Scene::load(&root().join("assets/scenes").join(name)).unwrap()
}

/// The world of `scene` after one tick, looking from `eye` at `at` where given.
fn world(scene: &Scene, view: Option<(Vec3, Vec3)>) -> Sim {
    let mut sim = Sim::from_scene(scene, scene.seed).unwrap();
    if let Some((eye, at)) = view {
        sim.set_up().camera(Head { pose: Pose::looking_at(eye, at), fov_y: 60f32.to_radians() });
    }
    sim.run(1);
    sim
}

/// The image and the main view's tree instances, with culling on and off.
fn both(scene: &Scene, sim: &Sim) -> [(RgbaImage, usize); 2] {
    both_with_shadow(scene, sim).map(|(img, main, _)| (img, main))
}

/// The image, the main view's tree instances and the shadow map's, with culling on and off.
fn both_with_shadow(scene: &Scene, sim: &Sim) -> [(RgbaImage, usize, usize); 2] {
    let _guard = LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let g = gpu();
    let mut r = Renderer::new(&g.device, &g.queue, offscreen::FORMAT, 320, 180).unwrap();
    grove::bank::load_for_scene(&mut r, scene, &[], sim.catalogue()).unwrap();
    [true, false].map(|cull| {
        r.options.cull_trees = cull;
        let img = offscreen::render_image(g, &mut r, sim).unwrap();
        (img, r.stats.instances, r.stats.shadow_instances)
    })
}

fn assert_same(name: &str, a: &RgbaImage, b: &RgbaImage) {
    let differ = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert_eq!(differ, 0, "{name}: {differ} pixels differ between culling on and off");
}

#[test]
fn the_park_renders_the_same_with_and_without_culling_and_its_main_view_draws_fewer_trees() {
    let s = scene("park.ron");
    let trees = s.trees.len();
    // The park's camera turned a little further east, to (3, 0.4, 0).
    let view = Some((Vec3::new(0.0, 1.7, 9.5), Vec3::new(3.0, 0.4, 0.0)));
    let [(culled, drawn), (all, every)] = both(&s, &world(&s, view));
    assert_same("park", &culled, &all);
    assert!(every >= trees, "without culling the main view draws every tree: {every} of {trees}");
    // The oak at (-10, 6.5) stands beside and behind the camera at (0, 1.7, 9.5), which looks
    // north-north-east: wholly outside the view (from the park's own camera, which looks more
    // to the north, the box of the oak's crown, 4.9 m about its trunk, reaches into it).
    assert!(drawn < every, "culling drew {drawn} of {every} trees");
}

#[test]
fn a_camera_turned_away_draws_no_tree_and_the_image_is_the_same() {
    // From 20 m south of the park looking south, away from it: every tree is behind.
    let s = scene("park.ron");
    let sim = world(&s, Some((Vec3::new(0.0, 1.7, 30.0), Vec3::new(0.0, 1.0, 60.0))));
    let [(culled, drawn), (all, every)] = both(&s, &sim);
    assert_same("park, looking away", &culled, &all);
    // Without culling every tree is drawn (a tree in its impostor cross-fade twice).
    assert!(every >= s.trees.len(), "{every} draws of {} trees", s.trees.len());
    assert_eq!(drawn, 0, "a tree behind the camera was drawn");
}

#[test]
fn the_pond_and_the_garden_render_the_same_with_and_without_culling() {
    for name in ["pond.ron", "garden.ron"] {
        let s = scene(name);
        let [(culled, drawn), (all, every)] = both(&s, &world(&s, None));
        assert_same(name, &culled, &all);
        assert!(drawn <= every && every > 0, "{name}: {drawn} of {every}");
        // And from above the pond's far shore, looking back across the water, so that the
        // reflection and refraction see other trees than the scene's camera does.
        let sim = world(&s, Some((Vec3::new(0.0, 3.0, -16.0), Vec3::new(0.0, 0.0, -4.0))));
        let [(culled, _), (all, _)] = both(&s, &sim);
        assert_same(&format!("{name}, from the far shore"), &culled, &all);
    }
}

/// The shadow map covers 80 m around the camera (`lighting::shadow_bounds`). In the forest, whose
/// trees stand up to 600 m deep in the view, it draws only the trees within its own volume,
/// though the shadows of many more would fall into the view: a tree outside the sun's view
/// draws nothing into the map, so the image stays the same byte for byte.
#[test]
fn the_shadow_map_draws_only_the_trees_in_its_own_volume() {
    let s = scene("forest.ron");
    let [(culled, main, casters), (all, every, every_caster)] = both_with_shadow(&s, &world(&s, None));
    assert_same("forest", &culled, &all);
    eprintln!(
        "forest: the main view draws {main} trees, the shadow map {casters} (without culling {every} and {every_caster})"
    );
    // (Trees lost in the haze, beyond about 566 m, are left out before any view: not all 10,106.)
    assert!(
        every_caster >= every && every > main,
        "without culling the shadow map and the main view draw every tree: {every_caster} and {every}, culled {main}"
    );
    assert!(casters > 0, "no tree casts a shadow near the camera");
    assert!(casters * 4 < main, "the shadow map draws {casters} trees, the main view {main}");
}
