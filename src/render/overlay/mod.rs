//! Overlay: the interaction visuals (controller and ray, hit marker, anchor ball, selection box
//! and handles, task targets) as triangles and lines rebuilt every frame ([`geometry`]), drawn
//! last, in [`Phase::Overlay`].

pub mod controller;
pub mod extract;
pub mod geometry;

use crate::render::error::{PipelineError, RenderError};
use wgpu::util::DeviceExt;

use self::controller::ControllerModel;
use self::geometry::{OverlayGhost, OverlayScene, OverlayVertex};
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind, color_target, depth_test};

/// The overlay's pipelines: triangles and lines.
pub(crate) struct OverlayPipelines {
    triangles: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
}

/// The overlay feature.
pub struct Overlay {
    /// Other participants' heads and rays drawn over the world from the next frame (a video's
    /// `--ghosts`); empty normally.
    pub ghosts: Vec<OverlayGhost>,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<OverlayPipelines>,
    /// This frame's triangles and their vertex count.
    triangles: Option<(wgpu::Buffer, u32)>,
    /// This frame's lines and their vertex count.
    lines: Option<(wgpu::Buffer, u32)>,
    /// The controller's model; `None` draws a box instead.
    controller: Option<ControllerModel>,
}

impl Overlay {
    /// The feature; the controller's model is loaded from the default assets folder (one
    /// line on stderr, and a box instead, when it cannot be).
    pub(crate) fn new(shared: &Shared) -> Overlay {
        let dir = controller::model_dir(&super::assets::default_assets_dir());
        let controller = ControllerModel::load(&dir)
            .inspect_err(|e| eprintln!("warning: the controller model did not load, a box stands in: {e}"))
            .ok();
        Overlay {
            module: shared.shader("overlay.wgsl", include_str!("overlay.wgsl")),
            layout: shared.layout("overlay layout", &[Some(&shared.view_layout)]),
            pipelines: PipelineCache::new("overlay"),
            triangles: None,
            lines: None,
            controller,
            ghosts: Vec::new(),
        }
    }
}

/// The overlay's pipelines of `key`: main view only.
fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> Result<OverlayPipelines, PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("the overlay"));
    }
    const OV: [wgpu::VertexAttribute; 3] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4, 2 => Float32x3];
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<OverlayVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &OV,
    })];
    let targets = color_target(key.format, wgpu::ColorWrites::ALL);
    let pipeline = |label, topology| {
        shared.pipeline(&PipelineSpec {
            label,
            layout,
            module,
            vertex: "vs_main",
            fragment: Some("fs_main"),
            buffers: &buffers,
            topology,
            cull: None,
            depth: depth_test(true, wgpu::CompareFunction::LessEqual),
            targets: &targets,
            constants: &[],
        })
    };
    Ok(OverlayPipelines {
        triangles: pipeline("overlay triangle pipeline", wgpu::PrimitiveTopology::TriangleList),
        lines: pipeline("overlay line pipeline", wgpu::PrimitiveTopology::LineList),
    })
}

impl Feature for Overlay {
    type Extracted = OverlayScene;

    /// The interaction visuals, the ghosts, and the eye at the camera drawn from (the head's,
    /// or a video's camera), so that markers keep their size as seen from it; a top view keeps
    /// the head's eye.
    fn extract(&self, sim: &grove_systems::Sim, cx: &ExtractContext<'_>) -> OverlayScene {
        let mut scene = extract::overlay_scene(sim);
        if cx.options.top_view.is_none() {
            scene.eye = cx.common.camera.position;
        }
        scene.ghosts.clone_from(&self.ghosts);
        scene
    }

    fn prepare(&mut self, cx: &FrameContext<'_>, scene: OverlayScene) -> Result<(), RenderError> {
        let g = geometry::build(&scene, self.controller.as_ref());
        let upload = |label, vertices: &[OverlayVertex]| {
            (!vertices.is_empty()).then(|| {
                let buffer = cx.shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytemuck::cast_slice(vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                });
                (buffer, vertices.len() as u32)
            })
        };
        self.triangles = upload("overlay triangles", &g.triangles);
        self.lines = upload("overlay lines", &g.lines);
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
        if phase != Phase::Overlay {
            return Ok(());
        }
        let p = self.pipelines.get(key)?;
        for (pipeline, geometry) in [(&p.triangles, &self.triangles), (&p.lines, &self.lines)] {
            if let Some((buffer, count)) = geometry {
                pass.set_pipeline(pipeline);
                pass.set_vertex_buffer(0, buffer.slice(..));
                pass.draw(0..*count, 0..1);
                stats.draws += 1;
            }
        }
        Ok(())
    }
}
