//! The window: a winit 0.30 application with a wgpu surface (Fifo present mode) and egui on top.
//! egui is drawn by [`EguiPass`] (egui-wgpu's textures, a lean shader) into a non-sRGB view of
//! the frame where the driver allows one, so that egui blends in gamma space as it prefers and no
//! colour conversion runs per pixel; the 3D view draws into the sRGB view of the same frame.
//!
//! [`run`] opens one window and drives a [`Frontend`] (the play session or the replay viewer):
//! device events go to [`Frontend::input`], each frame the frontend advances by the measured
//! wall-clock time ([`Frontend::update`]), draws the 3D view ([`Frontend::draw_3d`], under the
//! UI) and its egui UI ([`Frontend::ui`]). A gamepad, if gilrs can open one, feeds
//! [`Frontend::gamepad`]; gilrs failing to start is not an error.
//!
//! UI and scene input are kept apart here: a mouse press or wheel turn counts as over the UI
//! when the pointer, at the position of the event itself, is over any egui area (a window, a
//! popup, a modal dialog) or outside the scene's rectangle (the panels take the rest). egui's
//! own "pointer over UI" uses the pointer position of the previous frame, which a quick move and
//! click outruns.
//!
//! The window ends cleanly whatever way it ends: the close button asks the frontend first
//! ([`Frontend::close_requested`]); the X server destroying the window, or the windowing system
//! failing, ends the event loop, and the frontend still finishes (its recording gets its footer).

use std::sync::{Arc, Mutex};
use std::time::Instant;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

use super::budget::{Budget, Quality};
use super::input_map::PadInput;
use super::scaled::Upscaler;
use super::stats::{FrameStats, Rolling};
use super::surface::{clear_colour, init_gfx, Gfx};

/// The GPU objects a frontend may use to draw (the renderer, thumbnails).
pub struct GpuContext<'a> {
    /// The device.
    pub device: &'a wgpu::Device,
    /// The queue.
    pub queue: &'a wgpu::Queue,
    /// The surface's colour format.
    pub format: wgpu::TextureFormat,
    /// The egui renderer, to register textures with.
    pub egui: &'a mut egui_wgpu::Renderer,
}

/// A 3D renderer of the world that draws into the window's frame, under the UI.
pub trait WorldRenderer {
    /// The frame size changed, pixels.
    fn resize(&mut self, width: u32, height: u32);
    /// Records the world as seen from its head into `encoder`, drawing into `view`; the window
    /// submits the encoder, with the UI, as the frame's one command buffer.
    fn render(&mut self, sim: &grove_systems::Sim, view: &wgpu::TextureView, encoder: &mut wgpu::CommandEncoder) -> Result<(), grove::render::RenderError>;
    /// Turns the sun's shadows on or off (the frame-time budget's last resort).
    fn set_shadows(&mut self, _on: bool) {}
}

/// Makes a world renderer for the window's device, queue, surface format and size.
pub type RendererFactory = fn(&wgpu::Device, &wgpu::Queue, wgpu::TextureFormat, u32, u32) -> Result<Box<dyn WorldRenderer>, super::DesktopError>;

/// Renders one thumbnail per catalogue model (by model index) into sampleable textures.
pub type ThumbnailFactory = fn(&wgpu::Device, &wgpu::Queue) -> Result<Vec<wgpu::TextureView>, super::DesktopError>;

/// Makes the thumbnails and registers them with egui; a failure is logged and leaves the
/// tree buttons without pictures.
pub fn make_thumbnails(factory: ThumbnailFactory, gpu: GpuContext<'_>) -> Vec<Option<egui::TextureId>> {
    match factory(gpu.device, gpu.queue) {
        Ok(views) => views.iter().map(|v| Some(gpu.egui.register_native_texture(gpu.device, v, wgpu::FilterMode::Linear))).collect(),
        Err(e) => {
            tracing::warn!("no tree thumbnails: {e}");
            Vec::new()
        }
    }
}

