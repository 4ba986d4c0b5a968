//! A live session: the simulation, the fixed-step clock and the recording.
//!
//! The app measures wall-clock time between frames and hands it to [`FixedStep`], which says
//! how many fixed steps to run. Input events are queued with [`LiveSession::queue`] and applied
//! at the start of the next tick; each is recorded with the tick it applied at, so a replay of
//! the recording computes exactly the world the session showed.
//!
//! Queued events are grouped into per-tick batches. An event that would change the meaning of
//! a batch (a second edge of the same button, or a controller pose after a button edge, which
//! would move the ray the button acts on) starts a new batch, which applies one tick later. A
//! click therefore always lasts at least one tick, even when the press and the release arrive
//! in the same frame.

use std::collections::VecDeque;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use grove_systems::Sim;
use grove_systems::input::{InputEvent, StampedEvent};
use grove_systems::replay::{Header, Recorder};

use super::DesktopError;

/// A fixed-step accumulator: wall-clock time in, whole steps out.
#[derive(Clone, Debug)]
pub struct FixedStep {
    /// The step, seconds.
    pub dt: f64,
    /// Time not yet simulated, seconds.
    pub accumulator: f64,
    /// The most steps one frame may run; a longer stall is dropped rather than caught up.
    pub max_steps: u32,
}

impl FixedStep {
    /// A clock with step `dt` seconds that runs at most `max_steps` steps per frame.
    pub fn new(dt: f64, max_steps: u32) -> FixedStep {
        FixedStep { dt, accumulator: 0.0, max_steps }
    }

    /// Adds `elapsed` wall-clock seconds (times `speed`) and returns how many steps to run now.
    pub fn advance(&mut self, elapsed: f64, speed: f64) -> u32 {
        if !(elapsed.is_finite() && elapsed > 0.0 && self.dt > 0.0) {
            return 0;
        }
        self.accumulator += elapsed * speed.max(0.0);
        let n = (self.accumulator / self.dt).floor();
        let steps = n.min(self.max_steps as f64) as u32;
        self.accumulator -= steps as f64 * self.dt;
        if steps == self.max_steps {
            // Too far behind: drop the backlog so the session does not spiral.
            self.accumulator = self.accumulator.min(self.dt);
        }
        steps
    }
}

/// Whether adding `event` to `batch` would need a new tick (see the module docs).
fn conflicts(batch: &[InputEvent], event: &InputEvent) -> bool {
    use InputEvent::*;
    match event {
        ButtonDown { button } | ButtonUp { button } => {
            batch.iter().any(|e| matches!(e, ButtonDown { button: b } | ButtonUp { button: b } if b == button))
        }
        ControllerPose { .. } => batch.iter().any(|e| matches!(e, ButtonDown { .. } | ButtonUp { .. })),
        _ => false,
    }
}

/// The recording file of a session.
pub type FileRecorder = Recorder<BufWriter<File>>;

/// Creates a new recording file, refusing to replace an existing one.
pub fn create_recording(path: &Path, header: &Header) -> Result<FileRecorder, DesktopError> {
    let f = std::fs::OpenOptions::new().write(true).create_new(true).open(path).map_err(|error| {
        if error.kind() == std::io::ErrorKind::AlreadyExists {
            DesktopError::RecordingExists(path.to_path_buf())
        } else {
            DesktopError::CreateRecording { path: path.to_path_buf(), error }
        }
    })?;
    Recorder::new(BufWriter::new(f), header)
        .map_err(|error| DesktopError::RecordingHeader { path: path.to_path_buf(), error })
}

/// A running session: the simulation, queued input and an optional recording.
pub struct LiveSession {
    /// The simulation.
    pub sim: Sim,
    /// Where the recording goes, if anywhere.
    pub record_path: Option<std::path::PathBuf>,
    batches: VecDeque<Vec<InputEvent>>,
    recorder: Option<FileRecorder>,
    recorded: Vec<StampedEvent>,
    /// The display frame number, written with each recorded event.
    pub frame: u64,
}

impl LiveSession {
    /// A session over `sim`, recording to `recorder` if given.
    pub fn new(sim: Sim, recorder: Option<FileRecorder>) -> LiveSession {
        LiveSession { sim, record_path: None, batches: VecDeque::new(), recorder, recorded: Vec::new(), frame: 0 }
    }

    /// The recording's file, if the session records and its caller said where.
    pub fn recording_path(&self) -> Option<&Path> {
        self.recorder.as_ref().and(self.record_path.as_deref())
    }

    /// Queues an event for the next tick (or a later one, see the module docs). Events with
    /// invalid numbers are refused.
    pub fn queue(&mut self, event: InputEvent) -> Result<(), DesktopError> {
        event.validate()?;
        match self.batches.back_mut() {
            Some(batch) if !conflicts(batch, &event) => batch.push(event),
            _ => self.batches.push_back(vec![event]),
        }
        Ok(())
    }

