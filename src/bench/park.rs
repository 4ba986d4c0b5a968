//! `grove bench park`: Fukuda et al. (2007)'s park table (their Table 5) on `assets/scenes/park.ron`
//! (lawns of shells and blades, a pond, trees) from the scene's own camera at 1280×720: the park
//! with nothing but ground, sky and trees; with grass; with grass and water; and with grass,
//! water and the sun's shadows. One row each, frame time and fps; on a real GPU the same rows
//! run inside `grove bench render-gpu`, with the passes' GPU times.
//!
//! The shares of the frame that grass and water take (issue #39's goals: at most 25 % and 10 %)
//! are timed apart from the rows, in interleaved pairs of frames (one without, one with, in
//! turn), so that a machine whose speed drifts while the rows run one after another, as a
//! shared one does, weighs on both halves of each pair alike: rows timed seconds apart gave the
//! water's share anywhere from -25 to +14 % on one build.

use std::path::Path;

use crate::render::Renderer;
use crate::render::offscreen::{self, Gpu};
use grove_systems::Sim;
use grove_systems::scene::Scene;
use serde_json::{Value, json};

use super::BenchError;
use super::pairs::paired_share;
use super::render::{HEIGHT, RenderBenchOptions, WIDTH, frame_ms, setup, time_frames};

/// A configuration of the table: grass, water, shadows.
type Config = (bool, bool, bool);

/// The park scene's file: `scenes/park.ron` of the assets folder.
pub fn park_scene() -> std::path::PathBuf {
    crate::render::default_assets_dir().join("scenes/park.ron")
}

/// The table's rows: name, grass, water, shadows.
const ROWS: [(&str, bool, bool, bool); 4] = [
    ("nothing", false, false, false),
    ("grass", true, false, false),
    ("grass_water", true, true, false),
    ("grass_water_shadows", true, true, true),
];

/// The park table of `scene` (the park's, [`park_scene`], or another; read from `path`) with
/// `gpu` and `renderer`: one row per configuration, `frames` frames each.
pub fn park_figures(
    gpu: &Gpu,
    renderer: &mut Renderer,
    frames: usize,
    scene: &Scene,
    path: &Path,
) -> Result<Value, BenchError> {
    let sim = Sim::from_scene(scene, scene.seed).map_err(grove_systems::Error::from)?;
    crate::bank::load_for_scene(renderer, scene, &[], sim.catalogue())?;
    let saved = renderer.options;
    let mut rows = serde_json::Map::new();
    for (name, grass, water, shadows) in ROWS {
        eprintln!("bench: park, {name}");
        renderer.options.grass = grass;
        renderer.options.water = water;
        renderer.options.shadows = shadows;
        let t = time_frames(gpu, renderer, &sim, frames)?;
        let mut row = t.json(renderer);
        if grass {
            // The blades the last frame drew at each level of detail.
            let b = renderer.features.grass.visible_blades()?;
            (row["blades_near"], row["blades_mid"], row["blades_far"]) = (json!(b.near), json!(b.mid), json!(b.far));
        }
        rows.insert(name.into(), row);
    }
    eprintln!("bench: park, the shares of grass and water in {frames} interleaved pairs of frames each");
    let target = offscreen::Target::new(&gpu.device, WIDTH, HEIGHT);
    let mut share = |without: Config, with: Config| {
        paired_share(frames, |on| one_frame(gpu, renderer, &sim, &target, if on { with } else { without }))
    };
    let grass_share = share((false, false, false), (true, false, false));
    let water_share = share((true, false, false), (true, true, false));
    renderer.options = saved;
    Ok(json!({
        "scene": path.display().to_string(),
        "rows": rows,
        "grass_share_of_frame_percent": grass_share?,
        "water_share_of_frame_percent": water_share?,
        "shares": format!("the median over {frames} interleaved pairs of frames (nothing, grass; grass, grass and water) of (with - without) / with"),
    }))
}

/// Sets `renderer`'s grass, water and shadows to `config` and times one frame of `sim` into
/// `target` ([`frame_ms`]).
fn one_frame(
    gpu: &Gpu,
    renderer: &mut Renderer,
    sim: &Sim,
    target: &offscreen::Target,
    config: Config,
) -> Result<f64, BenchError> {
    (renderer.options.grass, renderer.options.water, renderer.options.shadows) = config;
    frame_ms(gpu, renderer, sim, target)
}

/// Runs `grove bench park` on whatever adapter wgpu picks (lavapipe here), on `scene` (the
/// park's by default).
pub fn bench_park(options: RenderBenchOptions, scene: Option<&Path>) -> Result<Value, BenchError> {
    let path = scene.map_or_else(park_scene, Path::to_path_buf);
    // A scene that does not load is the user's error, told before the device is set up.
    let scene = super::load_scene(&path)?;
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let figures = park_figures(&gpu, &mut renderer, 10, &scene, &path)?;
    Ok(
        json!({"adapter": adapter, "resolution": [WIDTH, HEIGHT], "timing": super::render::WALL_TIMING, "park": figures}),
    )
}
