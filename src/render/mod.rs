//! The wgpu renderer: draws a [`grove_systems::Sim`] and never writes it.
//!
//! Shaped like the wgpu examples' framework: [`Renderer::new`] with a device, queue, target
//! format and size; [`Renderer::resize`]; [`Renderer::render`] into any texture view. The
//! offscreen path ([`offscreen`]) wraps it for PNG output and tests.
//!
//! Passes per frame:
//! 1. **Shadow** (when the sun is up and shadows are on): depth of every tree from the sun, with
//!    alpha-tested leaves, into a 1024² map (by default) fitted to the scene.
//! 2. **Main**: the trees (one instanced draw per model, material and keep bucket; alpha-clipped
//!    materials behind a depth pre-pass, see [`TreePipelines`]), the ground planes (textured,
//!    lit, shadowed), the interaction visuals, and last the sky (environment cubemap) where
//!    nothing else was drawn.
//!
//! Far trees draw a share of their leaves, grown to keep the crown's area ([`lod`]). Where the
//! device has timestamp queries, [`Renderer::enable_pass_timing`] times both passes.
//!
//! The sun's direction comes from the `Sun` component; its colour and intensity from its
//! elevation ([`sun_light`]): warmer and dimmer near the horizon, off below it.

pub mod gltf_load;
pub mod lod;
pub mod offscreen;
pub mod overlay;
pub mod textures;

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use grove_systems::Sim;
use grove_systems::catalogue::{Catalogue, ModelId};
use grove_systems::components::{Gust, Head, Plane, Scale, Sun, Transform, Tree, Wind, WindState};
use grove_systems::wind_model::{WindModel, WindParams, WindResponse};
use wgpu::util::DeviceExt;

use gltf_load::{ModelData, Vertex};

/// Depth format of the main pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Depth format of the shadow map.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth16Unorm;

const LIGHTING_WGSL: &str = include_str!("lighting.wgsl");
/// The per-vertex wind functions (`WindParams`, `wind_displace`), prepended to the tree shader.
const WIND_WGSL: &str = include_str!("wind.wgsl");

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

/// The sun's light for an elevation: direct colour×intensity (linear RGB), the ambient
/// strength and the sky brightness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLight {
    /// Direct light, linear RGB times intensity; zero when the sun is below the horizon.
    pub direct: Vec3,
    /// Ambient (sky) light multiplier, linear RGB.
    pub ambient: Vec3,
    /// Brightness of the sky background, 0..1.
    pub sky: f32,
}

fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Light from the sun at `elevation_deg` (true elevation, degrees): off below the horizon,
/// ramping up over the first 8°, and shifting from a warm orange near the horizon to a slightly
/// warm white above 30°. The sky and ambient light fade through civil twilight (−6°).
pub fn sun_light(elevation_deg: f64) -> SunLight {
    let e = elevation_deg as f32;
    let on = if e <= 0.0 {
        0.0
    } else {
        smoothstep(0.0, 8.0, e)
    };
    let warm = 1.0 - smoothstep(0.0, 30.0, e);
    let white = Vec3::new(1.0, 0.96, 0.9);
    let orange = Vec3::new(1.0, 0.5, 0.2);
    let direct = white.lerp(orange, warm) * (2.6 * on);
    let sky = 0.06 + 0.94 * smoothstep(-6.0, 12.0, e);
    let ambient = Vec3::new(1.0, 1.0, 1.0).lerp(Vec3::new(1.0, 0.78, 0.6), warm) * (0.9 * sky);
    SunLight {
        direct,
        ambient,
        sky,
    }
}

/// The camera's view-projection matrix for a head pose (wgpu depth 0..1).
pub fn camera_matrix(head: &Head, aspect: f32) -> Mat4 {
    let view = Mat4::from_rotation_translation(head.pose.rotation, head.pose.position).inverse();
    let fov = head.fov_y.clamp(0.01, 3.1);
    let proj = glam::camera::rh::proj::directx::perspective(fov, aspect.max(1e-3), 0.05, 600.0);
    proj * view
}

/// An orthographic light matrix looking along `-sun_dir` that contains the box `min..max`.
/// Returns the matrix and the width of the box in light space (metres).
pub fn light_matrix(sun_dir: Vec3, min: Vec3, max: Vec3) -> (Mat4, f32) {
    let d = sun_dir.normalize_or(Vec3::Y);
    let centre = (min + max) * 0.5;
    let radius = (max - min).length() * 0.5 + 1.0;
    let up = if d.y.abs() > 0.99 { Vec3::Z } else { Vec3::Y };
    let view = glam::camera::rh::view::look_to_mat4(centre + d * radius * 2.0, -d, up);
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 != 0 { max.x } else { min.x },
            if i & 2 != 0 { max.y } else { min.y },
            if i & 4 != 0 { max.z } else { min.z },
        );
        let p = view.transform_point3(c);
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let proj = glam::camera::rh::proj::directx::orthographic(
        lo.x,
        hi.x,
        lo.y,
        hi.y,
        (-hi.z - 1.0).max(0.01),
        -lo.z + 1.0,
    );
    (proj * view, (hi.x - lo.x).max(hi.y - lo.y))
}

/// The per-frame uniforms (matches `Frame` in lighting.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniform {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    light_view_proj: [[f32; 4]; 4],
    camera_pos: [f32; 4],
    sun_dir: [f32; 4],
    sun_color: [f32; 4],
    ambient: [f32; 4],
    shadow: [f32; 4],
}

/// The per-material uniforms (matches `Material` in trees.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct MaterialUniform {
    base_color: [f32; 4],
    params: [f32; 4],
    flags: [f32; 4],
}

/// One tree instance (vertex buffer slot 1).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Instance {
    /// Origin xyz and uniform scale.
    pub a: [f32; 4],
    /// Yaw, wind bend x and z (metres per metre of height, `WindState::bend`), wind gain
    /// (`WindState::gain`).
    pub b: [f32; 4],
    /// The tree's wind phase in radians (`WindState::phase`); y, z and w are zero.
    pub c: [f32; 4],
}

struct GpuPrimitive {
    vertices: wgpu::Buffer,
    /// Per vertex, its leaf's centre and rank (vertex buffer slot 2; see [`lod`]).
    leaves: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Indices drawn for trees in each keep bucket; all of them where the primitive is not
    /// simplified.
    index_counts: [u32; lod::BUCKETS],
    material: usize,
}

struct GpuMaterial {
    bind_group: wgpu::BindGroup,
    double_sided: bool,
    /// Alpha-clipped (`alphaMode: MASK`).
    masked: bool,
}

