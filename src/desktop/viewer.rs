//! The replay viewer's model and UI (`grove view`).
//!
//! [`Viewer::open`] first runs the verifying headless replay ([`replay_file`]) over the whole
//! file: that gives the timeline's length, its markers (from the simulation's event log) and
//! whether the file verifies. The viewer then re-simulates from the start with the file's
//! events, applying each at the start of its tick exactly as the headless replay does, so the
//! world shown at tick T is the world `grove replay --until T` computes. Seeking forward steps
//! on; seeking backward re-simulates from the start (hecs worlds cannot be copied, so there
//! are no snapshots; a 5-minute session re-simulates in well under a second).

use std::path::{Path, PathBuf};

use egui::{Color32, RichText, Ui};
use grove_systems::input::StampedEvent;

use super::DesktopError;
use grove_systems::Sim;
use grove_systems::replay::{Header, ReplayOptions, read_events, replay_file, sim_for_header_in};

use super::play_ui::task_panel;
use super::session::FixedStep;

/// The playback speeds offered.
pub const SPEEDS: &[f64] = &[0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0];

/// A point of interest on the timeline.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// The tick it happened in.
    pub tick: u64,
    /// The log kind: "planted", "removed", "snapped", "task_started", "task_ended" or "task_completed".
    pub kind: &'static str,
}

/// The log kinds shown as timeline markers.
pub const MARKER_KINDS: &[&str] = &["planted", "removed", "snapped", "task_started", "task_ended", "task_completed"];

/// The colour of a marker kind.
pub fn marker_color(kind: &str) -> Color32 {
    match kind {
        "planted" => Color32::from_rgb(60, 200, 80),
        "removed" => Color32::from_rgb(230, 60, 50),
        "snapped" => Color32::WHITE,
        "task_completed" => Color32::from_rgb(250, 210, 40),
        _ => Color32::from_rgb(80, 160, 255),
    }
}

/// A replay being viewed.
pub struct Viewer {
    /// The file.
    pub path: PathBuf,
    /// Its header.
    pub header: Header,
    events: Vec<StampedEvent>,
    next_event: usize,
    /// The world at the current tick.
    pub sim: Sim,
    /// The last tick of the recording.
    pub end_tick: u64,
    /// Timeline markers from the headless pass.
    pub markers: Vec<Marker>,
    /// A warning about the file (divergent, incomplete, unverified), shown as a banner.
    pub banner: Option<String>,
    /// Whether playback runs.
    pub playing: bool,
    /// Playback speed, 0.25 to 16.
    pub speed: f64,
    clock: FixedStep,
    pending_seek: Option<u64>,
}

impl Viewer {
    /// Opens a recording: verifies it headless, then starts the view at tick 0. Unreadable or
    /// malformed files give a one-line error.
    pub fn open(path: &Path) -> Result<Viewer, DesktopError> {
        let outcome =
            replay_file(path, &ReplayOptions { banks: grove::bank::session_dirs(&[]), ..Default::default() })?;
        let (header, events) = read_events(path)?;
        let end_tick = outcome.sim.tick();
        let markers = outcome
            .sim
            .log()
            .entries
            .iter()
            .filter_map(|e| {
                MARKER_KINDS.iter().find(|k| **k == e.what.kind()).map(|k| Marker { tick: e.tick, kind: k })
            })
            .collect();
        let mut banner = Vec::new();
        if let Some(d) = &outcome.first_divergence {
            banner.push(format!(
                "DIVERGED at tick {}: recorded hash {}, re-simulated {}; the world shown after that tick is what this build computes, not what was recorded",
                d.tick, d.expected_hash, d.actual_hash
            ));
        }
        if !outcome.complete {
            banner.push(
                "INCOMPLETE: the recording has no footer (the session was cut off); it is shown up to its last line"
                    .to_string(),
            );
        }
        if outcome.first_divergence.is_none() && outcome.checkpoints_checked == 0 {
            banner.push("NOT VERIFIED: no checkpoint was reached".to_string());
        }
        let sim = sim_for_header_in(&header, path.parent(), &[], &grove::bank::open_session(&[])?)
            .map_err(|error| DesktopError::Header { path: path.to_path_buf(), error })?;
        let dt = header.dt as f64;
        Ok(Viewer {
            path: path.to_path_buf(),
            header,
            events,
            next_event: 0,
            sim,
            end_tick,
            markers,
            banner: if banner.is_empty() { None } else { Some(banner.join("; ")) },
            playing: false,
            speed: 1.0,
            clock: FixedStep::new(dt, 2000),
            pending_seek: None,
        })
    }

