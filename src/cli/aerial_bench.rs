//! `grove aerial bench --scene FILE`: a camera flight over a scene with aerial photographs,
//! rendered offscreen three ways: with the canopy, with the crowns as tree models instead
//! (`--no-canopy`), and the photographed ground alone (no crowns): frame time, clipmap texels
//! uploaded per frame, frames with tiles still missing (a coarser level shown; the frame never
//! waits for them), the longest clipmap update, CPU time per frame, the GPU memory the renderer
//! allocated and peak resident memory. The flight goes straight across the photographs from west to
//! east at `--height`, looking `--pitch` degrees below the horizon, at `--speed` metres per
//! second of simulated time at 30 frames per second.
//!
//! On a real GPU (`--width 1920 --height 1080`) the frame time is the wall time of submitting a
//! frame and waiting for it, as on lavapipe.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, bail};
use clap::Args;
use glam::Vec3;
use grove::render::offscreen::{self, Gpu};
use grove::render::{RenderOptions, Renderer};
use grove_systems::components::Pose;
use grove_systems::Sim;
use serde_json::json;

/// Arguments of `grove aerial bench`.
#[derive(Args)]
pub struct AerialBenchArgs {
    /// A scene with an `aerial` section.
    #[arg(long)]
    pub scene: PathBuf,
    /// Image width, pixels.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height, pixels.
    #[arg(long, default_value_t = 360)]
    pub height: u32,
    /// Frames per run (each run: with the canopy, then without).
    #[arg(long, default_value_t = 120)]
    pub frames: u32,
    /// Flying height, metres.
    #[arg(long, default_value_t = 40.0)]
    pub fly_height: f32,
    /// How far below the horizon the camera looks, degrees.
    #[arg(long, default_value_t = 35.0)]
    pub pitch: f32,
    /// Ground speed, metres per second (30 frames per second).
    #[arg(long, default_value_t = 20.0)]
    pub speed: f32,
    /// Turn the sun's shadow map off.
    #[arg(long)]
    pub no_shadows: bool,
    /// Print the results as JSON.
    #[arg(long)]
    pub json: bool,
    /// The runs to make, of `canopy`, `models` (the crowns as tree models) and `ground` (no
    /// crowns); all three by default.
    #[arg(long, value_delimiter = ',', default_values_t = [RunKind::Canopy, RunKind::Models, RunKind::Ground])]
    pub runs: Vec<RunKind>,
}

/// One of the bench's runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum RunKind {
    /// The crowns as canopy layers.
    Canopy,
    /// The crowns as tree models.
    Models,
    /// The photographed ground alone, no crowns.
    Ground,
}

impl std::fmt::Display for RunKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RunKind::Canopy => "canopy",
            RunKind::Models => "models",
            RunKind::Ground => "ground",
        })
    }
}

/// The process's CPU time so far (user and system, every thread), milliseconds (Linux; 0
/// elsewhere): lavapipe draws on worker threads, so on a shared machine this is steadier than
/// the wall time.
fn cpu_ms() -> f64 {
    let stat = grove_systems::files::read_text(std::path::Path::new("/proc/self/stat"), grove_systems::files::Kind::Status).unwrap_or_default();
    // The fields after the command's closing parenthesis; utime and stime are the 12th and 13th.
    let rest = stat.rsplit_once(')').map_or("", |r| r.1);
    let f: Vec<f64> = rest.split_whitespace().skip(11).take(2).filter_map(|v| v.parse().ok()).collect();
    // Clock ticks of 10 ms (USER_HZ is 100 on Linux).
    f.iter().sum::<f64>() * 10.0
}

/// The process's peak resident memory, MiB (Linux; 0 elsewhere).
fn peak_rss_mib() -> f64 {
    grove::bench::status_mib("VmHWM")
}

