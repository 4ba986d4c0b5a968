//! Water: ponds drawn after Fukuda et al. (2007). Before the main pass the frame draws the scene
//! twice more at half resolution: from the camera mirrored in the water plane and clipped at it
//! (the reflection: trees, ground and sky, so the sky's cubemap shows where nothing else is), and
//! from the camera with only what lies below the plane (the refraction, with its depth). The
//! surface ([`WaterFeature::draw`], `water.wgsl`, in the main pass's opaque phase before the
//! ground, so that the bed under it is skipped by the depth test) mixes the two with Schlick's Fresnel term, shifted by two scrolling normal maps, tinted
//! and darkened with the depth of water along the view, with a sun glint and a soft shore.
//!
//! Each extra pass draws only the part of its target the surface can read ([`scissor`]: the
//! ponds' outlines projected by its camera, widened by the ripples' largest shift).
//!
//! The two extra passes draw the other features with the main view's pipelines (they differ only
//! in the view bound as group 0: [`mirror`] makes the matrices, clipping at the plane with an
//! oblique near plane), so no feature needs a pipeline of its own for them. One reflection plane
//! serves every pond: the first body's surface height.
//!
//! Units: metres, seconds; right-handed, +Y up.

mod extract;
pub(crate) mod mesh;
pub(crate) mod mirror;
pub(crate) mod scissor;

use crate::render::error::{PipelineError, RenderError};
use wgpu::util::DeviceExt;

use self::extract::WaterDraw;
use super::clip::ClipRegion;
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{
    DEPTH_FORMAT, PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind, color_target, depth_test, sampler_entry,
    texture_entry, uniform_entry,
};
use super::options::WaterOutput;
use super::view::{Camera, View, ViewUniform, Views};

/// How far past the plane the clipped cameras keep geometry, metres, so that nothing touching
/// the surface is cut a little short.
const CLIP_BIAS: f32 = 0.02;

/// The water's uniforms (matches `WaterParams` in water.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct WaterParams {
    reflection_view_proj: [[f32; 4]; 4],
    refraction_inv_view_proj: [[f32; 4]; 4],
    misc: [f32; 4],
}

/// The half-resolution textures of the two extra passes and the surface's bind group over them.
struct Targets {
    size: (u32, u32),
    format: wgpu::TextureFormat,
    reflection: wgpu::TextureView,
    reflection_depth: wgpu::TextureView,
    refraction: wgpu::TextureView,
    refraction_depth: wgpu::TextureView,
    bind_group: wgpu::BindGroup,
}

/// One extra pass for the frame to draw: where, from which view, and whether with the sky.
pub(crate) struct WaterPass<'a> {
    /// The pass's name (its timestamp scope).
    pub label: &'static str,
    /// The colour target.
    pub color: &'a wgpu::TextureView,
    /// The depth target.
    pub depth: &'a wgpu::TextureView,
    /// Group 0 of the pass.
    pub view: &'a wgpu::BindGroup,
    /// Whether the sky is drawn (the reflection) or not (the refraction, cleared to black).
    pub sky: bool,
    /// The part of the target the surface can read ([`scissor::rect`]), the pass's scissor;
    /// `None`: the whole target.
    pub scissor: Option<scissor::Rect>,
}

/// The water feature.
pub(crate) struct WaterFeature {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    group_layout: wgpu::BindGroupLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
    normal_map: wgpu::TextureView,
    clamp_sampler: wgpu::Sampler,
    params: wgpu::Buffer,
    /// The bodies `mesh` was built from.
    bodies: Vec<WaterDraw>,
    mesh: Option<(wgpu::Buffer, u32)>,
    targets: Option<Targets>,
    reflection_view: View,
    refraction_view: View,
    /// Whether this frame draws water (asked for, and a mesh to draw).
    active: bool,
    /// This frame's scissors of the reflection and refraction passes.
    scissors: [Option<scissor::Rect>; 2],
    /// This frame's regions of the reflection and refraction passes (their views within their
    /// scissors); empty when no water is drawn.
    regions: Vec<ClipRegion>,
}

