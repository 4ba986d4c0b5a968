//! The wgpu renderer: draws a [`grove_systems::Sim`] and never writes it.
//!
//! Shaped like the wgpu examples' framework: [`Renderer::new`] with a device, queue, target
//! format and size; [`Renderer::resize`]; [`Renderer::render`] into any texture view (or
//! [`Renderer::render_into`] an encoder the caller submits). The offscreen path ([`offscreen`])
//! wraps it for PNG output and tests.
//!
//! A frame runs in stages ([`frame`]): extract (the one reader of the world, [`extract`]),
//! prepare, compute, shadow, main (opaque, alpha-clipped, sky, blended, overlay). Each drawn
//! feature is a folder with its module and shader: [`trees`], [`ground`], [`sky`], [`overlay`],
//! [`water`].
//! Shared pieces: [`gpu`] (device, layouts, pipeline keys), [`view`] (a camera's uniforms),
//! [`lighting`] (sun light, shadow map), [`timing`] (pass timestamps), [`assets`] (glTF,
//! textures).

pub mod aerial_ground;
pub mod assets;
pub mod canopy;
pub mod clipmap;
pub mod extract;
pub mod frame;
pub mod gpu;
pub mod grass;
pub mod ground;
pub mod lighting;
pub mod offscreen;
pub mod overlay;
pub mod sky;
pub mod timing;
pub mod trees;
pub mod view;
pub mod water;

use std::path::{Path, PathBuf};

use grove_systems::catalogue::Catalogue;
use grove_systems::Sim;

pub use assets::gltf_load;
pub use gpu::{PipelineKey, ViewKind, DEPTH_FORMAT, SHADOW_FORMAT};
pub use lighting::{light_matrix, sun_light, SunLight};
pub use timing::PassTimes;
pub use trees::instances::Instance;
pub use trees::lod;
pub use trees::model::GpuModel;
pub use view::{camera_matrix, Camera, TopView};
pub use water::WaterOutput;


/// The assets folder: `$GROVE_ASSETS`, else `./assets` when it exists, else the source tree's.
pub fn default_assets_dir() -> PathBuf {
    if let Some(d) = std::env::var_os("GROVE_ASSETS") {
        return PathBuf::from(d);
    }
    let local = PathBuf::from("assets");
    if local.join("trees").is_dir() {
        return local;
    }
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}

/// The default on-screen size, pixels, below which trees are impostors
/// ([`RenderOptions::impostor_pixels`]).
pub const DEFAULT_IMPOSTOR_PIXELS: f32 = 150.0;

/// Rendering options.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Draw the sun's shadow map.
    pub shadows: bool,
    /// Shadow-map edge, texels; clamped to [`lighting::SHADOW_SIZES`] (see
    /// [`Renderer::shadow_size`]).
    pub shadow_size: u32,
    /// Background colour where there is no sky (linear RGBA); the sky normally covers it.
    pub clear: wgpu::Color,
    /// The smallest area, in pixels, a drawn leaf should cover: farther trees draw a share of
    /// their leaves, grown to keep the crown's area ([`lod`]). 0 draws every leaf.
    pub leaf_pixels: f32,
    /// Draw the scene's water (its reflection and refraction passes and the surface).
    pub water: bool,
    /// What the water surface shows (normally the water itself).
    pub water_output: WaterOutput,
    /// Draw the scene's grass patches (`--no-grass` turns them off).
    pub grass: bool,
    /// Bend grass blades away from the eye and the controller's hit point when they are near.
    pub grass_bend: bool,
    /// Draw the interaction visuals (the controller's ray, the hit marker, the anchor ball, the
    /// selection and the task's targets).
    pub overlay: bool,
    /// The on-screen size, in pixels, of a tree's bounding sphere below which it is drawn as an
    /// impostor (with a cross-fade up to [`trees::impostor::BAND`] times as many). 0 draws
    /// every tree as a mesh. The default, [`DEFAULT_IMPOSTOR_PIXELS`], keeps the reference
    /// scene's image within a mean absolute error of 4 of 255 per channel of the full-detail
    /// render (README, `grove bench render-reference`).
    pub impostor_pixels: f32,
    /// Draw the photographed crowns as canopy layers (with aerial photographs set by
    /// [`Renderer::set_aerial`]); off, or without layer masks, they are drawn as tree models.
    pub canopy: bool,
    /// Draw from straight above with an orthographic projection ([`view::TopView`]) instead of
    /// the world's head camera.
    pub top_view: Option<view::TopView>,
    /// Draw from this camera instead of the world's head camera (a video's shoulder or orbit
    /// camera); the head is then drawn as a figure like the ghosts.
    pub camera: Option<Camera>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { shadows: true, shadow_size: 1024, clear: wgpu::Color::BLACK, leaf_pixels: 32.0, water: true, water_output: WaterOutput::Full, grass: true, grass_bend: true, overlay: true, impostor_pixels: DEFAULT_IMPOSTOR_PIXELS, canopy: true, top_view: None, camera: None }
    }
}

/// Draw statistics of the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStats {
    /// Tree instances drawn.
    pub instances: usize,
    /// Draw calls in the main pass.
    pub draws: usize,
    /// Triangles submitted in the main pass.
    pub triangles: usize,
}

