//! `grove bench grass`: what grass costs a frame, offscreen.
//!
//! - **Fukuda et al.'s grass test**: a 1 km² field (1000 × 1000 m) of shell grass whose strand
//!   texture tiles every 2 m (128 strands along a tile: 4,096 strands per m²), 20 layers, seen
//!   from 1.7 m above its edge at 1280 × 720; the frame time with and without the grass and the
//!   drop in frames per second (their GPU went from 60 to 48.2 fps, −19.7 %).
//! - **Blades**: patches of 10k, 37.6k (Project ARC's limit), 100k and 1M blades considered by
//!   the cull pass, at 640 × 360 and 1280 × 720, seen from 1.7 m above the patch's edge; and
//!   the goal case, a 16 × 16 m patch of 65,536 blades all in view from above, at 640 × 360
//!   (goal on lavapipe: at most 33 ms a frame), also timed without grass. Each figure gives the
//!   blades the cull pass kept (at each level of detail: near, middle, far) and, where the
//!   device has timestamp queries, the compute pass's and the main pass's GPU time.
//!
//! A frame is timed from the start of `Renderer::render` to the GPU finishing
//! (`device.poll(wait)`), without reading the image back: the median of several frames after a
//! warm-up frame. On a software adapter (lavapipe) this is CPU time; `cpu_ms_per_frame` is the
//! CPU time of the whole process (all of lavapipe's threads) per frame, which other programs
//! on the machine disturb far less than the wall time.

use crate::render::Renderer;
use crate::render::offscreen::{self, Gpu};
use glam::Vec3;
use grove_systems::Sim;
use grove_systems::components::{Head, Pose};
use grove_systems::grass::{GrassDef, GrassKind};
use grove_systems::scene::{CameraDef, PlaneShape, Scene, WindDef};
use serde_json::{Value, json};

use super::BenchError;
use super::render::frame_ms;

/// A flat square plane of `side` metres centred on the origin, cells of `cell` metres, with one
/// grass patch over all of it.
fn field(side: f32, cell: f32, grass: GrassDef) -> Scene {
    // The render benchmarks' flat ground, made perfectly flat, in a calmer wind.
    let mut scene = super::render::ground_scene(side / 2.0, cell);
    scene.name = "grass benchmark".into();
    scene.seed = 11;
    scene.planes[0].name = "field".into();
    if let PlaneShape::Grid { unevenness, noise_seed, .. } = &mut scene.planes[0].shape {
        *unevenness = 0.0;
        *noise_seed = 0;
    }
    scene.wind = WindDef { strength: 0.6, gust_average: 0.8, gust_strength: 0.3, ..scene.wind };
    scene.camera = CameraDef { position: Vec3::new(0.0, 1.7, side / 2.0), ..CameraDef::default() };
    scene.grass = vec![grass];
    scene
}

fn patch(kind: GrassKind, density: f32) -> GrassDef {
    GrassDef {
        name: "bench".into(),
        planes: vec![],
        polygon: vec![],
        kind,
        density,
        height: (0.12, 0.3),
        base_color: Vec3::new(0.02, 0.07, 0.01),
        tip_color: Vec3::new(0.12, 0.24, 0.04),
        shells: 20,
    }
}

fn sim_of(scene: &Scene, eye: Vec3, target: Vec3) -> Result<Sim, BenchError> {
    let mut sim = Sim::from_scene(scene, scene.seed).map_err(grove_systems::Error::from)?;
    sim.run(1);
    sim.set_up().camera(Head { pose: Pose::looking_at(eye, target), fov_y: 60f32.to_radians() });
    Ok(sim)
}

/// A renderer of `width`×`height` with pass timing where the device has it.
fn renderer(gpu: &Gpu, width: u32, height: u32) -> Result<Renderer, BenchError> {
    let mut r = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, width, height)?;
    let _ = r.enable_pass_timing();
    Ok(r)
}

