//! `grove render --replay FILE --video OUT.mp4`: the arguments checked, the recording, its
//! ghosts and the renderer opened; drawing and encoding are `grove::video`'s. The video is
//! written through a temporary file and a rename, so a failed or bad run leaves no file.

use std::process::ExitCode;
use std::time::Instant;

use anyhow::{anyhow, bail};
use grove::atomic_write::write_via_temp;
use grove::render::offscreen::Gpu;
use grove::video::{self, Mark, VideoSpec, camera::CameraKind};
use grove_systems::replay::Player;

use super::{OutFile, RenderArgs, check_out_file};

/// `--video`: an `.mp4` file.
const MP4_OUT: OutFile = OutFile { flag: "--video", ext: "mp4", name: "an .mp4", kind: "an .mp4 file" };

/// Runs `grove render --replay FILE --video OUT.mp4`.
pub fn run(args: RenderArgs) -> anyhow::Result<ExitCode> {
    let args = &args;
    let out = args.video.as_deref().ok_or_else(|| anyhow!("give --video OUT.mp4"))?;
    super::check_size(args.width, args.height)?;
    let replay = args.replay.as_deref().ok_or_else(|| anyhow!("--video needs --replay FILE"))?;
    check_out_file(out, args.force, &MP4_OUT)?;
    if args.width % 2 != 0 || args.height % 2 != 0 {
        bail!("--width and --height must be even for a video (got {}x{})", args.width, args.height);
    }
    if !(args.fps.fract() == 0.0 && (1.0..=120.0).contains(&args.fps)) {
        bail!("--fps must be a whole number from 1 to 120 for a video (got {})", args.fps);
    }
    if !(args.speed.is_finite() && args.speed > 0.0 && args.speed <= 1000.0) {
        bail!("--speed must be in (0, 1000] (got {})", args.speed);
    }
    let fps = args.fps as u32;
    if let Some(dir) = &args.ghosts {
        if !dir.is_dir() {
            bail!("{}: --ghosts needs a folder of recordings", dir.display());
        }
    }
    let banks = grove::bank::open_session(&args.banks).map_err(|e| anyhow!(e))?;
    let player = Player::open(replay, &[], &banks).map_err(|e| anyhow!(e))?;
    let end = player.final_tick();
    let from =
        args.from.unwrap_or(Mark::Tick(0)).tick(&player).map_err(|e| anyhow!("{}: --from: {e}", replay.display()))?;
    let to = args.to.map_or(Ok(end), |m| m.tick(&player)).map_err(|e| anyhow!("{}: --to: {e}", replay.display()))?;
    if to > end {
        bail!("{}: --to {to} is past the recording's end (tick {end})", replay.display());
    }
    if from >= to {
        bail!("--from (tick {from}) must come before --to (tick {to})");
    }
    let dt = player.sim().dt();
    let frames = (to - from) as f64 * dt as f64 / args.speed * fps as f64;
    if frames > video::MAX_FRAMES as f64 {
        bail!(
            "{frames:.0} frames asked for; a video has at most {} (raise --speed or narrow --from/--to)",
            video::MAX_FRAMES
        );
    }
    let ghosts = match &args.ghosts {
        Some(dir) => video::ghosts::open(dir, replay, player.header.task.as_deref(), player.task_start_tick(), &banks)
            .map_err(|e| anyhow!(e))?,
        None => Vec::new(),
    };
    let (area, condition) = video::survey(Player::open(replay, &[], &banks).map_err(|e| anyhow!(e))?);
    let participant = player.header.participant.clone().unwrap_or_else(|| "participant".into());
    let who = match &player.header.task {
        Some(task) => format!("{participant} · {condition} · {task}"),
        None => format!("{participant} · {condition}"),
    };

    let scene = grove_systems::replay::scene_ref::resolve_scene(&player.header.scene, replay.parent())
        .map_err(|e| anyhow!(e))?;
    let aerial = grove::render::aerial_ground::open::open_sources(&scene, args.debug_lod).map_err(|e| anyhow!(e))?;
    let gpu = Gpu::new()?;
    let mut renderer = super::renderer(&gpu, args, player.sim(), &scene, aerial)?;
    let n = video::frame_ticks(from, to, fps, args.speed, dt).len() as u64;
    let bar = indicatif::ProgressBar::new(n);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} {wide_bar} {pos}/{len} frames, {per_sec}, {eta} left")
            .map_err(|e| anyhow!(e))?,
    );
    bar.set_message("rendering");
    let ghost_count = ghosts.len();
    let started = Instant::now();
    let summary = write_via_temp(out, |tmp| {
        let spec = VideoSpec { camera: args.camera, from, to, fps, speed: args.speed, area, who, out: tmp };
        video::write(&gpu, &mut renderer, player, ghosts, &spec, &mut |k| bar.set_position(k)).map_err(|e| anyhow!(e))
    })?;
    bar.finish_and_clear();
    let secs = started.elapsed().as_secs_f64();
    let camera = match args.camera {
        CameraKind::Head => "head",
        CameraKind::Shoulder => "shoulder",
        CameraKind::Top => "top",
        CameraKind::Orbit => "orbit",
    };
    println!(
        "{}: wrote {} frames ({:.1} s of video at {fps} fps, ticks {from}–{to}, {camera} camera, {ghost_count} ghosts, {:.1} MB) of {} in {secs:.1} s ({:.1} frames/s) on {}",
        out.display(),
        summary.frames,
        summary.frames as f64 / fps as f64,
        summary.bytes as f64 / 1e6,
        replay.display(),
        summary.frames as f64 / secs.max(1e-9),
        gpu.adapter_name()
    );
    Ok(ExitCode::SUCCESS)
}
