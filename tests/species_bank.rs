//! The shipped species bank (`assets/banks/species`, docs/species.md): it is exactly what
//! `scripts/species-bank.sh` writes with this grove, its files match its catalogue, and the
//! scenes that plant its trees name them.

mod common;

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
    assert_eq!(got, want, "assets/banks/species is not what scripts/species-bank.sh writes: regenerate it (docs/species.md)");
    // Every model of every species at two levels of detail.
    for species in ["oak", "birch", "beech", "scots_pine", "norway_spruce", "shrub"] {
        for (lod, kind) in [(1, "Mesh"), (2, "Billboard")] {
            let entry = format!("name: \"{species}-lod{lod}\",\n            species: \"{species}\",\n            kind: {kind},");
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
    use grove_systems::components::Tree;
    use grove_systems::scene::Scene;
    use grove_systems::Sim;
    for name in ["park", "garden", "forest"] {
        let scene = Scene::load(&root().join(format!("assets/scenes/{name}.ron"))).unwrap();
        let sim = Sim::from_scene(&scene, scene.seed).unwrap();
        let cat = &sim.res().catalogue;
        let mut species = std::collections::BTreeSet::new();
        for t in sim.world().query::<&Tree>().iter() {
            let m = &cat.models[t.model.0 as usize];
            assert!(t.model.0 >= 8, "{name}: a classic model, {}", m.name);
            if !m.name.starts_with("lsys-") {
                species.insert(m.species.clone());
            }
        }
        assert!(species.len() >= 4, "{name}: only {species:?}");
    }
}
