//! `grove bench render`: frame times of the renderer, offscreen at 1280×720.
//!
//! - **Reference scene** (after Fukuda et al. 2007): 100 trees at 10 m spacing on a 100 × 100 m
//!   ground, the sun at 45° elevation, with the shadow map on and off; with all eight classic
//!   models in turn, with only billboard models, with only mesh models, and with the twelve
//!   models of the shipped species bank as young trees (`species`).
//! - **Cost per model**: 1k and 10k instances of each model (shadows off), with triangles per
//!   frame, billboard versus mesh.
//!
//! A frame is timed from the start of `Renderer::render` to the GPU finishing its work
//! (`device.poll(wait)`), without reading the image back; each figure is the median of several
//! frames after a warm-up frame. On a software adapter (lavapipe) this is CPU time. On a real GPU
//! timestamp queries would separate GPU time; this benchmark does not use them.

use std::time::Instant;

use crate::render::Renderer;
use crate::render::offscreen::{self, Gpu};
use glam::{Vec2, Vec3};
use grove_systems::Sim;
use grove_systems::catalogue::ModelId;
use grove_systems::components::{Head, Pose};
use grove_systems::scene::{CameraDef, PlaneDef, PlaneShape, Scene, SunDef, WindDef};
use serde_json::{Value, json};

use super::BenchError;

/// The benchmark's image width, pixels.
pub(super) const WIDTH: u32 = 1280;
/// The benchmark's image height, pixels.
pub(super) const HEIGHT: u32 = 720;

/// A flat benchmark scene: a ground grid of half-size `half` and cell `cell` metres.
pub(super) fn ground_scene(half: f32, cell: f32) -> Scene {
    Scene {
        name: "render benchmark".into(),
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
        sun: SunDef::default(),
        wind: WindDef {
            strength: 1.0,
            density: 0.15,
            gust_average: 0.6,
            gust_strength: 0.4,
            gust_frequency: 0.2,
            ..WindDef::default()
        },
        camera: CameraDef::default(),
        ..Scene::default()
    }
}

/// Puts the camera at `eye` looking at `target` and the sun at 45° from the south-east.
pub(super) fn place(sim: &mut Sim, eye: Vec3, target: Vec3) {
    // The sun at 45° elevation, from the south-east.
    sim.set_up()
        .camera(Head { pose: Pose::looking_at(eye, target), fov_y: 60f32.to_radians() })
        .sun_angles(45.0, 135.0);
}

