//! Headless rendering: a device on any adapter (lavapipe in CI), a renderer drawing into an
//! offscreen texture, read back to an RGBA image and saved as PNG.

use std::path::Path;

use glam::Vec3;
use grove_systems::Sim;
use grove_systems::catalogue::{Catalogue, ModelId, ModelInfo, ModelKind};
use grove_systems::components::{Controller, Head, Pose, Sun};
use grove_systems::scene::{CameraDef, Hole, PlaneDef, PlaneShape, Scene, SunDef, WindDef};
use image::RgbaImage;

use super::{Renderer, gltf_load};

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
    pub fn new() -> Result<Gpu, String> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            ..Default::default()
        }))
        .map_err(|e| format!("no GPU adapter available ({e}); install a Vulkan driver such as mesa-vulkan-drivers (lavapipe)"))?;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("grove offscreen device"),
            required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
            required_limits: wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| format!("cannot open the GPU device ({e})"))?;
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
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<RgbaImage, String> {
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
            .map_err(|e| format!("GPU poll failed ({e})"))?;
        rx.recv()
            .map_err(|_| "GPU readback was dropped".to_string())?
            .map_err(|e| format!("GPU readback failed ({e})"))?;
        let mut pixels = Vec::with_capacity((self.width * self.height * 4) as usize);
        {
            let data = slice
                .get_mapped_range()
                .map_err(|e| format!("GPU readback failed ({e:?})"))?;
            for row in 0..self.height {
                let start = (row * self.padded_row) as usize;
                pixels.extend_from_slice(&data[start..start + (self.width * 4) as usize]);
            }
        }
        self.readback.unmap();
        RgbaImage::from_raw(self.width, self.height, pixels)
            .ok_or_else(|| "readback size mismatch".to_string())
    }
}

/// Renders a world into a new image of the renderer's size.
pub fn render_image(gpu: &Gpu, renderer: &mut Renderer, sim: &Sim) -> Result<RgbaImage, String> {
    let (w, h) = renderer.size();
    let target = Target::new(&gpu.device, w, h);
    renderer.render(sim, target.view());
    target.read(&gpu.device, &gpu.queue)
}

/// Saves an image as PNG; the error names the file.
pub fn save_png(img: &RgbaImage, path: &Path) -> Result<(), String> {
    img.save(path).map_err(|e| {
        format!(
            "{}: cannot write PNG ({})",
            path.display(),
            super::textures::one_line_image_error(&e)
        )
    })
}

/// A small world for showing one model: a ground plane under its bounds, a fixed morning sun,
/// no wind, and the camera framing the bounds. `bounds` are the model's, in model space.
pub fn model_stage(bounds: (Vec3, Vec3), aspect: f32, with_hole: bool) -> Result<Sim, String> {
    let (min, max) = bounds;
    let size = (max - min).max_element().max(0.1);
    let half = size * 1.5;
    let scene = Scene {
        name: "model stage".into(),
        dt: 1.0 / 60.0,
        seed: 1,
        planes: vec![PlaneDef {
            name: "ground".into(),
            shape: PlaneShape::Grid {
                min: glam::Vec2::new(-half, -half),
                size: glam::Vec2::splat(2.0 * half),
                cell: (size / 8.0).max(0.05),
                elevation: min.y,
                unevenness: 0.0,
                noise_seed: 0,
                holes: if with_hole {
                    vec![Hole {
                        center: glam::Vec2::new(half * 0.55, half * 0.3),
                        radius: size * 0.2,
                    }]
                } else {
                    vec![]
                },
            },
        }],
        sun: SunDef {
            latitude_deg: 47.37,
            longitude_deg: 8.54,
            utc: "2026-06-21T08:00:00Z".into(),
            time_rate: 0.0,
        },
        wind: WindDef {
            direction: Vec3::X,
            strength: 0.0,
            density: 0.1,
            gust_average: 0.0,
            gust_strength: 0.0,
            gust_frequency: 0.0,
            model: Default::default(),
            response: Default::default(),
        },
        trees: vec![],
        camera: CameraDef {
            position: Vec3::new(0.0, 1.0, 5.0),
            look_at: Vec3::ZERO,
            fov_y_deg: 40.0,
        },
    };
    let info = ModelInfo {
        id: ModelId(0),
        name: "model".into(),
        species: "any".into(),
        kind: ModelKind::Mesh,
        bounds_min: min,
        bounds_max: max,
        crown_radius: Vec3::new(
            min.x.abs().max(max.x.abs()),
            0.0,
            min.z.abs().max(max.z.abs()),
        )
        .length(),
        triangles: 0,
        pick: None,
    };
    let mut sim = Sim::from_scene_with(&scene, 1, Catalogue { models: vec![info] })?;
    sim.spawn_tree(ModelId(0), Vec3::ZERO, 0.0, 1.0, false);
    let fov = 40f32.to_radians();
    let (eye, target) = super::frame_bounds(min, max, fov, aspect);
    for (_, head) in sim.world.query_mut::<(hecs::Entity, &mut Head)>() {
        *head = Head {
            pose: Pose::looking_at(eye, target),
            fov_y: fov,
        };
    }
    // A sun from over the camera's left shoulder, 40° up, so the model is lit from the front
    // and its shadow falls to the right where the camera sees it.
    for (_, sun) in sim.world.query_mut::<(hecs::Entity, &mut Sun)>() {
        sun.elevation_deg = 40.0;
        sun.azimuth_deg = 110.0;
        sun.direction = grove_systems::systems::sun::direction_from_angles(110.0, 40.0);
    }
    // No controller ray in a model view.
    let controllers: Vec<hecs::Entity> = sim
        .world
        .query::<(hecs::Entity, &Controller)>()
        .iter()
        .map(|(e, _)| e)
        .collect();
    for e in controllers {
        let _ = sim.world.despawn(e);
    }
    Ok(sim)
}

/// Renders any glTF 2.0 file at `width`×`height`, framed from its bounds, on a ground plane.
pub fn render_model_file(
    gpu: &Gpu,
    path: &Path,
    width: u32,
    height: u32,
    shadows: bool,
) -> Result<RgbaImage, String> {
    let data = gltf_load::load_model(path)?;
    let mut renderer = Renderer::empty(
        &gpu.device,
        &gpu.queue,
        FORMAT,
        width,
        height,
        &super::default_assets_dir(),
    )?;
    renderer.options.shadows = shadows;
    renderer.set_model(ModelId(0), &data);
    let sim = model_stage(data.bounds, width as f32 / height as f32, false)?;
    render_image(gpu, &mut renderer, &sim)
}