/// The tree pipelines of one wind model (see [`Specialised`]). The inner arrays are indexed by
/// `double_sided as usize` (back faces culled at 0); the outer arrays of the lit pipelines by
/// `shadows as usize`.
///
/// Opaque materials are shaded in one step with the usual depth test. Alpha-clipped materials
/// take two: a depth pre-pass that only samples the albedo's alpha and discards clipped texels,
/// then a shading pass that tests for equal depth and never discards. Without the pre-pass, a
/// shader that may discard cannot write depth before it has run, so every layer of leaves in a
/// crown would be fully shaded; with it, each pixel is shaded once. Both passes mark the clip
/// position `@invariant`, so their depths agree exactly.
struct TreePipelines {
    opaque: [[wgpu::RenderPipeline; 2]; 2],
    masked_depth: [wgpu::RenderPipeline; 2],
    masked_shade: [[wgpu::RenderPipeline; 2]; 2],
    /// The shadow map: depth only for opaque materials, alpha-tested for masked ones.
    shadow_opaque: wgpu::RenderPipeline,
    shadow_masked: wgpu::RenderPipeline,
}

/// The values of the shaders' pipeline-overridable constants that a pipeline is built for.
///
/// Lavapipe runs both sides of a branch, even one on a uniform value, so a shader that checks
/// a uniform to skip work pays for that work anyway. The two choices that hold for a whole frame
/// are therefore compiled in instead: `SHADOWS` (lighting.wgsl: whether lit shaders look up the
/// shadow map) and `WIND_MODEL` (trees.wgsl: the global wind model, as `WindParams::model`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Specialised {
    shadows: bool,
    wind_model: u32,
}

impl Specialised {
    /// The overridable constants of lit shaders (lighting.wgsl is prepended to each).
    fn lit(shadows: bool) -> [(&'static str, f64); 1] {
        [("SHADOWS", if shadows { 1.0 } else { 0.0 })]
    }

    /// The overridable constants of the tree shaders.
    fn trees(self) -> [(&'static str, f64); 2] {
        let [lit] = Specialised::lit(self.shadows);
        [lit, ("WIND_MODEL", self.wind_model as f64)]
    }
}

/// Which tree materials a loop over the trees draws.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Materials {
    Opaque,
    Masked,
}

/// A model on the GPU.
pub struct GpuModel {
    name: String,
    primitives: Vec<GpuPrimitive>,
    materials: Vec<GpuMaterial>,
    /// Model-space bounds.
    pub bounds: (Vec3, Vec3),
    /// Triangle count.
    pub triangles: usize,
    /// Mean leaf area of the simplified primitives, square metres; 0 when none is simplified.
    pub leaf_area: f32,
}

struct Ground {
    key: Vec<(u64, usize, usize)>,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// Rendering options.
#[derive(Clone, Copy, Debug)]
pub struct RenderOptions {
    /// Draw the sun's shadow map.
    pub shadows: bool,
    /// Shadow-map edge, texels.
    pub shadow_size: u32,
    /// Background colour where there is no sky (linear RGBA); the sky normally covers it.
    pub clear: wgpu::Color,
    /// The smallest area, in pixels, a drawn leaf should cover: farther trees draw a share of
    /// their leaves, grown to keep the crown's area ([`lod`]). 0 draws every leaf.
    pub leaf_pixels: f32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            shadows: true,
            shadow_size: 1024,
            clear: wgpu::Color::BLACK,
            leaf_pixels: 32.0,
        }
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

/// The renderer. It owns the GPU resources and reads the world.
pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    format: wgpu::TextureFormat,
    width: u32,
    height: u32,
    /// Options that apply from the next frame.
    pub options: RenderOptions,
    /// Statistics of the last frame.
    pub stats: FrameStats,
    depth: wgpu::TextureView,
    shadow_view: wgpu::TextureView,
    shadow_size: u32,
    frame_buf: wgpu::Buffer,
    shadow_frame_buf: wgpu::Buffer,
    wind_buf: wgpu::Buffer,
    frame_bg: wgpu::BindGroup,
    shadow_frame_bg: wgpu::BindGroup,
    lighting_bg: wgpu::BindGroup,
    lighting_layout: wgpu::BindGroupLayout,
    material_layout: wgpu::BindGroupLayout,
    env: textures::Environment,
    env_sampler: wgpu::Sampler,
    shadow_sampler: wgpu::Sampler,
    material_sampler: wgpu::Sampler,
    /// Indexed by the wind model: 0 noise, 1 hierarchical.
    trees: [TreePipelines; 2],
    /// Indexed by `shadows as usize`.
    ground_pipeline: [wgpu::RenderPipeline; 2],
    sky_pipeline: wgpu::RenderPipeline,
    overlay_tris: wgpu::RenderPipeline,
    overlay_lines: wgpu::RenderPipeline,
    ground_bg: wgpu::BindGroup,
    models: Vec<Option<GpuModel>>,
    instances: wgpu::Buffer,
    instance_capacity: usize,
    ground: Option<Ground>,
    white: wgpu::TextureView,
    flat_normal: wgpu::TextureView,
    timer: Option<PassTimer>,
}

/// GPU time of each pass of the last frame, in milliseconds, from timestamp queries.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PassTimes {
    /// The sun's shadow-map pass.
    pub shadow_ms: f64,
    /// The main pass: trees, ground, interaction visuals and sky.
    pub main_ms: f64,
}

/// Timestamp queries at the start and end of the shadow and main passes (indices 0–1 and 2–3),
/// resolved into a buffer and copied to a mappable one after every frame.
struct PassTimer {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    period_ns: f64,
}

/// The number of timestamps a frame writes.
const TIMESTAMPS: u32 = 4;

fn vertex_layout() -> [Option<wgpu::VertexBufferLayout<'static>>; 3] {
    const V: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x4];
    const I: [wgpu::VertexAttribute; 3] =
        wgpu::vertex_attr_array![5 => Float32x4, 6 => Float32x4, 7 => Float32x4];
    const L: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![8 => Float32x4];
    [
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &V,
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Instance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &I,
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: 16,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &L,
        }),
    ]
}

fn shader(device: &wgpu::Device, label: &str, src: &str) -> wgpu::ShaderModule {
    let full = format!("{LIGHTING_WGSL}\n{src}");
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(full.into()),
    })
}

fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn texture_entry(
    binding: u32,
    dim: wgpu::TextureViewDimension,
    sample: wgpu::TextureSampleType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: sample,
            view_dimension: dim,
            multisampled: false,
        },
        count: None,
    }
}