/// The 3D view of a frontend: a world renderer once the GPU is ready, if a factory was given
/// and it could be made; otherwise the frontend draws the world with egui's painter. The world
/// is rendered at the internal resolution the frame-time [`Budget`] chooses and scaled up.
pub struct World3d {
    /// How to make the renderer.
    pub factory: Option<RendererFactory>,
    /// The internal resolution controller.
    pub budget: Budget,
    renderer: Option<Box<dyn WorldRenderer>>,
    upscaler: Option<Upscaler>,
    format: Option<wgpu::TextureFormat>,
    size: (u32, u32),
    last_draw: Option<Instant>,
}

impl Default for World3d {
    fn default() -> World3d {
        World3d { factory: None, budget: Budget::new(Quality::Auto), renderer: None, upscaler: None, format: None, size: (0, 0), last_draw: None }
    }
}

impl World3d {
    /// Makes the renderer for a window of `size` pixels. A failure is logged and leaves the
    /// painter view in place.
    pub fn gpu_ready(&mut self, gpu: &GpuContext<'_>, size: (u32, u32)) {
        if let Some(make) = self.factory {
            match make(gpu.device, gpu.queue, gpu.format, size.0.max(1), size.1.max(1)) {
                Ok(r) => {
                    self.renderer = Some(r);
                    self.size = size;
                    self.format = Some(gpu.format);
                }
                Err(e) => tracing::warn!("3D renderer unavailable, drawing a simple view instead: {e}"),
            }
        }
    }

    /// Whether a renderer draws the world.
    pub fn active(&self) -> bool {
        self.renderer.is_some()
    }

    /// The internal resolution the world was last drawn at, pixels.
    pub fn internal_size(&self) -> (u32, u32) {
        self.size
    }

    /// Draws `sim` into `view` (a frame of `size` pixels), at the budget's internal resolution;
    /// the upscaling pass goes into `encoder`. Returns whether it drew.
    pub fn draw(&mut self, gpu: &GpuContext<'_>, encoder: &mut wgpu::CommandEncoder, sim: &grove_systems::Sim, view: &wgpu::TextureView, size: (u32, u32)) -> bool {
        let Some(r) = self.renderer.as_mut() else { return false };
        // The time between draws is the whole frame's time, which is what the budget is for.
        let now = Instant::now();
        if let Some(last) = self.last_draw {
            self.budget.frame(now.duration_since(last).as_secs_f64());
        }
        self.last_draw = Some(now);
        r.set_shadows(self.budget.shadows());
        let internal = self.budget.internal_size((size.0.max(1), size.1.max(1)));
        if internal != self.size {
            r.resize(internal.0, internal.1);
            self.size = internal;
        }
        // The world goes into the window's encoder, before the upscaling pass when the budget
        // draws it smaller: one command buffer per frame.
        let drawn = if internal == (size.0.max(1), size.1.max(1)) {
            r.render(sim, view, encoder)
        } else {
            let format = self.format.unwrap_or(gpu.format);
            let up = self.upscaler.get_or_insert_with(|| Upscaler::new(gpu.device, format));
            let drawn = r.render(sim, up.target(gpu.device, internal), encoder);
            if drawn.is_ok() {
                up.draw(encoder, view);
            }
            drawn
        };
        match drawn {
            Ok(()) => true,
            Err(e) => {
                eprintln!("grove: cannot draw the 3D view: {e}");
                false
            }
        }
    }
}

