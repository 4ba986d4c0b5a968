//! The `grove play` frontend: device input through [`Controls`], the [`PlayUi`], and a
//! [`LiveSession`] stepped by a fixed-step clock from the frame times.

use std::time::Instant;

use glam::Vec2;
use grove_systems::input::InputEvent;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::PhysicalKey;

use super::input_map::{Controls, PadInput};
use super::play_ui::{PlayUi, Screen};
use super::session::{FixedStep, LiveSession};
use super::window::{make_thumbnails, Frontend, GpuContext, ThumbnailFactory, World3d};
use super::world_view::{head_of, paint_world, ViewOptions};

/// How often the recording is flushed to disk, wall-clock seconds.
pub const FLUSH_EVERY_S: f64 = 1.0;

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
}

impl PlayApp {
    /// A play app over a session. With `task`, the task starts at once; with `skip_menu`,
    /// free planting starts at once.
    pub fn new(session: LiveSession, task: Option<&str>, skip_menu: bool) -> Result<PlayApp, String> {
        let head = head_of(&session.sim);
        let mut app = PlayApp {
            ui: PlayUi::new(head.pose),
            controls: Controls::new(head.pose, head.fov_y, Vec2::new(1280.0, 720.0)),
            clock: FixedStep::new(session.sim.res.dt as f64, 30),
            session: Some(session),
            started: Instant::now(),
            last_flush: Instant::now(),
            world_buttons: [false; 2],
            world3d: World3d::default(),
            thumbnails: None,
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

    fn queue(&mut self, e: InputEvent) -> Result<(), String> {
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
        self.session.as_ref().is_some_and(|s| s.sim.res.menu.open)
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

    fn draw_3d(&mut self, _gpu: GpuContext<'_>, encoder: &mut wgpu::CommandEncoder, view: &wgpu::TextureView, size: (u32, u32)) -> bool {
        match self.session.as_ref() {
            Some(s) => self.world3d.draw(&s.sim, view, size, encoder),
            None => false,
        }
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
                // A press counts only on the world; its release always follows it there.
                if pressed && (over_ui || !self.live()) || !pressed && !self.world_buttons[slot] {
                    return;
                }
                self.world_buttons[slot] = pressed;
                let ev = self.controls.mouse_button(*button, pressed);
                self.queue_all(ev);
            }
            WindowEvent::MouseWheel { delta, .. } if !over_ui && self.live() => {
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
                let menu_open = self.menu_open();
                let (ev, app) = self.controls.key(code, event.state == ElementState::Pressed, menu_open);
                if self.live() {
                    self.queue_all(ev);
                }
                self.ui.quit |= app.quit;
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

    fn frame_stats(&mut self, fps: f32, frame_ms: f32) {
        self.ui.stats.fps = fps;
        self.ui.stats.frame_ms = frame_ms;
    }

    fn wants_quit(&self) -> bool {
        self.ui.quit
    }

    fn finish(&mut self) -> Result<(), String> {
        match self.session.take() {
            Some(s) => s.finish().map(|_| ()),
            None => Ok(()),
        }
    }
}
