//! The window: a winit 0.30 application with a wgpu surface (Fifo present mode) and egui on top.
//!
//! [`run`] opens one window and drives a [`Frontend`] (the play session or the replay viewer):
//! device events go to [`Frontend::input`], each frame the frontend advances by the measured
//! wall-clock time ([`Frontend::update`]), draws the 3D view ([`Frontend::draw_3d`], under the
//! UI) and its egui UI ([`Frontend::ui`]). A gamepad, if gilrs can open one, feeds
//! [`Frontend::gamepad`]; gilrs failing to start is not an error.

use std::sync::Arc;
use std::time::Instant;

use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::window::{Window, WindowId};

use super::input_map::PadInput;

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
    fn render(&mut self, sim: &grove_systems::Sim, view: &wgpu::TextureView, encoder: &mut wgpu::CommandEncoder) -> Result<(), String>;
}

/// Makes a world renderer for the window's device, queue, surface format and size.
pub type RendererFactory = fn(&wgpu::Device, &wgpu::Queue, wgpu::TextureFormat, u32, u32) -> Result<Box<dyn WorldRenderer>, String>;

/// Renders one thumbnail per catalogue model (by model index) into sampleable textures.
pub type ThumbnailFactory = fn(&wgpu::Device, &wgpu::Queue) -> Result<Vec<wgpu::TextureView>, String>;

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
/// and it could be made; otherwise the frontend draws the world with egui's painter.
#[derive(Default)]
pub struct World3d {
    /// How to make the renderer.
    pub factory: Option<RendererFactory>,
    renderer: Option<Box<dyn WorldRenderer>>,
    size: (u32, u32),
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
                }
                Err(e) => tracing::warn!("3D renderer unavailable, drawing a simple view instead: {e}"),
            }
        }
    }

    /// Whether a renderer draws the world.
    pub fn active(&self) -> bool {
        self.renderer.is_some()
    }

    /// Draws `sim` into `view`; returns whether it drew.
    pub fn draw(&mut self, sim: &grove_systems::Sim, view: &wgpu::TextureView, size: (u32, u32), encoder: &mut wgpu::CommandEncoder) -> bool {
        let Some(r) = self.renderer.as_mut() else { return false };
        if size != self.size {
            r.resize(size.0.max(1), size.1.max(1));
            self.size = size;
        }
        match r.render(sim, view, encoder) {
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
    /// A window event. `over_ui` is whether egui took it (e.g. a click on a window).
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
    /// Frame statistics: smoothed frames per second and the last frame's milliseconds.
    fn frame_stats(&mut self, _fps: f32, _frame_ms: f32) {}
    /// Whether the frontend wants the app to end.
    fn wants_quit(&self) -> bool;
    /// Called once when the window closes (cleanly): finish recordings here.
    fn finish(&mut self) -> Result<(), String>;
}

struct Gfx {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    egui_renderer: egui_wgpu::Renderer,
    egui_state: egui_winit::State,
    ctx: egui::Context,
}

struct App<F: Frontend> {
    title: String,
    frontend: F,
    gfx: Option<Gfx>,
    error: Option<String>,
    last_frame: Instant,
    fps: f32,
    gilrs: Option<gilrs::Gilrs>,
}

fn init_gfx(event_loop: &ActiveEventLoop, title: &str) -> Result<(Gfx, String), String> {
    let attrs = Window::default_attributes().with_title(title).with_inner_size(winit::dpi::LogicalSize::new(1280.0, 720.0));
    let window = Arc::new(event_loop.create_window(attrs).map_err(|e| format!("cannot open a window: {e}"))?);
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(window.clone())));
    let surface = instance.create_surface(window.clone()).map_err(|e| format!("cannot create a drawing surface: {e}"))?;
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        compatible_surface: Some(&surface),
        ..Default::default()
    }))
    .map_err(|e| format!("no GPU adapter for the window ({e}); install a Vulkan driver such as mesa-vulkan-drivers"))?;
    let info = adapter.get_info();
    let adapter_name = format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("grove window device"),
        required_features: wgpu::Features::empty(),
        required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
        ..Default::default()
    }))
    .map_err(|e| format!("cannot open the GPU device: {e}"))?;
    let size = window.inner_size();
    let caps = surface.get_capabilities(&adapter);
    let format = caps.formats.iter().copied().find(|f| f.is_srgb()).or_else(|| caps.formats.first().copied()).ok_or("the surface offers no format")?;
    let config = wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        width: size.width.max(1),
        height: size.height.max(1),
        present_mode: wgpu::PresentMode::Fifo,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
        color_space: wgpu::SurfaceColorSpace::Auto,
    };
    surface.configure(&device, &config);
    let egui_renderer = egui_wgpu::Renderer::new(&device, format, egui_wgpu::RendererOptions::default());
    let ctx = egui::Context::default();
    let egui_state = egui_winit::State::new(ctx.clone(), egui::ViewportId::ROOT, &window, Some(window.scale_factor() as f32), None, Some(device.limits().max_texture_dimension_2d as usize));
    Ok((Gfx { window, surface, device, queue, config, egui_renderer, egui_state, ctx }, adapter_name))
}