/// A frame figure: the median wall time of a frame and, where the renderer times its passes,
/// the median GPU time of each pass.
pub(super) struct FrameTime {
    ms: f64,
    /// Each timestamp scope's median time, milliseconds, in the frame's order (the shadow and
    /// main passes first, 0 in a frame without them); empty without timestamp queries.
    passes: Vec<(&'static str, f64)>,
    /// The process's CPU time per frame over the timed frames (every thread: on a software
    /// adapter, the rasteriser's too), milliseconds, where the system tells it (Linux).
    cpu_ms: Option<f64>,
}

impl FrameTime {
    /// The figure as JSON, with the draw statistics of the last frame.
    pub(super) fn json(&self, renderer: &Renderer) -> Value {
        let mut v = json!({"ms_per_frame": self.ms, "fps": 1e3 / self.ms, "triangles": renderer.stats.triangles, "draws": renderer.stats.draws});
        if let Some(cpu) = self.cpu_ms {
            v["cpu_ms_per_frame"] = json!(cpu);
        }
        // `gpu_shadow_pass_ms`, `gpu_main_pass_ms`, and where the frame has them
        // `gpu_reflection_pass_ms`, `gpu_refraction_pass_ms` and `gpu_grass_compute_pass_ms`.
        for (name, ms) in &self.passes {
            v[format!("gpu_{}_pass_ms", name.replace(' ', "_"))] = json!(ms);
        }
        v
    }
}

/// Renders one frame of `sim` into `target` and waits for the device: the wall time of both,
/// milliseconds. Every render benchmark times its frames with this.
pub(super) fn frame_ms(
    gpu: &Gpu,
    renderer: &mut Renderer,
    sim: &Sim,
    target: &offscreen::Target,
) -> Result<f64, BenchError> {
    let t = Instant::now();
    renderer.render(sim, target.view())?;
    gpu.device.poll(wgpu::PollType::wait_indefinitely())?;
    Ok(t.elapsed().as_secs_f64() * 1e3)
}

/// Times `frames` frames after one warm-up frame and returns the medians.
pub(super) fn time_frames(
    gpu: &Gpu,
    renderer: &mut Renderer,
    sim: &Sim,
    frames: usize,
) -> Result<FrameTime, BenchError> {
    time_frames_at(gpu, renderer, sim, frames, (WIDTH, HEIGHT))
}

/// [`time_frames`] into a target of `size` (the renderer must have that size).
pub(super) fn time_frames_at(
    gpu: &Gpu,
    renderer: &mut Renderer,
    sim: &Sim,
    frames: usize,
    size: (u32, u32),
) -> Result<FrameTime, BenchError> {
    let target = offscreen::Target::new(&gpu.device, size.0, size.1);
    let mut times = Vec::new();
    let mut scopes: Vec<(&'static str, Vec<f64>)> = Vec::new();
    let mut cpu_start = None;
    for i in 0..=frames.max(1) {
        if i == 1 {
            cpu_start = process_cpu_ns();
        }
        let ms = frame_ms(gpu, renderer, sim, &target)?;
        let passes = renderer.pass_times()?;
        if i == 0 {
            continue;
        }
        times.push(ms);
        if let Some(p) = passes {
            let others = p.scopes.iter().filter(|(n, _)| !matches!(*n, "shadow" | "main"));
            for (name, ms) in [("shadow", p.ms("shadow")), ("main", p.ms("main"))].into_iter().chain(others.copied()) {
                match scopes.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, v)) => v.push(ms),
                    None => scopes.push((name, vec![ms])),
                }
            }
        }
    }
    let passes = scopes.into_iter().map(|(name, mut v)| (name, super::median(&mut v))).collect();
    let cpu_ms =
        cpu_start.zip(process_cpu_ns()).map(|(a, b)| b.saturating_sub(a) as f64 / 1e6 / times.len().max(1) as f64);
    Ok(FrameTime { cpu_ms, ms: super::median(&mut times), passes })
}

/// The CPU time of every thread of this process so far, nanoseconds: the sum of the run times
/// in `/proc/self/task/*/schedstat` (Linux). `None` where that cannot be read. Unlike wall time
/// it barely moves when other processes load the machine, so it compares builds on a busy one.
fn process_cpu_ns() -> Option<u64> {
    let mut sum = 0u64;
    for task in std::fs::read_dir("/proc/self/task").ok()?.flatten() {
        let stat =
            grove_systems::files::read_text(&task.path().join("schedstat"), grove_systems::files::Kind::Status).ok()?;
        sum += stat.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(sum)
}

/// The renderer settings a render benchmark runs with.
#[derive(Clone, Copy, Debug)]
pub struct RenderBenchOptions {
    /// Shadow-map edge, texels (`RenderOptions::shadow_size`).
    pub shadow_size: u32,
    /// Leaf pixel budget of the foliage level of detail (`RenderOptions::leaf_pixels`).
    pub leaf_pixels: f32,
    /// On-screen size below which trees are impostors (`RenderOptions::impostor_pixels`).
    pub impostor_pixels: f32,
}

/// Builds the GPU and the renderer at the benchmark's size, and names the adapter on stderr.
/// With `need_gpu`, a software adapter is an error: its timings would say nothing of a GPU.
pub(super) fn setup(options: RenderBenchOptions, need_gpu: bool) -> Result<(Gpu, Renderer, String), BenchError> {
    let gpu = Gpu::new()?;
    let adapter = gpu.adapter_name();
    if need_gpu && gpu.is_cpu() {
        return Err(BenchError::SoftwareAdapter(adapter));
    }
    eprintln!("bench: render on {adapter}");
    let mut renderer = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, WIDTH, HEIGHT)?;
    renderer.options.shadow_size = options.shadow_size;
    renderer.options.leaf_pixels = options.leaf_pixels;
    renderer.options.impostor_pixels = options.impostor_pixels;
    // Pass times where the device has timestamp queries; frame times do not depend on them.
    if let Err(e) = renderer.enable_pass_timing() {
        if need_gpu {
            return Err(BenchError::NoTimestamps(e));
        }
    }
    Ok((gpu, renderer, adapter))
}

