//! Fuzz target: any text as a scene file. Parsing, checking and building the world must return
//! (an error or a simulation) and never panic; a built scene is stepped a few times.

#![no_main]

use grove_systems::scene::Scene;
use grove_systems::Sim;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(scene) = Scene::parse(text, "fuzz.ron")
        && let Ok(mut sim) = Sim::from_scene(&scene, scene.seed)
    {
        sim.run(3);
    }
});
