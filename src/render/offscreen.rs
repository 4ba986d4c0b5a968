//! Headless rendering: a device on any adapter (lavapipe in CI), a renderer drawing into an
//! offscreen texture, read back to an RGBA image and saved as PNG.

use std::path::Path;

use grove_systems::catalogue::ModelId;
use grove_systems::stage::{in_study_wind, model_stage};
use grove_systems::Sim;
use image::RgbaImage;

use super::error::RenderError;
use super::{RenderOptions, Renderer};
use crate::models::{load_model, ModelData};

/// The offscreen target format.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// A GPU device without a window.
pub struct Gpu {
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

impl Gpu {
    /// A device on the first adapter wgpu offers (backends from `WGPU_BACKEND`, else all;
    /// software adapters such as lavapipe are accepted), with timestamp queries where the
    /// adapter has them. Fails with one line when there is none.
    pub fn new() -> Result<Gpu, RenderError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(RenderError::Adapter)?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("grove offscreen device"),
            required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(RenderError::Device)?;
        Ok(Gpu {
            adapter,
            device,
            queue,
        })
    }

    /// Whether the adapter is a software rasteriser (lavapipe, llvmpipe, WARP) rather than a GPU.
    pub fn is_cpu(&self) -> bool {
        self.adapter.get_info().device_type == wgpu::DeviceType::Cpu
    }

    /// A one-line description of the adapter, e.g. "llvmpipe (LLVM 15.0.6) (Vulkan, Cpu)".
    pub fn adapter_name(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }
}

/// An offscreen colour target with its readback buffer.
pub struct Target {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    readback: wgpu::Buffer,
    width: u32,
    height: u32,
    padded_row: u32,
}

impl Target {
    /// A `width`×`height` target of [`FORMAT`].
    pub fn new(device: &wgpu::Device, width: u32, height: u32) -> Target {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("offscreen colour target"),
            size: wgpu::Extent3d {
                width,
                height,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some("offscreen colour view"),
            ..Default::default()
        });
        let padded_row = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("offscreen readback buffer"),
            size: (padded_row * height) as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Target {
            texture,
            view,
            readback,
            width,
            height,
            padded_row,
        }
    }

    /// The view to render into.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Copies the target to the CPU.
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<RgbaImage, RenderError> {
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("readback encoder"),
        });
        enc.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &self.readback,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.padded_row),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
        queue.submit([enc.finish()]);
        let slice = self.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(RenderError::Poll)?;
        rx.recv()
            .map_err(|_| RenderError::ReadbackDropped)?
            .map_err(RenderError::Readback)?;
        let mut pixels = Vec::with_capacity((self.width * self.height * 4) as usize);
        {
            let data = slice
                .get_mapped_range()
                .map_err(RenderError::ReadbackRange)?;
            for row in 0..self.height {
                let start = (row * self.padded_row) as usize;
                pixels.extend_from_slice(&data[start..start + (self.width * 4) as usize]);
            }
        }
        self.readback.unmap();
        RgbaImage::from_raw(self.width, self.height, pixels)
            .ok_or(RenderError::ReadbackSize)
    }
}

/// Renders a world into a new image of the renderer's size.
pub fn render_image(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim) -> Result<RgbaImage, RenderError> {
    let (w, h) = renderer.size();
    let target = Target::new(&gpu.device, w, h);
    renderer.render(sim, target.view())?;
    target.read(&gpu.device, &gpu.queue)
}

/// Saves an image as PNG; the error names the file.
pub fn save_png(img: &RgbaImage, path: &Path) -> Result<(), RenderError> {
    img.save(path).map_err(|error| RenderError::SavePng { path: path.to_path_buf(), error })
}

/// Renders any glTF 2.0 file at `width`×`height` with `options`, framed from its bounds, on a
/// ground plane (the simulation crate's staging scene, [`model_stage`]), always as the mesh
/// (`options.impostor_pixels` is ignored).
pub fn render_model_file(gpu: &Gpu, path: &Path, width: u32, height: u32, options: RenderOptions) -> Result<RgbaImage, RenderError> {
    render_model_data(gpu, &load_model(path)?, width, height, options, None)
}

/// [`render_model_file`] of a model already loaded; with `tick`, the stage in the study's wind
/// ([`in_study_wind`]) after that many ticks.
pub fn render_model_data(gpu: &Gpu, data: &ModelData, width: u32, height: u32, options: RenderOptions, tick: Option<u64>) -> Result<RgbaImage, RenderError> {
    let mut renderer = Renderer::empty(&gpu.device, &gpu.queue, FORMAT, width, height, &super::default_assets_dir())?;
    // The model alone on its stage is shown as itself: never as an impostor.
    renderer.options = RenderOptions { impostor_pixels: 0.0, far_pixels: 0.0, ..options };
    renderer.features.trees.set_model(ModelId(0), data);
    let mut sim = model_stage(data.bounds, width as f32 / height as f32, false, ModelId(0)).map_err(RenderError::Stage)?;
    if let Some(t) = tick {
        in_study_wind(&mut sim).map_err(RenderError::Stage)?;
        sim.run(t);
    }
    render_image(gpu, &mut renderer, &sim)
}
