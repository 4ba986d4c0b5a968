//! The tree pipelines of one [`PipelineKey`].
//!
//! Opaque materials are shaded in one step with the usual depth test. Alpha-clipped materials
//! take two: a depth pre-pass that only samples the albedo's alpha and discards clipped texels,
//! then a shading pass that tests for equal depth and never discards. Without the pre-pass, a
//! shader that may discard cannot write depth before it has run, so every layer of leaves in a
//! crown would be fully shaded; with it, each pixel is shaded once. Both passes mark the clip
//! position `@invariant`, so their depths agree exactly.

use crate::render::error::PipelineError;
use crate::render::gpu::{PipelineKey, PipelineSpec, SHADOW_FORMAT, Shared, ViewKind, color_target, depth_test};

use super::instances::Instance;

/// The pipelines of the main view, indexed by `double_sided as usize` (back faces culled at 0).
pub(crate) struct MainPipelines {
    /// Opaque materials.
    pub opaque: [wgpu::RenderPipeline; 2],
    /// The depth pre-pass of alpha-clipped materials.
    pub masked_depth: [wgpu::RenderPipeline; 2],
    /// The shading of alpha-clipped materials, at equal depth.
    pub masked_shade: [wgpu::RenderPipeline; 2],
}

/// The pipelines of the sun's view: depth only for opaque materials, alpha-tested for masked
/// ones, both sides (leaves and thin branches cast from both sides).
pub(crate) struct ShadowPipelines {
    /// Opaque materials.
    pub opaque: wgpu::RenderPipeline,
    /// Alpha-clipped materials.
    pub masked: wgpu::RenderPipeline,
}

/// The pipelines of one key: the main view's or the sun's.
pub(crate) enum TreePipelines {
    /// For the main pass.
    Main(MainPipelines),
    /// For the shadow map.
    Shadow(ShadowPipelines),
}

/// The vertex buffers: 0 the model's vertices, 1 the instances, 2 the leaves (see `lod`).
fn vertex_layout() -> [Option<wgpu::VertexBufferLayout<'static>>; 3] {
    const V: [wgpu::VertexAttribute; 6] = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4, 4 => Float32x4, 14 => Unorm8x4];
    const I: [wgpu::VertexAttribute; 9] = wgpu::vertex_attr_array![
        5 => Float32x3, 6 => Float32, 7 => Float32, 8 => Float32x2, 9 => Float32, 10 => Float32, 11 => Float32, 13 => Float32, 15 => Float32
    ];
    const L: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![12 => Float32x4];
    [
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<crate::models::Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &V,
        }),
        Some(wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Instance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &I,
        }),
        Some(wgpu::VertexBufferLayout { array_stride: 16, step_mode: wgpu::VertexStepMode::Vertex, attributes: &L }),
    ]
}

/// Builds the pipelines of `key` from the tree shader and the lit and shadow layouts.
pub(crate) fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    lit_layout: &wgpu::PipelineLayout,
    shadow_layout: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> Result<TreePipelines, PipelineError> {
    let buffers = vertex_layout();
    let constants = key.tree_constants();
    // Depth-only pipelines do not shade, so their shadow constant is moot.
    let depth_constants = PipelineKey { shadows: false, ..key }.tree_constants();
    let pipeline = |label: &str,
                    layout,
                    two_sided: bool,
                    (vertex, fragment): (&str, Option<&str>),
                    depth,
                    targets: &[Option<wgpu::ColorTargetState>],
                    constants: &[(&str, f64)]| {
        let sides = if two_sided { "two-sided" } else { "one-sided" };
        shared.pipeline(&PipelineSpec {
            label: &format!("tree {label} pipeline ({sides}, {key:?})"),
            layout,
            module,
            vertex,
            fragment,
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: if two_sided { None } else { Some(wgpu::Face::Back) },
            depth,
            targets,
            constants,
        })
    };
    match key.view {
        ViewKind::Main => {
            let color = color_target(key.format, wgpu::ColorWrites::ALL);
            let no_color = color_target(key.format, wgpu::ColorWrites::empty());
            let less = depth_test(true, wgpu::CompareFunction::Less);
            let equal = depth_test(false, wgpu::CompareFunction::Equal);
            let both = |label: &str,
                        stages,
                        depth: &wgpu::DepthStencilState,
                        targets: &[Option<wgpu::ColorTargetState>],
                        constants: &[(&str, f64)]| {
                [false, true]
                    .map(|two_sided| pipeline(label, lit_layout, two_sided, stages, depth.clone(), targets, constants))
            };
            Ok(TreePipelines::Main(MainPipelines {
                opaque: both("opaque", ("vs_main", Some("fs_main")), &less, &color, &constants),
                masked_depth: both(
                    "depth pre-pass",
                    ("vs_depth", Some("fs_alpha_test")),
                    &less,
                    &no_color,
                    &depth_constants,
                ),
                masked_shade: both("alpha-clipped", ("vs_main", Some("fs_main")), &equal, &color, &constants),
            }))
        }
        ViewKind::Sun => {
            let depth = wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 },
                ..depth_test(true, wgpu::CompareFunction::Less)
            };
            Ok(TreePipelines::Shadow(ShadowPipelines {
                opaque: pipeline(
                    "shadow (opaque)",
                    shadow_layout,
                    true,
                    ("vs_depth", None),
                    depth.clone(),
                    &[],
                    &depth_constants,
                ),
                masked: pipeline(
                    "shadow (alpha-clipped)",
                    shadow_layout,
                    true,
                    ("vs_depth", Some("fs_alpha_test")),
                    depth,
                    &[],
                    &depth_constants,
                ),
            }))
        }
    }
}
