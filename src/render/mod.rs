//! The wgpu renderer: draws a [`grove_systems::Sim`] and never writes it.
//!
//! Shaped like the wgpu examples' framework: [`Renderer::new`] with a device, queue, target
//! format and size; [`Renderer::resize`]; [`Renderer::render`] into any texture view (or
//! [`Renderer::render_into`] an encoder the caller submits). The offscreen path ([`offscreen`])
//! wraps it for PNG output and tests.
//!
//! A frame runs in stages ([`frame`]): extract (the frame's `extract::common`, then each
//! feature's own), views, prepare, compute, shadow, main (opaque, alpha-clipped, sky, blended,
//! overlay). Each drawn feature is a folder with its module, its `extract.rs` and its shader:
//! [`trees`], [`ground`], [`grass`], [`sky`], [`overlay`], [`water`], [`aerial_ground`] and
//! [`canopy`], the fields of [`Features`].
//! Shared pieces, leaves that import no feature: [`feature`] (the frame types and the
//! `Feature` trait), [`options`], [`gpu`] (device, layouts, pipeline keys), [`key`] (the
//! pipeline key), [`error`] ([`RenderError`], what every fallible function of the renderer
//! returns), [`view`] (a camera's uniforms), [`lighting`] (sun light, shadow map), [`timing`]
//! (pass timestamps), [`assets`] (glTF, textures).

pub mod aerial_ground;
pub mod assets;
pub mod canopy;
pub mod clip;
pub mod clipmap;
pub mod error;
pub mod extract;
pub mod feature;
pub mod frame;
pub mod gpu;
pub mod grass;
pub mod ground;
pub mod haze;
pub mod key;
pub mod lighting;
pub(crate) mod mix;
pub mod offscreen;
pub mod options;
pub mod overlay;
pub(crate) mod shader;
pub mod sky;
pub mod timing;
pub mod trees;
pub mod view;
pub mod water;

use std::path::Path;

use grove_systems::Sim;
use grove_systems::catalogue::Catalogue;

pub use aerial_ground::AerialPhotos;
pub use assets::default_assets_dir;
pub use error::{ClipmapError, PipelineError, RenderError};
pub use feature::FrameStats;
pub use gpu::{DEPTH_FORMAT, PipelineKey, SHADOW_FORMAT, ViewKind};
pub use lighting::{SunLight, light_matrix, sun_light};
pub use options::{DEFAULT_FAR_PIXELS, DEFAULT_IMPOSTOR_PIXELS, RenderOptions, WaterOutput};
pub use timing::PassTimes;
pub use trees::instances::Instance;
pub use trees::lod;
pub use trees::model::GpuModel;
pub use view::{Camera, TopView, camera_matrix};

/// The drawn features, one named field each; the frame ([`frame`]) calls them in its order.
/// What a caller sets or reads of one feature is that feature's own method.
pub struct Features {
    /// Tree models, instances, impostors.
    pub trees: trees::Trees,
    pub(crate) ground: ground::Ground,
    /// Grass shells and blades.
    pub grass: grass::Grass,
    pub(crate) sky: sky::Sky,
    /// The interaction visuals and a video's ghosts.
    pub overlay: overlay::Overlay,
    pub(crate) water: water::WaterFeature,
    /// The aerial photographs: the aerial ground and the canopy.
    pub aerial: aerial_ground::AerialPhotos,
}

/// The renderer: the frame's shared state and the drawn features.
pub struct Renderer {
    shared: gpu::Shared,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
    /// Options that apply from the next frame.
    pub options: RenderOptions,
    /// Statistics of the last frame.
    pub stats: FrameStats,
    /// The drawn features.
    pub features: Features,
    depth: wgpu::TextureView,
    views: view::Views,
    lighting: lighting::Lighting,
    timer: Option<timing::Timer>,
}

impl Renderer {
    /// A renderer for targets of `target_format` at `width`×`height`, with the models of the
    /// built-in catalogue and the environment from [`default_assets_dir`].
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        width: u32,
        height: u32,
    ) -> Result<Renderer, RenderError> {
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
    ) -> Result<Renderer, RenderError> {
        let mut r = Renderer::empty(device, queue, target_format, width, height, assets)?;
        for m in &catalogue.models {
            let path = assets.join("trees").join(format!("{}.gltf", m.name));
            let data = crate::models::load_model(&path)?;
            r.features.trees.set_model(m.id, &data);
        }
        Ok(r)
    }

    /// A renderer with no models yet (add them with [`trees::Trees::set_model`]), the environment
    /// and ground texture from `assets/env/`. Pipelines are built on first use.
    pub fn empty(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        width: u32,
        height: u32,
        assets: &Path,
    ) -> Result<Renderer, RenderError> {
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
            depth: depth_texture(device, width, height),
            views,
            lighting,
            timer: None,
            features: Features {
                trees: trees::Trees::new(&shared),
                ground,
                grass,
                sky: sky::Sky::new(&shared),
                overlay: overlay::Overlay::new(&shared),
                water,
                aerial: aerial_ground::AerialPhotos::new(&shared),
            },
            shared,
        })
    }

    /// Times every following frame's passes with GPU timestamp queries; read them with
    /// [`Renderer::pass_times`]. Fails when the device was opened without
    /// `Features::TIMESTAMP_QUERY` (see [`offscreen::Gpu::new`]).
    pub fn enable_pass_timing(&mut self) -> Result<(), RenderError> {
        self.timer = Some(timing::Timer::new(&self.shared.device, &self.shared.queue)?);
        Ok(())
    }

    /// The GPU time of the last frame's passes by name ("shadow", "main"). Waits for the GPU;
    /// `None` when pass timing is off. Call it after the frame was submitted and before the next.
    pub fn pass_times(&self) -> Result<Option<PassTimes>, RenderError> {
        self.timer.as_ref().map(|t| t.read(&self.shared.device)).transpose()
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
    pub fn render(&mut self, sim: &Sim, view: &wgpu::TextureView) -> Result<(), RenderError> {
        let mut encoder =
            self.shared.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame encoder") });
        self.encode_frame(sim, view, &mut encoder)?;
        self.shared.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// Records the frame into `encoder` without submitting it, for a caller that adds its own
    /// passes (the desktop app's UI) and submits one command buffer. Buffer uploads go through
    /// the queue and take effect at that submission.
    pub fn render_into(
        &mut self,
        sim: &Sim,
        view: &wgpu::TextureView,
        encoder: &mut wgpu::CommandEncoder,
    ) -> Result<(), RenderError> {
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
