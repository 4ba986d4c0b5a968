//! Grass's GPU set-up (`mod.rs` draws with it): the bind group layouts, the cull and order
//! compute pipelines, the noise textures and samplers made once by [`Grass::new`], and the
//! shells' and blades' render pipelines built per pipeline key.

use super::data::{self};
use super::extract::GrassKey;
use super::Grass;
use crate::render::error::PipelineError;
use crate::render::gpu::{depth_test, PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind};

fn entry(binding: u32, visibility: wgpu::ShaderStages, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry { binding, visibility, ty, count: None }
}

fn buffer_ty(ty: wgpu::BufferBindingType) -> wgpu::BindingType {
    wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None }
}

fn storage(read_only: bool) -> wgpu::BindingType {
    buffer_ty(wgpu::BufferBindingType::Storage { read_only })
}

fn float_texture() -> wgpu::BindingType {
    wgpu::BindingType::Texture { sample_type: wgpu::TextureSampleType::Float { filterable: true }, view_dimension: wgpu::TextureViewDimension::D2, multisampled: false }
}

/// Bind group entries 0, 1, … for whole buffers.
pub(super) fn buffer_entries<'a>(buffers: &[&'a wgpu::Buffer]) -> Vec<wgpu::BindGroupEntry<'a>> {
    buffers.iter().enumerate().map(|(k, b)| wgpu::BindGroupEntry { binding: k as u32, resource: b.as_entire_binding() }).collect()
}

impl Grass {
    /// The feature: shaders, layouts, the cull pipeline, the noise textures; no patches yet.
    /// `irradiance` is the sky's irradiance cube (the lighting's), with which the cull pass
    /// lights the far blades.
    pub(crate) fn new(shared: &Shared, irradiance: &wgpu::TextureView) -> Grass {
        let device = &shared.device;
        let (v, f, vf, c) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT, wgpu::ShaderStages::VERTEX_FRAGMENT, wgpu::ShaderStages::COMPUTE);
        let uniform = buffer_ty(wgpu::BufferBindingType::Uniform);
        let filtering = wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering);
        let shell_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass shell layout"),
            entries: &[entry(0, vf, uniform), entry(1, f, float_texture()), entry(2, v, float_texture()), entry(3, f, filtering), entry(4, v, filtering)],
        });
        let blade_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass blade layout"),
            entries: &[entry(0, vf, uniform), entry(1, v, storage(true)), entry(2, v, storage(true)), entry(3, vf, storage(true))],
        });
        let cull_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("grass cull layout"),
            entries: &[
                entry(0, c, uniform),
                entry(1, c, storage(true)),
                entry(2, c, storage(false)),
                entry(3, c, storage(false)),
                entry(4, c, storage(false)),
                entry(5, c, float_texture()),
                entry(6, c, filtering),
                entry(7, c, uniform),
                entry(8, c, wgpu::BindingType::Texture { sample_type: wgpu::TextureSampleType::Float { filterable: true }, view_dimension: wgpu::TextureViewDimension::Cube, multisampled: false }),
            ],
        });
        let cull_module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some("cull.wgsl"), source: wgpu::ShaderSource::Wgsl(crate::render::shader::compose(include_str!("cull.wgsl"), &[("grass_constants", &data::shader_constants())]).into()) });
        let cull_layout = shared.layout("grass cull pipeline layout", &[Some(&cull_group_layout)]);
        // The general pipeline and the one specialised to blocks of far blades (blocks.rs).
        let cull_pipelines = [("grass cull pipeline", 0.0), ("grass cull pipeline (far blocks)", 1.0)].map(|(label, far_only)| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(label),
                layout: Some(&cull_layout),
                module: &cull_module,
                entry_point: Some("cs_cull"),
                compilation_options: wgpu::PipelineCompilationOptions { constants: &[("FAR_ONLY", far_only)], ..Default::default() },
                cache: None,
            })
        });
        let order_pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("grass order pipeline"),
            layout: Some(&cull_layout),
            module: &cull_module,
            entry_point: Some("cs_order"),
            compilation_options: Default::default(),
            cache: None,
        });
        let sampler = |label, filter, address| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: address,
                address_mode_v: address,
                mag_filter: filter,
                min_filter: filter,
                ..Default::default()
            })
        };
        Grass {
            shell_module: shared.shader("shells.wgsl", include_str!("shells.wgsl")),
            blade_module: shared.shader_with("blades.wgsl", include_str!("blades.wgsl"), &[("grass_constants", &data::shader_constants())]),
            shell_layout: shared.layout("grass shell pipeline layout", &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&shell_group_layout)]),
            blade_layout: shared.layout("grass blade pipeline layout", &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&blade_group_layout)]),
            shell_group_layout,
            blade_group_layout,
            cull_group_layout,
            cull_pipelines,
            order_pipeline,
            shell_pipelines: PipelineCache::new("grass shells"),
            blade_pipelines: PipelineCache::new("grass blades"),
            strand_tex: data::strand_texture(device, &shared.queue),
            wind_tex: data::wind_texture(device, &shared.queue),
            nearest: sampler("grass strand sampler", wgpu::FilterMode::Nearest, wgpu::AddressMode::Repeat),
            linear: sampler("grass wind sampler", wgpu::FilterMode::Linear, wgpu::AddressMode::Repeat),
            irradiance: irradiance.clone(),
            key: GrassKey::default(),
            shells: Vec::new(),
            blades: None,
            enabled: true,
            shared: shared.clone(),
        }
    }
}