/// What a window's content does. Implemented by the play session and the replay viewer.
pub trait Frontend {
    /// Called once the GPU is ready, with the adapter's name and the frame size in pixels.
    fn gpu_ready(&mut self, _gpu: GpuContext<'_>, _adapter: &str, _size: (u32, u32)) {}
    /// A window event. `over_ui` is whether it happened over the UI (see the module docs).
    fn input(&mut self, event: &WindowEvent, over_ui: bool);
    /// A gamepad input.
    fn gamepad(&mut self, _input: PadInput) {}
    /// Advances by `elapsed` wall-clock seconds. An error ends the app.
    fn update(&mut self, elapsed: f64) -> Result<(), String>;
    /// Draws the 3D view into `view` with the renderer, if the frontend has one; returns
    /// whether it drew (then the UI keeps the scenery out of its own view).
    fn draw_3d(&mut self, _gpu: GpuContext<'_>, _encoder: &mut wgpu::CommandEncoder, _view: &wgpu::TextureView, _size: (u32, u32)) -> bool {
        false
    }
    /// Draws the UI for one frame.
    fn ui(&mut self, ui: &mut egui::Ui);
    /// Frame statistics over a rolling window (frames per second and the mean frame time).
    fn frame_stats(&mut self, _stats: FrameStats) {}
    /// Whether the frontend wants the app to end.
    fn wants_quit(&self) -> bool;
    /// The window's close button was pressed: return `true` to close now, or `false` to keep
    /// the window open (for example to ask for confirmation first).
    fn close_requested(&mut self) -> bool {
        true
    }
    /// Called once when the window closes (cleanly): finish recordings here.
    fn finish(&mut self) -> Result<(), String>;
}

struct App<F: Frontend> {
    title: String,
    frontend: F,
    gfx: Option<Gfx>,
    error: Option<String>,
    last_frame: Instant,
    frames: Rolling,
    gilrs: Option<gilrs::Gilrs>,
    /// The pointer's last position, egui points.
    pointer: Option<egui::Pos2>,
    /// The part of the window not covered by panels in the last frame, egui points.
    scene_rect: Option<egui::Rect>,
    /// Set once the window is gone or closing: nothing touches it any more.
    closing: bool,
}

impl<F: Frontend> App<F> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, msg: String) {
        if self.error.is_none() {
            self.error = Some(msg);
        }
        event_loop.exit();
    }

    fn frame(&mut self, event_loop: &ActiveEventLoop) {
        if self.closing {
            return;
        }
        let now = Instant::now();
        let elapsed = now.duration_since(self.last_frame).as_secs_f64();
        self.last_frame = now;
        self.frames.push(elapsed, 1);
        self.frontend.frame_stats(FrameStats::of(&self.frames));
        if let Err(e) = self.frontend.update(elapsed) {
            return self.fail(event_loop, e);
        }
        let Some(gfx) = self.gfx.as_mut() else { return };

        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let frontend = &mut self.frontend;
        let mut scene_rect = None;
        let mut full = gfx.ctx.run_ui(raw, |ui| {
            frontend.ui(ui);
            // What the panels left is the scene.
            scene_rect = Some(ui.available_rect_before_wrap());
        });
        self.scene_rect = scene_rect;
        gfx.egui_state.handle_platform_output(&gfx.window, std::mem::take(&mut full.platform_output));
        let ppp = full.pixels_per_point;
        let jobs = gfx.ctx.tessellate(std::mem::take(&mut full.shapes), ppp);
        for (id, deltas) in full.textures_delta.set.drain() {
            for delta in deltas.iter() {
                gfx.egui_renderer.update_texture(&gfx.device, &gfx.queue, id, delta);
            }
        }
        let to_free: Vec<egui::TextureId> = full.textures_delta.free.drain().collect();

        let frame = match gfx.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) | wgpu::CurrentSurfaceTexture::Suboptimal(f) => Some(f),
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                gfx.surface.configure(&gfx.device, &gfx.config);
                None
            }
            _ => None,
        };
        let Some(frame) = frame else {
            for id in &to_free {
                gfx.egui_renderer.free_texture(id);
            }
            return;
        };
        let view = frame.texture.create_view(&wgpu::TextureViewDescriptor { label: Some("grove window frame"), ..Default::default() });
        let mut encoder = gfx.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("grove window frame") });
        let size = (gfx.config.width, gfx.config.height);
        let drew_3d = self.frontend.draw_3d(
            GpuContext { device: &gfx.device, queue: &gfx.queue, format: gfx.config.format, egui: &mut gfx.egui_renderer },
            &mut encoder,
            &view,
            size,
        );
        let size_px = [size.0, size.1];
        let points = [size.0 as f32 / ppp.max(1e-3), size.1 as f32 / ppp.max(1e-3)];
        gfx.egui_pass.prepare(&gfx.device, &gfx.queue, &jobs, points);
        let egui_view = if gfx.egui_format == gfx.config.format {
            None
        } else {
            Some(frame.texture.create_view(&wgpu::TextureViewDescriptor { label: Some("grove window frame (egui)"), format: Some(gfx.egui_format), ..Default::default() }))
        };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("grove egui pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: egui_view.as_ref().unwrap_or(&view),
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: if drew_3d { wgpu::LoadOp::Load } else { wgpu::LoadOp::Clear(clear_colour(gfx.egui_format)) },
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            gfx.egui_pass.render(&mut pass, &jobs, &gfx.egui_renderer, ppp, size_px);
        }
        gfx.queue.submit(std::iter::once(encoder.finish()));
        gfx.window.pre_present_notify();
        gfx.queue.present(frame);
        for id in &to_free {
            gfx.egui_renderer.free_texture(id);
        }
        if self.frontend.wants_quit() {
            self.closing = true;
            event_loop.exit();
        }
    }

    /// Whether the pointer at `pos` (points) is over the UI rather than the scene. Before the
    /// first frame has been drawn nothing is known, and nothing counts as the scene.
    fn over_ui(&self, pos: Option<egui::Pos2>) -> bool {
        let (Some(gfx), Some(pos)) = (self.gfx.as_ref(), pos) else { return true };
        if self.scene_rect.is_none() {
            return true;
        }
        let over_area = gfx.ctx.layer_id_at(pos).is_some_and(|l| l.order != egui::Order::Background);
        over_area || self.scene_rect.is_some_and(|r| !r.contains(pos))
    }
}