/// A square forest of `side`² trees 10 m apart on a ground 10 m wider than it, seen from the
/// south at 14 m above the ground, the sun at 45°. `models` picks a tree's model from its index
/// (`None`: no trees, the ground and sky alone).
pub(super) fn forest(side: u32, models: Option<&dyn Fn(u32) -> u8>) -> Result<Sim, BenchError> {
    let half = side as f32 * 5.0;
    let scene = ground_scene(half, (half / 25.0).max(2.0));
    let sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    Ok(plant(sim, side, models, 1.0))
}

/// The shipped species bank's folder (`assets/banks/species`, docs/species.md).
pub fn species_bank() -> std::path::PathBuf {
    crate::render::default_assets_dir().join("banks/species")
}

/// The forest of [`forest`] with the twelve models of the shipped species bank in turn, as young
/// trees (half their grown size, about as tall as the eight classic models), loaded into
/// `renderer`.
pub(super) fn species_forest(renderer: &mut Renderer, side: u32) -> Result<Sim, BenchError> {
    let half = side as f32 * 5.0;
    let mut scene = ground_scene(half, (half / 25.0).max(2.0));
    scene.banks = vec![species_bank().display().to_string()];
    let sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
    crate::bank::load_for_scene(renderer, &scene, &[], sim.catalogue())?;
    let first = grove_systems::catalogue::SHIPPED_MODELS as u32;
    let count = sim.catalogue().models.len() as u32 - first;
    Ok(plant(sim, side, Some(&|i| (first + i % count) as u8), 0.5))
}

/// Plants `side`² trees of `models` at `scale` in `sim` and places the camera and the sun.
fn plant(mut sim: Sim, side: u32, models: Option<&dyn Fn(u32) -> u8>, scale: f32) -> Sim {
    let half = side as f32 * 5.0;
    if let Some(model) = models {
        for i in 0..side * side {
            let (x, z) = ((i % side) as f32 * 10.0 - half + 5.0, (i / side) as f32 * 10.0 - half + 5.0);
            sim.spawn_tree(ModelId(model(i)), Vec3::new(x, 0.0, z), i as f32 * 0.7, scale, true);
        }
    }
    place(&mut sim, Vec3::new(0.0, 14.0, half + 12.0), Vec3::new(0.0, 0.0, 0.0));
    sim
}

/// The forest's variants: all 8 classic models in turn ("mixed"), only their billboard models,
/// only their mesh models, no trees, and the species bank's twelve models ("species").
const VARIANTS: [(&str, Option<fn(u32) -> u8>); 5] = [
    ("mixed", Some(|i| (i % 8) as u8)),
    ("billboard", Some(|i| 4 + (i % 4) as u8)),
    ("mesh", Some(|i| (i % 4) as u8)),
    ("no_trees", None),
    ("species", None),
];