    /// The current tick.
    pub fn tick(&self) -> u64 {
        self.sim.tick()
    }

    /// Runs one tick: the events stamped with the current tick, then a step. Does nothing at
    /// the end of the recording.
    pub fn step_once(&mut self) {
        if self.sim.tick() >= self.end_tick {
            return;
        }
        let start = self.next_event;
        while self.events.get(self.next_event).is_some_and(|e| e.tick <= self.sim.tick()) {
            self.next_event += 1;
        }
        // The headless pass accepted every event (an invalid one would have been reported by
        // `open`); any other is skipped, so the step always happens.
        let events = self.events[start..self.next_event].iter().filter(|e| e.event.validate().is_ok());
        let _ = self.sim.step_with(events.map(|e| e.event.clone()));
    }

    /// Shows the world at `tick` (clamped to the recording), re-simulating from the start when
    /// going back.
    pub fn seek(&mut self, tick: u64) {
        let tick = tick.min(self.end_tick);
        if tick < self.sim.tick() {
            if let Ok(sim) = grove::bank::open_session(&[]).map_err(DesktopError::from).and_then(|banks| {
                sim_for_header_in(&self.header, self.path.parent(), &[], &banks)
                    .map_err(|error| DesktopError::Header { path: self.path.clone(), error })
            }) {
                self.sim = sim;
                self.next_event = 0;
            }
        }
        while self.sim.tick() < tick {
            self.step_once();
        }
    }

    /// Advances playback by `elapsed` wall-clock seconds at the current speed.
    pub fn advance(&mut self, elapsed: f64) {
        if !self.playing {
            self.clock.accumulator = 0.0;
            return;
        }
        let n = self.clock.advance(elapsed, self.speed);
        for _ in 0..n {
            self.step_once();
        }
        if self.sim.tick() >= self.end_tick {
            self.playing = false;
        }
    }