fn sampler_entry(binding: u32, ty: wgpu::SamplerBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(ty),
        count: None,
    }
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
    ) -> Result<Renderer, String> {
        Renderer::with_assets(
            device,
            queue,
            target_format,
            width,
            height,
            &default_assets_dir(),
            &Catalogue::builtin(),
        )
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
    /// and ground texture from `assets/env/`.
    pub fn empty(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        width: u32,
        height: u32,
        assets: &Path,
    ) -> Result<Renderer, String> {
        let (face_size, faces) = textures::load_faces(&assets.join("env"))?;
        let ground_path = assets.join("env").join("ground.png");
        let ground_img = image::open(&ground_path)
            .map_err(|e| {
                format!(
                    "{}: {}",
                    ground_path.display(),
                    textures::one_line_image_error(&e)
                )
            })?
            .to_rgba8();

        // Group 0: binding 0 the frame uniforms (lighting.wgsl), binding 1 the wind parameters
        // (wind.wgsl's `WindParams`, read by the tree shader only).
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame layout"),
            entries: &[uniform_entry(0), uniform_entry(1)],
        });
        let lighting_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lighting layout"),
            entries: &[
                texture_entry(
                    0,
                    wgpu::TextureViewDimension::D2,
                    wgpu::TextureSampleType::Depth,
                ),
                sampler_entry(1, wgpu::SamplerBindingType::Comparison),
                texture_entry(
                    2,
                    wgpu::TextureViewDimension::Cube,
                    wgpu::TextureSampleType::Float { filterable: true },
                ),
                // The ground looks up the irradiance per vertex.
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..texture_entry(
                        3,
                        wgpu::TextureViewDimension::Cube,
                        wgpu::TextureSampleType::Float { filterable: true },
                    )
                },
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..sampler_entry(4, wgpu::SamplerBindingType::Filtering)
                },
            ],
        });
        let float_tex = wgpu::TextureSampleType::Float { filterable: true };
        let material_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material layout"),
            entries: &[
                uniform_entry(0),
                texture_entry(1, wgpu::TextureViewDimension::D2, float_tex),
                texture_entry(2, wgpu::TextureViewDimension::D2, float_tex),
                texture_entry(3, wgpu::TextureViewDimension::D2, float_tex),
                sampler_entry(4, wgpu::SamplerBindingType::Filtering),
            ],
        });

        let frame_size = std::mem::size_of::<FrameUniform>() as u64;
        let mk_frame_buf = |label| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: frame_size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let frame_buf = mk_frame_buf("frame uniforms");
        let shadow_frame_buf = mk_frame_buf("shadow frame uniforms");
        let wind_buf = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("wind parameters"),
            size: WindParams::SIZE as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mk_frame_bg = |label, buf: &wgpu::Buffer| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &frame_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: buf.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wind_buf.as_entire_binding(),
                    },
                ],
            })
        };
        let frame_bg = mk_frame_bg("frame bind group", &frame_buf);
        let shadow_frame_bg = mk_frame_bg("shadow frame bind group", &shadow_frame_buf);

        let env = textures::upload_environment(device, queue, face_size, &faces);
        let env_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("environment sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow comparison sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let material_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material sampler"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        let shadow_size = RenderOptions::default().shadow_size;
        let shadow_view = Renderer::shadow_texture(device, shadow_size);

        let tree_shader = shader(
            device,
            "trees.wgsl",
            &format!("{WIND_WGSL}\n{}", include_str!("trees.wgsl")),
        );
        let ground_shader = shader(device, "ground.wgsl", include_str!("ground.wgsl"));
        let sky_shader = shader(device, "sky.wgsl", include_str!("sky.wgsl"));
        let overlay_shader = shader(device, "overlay.wgsl", include_str!("overlay.wgsl"));

        let lit_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lit pipeline layout"),
            bind_group_layouts: &[
                Some(&frame_layout),
                Some(&lighting_layout),
                Some(&material_layout),
            ],
            immediate_size: 0,
        });
        let shadow_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow pipeline layout"),
            bind_group_layouts: &[Some(&frame_layout), None, Some(&material_layout)],
            immediate_size: 0,
        });
        let sky_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sky pipeline layout"),
            bind_group_layouts: &[Some(&frame_layout), Some(&lighting_layout)],
            immediate_size: 0,
        });
        let overlay_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("overlay pipeline layout"),
            bind_group_layouts: &[Some(&frame_layout)],
            immediate_size: 0,
        });

        let depth_state =
            |write: bool, compare: wgpu::CompareFunction, bias: wgpu::DepthBiasState| {
                wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(write),
                    depth_compare: Some(compare),
                    stencil: wgpu::StencilState::default(),
                    bias,
                }
            };
        let color_target = [Some(wgpu::ColorTargetState {
            format: target_format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })];
        let tree_buffers = vertex_layout();
        let no_color = [Some(wgpu::ColorTargetState {
            format: target_format,
            blend: None,
            write_mask: wgpu::ColorWrites::empty(),
        })];
        let tree_pipeline = |label: &str,
                             layout: &wgpu::PipelineLayout,
                             two_sided: bool,
                             (vs, fs): (&str, Option<&str>),
                             depth: wgpu::DepthStencilState,
                             targets: &[Option<wgpu::ColorTargetState>],
                             spec: Specialised| {
            let sides = if two_sided { "two-sided" } else { "one-sided" };
            let constants = spec.trees();
            let compilation_options = wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&format!(
                    "tree {label} pipeline ({sides}, wind model {}, shadows {})",
                    spec.wind_model, spec.shadows
                )),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &tree_shader,
                    entry_point: Some(vs),
                    compilation_options: compilation_options.clone(),
                    buffers: &tree_buffers,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: if two_sided {
                        None
                    } else {
                        Some(wgpu::Face::Back)
                    },
                    ..Default::default()
                },
                depth_stencil: Some(depth),
                multisample: Default::default(),
                fragment: fs.map(|fs| wgpu::FragmentState {
                    module: &tree_shader,
                    entry_point: Some(fs),
                    compilation_options,
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let both = |label: &str,
                    stages: (&str, Option<&str>),
                    depth: wgpu::DepthStencilState,
                    targets: &[Option<wgpu::ColorTargetState>],
                    spec: Specialised| {
            [false, true].map(|two_sided| {
                tree_pipeline(
                    label,
                    &lit_layout,
                    two_sided,
                    stages,
                    depth.clone(),
                    targets,
                    spec,
                )
            })
        };
        let less = depth_state(true, wgpu::CompareFunction::Less, Default::default());
        // The shadow map: no culling, as leaves and thin branches cast from both sides.
        let shadow_depth = wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            bias: wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 1.5,
                clamp: 0.0,
            },
            ..less.clone()
        };
        let equal = depth_state(false, wgpu::CompareFunction::Equal, Default::default());
        // Depth-only pipelines do not shade, so their shadow constant is moot.
        let trees = [0u32, 1].map(|wind_model| {
            let spec = |shadows| Specialised {
                shadows,
                wind_model,
            };
            TreePipelines {
                opaque: [false, true].map(|shadows| {
                    let stages = ("vs_main", Some("fs_main"));
                    both("opaque", stages, less.clone(), &color_target, spec(shadows))
                }),
                masked_depth: both(
                    "depth pre-pass",
                    ("vs_depth", Some("fs_alpha_test")),
                    less.clone(),
                    &no_color,
                    spec(false),
                ),
                masked_shade: [false, true].map(|shadows| {
                    let stages = ("vs_main", Some("fs_main"));
                    both(
                        "alpha-clipped",
                        stages,
                        equal.clone(),
                        &color_target,
                        spec(shadows),
                    )
                }),
                shadow_opaque: tree_pipeline(
                    "shadow (opaque)",
                    &shadow_layout,
                    true,
                    ("vs_depth", None),
                    shadow_depth.clone(),
                    &[],
                    spec(false),
                ),
                shadow_masked: tree_pipeline(
                    "shadow (alpha-clipped)",
                    &shadow_layout,
                    true,
                    ("vs_depth", Some("fs_alpha_test")),
                    shadow_depth.clone(),
                    &[],
                    spec(false),
                ),
            }
        });
        const GV: [wgpu::VertexAttribute; 2] =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
        let ground_pipeline = [false, true].map(|shadows| {
            let constants = Specialised::lit(shadows);
            let compilation_options = wgpu::PipelineCompilationOptions {
                constants: &constants,
                ..Default::default()
            };
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(if shadows {
                    "ground pipeline (shadows)"
                } else {
                    "ground pipeline (no shadows)"
                }),
                layout: Some(&lit_layout),
                vertex: wgpu::VertexState {
                    module: &ground_shader,
                    entry_point: Some("vs_main"),
                    compilation_options: compilation_options.clone(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: 24,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &GV,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(depth_state(
                    true,
                    wgpu::CompareFunction::Less,
                    Default::default(),
                )),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &ground_shader,
                    entry_point: Some("fs_main"),
                    compilation_options,
                    targets: &color_target,
                }),
                multiview_mask: None,
                cache: None,
            })
        });
        let sky_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("sky pipeline"),
            layout: Some(&sky_layout),
            vertex: wgpu::VertexState {
                module: &sky_shader,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            // Drawn last at the far plane: only where nothing else was drawn.
            depth_stencil: Some(depth_state(
                false,
                wgpu::CompareFunction::LessEqual,
                Default::default(),
            )),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &sky_shader,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &color_target,
            }),
            multiview_mask: None,
            cache: None,
        });
        const OV: [wgpu::VertexAttribute; 3] =
            wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4, 2 => Float32x3];
        let overlay_pipeline = |label: &str, topology: wgpu::PrimitiveTopology| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&overlay_layout),
                vertex: wgpu::VertexState {
                    module: &overlay_shader,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<overlay::OverlayVertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &OV,
                    })],
                },
                primitive: wgpu::PrimitiveState {
                    topology,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: Some(depth_state(
                    true,
                    wgpu::CompareFunction::LessEqual,
                    Default::default(),
                )),
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &overlay_shader,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &color_target,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let overlay_tris = overlay_pipeline(
            "overlay triangle pipeline",
            wgpu::PrimitiveTopology::TriangleList,
        );
        let overlay_lines =
            overlay_pipeline("overlay line pipeline", wgpu::PrimitiveTopology::LineList);

        let white = textures::solid(device, queue, "white 1x1", [255, 255, 255, 255], true);
        let flat_normal = textures::solid(
            device,
            queue,
            "flat normal 1x1",
            [128, 128, 255, 255],
            false,
        );
        let ground_tex = textures::upload_2d(
            device,
            queue,
            "ground albedo",
            ground_img.width(),
            ground_img.height(),
            ground_img.as_raw(),
            true,
        );
        let ground_params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ground parameters"),
            contents: bytemuck::cast_slice(&[MaterialUniform {
                base_color: [2.5, 0.0, 0.0, 0.0],
                params: [0.0; 4],
                flags: [0.0; 4],
            }]),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let ground_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ground bind group"),
            layout: &material_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: ground_params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&ground_tex),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&flat_normal),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&white),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&material_sampler),
                },
            ],
        });
        let lighting_bg = Renderer::lighting_bind_group(
            device,
            &lighting_layout,
            &shadow_view,
            &shadow_sampler,
            &env,
            &env_sampler,
        );
        let instance_capacity = 1024;
        let instances = Renderer::instance_buffer(device, instance_capacity);
        let depth = Renderer::depth_texture(device, width, height);
        Ok(Renderer {
            device: device.clone(),
            queue: queue.clone(),
            format: target_format,
            width: width.max(1),
            height: height.max(1),
            options: RenderOptions::default(),
            stats: FrameStats::default(),
            depth,
            shadow_view,
            shadow_size,
            frame_buf,
            shadow_frame_buf,
            wind_buf,
            frame_bg,
            shadow_frame_bg,
            lighting_bg,
            lighting_layout,
            material_layout,
            env,
            env_sampler,
            shadow_sampler,
            material_sampler,
            trees,
            ground_pipeline,
            sky_pipeline,
            overlay_tris,
            overlay_lines,
            ground_bg,
            models: Vec::new(),
            instances,
            instance_capacity,
            ground: None,
            white,
            flat_normal,
            timer: None,
        })
    }

    /// Times every following frame's shadow and main passes with GPU timestamp queries; read
    /// them with [`Renderer::pass_times`]. Fails when the device was opened without
    /// `Features::TIMESTAMP_QUERY` (see [`offscreen::Gpu::new`]).
    pub fn enable_pass_timing(&mut self) -> Result<(), String> {
        if !self
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
        {
            return Err(
                "this GPU device has no timestamp queries (Features::TIMESTAMP_QUERY)".into(),
            );
        }
        let size = u64::from(TIMESTAMPS) * wgpu::QUERY_SIZE as u64;
        let buffer = |label: &str, usage: wgpu::BufferUsages| {
            self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        self.timer = Some(PassTimer {
            set: self.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: TIMESTAMPS,
            }),
            resolve: buffer(
                "pass timestamps resolve",
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            readback: buffer(
                "pass timestamps readback",
                wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            ),
            period_ns: f64::from(self.queue.get_timestamp_period()),
        });
        Ok(())
    }

    /// The timestamp writes of pass `index` (0: shadow, 1: main) when pass timing is on.
    fn pass_timestamps(&self, index: u32) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.timer
            .as_ref()
            .map(|t| wgpu::RenderPassTimestampWrites {
                query_set: &t.set,
                beginning_of_pass_write_index: Some(2 * index),
                end_of_pass_write_index: Some(2 * index + 1),
            })
    }

    /// The GPU time of the last frame's passes. Waits for the GPU; `None` when pass timing is
    /// off. Call it after [`Renderer::render`] and before the next frame.
    pub fn pass_times(&self) -> Result<Option<PassTimes>, String> {
        let Some(t) = &self.timer else {
            return Ok(None);
        };
        let slice = t.readback.slice(..);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| format!("GPU poll failed ({e})"))?;
        rx.recv()
            .map_err(|_| "GPU timestamp readback was dropped".to_string())?
            .map_err(|e| format!("GPU timestamp readback failed ({e})"))?;
        let ticks: Vec<u64> = {
            let data = slice
                .get_mapped_range()
                .map_err(|e| format!("GPU timestamp readback failed ({e:?})"))?;
            data.chunks_exact(8)
                .map(|c| u64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
                .collect()
        };
        t.readback.unmap();
        let ms = |a: usize, b: usize| ticks[b].saturating_sub(ticks[a]) as f64 * t.period_ns * 1e-6;
        Ok(Some(PassTimes {
            shadow_ms: ms(0, 1),
            main_ms: ms(2, 3),
        }))
    }

    fn shadow_texture(device: &wgpu::Device, size: u32) -> wgpu::TextureView {
        let tex = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some("shadow map view"),
            ..Default::default()
        })
    }

    fn depth_texture(device: &wgpu::Device, width: u32, height: u32) -> wgpu::TextureView {
        let tex = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("depth buffer"),
            size: wgpu::Extent3d {
                width: width.max(1),
                height: height.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        tex.create_view(&wgpu::TextureViewDescriptor {
            label: Some("depth buffer view"),
            ..Default::default()
        })
    }

    fn instance_buffer(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("tree instances"),
            size: (capacity * std::mem::size_of::<Instance>()) as u64,
            usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    fn lighting_bind_group(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        shadow: &wgpu::TextureView,
        shadow_sampler: &wgpu::Sampler,
        env: &textures::Environment,
        env_sampler: &wgpu::Sampler,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lighting bind group"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(shadow),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(shadow_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&env.env),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&env.irradiance),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(env_sampler),
                },
            ],
        })
    }

    /// Uploads a model and uses it for trees of `id`, replacing any previous one.
    pub fn set_model(&mut self, id: ModelId, data: &ModelData) {
        let name = data
            .path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let device = &self.device;
        let images: Vec<(wgpu::TextureView, wgpu::TextureView)> = data
            .images
            .iter()
            .enumerate()
            .map(|(i, img)| {
                // Each image is uploaded as sRGB (for albedo) and linear (for normal and specular
                // maps); only the views that materials use are sampled.
                let srgb = textures::upload_2d(
                    device,
                    &self.queue,
                    &format!("{name} image {i} (sRGB)"),
                    img.width,
                    img.height,
                    &img.rgba,
                    true,
                );
                let lin = textures::upload_2d(
                    device,
                    &self.queue,
                    &format!("{name} image {i} (linear)"),
                    img.width,
                    img.height,
                    &img.rgba,
                    false,
                );
                (srgb, lin)
            })
            .collect();
        let materials = data
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let uniform = MaterialUniform {
                    base_color: m.base_color.to_array(),
                    params: [
                        m.alpha_cutoff.unwrap_or(-1.0),
                        m.normal_scale,
                        m.specular_factor,
                        m.roughness,
                    ],
                    flags: [
                        if m.double_sided { 1.0 } else { 0.0 },
                        if m.alpha_cutoff.is_some() { 0.35 } else { 0.0 },
                        0.0,
                        0.0,
                    ],
                };
                let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{name} material {i} ({})", m.name)),
                    contents: bytemuck::cast_slice(&[uniform]),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let albedo = m
                    .albedo
                    .and_then(|k| images.get(k))
                    .map_or(&self.white, |v| &v.0);
                let normal = m
                    .normal
                    .and_then(|k| images.get(k))
                    .map_or(&self.flat_normal, |v| &v.1);
                let spec = m
                    .specular
                    .and_then(|k| images.get(k))
                    .map_or(&self.white, |v| &v.1);
                let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(&format!("{name} material {i} bind group")),
                    layout: &self.material_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: buf.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 1,
                            resource: wgpu::BindingResource::TextureView(albedo),
                        },
                        wgpu::BindGroupEntry {
                            binding: 2,
                            resource: wgpu::BindingResource::TextureView(normal),
                        },
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: wgpu::BindingResource::TextureView(spec),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: wgpu::BindingResource::Sampler(&self.material_sampler),
                        },
                    ],
                });
                GpuMaterial {
                    bind_group,
                    double_sided: m.double_sided,
                    masked: m.alpha_cutoff.is_some(),
                }
            })
            .collect();
        // Alpha-clipped primitives of many pieces are simplified with distance (see `lod`),
        // with a shuffle seeded by the model's name, so every run draws the same leaves.
        let seed = name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        });
        let (mut leaf_area, mut simplified) = (0.0f32, 0usize);
        let primitives = data
            .primitives
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let masked = data
                    .materials
                    .get(p.material)
                    .is_some_and(|m| m.alpha_cutoff.is_some());
                let order = masked
                    .then(|| lod::order_leaves(&p.vertices, &p.indices, seed ^ i as u64))
                    .flatten();
                let full = p.indices.len() as u32;
                let (indices, leaves, index_counts) = match &order {
                    Some(o) => {
                        leaf_area += o.mean_leaf_area;
                        simplified += 1;
                        (
                            &o.indices,
                            o.leaf.clone(),
                            std::array::from_fn(|b| o.index_count(b)),
                        )
                    }
                    None => (
                        &p.indices,
                        lod::unsimplified(p.vertices.len()),
                        [full; lod::BUCKETS],
                    ),
                };
                GpuPrimitive {
                    vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&format!("{name} primitive {i} vertices")),
                        contents: bytemuck::cast_slice(&p.vertices),
                        usage: wgpu::BufferUsages::VERTEX,
                    }),
                    leaves: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&format!("{name} primitive {i} leaves")),
                        contents: bytemuck::cast_slice(&leaves),
                        usage: wgpu::BufferUsages::VERTEX,
                    }),
                    indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&format!("{name} primitive {i} indices")),
                        contents: bytemuck::cast_slice(indices),
                        usage: wgpu::BufferUsages::INDEX,
                    }),
                    index_counts,
                    material: p.material,
                }
            })
            .collect();
        let leaf_area = if simplified > 0 {
            leaf_area / simplified as f32
        } else {
            0.0
        };
        let idx = id.0 as usize;
        if self.models.len() <= idx {
            self.models.resize_with(idx + 1, || None);
        }
        self.models[idx] = Some(GpuModel {
            name,
            primitives,
            materials,
            bounds: data.bounds,
            triangles: data.triangles(),
            leaf_area,
        });
    }

    /// The model drawn for `id`, if one is loaded.
    pub fn model(&self, id: ModelId) -> Option<&GpuModel> {
        self.models.get(id.0 as usize).and_then(|m| m.as_ref())
    }

    /// The target format.
    pub fn format(&self) -> wgpu::TextureFormat {
        self.format
    }

    /// The target size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Resizes the depth buffer for a new target size.
    pub fn resize(&mut self, width: u32, height: u32) {
        self.width = width.max(1);
        self.height = height.max(1);
        self.depth = Renderer::depth_texture(&self.device, self.width, self.height);
    }

    fn update_ground(&mut self, sim: &Sim) {
        let mut key: Vec<(u64, usize, usize)> = sim
            .world
            .query::<(hecs::Entity, &Plane)>()
            .iter()
            .map(|(e, p)| (e.to_bits().get(), p.vertices.len(), p.triangles.len()))
            .collect();
        key.sort_unstable();
        if self.ground.as_ref().is_some_and(|g| g.key == key) {
            return;
        }
        let mut verts: Vec<[f32; 6]> = Vec::new();
        let mut idx: Vec<u32> = Vec::new();
        let mut planes: Vec<(u64, Plane)> = sim
            .world
            .query::<(hecs::Entity, &Plane)>()
            .iter()
            .map(|(e, p)| (e.to_bits().get(), p.clone()))
            .collect();
        planes.sort_by_key(|(e, _)| *e);
        for (_, p) in &planes {
            let base = verts.len() as u32;
            let tris: Vec<u32> = p
                .triangles
                .iter()
                .flatten()
                .copied()
                .filter(|&i| (i as usize) < p.vertices.len())
                .collect();
            let normals = gltf_load::compute_normals(&p.vertices, &tris);
            for (v, n) in p.vertices.iter().zip(&normals) {
                verts.push([v.x, v.y, v.z, n.x, n.y, n.z]);
            }
            idx.extend(tris.iter().map(|i| i + base));
        }
        if idx.is_empty() {
            self.ground = None;
            return;
        }
        let vertices = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ground vertices"),
                contents: bytemuck::cast_slice(&verts),
                usage: wgpu::BufferUsages::VERTEX,
            });
        let indices = self
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ground indices"),
                contents: bytemuck::cast_slice(&idx),
                usage: wgpu::BufferUsages::INDEX,
            });
        self.ground = Some(Ground {
            key,
            vertices,
            indices,
            index_count: idx.len() as u32,
        });
    }

    /// Groups the world's trees by model into instance data; returns per-model ranges and the
    /// bounds of everything drawn.
    /// The instances of every tree, grouped by model and, within a model, by keep bucket
    /// ([`lod::bucket`]), nearest first; the instance range of each (model, bucket); and the
    /// trees' bounds. `head` is the camera.
    fn gather_instances(
        &self,
        sim: &Sim,
        head: &Head,
    ) -> (
        Vec<Instance>,
        Vec<[std::ops::Range<u32>; lod::BUCKETS]>,
        Option<(Vec3, Vec3)>,
    ) {
        let eye = head.pose.position;
        let pixels_per_radian = self.height as f32 * 0.5 / (head.fov_y * 0.5).tan().max(1e-3);
        // Per model: (bucket, squared distance, instance).
        let mut per_model: Vec<Vec<(usize, f32, Instance)>> =
            (0..self.models.len()).map(|_| Vec::new()).collect();
        let mut bounds: Option<(Vec3, Vec3)> = None;
        for (_, tree, t, s, w) in sim
            .world
            .query::<(
                hecs::Entity,
                &Tree,
                &Transform,
                Option<&Scale>,
                Option<&WindState>,
            )>()
            .iter()
        {
            let Some(Some(model)) = self.models.get(tree.model.0 as usize) else {
                continue;
            };
            let scale = s.map_or(1.0, |s| s.0);
            // A tree without a wind state stands still: no bend and zero gain.
            let (bend, gain, phase) =
                w.map_or((glam::Vec2::ZERO, 0.0, 0.0), |w| (w.bend, w.gain, w.phase));
            let d2 = (t.translation - eye).length_squared();
            let keep = lod::keep_fraction(
                model.leaf_area * scale * scale,
                d2.sqrt(),
                pixels_per_radian,
                self.options.leaf_pixels,
            );
            per_model[tree.model.0 as usize].push((
                lod::bucket(keep),
                d2,
                Instance {
                    a: [t.translation.x, t.translation.y, t.translation.z, scale],
                    b: [t.yaw, bend.x, bend.y, gain],
                    c: [phase, keep, 0.0, 0.0],
                },
            ));
            let r = model.bounds.0.abs().max(model.bounds.1.abs());
            let ext = Vec3::new(r.x.max(r.z), 0.0, r.x.max(r.z)) * scale;
            let lo = t.translation + Vec3::new(-ext.x, model.bounds.0.y * scale, -ext.z);
            let hi = t.translation + Vec3::new(ext.x, model.bounds.1.y * scale, ext.z);
            bounds = Some(bounds.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
        }
        // Nearest first within each bucket, so that the early depth test of a software
        // rasteriser skips more hidden fragments of farther trees. Ties are broken by position,
        // so the order never depends on the world's storage order.
        let mut all = Vec::new();
        let mut ranges = Vec::new();
        for mut list in per_model {
            list.sort_by(|p, q| {
                p.0.cmp(&q.0)
                    .then(p.1.total_cmp(&q.1))
                    .then(p.2.a[0].total_cmp(&q.2.a[0]))
                    .then(p.2.a[2].total_cmp(&q.2.a[2]))
            });
            // The list is sorted by bucket, so each bucket is one run of it.
            let base = all.len() as u32;
            let end = |b: usize| base + list.partition_point(|e| e.0 < b) as u32;
            ranges.push(std::array::from_fn(|b| end(b)..end(b + 1)));
            all.extend(list.iter().map(|e| e.2));
        }
        (all, ranges, bounds)
    }

    /// Renders the world into `view` (a texture of the target format and size). Reads the world
    /// only.
    pub fn render(&mut self, sim: &Sim, view: &wgpu::TextureView) {
        self.update_ground(sim);
        let head = sim
            .world
            .query::<&Head>()
            .iter()
            .next()
            .copied()
            .unwrap_or(Head {
                pose: grove_systems::components::Pose::looking_at(
                    Vec3::new(0.0, 1.7, 6.0),
                    Vec3::ZERO,
                ),
                fov_y: 60f32.to_radians(),
            });
        let sun = sim.world.query::<&Sun>().iter().next().copied();
        let (sun_dir, elevation) = sun.map_or((Vec3::new(0.3, 0.8, 0.2).normalize(), 45.0), |s| {
            (s.direction.normalize_or(Vec3::Y), s.elevation_deg)
        });
        let light = sun_light(elevation);
        let view_proj = camera_matrix(&head, self.width as f32 / self.height as f32);

        let (instances, ranges, tree_bounds) = self.gather_instances(sim, &head);
        if instances.len() > self.instance_capacity {
            self.instance_capacity = instances.len().next_power_of_two();
            self.instances = Renderer::instance_buffer(&self.device, self.instance_capacity);
        }
        if !instances.is_empty() {
            self.queue
                .write_buffer(&self.instances, 0, bytemuck::cast_slice(&instances));
        }

        // Fit the shadow map to the trees and planes, within 80 m of the camera.
        let mut scene_bounds = tree_bounds;
        for p in sim.world.query::<&Plane>().iter() {
            for v in &p.vertices {
                scene_bounds = Some(scene_bounds.map_or((*v, *v), |(a, b)| (a.min(*v), b.max(*v))));
            }
        }
        let cam = head.pose.position;
        let (smin, smax) = scene_bounds.unwrap_or((Vec3::splat(-10.0), Vec3::splat(10.0)));
        let reach = Vec3::new(80.0, 1000.0, 80.0);
        let (smin, smax) = (smin.max(cam - reach), smax.min(cam + reach));
        let (smin, smax) = (smin.min(smax), smax.max(smin));
        let (light_vp, extent) = light_matrix(sun_dir, smin, smax);
        let shadows =
            self.options.shadows && light.direct.max_element() > 0.0 && !instances.is_empty();
        if self.options.shadow_size != self.shadow_size {
            self.shadow_size = self.options.shadow_size.clamp(256, 8192);
            self.options.shadow_size = self.shadow_size;
            self.shadow_view = Renderer::shadow_texture(&self.device, self.shadow_size);
            self.lighting_bg = Renderer::lighting_bind_group(
                &self.device,
                &self.lighting_layout,
                &self.shadow_view,
                &self.shadow_sampler,
                &self.env,
                &self.env_sampler,
            );
        }
        let texel_world = extent / self.shadow_size as f32;
        let frame = FrameUniform {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            light_view_proj: light_vp.to_cols_array_2d(),
            camera_pos: cam.extend((sim.res.time() % 3600.0) as f32).to_array(),
            sun_dir: sun_dir.extend(0.0).to_array(),
            sun_color: light.direct.extend(0.0).to_array(),
            ambient: light.ambient.extend(light.sky).to_array(),
            shadow: [
                1.0 / self.shadow_size as f32,
                texel_world * 1.5,
                0.0005,
                if shadows { 1.0 } else { 0.0 },
            ],
        };
        self.queue
            .write_buffer(&self.frame_buf, 0, bytemuck::bytes_of(&frame));
        let shadow_frame = FrameUniform {
            view_proj: light_vp.to_cols_array_2d(),
            ..frame
        };
        self.queue
            .write_buffer(&self.shadow_frame_buf, 0, bytemuck::bytes_of(&shadow_frame));
        let wind = wind_uniform(sim);
        self.queue
            .write_buffer(&self.wind_buf, 0, &wind.to_le_bytes());
        // The pipelines built for this frame's wind model (see `Specialised`).
        let t = &self.trees[(wind.model != 0) as usize];

        let ov = overlay::build(sim);
        let ov_tris = (!ov.triangles.is_empty()).then(|| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("overlay triangles"),
                    contents: bytemuck::cast_slice(&ov.triangles),
                    usage: wgpu::BufferUsages::VERTEX,
                })
        });
        let ov_lines = (!ov.lines.is_empty()).then(|| {
            self.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("overlay lines"),
                    contents: bytemuck::cast_slice(&ov.lines),
                    usage: wgpu::BufferUsages::VERTEX,
                })
        });

        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame encoder"),
            });
        {
            // The shadow pass always runs, so the map is cleared even when nothing casts.
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow pass"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.shadow_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.pass_timestamps(0),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if shadows {
                pass.set_bind_group(0, &self.shadow_frame_bg, &[]);
                pass.set_pipeline(&t.shadow_opaque);
                self.draw_trees(&mut pass, &ranges, Materials::Opaque, |_, _, _, _| {});
                pass.set_pipeline(&t.shadow_masked);
                self.draw_trees(&mut pass, &ranges, Materials::Masked, |_, _, _, _| {});
            }
        }
        let mut stats = FrameStats {
            instances: instances.len(),
            ..Default::default()
        };
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("main pass"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(self.options.clear),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: self.pass_timestamps(1),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_bg, &[]);
            pass.set_bind_group(1, &self.lighting_bg, &[]);
            // Trees first (opaque parts, then the depth of the alpha-clipped parts, then their
            // shading), then the ground, then the sky where nothing was drawn: on a software
            // rasteriser the early depth test then skips most hidden ground and sky fragments.
            self.draw_trees(
                &mut pass,
                &ranges,
                Materials::Opaque,
                |pass, mat, count, range| {
                    pass.set_pipeline(&t.opaque[shadows as usize][mat.double_sided as usize]);
                    stats.draws += 1;
                    stats.triangles += count as usize / 3 * range.len();
                },
            );
            self.draw_trees(&mut pass, &ranges, Materials::Masked, |pass, mat, _, _| {
                pass.set_pipeline(&t.masked_depth[mat.double_sided as usize])
            });
            self.draw_trees(
                &mut pass,
                &ranges,
                Materials::Masked,
                |pass, mat, count, range| {
                    pass.set_pipeline(&t.masked_shade[shadows as usize][mat.double_sided as usize]);
                    stats.draws += 1;
                    stats.triangles += count as usize / 3 * range.len();
                },
            );
            if let Some(g) = &self.ground {
                pass.set_pipeline(&self.ground_pipeline[shadows as usize]);
                pass.set_bind_group(2, &self.ground_bg, &[]);
                pass.set_vertex_buffer(0, g.vertices.slice(..));
                pass.set_index_buffer(g.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..g.index_count, 0, 0..1);
                stats.draws += 1;
                stats.triangles += g.index_count as usize / 3;
            }
            if let Some(b) = &ov_tris {
                pass.set_pipeline(&self.overlay_tris);
                pass.set_vertex_buffer(0, b.slice(..));
                pass.draw(0..ov.triangles.len() as u32, 0..1);
                stats.draws += 1;
            }
            if let Some(b) = &ov_lines {
                pass.set_pipeline(&self.overlay_lines);
                pass.set_vertex_buffer(0, b.slice(..));
                pass.draw(0..ov.lines.len() as u32, 0..1);
                stats.draws += 1;
            }
            pass.set_pipeline(&self.sky_pipeline);
            pass.draw(0..3, 0..1);
            stats.draws += 1;
        }
        if let Some(t) = &self.timer {
            encoder.resolve_query_set(&t.set, 0..TIMESTAMPS, &t.resolve, 0);
            encoder.copy_buffer_to_buffer(&t.resolve, 0, &t.readback, 0, None);
        }
        self.queue.submit([encoder.finish()]);
        self.stats = stats;
    }

    /// The names of the loaded models, by id (empty where none).
    pub fn model_names(&self) -> Vec<String> {
        self.models
            .iter()
            .map(|m| m.as_ref().map(|m| m.name.clone()).unwrap_or_default())
            .collect()
    }
}