impl WaterFeature {
    /// The feature: its shader, layouts, ripple texture and two views sharing `views`' wind.
    pub fn new(shared: &Shared, views: &Views) -> WaterFeature {
        let device = &shared.device;
        let float_tex = wgpu::TextureSampleType::Float { filterable: true };
        let d2 = wgpu::TextureViewDimension::D2;
        let group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("water layout"),
            entries: &[
                uniform_entry(0),
                texture_entry(1, d2, float_tex),
                texture_entry(2, d2, float_tex),
                texture_entry(3, d2, wgpu::TextureSampleType::Depth),
                texture_entry(4, d2, float_tex),
                sampler_entry(5, wgpu::SamplerBindingType::Filtering),
                sampler_entry(6, wgpu::SamplerBindingType::Filtering),
            ],
        });
        let n = mesh::NORMAL_MAP_SIZE;
        let normal_map = super::assets::textures::upload_2d(
            device,
            &shared.queue,
            "water normal map",
            n,
            n,
            &mesh::normal_map(),
            false,
        );
        let clamp_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("water clamp sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("water parameters"),
            contents: bytemuck::bytes_of(&WaterParams {
                reflection_view_proj: [[0.0; 4]; 4],
                refraction_inv_view_proj: [[0.0; 4]; 4],
                misc: [0.0; 4],
            }),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        WaterFeature {
            module: shared.shader("water.wgsl", include_str!("water.wgsl")),
            layout: shared.layout(
                "water pipeline layout",
                &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&group_layout)],
            ),
            group_layout,
            pipelines: PipelineCache::new("water"),
            normal_map,
            clamp_sampler,
            params,
            bodies: Vec::new(),
            mesh: None,
            targets: None,
            reflection_view: views.extra(shared, "water reflection view"),
            refraction_view: views.extra(shared, "water refraction view"),
            active: false,
            scissors: [None; 2],
            regions: Vec::new(),
        }
    }

    /// The frame's two extra passes, reflection first; empty when no water is drawn.
    pub fn passes(&self) -> Vec<WaterPass<'_>> {
        let (true, Some(t)) = (self.active, &self.targets) else { return Vec::new() };
        vec![
            WaterPass {
                label: "reflection",
                color: &t.reflection,
                depth: &t.reflection_depth,
                view: &self.reflection_view.bind_group,
                sky: true,
                scissor: self.scissors[0],
            },
            WaterPass {
                label: "refraction",
                color: &t.refraction,
                depth: &t.refraction_depth,
                view: &self.refraction_view.bind_group,
                sky: false,
                scissor: self.scissors[1],
            },
        ]
    }

    /// The regions of [`WaterFeature::passes`], in the same order: what each pass can draw.
    pub fn regions(&self) -> &[ClipRegion] {
        &self.regions
    }

    /// Writes the two views and the surface's uniforms for this frame: `main` is the main view's
    /// uniform, `camera` the head's camera, `size` the main target's. Returns the reflection's
    /// and the refraction's view-projection matrices.
    fn write(
        &self,
        queue: &wgpu::Queue,
        main: &ViewUniform,
        camera: &Camera,
        size: (u32, u32),
        output: WaterOutput,
        plane: f32,
    ) -> [glam::Mat4; 2] {
        let aspect = size.0 as f32 / size.1.max(1) as f32;
        let refl = mirror::reflection(camera, aspect, plane, CLIP_BIAS);
        let refr = mirror::refraction(camera, aspect, plane, CLIP_BIAS);
        let view = |c: &mirror::WaterCamera| ViewUniform {
            view_proj: c.view_proj.to_cols_array_2d(),
            inv_view_proj: c.inv_view_proj.to_cols_array_2d(),
            camera_pos: c.eye.to_array(),
            ..*main
        };
        self.reflection_view.write(queue, &view(&refl));
        self.refraction_view.write(queue, &view(&refr));
        let mode = match output {
            WaterOutput::Full => 0.0,
            WaterOutput::Reflection => 1.0,
            WaterOutput::Refraction => 2.0,
        };
        let params = WaterParams {
            reflection_view_proj: refl.view_proj.to_cols_array_2d(),
            refraction_inv_view_proj: refr.view_proj.inverse().to_cols_array_2d(),
            misc: [mode, size.0 as f32, size.1 as f32, 0.0],
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        [refl.view_proj, refr.view_proj]
    }

    fn rebuild_mesh(&mut self, shared: &Shared, bodies: &[WaterDraw]) {
        self.bodies = bodies.to_vec();
        let verts = mesh::build(bodies);
        self.mesh = (!verts.is_empty()).then(|| {
            let buffer = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("water vertices"),
                contents: bytemuck::cast_slice(&verts),
                usage: wgpu::BufferUsages::VERTEX,
            });
            (buffer, verts.len() as u32)
        });
    }

    fn make_targets(&self, shared: &Shared, size: (u32, u32), format: wgpu::TextureFormat) -> Targets {
        let device = &shared.device;
        let texture = |label: &str, format| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let reflection = texture("water reflection", format);
        let reflection_depth = texture("water reflection depth", DEPTH_FORMAT);
        let refraction = texture("water refraction", format);
        let refraction_depth = texture("water refraction depth", DEPTH_FORMAT);
        let tex = wgpu::BindingResource::TextureView;
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("water bind group"),
            layout: &self.group_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: tex(&reflection) },
                wgpu::BindGroupEntry { binding: 2, resource: tex(&refraction) },
                wgpu::BindGroupEntry { binding: 3, resource: tex(&refraction_depth) },
                wgpu::BindGroupEntry { binding: 4, resource: tex(&self.normal_map) },
                wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::Sampler(&self.clamp_sampler) },
                wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::Sampler(&shared.material_sampler) },
            ],
        });
        Targets { size, format, reflection, reflection_depth, refraction, refraction_depth, bind_group }
    }
}

