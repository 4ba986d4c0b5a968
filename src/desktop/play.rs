//! The `grove play` frontend: device input through [`Controls`], the [`PlayUi`], and a
//! [`LiveSession`] stepped by a fixed-step clock from the frame times.

use std::time::Instant;

use glam::Vec2;
use grove_systems::input::InputEvent;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{KeyCode, PhysicalKey};

use super::input_map::{Controls, PadInput};
use super::play_ui::{PlayUi, Screen};
use super::session::{FixedStep, LiveSession};
use super::stats::{FrameStats, Rolling};
use super::window::{Frontend, GpuContext, ThumbnailFactory, World3d, make_thumbnails};
use super::world_view::{ViewOptions, head_of, paint_world};

/// How often the recording is flushed to disk, wall-clock seconds.
pub const FLUSH_EVERY_S: f64 = 1.0;

/// `grove play --measure`: run the window for a while, then quit and report the frame rate.
#[derive(Clone, Debug)]
pub struct Measure {
    /// How long to run, wall-clock seconds.
    pub seconds: f64,
    /// Frames counted after the warm-up.
    pub frames: u64,
    /// Wall-clock seconds those frames took.
    pub time: f64,
    /// Scale of the 3D view's internal resolution, summed over the counted frames.
    pub scale_sum: f64,
    /// When the first frame was drawn; the measurement's time counts from there.
    pub first_frame: Option<Instant>,
    /// The process's CPU time (every thread, the software rasteriser's included), seconds, when
    /// the warm-up ended.
    pub cpu_start: Option<f64>,
}

/// The first seconds after the first frame (shader compilation, the budget settling) are not
/// counted.
pub const MEASURE_WARMUP_S: f64 = 3.0;

/// A live play session in a window.
pub struct PlayApp {
    /// The UI.
    pub ui: PlayUi,
    /// The simulation and its recording.
    pub session: Option<LiveSession>,
    /// The device mapping.
    pub controls: Controls,
    clock: FixedStep,
    started: Instant,
    last_flush: Instant,
    world_buttons: [bool; 2],
    /// The 3D view.
    pub world3d: World3d,
    /// How to render the tree-selection thumbnails, if anything can.
    pub thumbnails: Option<ThumbnailFactory>,
    /// Simulation ticks run per frame, over a rolling window.
    ticks: Rolling,
    /// A frame-rate measurement, if one was asked for.
    pub measure: Option<Measure>,
}

impl PlayApp {
    /// A play app over a session. With `task`, the task starts at once; with `skip_menu`,
    /// free planting starts at once.
    pub fn new(session: LiveSession, task: Option<&str>, skip_menu: bool) -> Result<PlayApp, super::DesktopError> {
        let head = head_of(&session.sim);
        let mut app = PlayApp {
            ui: PlayUi::new(head.pose),
            controls: Controls::new(head.pose, head.fov_y, Vec2::new(1280.0, 720.0)),
            clock: FixedStep::new(session.sim.dt() as f64, 30),
            session: Some(session),
            started: Instant::now(),
            last_flush: Instant::now(),
            world_buttons: [false; 2],
            world3d: World3d::default(),
            thumbnails: None,
            ticks: Rolling::default(),
            measure: None,
        };
        if let Some(id) = task {
            app.ui.screen = Screen::Session;
            for e in PlayUi::start_task_events(id) {
                app.queue(e)?;
            }
        } else if skip_menu {
            app.ui.screen = Screen::Session;
        }
        Ok(app)
    }

    fn queue(&mut self, e: InputEvent) -> Result<(), super::DesktopError> {
        if let InputEvent::HeadPose { pose } = &e {
            self.controls.head = *pose;
        }
        match self.session.as_mut() {
            Some(s) => s.queue(e),
            None => Ok(()),
        }
    }

    fn queue_all(&mut self, events: Vec<InputEvent>) {
        for e in events {
            // Events from the device mapping are finite by construction; an invalid one is
            // dropped rather than ending the session.
            if let Err(msg) = self.queue(e) {
                tracing::warn!("dropped an input event: {msg}");
            }
        }
    }

    fn menu_open(&self) -> bool {
        self.session.as_ref().is_some_and(|s| s.sim.menu().open)
    }

    fn live(&self) -> bool {
        self.ui.screen == Screen::Session
    }
}

impl Frontend for PlayApp {
    fn gpu_ready(&mut self, gpu: GpuContext<'_>, adapter: &str, size: (u32, u32)) {
        self.ui.stats.adapter = adapter.to_string();
        self.world3d.gpu_ready(&gpu, size);
        if let Some(f) = self.thumbnails {
            self.ui.thumbnails = make_thumbnails(f, gpu);
        }
    }

