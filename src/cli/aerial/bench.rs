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

use anyhow::bail;
use clap::Args;
use grove::bench::aerial::{Flight, fly};
use grove::render::offscreen::Gpu;
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

/// Runs `grove aerial bench`.
pub fn run(a: AerialBenchArgs) -> anyhow::Result<ExitCode> {
    if !(1..=8192).contains(&a.width) || !(1..=8192).contains(&a.height) {
        bail!("--width and --height must be between 1 and 8192");
    }
    if !(1..=100_000).contains(&a.frames) {
        bail!("--frames {} must be between 1 and 100000", a.frames);
    }
    if !(a.fly_height.is_finite()
        && a.fly_height > 0.0
        && a.pitch.is_finite()
        && (1.0..=90.0).contains(&a.pitch)
        && a.speed.is_finite()
        && a.speed >= 0.0)
    {
        bail!("--fly-height must be positive, --pitch in 1..=90 degrees and --speed non-negative");
    }
    let scene = crate::cli::load_scene(&a.scene)?;
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
    let flight = Flight {
        width: a.width,
        height: a.height,
        frames: a.frames,
        fly_height: a.fly_height,
        pitch: a.pitch,
        speed: a.speed,
        shadows: !a.no_shadows,
    };
    let mut runs = Vec::new();
    for kind in &a.runs {
        let run = match kind {
            RunKind::Canopy => fly(&gpu, &flight, &scene, true)?,
            RunKind::Models => fly(&gpu, &flight, &scene, false)?,
            RunKind::Ground => fly(&gpu, &flight, &bare, true)?,
        };
        runs.push((*kind, run));
    }
    let peak = grove::bench::status_mib("VmHWM");
    let name = |k: RunKind| match k {
        RunKind::Canopy => "canopy",
        RunKind::Models => "crowns_as_models",
        RunKind::Ground => "ground_only",
    };
    // MiB of texels: RGBA8, 4 bytes a texel.
    let texels = |kib: f64| kib * 1024.0 / 4.0;
    if a.json {
        let mut out = serde_json::Map::new();
        for (k, r) in &runs {
            out.insert(name(*k).to_string(), r.json());
        }
        crate::cli::print_json(
            &json!({ "adapter": gpu.adapter_name(), "width": a.width, "height": a.height, "frames": a.frames, "runs": out, "peak_rss_mib": peak }),
        )?;
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
                r.gpu_mib
                    .map_or("not reported".to_string(), |(a, r)| format!("{a:.0} MiB at most ({r:.0} MiB reserved)"))
            );
        }
        println!("  peak resident memory {peak:.0} MiB");
    }
    Ok(ExitCode::SUCCESS)
}
