//! What every feature shares: the device and queue, the bind group layouts of the frame, the
//! lighting and the materials, the samplers, the 1×1 fallback textures, the pipeline key and one
//! helper that builds a render pipeline.
//!
//! Bind groups, the same for every feature: group 0 is the view ([`super::view`]: its uniforms
//! and the wind parameters), group 1 the lighting ([`super::lighting`]: shadow map and
//! environment), group 2 the feature's own material.

use std::collections::HashMap;

use super::assets::textures;
use super::error::PipelineError;
pub use super::key::{PipelineKey, ViewKind};

/// Depth format of the main pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Depth format of the shadow map.
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth16Unorm;

/// The device, the queue and the resources every feature binds.
#[derive(Clone)]
pub(crate) struct Shared {
    /// The device.
    pub device: wgpu::Device,
    /// The queue.
    pub queue: wgpu::Queue,
    /// Group 0: binding 0 the view uniforms, binding 1 the wind parameters.
    pub view_layout: wgpu::BindGroupLayout,
    /// Group 1: the shadow map, its comparison sampler, the environment and irradiance cubes and
    /// their sampler.
    pub lighting_layout: wgpu::BindGroupLayout,
    /// Group 2: a material's uniforms, albedo, normal and specular textures and sampler.
    pub material_layout: wgpu::BindGroupLayout,
    /// Trilinear, repeating: material textures.
    pub material_sampler: wgpu::Sampler,
    /// A white sRGB texel, for materials without an albedo or specular map.
    pub white: wgpu::TextureView,
    /// A flat tangent-space normal, for materials without a normal map.
    pub flat_normal: wgpu::TextureView,
}

impl Shared {
    /// The shared layouts, sampler and fallback textures on `device`.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Shared {
        let view_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("view layout"),
            entries: &[uniform_entry(0), uniform_entry(1)],
        });
        let float_tex = wgpu::TextureSampleType::Float { filterable: true };
        let cube = wgpu::TextureViewDimension::Cube;
        let lighting_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lighting layout"),
            entries: &[
                // The middle grass blades look up the shadow per vertex.
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..texture_entry(0, wgpu::TextureViewDimension::D2, wgpu::TextureSampleType::Depth)
                },
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..sampler_entry(1, wgpu::SamplerBindingType::Comparison)
                },
                // The ground and the grass shells look up the aerial perspective's haze per vertex.
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..texture_entry(2, cube, float_tex)
                },
                // The ground looks up the irradiance per vertex.
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..texture_entry(3, cube, float_tex)
                },
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
                    ..sampler_entry(4, wgpu::SamplerBindingType::Filtering)
                },
            ],
        });
        let d2 = wgpu::TextureViewDimension::D2;
        let material_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("material layout"),
            entries: &[
                uniform_entry(0),
                texture_entry(1, d2, float_tex),
                texture_entry(2, d2, float_tex),
                texture_entry(3, d2, float_tex),
                sampler_entry(4, wgpu::SamplerBindingType::Filtering),
            ],
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
        let white = textures::solid(device, queue, "white 1x1", [255, 255, 255, 255], true);
        let flat_normal = textures::solid(device, queue, "flat normal 1x1", textures::FLAT_NORMAL, false);
        Shared {
            device: device.clone(),
            queue: queue.clone(),
            view_layout,
            lighting_layout,
            material_layout,
            material_sampler,
            white,
            flat_normal,
        }
    }

    /// A shader module of `src` with the pieces it imports ([`super::shader::compose`]).
    pub fn shader(&self, label: &str, src: &str) -> wgpu::ShaderModule {
        self.shader_with(label, src, &[])
    }

    /// A shader module of `src` with the pieces it imports, among them `generated` ones (name,
    /// WGSL text written from Rust constants).
    pub fn shader_with(&self, label: &str, src: &str, generated: &[(&str, &str)]) -> wgpu::ShaderModule {
        self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(super::shader::compose(src, generated).into()),
        })
    }

    /// A pipeline layout of the given groups (`None` for a group the pipeline does not use).
    pub fn layout(&self, label: &str, groups: &[Option<&wgpu::BindGroupLayout>]) -> wgpu::PipelineLayout {
        self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: groups,
            immediate_size: 0,
        })
    }

    /// A material bind group: uniforms, albedo, normal map, specular map, the material sampler.
    pub fn material_bind_group(
        &self,
        label: &str,
        uniforms: &wgpu::Buffer,
        views: [&wgpu::TextureView; 3],
    ) -> wgpu::BindGroup {
        let [albedo, normal, spec] = views;
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &self.material_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: uniforms.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(albedo) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(normal) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(spec) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&self.material_sampler) },
            ],
        })
    }

    /// Builds a render pipeline from a [`PipelineSpec`]: the one place pipelines are made.
    pub fn pipeline(&self, spec: &PipelineSpec<'_>) -> wgpu::RenderPipeline {
        let compilation_options = wgpu::PipelineCompilationOptions { constants: spec.constants, ..Default::default() };
        self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(spec.label),
            layout: Some(spec.layout),
            vertex: wgpu::VertexState {
                module: spec.module,
                entry_point: Some(spec.vertex),
                compilation_options: compilation_options.clone(),
                buffers: spec.buffers,
            },
            primitive: wgpu::PrimitiveState { topology: spec.topology, cull_mode: spec.cull, ..Default::default() },
            depth_stencil: Some(spec.depth.clone()),
            multisample: Default::default(),
            fragment: spec.fragment.map(|fs| wgpu::FragmentState {
                module: spec.module,
                entry_point: Some(fs),
                compilation_options,
                targets: spec.targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// Everything that differs between two render pipelines of the renderer.
pub(crate) struct PipelineSpec<'a> {
    /// The debug label.
    pub label: &'a str,
    /// The pipeline layout.
    pub layout: &'a wgpu::PipelineLayout,
    /// The shader module.
    pub module: &'a wgpu::ShaderModule,
    /// The vertex entry point.
    pub vertex: &'a str,
    /// The fragment entry point; `None` for depth only.
    pub fragment: Option<&'a str>,
    /// The vertex buffer layouts.
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    /// The primitive topology.
    pub topology: wgpu::PrimitiveTopology,
    /// Which faces are culled.
    pub cull: Option<wgpu::Face>,
    /// The depth test.
    pub depth: wgpu::DepthStencilState,
    /// The colour targets.
    pub targets: &'a [Option<wgpu::ColorTargetState>],
    /// The values of the shader's `override` constants.
    pub constants: &'a [(&'a str, f64)],
}

