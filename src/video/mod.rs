//! Replays as video: a recording re-simulated tick by tick ([`grove_systems::replay::Player`]),
//! drawn at every frame's tick from one of four cameras ([`camera`]), with the interaction
//! overlay, other participants as ghosts ([`ghosts`]) and burned-in captions ([`captions`]),
//! encoded as H.264 in MP4 ([`encode`]). Frames are drawn on this thread and encoded on a
//! second one, two frames apart at most, so memory stays flat however long the video.
//!
//! Knows nothing of the command line: `cli/render/` parses the arguments, builds the renderer
//! and calls [`write`].

pub mod camera;
pub mod captions;
pub mod encode;
pub mod ghosts;

use std::path::Path;
use std::sync::mpsc;

use crate::render::Renderer;
use crate::render::offscreen::{Gpu, Target};
use grove_systems::replay::Player;

use camera::{CameraKind, Shoulder, TaskArea};
use captions::Captions;
use encode::{VideoError, VideoWriter};
use ghosts::Ghost;

/// A point of a recording a video starts or ends at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A tick.
    Tick(u64),
    /// The tick of the `start_task` event.
    TaskStart,
    /// The tick of the `end_task` event.
    TaskEnd,
}

/// Why a mark names no tick.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum MarkError {
    /// Neither a number nor a task mark.
    #[error("'{0}' is neither a tick (a whole number) nor a task mark (task-start, task-end)")]
    Unknown(String),
    /// `task-start` in a recording without a `start_task` event.
    #[error("the recording starts no task (no task-start mark)")]
    NoTaskStart,
    /// `task-end` in a recording without an `end_task` event.
    #[error("the recording ends no task (no task-end mark)")]
    NoTaskEnd,
}

impl std::str::FromStr for Mark {
    type Err = MarkError;
    fn from_str(s: &str) -> Result<Mark, MarkError> {
        match s {
            "task-start" => Ok(Mark::TaskStart),
            "task-end" => Ok(Mark::TaskEnd),
            _ => s.parse::<u64>().map(Mark::Tick).map_err(|_| MarkError::Unknown(s.to_string())),
        }
    }
}

impl Mark {
    /// The tick this mark names in `player`'s recording.
    pub fn tick(self, player: &Player) -> Result<u64, MarkError> {
        match self {
            Mark::Tick(t) => Ok(t),
            Mark::TaskStart => player.task_start_tick().ok_or(MarkError::NoTaskStart),
            Mark::TaskEnd => player.task_end_tick().ok_or(MarkError::NoTaskEnd),
        }
    }
}

/// The most frames one video may have (an hour at 60 fps).
pub const MAX_FRAMES: u64 = 216_000;

/// The ticks the frames of a video from tick `from` to `to` show at `fps` frames per second
/// played at `speed` times real time, with a fixed step of `dt` seconds: one frame every
/// `speed / fps` simulated seconds, starting at `from`, as many as fit in `(to − from)·dt /
/// speed` seconds of video (at least one).
pub fn frame_ticks(from: u64, to: u64, fps: u32, speed: f64, dt: f32) -> Vec<u64> {
    let span = to.saturating_sub(from) as f64 * dt as f64;
    let n = ((span / speed * fps as f64).round() as u64).clamp(1, MAX_FRAMES);
    let ticks_per_frame = speed / (fps as f64 * dt as f64);
    // The step is an f32 (1/60 is 0.016666668): a millionth of a tick absorbs its rounding.
    (0..n).map(|k| (from + (k as f64 * ticks_per_frame + 1e-6).round() as u64).min(to)).collect()
}

/// What a video needs to know of its recording before the first frame: the task area (its
/// targets and where the participant stood when the task started, or at the first tick
/// without a task) and the condition (the interaction mode then), found by replaying a second
/// copy of it to there.
pub fn survey(mut probe: Player) -> (TaskArea, String) {
    let at = probe.task_start_tick().map_or(1, |t| t + 1).min(probe.final_tick().max(1));
    probe.advance_to(at);
    let sim = probe.sim();
    let head = sim.head().pose.position;
    let mut points = vec![head];
    let mut ground = head.y - 1.6;
    if let Some(task) = sim.task() {
        points.extend(task.def.targets.iter().map(|t| t.position));
        if !task.def.targets.is_empty() {
            ground = task.def.targets.iter().map(|t| t.position.y).sum::<f32>() / task.def.targets.len() as f32;
        }
    }
    (TaskArea::around(&points, ground), sim.mode().name().to_string())
}

/// What to draw.
pub struct VideoSpec<'a> {
    /// The camera.
    pub camera: CameraKind,
    /// The first and last tick.
    pub from: u64,
    /// The last tick.
    pub to: u64,
    /// Frames per second.
    pub fps: u32,
    /// Simulated seconds per video second.
    pub speed: f64,
    /// The task area (the top and orbit cameras frame it).
    pub area: TaskArea,
    /// The chosen participant's id and condition for the captions.
    pub who: String,
    /// The output file (written as is: the caller renames a temporary file).
    pub out: &'a Path,
}

/// What was written.
#[derive(Clone, Copy, Debug)]
pub struct VideoSummary {
    /// Frames.
    pub frames: u64,
    /// Bytes of video data.
    pub bytes: u64,
}

