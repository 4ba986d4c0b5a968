//! `grove bench water`: the cost of water, after Fukuda et al. (2007)'s water test: 500 × 500 m
//! of water 50 m deep over a bed, under the cube-mapped sky, seen from the shore 10 m up at
//! 1280×720, with water and with `--no-water` (the bed and sky alone). Their GPU lost 1.7 %
//! (60 → 59.9 fps). The same figures run on a real GPU as part of `grove bench render-gpu`,
//! where the timestamp queries also give the reflection, refraction and main passes' GPU time.
//!
//! A frame is timed as in `bench_render`: the wall time of `Renderer::render` until the device
//! is idle, the median of several frames after a warm-up frame; pass times where the device has
//! timestamp queries.

use crate::render::Renderer;
use crate::render::offscreen::{self, Gpu};
use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::scene::PlaneShape;
use grove_systems::water::WaterDef;
use serde_json::{Value, json};

use super::BenchError;
use super::render::{HEIGHT, RenderBenchOptions, WIDTH, ground_scene, place, setup};

/// The water test's world: a 600 × 600 m bed 50 m down, 500 × 500 m of water at height 0, the
/// camera on the south shore 10 m up looking north, the sun at 45°.
pub fn water_test_scene() -> Result<Sim, BenchError> {
    let mut scene = ground_scene(300.0, 20.0);
    if let PlaneShape::Grid { elevation, unevenness, .. } = &mut scene.planes[0].shape {
        *elevation = -50.0;
        *unevenness = 0.0;
    }
    let h = 250.0;
    scene.water = vec![WaterDef {
        name: "water test".into(),
        polygon: vec![Vec2::new(-h, -h), Vec2::new(h, -h), Vec2::new(h, h), Vec2::new(-h, h)],
        height: 0.0,
        depth: 50.0,
        colour: [0.02, 0.07, 0.06],
        ripples: 1.0,
        ripple_speed: 0.05,
    }];
    let mut sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    place(&mut sim, Vec3::new(0.0, 10.0, 250.0), Vec3::new(0.0, 0.0, 0.0));
    Ok(sim)
}

/// Times `frames` frames (after a warm-up) with water on or off: the median wall time and,
/// with timestamp queries, the median GPU time of each pass.
fn time_water(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim, water: bool, frames: usize) -> Result<Value, BenchError> {
    renderer.options.water = water;
    let target = offscreen::Target::new(&gpu.device, WIDTH, HEIGHT);
    let mut wall = Vec::new();
    let names = ["shadow", "reflection", "refraction", "main"];
    let mut passes: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut timed = false;
    for i in 0..=frames.max(1) {
        let ms = super::render::frame_ms(gpu, renderer, sim, &target)?;
        let times = renderer.pass_times()?;
        if i == 0 {
            continue;
        }
        wall.push(ms);
        if let Some(p) = times {
            timed = true;
            for (k, name) in names.iter().enumerate() {
                passes[k].push(p.ms(name));
            }
        }
    }
    renderer.options.water = true;
    let ms = super::median(&mut wall);
    let mut v = json!({"ms_per_frame": ms, "fps": 1e3 / ms, "draws": renderer.stats.draws, "triangles": renderer.stats.triangles});
    if timed {
        for (k, name) in names.iter().enumerate() {
            v[format!("gpu_{name}_pass_ms")] = json!(super::median(&mut passes[k]));
        }
    }
    Ok(v)
}

/// The water test's figures with `gpu` and `renderer`: with and without water, and the cost.
pub fn water_figures(gpu: &Gpu, renderer: &mut Renderer, frames: usize) -> Result<Value, BenchError> {
    let sim = water_test_scene()?;
    eprintln!("bench: water test, with water");
    let with = time_water(gpu, renderer, &sim, true, frames)?;
    eprintln!("bench: water test, without water");
    let without = time_water(gpu, renderer, &sim, false, frames)?;
    let (a, b) = (with["ms_per_frame"].as_f64().unwrap_or(0.0), without["ms_per_frame"].as_f64().unwrap_or(0.0));
    let cost = if b > 0.0 { (a - b) / a * 100.0 } else { 0.0 };
    Ok(json!({
        "scene": "500 x 500 m of water, 50 m deep, cube-mapped sky, camera 10 m up on the shore",
        "with_water": with,
        "without_water": without,
        "water_share_of_frame_percent": cost,
    }))
}

/// Runs `grove bench water` on whatever adapter wgpu picks (lavapipe here).
pub fn bench_water(options: RenderBenchOptions) -> Result<Value, BenchError> {
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let figures = water_figures(&gpu, &mut renderer, 10)?;
    Ok(
        json!({"adapter": adapter, "resolution": [WIDTH, HEIGHT], "timing": "median of 10 frames: wall time of render + device.poll(wait)", "water_test": figures}),
    )
}