impl Renderer {
    /// Draws every tree primitive whose material is of the kind `which`, instanced over its
    /// model's range of the instance buffer, with its material bound. `before_draw` runs just
    /// before each draw, to pick the pipeline or count what is drawn; the shadow pass sets its
    /// pipeline beforehand.
    fn draw_trees<'p>(
        &'p self,
        pass: &mut wgpu::RenderPass<'p>,
        ranges: &[[std::ops::Range<u32>; lod::BUCKETS]],
        which: Materials,
        mut before_draw: impl FnMut(
            &mut wgpu::RenderPass<'p>,
            &'p GpuMaterial,
            u32,
            &std::ops::Range<u32>,
        ),
    ) {
        pass.set_vertex_buffer(1, self.instances.slice(..));
        for (m, buckets) in self.models.iter().zip(ranges) {
            let Some(m) = m else { continue };
            for p in &m.primitives {
                let Some(mat) = m.materials.get(p.material) else {
                    continue;
                };
                if mat.masked != (which == Materials::Masked) {
                    continue;
                }
                pass.set_bind_group(2, &mat.bind_group, &[]);
                pass.set_vertex_buffer(0, p.vertices.slice(..));
                pass.set_vertex_buffer(2, p.leaves.slice(..));
                pass.set_index_buffer(p.indices.slice(..), wgpu::IndexFormat::Uint32);
                for (range, &count) in buckets.iter().zip(&p.index_counts) {
                    if range.is_empty() {
                        continue;
                    }
                    before_draw(pass, mat, count, range);
                    pass.draw_indexed(0..count, 0, range.clone());
                }
            }
        }
    }
}

