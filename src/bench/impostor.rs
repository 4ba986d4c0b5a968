//! The impostor benchmarks: the 10,000-tree forest scene's frame time, and how far the level of
//! detail (simplified foliage and impostors) moves the reference scene's image from the
//! full-detail render.

use crate::render::Renderer;
use crate::render::offscreen::{self, Gpu};
use grove_systems::Sim;
use serde_json::{Value, json};

use super::BenchError;
use super::render::{
    HEIGHT, RenderBenchOptions, WALL_TIMING, WIDTH, forest, header, setup, time_frames, time_frames_at,
};

/// The image difference between `sim` drawn with the renderer's options and drawn at full
/// detail (every leaf, no impostors), shadows as set: the mean absolute difference per channel
/// (0..255) and the share of pixels whose largest channel difference exceeds 40.
pub fn image_error(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim) -> Result<Value, BenchError> {
    let lod = offscreen::render_image(gpu, renderer, sim)?;
    let saved = renderer.options;
    renderer.options.leaf_pixels = 0.0;
    renderer.options.impostor_pixels = 0.0;
    renderer.options.far_pixels = 0.0;
    let full = offscreen::render_image(gpu, renderer, sim);
    renderer.options = saved;
    let full = full?;
    let mut sums = [0u64; 3];
    let mut over = 0u64;
    for (a, b) in lod.pixels().zip(full.pixels()) {
        let d: [u8; 3] = std::array::from_fn(|c| a.0[c].abs_diff(b.0[c]));
        for c in 0..3 {
            sums[c] += u64::from(d[c]);
        }
        over += u64::from(d.iter().any(|&x| x > 40));
    }
    let n = f64::from(lod.width() * lod.height());
    let mae = sums.map(|s| s as f64 / n);
    Ok(json!({
        "mean_abs_error_rgb": mae,
        "mean_abs_error": mae.iter().sum::<f64>() / 3.0,
        "percent_pixels_over_40": over as f64 / n * 100.0,
        "shadows": saved.shadows,
    }))
}

/// The forest scene at 1920 × 1080 and a million trees (1000 × 1000, 10 m apart, all eight
/// models in turn) at 1920 × 1080, shadows on and off, for `grove bench render-gpu` (which has
/// refused a software adapter and turned the timestamp queries on). Adds them to `out`.
pub fn forest_gpu_figures(
    gpu: &Gpu,
    renderer: &mut Renderer,
    out: &mut serde_json::Map<String, Value>,
) -> Result<(), BenchError> {
    const FULL_HD: (u32, u32) = (1920, 1080);
    renderer.resize(FULL_HD.0, FULL_HD.1);
    let path = crate::render::default_assets_dir().join("scenes/forest.ron");
    let scene = super::load_scene(&path)?;
    let forest_sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    crate::bank::load_for_scene(renderer, &scene, &[], forest_sim.catalogue())?;
    eprintln!("bench: a million trees (building the world)");
    let million = forest(1000, Some(&|i| (i % 8) as u8))?;
    for (name, sim) in [("forest_10k_trees_1920x1080", &forest_sim), ("million_trees_1920x1080", &million)] {
        let mut figures = serde_json::Map::new();
        for shadows in [true, false] {
            renderer.options.shadows = shadows;
            let on = if shadows { "on" } else { "off" };
            eprintln!("bench: {name}, shadows {on}");
            let ft = time_frames_at(gpu, renderer, sim, 30, FULL_HD)?;
            figures.insert(format!("shadows_{on}"), ft.json(renderer));
        }
        out.insert(name.into(), Value::Object(figures));
    }
    renderer.options.shadows = true;
    renderer.resize(WIDTH, HEIGHT);
    Ok(())
}

/// `grove bench render-forest`: the forest scene (assets/scenes/forest.ron, or `scene`) from its
/// camera, shadows on and off, and its image difference from the full-detail render.
pub fn bench_forest(options: RenderBenchOptions, scene: Option<&std::path::Path>) -> Result<Value, BenchError> {
    let path = scene
        .map_or_else(|| crate::render::default_assets_dir().join("scenes/forest.ron"), std::path::Path::to_path_buf);
    let scene = super::load_scene(&path)?;
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    crate::bank::load_for_scene(&mut renderer, &scene, &[], sim.catalogue())?;
    let mut figures = serde_json::Map::new();
    for shadows in [true, false] {
        renderer.options.shadows = shadows;
        let on = if shadows { "on" } else { "off" };
        eprintln!("bench: forest, shadows {on}");
        let ft = time_frames(&gpu, &mut renderer, &sim, 5)?;
        figures.insert(format!("shadows_{on}"), ft.json(&renderer));
    }
    renderer.options.shadows = true;
    figures.insert("image_vs_full_detail".into(), image_error(&gpu, &mut renderer, &sim)?);
    let mut out = header(adapter, &renderer, WALL_TIMING);
    out.insert("scene".into(), json!(path.display().to_string()));
    out.insert("forest_10k_trees".into(), Value::Object(figures));
    Ok(Value::Object(out))
}
