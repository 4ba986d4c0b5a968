//! Sky: the environment cubemap seen through each pixel where nothing else was drawn, dimmed
//! with the sun's elevation, with a sun disc and glow. Drawn in [`Phase::Sky`], at the far
//! plane, after everything opaque.

use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind, color_target, depth_test};
use crate::render::error::{PipelineError, RenderError};

/// The sky feature.
pub(crate) struct Sky {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
}

impl Sky {
    /// The feature: one full-screen triangle.
    pub fn new(shared: &Shared) -> Sky {
        Sky {
            module: shared.shader("sky.wgsl", include_str!("sky.wgsl")),
            layout: shared.layout("sky layout", &[Some(&shared.view_layout), Some(&shared.lighting_layout)]),
            pipelines: PipelineCache::new("sky"),
        }
    }
}

/// The sky's pipeline of `key`: main view only; the shadow and wind choices do not change it.
fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> Result<wgpu::RenderPipeline, PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("the sky"));
    }
    Ok(shared.pipeline(&PipelineSpec {
        label: "sky pipeline",
        layout,
        module,
        vertex: "vs_main",
        fragment: Some("fs_main"),
        buffers: &[],
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull: None,
        // Drawn at the far plane: only where nothing else was drawn.
        depth: depth_test(false, wgpu::CompareFunction::LessEqual),
        targets: &color_target(key.format, wgpu::ColorWrites::ALL),
        constants: &[],
    }))
}

impl Feature for Sky {
    /// The sky draws the environment: nothing of the world.
    type Extracted = ();

    fn extract(&self, _sim: &grove_systems::Sim, _cx: &ExtractContext<'_>) {}

    fn prepare(&mut self, cx: &FrameContext<'_>, _data: ()) -> Result<(), RenderError> {
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
        if phase == Phase::Sky {
            pass.set_pipeline(self.pipelines.get(key)?);
            pass.draw(0..3, 0..1);
            stats.draws += 1;
        }
        Ok(())
    }
}
