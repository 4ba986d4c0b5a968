//! `grove bench video`: the 5-minute session of the replay benchmark
//! ([`super::replay::five_minute_session`]: the controller sweeping, planting and removing)
//! written as a 1280 × 720, 30 fps video from the head camera (9,000 frames), timed as a whole,
//! with the process's memory every 1,000 frames to show that it stays flat.

use std::time::Instant;

use crate::render::Renderer;
use crate::render::offscreen::{self, Gpu};
use crate::video::{self, VideoSpec, camera::CameraKind};
use grove_systems::replay::Player;
use serde_json::{Value, json};

use super::{BenchError, status_mib};

/// The goal: a 5-minute session encoded in at most real time.
const GOAL_S: f64 = 300.0;

/// Writes the video and returns its figures.
pub fn bench_video() -> Result<Value, BenchError> {
    eprintln!("bench: a 5-minute session as a 1280x720, 30 fps video");
    let dir = tempfile_dir()?;
    let recording = dir.join("five-minutes.jsonl");
    crate::atomic_write::write_bytes(&recording, &super::replay::five_minute_session()?)?;
    let open = || Player::open(&recording, &[], &Default::default()).map_err(grove_systems::Error::from);
    let player = open()?;
    let (area, condition) = video::survey(open()?);
    let (from, to) = (0, player.final_tick());
    let gpu = Gpu::new()?;
    let mut renderer = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, 1280, 720)?;
    let out = dir.join("five-minutes.mp4");
    let spec = VideoSpec {
        camera: CameraKind::Head,
        from,
        to,
        fps: 30,
        speed: 1.0,
        area,
        who: format!("bench · {condition}"),
        out: &out,
    };
    let mut rss = Vec::new();
    let started = Instant::now();
    let cpu0 = super::process_cpu_seconds();
    let summary = video::write(&gpu, &mut renderer, player, Vec::new(), &spec, &mut |k| {
        if k % 1000 == 0 {
            rss.push(json!({"frame": k, "rss_mib": (status_mib("VmRSS") * 10.0).round() / 10.0}));
        }
    })?;
    let wall = started.elapsed().as_secs_f64();
    let cpu = super::process_cpu_seconds() - cpu0;
    let video_s = summary.frames as f64 / 30.0;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(json!({
        "adapter": gpu.adapter_name(),
        "size": "1280x720",
        "fps": 30,
        "camera": "head",
        "frames": summary.frames,
        "video_s": video_s,
        "wall_s": (wall * 10.0).round() / 10.0,
        "cpu_s": (cpu * 10.0).round() / 10.0,
        "frames_per_s": (summary.frames as f64 / wall * 10.0).round() / 10.0,
        "x_real_time": (video_s / wall * 100.0).round() / 100.0,
        "goal_wall_s": GOAL_S,
        "mb": (summary.bytes as f64 / 1e5).round() / 10.0,
        "peak_rss_mib": (status_mib("VmHWM") * 10.0).round() / 10.0,
        "rss_every_1000_frames": rss,
    }))
}

/// A fresh folder under the system's temporary folder.
fn tempfile_dir() -> Result<std::path::PathBuf, BenchError> {
    let dir = std::env::temp_dir().join(format!("grove-bench-video-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|source| BenchError::Folder { path: dir.clone(), source })?;
    Ok(dir)
}