    fn draw_3d(
        &mut self,
        gpu: GpuContext<'_>,
        encoder: &mut wgpu::CommandEncoder,
        view: &wgpu::TextureView,
        size: (u32, u32),
    ) -> bool {
        let drew = match self.session.as_ref() {
            Some(s) => self.world3d.draw(&gpu, encoder, &s.sim, view, size),
            None => false,
        };
        self.ui.stats.view_size = drew.then(|| (self.world3d.internal_size(), size));
        self.ui.stats.shadows_off = !self.world3d.budget.shadows();
        drew
    }

    fn input(&mut self, event: &WindowEvent, over_ui: bool) {
        match event {
            WindowEvent::Resized(size) => {
                self.controls.size = Vec2::new(size.width.max(1) as f32, size.height.max(1) as f32);
            }
            WindowEvent::CursorMoved { position, .. } => {
                let ev = self.controls.cursor_moved(Vec2::new(position.x as f32, position.y as f32));
                if self.live() {
                    self.queue_all(ev);
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let slot = match button {
                    MouseButton::Left => 0,
                    MouseButton::Right => 1,
                    _ => return,
                };
                let pressed = *state == ElementState::Pressed;
                // A press counts only on the world (not over the UI, nor while the quit
                // confirmation is open); its release always follows it there, wherever the
                // pointer is then. A press that started over the UI never reaches the world,
                // and neither does its release.
                let blocked = over_ui || !self.live() || self.ui.confirm_quit;
                if pressed && blocked || !pressed && !self.world_buttons[slot] {
                    return;
                }
                self.world_buttons[slot] = pressed;
                let ev = self.controls.mouse_button(*button, pressed);
                self.queue_all(ev);
            }
            WindowEvent::MouseWheel { delta, .. } if !over_ui && self.live() && !self.ui.confirm_quit => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.controls.wheel(lines);
            }
            WindowEvent::KeyboardInput { event, is_synthetic, .. } => {
                if *is_synthetic || event.repeat {
                    return;
                }
                let PhysicalKey::Code(code) = event.physical_key else { return };
                let pressed = event.state == ElementState::Pressed;
                if self.ui.confirm_quit && pressed {
                    // The quit confirmation takes Enter (quit) and Escape (keep going).
                    match code {
                        KeyCode::Enter | KeyCode::NumpadEnter => self.ui.quit = true,
                        KeyCode::Escape => self.ui.confirm_quit = false,
                        _ => {}
                    }
                    return;
                }
                let menu_open = self.menu_open();
                let (ev, app) = self.controls.key(code, event.state == ElementState::Pressed, menu_open);
                if self.live() {
                    self.queue_all(ev);
                }
                if app.quit {
                    let sim = self.session.as_ref().map(|s| &s.sim);
                    self.ui.request_quit(sim);
                }
                self.ui.show_help ^= app.toggle_help;
                self.ui.show_debug ^= app.toggle_debug;
            }
            _ => {}
        }
    }

    fn gamepad(&mut self, input: PadInput) {
        let menu_open = self.menu_open();
        let ev = self.controls.pad(input, menu_open);
        if self.live() {
            self.queue_all(ev);
        }
    }

    fn update(&mut self, elapsed: f64) -> Result<(), String> {
        if let Some(m) = self.measure.as_mut() {
            let run_for = m.first_frame.get_or_insert_with(Instant::now).elapsed().as_secs_f64();
            if run_for > MEASURE_WARMUP_S {
                m.cpu_start.get_or_insert_with(grove::bench::process_cpu_seconds);
                m.frames += 1;
                m.time += elapsed;
                m.scale_sum += self.world3d.budget.scale() as f64;
            }
            if run_for >= m.seconds {
                self.ui.quit = true;
            }
        }
        let ev = self.controls.frame(elapsed as f32);
        if self.live() {
            self.queue_all(ev);
        }
        let steps = if self.live() { self.clock.advance(elapsed, 1.0) } else { 0 };
        let ms = self.started.elapsed().as_millis() as u64;
        let Some(s) = self.session.as_mut() else { return Ok(()) };
        s.frame += 1;
        for _ in 0..steps {
            s.step(ms)?;
        }
        self.ticks.push(elapsed, steps as u64);
        self.ui.stats.ticks_per_s = self.ticks.rate() as f32;
        if self.last_flush.elapsed().as_secs_f64() >= FLUSH_EVERY_S {
            s.flush()?;
            self.last_flush = Instant::now();
        }
        Ok(())
    }