/// One run's figures.
struct Run {
    median_ms: f64,
    p95_ms: f64,
    upload_mean_kib: f64,
    upload_max_kib: f64,
    /// CPU time per timed frame, milliseconds.
    cpu_ms: f64,
    /// Timed frames with tiles still missing (a coarser level shown).
    frames_missing: u32,
    /// The longest clipmap update of a timed frame, milliseconds.
    update_max_ms: f64,
    /// The most GPU memory in textures and buffers, and the most the device's allocator
    /// reserved for them, during the run, MiB (None where the backend does not report it).
    gpu_mib: Option<(f64, f64)>,
}

fn fly(gpu: &Gpu, a: &AerialBenchArgs, scene: &grove_systems::scene::Scene, canopy: bool) -> anyhow::Result<Run> {
    let mut sim = Sim::from_scene(scene, scene.seed).map_err(|e| anyhow!(e))?;
    let mut r = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, a.width, a.height)?;
    r.options = RenderOptions { overlay: false, canopy, shadows: !a.no_shadows, ..Default::default() };
    let sources = grove::aerial::open::open_sources(scene, false).map_err(|e| anyhow!(e))?.ok_or_else(|| anyhow!("{}: the scene has no aerial section", a.scene.display()))?;
    let def = scene.aerial.as_ref().expect("checked");
    let (x0, x1) = (def.origin.x, def.origin.x + sources.size_m.x);
    let z = def.origin.y + sources.size_m.y * 0.75;
    r.features.aerial.set(sources)?;
    let target = offscreen::Target::new(&gpu.device, a.width, a.height);
    let (mut times, mut uploads) = (Vec::new(), Vec::new());
    let (mut cpu_start, mut frames_missing, mut update_max_ms, mut gpu_bytes) = (0.0, 0u32, 0.0f64, None::<(u64, u64)>);
    // Two frames to build the pipelines, not timed.
    for i in 0..a.frames + 2 {
        let x = (x0 + (i as f32) * a.speed / 30.0).min(x1);
        let eye = Vec3::new(x, a.fly_height, z);
        let look = eye + Vec3::new(0.0, -a.pitch.to_radians().sin(), -a.pitch.to_radians().cos());
        sim.set_up().camera_pose(Pose::looking_at(eye, look));
        if i == 2 {
            cpu_start = cpu_ms();
        }
        let t = Instant::now();
        r.render(&sim, target.view())?;
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow!("{e}"))?;
        if i >= 2 {
            times.push(t.elapsed().as_secs_f64() * 1e3);
            uploads.push(r.features.aerial.upload_bytes() as f64 / 1024.0);
            let (missing, update_ms) = r.features.aerial.streaming();
            frames_missing += u32::from(missing > 0);
            update_max_ms = update_max_ms.max(update_ms);
        }
        if let Some(report) = gpu.device.generate_allocator_report() {
            let (a, r) = gpu_bytes.unwrap_or((0, 0));
            gpu_bytes = Some((a.max(report.total_allocated_bytes), r.max(report.total_reserved_bytes)));
        }
    }
    let cpu = (cpu_ms() - cpu_start) / f64::from(a.frames.max(1));
    times.sort_by(f64::total_cmp);
    let n = times.len().max(1);
    Ok(Run {
        median_ms: times[n / 2],
        p95_ms: times[((n - 1) as f64 * 0.95).round() as usize],
        upload_mean_kib: uploads.iter().sum::<f64>() / n as f64,
        upload_max_kib: uploads.iter().copied().fold(0.0, f64::max),
        cpu_ms: cpu,
        frames_missing,
        update_max_ms,
        gpu_mib: gpu_bytes.map(|(a, r)| (a as f64 / 1_048_576.0, r as f64 / 1_048_576.0)),
    })
}

