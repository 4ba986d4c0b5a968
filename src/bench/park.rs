//! `grove bench park`: Fukuda et al. (2007)'s park table (their Table 5) on `assets/scenes/park.ron`
//! (lawns of shells and blades, a pond, trees) from the scene's own camera at 1280×720: the park
//! with nothing but ground, sky and trees; with grass; with grass and water; and with grass,
//! water and the sun's shadows. One row each, frame time and fps; on a real GPU the same rows
//! run inside `grove bench render-gpu`, with the passes' GPU times.

use std::path::Path;

use anyhow::anyhow;
use crate::render::offscreen::Gpu;
use crate::render::Renderer;
use grove_systems::scene::Scene;
use grove_systems::Sim;
use serde_json::{json, Value};

use super::render::{setup, time_frames, RenderBenchOptions, HEIGHT, WIDTH};

/// The park scene's file, relative to the repository root (where the benchmarks run).
pub const PARK: &str = "assets/scenes/park.ron";

/// The table's rows: name, grass, water, shadows.
const ROWS: [(&str, bool, bool, bool); 4] = [
    ("nothing", false, false, false),
    ("grass", true, false, false),
    ("grass_water", true, true, false),
    ("grass_water_shadows", true, true, true),
];

/// The park table with `gpu` and `renderer`: one row per configuration, `frames` frames each.
pub fn park_figures(gpu: &Gpu, renderer: &mut Renderer, frames: usize) -> anyhow::Result<Value> {
    let scene = Scene::load(Path::new(PARK)).map_err(|e| anyhow!("{PARK}: {e}"))?;
    let sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!(e))?;
    crate::bank::load_for_scene(renderer, &scene, &[], &sim.res().catalogue).map_err(|e| anyhow!(e))?;
    let saved = renderer.options;
    let mut rows = serde_json::Map::new();
    for (name, grass, water, shadows) in ROWS {
        eprintln!("bench: park, {name}");
        renderer.options.grass = grass;
        renderer.options.water = water;
        renderer.options.shadows = shadows;
        let t = time_frames(gpu, renderer, &sim, frames)?;
        rows.insert(name.into(), t.json(renderer));
    }
    renderer.options = saved;
    let water_share = match (rows["grass"]["ms_per_frame"].as_f64(), rows["grass_water"]["ms_per_frame"].as_f64()) {
        (Some(a), Some(b)) if b > 0.0 => (b - a) / b * 100.0,
        _ => 0.0,
    };
    Ok(json!({"scene": PARK, "rows": rows, "water_share_of_frame_percent": water_share}))
}

/// Runs `grove bench park` on whatever adapter wgpu picks (lavapipe here).
pub fn bench_park(options: RenderBenchOptions) -> anyhow::Result<Value> {
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let figures = park_figures(&gpu, &mut renderer, 10)?;
    Ok(json!({"adapter": adapter, "resolution": [WIDTH, HEIGHT], "timing": super::render::WALL_TIMING, "park": figures}))
}