impl<F: Frontend> App<F> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, msg: String) {
        if self.error.is_none() {
            self.error = Some(msg);
        }
        event_loop.exit();
    }

    fn frame(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let elapsed = now.duration_since(self.last_frame).as_secs_f64();
        self.last_frame = now;
        if elapsed > 0.0 {
            let inst = (1.0 / elapsed) as f32;
            self.fps = if self.fps == 0.0 { inst } else { self.fps * 0.9 + inst * 0.1 };
        }
        self.frontend.frame_stats(self.fps, (elapsed * 1000.0) as f32);
        if let Err(e) = self.frontend.update(elapsed) {
            return self.fail(event_loop, e);
        }
        let Some(gfx) = self.gfx.as_mut() else { return };

        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let frontend = &mut self.frontend;
        let mut full = gfx.ctx.run_ui(raw, |ui| frontend.ui(ui));
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
        let screen = egui_wgpu::ScreenDescriptor { size_in_pixels: [size.0, size.1], pixels_per_point: ppp };
        let extra = gfx.egui_renderer.update_buffers(&gfx.device, &gfx.queue, &mut encoder, &jobs, &screen);
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("grove egui pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: if drew_3d { wgpu::LoadOp::Load } else { wgpu::LoadOp::Clear(wgpu::Color { r: 0.3, g: 0.5, b: 0.75, a: 1.0 }) },
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mut pass = pass.forget_lifetime();
            gfx.egui_renderer.render(&mut pass, &jobs, &screen);
        }
        gfx.queue.submit(extra.into_iter().chain(std::iter::once(encoder.finish())));
        gfx.window.pre_present_notify();
        gfx.queue.present(frame);
        for id in &to_free {
            gfx.egui_renderer.free_texture(id);
        }
        if self.frontend.wants_quit() {
            event_loop.exit();
        }
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
        let Some(gfx) = self.gfx.as_mut() else { return };
        let response = gfx.egui_state.on_window_event(&gfx.window, &event);
        match &event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => event_loop.exit(),
            WindowEvent::Resized(size) => {
                gfx.config.width = size.width.max(1);
                gfx.config.height = size.height.max(1);
                gfx.surface.configure(&gfx.device, &gfx.config);
                self.frontend.input(&event, false);
            }
            WindowEvent::RedrawRequested => self.frame(event_loop),
            _ => {
                self.frontend.input(&event, response.consumed);
                if self.frontend.wants_quit() {
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
        if let Some(gfx) = self.gfx.as_ref() {
            gfx.window.request_redraw();
        }
    }
}

/// Opens a window titled `title` and runs `frontend` until the window closes or the frontend
/// quits; then calls [`Frontend::finish`]. Errors (no display, no GPU, a failed recording) are
/// one line.
pub fn run<F: Frontend>(title: &str, frontend: F) -> Result<(), String> {
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open the display ({e}); is DISPLAY set?"))?;
    let gilrs = match gilrs::Gilrs::new() {
        Ok(g) => Some(g),
        Err(e) => {
            tracing::warn!("no gamepad support: {e}");
            None
        }
    };
    let mut app = App { title: title.to_string(), frontend, gfx: None, error: None, last_frame: Instant::now(), fps: 0.0, gilrs };
    let run = event_loop.run_app(&mut app);
    // Release the surface before the window goes.
    app.gfx = None;
    let finished = app.frontend.finish();
    if let Some(e) = app.error {
        return Err(e);
    }
    run.map_err(|e| format!("window event loop: {e}"))?;
    finished
}
