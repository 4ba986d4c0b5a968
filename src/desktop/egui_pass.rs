//! The window's egui pass with a lean fragment shader.
//!
//! egui-wgpu's own shader carries a software texture filter for reproducible test snapshots,
//! chosen by a uniform at run time. A software rasteriser such as lavapipe runs both sides of
//! such a branch for every pixel, so on a machine without a GPU egui's panels cost about five
//! times what they need to: at 1280 × 720 the play UI took about 120 ms of CPU a frame, most of
//! the window's frame time. This pass draws the same meshes with the same vertex layout, blend
//! state and textures, but its fragment shader only samples the texture with the sampler's own
//! filtering. Textures stay with [`egui_wgpu::Renderer`] (font atlas updates, thumbnails
//! registered as native textures): this pass binds each texture's bind group from it, through a
//! bind group layout with the same entries as egui-wgpu's.
//!
//! Colours are egui's: premultiplied, gamma-encoded vertex colours times the texture, blended in
//! gamma space. The window gives this pass a non-sRGB view of its frame where the driver allows
//! one (lavapipe does), so nothing is converted per pixel; on an sRGB target the shader decodes
//! sRGB to linear exactly, as egui-wgpu does.

use egui::epaint::{ClippedPrimitive, Primitive, Vertex};

/// The lean egui shader: vertices as egui-wgpu's, one texture sample per fragment.
const EGUI_WGSL: &str = r#"
struct Locals {
    screen_size: vec2<f32>,
    pad: vec2<f32>,
};
@group(0) @binding(0) var<uniform> locals: Locals;
@group(1) @binding(0) var tex: texture_2d<f32>;
@group(1) @binding(1) var samp: sampler;

struct VsOut {
    @location(0) uv: vec2<f32>,
    @location(1) color: vec4<f32>,
    @builtin(position) pos: vec4<f32>,
};

@vertex
fn vs_main(@location(0) pos: vec2<f32>, @location(1) uv: vec2<f32>, @location(2) color: u32) -> VsOut {
    var out: VsOut;
    out.uv = uv;
    out.color = vec4<f32>(f32(color & 255u), f32((color >> 8u) & 255u), f32((color >> 16u) & 255u), f32(color >> 24u)) / 255.0;
    out.pos = vec4<f32>(2.0 * pos.x / locals.screen_size.x - 1.0, 1.0 - 2.0 * pos.y / locals.screen_size.y, 0.0, 1.0);
    return out;
}

@fragment
fn fs_gamma(in: VsOut) -> @location(0) vec4<f32> {
    return in.color * textureSample(tex, samp, in.uv);
}

@fragment
fn fs_linear(in: VsOut) -> @location(0) vec4<f32> {
    let c = in.color * textureSample(tex, samp, in.uv);
    // The sRGB transfer function, decoded.
    let lin = select(pow((c.rgb + vec3<f32>(0.055)) / 1.055, vec3<f32>(2.4)), c.rgb / 12.92, c.rgb < vec3<f32>(0.04045));
    return vec4<f32>(lin, c.a);
}
"#;

/// The pipeline and buffers of the lean egui pass.
pub struct EguiPass {
    pipeline: wgpu::RenderPipeline,
    uniform: wgpu::Buffer,
    uniform_group: wgpu::BindGroup,
    vertices: Option<wgpu::Buffer>,
    indices: Option<wgpu::Buffer>,
    /// Per paint job, its first index and first vertex in the buffers (`None`: not drawn).
    ranges: Vec<Option<(u32, u32, i32)>>,
}

/// The bind group layout of one egui texture, entry for entry as egui-wgpu makes it, so that
/// egui-wgpu's texture bind groups fit this pass's pipeline.
fn texture_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("egui_texture_bind_group_layout"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    multisampled: false,
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 2,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    has_dynamic_offset: false,
                    min_binding_size: std::num::NonZeroU64::new(16),
                    ty: wgpu::BufferBindingType::Uniform,
                },
                count: None,
            },
        ],
    })
}

/// A job's clip rectangle in whole pixels inside the target: (x, y, width, height).
pub fn scissor(clip: egui::Rect, pixels_per_point: f32, size: [u32; 2]) -> (u32, u32, u32, u32) {
    let px = |v: f32, max: u32| ((v * pixels_per_point).round().max(0.0) as u32).min(max);
    let (x0, y0) = (px(clip.min.x, size[0]), px(clip.min.y, size[1]));
    let (x1, y1) = (px(clip.max.x, size[0]).max(x0), px(clip.max.y, size[1]).max(y0));
    (x0, y0, x1 - x0, y1 - y0)
}