/// The surface's pipeline of `key`: main view only.
fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> Result<wgpu::RenderPipeline, PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("water"));
    }
    const ATTRS: [wgpu::VertexAttribute; 3] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4, 2 => Float32x2];
    Ok(shared.pipeline(&PipelineSpec {
        label: "water pipeline",
        layout,
        module,
        vertex: "vs_main",
        fragment: Some("fs_main"),
        buffers: &[Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<mesh::WaterVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &ATTRS,
        })],
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull: None,
        depth: depth_test(true, wgpu::CompareFunction::Less),
        targets: &color_target(key.format, wgpu::ColorWrites::ALL),
        constants: &[],
    }))
}

impl Feature for WaterFeature {
    /// The water bodies, sorted by entity.
    type Extracted = Vec<WaterDraw>;

    fn extract(&self, sim: &grove_systems::Sim, _cx: &ExtractContext<'_>) -> Vec<WaterDraw> {
        extract::water_bodies(sim)
    }

    fn prepare(&mut self, cx: &FrameContext<'_>, bodies: Vec<WaterDraw>) -> Result<(), RenderError> {
        self.active = false;
        self.regions.clear();
        if !cx.options.water || bodies.is_empty() {
            return Ok(());
        }
        if self.bodies != bodies {
            self.rebuild_mesh(cx.shared, &bodies);
        }
        if self.mesh.is_none() {
            return Ok(());
        }
        // Half the target's resolution, rounded up.
        let size = (cx.size.0.div_ceil(2).max(1), cx.size.1.div_ceil(2).max(1));
        if self.targets.as_ref().is_none_or(|t| t.size != size || t.format != cx.key.format) {
            self.targets = Some(self.make_targets(cx.shared, size, cx.key.format));
        }
        let (module, layout) = (&self.module, &self.layout);
        self.pipelines.prepare(cx.key, |k| build(cx.shared, module, layout, k))?;
        self.active = true;
        // Its views: the camera mirrored in the first body's surface, and the camera below it.
        let matrices = self.write(
            &cx.shared.queue,
            &cx.views.main,
            &cx.common.camera,
            cx.size,
            cx.options.water_output,
            bodies[0].height,
        );
        self.scissors = matrices.map(|m| scissor::rect(m, &bodies, size));
        self.regions = (0..2).map(|i| ClipRegion::scissored(matrices[i], self.scissors[i], size)).collect();
        Ok(())
    }

    fn draw<'p>(
        &'p self,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        let (Phase::Opaque, true, Some((buffer, count)), Some(t)) = (phase, self.active, &self.mesh, &self.targets)
        else {
            return Ok(());
        };
        pass.set_pipeline(self.pipelines.get(key)?);
        pass.set_bind_group(2, &t.bind_group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..*count, 0..1);
        stats.draws += 1;
        stats.triangles += *count as usize / 3;
        Ok(())
    }
}