    /// Number of ticks' worth of queued input.
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn pending_ticks(&self) -> usize {
        self.batches.len()
    }

    /// Runs one tick: applies (and records) the next batch of input, steps, and writes a
    /// checkpoint when one is due. `ms` is the wall-clock milliseconds since the session began.
    pub fn step(&mut self, ms: u64) -> Result<(), DesktopError> {
        let tick = self.sim.tick();
        let batch = self.batches.pop_front().unwrap_or_default();
        for event in &batch {
            if let Some(r) = self.recorder.as_mut() {
                r.event(tick, ms, self.frame, event).map_err(DesktopError::Recording)?;
            }
            self.recorded.push(StampedEvent { tick, event: event.clone() });
        }
        self.sim.step_with(batch)?;
        if let Some(r) = self.recorder.as_mut() {
            r.after_step(&self.sim).map_err(DesktopError::Recording)?;
        }
        Ok(())
    }

    /// Every event applied so far, with its tick.
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn recorded(&self) -> &[StampedEvent] {
        &self.recorded
    }

    /// Writes buffered recording lines to the file.
    pub fn flush(&mut self) -> Result<(), DesktopError> {
        match self.recorder.as_mut() {
            Some(r) => r.flush().map_err(DesktopError::Recording),
            None => Ok(()),
        }
    }

    /// Ends the session: input still queued is applied first (one tick per batch), then the
    /// recording gets its footer.
    pub fn finish(mut self) -> Result<Sim, DesktopError> {
        while !self.batches.is_empty() {
            self.step(0)?;
        }
        if let Some(r) = self.recorder.take() {
            let sim = &self.sim;
            let summary = serde_json::json!({
                "trees": sim.counts().trees,
                "task": sim.task().map(|t| t.def.id.clone()),
                "task_completed": sim.task().map(|t| t.is_complete()),
            });
            r.finish(sim, summary).map_err(DesktopError::Recording)?;
        }
        Ok(self.sim)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use grove_systems::components::Pose;
    use grove_systems::input::Button;
    use grove_systems::replay::{ReplayOptions, replay_file};
    use grove_systems::scene::Scene;

    #[test]
    fn the_clock_runs_whole_steps_and_keeps_the_rest() {
        let mut c = FixedStep::new(0.01, 10);
        assert_eq!(c.advance(0.025, 1.0), 2);
        assert_eq!(c.advance(0.006, 1.0), 1);
        assert!((c.accumulator - 0.001).abs() < 1e-9);
        assert_eq!(c.advance(0.01, 4.0), 4, "speed multiplies time");
        assert_eq!(c.advance(5.0, 1.0), 10, "a stall is capped");
        assert!(c.accumulator <= 0.01 + 1e-12);
        assert_eq!(c.advance(f64::NAN, 1.0), 0);
    }

    #[test]
    fn a_press_and_release_in_one_frame_span_two_ticks() {
        let sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 1).unwrap();
        let mut s = LiveSession::new(sim, None);
        let pose = Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::new(0.0, 0.0, 2.0));
        s.queue(InputEvent::ControllerPose { pose }).unwrap();
        s.queue(InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
        s.queue(InputEvent::ButtonUp { button: Button::Trigger }).unwrap();
        assert_eq!(s.pending_ticks(), 2);
        let before = s.sim.counts().trees;
        s.step(0).unwrap();
        s.step(0).unwrap();
        assert_eq!(s.sim.counts().trees, before + 1, "the click planted a tree");
        let ticks: Vec<u64> = s.recorded().iter().map(|e| e.tick).collect();
        assert_eq!(ticks, vec![0, 0, 1]);
    }

    #[test]
    fn a_recording_refuses_to_overwrite_and_replays_to_the_same_hash() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.jsonl");
        std::fs::write(&path, "keep").unwrap();
        let header = Header::new("study", 5, Scene::builtin("study").unwrap().dt);
        let err = create_recording(&path, &header).err().unwrap().to_string();
        assert!(err.contains("already exists"), "{err}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "keep");

        let path = dir.path().join("new.jsonl");
        let rec = create_recording(&path, &header).unwrap();
        let sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 5).unwrap();
        let mut s = LiveSession::new(sim, Some(rec));
        let pose = Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::new(1.0, 0.0, 1.0));
        for _ in 0..3 {
            s.step(0).unwrap();
        }
        s.queue(InputEvent::ControllerPose { pose }).unwrap();
        s.queue(InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
        s.queue(InputEvent::ButtonUp { button: Button::Trigger }).unwrap();
        for _ in 0..70 {
            s.step(0).unwrap();
        }
        let sim = s.finish().unwrap();
        let out = replay_file(&path, &ReplayOptions::default()).unwrap();
        assert!(out.complete && out.first_divergence.is_none() && out.checkpoints_checked >= 2);
        assert_eq!(out.sim.hash().total, sim.hash().total);
        assert_eq!(out.sim.counts().trees, sim.counts().trees);
    }
}