/// Runs `grove aerial bench`.
pub fn run(a: AerialBenchArgs) -> anyhow::Result<ExitCode> {
    if !(1..=8192).contains(&a.width) || !(1..=8192).contains(&a.height) {
        bail!("--width and --height must be between 1 and 8192");
    }
    if !(1..=100_000).contains(&a.frames) {
        bail!("--frames {} must be between 1 and 100000", a.frames);
    }
    if !(a.fly_height.is_finite() && a.fly_height > 0.0 && a.pitch.is_finite() && (1.0..=90.0).contains(&a.pitch) && a.speed.is_finite() && a.speed >= 0.0) {
        bail!("--fly-height must be positive, --pitch in 1..=90 degrees and --speed non-negative");
    }
    let scene = super::load_scene(&a.scene)?;
    if scene.aerial.is_none() {
        bail!("{}: the scene has no aerial section", a.scene.display());
    }
    if a.runs.is_empty() {
        bail!("--runs needs at least one of canopy, models, ground");
    }
    let gpu = Gpu::new()?;
    let mut bare = scene.clone();
    if let Some(def) = &mut bare.aerial {
        def.crowns = None;
        def.crown_list.clear();
    }
    let mut runs = Vec::new();
    for kind in &a.runs {
        let run = match kind {
            RunKind::Canopy => fly(&gpu, &a, &scene, true)?,
            RunKind::Models => fly(&gpu, &a, &scene, false)?,
            RunKind::Ground => fly(&gpu, &a, &bare, true)?,
        };
        runs.push((*kind, run));
    }
    let peak = peak_rss_mib();
    let name = |k: RunKind| match k {
        RunKind::Canopy => "canopy",
        RunKind::Models => "crowns_as_models",
        RunKind::Ground => "ground_only",
    };
    // MiB of texels: RGBA8, 4 bytes a texel.
    let texels = |kib: f64| kib * 1024.0 / 4.0;
    if a.json {
        let j = |r: &Run| {
            json!({ "median_ms": r.median_ms, "p95_ms": r.p95_ms, "fps": 1e3 / r.median_ms, "cpu_ms_per_frame": r.cpu_ms, "upload_kib_mean": r.upload_mean_kib, "upload_kib_max": r.upload_max_kib,
                "upload_texels_mean": texels(r.upload_mean_kib), "upload_texels_max": texels(r.upload_max_kib), "frames_with_missing_tiles": r.frames_missing,
                "frames_waiting_on_disk": 0, "clipmap_update_max_ms": r.update_max_ms, "gpu_allocated_mib_peak": r.gpu_mib.map(|g| g.0), "gpu_reserved_mib_peak": r.gpu_mib.map(|g| g.1) })
        };
        let mut out = serde_json::Map::new();
        for (k, r) in &runs {
            out.insert(name(*k).to_string(), j(r));
        }
        super::print_json(&json!({ "adapter": gpu.adapter_name(), "width": a.width, "height": a.height, "frames": a.frames, "runs": out, "peak_rss_mib": peak }))?;
    } else {
        println!("{} at {}x{}, {} frames", gpu.adapter_name(), a.width, a.height, a.frames);
        for (k, r) in &runs {
            println!(
                "  {:>16}: median {:.1} ms ({:.1} fps), p95 {:.1} ms, CPU {:.1} ms a frame; clipmap upload {:.0} KiB ({:.0} texels) a frame on average, {:.0} KiB at most; {} frames with tiles missing (none waits: the longest clipmap update took {:.1} ms); GPU memory {}",
                name(*k).replace('_', " "),
                r.median_ms,
                1e3 / r.median_ms,
                r.p95_ms,
                r.cpu_ms,
                r.upload_mean_kib,
                texels(r.upload_mean_kib),
                r.upload_max_kib,
                r.frames_missing,
                r.update_max_ms,
                r.gpu_mib.map_or("not reported".to_string(), |(a, r)| format!("{a:.0} MiB at most ({r:.0} MiB reserved)"))
            );
        }
        println!("  peak resident memory {peak:.0} MiB");
    }
    Ok(ExitCode::SUCCESS)
}