    /// Draws the viewer's controls for one frame.
    pub fn ui(&mut self, ui: &mut Ui) {
        if let Some(b) = &self.banner {
            egui::Panel::top("banner").show(ui, |ui| {
                ui.label(RichText::new(b).color(Color32::from_rgb(255, 90, 70)).strong());
            });
        }
        egui::Panel::bottom("timeline").show(ui, |ui| {
            ui.horizontal(|ui| {
                if ui.button("Start").clicked() {
                    self.seek(0);
                }
                let label = if self.playing { "Pause" } else { "Play" };
                if ui.button(label).clicked() {
                    if !self.playing && self.tick() >= self.end_tick {
                        self.seek(0);
                    }
                    self.playing = !self.playing;
                }
                if ui.button("Step").clicked() {
                    self.playing = false;
                    self.step_once();
                }
                egui::ComboBox::from_label("Speed").selected_text(format!("{}x", self.speed)).show_ui(ui, |ui| {
                    for s in SPEEDS {
                        ui.selectable_value(&mut self.speed, *s, format!("{s}x"));
                    }
                });
                let dt = self.sim.dt() as f64;
                ui.label(
                    RichText::new(format!(
                        "tick {} / {}  ({:.2} s / {:.2} s)",
                        self.tick(),
                        self.end_tick,
                        self.tick() as f64 * dt,
                        self.end_tick as f64 * dt
                    ))
                    .monospace(),
                );
            });
            let mut t = self.tick();
            let width = ui.available_width();
            ui.spacing_mut().slider_width = width - 80.0;
            let r = ui.add(egui::Slider::new(&mut t, 0..=self.end_tick.max(1)).text("tick"));
            // Forward seeks step on; a backward seek re-simulates from the start, so while the
            // handle is being dragged back it waits for the release.
            if r.changed() && (t > self.tick() || !r.dragged()) {
                self.seek(t);
                self.pending_seek = None;
            } else if r.changed() {
                self.pending_seek = Some(t);
            }
            if let (Some(p), false) = (self.pending_seek, r.dragged()) {
                self.seek(p);
                self.pending_seek = None;
            }
            // The markers, under the slider's rail.
            let rail = r.rect;
            let (strip, _) = ui.allocate_exact_size(egui::vec2(width, 10.0), egui::Sense::hover());
            let x0 = rail.min.x + 6.0;
            let x1 = rail.min.x + ui.spacing().slider_width - 6.0;
            let painter = ui.painter();
            for m in &self.markers {
                let x = x0 + (x1 - x0) * (m.tick as f32 / self.end_tick.max(1) as f32);
                painter.line_segment(
                    [egui::pos2(x, strip.min.y), egui::pos2(x, strip.max.y)],
                    egui::Stroke::new(2.0, marker_color(m.kind)),
                );
            }
            ui.horizontal(|ui| {
                for k in MARKER_KINDS {
                    let n = self.markers.iter().filter(|m| m.kind == *k).count();
                    ui.label(RichText::new(format!("| {k} {n}")).color(marker_color(k)));
                }
            });
        });
        egui::Window::new("Recording").default_pos([10.0, 60.0]).resizable(false).show(ui.ctx(), |ui| {
            ui.label(format!("{}", self.path.display()));
            ui.label(format!("scene {}, seed {}", self.header.scene, self.header.seed));
            ui.label(format!(
                "participant {}, task {}{}",
                self.header.participant.as_deref().unwrap_or("-"),
                self.header.task.as_deref().unwrap_or("-"),
                if self.header.synthetic { ", synthetic" } else { "" }
            ));
            let c = self.sim.counts();
            ui.label(format!("{} trees, mode {}", c.trees, self.sim.mode().name()));
        });
        let mut ignored = Vec::new();
        task_panel(ui, &self.sim, &mut ignored, false);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use grove_systems::components::Pose;
    use grove_systems::input::{Button, InputEvent};
    use grove_systems::replay::record_events;
    use grove_systems::scene::Scene;
    use grove_systems::script::Script;

    fn recording(dir: &Path) -> PathBuf {
        let scene = Scene::builtin("study").unwrap();
        let mut s = Script::new(Sim::from_scene(&scene, 9).unwrap());
        s.start_task("ray-casting-7").wait(5);
        for p in [Vec3::new(4.0, 0.0, -2.0), Vec3::new(-4.0, 0.0, -2.0)] {
            s.point_at(p).press(Button::Trigger).wait(20);
        }
        s.push(InputEvent::ControllerPose {
            pose: Pose::looking_at(Vec3::new(0.0, 1.7, 6.0), Vec3::new(4.0, 0.5, -2.0)),
        })
        .wait(1);
        s.press(Button::Bumper).wait(30);
        let events = s.recorded().to_vec();
        let mut header = Header::new("study", 9, scene.dt);
        header.task = Some("ray-casting-7".into());
        let path = dir.join("r.jsonl");
        let f = std::fs::File::create(&path).unwrap();
        record_events(f, &header, &events, 200, serde_json::json!({})).unwrap();
        path
    }

    #[test]
    fn every_tick_matches_the_headless_replay_and_markers_come_from_the_log() {
        let dir = tempfile::tempdir().unwrap();
        let path = recording(dir.path());
        let mut v = Viewer::open(&path).unwrap();
        assert!(v.banner.is_none(), "{:?}", v.banner);
        assert_eq!(v.end_tick, 200);
        assert_eq!(v.markers.iter().filter(|m| m.kind == "planted").count(), 2);
        assert_eq!(v.markers.iter().filter(|m| m.kind == "removed").count(), 1);
        assert_eq!(v.markers.iter().filter(|m| m.kind == "task_started").count(), 1);
        // Forward, backward, forward again, and single steps.
        for t in [150, 10, 33, 34, 200, 0, 71] {
            v.seek(t);
            let headless = replay_file(&path, &ReplayOptions { until: Some(t), ..Default::default() }).unwrap();
            assert_eq!(v.tick(), t);
            assert_eq!(v.sim.hash().total, headless.sim.hash().total, "tick {t}");
        }
        v.step_once();
        let headless = replay_file(&path, &ReplayOptions { until: Some(72), ..Default::default() }).unwrap();
        assert_eq!(v.sim.hash().total, headless.sim.hash().total);
    }

    #[test]
    fn playback_follows_speed_and_stops_at_the_end() {
        let dir = tempfile::tempdir().unwrap();
        let path = recording(dir.path());
        let mut v = Viewer::open(&path).unwrap();
        v.advance(1.0);
        assert_eq!(v.tick(), 0, "paused");
        v.playing = true;
        v.speed = 0.25;
        v.advance(0.5);
        assert!((7..=8).contains(&v.tick()), "{}", v.tick());
        v.speed = 16.0;
        v.advance(1.0);
        assert_eq!(v.tick(), 200);
        assert!(!v.playing);
    }

    #[test]
    fn an_incomplete_or_divergent_file_opens_with_a_banner() {
        let dir = tempfile::tempdir().unwrap();
        let path = recording(dir.path());
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let cut = dir.path().join("cut.jsonl");
        std::fs::write(&cut, lines[..lines.len() - 1].join("\n") + "\n").unwrap();
        let v = Viewer::open(&cut).unwrap();
        assert!(v.banner.as_deref().unwrap().contains("INCOMPLETE"), "{:?}", v.banner);

        // A different seed in the header makes the checkpoints diverge.
        let header = grove_systems::replay::decode_line(lines[0]).unwrap();
        let grove_systems::replay::Line::Header(mut h) = header else { panic!("no header") };
        h.seed = 10;
        let mut out = vec![grove_systems::replay::encode_line(&grove_systems::replay::Line::Header(h))];
        out.extend(lines[1..].iter().map(|l| l.to_string()));
        let bad = dir.path().join("bad.jsonl");
        std::fs::write(&bad, out.join("\n") + "\n").unwrap();
        let v = Viewer::open(&bad).unwrap();
        assert!(v.banner.as_deref().unwrap().contains("DIVERGED"), "{:?}", v.banner);

        let garbage = dir.path().join("garbage.jsonl");
        std::fs::write(&garbage, "not a recording\n").unwrap();
        let err = Viewer::open(&garbage).err().unwrap().to_string();
        assert!(!err.contains('\n') && err.contains("garbage.jsonl"), "{err}");
    }

    #[test]
    fn the_timeline_controls_work_by_label() {
        use egui_kittest::kittest::Queryable;
        let dir = tempfile::tempdir().unwrap();
        let path = recording(dir.path());
        let v = Viewer::open(&path).unwrap();
        let mut h = egui_kittest::Harness::builder()
            .with_size(egui::vec2(1280.0, 720.0))
            .build_ui_state(|ui, v: &mut Viewer| v.ui(ui), v);
        h.get_by_label("Step").click();
        h.run();
        assert_eq!(h.state().tick(), 1);
        h.get_by_label("Play").click();
        h.run();
        assert!(h.state().playing);
        h.get_by_label("Pause").click();
        h.run();
        assert!(!h.state().playing);
        h.get_by_label_contains("planted 2");
        h.get_by_label("Task ray-casting-7");
    }
}

/// The replay viewer in a window.
pub struct ViewApp {
    /// The viewer.
    pub viewer: Viewer,
    /// The 3D view.
    pub world3d: super::window::World3d,
    quit: bool,
}

impl ViewApp {
    /// A window frontend for a viewer.
    pub fn new(viewer: Viewer) -> ViewApp {
        ViewApp { viewer, world3d: Default::default(), quit: false }
    }
}

impl super::window::Frontend for ViewApp {
    fn gpu_ready(&mut self, gpu: super::window::GpuContext<'_>, _adapter: &str, size: (u32, u32)) {
        self.world3d.gpu_ready(&gpu, size);
    }