impl<F: Frontend> ApplicationHandler for App<F> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match init_gfx(event_loop, &self.title) {
            Ok((mut gfx, adapter)) => {
                let size = (gfx.config.width, gfx.config.height);
                self.frontend.gpu_ready(
                    GpuContext { device: &gfx.device, queue: &gfx.queue, format: gfx.config.format, egui: &mut gfx.egui_renderer },
                    &adapter,
                    size,
                );
                let size = gfx.window.inner_size();
                self.frontend.input(&WindowEvent::Resized(size), false);
                gfx.window.request_redraw();
                self.gfx = Some(gfx);
                self.last_frame = Instant::now();
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if self.closing {
            return;
        }
        let Some(gfx) = self.gfx.as_mut() else { return };
        if let WindowEvent::Destroyed = event {
            // The X server destroyed the window (e.g. `xdotool windowclose`): it cannot be
            // drawn to or asked anything any more.
            tracing::warn!("the window was destroyed from outside; ending the session");
            self.closing = true;
            event_loop.exit();
            return;
        }
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        if let WindowEvent::CursorMoved { position, .. } = &event {
            let ppp = gfx.ctx.pixels_per_point().max(1e-3);
            self.pointer = Some(egui::pos2(position.x as f32 / ppp, position.y as f32 / ppp));
        }
        if let WindowEvent::CursorLeft { .. } = &event {
            self.pointer = None;
        }
        match &event {
            WindowEvent::CloseRequested => {
                if self.frontend.close_requested() {
                    self.closing = true;
                    event_loop.exit();
                }
            }
            WindowEvent::Resized(size) => {
                gfx.config.width = size.width.max(1);
                gfx.config.height = size.height.max(1);
                gfx.surface.configure(&gfx.device, &gfx.config);
                self.frontend.input(&event, false);
            }
            WindowEvent::RedrawRequested => self.frame(event_loop),
            WindowEvent::MouseInput { .. } | WindowEvent::MouseWheel { .. } => {
                // Decided by where this event happens, not by egui's view of the last frame
                // (which a quick hand outruns both ways).
                let over_ui = self.over_ui(self.pointer);
                self.frontend.input(&event, over_ui);
            }
            _ => {
                self.frontend.input(&event, response.consumed);
                if self.frontend.wants_quit() {
                    self.closing = true;
                    event_loop.exit();
                }
            }
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = self.gilrs.as_mut() {
            while let Some(ev) = g.next_event() {
                let input = match ev.event {
                    gilrs::EventType::ButtonPressed(b, _) => Some(PadInput::Button(b, true)),
                    gilrs::EventType::ButtonReleased(b, _) => Some(PadInput::Button(b, false)),
                    gilrs::EventType::AxisChanged(a, v, _) => Some(PadInput::Axis(a, v)),
                    _ => None,
                };
                if let Some(i) = input {
                    self.frontend.gamepad(i);
                }
            }
        }
        if self.closing {
            return;
        }
        if let Some(gfx) = self.gfx.as_ref() {
            gfx.window.request_redraw();
        }
    }
}

/// Opens a window titled `title` and runs `frontend` until the window closes or the frontend
/// quits; then calls [`Frontend::finish`]. Errors (no display, no GPU, a failed recording) are
/// one line. If the windowing system fails while the window runs (winit panics on some X
/// errors, for example when the window was destroyed from outside), the failure is caught, the
/// frontend still finishes, and the session ends normally with a warning line.
pub fn run<F: Frontend>(title: &str, frontend: F) -> Result<(), super::DesktopError> {
    use super::DesktopError;
    let event_loop = EventLoop::new().map_err(DesktopError::Display)?;
    let gilrs = match gilrs::Gilrs::new() {
        Ok(g) => Some(g),
        Err(e) => {
            tracing::warn!("no gamepad support: {e}");
            None
        }
    };
    let mut app = App {
        title: title.to_string(),
        frontend,
        gfx: None,
        error: None,
        last_frame: Instant::now(),
        frames: Rolling::default(),
        gilrs,
        pointer: None,
        scene_rect: None,
        closing: false,
    };
    // While the window runs, a panic is recorded here instead of printed, so that the session
    // can still be finished and the failure reported as one line.
    let caught: Arc<Mutex<Option<(String, String)>>> = Arc::new(Mutex::new(None));
    let previous = std::panic::take_hook();
    let sink = caught.clone();
    std::panic::set_hook(Box::new(move |info| {
        let msg = info.payload().downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| info.payload().downcast_ref::<String>().cloned()).unwrap_or_else(|| "unknown cause".into());
        let at = info.location().map(|l| l.file().to_string()).unwrap_or_default();
        if let Ok(mut c) = sink.lock() {
            c.get_or_insert((msg.replace('\n', " "), at));
        }
    }));
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| event_loop.run_app(&mut app)));
    // Release the surface before the window goes (this too may fail on a lost display).
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| app.gfx = None));
    std::panic::set_hook(previous);
    let panic = caught.lock().ok().and_then(|mut c| c.take());
    // winit's X11 back end panics on X errors such as a window destroyed under it; that is the
    // display going away, not a bug in grove. Warnings come first, so that the frontend's own
    // last line (where the recording is) stays the last.
    let mut bug = None;
    match (&panic, &run) {
        (Some((msg, at)), _) if at.contains("winit") || at.contains("x11") || at.contains("wgpu") => {
            eprintln!("warning: the window ended abruptly ({msg}); the session was ended there");
        }
        (Some((msg, _)), _) => bug = Some(DesktopError::Internal(msg.clone())),
        (None, Ok(Err(e))) => eprintln!("warning: the window event loop ended with an error ({e}); the session was ended there"),
        _ => {}
    }
    let finished = app.frontend.finish().map_err(DesktopError::Window);
    if let Some(e) = app.error.map(DesktopError::Window).or(bug) {
        finished?;
        return Err(e);
    }
    finished
}
