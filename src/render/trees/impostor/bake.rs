//! Baking a model's impostor atlases on the GPU, once per model at load time.

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::{Atlas, CELL, GRID, MIP_LEVELS};
use crate::render::gpu::{PipelineSpec, Shared, depth_test, uniform_entry};
use crate::render::trees::model::GpuModel;

/// The albedo atlas's format (coverage in alpha).
pub const ALBEDO_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// The format the impostor shader reads the albedo atlas as: its sRGB bytes unconverted,
/// decoded in the shader after filtering.
pub const ALBEDO_VIEW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The normal atlas's format (model-space normal encoded as `n / 2 + 1/2`, depth in alpha).
pub const NORMAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

const BAKE_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The bake's uniforms (matches `BakeParams` in bake.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct BakeParams {
    /// The bounding sphere's centre, model-space metres.
    pub centre: [f32; 3],
    /// Its radius, metres.
    pub radius: f32,
}

/// The bake shader composed with what it imports (srgb.wgsl and octa.wgsl): its text is part
/// of the impostor cache's key.
pub fn bake_wgsl() -> String {
    crate::render::shader::compose(include_str!("bake.wgsl"), &[crate::render::trees::model::MATERIAL_PIECE])
}

/// The bake's shader and pipeline, built once per renderer.
pub(crate) struct Baker {
    params_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl Baker {
    /// Builds the bake pipeline.
    pub fn new(shared: &Shared) -> Baker {
        let device = &shared.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("impostor bake shader"),
            source: wgpu::ShaderSource::Wgsl(bake_wgsl().into()),
        });
        let params_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor bake params layout"),
            entries: &[uniform_entry(0)],
        });
        let layout =
            shared.layout("impostor bake layout", &[Some(&params_layout), None, Some(&shared.material_layout)]);
        const V: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x4, 14 => Unorm8x4];
        let buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<crate::models::Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &V,
        })];
        let target = |format| Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL });
        let pipeline = shared.pipeline(&PipelineSpec {
            label: "impostor bake pipeline",
            layout: &layout,
            module: &module,
            vertex: "vs_bake",
            fragment: Some("fs_bake"),
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: None,
            depth: wgpu::DepthStencilState {
                format: BAKE_DEPTH_FORMAT,
                ..depth_test(true, wgpu::CompareFunction::Less)
            },
            targets: &[target(ALBEDO_FORMAT), target(NORMAL_FORMAT)],
            constants: &[],
        });
        Baker { params_layout, pipeline }
    }

    /// The bounding sphere (centre, radius; model-space metres) of `model`, or `None` for a
    /// model with empty bounds or nothing to draw, which has no atlas.
    fn sphere(model: &GpuModel) -> Option<(Vec3, f32)> {
        let (lo, hi) = model.bounds;
        let radius = (hi - lo).length() * 0.5;
        (radius > 1e-4 && radius.is_finite() && !model.primitives.is_empty()).then_some(((lo + hi) * 0.5, radius))
    }

    /// New, empty albedo and normal atlases for `model`, every mip level.
    fn textures(shared: &Shared, model: &GpuModel) -> (wgpu::Texture, wgpu::Texture) {
        let size = wgpu::Extent3d { width: GRID * CELL, height: GRID * CELL, depth_or_array_layers: 1 };
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC
            | wgpu::TextureUsages::COPY_DST;
        let texture = |label: &str, format| {
            shared.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: MIP_LEVELS,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: if format == ALBEDO_FORMAT { &[ALBEDO_VIEW_FORMAT] } else { &[] },
            })
        };
        (
            texture(&format!("{} impostor albedo", model.name), ALBEDO_FORMAT),
            texture(&format!("{} impostor normal", model.name), NORMAL_FORMAT),
        )
    }

    /// The atlases of `model` from texels read from the cache ([`super::cache::decode`]):
    /// albedo levels, then normal levels.
    pub fn from_levels(
        &self,
        shared: &Shared,
        model: &GpuModel,
        positions: &[Vec3],
        levels: &[Vec<u8>],
    ) -> Option<Atlas> {
        let (centre, radius) = Self::sphere(model)?;
        let (albedo, normal) = Self::textures(shared, model);
        super::cache::upload(&shared.queue, [&albedo, &normal], levels);
        let rects = super::view_rects(positions, centre, radius);
        Some(Atlas { albedo, normal, centre, radius, rects, bind_group: None })
    }

    /// Draws `model` into new atlases: every primitive whole, once per view. `None` for a model
    /// with empty bounds.
    pub fn bake(&self, shared: &Shared, model: &GpuModel, positions: &[Vec3]) -> Option<Atlas> {
        let (centre, radius) = Self::sphere(model)?;
        let device = &shared.device;
        let (albedo, normal) = Self::textures(shared, model);
        let depth = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("impostor bake depth"),
            size: wgpu::Extent3d { width: GRID * CELL, height: GRID * CELL, depth_or_array_layers: 1 },
            mip_level_count: MIP_LEVELS,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: BAKE_DEPTH_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let params = BakeParams { centre: centre.to_array(), radius };
        let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("impostor bake params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let params_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor bake params"),
            layout: &self.params_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
        });
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("impostor bake encoder") });
        for level in 0..MIP_LEVELS {
            let views = [&albedo, &normal, &depth].map(|t| {
                t.create_view(&wgpu::TextureViewDescriptor {
                    base_mip_level: level,
                    mip_level_count: Some(1),
                    ..Default::default()
                })
            });
            let attach = |view, clear| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear), store: wgpu::StoreOp::Store },
                })
            };
            // Empty texels: no coverage, and a zero normal (0.5 encoded), so that filtering at
            // a silhouette blends towards nothing rather than towards a wrong direction.
            let empty_normal = wgpu::Color { r: 0.5, g: 0.5, b: 0.5, a: 1.0 };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("impostor bake pass"),
                color_attachments: &[attach(&views[0], wgpu::Color::TRANSPARENT), attach(&views[1], empty_normal)],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &views[2],
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(&self.pipeline);
            pass.set_bind_group(0, &params_group, &[]);
            for p in &model.primitives {
                let Some(mat) = model.materials.get(p.material) else {
                    continue;
                };
                pass.set_bind_group(2, &mat.bind_group, &[]);
                pass.set_vertex_buffer(0, p.vertices.slice(..));
                pass.set_index_buffer(p.indices.slice(..), wgpu::IndexFormat::Uint32);
                // Bucket 0 draws every index; one instance per view.
                pass.draw_indexed(0..p.index_counts[0], 0, 0..GRID * GRID);
            }
        }
        shared.queue.submit([encoder.finish()]);
        let rects = super::view_rects(positions, centre, radius);
        Some(Atlas { albedo, normal, centre, radius, rects, bind_group: None })
    }
}