    fn draw_3d(
        &mut self,
        gpu: super::window::GpuContext<'_>,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        size: (u32, u32),
    ) -> bool {
        self.world3d.draw(&gpu, encoder, &self.viewer.sim, view, size)
    }

    fn input(&mut self, event: &winit::event::WindowEvent, _over_ui: bool) {
        use winit::event::{ElementState, WindowEvent};
        use winit::keyboard::{KeyCode, PhysicalKey};
        if let WindowEvent::KeyboardInput { event, is_synthetic: false, .. } = event {
            if event.state != ElementState::Pressed || event.repeat {
                return;
            }
            match event.physical_key {
                PhysicalKey::Code(KeyCode::Escape) => self.quit = true,
                PhysicalKey::Code(KeyCode::Space) => self.viewer.playing = !self.viewer.playing,
                PhysicalKey::Code(KeyCode::ArrowRight) => self.viewer.step_once(),
                _ => {}
            }
        }
    }

    fn update(&mut self, elapsed: f64) -> Result<(), String> {
        self.viewer.advance(elapsed);
        Ok(())
    }

    fn ui(&mut self, ui: &mut egui::Ui) {
        let painter = ui.ctx().layer_painter(egui::LayerId::background());
        super::world_view::paint_world(
            &painter,
            ui.ctx().content_rect(),
            &self.viewer.sim,
            super::world_view::ViewOptions::with_renderer(self.world3d.active()),
        );
        self.viewer.ui(ui);
    }

    fn wants_quit(&self) -> bool {
        self.quit
    }

    fn finish(&mut self) -> Result<(), String> {
        Ok(())
    }
}