    fn ui(&mut self, ui: &mut egui::Ui) {
        let Some(s) = self.session.as_ref() else { return };
        let painter = ui.ctx().layer_painter(egui::LayerId::background());
        paint_world(&painter, ui.ctx().content_rect(), &s.sim, ViewOptions::with_renderer(self.world3d.active()));
        let events = self.ui.ui(ui, &s.sim);
        self.queue_all(events);
    }

    fn frame_stats(&mut self, stats: FrameStats) {
        self.ui.stats.fps = stats.fps;
        self.ui.stats.frame_ms = stats.frame_ms;
    }

    fn wants_quit(&self) -> bool {
        self.ui.quit
    }

    fn close_requested(&mut self) -> bool {
        let sim = self.session.as_ref().map(|s| &s.sim);
        self.ui.request_quit(sim);
        self.ui.quit
    }

    fn finish(&mut self) -> Result<(), String> {
        if let Some(m) = &self.measure {
            let fps = if m.time > 0.0 { m.frames as f64 / m.time } else { 0.0 };
            let report = serde_json::json!({
                "frames": m.frames,
                "seconds": m.time,
                "fps": fps,
                "frame_ms": if m.frames > 0 { 1000.0 * m.time / m.frames as f64 } else { 0.0 },
                "mean_scale": if m.frames > 0 { m.scale_sum / m.frames as f64 } else { 0.0 },
                "cpu_ms_per_frame": match m.cpu_start {
                    Some(c) if m.frames > 0 => 1000.0 * (grove::bench::process_cpu_seconds() - c) / m.frames as f64,
                    _ => 0.0,
                },
                "renderer": self.world3d.active(),
                "adapter": self.ui.stats.adapter,
            });
            println!("{report}");
        }
        let Some(s) = self.session.take() else { return Ok(()) };
        let recording = s.recording_path().map(|p| p.display().to_string());
        let sim = s.finish()?;
        // The same report `grove replay` and `grove study` compute from the recording.
        if let Some(report) = super::play_ui::task_result(&sim) {
            eprintln!("{}", super::play_ui::result_line(&report));
        }
        if let Some(path) = recording {
            eprintln!("recording saved to {path} ({} ticks, complete)", sim.tick());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use grove_systems::Sim;
    use grove_systems::components::Pose;
    use grove_systems::input::{Button, InputEvent};
    use grove_systems::replay::{Header, ReplayOptions, replay_file};
    use grove_systems::scene::Scene;
    use grove_systems::task::TaskDef;

    use super::super::play_ui::{PlayUi, task_result};
    use super::super::session::{LiveSession, create_recording};

    /// Clicks Trigger with the controller aimed from above at a ground point.
    fn plant_at(s: &mut LiveSession, at: Vec3) {
        let pose = Pose::looking_at(at + Vec3::new(0.0, 6.0, 2.0), at);
        s.queue(InputEvent::ControllerPose { pose }).unwrap();
        s.queue(InputEvent::ButtonDown { button: Button::Trigger }).unwrap();
        s.queue(InputEvent::ButtonUp { button: Button::Trigger }).unwrap();
        for _ in 0..40 {
            s.step(0).unwrap();
        }
    }

    fn mouse(app: &mut super::PlayApp, pressed: bool, over_ui: bool) {
        use super::super::window::Frontend;
        use winit::event::{DeviceId, ElementState, MouseButton, WindowEvent};
        // SAFETY: a dummy device id is only compared, never used to reach a device.
        let device_id = DeviceId::dummy();
        let state = if pressed { ElementState::Pressed } else { ElementState::Released };
        app.input(&WindowEvent::MouseInput { device_id, state, button: MouseButton::Left }, over_ui);
    }

    fn triggers(app: &mut super::PlayApp) -> Vec<InputEvent> {
        let s = app.session.as_mut().unwrap();
        for _ in 0..6 {
            s.step(0).unwrap();
        }
        s.recorded()
            .iter()
            .map(|e| e.event.clone())
            .filter(|e| {
                matches!(
                    e,
                    InputEvent::ButtonDown { button: Button::Trigger }
                        | InputEvent::ButtonUp { button: Button::Trigger }
                )
            })
            .collect()
    }

    #[test]
    fn presses_over_the_ui_never_reach_the_scene_and_scene_presses_keep_their_release() {
        let sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 2).unwrap();
        let mut app = super::PlayApp::new(LiveSession::new(sim, None), None, true).unwrap();
        // Pressed over a menu, released over the scene: nothing.
        mouse(&mut app, true, true);
        mouse(&mut app, false, false);
        assert_eq!(triggers(&mut app), vec![]);
        // Pressed in the scene, released over a menu: a whole click in the scene.
        mouse(&mut app, true, false);
        mouse(&mut app, false, true);
        assert_eq!(
            triggers(&mut app),
            vec![InputEvent::ButtonDown { button: Button::Trigger }, InputEvent::ButtonUp { button: Button::Trigger }]
        );
        // While the quit confirmation is open, the scene takes no press.
        app.ui.confirm_quit = true;
        mouse(&mut app, true, false);
        mouse(&mut app, false, false);
        assert_eq!(triggers(&mut app).len(), 2, "no new Trigger");
    }

    #[test]
    fn quitting_asks_during_a_task_or_a_recording_only() {
        let sim = Sim::from_scene(&Scene::builtin("study").unwrap(), 2).unwrap();
        let mut app = super::PlayApp::new(LiveSession::new(sim, None), Some("manual-7"), false).unwrap();
        for _ in 0..3 {
            app.session.as_mut().unwrap().step(0).unwrap();
        }
        assert!(!super::super::window::Frontend::close_requested(&mut app), "a running task: ask first");
        assert!(app.ui.confirm_quit && !app.ui.quit);
        app.ui.confirm_quit = false;
        app.session.as_mut().unwrap().queue(InputEvent::EndTask).unwrap();
        app.session.as_mut().unwrap().step(0).unwrap();
        assert!(
            super::super::window::Frontend::close_requested(&mut app),
            "an ended task without a recording closes at once"
        );
        app.ui.quit = false;
        app.ui.stats.recording = Some("x.jsonl".into());
        assert!(!super::super::window::Frontend::close_requested(&mut app), "a recording: ask first");
    }

    #[test]
    fn the_window_result_agrees_with_replay_and_study_and_stops_at_end_task() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("P77-ray-casting-7.jsonl");
        let scene = Scene::builtin("study").unwrap();
        let mut header = Header::new("study", 4, scene.dt);
        header.task = Some("ray-casting-7".into());
        header.participant = Some("P77".into());
        header.synthetic = false;
        let rec = create_recording(&path, &header).unwrap();
        let mut s = LiveSession::new(Sim::from_scene(&scene, 4).unwrap(), Some(rec));
        for e in PlayUi::start_task_events("ray-casting-7") {
            s.queue(e).unwrap();
        }
        for _ in 0..30 {
            s.step(0).unwrap();
        }
        let def = TaskDef::builtin("ray-casting-7").unwrap();
        let cat = s.sim.catalogue().clone();
        // Two right trees at their targets, and one of the first target's model far from any
        // target (an off-target error).
        for t in &def.targets[..2] {
            let model = cat.by_name(&t.model).unwrap().name.as_str().into();
            s.queue(InputEvent::ChooseModel { model }).unwrap();
            plant_at(&mut s, t.position);
        }
        plant_at(&mut s, Vec3::new(2.0, 0.0, 3.0));
        s.queue(InputEvent::EndTask).unwrap();
        for _ in 0..5 {
            s.step(0).unwrap();
        }
        // What the window shows once the task has ended.
        let shown = task_result(&s.sim).unwrap();
        let end = s.sim.task().unwrap().ended_tick.expect("the task ended");
        let started = s.sim.task().unwrap().started_tick;
        // The participant lingers for 10 more seconds, then closes the window.
        for _ in 0..(10.0 / scene.dt) as usize {
            s.step(0).unwrap();
        }
        let sim = s.finish().unwrap();
        assert!(
            (shown.time_s - grove_systems::task::ticks_to_seconds(end - started, scene.dt)).abs() < 1e-9,
            "the time is the time at end_task"
        );
        assert_eq!(shown.trees.len(), 2, "{shown:?}");
        assert_eq!(shown.errors, 1, "{shown:?}");
        assert_eq!(task_result(&sim).unwrap(), shown, "the result does not change after the end");

        let outcome = replay_file(&path, &ReplayOptions::default()).unwrap();
        assert!(
            outcome.verifying
                && outcome.complete
                && outcome.checkpoints_checked > 0
                && outcome.first_divergence.is_none()
        );
        assert_eq!(
            task_result(&outcome.sim).as_ref(),
            Some(&shown),
            "the replayed session reports what the window showed"
        );
        let trial = grove::study::evaluate(&path, &[]);
        assert_eq!(trial.task.as_ref(), Some(&shown), "grove study reports what the window showed");
    }
}
