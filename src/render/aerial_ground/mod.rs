//! The aerial ground (issue #22): the winter photograph, read from its clipmap, draped flat over
//! the photographed rectangle at the ground's height, lit by the sun and receiving shadows. It
//! is drawn before the ordinary ground, a little above it, so the ground is hidden where the
//! photograph lies; where no level of the clipmap has a texel yet the fragment is discarded and
//! the ground shows. A shadow receiver only.
//!
//! [`AerialSources`] is what an app hands the renderer ([`AerialPhotos::set`]): the clipmap
//! sources of the pair and of the canopy's layer masks.

pub mod open;
mod photos;
pub use photos::AerialPhotos;

use crate::render::error::{PipelineError, RenderError};
use glam::Vec2;
use wgpu::util::DeviceExt;

use super::clipmap::{ClipmapSource, FedClipmap, GpuClipmap, clip_camera};
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind, color_target, depth_test};

/// How far above the ground the photograph lies, metres: with the depth bias of its pipeline,
/// enough for it to hide the ground at the same height.
pub const LIFT_M: f32 = 0.02;

/// The photographs of a scene as clipmap sources, for [`AerialPhotos::set`].
pub struct AerialSources {
    /// The winter photograph: the ground.
    pub winter: Box<dyn ClipmapSource>,
    /// The summer photograph: the canopy's colours.
    pub summer: Box<dyn ClipmapSource>,
    /// The layer masks (bit i of the red byte: layer i is treetop); without them no canopy.
    pub layers: Option<Box<dyn ClipmapSource>>,
    /// The layer masks' bits in memory, for the canopy's per-layer quad sizes (optional: without
    /// them every layer's quad is as wide as the crown's).
    pub layer_bits: Option<super::canopy::extents::LayerBits>,
    /// The photographed rectangle's size, metres (east, south), from the sources' origin.
    pub size_m: Vec2,
    /// The ground's height, metres.
    pub elevation_m: f32,
    /// The canopy's layers, 1..=8.
    pub layer_count: u32,
    /// Colour the clipmap levels (`--debug-lod`).
    pub debug_lod: bool,
}

/// The aerial ground's uniforms (matches `AerialGroundParams` in aerial_ground.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    lo: [f32; 2],
    hi: [f32; 2],
    height: f32,
    pad: [f32; 3],
}

/// The aerial ground feature.
pub(crate) struct AerialGround {
    /// The winter clipmap.
    pub winter: FedClipmap,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
    bind_group: wgpu::BindGroup,
}

impl AerialGround {
    /// The feature for a winter clipmap over `size_m` metres at `elevation_m`.
    pub fn new(shared: &Shared, winter: FedClipmap, size_m: Vec2, elevation_m: f32) -> AerialGround {
        let o = winter.source.placement().origin_m.as_vec2();
        let (lo, hi) = (o, o + size_m);
        let params = Params { lo: lo.to_array(), hi: hi.to_array(), height: elevation_m + LIFT_M, pad: [0.0; 3] };
        let buffer = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("aerial ground parameters"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let [a, b, c] = GpuClipmap::layout_entries(0);
        let group = shared.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("aerial ground layout"),
            entries: &[a, b, c, super::gpu::uniform_entry(3)],
        });
        let [e0, e1, e2] = winter.gpu.bind_entries(0);
        let bind_group = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("aerial ground bind group"),
            layout: &group,
            entries: &[e0, e1, e2, wgpu::BindGroupEntry { binding: 3, resource: buffer.as_entire_binding() }],
        });
        AerialGround {
            module: shared.shader("aerial_ground.wgsl", include_str!("aerial_ground.wgsl")),
            layout: shared.layout(
                "aerial ground layout",
                &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&group)],
            ),
            pipelines: PipelineCache::new("aerial ground"),
            bind_group,
            winter,
        }
    }
}

/// The aerial ground's pipeline of `key`: main view only, pulled towards the eye by a depth bias.
fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> Result<wgpu::RenderPipeline, PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("the aerial ground"));
    }
    let depth = wgpu::DepthStencilState {
        bias: wgpu::DepthBiasState { constant: -4, slope_scale: -1.0, clamp: 0.0 },
        ..depth_test(true, wgpu::CompareFunction::Less)
    };
    Ok(shared.pipeline(&PipelineSpec {
        label: "aerial ground pipeline",
        layout,
        module,
        vertex: "vs_main",
        fragment: Some("fs_main"),
        buffers: &[],
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull: None,
        depth,
        targets: &color_target(key.format, wgpu::ColorWrites::ALL),
        constants: &key.lit_constants(),
    }))
}

impl Feature for AerialGround {
    /// The photograph is the feature's own: it reads nothing of the world.
    type Extracted = ();

    fn extract(&self, _sim: &grove_systems::Sim, _cx: &ExtractContext<'_>) {}

    fn prepare(&mut self, cx: &FrameContext<'_>, _data: ()) -> Result<(), RenderError> {
        self.winter.update(&cx.shared.queue, &clip_camera(&cx.common.camera, cx.size))?;
        let (module, layout) = (&self.module, &self.layout);
        Ok(self.pipelines.prepare(cx.key, |k| build(cx.shared, module, layout, k))?)
    }

    fn draw<'p>(
        &'p self,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        if phase != Phase::Opaque {
            return Ok(());
        }
        pass.set_pipeline(self.pipelines.get(key)?);
        pass.set_bind_group(2, &self.bind_group, &[]);
        pass.draw(0..6, 0..1);
        stats.draws += 1;
        stats.triangles += 2;
        Ok(())
    }
}
