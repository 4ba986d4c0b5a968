//! `grove aerial flight --pyramid DIR`: the clipmap's CPU half on a scripted camera flight,
//! without a GPU: time in `update`, texels uploaded per frame, tiles loaded, frames with tiles
//! still missing, and the process's peak memory.
//!
//! The flight: a loop around the photograph's centre at a radius of 0.3 of its side, at
//! `--height` metres, the camera looking ahead along the path and `--pitch` degrees down, except
//! for the last tenth of the frames, which look straight down. Frames are paced at `--fps`
//! (what a renderer would take), so the loader thread reads tiles while frames go by.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::bail;
use clap::Args;
use glam::{DVec2, DVec3};
use grove::render::clipmap::Clipmap;
use grove::render::clipmap::{AerialPlacement, ClipCamera, ClipmapConfig, ClipmapSource};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;

/// Arguments of `grove aerial flight`.
#[derive(Args)]
pub struct FlightArgs {
    /// A pyramid folder written by `grove aerial tile`.
    #[arg(long)]
    pub pyramid: PathBuf,
    /// Clipmap levels (1..=16).
    #[arg(long, default_value_t = 8)]
    pub levels: u32,
    /// Texels per level side (a power of two, 16..=4096).
    #[arg(long, default_value_t = 1024)]
    pub size: u32,
    /// Ground sample distance of the photograph, metres per texel.
    #[arg(long, default_value_t = 0.1)]
    pub gsd: f64,
    /// Frames to fly.
    #[arg(long, default_value_t = 1200)]
    pub frames: u32,
    /// Frames per second the flight is paced at (0: as fast as `update` goes).
    #[arg(long, default_value_t = 60.0)]
    pub fps: f64,
    /// Ground speed, metres per second.
    #[arg(long, default_value_t = 40.0)]
    pub speed: f64,
    /// Flying height above the photograph, metres.
    #[arg(long, default_value_t = 60.0)]
    pub height: f64,
    /// How far below the horizon the camera looks, degrees.
    #[arg(long, default_value_t = 35.0)]
    pub pitch: f64,
    /// Print the results as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The camera at frame `i` of `frames`.
fn camera(a: &FlightArgs, side_m: DVec2, i: u32) -> ClipCamera {
    let centre = side_m / 2.0;
    let radius = 0.3 * side_m.min_element();
    let t = i as f64 / a.fps.max(1.0);
    let angle = a.speed * t / radius;
    let pos = centre + DVec2::new(angle.cos(), angle.sin()) * radius;
    let heading = DVec2::new(-angle.sin(), angle.cos());
    let forward = if i >= a.frames - a.frames / 10 {
        DVec3::NEG_Y
    } else {
        let p = a.pitch.to_radians();
        DVec3::new(heading.x * p.cos(), -p.sin(), heading.y * p.cos())
    };
    ClipCamera { eye: DVec3::new(pos.x, a.height, pos.y), forward, fov_y: 60f64.to_radians(), aspect: 16.0 / 9.0 }
}

/// The process's peak resident memory, MiB (Linux; 0 elsewhere).
fn peak_rss_mib() -> f64 {
    let status =
        grove_systems::files::read_text(std::path::Path::new("/proc/self/status"), grove_systems::files::Kind::Status)
            .unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(0.0, |kb| kb / 1024.0)
}

fn quantile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// Runs `grove aerial flight`.
pub fn flight(a: FlightArgs) -> anyhow::Result<ExitCode> {
    if a.frames == 0 || a.frames > 1_000_000 {
        bail!("--frames {} must be between 1 and 1000000", a.frames);
    }
    for (name, v) in [("gsd", a.gsd), ("speed", a.speed), ("height", a.height)] {
        if !(v.is_finite() && v > 0.0) {
            bail!("--{name} {v} must be a positive number");
        }
    }
    if !(a.fps.is_finite() && (0.0..=1000.0).contains(&a.fps)) {
        bail!("--fps {} must be between 0 and 1000", a.fps);
    }
    if !(a.pitch.is_finite() && (0.0..=90.0).contains(&a.pitch)) {
        bail!("--pitch {} must be between 0 and 90 degrees", a.pitch);
    }
    let config = ClipmapConfig { levels: a.levels, size: a.size };
    let placement = AerialPlacement { origin_m: DVec2::ZERO, gsd_m: a.gsd };
    let mut map = Clipmap::open(&a.pyramid, config, placement)?;
    let meta = map.meta().clone();
    let side_m = DVec2::new(meta.width as f64, meta.height as f64) * a.gsd;
    let bar = ProgressBar::new(a.frames as u64);
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} frames {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix("flight");
    let (mut times, mut texels) = (Vec::with_capacity(a.frames as usize), Vec::with_capacity(a.frames as usize));
    let mut frames_missing = 0u32;
    let start = Instant::now();
    for i in 0..a.frames {
        let cam = camera(&a, side_m, i);
        let t = Instant::now();
        let frame = map.update(&cam);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        texels.push(frame.uploads.iter().map(|u| u.w as u64 * u.h as u64).sum::<u64>());
        if map.stats().missing > 0 {
            frames_missing += 1;
        }
        drop(frame);
        bar.set_position(i as u64 + 1);
        if a.fps > 0.0 {
            let due = start + Duration::from_secs_f64((i + 1) as f64 / a.fps);
            if let Some(wait) = due.checked_duration_since(Instant::now()) {
                std::thread::sleep(wait);
            }
        }
    }
    bar.finish_and_clear();
    let stats = map.stats();
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let steady: Vec<u64> = texels[1..].to_vec();
    let mean_texels = steady.iter().sum::<u64>() as f64 / steady.len().max(1) as f64;
    let max_texels = steady.iter().copied().max().unwrap_or(0);
    let result = json!({
        "pyramid": a.pyramid.display().to_string(),
        "image": [meta.width, meta.height],
        "levels": a.levels,
        "size": a.size,
        "frames": a.frames,
        "fps": a.fps,
        "speed_m_per_s": a.speed,
        "height_m": a.height,
        "update_ms": {"mean": times.iter().sum::<f64>() / times.len() as f64, "p50": quantile(&sorted, 0.5), "p99": quantile(&sorted, 0.99), "max": sorted[sorted.len() - 1], "first": times[0]},
        "texels_per_frame": {"first": texels[0], "mean_after_first": mean_texels, "max_after_first": max_texels, "mean_after_first_mib": mean_texels * 4.0 / (1 << 20) as f64},
        "tiles": {"loaded": stats.loaded, "failed": stats.failed, "cancelled": stats.cancelled},
        "frames_with_missing_tiles": frames_missing,
        "peak_rss_mib": peak_rss_mib(),
        "last_error": stats.last_error,
    });
    if a.json {
        crate::cli::print_json(&result)?;
    } else {
        println!(
            "{}: {} frames, update {:.3} ms mean, {:.3} ms p99, {:.3} ms max; {:.0} texels per frame after the first ({} at most, {} in the first); {} tiles loaded, {} failed; {} frames with tiles missing; peak memory {:.0} MiB",
            a.pyramid.display(),
            a.frames,
            result["update_ms"]["mean"].as_f64().unwrap_or(0.0),
            quantile(&sorted, 0.99),
            sorted[sorted.len() - 1],
            mean_texels,
            max_texels,
            texels[0],
            stats.loaded,
            stats.failed,
            frames_missing,
            peak_rss_mib()
        );
    }
    Ok(ExitCode::SUCCESS)
}