/// The figures of a `side`² forest in every variant, shadows on and off, `frames` frames each.
pub(super) fn forest_figures(
    gpu: &Gpu,
    renderer: &mut Renderer,
    side: u32,
    frames: usize,
) -> Result<Value, BenchError> {
    let mut figures = serde_json::Map::new();
    for (variant, models) in VARIANTS {
        let sim = if variant == "species" {
            species_forest(renderer, side)?
        } else {
            forest(side, models.as_ref().map(|f| f as &dyn Fn(u32) -> u8))?
        };
        for shadows in [true, false] {
            renderer.options.shadows = shadows;
            let on = if shadows { "on" } else { "off" };
            eprintln!("bench: {} trees ({variant}), shadows {on}", side * side);
            let ft = time_frames(gpu, renderer, &sim, frames)?;
            figures.insert(format!("{variant}_shadows_{on}"), ft.json(renderer));
        }
    }
    renderer.options.shadows = true;
    Ok(Value::Object(figures))
}

/// The reference scene (after Fukuda et al. 2007): 100 trees, 10 m apart on a 100 × 100 m
/// ground; and the ground and sky alone, the floor under every other figure.
pub(super) fn reference_scene(gpu: &Gpu, renderer: &mut Renderer) -> Result<Value, BenchError> {
    forest_figures(gpu, renderer, 10, 10)
}

pub(super) fn header(adapter: String, renderer: &Renderer, timing: &str) -> serde_json::Map<String, Value> {
    let mut m = serde_json::Map::new();
    m.insert("adapter".into(), json!(adapter));
    m.insert("resolution".into(), json!([WIDTH, HEIGHT]));
    m.insert("shadow_size".into(), json!(renderer.shadow_size()));
    m.insert("leaf_pixels".into(), json!(renderer.options.leaf_pixels));
    m.insert("impostor_pixels".into(), json!(renderer.options.impostor_pixels));
    m.insert("timing".into(), json!(timing));
    m
}

pub(super) const WALL_TIMING: &str = "median of 10 frames: wall time of render + device.poll(wait); gpu_*_pass_ms from timestamp queries where the device has them";

/// Runs the render benchmarks and returns their figures.
pub fn bench_render(options: RenderBenchOptions) -> Result<Value, BenchError> {
    let (gpu, mut renderer, adapter) = setup(options, false)?;
    let models = renderer.features.trees.model_names();
    let reference = reference_scene(&gpu, &mut renderer)?;

    // Cost per model: n instances on a square grid 3 m apart, seen from above at an angle.
    renderer.options.shadows = false;
    let mut per_model = Vec::new();
    for (id, name) in models.iter().enumerate() {
        if name.is_empty() {
            continue;
        }
        let mut row = serde_json::Map::new();
        row.insert("model".into(), json!(name));
        row.insert(
            "triangles_per_tree".into(),
            json!(renderer.features.trees.model(ModelId(id as u8)).map_or(0, |m| m.triangles)),
        );
        for n in [1_000usize, 10_000] {
            let side = (n as f32).sqrt().ceil() as usize;
            let half = side as f32 * 1.5;
            let scene = ground_scene(half + 2.0, (half / 25.0).max(1.0));
            let mut sim = Sim::from_scene(&scene, scene.seed).map_err(grove_systems::Error::from)?;
            for i in 0..n {
                let (x, z) = ((i % side) as f32 * 3.0 - half, (i / side) as f32 * 3.0 - half);
                sim.spawn_tree(ModelId(id as u8), Vec3::new(x, 0.0, z), i as f32 * 0.7, 1.0, false);
            }
            place(&mut sim, Vec3::new(0.0, half * 0.9, half * 1.9), Vec3::new(0.0, 0.0, 0.0));
            eprintln!("bench: {name} × {n}");
            let ft = time_frames(&gpu, &mut renderer, &sim, if n >= 10_000 { 2 } else { 4 })?;
            row.insert(format!("ms_per_frame_{n}"), json!(ft.ms));
            row.insert(format!("triangles_per_frame_{n}"), json!(renderer.stats.triangles));
        }
        per_model.push(Value::Object(row));
    }
    let mut out = header(adapter, &renderer, WALL_TIMING);
    out.insert("reference_100_trees".into(), reference);
    out.insert("per_model_shadows_off".into(), Value::Array(per_model));
    Ok(Value::Object(out))
}
