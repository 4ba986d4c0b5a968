//! The wgpu renderer ([`grove::render::Renderer`]) as the desktop's 3D view, and the tree
//! thumbnails it draws offscreen for the tree-selection window.

use std::sync::OnceLock;

use grove::render::Renderer;
use grove_systems::Sim;
use grove_systems::catalogue::Catalogue;
use grove_systems::stage::model_stage;

use super::DesktopError;
use super::window::WorldRenderer;

/// Thumbnail edge, pixels.
pub const THUMB_SIZE: u32 = 96;
/// Thumbnail colour format (sampleable by egui).
pub const THUMB_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

impl WorldRenderer for Renderer {
    fn resize(&mut self, width: u32, height: u32) {
        Renderer::resize(self, width, height);
    }

    fn render(
        &mut self,
        sim: &Sim,
        view: &wgpu::TextureView,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<(), grove::render::RenderError> {
        Renderer::render_into(self, sim, view, encoder)
    }

    fn set_shadows(&mut self, on: bool) {
        self.options.shadows = on;
    }
}

/// The session's catalogue and the glTF files of its bank models, set once by `grove play`
/// before the window opens (the factories below are plain functions, so they read it here).
static SESSION_MODELS: OnceLock<(Catalogue, Vec<grove::bank::ModelFile>)> = OnceLock::new();

/// Sets the session's catalogue and bank model files for the renderer and the thumbnails; only
/// the first call has an effect.
pub fn set_session_models(catalogue: Catalogue, files: Vec<grove::bank::ModelFile>) {
    let _ = SESSION_MODELS.set((catalogue, files));
}

/// A renderer with the shipped models and the session's bank models.
fn session_renderer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> Result<Renderer, DesktopError> {
    let mut r = Renderer::new(device, queue, format, width, height)?;
    if let Some((_, files)) = SESSION_MODELS.get() {
        grove::bank::load_into(&mut r, files)?;
    }
    Ok(r)
}

/// The session's scene when it has aerial photographs, set once by `grove play`.
static SESSION_AERIAL: OnceLock<grove_systems::scene::Scene> = OnceLock::new();

/// Sets the session's scene with aerial photographs for the world renderer; only the first call
/// has an effect. `grove play` checks beforehand that they open.
pub fn set_session_aerial(scene: grove_systems::scene::Scene) {
    let _ = SESSION_AERIAL.set(scene);
}

/// Makes the window's world renderer (a [`super::window::RendererFactory`]), with the session's
/// aerial photographs.
pub fn make_renderer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
) -> Result<Box<dyn WorldRenderer>, DesktopError> {
    let mut r = session_renderer(device, queue, format, width, height)?;
    if let Some(sources) =
        SESSION_AERIAL.get().map(|s| grove::render::aerial_ground::open::open_sources(s, false)).transpose()?.flatten()
    {
        r.features.aerial.set(sources)?;
    }
    Ok(Box::new(r))
}

/// Renders one thumbnail per model of the session's catalogue (the shipped models, then the
/// banks'), in model order, each on a small ground plane framed from its bounds (a
/// [`super::window::ThumbnailFactory`]).
pub fn render_thumbnails(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<Vec<wgpu::TextureView>, DesktopError> {
    let catalogue = SESSION_MODELS.get().map_or_else(Catalogue::builtin, |(c, _)| c.clone());
    let mut renderer = session_renderer(device, queue, THUMB_FORMAT, THUMB_SIZE, THUMB_SIZE)?;
    // A thumbnail shows the model itself, not the far model its size would pick.
    renderer.options.far_pixels = 0.0;
    let mut views = Vec::new();
    for m in &catalogue.models {
        let sim = model_stage((m.bounds_min, m.bounds_max), 1.0, false, m.id).map_err(DesktopError::Stage)?;
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("tree thumbnail"),
            size: wgpu::Extent3d { width: THUMB_SIZE, height: THUMB_SIZE, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: THUMB_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture
            .create_view(&wgpu::TextureViewDescriptor { label: Some("tree thumbnail view"), ..Default::default() });
        renderer.render(&sim, &view)?;
        views.push(view);
    }
    Ok(views)
}