/// Draws `player`'s recording with `renderer` as `spec` asks, and the `ghosts` beside it;
/// `progress` is called after each frame is drawn.
pub fn write(
    gpu: &Gpu,
    renderer: &mut Renderer,
    mut player: Player,
    mut ghosts: Vec<Ghost>,
    spec: &VideoSpec<'_>,
    progress: &mut dyn FnMut(u64),
) -> Result<VideoSummary, VideoError> {
    let (w, h) = renderer.size();
    let dt = player.sim().dt();
    let ticks = frame_ticks(spec.from, spec.to, spec.fps, spec.speed, dt);
    let (start, end) = (player.task_start_tick(), player.task_end_tick());
    let own_color = ghosts::participant_color(player.header.participant.as_deref().unwrap_or(""));
    let mut writer = VideoWriter::create(spec.out, w, h, spec.fps)?;
    let target = Target::new(&gpu.device, w, h);

    // The encoder's thread takes frames from a queue two deep.
    let (send, recv) = mpsc::sync_channel::<image::RgbaImage>(2);
    let encoder = std::thread::spawn(move || -> Result<VideoWriter, VideoError> {
        for frame in recv {
            writer.push(&frame)?;
        }
        Ok(writer)
    });

    let mut shoulder: Option<Shoulder> = None;
    let mut seen = 0;
    let mut recent: Vec<(usize, String)> = Vec::new();
    let frame_s = 1.0 / spec.fps as f32;
    let mut drawn: Result<(), VideoError> = Ok(());
    for (k, &tick) in ticks.iter().enumerate() {
        player.advance_to(tick);
        let sim = player.sim();
        // Captions: what happened since the last frame, each for a second of video.
        for e in &sim.log().entries[seen..] {
            if let Some(words) = captions::event_words(&e.what) {
                recent.push((k, words));
            }
        }
        seen = sim.log().entries.len();
        recent.retain(|(at, _)| k - at < spec.fps as usize);
        let text = Captions {
            who: spec.who.clone(),
            clock: captions::clock(sim.tick(), start, end, dt),
            events: recent.iter().map(|(_, t)| t.clone()).collect(),
        };

        // The camera, and the participant as a figure when seen from outside.
        let head = sim.head();
        renderer.options.top_view = None;
        renderer.options.camera = None;
        match spec.camera {
            CameraKind::Head => {}
            CameraKind::Shoulder => {
                let s = camera::shoulder_step(shoulder, &head, frame_s * spec.speed as f32);
                shoulder = Some(s);
                renderer.options.camera = Some(s.camera());
            }
            CameraKind::Top => renderer.options.top_view = Some(camera::top(&spec.area, w as f32 / h as f32)),
            CameraKind::Orbit => renderer.options.camera = Some(camera::orbit(&spec.area, k as f32 * frame_s)),
        }
        let mut figures: Vec<_> = ghosts.iter_mut().map(|g| g.figure_at(tick)).collect();
        if spec.camera != CameraKind::Head {
            figures.push(ghosts::figure(sim, own_color, true));
        }
        renderer.features.overlay.ghosts = figures;

        renderer.render(sim, target.view()).map_err(VideoError::Render)?;
        let mut img = target.read(&gpu.device, &gpu.queue).map_err(VideoError::Render)?;
        captions::burn(&mut img, &text);
        if send.send(img).is_err() {
            // The encoder stopped: its error is reported below.
            drawn = Err(VideoError::Encoder("stopped".into()));
            break;
        }
        progress(k as u64 + 1);
    }
    drop(send);
    renderer.features.overlay.ghosts.clear();
    let writer = encoder.join().map_err(|_| VideoError::Encoder("its thread stopped unexpectedly".into()))??;
    drawn?;
    let bytes = writer.bytes();
    let frames = writer.finish()?;
    Ok(VideoSummary { frames, bytes })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_fall_every_speed_over_fps_seconds() {
        let dt = 1.0 / 60.0;
        // 300 ticks = 5 s at 30 fps: 150 frames, two ticks apart.
        let t = frame_ticks(100, 400, 30, 1.0, dt);
        assert_eq!(t.len(), 150);
        assert_eq!((t[0], t[1], t[149]), (100, 102, 398));
        // Twice as fast: half the frames, four ticks apart.
        let t = frame_ticks(100, 400, 30, 2.0, dt);
        assert_eq!((t.len(), t[1]), (75, 104));
        // Slow motion at 60 fps and a quarter speed: a tick every four frames.
        let t = frame_ticks(0, 60, 60, 0.25, dt);
        assert_eq!(t.len(), 240);
        assert_eq!(&t[..6], &[0, 0, 1, 1, 1, 1][..]);
        // An empty span still gives one frame.
        assert_eq!(frame_ticks(7, 7, 30, 1.0, dt), vec![7]);
    }

    #[test]
    fn marks_are_ticks_or_task_marks() {
        assert_eq!("120".parse::<Mark>(), Ok(Mark::Tick(120)));
        assert_eq!("task-start".parse::<Mark>(), Ok(Mark::TaskStart));
        assert_eq!("task-end".parse::<Mark>(), Ok(Mark::TaskEnd));
        assert!("-3".parse::<Mark>().is_err() && "soon".parse::<Mark>().is_err());
    }
}
