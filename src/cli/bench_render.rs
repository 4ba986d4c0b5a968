//! `grove bench render`: frame times of the renderer, offscreen at 1280×720.
//!
//! - **Reference scene** (after Fukuda et al. 2007): 100 trees at 10 m spacing on a 100 × 100 m
//!   ground, the sun at 45° elevation, with the shadow map on and off; with all eight models in
//!   turn, with only billboard models and with only mesh models.
//! - **Cost per model**: 1k and 10k instances of each model (shadows off), with triangles per
//!   frame, billboard versus mesh.
//!
//! A frame is timed from the start of `Renderer::render` to the GPU finishing its work
//! (`device.poll(wait)`), without reading the image back; each figure is the median of several
//! frames after a warm-up frame. On a software adapter (lavapipe) this is CPU time. On a real GPU
//! timestamp queries would separate GPU time; this benchmark does not use them.

use std::time::Instant;

use anyhow::anyhow;
use glam::{Vec2, Vec3};
use grove::render::offscreen::{self, Gpu};
use grove::render::Renderer;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{Head, Pose, Sun};
use grove_systems::scene::{CameraDef, PlaneDef, PlaneShape, Scene, SunDef, WindDef};
use grove_systems::Sim;
use serde_json::{json, Value};

const WIDTH: u32 = 1280;
const HEIGHT: u32 = 720;

fn ground_scene(half: f32, cell: f32) -> Scene {
    Scene {
        name: "render benchmark".into(),
        dt: 1.0 / 60.0,
        seed: 7,
        planes: vec![PlaneDef {
            name: "ground".into(),
            shape: PlaneShape::Grid {
                min: Vec2::splat(-half),
                size: Vec2::splat(2.0 * half),
                cell,
                elevation: 0.0,
                unevenness: 0.05,
                noise_seed: 3,
                holes: vec![],
            },
        }],
        sun: SunDef { latitude_deg: 47.37, longitude_deg: 8.54, utc: "2026-06-21T10:00:00Z".into(), time_rate: 0.0 },
        wind: WindDef { direction: Vec3::X, strength: 1.0, density: 0.15, gust_average: 0.6, gust_strength: 0.4, gust_frequency: 0.2, model: Default::default(), response: Default::default() },
        trees: vec![],
        camera: CameraDef { position: Vec3::new(0.0, 1.7, 6.0), look_at: Vec3::ZERO, fov_y_deg: 60.0 },
    }
}

fn place(sim: &mut Sim, eye: Vec3, target: Vec3) {
    for h in sim.world.query_mut::<&mut Head>() {
        *h = Head { pose: Pose::looking_at(eye, target), fov_y: 60f32.to_radians() };
    }
    // The sun at 45° elevation, from the south-east.
    for s in sim.world.query_mut::<&mut Sun>() {
        s.elevation_deg = 45.0;
        s.azimuth_deg = 135.0;
        s.direction = grove_systems::systems::sun::direction_from_angles(135.0, 45.0);
    }
}

/// Median frame time in milliseconds over `frames` frames after one warm-up frame.
fn time_frames(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim, frames: usize) -> anyhow::Result<f64> {
    let target = offscreen::Target::new(&gpu.device, WIDTH, HEIGHT);
    let mut once = || -> anyhow::Result<f64> {
        let t = Instant::now();
        renderer.render(sim, target.view());
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow!("GPU poll failed ({e})"))?;
        Ok(t.elapsed().as_secs_f64() * 1e3)
    };
    once()?;
    let mut times = Vec::new();
    for _ in 0..frames.max(1) {
        times.push(once()?);
    }
    Ok(super::bench::median(&mut times))
}

/// Runs the render benchmarks and returns their figures.
pub fn bench_render() -> anyhow::Result<Value> {
    let gpu = Gpu::new().map_err(|e| anyhow!(e))?;
    let adapter = gpu.adapter_name();
    eprintln!("bench: render on {adapter}");
    let mut renderer = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, WIDTH, HEIGHT).map_err(|e| anyhow!(e))?;
    let models = renderer.model_names();

    // Reference scene: 10 × 10 trees, 10 m apart: all 8 models in turn ("mixed"), only the
    // billboard models, or only the mesh models.
    let scene = ground_scene(50.0, 2.0);
    let mut reference = serde_json::Map::new();
    for (variant, first, step) in [("mixed", 0u8, 1u8), ("billboard", 4, 1), ("mesh", 0, 1)] {
        let mut sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!(e))?;
        for i in 0..100u32 {
            let (x, z) = ((i % 10) as f32 * 10.0 - 45.0, (i / 10) as f32 * 10.0 - 45.0);
            let model = if variant == "mixed" { (i % 8) as u8 } else { first + ((i as u8 * step) % 4) };
            sim.spawn_tree(ModelId(model), Vec3::new(x, 0.0, z), i as f32 * 0.7, 1.0, true);
        }
        place(&mut sim, Vec3::new(0.0, 14.0, 62.0), Vec3::new(0.0, 0.0, 0.0));
        for shadows in [true, false] {
            renderer.options.shadows = shadows;
            eprintln!("bench: reference scene ({variant}), shadows {}", if shadows { "on" } else { "off" });
            let ms = time_frames(&gpu, &mut renderer, &sim, 10)?;
            let key = format!("{variant}_shadows_{}", if shadows { "on" } else { "off" });
            reference.insert(key, json!({"ms_per_frame": ms, "fps": 1e3 / ms, "triangles": renderer.stats.triangles, "draws": renderer.stats.draws}));
        }
    }

    // Cost per model: n instances on a square grid 3 m apart, seen from above at an angle.
    renderer.options.shadows = false;
    let mut per_model = Vec::new();
    for (id, name) in models.iter().enumerate() {
        if name.is_empty() {
            continue;
        }
        let mut row = serde_json::Map::new();
        row.insert("model".into(), json!(name));
        row.insert("triangles_per_tree".into(), json!(renderer.model(ModelId(id as u8)).map_or(0, |m| m.triangles)));
        for n in [1_000usize, 10_000] {
            let side = (n as f32).sqrt().ceil() as usize;
            let half = side as f32 * 1.5;
            let scene = ground_scene(half + 2.0, (half / 25.0).max(1.0));
            let mut sim = Sim::from_scene(&scene, scene.seed).map_err(|e| anyhow!(e))?;
            for i in 0..n {
                let (x, z) = ((i % side) as f32 * 3.0 - half, (i / side) as f32 * 3.0 - half);
                sim.spawn_tree(ModelId(id as u8), Vec3::new(x, 0.0, z), i as f32 * 0.7, 1.0, false);
            }
            place(&mut sim, Vec3::new(0.0, half * 0.9, half * 1.9), Vec3::new(0.0, 0.0, 0.0));
            eprintln!("bench: {name} × {n}");
            let ms = time_frames(&gpu, &mut renderer, &sim, if n >= 10_000 { 2 } else { 4 })?;
            row.insert(format!("ms_per_frame_{n}"), json!(ms));
            row.insert(format!("triangles_per_frame_{n}"), json!(renderer.stats.triangles));
        }
        per_model.push(Value::Object(row));
    }
    Ok(json!({
        "adapter": adapter,
        "resolution": [WIDTH, HEIGHT],
        "timing": "wall time of render + device.poll(wait), median; no GPU timestamp queries (software adapter)",
        "reference_100_trees": reference,
        "per_model_shadows_off": per_model,
    }))
}
