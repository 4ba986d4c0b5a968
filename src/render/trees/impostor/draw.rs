//! The impostor pipelines and their per-model bind groups.

use crate::render::error::RenderError;
use wgpu::util::DeviceExt;

use super::Atlas;
use super::bake::Baker;
use crate::render::gpu::{
    PipelineCache, PipelineKey, PipelineSpec, SHADOW_FORMAT, Shared, ViewKind, color_target, depth_test, sampler_entry,
    texture_entry, uniform_entry,
};
use crate::render::trees::instances::Instance;

/// The per-model uniforms of the impostor shader (matches `ImpostorParams` in impostor.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct ImpostorParams {
    /// The bounding sphere's centre, model-space metres.
    centre: [f32; 3],
    /// Its radius, metres.
    radius: f32,
    /// The model's extent in each view, in radii (min x, min y, max x, max y), row-major.
    rects: [[f32; 4]; 64],
}

// The uniform holds one rectangle per view.
const _: () = assert!(super::GRID * super::GRID == 64);

/// The impostor pipelines of one key: for the main view a depth pre-pass (alpha-tested) and
/// the shading at equal depth; for the sun's, the pre-pass alone into the shadow map.
pub(crate) struct ImpostorPipeline {
    /// Depth only, alpha-tested and dithered.
    pub depth: wgpu::RenderPipeline,
    /// The shading at equal depth (main view only).
    pub shade: Option<wgpu::RenderPipeline>,
}

/// Everything the impostors share: the bake, the shader, the layouts and the pipelines.
pub(crate) struct ImpostorGpu {
    /// Bakes the atlases of new models.
    pub baker: Baker,
    module: wgpu::ShaderModule,
    atlas_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    lit_layout: wgpu::PipelineLayout,
    shadow_layout: wgpu::PipelineLayout,
    /// The pipelines by key.
    pub pipelines: PipelineCache<ImpostorPipeline>,
}

impl ImpostorGpu {
    /// The shader, layouts and bake pipeline; draw pipelines are built on first use.
    pub fn new(shared: &Shared) -> ImpostorGpu {
        let float_tex = wgpu::TextureSampleType::Float { filterable: true };
        let d2 = wgpu::TextureViewDimension::D2;
        let atlas_layout = shared.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor atlas layout"),
            entries: &[
                uniform_entry(0),
                texture_entry(1, d2, float_tex),
                texture_entry(2, d2, float_tex),
                sampler_entry(3, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let sampler = shared.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("impostor sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            // Bilinear within the nearest mip level: on a software rasteriser a trilinear
            // sample reads twice the texels and costs the frame about a fifth more.
            mipmap_filter: wgpu::MipmapFilterMode::Nearest,
            ..Default::default()
        });
        ImpostorGpu {
            baker: Baker::new(shared),
            module: shared.shader("impostor.wgsl", include_str!("impostor.wgsl")),
            lit_layout: shared.layout(
                "impostor lit layout",
                &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&atlas_layout)],
            ),
            shadow_layout: shared
                .layout("impostor shadow layout", &[Some(&shared.view_layout), None, Some(&atlas_layout)]),
            atlas_layout,
            sampler,
            pipelines: PipelineCache::new("impostors"),
        }
    }

    /// Gives a baked atlas its bind group (uniforms, both atlases, the sampler).
    pub fn bind(&self, shared: &Shared, atlas: &mut Atlas) {
        let mut rects = [[-1.0, -1.0, 1.0, 1.0]; 64];
        for (r, v) in rects.iter_mut().zip(&atlas.rects) {
            *r = v.to_array();
        }
        let params = ImpostorParams { centre: atlas.centre.to_array(), radius: atlas.radius, rects };
        let buffer = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("impostor params"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // The albedo is read through a linear view of its sRGB texels and decoded in the
        // shader (impostor.wgsl `srgb_to_linear`): lavapipe filters those faster.
        let albedo = atlas.albedo.create_view(&wgpu::TextureViewDescriptor {
            format: Some(super::bake::ALBEDO_VIEW_FORMAT),
            ..Default::default()
        });
        let normal = atlas.normal.create_view(&Default::default());
        atlas.bind_group = Some(shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor atlas bind group"),
            layout: &self.atlas_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&albedo) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&normal) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&self.sampler) },
            ],
        }));
    }

    /// Builds the pipeline of `key` on first use.
    pub fn prepare(&mut self, shared: &Shared, key: PipelineKey) -> Result<(), RenderError> {
        let (module, lit, shadow) = (&self.module, &self.lit_layout, &self.shadow_layout);
        Ok(self.pipelines.prepare(key, |k| Ok(build(shared, module, lit, shadow, k)))?)
    }
}

/// The instance buffer's layout (slot 0): the tree instance, as trees.wgsl reads it.
fn instance_layout() -> [Option<wgpu::VertexBufferLayout<'static>>; 1] {
    const I: [wgpu::VertexAttribute; 8] = wgpu::vertex_attr_array![
        5 => Float32x3, 6 => Float32, 7 => Float32, 8 => Float32x2, 9 => Float32, 10 => Float32, 11 => Float32, 13 => Float32
    ];
    [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Instance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &I,
    })]
}

fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    lit: &wgpu::PipelineLayout,
    shadow: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> ImpostorPipeline {
    let buffers = instance_layout();
    let [shadows] = key.lit_constants();
    let sun = matches!(key.view, ViewKind::Sun);
    let constants = [shadows, ("SUN_VIEW", if sun { 1.0 } else { 0.0 })];
    let label = format!("impostor pipeline ({key:?})");
    let spec = |layout, (vertex, fragment), depth, targets: &[Option<wgpu::ColorTargetState>]| {
        shared.pipeline(&PipelineSpec {
            label: &label,
            layout,
            module,
            vertex,
            fragment: Some(fragment),
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: None,
            depth,
            targets,
            constants: &constants,
        })
    };
    if sun {
        let depth = wgpu::DepthStencilState {
            format: SHADOW_FORMAT,
            bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 },
            ..depth_test(true, wgpu::CompareFunction::Less)
        };
        ImpostorPipeline { depth: spec(shadow, ("vs_impostor_depth", "fs_impostor_shadow"), depth, &[]), shade: None }
    } else {
        ImpostorPipeline {
            depth: spec(
                lit,
                ("vs_impostor_depth", "fs_impostor_depth"),
                depth_test(true, wgpu::CompareFunction::Less),
                &color_target(key.format, wgpu::ColorWrites::empty()),
            ),
            shade: Some(spec(
                lit,
                ("vs_impostor", "fs_impostor"),
                depth_test(false, wgpu::CompareFunction::Equal),
                &color_target(key.format, wgpu::ColorWrites::ALL),
            )),
        }
    }
}
