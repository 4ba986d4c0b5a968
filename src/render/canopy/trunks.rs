//! The trunks under the canopy (issue #22: "trunks at the crown centres"): a tapered six-sided
//! prism under each photographed crown's tree, from its foot to a little into the crown, drawn
//! in one instanced draw with the crowns the canopy draws this frame, and casting shadows (one
//! more instanced draw into the sun's depth). Part of the canopy feature
//! ([`super::Canopy`]): it has no field or stage of its own in the frame.

use crate::render::error::{PipelineError, RenderError};
use wgpu::util::DeviceExt;

use super::super::gpu::{
    PipelineCache, PipelineKey, PipelineSpec, SHADOW_FORMAT, Shared, ViewKind, color_target, depth_test,
};
use super::extract::CrownDraw;

/// One trunk instance: the tree's foot (world metres), the trunk's radius at the foot, its
/// height over the foot and padding (matches `TrunkIn` in trunks.wgsl).
pub(crate) type TrunkInstance = [f32; 8];

/// Triangles per trunk: six sides of two.
pub(crate) const TRIANGLES: u32 = 12;

/// How far into the crown the trunk reaches, as a share of the crown's depth (top − base).
const INTO_CROWN: f32 = 0.3;

/// The trunk's radius at the foot as a share of the crown's radius, and its bounds, metres.
const RADIUS_SHARE: f32 = 0.07;
const RADIUS_MIN_M: f32 = 0.08;
const RADIUS_MAX_M: f32 = 0.6;

/// The trunk of a crown's tree: at its foot, `RADIUS_SHARE` of the crown's radius wide (within
/// 0.08..=0.6 m) and reaching `INTO_CROWN` of the crown's depth above its base, so its top is
/// hidden among the layers.
pub(crate) fn trunk_instance(c: &CrownDraw) -> TrunkInstance {
    let radius = (c.radius_m * RADIUS_SHARE).clamp(RADIUS_MIN_M, RADIUS_MAX_M);
    let height = c.base_m + INTO_CROWN * (c.top_m - c.base_m).max(0.0);
    [c.foot.x, c.foot.y, c.foot.z, radius, height, 0.0, 0.0, 0.0]
}

/// The trunks' pipelines of one key.
enum Pipelines {
    /// Lit and shadowed, depth-tested and written.
    Main(wgpu::RenderPipeline),
    /// The sun's depth.
    Shadow(wgpu::RenderPipeline),
}

/// The trunks of the crowns drawn this frame.
pub(crate) struct Trunks {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    shadow_layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<Pipelines>,
    instances: Option<(wgpu::Buffer, u32)>,
}

impl Trunks {
    /// The trunks' shader and layouts.
    pub fn new(shared: &Shared) -> Trunks {
        Trunks {
            module: shared.shader("trunks.wgsl", include_str!("trunks.wgsl")),
            layout: shared.layout("trunks layout", &[Some(&shared.view_layout), Some(&shared.lighting_layout)]),
            shadow_layout: shared.layout("trunks shadow layout", &[Some(&shared.view_layout)]),
            pipelines: PipelineCache::new("trunks"),
            instances: None,
        }
    }

    /// Uploads the trunks of `crowns` and builds the pipelines of `keys` on first use.
    pub fn prepare(&mut self, shared: &Shared, crowns: &[CrownDraw], keys: &[PipelineKey]) -> Result<(), RenderError> {
        let trunks: Vec<TrunkInstance> = crowns.iter().map(trunk_instance).collect();
        self.instances = (!trunks.is_empty()).then(|| {
            let buffer = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("trunks"),
                contents: bytemuck::cast_slice(&trunks),
                usage: wgpu::BufferUsages::VERTEX,
            });
            (buffer, trunks.len() as u32)
        });
        for &k in keys {
            let (module, layout, shadow_layout) = (&self.module, &self.layout, &self.shadow_layout);
            self.pipelines.prepare(k, |k| build(shared, module, layout, shadow_layout, k))?;
        }
        Ok(())
    }

    /// Draws the trunks' depth from the sun.
    pub fn draw_depth<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey) -> Result<(), RenderError> {
        let Some((buffer, n)) = &self.instances else { return Ok(()) };
        let Pipelines::Shadow(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NoShadowPipeline("trunks").into());
        };
        pass.set_pipeline(p);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..3 * TRIANGLES, 0..*n);
        Ok(())
    }

    /// Draws the trunks in the main view; the number of trunks drawn.
    pub fn draw<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey) -> Result<u32, RenderError> {
        let Some((buffer, n)) = &self.instances else { return Ok(0) };
        let Pipelines::Main(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NoMainPipeline("trunks").into());
        };
        pass.set_pipeline(p);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..3 * TRIANGLES, 0..*n);
        Ok(*n)
    }
}

/// The trunks' pipeline of `key`: lit for the main view, depth only for the sun's.
fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    shadow_layout: &wgpu::PipelineLayout,
    key: PipelineKey,
) -> Result<Pipelines, PipelineError> {
    const ATTRS: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4];
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: 32,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRS,
    })];
    let constants = key.lit_constants();
    Ok(match key.view {
        ViewKind::Main => Pipelines::Main(shared.pipeline(&PipelineSpec {
            label: "trunks pipeline",
            layout,
            module,
            vertex: "vs_main",
            fragment: Some("fs_main"),
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: Some(wgpu::Face::Back),
            depth: depth_test(true, wgpu::CompareFunction::Less),
            targets: &color_target(key.format, wgpu::ColorWrites::ALL),
            constants: &constants,
        })),
        ViewKind::Sun => Pipelines::Shadow(shared.pipeline(&PipelineSpec {
            label: "trunks shadow pipeline",
            layout: shadow_layout,
            module,
            vertex: "vs_main",
            fragment: None,
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: None,
            depth: wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 },
                ..depth_test(true, wgpu::CompareFunction::Less)
            },
            targets: &[],
            constants: &constants,
        })),
    })
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;

    #[test]
    fn a_trunk_stands_at_the_foot_and_reaches_into_the_crown() {
        // A crown 2 m wide in radius from 3.6 m to 6 m: the trunk is 0.14 m wide at the foot and
        // 3.6 + 0.3 · 2.4 = 4.32 m high.
        let c = CrownDraw {
            foot: Vec3::new(1.0, 0.5, -2.0),
            photo_centre: Vec2::new(9.0, 9.0),
            radius_m: 2.0,
            base_m: 3.6,
            top_m: 6.0,
        };
        let t = trunk_instance(&c);
        assert_eq!(t[..3], [1.0, 0.5, -2.0]);
        assert!((t[3] - 0.14).abs() < 1e-6 && (t[4] - 4.32).abs() < 1e-5, "{t:?}");
        // A tiny crown keeps a trunk 0.08 m wide and a huge one at most 0.6 m.
        let tiny = CrownDraw { radius_m: 0.3, base_m: 0.5, top_m: 0.9, ..c };
        assert!((trunk_instance(&tiny)[3] - 0.08).abs() < 1e-6);
        let huge = CrownDraw { radius_m: 30.0, ..c };
        assert!((trunk_instance(&huge)[3] - 0.6).abs() < 1e-6);
    }
}
