//! The shipped species bank (`assets/banks/species`, docs/species.md): it is exactly what
//! `scripts/species-bank.sh` writes with this grove, its files match its catalogue, and the
//! scenes that plant its trees name them.

use crate::common;

use std::process::Command;

use common::{grove, root};

/// The committed bank is what the script writes today: the same catalogue (names, kinds,
/// bounds, pick shapes and the content hash of every file) and the same files.
#[test]
fn the_committed_bank_is_what_the_script_writes() {
    let dir = std::env::temp_dir().join(format!("grove-species-bank-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fresh = dir.join("species");
    let out = Command::new("bash")
        .current_dir(root())
        .arg("scripts/species-bank.sh")
        .arg(env!("CARGO_BIN_EXE_grove"))
        .arg(&fresh)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let shipped = root().join("assets/banks/species");
    let want = std::fs::read_to_string(shipped.join("catalogue.ron")).unwrap();
    let got = std::fs::read_to_string(fresh.join("catalogue.ron")).unwrap();
    assert_eq!(
        got, want,
        "assets/banks/species is not what scripts/species-bank.sh writes: regenerate it (docs/species.md)"
    );
    // Every model of every species at two levels of detail.
    for species in ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"] {
        for (lod, kind) in [(1, "Mesh"), (2, "Billboard")] {
            let entry = format!(
                "name: \"{species}-lod{lod}\",\n            species: \"{species}\",\n            kind: {kind},"
            );
            assert!(want.contains(&entry), "no {species}-lod{lod} of kind {kind} in the bank");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `grove models check` finds every file of the bank as its catalogue describes it.
#[test]
fn the_bank_checks() {
    let out = grove(&["models", "check", "--bank", root().join("assets/banks/species").to_str().unwrap()]);
    assert!(out.status.success(), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
}

/// The park, the garden and the forest plant the species bank's trees and none of the eight
/// classic models (the study scene keeps those: its recordings name them).
#[test]
fn the_landscape_scenes_plant_species() {
    use grove_systems::Sim;
    use grove_systems::scene::Scene;
    for name in ["park", "garden", "forest"] {
        let scene = Scene::load(&root().join(format!("assets/scenes/{name}.ron"))).unwrap();
        let sim = Sim::from_scene(&scene, scene.seed).unwrap();
        let cat = sim.catalogue();
        let mut species = std::collections::BTreeSet::new();
        let mut models = Vec::new();
        sim.for_each_tree(|t| models.push(t.model));
        for model in models {
            let m = &cat.models[model.0 as usize];
            assert!(model.0 >= 8, "{name}: a classic model, {}", m.name);
            if !m.name.starts_with("lsys-") {
                species.insert(m.species.clone());
            }
        }
        assert!(species.len() >= 4, "{name}: only {species:?}");
    }
}

/// A species tree small on screen is drawn as its far model: the bank's `NAME-lod1` names
/// `NAME-lod2`, and the renderer draws exactly the far model's triangles in its place (leaves
/// and impostors at full detail, no shadows, so that the counts are the models' own).
#[test]
fn a_far_tree_is_drawn_as_its_far_model() {
    use glam::Vec3;
    use grove::render::Renderer;
    use grove::render::offscreen::{self, Gpu};
    use grove_systems::Sim;
    use grove_systems::components::{Head, Pose};
    use grove_systems::scene::Scene;
    let mut scene = Scene::load(&root().join("assets/scenes/park.ron")).unwrap();
    scene.trees.clear();
    scene.grass.clear();
    scene.water.clear();
    let mut sim = Sim::from_scene(&scene, scene.seed).unwrap();
    let cat = sim.catalogue().clone();
    let id = |name: &str| cat.models.iter().find(|m| m.name == name).unwrap_or_else(|| panic!("{name}")).clone();
    let (near, far) = (id("oak-lod1"), id("oak-lod2"));
    sim.spawn_tree(near.id, Vec3::new(0.0, 0.0, -60.0), 0.0, 0.5, true);
    sim.set_up().camera(Head {
        pose: Pose::looking_at(Vec3::new(0.0, 2.0, 0.0), Vec3::new(0.0, 4.0, -60.0)),
        fov_y: 60f32.to_radians(),
    });
    let gpu = Gpu::new().unwrap();
    let mut r = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, 160, 120).unwrap();
    grove::bank::load_for_scene(&mut r, &scene, &[], &cat).unwrap();
    r.options.shadows = false;
    r.options.leaf_pixels = 0.0;
    r.options.impostor_pixels = 0.0;
    let mut triangles = |far_pixels: f32| {
        r.options.far_pixels = far_pixels;
        offscreen::render_image(&gpu, &mut r, &sim).unwrap();
        r.stats.triangles as i64
    };
    // The tree at half size has a bounding sphere of about 9.7 m radius; at 60 m, with 104
    // pixels per radian (120 lines, 60°), it covers about 34 pixels: below 400, above 20.
    let (as_far, as_near, default) = (triangles(400.0), triangles(20.0), triangles(grove::render::DEFAULT_FAR_PIXELS));
    assert_eq!(as_near - as_far, i64::from(near.triangles) - i64::from(far.triangles), "near {as_near}, far {as_far}");
    assert_eq!(default, as_far);
    assert_eq!(triangles(0.0), as_near, "0 always draws the model itself");
}
