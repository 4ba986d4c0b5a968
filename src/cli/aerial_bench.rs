//! `grove aerial bench --scene FILE`: a camera flight over a scene with aerial photographs,
//! rendered offscreen three ways: with the canopy, with the crowns as tree models instead
//! (`--no-canopy`), and the photographed ground alone (no crowns): frame time, clipmap texels
//! uploaded per frame and peak resident memory. The flight goes straight across the photographs from west to
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
use grove_systems::components::{Head, Pose};
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
}

/// The process's peak resident memory, MiB (Linux; 0 elsewhere).
fn peak_rss_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status.lines().find_map(|l| l.strip_prefix("VmHWM:")).and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok()).map_or(0.0, |kb| kb / 1024.0)
}

/// One run's figures.
struct Run {
    median_ms: f64,
    p95_ms: f64,
    upload_mean_kib: f64,
    upload_max_kib: f64,
}

fn fly(gpu: &Gpu, a: &AerialBenchArgs, scene: &grove_systems::scene::Scene, canopy: bool) -> anyhow::Result<Run> {
    let mut sim = Sim::from_scene(scene, scene.seed).map_err(|e| anyhow!(e))?;
    let mut r = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, a.width, a.height).map_err(|e| anyhow!(e))?;
    r.options = RenderOptions { overlay: false, canopy, shadows: !a.no_shadows, ..Default::default() };
    let sources = grove::aerial::open::open_sources(scene, false).map_err(|e| anyhow!(e))?.ok_or_else(|| anyhow!("{}: the scene has no aerial section", a.scene.display()))?;
    let def = scene.aerial.as_ref().expect("checked");
    let (x0, x1) = (def.origin.x, def.origin.x + sources.size_m.x);
    let z = def.origin.y + sources.size_m.y * 0.75;
    r.set_aerial(sources).map_err(|e| anyhow!(e))?;
    let target = offscreen::Target::new(&gpu.device, a.width, a.height);
    let (mut times, mut uploads) = (Vec::new(), Vec::new());
    // Two frames to build the pipelines, not timed.
    for i in 0..a.frames + 2 {
        let x = (x0 + (i as f32) * a.speed / 30.0).min(x1);
        let eye = Vec3::new(x, a.fly_height, z);
        let look = eye + Vec3::new(0.0, -a.pitch.to_radians().sin(), -a.pitch.to_radians().cos());
        for head in sim.world.query_mut::<&mut Head>() {
            head.pose = Pose::looking_at(eye, look);
        }
        let t = Instant::now();
        r.render(&sim, target.view()).map_err(|e| anyhow!(e))?;
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow!("{e}"))?;
        if i >= 2 {
            times.push(t.elapsed().as_secs_f64() * 1e3);
            uploads.push(r.aerial_upload_bytes() as f64 / 1024.0);
        }
    }
    times.sort_by(f64::total_cmp);
    let n = times.len().max(1);
    Ok(Run {
        median_ms: times[n / 2],
        p95_ms: times[((n - 1) as f64 * 0.95).round() as usize],
        upload_mean_kib: uploads.iter().sum::<f64>() / n as f64,
        upload_max_kib: uploads.iter().copied().fold(0.0, f64::max),
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
    let gpu = Gpu::new().map_err(|e| anyhow!(e))?;
    let with = fly(&gpu, &a, &scene, true)?;
    let without = fly(&gpu, &a, &scene, false)?;
    let mut bare = scene.clone();
    if let Some(def) = &mut bare.aerial {
        def.crowns = None;
        def.crown_list.clear();
    }
    let ground = fly(&gpu, &a, &bare, true)?;
    let peak = peak_rss_mib();
    if a.json {
        let j = |r: &Run| json!({ "median_ms": r.median_ms, "p95_ms": r.p95_ms, "fps": 1e3 / r.median_ms, "upload_kib_mean": r.upload_mean_kib, "upload_kib_max": r.upload_max_kib });
        super::print_json(&json!({ "adapter": gpu.adapter_name(), "width": a.width, "height": a.height, "frames": a.frames, "canopy": j(&with), "crowns_as_models": j(&without), "ground_only": j(&ground), "peak_rss_mib": peak }))?;
    } else {
        println!("{} at {}x{}, {} frames", gpu.adapter_name(), a.width, a.height, a.frames);
        for (name, r) in [("canopy", &with), ("crowns as models", &without), ("ground only", &ground)] {
            println!(
                "  {name:>16}: median {:.1} ms ({:.1} fps), p95 {:.1} ms; clipmap upload {:.0} KiB a frame on average, {:.0} KiB at most",
                r.median_ms,
                1e3 / r.median_ms,
                r.p95_ms,
                r.upload_mean_kib,
                r.upload_max_kib
            );
        }
        println!("  peak resident memory {peak:.0} MiB");
    }
    Ok(ExitCode::SUCCESS)
}