/// The renderer: the frame's shared state and one named field per drawn feature.
pub struct Renderer {
    shared: gpu::Shared,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
    /// Options that apply from the next frame.
    pub options: RenderOptions,
    /// Statistics of the last frame.
    pub stats: FrameStats,
    /// Other participants' heads and rays drawn over the world from the next frame (a video's
    /// `--ghosts`); empty normally.
    pub ghosts: Vec<overlay::geometry::OverlayGhost>,
    depth: wgpu::TextureView,
    views: view::Views,
    lighting: lighting::Lighting,
    timer: Option<timing::Timer>,
    trees: trees::Trees,
    ground: ground::Ground,
    grass: grass::Grass,
    sky: sky::Sky,
    overlay: overlay::Overlay,
    water: water::WaterFeature,
    aerial_ground: Option<aerial_ground::AerialGround>,
    canopy: Option<canopy::Canopy>,
}

impl Renderer {
    /// A renderer for targets of `target_format` at `width`×`height`, with the models of the
    /// built-in catalogue and the environment from [`default_assets_dir`].
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, target_format: wgpu::TextureFormat, width: u32, height: u32) -> Result<Renderer, String> {
        Renderer::with_assets(device, queue, target_format, width, height, &default_assets_dir(), &Catalogue::builtin())
    }

    /// Like [`Renderer::new`], with an explicit assets folder and catalogue: models are read
    /// from `assets/trees/<name>.gltf`, the sky from `assets/env/`.
    pub fn with_assets(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        width: u32,
        height: u32,
        assets: &Path,
        catalogue: &Catalogue,
    ) -> Result<Renderer, String> {
        let mut r = Renderer::empty(device, queue, target_format, width, height, assets)?;
        for m in &catalogue.models {
            let path = assets.join("trees").join(format!("{}.gltf", m.name));
            let data = gltf_load::load_model(&path)?;
            r.set_model(m.id, &data);
        }
        Ok(r)
    }

    /// A renderer with no models yet (add them with [`Renderer::set_model`]), the environment
    /// and ground texture from `assets/env/`. Pipelines are built on first use.
    pub fn empty(device: &wgpu::Device, queue: &wgpu::Queue, target_format: wgpu::TextureFormat, width: u32, height: u32, assets: &Path) -> Result<Renderer, String> {
        let (face_size, faces) = assets::textures::load_faces(&assets.join("env"))?;
        let shared = gpu::Shared::new(device, queue);
        let options = RenderOptions::default();
        let ground = ground::Ground::new(&shared, assets)?;
        let views = view::Views::new(&shared);
        let water = water::WaterFeature::new(&shared, &views);
        let lighting = lighting::Lighting::new(&shared, face_size, &faces, options.shadow_size);
        let grass = grass::Grass::new(&shared, lighting.irradiance());
        Ok(Renderer {
            format: target_format,
            width: width.max(1),
            height: height.max(1),
            options,
            stats: FrameStats::default(),
            ghosts: Vec::new(),
            depth: depth_texture(device, width, height),
            views,
            lighting,
            timer: None,
            trees: trees::Trees::new(&shared),
            ground,
            grass,
            sky: sky::Sky::new(&shared),
            overlay: overlay::Overlay::new(&shared),
            water,
            aerial_ground: None,
            canopy: None,
            shared,
        })
    }

    /// Times every following frame's passes with GPU timestamp queries; read them with
    /// [`Renderer::pass_times`]. Fails when the device was opened without
    /// `Features::TIMESTAMP_QUERY` (see [`offscreen::Gpu::new`]).
    pub fn enable_pass_timing(&mut self) -> Result<(), String> {
        self.timer = Some(timing::Timer::new(&self.shared.device, &self.shared.queue)?);
        Ok(())
    }

    /// The GPU time of the last frame's passes by name ("shadow", "main"). Waits for the GPU;
    /// `None` when pass timing is off. Call it after the frame was submitted and before the next.
    pub fn pass_times(&self) -> Result<Option<PassTimes>, String> {
        self.timer.as_ref().map(|t| t.read(&self.shared.device)).transpose()
    }

    /// The numbers of grass blades the last frame drew at each level of detail, read back from
    /// the GPU's indirect draws (waits for the GPU); all zero without blades.
    pub fn visible_blades(&self) -> Result<grass::BladeCounts, String> {
        self.grass.visible_blades(&self.shared)
    }

    /// The target format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// The target size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The shadow map's edge in texels as the last frame drew it: `options.shadow_size` clamped
    /// to [`lighting::SHADOW_SIZES`].
    pub fn shadow_size(&self) -> u32 {
        self.lighting.shadow_size
    }

    /// Resizes the depth buffer for a new target size.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.width = width.max(1);
        self.height = height.max(1);
        self.depth = depth_texture(&self.shared.device, self.width, self.height);
    }

    /// Renders the world into `view` (a texture of the target format and size) and submits the
    /// frame. Reads the world only.
    pub fn render(&mut self, sim: &Sim, view: &wgpu::TextureView) -> Result<(), String> {
        let mut encoder = self.shared.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame encoder") });
        self.encode_frame(sim, view, &mut encoder)?;
        self.shared.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Records the frame into `encoder` without submitting it, for a caller that adds its own
    /// passes (the desktop app's UI) and submits one command buffer. Buffer uploads go through
    /// the queue and take effect at that submission.
    pub fn render_into(&mut self, sim: &Sim, view: &wgpu::TextureView, encoder: &mut wgpu::CommandEncoder) -> Result<(), String> {
        self.encode_frame(sim, view, encoder)
    }
}

fn depth_texture(device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
    let tex = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("depth buffer"),
        size: wgpu::Extent3d { width: width.max(1), height: height.max(1), depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    });
    tex.create_view(&wgpu::TextureViewDescriptor { label: Some("depth buffer view"), ..Default::default() })
}