/// The median frame time and pass times of `frames` frames after a warm-up frame, with the
/// blades the cull pass kept.
fn time(gpu: &Gpu, r: &mut Renderer, sim: &Sim, frames: usize) -> Result<Value, BenchError> {
    let (w, h) = r.size();
    let target = offscreen::Target::new(&gpu.device, w, h);
    let (mut wall, mut compute, mut main) = (Vec::new(), Vec::new(), Vec::new());
    let mut cpu_start = None;
    for i in 0..=frames.max(1) {
        if i == 1 {
            cpu_start = Some(super::process_cpu_seconds() * 1e3);
        }
        let ms = frame_ms(gpu, r, sim, &target)?;
        let passes = r.pass_times()?;
        if i == 0 {
            continue;
        }
        wall.push(ms);
        if let Some(p) = passes {
            compute.push(p.ms("grass compute"));
            main.push(p.ms("main"));
        }
    }
    let cpu = cpu_start.map(|a| (super::process_cpu_seconds() * 1e3 - a) / frames.max(1) as f64);
    let blades = r.features.grass.visible_blades()?;
    let ms = super::median(&mut wall);
    let mut v = json!({
        "ms_per_frame": ms,
        "fps": 1e3 / ms,
        "visible_blades": blades.total(),
        "visible_blades_near_mid_far": [blades.near, blades.mid, blades.far],
        "triangles": r.stats.triangles,
        "draws": r.stats.draws,
    });
    if let Some(cpu) = cpu {
        v["cpu_ms_per_frame"] = json!(cpu);
    }
    if !compute.is_empty() {
        v["gpu_compute_pass_ms"] = json!(super::median(&mut compute));
        v["gpu_main_pass_ms"] = json!(super::median(&mut main));
    }
    Ok(v)
}

/// Fukuda et al.'s test: the 1 km² shell field at 1280 × 720, with and without grass.
fn fukuda(gpu: &Gpu, frames: usize) -> Result<Value, BenchError> {
    // 128 strands per 2 m tile: 64 per metre, 4,096 per m². Cells of 20 m: 2,500 cells.
    let scene = field(1000.0, 20.0, GrassDef { height: (0.05, 0.1), ..patch(GrassKind::Shells, 4096.0) });
    let sim = sim_of(&scene, Vec3::new(0.0, 1.7, 480.0), Vec3::new(0.0, 0.0, 400.0))?;
    let mut r = renderer(gpu, 1280, 720)?;
    eprintln!("bench: grass, 1 km² shell field with grass");
    let with = time(gpu, &mut r, &sim, frames)?;
    r.options.grass = false;
    eprintln!("bench: grass, 1 km² shell field without grass");
    let without = time(gpu, &mut r, &sim, frames)?;
    // The frame rate lost, 1 - fps with / fps without = (with - without) / with in time, timed in
    // interleaved pairs of frames (src/bench/pairs.rs), not from the two rows above.
    eprintln!("bench: grass, 1 km² shell field in {frames} interleaved pairs of frames");
    let target = offscreen::Target::new(&gpu.device, 1280, 720);
    let drop = super::pairs::paired_share(frames, |on| {
        r.options.grass = on;
        frame_ms(gpu, &mut r, &sim, &target)
    })?;
    Ok(json!({
        "resolution": [1280, 720],
        "field_m": [1000, 1000],
        "tile_m": 2.0,
        "layers": 20,
        "with_grass": with,
        "without_grass": without,
        "fps_drop_percent": drop,
        "fps_drop": format!("the median over {frames} interleaved pairs of frames (without grass, with grass) of (with - without) / with"),
    }))
}

/// The blade counts considered, with the patch side (metres) at 400 blades per m².
const BLADE_COUNTS: [(&str, u32); 4] = [("10k", 10_000), ("37.6k", 37_600), ("100k", 100_000), ("1M", 1_000_000)];

/// A square blade patch of `n` blades at 400 per m², seen from 1.7 m above its near edge.
fn blade_sim(n: u32) -> Result<Sim, BenchError> {
    let side = (n as f32 / 400.0).sqrt();
    let scene = field(side, (side / 20.0).max(0.25), patch(GrassKind::Blades, 400.0));
    sim_of(&scene, Vec3::new(0.0, 1.7, side / 2.0 + 1.0), Vec3::new(0.0, 0.0, 0.0))
}