/// The wind parameters of both tree passes: the world's `Wind` at the simulated time. A world
/// without a `Wind` entity gets a calm one (strength and gust 0, default response), so only the
/// trees' own `WindState::bend` moves them.
fn wind_uniform(sim: &Sim) -> WindParams {
    let time = sim.res.time();
    if let Some(w) = sim.world.query::<&Wind>().iter().next() {
        return WindParams::from_wind(w, time);
    }
    let calm = Wind {
        direction: Vec3::X,
        strength: 0.0,
        density: 0.0,
        gust: Gust {
            average: 0.0,
            strength: 0.0,
            frequency: 0.0,
        },
        current: 0.0,
        model: WindModel::Hierarchical,
        response: WindResponse::default(),
    };
    WindParams::from_wind(&calm, time)
}

/// Bounds helper for framing: the eye position that shows the box `min..max` whole with a
/// vertical field of view `fov_y` and aspect ratio, looking from the south-east and a bit above.
pub fn frame_bounds(min: Vec3, max: Vec3, fov_y: f32, aspect: f32) -> (Vec3, Vec3) {
    let centre = (min + max) * 0.5;
    let radius = ((max - min).length() * 0.5).max(0.01);
    let half = (fov_y * 0.5).min(((fov_y * 0.5).tan() * aspect).atan());
    let dist = radius / half.sin() * 1.05;
    let dir = Vec3::new(0.55, 0.3, 0.78).normalize();
    (centre + dir * dist, centre)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sun_is_off_below_the_horizon() {
        assert_eq!(sun_light(-0.5).direct, Vec3::ZERO);
        assert_eq!(sun_light(0.0).direct, Vec3::ZERO);
        assert!(sun_light(2.0).direct.max_element() > 0.0);
    }

    #[test]
    fn sun_is_dimmer_and_warmer_near_the_horizon() {
        let low = sun_light(4.0).direct;
        let high = sun_light(50.0).direct;
        assert!(low.length() < high.length());
        // Warmer: less blue relative to red.
        assert!(low.z / low.x < high.z / high.x);
        assert!(sun_light(-10.0).sky < sun_light(30.0).sky);
    }

    #[test]
    fn light_matrix_contains_the_box() {
        let (min, max) = (Vec3::new(-50.0, 0.0, -50.0), Vec3::new(50.0, 10.0, 50.0));
        let (m, _) = light_matrix(Vec3::new(0.5, 0.7, -0.3).normalize(), min, max);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 != 0 { max.x } else { min.x },
                if i & 2 != 0 { max.y } else { min.y },
                if i & 4 != 0 { max.z } else { min.z },
            );
            let p = m.project_point3(c);
            assert!(
                p.x.abs() <= 1.0001 && p.y.abs() <= 1.0001 && (0.0..=1.0).contains(&p.z),
                "{p:?}"
            );
        }
    }

    #[test]
    fn framing_keeps_the_box_in_view() {
        let (min, max) = (Vec3::new(-2.0, 0.0, -2.0), Vec3::new(2.0, 8.0, 2.0));
        let (eye, target) = frame_bounds(min, max, 0.8, 4.0 / 3.0);
        let head = Head {
            pose: grove_systems::components::Pose::looking_at(eye, target),
            fov_y: 0.8,
        };
        let m = camera_matrix(&head, 4.0 / 3.0);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 != 0 { max.x } else { min.x },
                if i & 2 != 0 { max.y } else { min.y },
                if i & 4 != 0 { max.z } else { min.z },
            );
            let p = m.project_point3(c);
            assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0, "{p:?}");
        }
    }
}
