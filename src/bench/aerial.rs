//! The aerial flight benchmark behind `grove aerial bench` (`docs/aerial-canopy.md`): a camera
//! flight over a scene with aerial photographs, rendered offscreen with the canopy, with the
//! crowns as tree models, or over the photographed ground alone. The flight goes straight across
//! the photographs from west to east at a height, looking some degrees below the horizon, at a
//! ground speed in metres per second of simulated time at 30 frames per second. Per run: frame
//! times, clipmap texels uploaded per frame, frames with tiles still missing (a coarser level
//! shown; the frame never waits for them), the longest clipmap update, CPU time per frame and
//! the GPU memory the renderer allocated.
//!
//! On a real GPU the frame time is the wall time of submitting a frame and waiting for it, as on
//! lavapipe.

use std::time::Instant;

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::components::Pose;
use grove_systems::scene::Scene;
use serde_json::{Value, json};

use crate::render::offscreen::{self, Gpu};
use crate::render::{RenderOptions, Renderer};

use super::BenchError;

/// How a flight is flown and drawn.
#[derive(Clone, Copy, Debug)]
pub struct Flight {
    /// Image width, pixels.
    pub width: u32,
    /// Image height, pixels.
    pub height: u32,
    /// Timed frames (two more build the pipelines first).
    pub frames: u32,
    /// Flying height, metres.
    pub fly_height: f32,
    /// How far below the horizon the camera looks, degrees.
    pub pitch: f32,
    /// Ground speed, metres per second at 30 frames per second.
    pub speed: f32,
    /// Draw the sun's shadow map.
    pub shadows: bool,
}

/// One run's figures.
pub struct Run {
    /// The median frame time, milliseconds.
    pub median_ms: f64,
    /// The 95th percentile of the frame times, milliseconds.
    pub p95_ms: f64,
    /// Clipmap texels uploaded per timed frame on average, KiB.
    pub upload_mean_kib: f64,
    /// The most clipmap texels one timed frame uploaded, KiB.
    pub upload_max_kib: f64,
    /// CPU time per timed frame, milliseconds.
    pub cpu_ms: f64,
    /// Timed frames with tiles still missing (a coarser level shown).
    pub frames_missing: u32,
    /// The longest clipmap update of a timed frame, milliseconds.
    pub update_max_ms: f64,
    /// The most GPU memory in textures and buffers, and the most the device's allocator
    /// reserved for them, during the run, MiB (None where the backend does not report it).
    pub gpu_mib: Option<(f64, f64)>,
}

/// Flies `scene` (which has an `aerial` section) with the canopy or with the crowns as models.
pub fn fly(gpu: &Gpu, a: &Flight, scene: &Scene, canopy: bool) -> Result<Run, BenchError> {
    let mut sim = Sim::from_scene(scene, scene.seed).map_err(grove_systems::Error::from)?;
    let mut r = Renderer::new(&gpu.device, &gpu.queue, offscreen::FORMAT, a.width, a.height)?;
    r.options = RenderOptions { overlay: false, canopy, shadows: a.shadows, ..Default::default() };
    let sources = crate::render::aerial_ground::open::open_sources(scene, false)?.ok_or(BenchError::NoAerial)?;
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
            cpu_start = super::process_cpu_seconds();
        }
        let t = Instant::now();
        r.render(&sim, target.view())?;
        gpu.device.poll(wgpu::PollType::wait_indefinitely())?;
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
    let cpu = (super::process_cpu_seconds() - cpu_start) * 1e3 / f64::from(a.frames.max(1));
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

impl Run {
    /// The run's figures as JSON (`grove aerial bench --json`).
    pub fn json(&self) -> Value {
        // RGBA8: 4 bytes a texel.
        let texels = |kib: f64| kib * 1024.0 / 4.0;
        json!({ "median_ms": self.median_ms, "p95_ms": self.p95_ms, "fps": 1e3 / self.median_ms, "cpu_ms_per_frame": self.cpu_ms, "upload_kib_mean": self.upload_mean_kib, "upload_kib_max": self.upload_max_kib,
            "upload_texels_mean": texels(self.upload_mean_kib), "upload_texels_max": texels(self.upload_max_kib), "frames_with_missing_tiles": self.frames_missing,
            "frames_waiting_on_disk": 0, "clipmap_update_max_ms": self.update_max_ms, "gpu_allocated_mib_peak": self.gpu_mib.map(|g| g.0), "gpu_reserved_mib_peak": self.gpu_mib.map(|g| g.1) })
    }
}