/// The blade figures at `sizes`.
fn blades(gpu: &Gpu, sizes: &[(u32, u32)], frames: usize) -> Result<Value, BenchError> {
    let mut out = serde_json::Map::new();
    for &(w, h) in sizes {
        let mut row = serde_json::Map::new();
        for (name, n) in BLADE_COUNTS {
            eprintln!("bench: grass, {name} blades at {w}x{h}");
            let sim = blade_sim(n)?;
            // A renderer per case: each builds its ground and blades from its own world.
            let mut r = renderer(gpu, w, h)?;
            row.insert(name.into(), time(gpu, &mut r, &sim, if n > 100_000 { frames.min(3) } else { frames })?);
        }
        out.insert(format!("{w}x{h}"), Value::Object(row));
    }
    Ok(Value::Object(out))
}

/// The goal case: 65,536 blades (16 × 16 m at 256 per m²) all in view from above, 640 × 360.
fn goal(gpu: &Gpu, frames: usize) -> Result<Value, BenchError> {
    let scene = field(16.0, 0.5, patch(GrassKind::Blades, 256.0));
    let sim = sim_of(&scene, Vec3::new(0.0, 12.0, 14.0), Vec3::new(0.0, 0.0, 0.5))?;
    let mut r = renderer(gpu, 640, 360)?;
    eprintln!("bench: grass, 65,536 blades in view at 640x360");
    let mut v = time(gpu, &mut r, &sim, frames)?;
    v["goal_ms"] = json!(33.0);
    // The same frame without grass: what the ground and the sky cost on their own.
    r.options.grass = false;
    let bare = time(gpu, &mut r, &sim, frames)?;
    v["without_grass_ms_per_frame"] = bare["ms_per_frame"].clone();
    v["without_grass_cpu_ms_per_frame"] = bare["cpu_ms_per_frame"].clone();
    Ok(v)
}

/// Runs `grove bench grass` (lavapipe or any adapter).
pub fn bench_grass() -> Result<Value, BenchError> {
    let gpu = Gpu::new()?;
    eprintln!("bench: grass on {}", gpu.adapter_name());
    Ok(json!({
        "adapter": gpu.adapter_name(),
        "timing": "median of frames after a warm-up: wall time of render + device.poll(wait); gpu_*_ms from timestamp queries where the device has them",
        "fukuda_1km2_shells": fukuda(&gpu, 5)?,
        "blades_considered": blades(&gpu, &[(640, 360), (1280, 720)], 5)?,
        "goal_65536_visible_640x360": goal(&gpu, 5)?,
    }))
}

/// Runs `grove bench grass-goals`: only the blade goal case and Fukuda et al.'s field, the
/// median of 20 and 10 frames.
pub fn bench_grass_goals() -> Result<Value, BenchError> {
    let gpu = Gpu::new()?;
    eprintln!("bench: grass goals on {}", gpu.adapter_name());
    Ok(json!({
        "adapter": gpu.adapter_name(),
        "goal_65536_visible_640x360": goal(&gpu, 20)?,
        "fukuda_1km2_shells": fukuda(&gpu, 10)?,
    }))
}

/// The grass case of `grove bench render-gpu` (a real GPU): 1M blades considered at 1280 × 720
/// (goal: at most 2.5 ms of GPU time) and 4M at 1920 × 1080 (goal: 160 fps or better), and the
/// 1 km² shell field.
pub fn bench_grass_gpu(gpu: &Gpu) -> Result<Value, BenchError> {
    let mut r = renderer(gpu, 1280, 720)?;
    eprintln!("bench: grass, 1M blades at 1280x720");
    let one = time(gpu, &mut r, &blade_sim(1_000_000)?, 30)?;
    let mut r = renderer(gpu, 1920, 1080)?;
    eprintln!("bench: grass, 4M blades at 1920x1080");
    let four = time(gpu, &mut r, &blade_sim(4_000_000)?, 30)?;
    Ok(json!({
        "blades_1M_1280x720": one,
        "blades_1M_goal_gpu_ms": 2.5,
        "blades_4M_1920x1080": four,
        "blades_4M_goal_fps": 160.0,
        "fukuda_1km2_shells": fukuda(gpu, 30)?,
    }))
}
