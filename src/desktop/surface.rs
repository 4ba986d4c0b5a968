//! The window's drawing surface: the winit window, its wgpu surface (an sRGB format, and the
//! non-sRGB view egui draws into where the driver allows one), the device and egui's renderer and
//! state, opened together by [`init_gfx`] for `window.rs`'s application.

use std::sync::Arc;

use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::egui_pass::EguiPass;

/// The window and what draws into it: the surface, the device, egui's renderer and state.
pub(super) struct Gfx {
    pub(super) window: Arc<Window>,
    pub(super) surface: wgpu::Surface<'static>,
    pub(super) device: wgpu::Device,
    pub(super) queue: wgpu::Queue,
    pub(super) config: wgpu::SurfaceConfiguration,
    pub(super) egui_renderer: egui_wgpu::Renderer,
    /// Draws egui's meshes with egui_renderer's textures.
    pub(super) egui_pass: EguiPass,
    /// The format of the frame view egui draws into (the surface's own, or its non-sRGB twin).
    pub(super) egui_format: wgpu::TextureFormat,
    pub(super) egui_state: egui_winit::State,
    pub(super) ctx: egui::Context,
}


/// Opens the window and its drawing surface, the GPU device and egui on it; gives the adapter's
/// name too.
pub(super) fn init_gfx(event_loop: &ActiveEventLoop, title: &str) -> Result<(Gfx, String), String> {
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
    // egui wants a gamma-space (non-sRGB) target; the 3D view an sRGB one. Where the surface
    // allows views of the other kind, egui gets the non-sRGB view of the same frame.
    let view_formats = if adapter.get_downlevel_capabilities().flags.contains(wgpu::DownlevelFlags::SURFACE_VIEW_FORMATS) && format.remove_srgb_suffix() != format {
        vec![format.remove_srgb_suffix()]
    } else {
        vec![]
    };
    let egui_format = view_formats.first().copied().unwrap_or(format);
    let config = wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        format,
        width: size.width.max(1),
        height: size.height.max(1),
        present_mode: wgpu::PresentMode::Fifo,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats,
        color_space: wgpu::SurfaceColorSpace::Auto,
    };
    surface.configure(&device, &config);
    let egui_renderer = egui_wgpu::Renderer::new(&device, egui_format, egui_wgpu::RendererOptions::default());
    let egui_pass = EguiPass::new(&device, egui_format);
    let ctx = egui::Context::default();
    let egui_state = egui_winit::State::new(ctx.clone(), egui::ViewportId::ROOT, &window, Some(window.scale_factor() as f32), None, Some(device.limits().max_texture_dimension_2d as usize));
    Ok((Gfx { window, surface, device, queue, config, egui_renderer, egui_pass, egui_format, egui_state, ctx }, adapter_name))
}

/// The background where no 3D view was drawn: a linear sky blue, sRGB-encoded for a non-sRGB
/// target.
pub(super) fn clear_colour(target: wgpu::TextureFormat) -> wgpu::Color {
    let encode = |c: f64| if target.is_srgb() { c } else if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    wgpu::Color { r: encode(0.3), g: encode(0.5), b: encode(0.75), a: 1.0 }
}