/// The shells' pipeline of `key`: opaque but along the lawn's edge (the fragment blends the
/// layers itself), depth written, main view only.
pub(super) fn build_shells(shared: &Shared, module: &wgpu::ShaderModule, layout: &wgpu::PipelineLayout, key: PipelineKey) -> Result<wgpu::RenderPipeline, PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("grass"));
    }
    const SV: [wgpu::VertexAttribute; 4] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Float32];
    // Blended over the ground only along the lawn's edge ([`edges`]): alpha is 1 elsewhere.
    let targets = [Some(wgpu::ColorTargetState { format: key.format, blend: Some(wgpu::BlendState::ALPHA_BLENDING), write_mask: wgpu::ColorWrites::ALL })];
    Ok(shared.pipeline(&PipelineSpec {
        label: "grass shell pipeline",
        layout,
        module,
        vertex: "vs_main",
        fragment: Some("fs_main"),
        buffers: &[Some(wgpu::VertexBufferLayout { array_stride: 44, step_mode: wgpu::VertexStepMode::Vertex, attributes: &SV })],
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull: None,
        depth: depth_test(true, wgpu::CompareFunction::Less),
        targets: &targets,
        constants: &key.lit_constants(),
    }))
}

/// The blades' pipelines of `key` (near, middle, and the far blades' rectangle,
/// which writes the depth of each pixel it keeps): main view only.
pub(super) fn build_blades(shared: &Shared, module: &wgpu::ShaderModule, layout: &wgpu::PipelineLayout, key: PipelineKey) -> Result<[wgpu::RenderPipeline; 3], PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("grass"));
    }
    let targets = crate::render::gpu::color_target(key.format, wgpu::ColorWrites::ALL);
    let constants = key.lit_constants();
    let one = |label, vertex, fragment| {
        shared.pipeline(&PipelineSpec {
            label,
            layout,
            module,
            vertex,
            fragment: Some(fragment),
            buffers: &[],
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: None,
            depth: depth_test(true, wgpu::CompareFunction::Less),
            targets: &targets,
            constants: &constants,
        })
    };
    Ok([one("grass blade pipeline (near)", "vs_near", "fs_main"), one("grass blade pipeline (middle)", "vs_mid", "fs_lit"), one("grass blade pipeline (far)", "vs_far", "fs_far")])
}