/// A depth test on the main pass's depth buffer.
pub(crate) fn depth_test(write: bool, compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(write),
        depth_compare: Some(compare),
        stencil: wgpu::StencilState::default(),
        bias: Default::default(),
    }
}

/// One colour target of `format`, unblended, writing `mask`.
pub(crate) fn color_target(
    format: wgpu::TextureFormat,
    mask: wgpu::ColorWrites,
) -> [Option<wgpu::ColorTargetState>; 1] {
    [Some(wgpu::ColorTargetState { format, blend: None, write_mask: mask })]
}

/// A feature's pipelines by key, built on first use.
pub(crate) struct PipelineCache<T> {
    /// The feature's name, for errors.
    feature: &'static str,
    built: HashMap<PipelineKey, T>,
}

impl<T> PipelineCache<T> {
    /// An empty cache of `feature`'s pipelines.
    pub fn new(feature: &'static str) -> PipelineCache<T> {
        PipelineCache { feature, built: HashMap::new() }
    }

    /// Builds the pipelines of `key` unless they exist. `build` fails for a key the feature
    /// does not support; the error names the feature and the key.
    pub fn prepare(
        &mut self,
        key: PipelineKey,
        build: impl FnOnce(PipelineKey) -> Result<T, PipelineError>,
    ) -> Result<(), PipelineError> {
        if !self.built.contains_key(&key) {
            let value =
                build(key).map_err(|e| PipelineError::Refused { feature: self.feature, key, reason: Box::new(e) })?;
            self.built.insert(key, value);
        }
        Ok(())
    }

    /// The pipelines of `key`; an error when they were never prepared.
    pub fn get(&self, key: PipelineKey) -> Result<&T, PipelineError> {
        self.built.get(&key).ok_or(PipelineError::NotPrepared { feature: self.feature, key })
    }
}

/// A uniform buffer binding, seen by the vertex and fragment stages.
pub(crate) fn uniform_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
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

/// A texture binding, seen by the fragment stage.
pub(crate) fn texture_entry(
    binding: u32,
    dim: wgpu::TextureViewDimension,
    sample: wgpu::TextureSampleType,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture { sample_type: sample, view_dimension: dim, multisampled: false },
        count: None,
    }
}

/// A sampler binding, seen by the fragment stage.
pub(crate) fn sampler_entry(binding: u32, ty: wgpu::SamplerBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(ty),
        count: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use grove_systems::wind_model::WindModel;

    fn key(view: ViewKind) -> PipelineKey {
        PipelineKey { shadows: true, wind: WindModel::Noise, format: wgpu::TextureFormat::Rgba8UnormSrgb, view }
    }

    #[test]
    fn an_unprepared_or_refused_key_is_an_error() {
        let mut cache: PipelineCache<u32> = PipelineCache::new("test feature");
        let err = cache.get(key(ViewKind::Main)).unwrap_err().to_string();
        assert!(err.contains("test feature") && err.contains("Main"), "{err}");
        let err = cache
            .prepare(key(ViewKind::Sun), |_| Err(PipelineError::MainViewOnly("the test")))
            .unwrap_err()
            .to_string();
        assert!(err.contains("test feature") && err.contains("Sun") && err.contains("main view only"), "{err}");
        assert!(cache.get(key(ViewKind::Sun)).is_err());
    }

    #[test]
    fn pipelines_are_built_once_per_key() {
        let mut cache: PipelineCache<u32> = PipelineCache::new("test feature");
        let mut builds = 0;
        for _ in 0..3 {
            cache
                .prepare(key(ViewKind::Main), |_| {
                    builds += 1;
                    Ok(7)
                })
                .unwrap();
        }
        assert_eq!(builds, 1);
        assert_eq!(*cache.get(key(ViewKind::Main)).unwrap(), 7);
        // Another wind model is another key.
        let other = PipelineKey { wind: WindModel::Hierarchical, ..key(ViewKind::Main) };
        assert!(cache.get(other).is_err());
    }

    #[test]
    fn the_wind_constant_is_the_models_code() {
        let k = PipelineKey { shadows: false, ..key(ViewKind::Main) };
        assert_eq!(k.tree_constants(), [("SHADOWS", 0.0), ("WIND_MODEL", 0.0)]);
        let k = PipelineKey { wind: WindModel::Hierarchical, ..key(ViewKind::Main) };
        assert_eq!(k.tree_constants(), [("SHADOWS", 1.0), ("WIND_MODEL", 1.0)]);
    }
}