impl EguiPass {
    /// The pass for frames of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> EguiPass {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lean egui shader"),
            source: wgpu::ShaderSource::Wgsl(EGUI_WGSL.into()),
        });
        let uniform_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lean egui locals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    has_dynamic_offset: false,
                    min_binding_size: std::num::NonZeroU64::new(16),
                    ty: wgpu::BufferBindingType::Uniform,
                },
                count: None,
            }],
        });
        let uniform = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("lean egui locals"),
            size: 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let uniform_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lean egui locals"),
            layout: &uniform_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() }],
        });
        let textures = texture_layout(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lean egui layout"),
            bind_group_layouts: &[Some(&uniform_layout), Some(&textures)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("lean egui pipeline"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<Vertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x2, 2 => Uint32],
                })],
            },
            primitive: wgpu::PrimitiveState {
                topology: wgpu::PrimitiveTopology::TriangleList,
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(if format.is_srgb() { "fs_linear" } else { "fs_gamma" }),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    // egui's blending: premultiplied colour, and alpha as egui-wgpu blends it.
                    blend: Some(wgpu::BlendState {
                        color: wgpu::BlendComponent {
                            src_factor: wgpu::BlendFactor::One,
                            dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                            operation: wgpu::BlendOperation::Add,
                        },
                        alpha: wgpu::BlendComponent {
                            src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
                            dst_factor: wgpu::BlendFactor::One,
                            operation: wgpu::BlendOperation::Add,
                        },
                    }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        EguiPass { pipeline, uniform, uniform_group, vertices: None, indices: None, ranges: Vec::new() }
    }

    /// Uploads the jobs' meshes and the screen size (in points) for the next [`EguiPass::render`].
    pub fn prepare(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        jobs: &[ClippedPrimitive],
        size_in_points: [f32; 2],
    ) {
        let mut locals = [0u8; 16];
        locals[0..4].copy_from_slice(&size_in_points[0].to_ne_bytes());
        locals[4..8].copy_from_slice(&size_in_points[1].to_ne_bytes());
        queue.write_buffer(&self.uniform, 0, &locals);
        let mut verts: Vec<Vertex> = Vec::new();
        let mut idx: Vec<u32> = Vec::new();
        self.ranges.clear();
        for job in jobs {
            match &job.primitive {
                Primitive::Mesh(m) if !m.indices.is_empty() => {
                    self.ranges.push(Some((idx.len() as u32, m.indices.len() as u32, verts.len() as i32)));
                    verts.extend_from_slice(&m.vertices);
                    idx.extend_from_slice(&m.indices);
                }
                _ => self.ranges.push(None),
            }
        }
        let upload = |buffer: &mut Option<wgpu::Buffer>, bytes: &[u8], usage: wgpu::BufferUsages, label: &str| {
            // Sizes are kept a multiple of 4 bytes, as copies require.
            let needed = (bytes.len() as u64).next_multiple_of(4).max(4);
            if buffer.as_ref().is_none_or(|b| b.size() < needed) {
                *buffer = Some(device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: needed.next_power_of_two(),
                    usage: usage | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
            }
            if !bytes.is_empty() {
                let b = buffer.as_ref().expect("made above");
                let mut padded = bytes.to_vec();
                padded.resize(needed as usize, 0);
                queue.write_buffer(b, 0, &padded);
            }
        };
        upload(&mut self.vertices, bytemuck::cast_slice(&verts), wgpu::BufferUsages::VERTEX, "lean egui vertices");
        upload(&mut self.indices, bytemuck::cast_slice(&idx), wgpu::BufferUsages::INDEX, "lean egui indices");
    }

    /// Draws the jobs prepared last into `pass` (a target of `size` pixels), binding each
    /// mesh's texture from `textures`. A mesh whose texture is unknown is skipped.
    pub fn render(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        jobs: &[ClippedPrimitive],
        textures: &egui_wgpu::Renderer,
        pixels_per_point: f32,
        size: [u32; 2],
    ) {
        let (Some(vertices), Some(indices)) = (&self.vertices, &self.indices) else { return };
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.uniform_group, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        for (job, range) in jobs.iter().zip(&self.ranges) {
            let (Some((first, count, base)), Primitive::Mesh(mesh)) = (range, &job.primitive) else { continue };
            let (x, y, w, h) = scissor(job.clip_rect, pixels_per_point, size);
            if w == 0 || h == 0 {
                continue;
            }
            let Some(texture) = textures.texture(&mesh.texture_id) else { continue };
            pass.set_scissor_rect(x, y, w, h);
            pass.set_bind_group(1, &texture.bind_group, &[]);
            pass.draw_indexed(*first..first + count, *base, 0..1);
        }
        pass.set_scissor_rect(0, 0, size[0].max(1), size[1].max(1));
    }
}

#[cfg(test)]
mod tests {
    use super::scissor;

    #[test]
    fn scissors_are_whole_pixels_inside_the_target() {
        let r = |x0: f32, y0: f32, x1: f32, y1: f32| egui::Rect::from_min_max(egui::pos2(x0, y0), egui::pos2(x1, y1));
        assert_eq!(scissor(r(10.2, 20.6, 110.4, 40.5), 1.0, [1280, 720]), (10, 21, 100, 20));
        // Points are scaled to pixels.
        assert_eq!(scissor(r(10.0, 20.0, 30.0, 40.0), 2.0, [1280, 720]), (20, 40, 40, 40));
        // Clipped to the target, and empty when outside it.
        assert_eq!(scissor(r(-50.0, -10.0, 2000.0, 9000.0), 1.0, [1280, 720]), (0, 0, 1280, 720));
        assert_eq!(scissor(r(1300.0, 10.0, 1400.0, 20.0), 1.0, [1280, 720]).2, 0);
        assert_eq!(scissor(r(50.0, 10.0, 40.0, 20.0), 1.0, [1280, 720]).2, 0, "an inverted rectangle is empty");
    }
}
