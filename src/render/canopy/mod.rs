//! The canopy (issue #22, after Ropinski et al. 2007): each photographed crown tree drawn as
//! stacked horizontal layers between its crown base and top, textured from the summer
//! photograph's clipmap where that layer's bit of the layer masks (`grove aerial layers`) says
//! treetop. Alpha-tested, lit by the sun, casting shadows (a depth pass with the same test).
//!
//! The layers stand at each crown tree's current position (it can be moved), and read the
//! photograph around the crown's photographed centre ([`grove_systems::aerial::AerialCrown`]).
//! One instance per (crown, layer), built each frame from the extracted crowns. Under each crown
//! stands a trunk ([`trunks`]), drawn and casting shadows with the layers.

pub(crate) mod trunks;

use wgpu::util::DeviceExt;

use super::aerial_ground::{clip_camera, FedClipmap};
use super::clipmap::{gpu::WGSL as CLIPMAP_WGSL, GpuClipmap};
use super::extract::CrownDraw;
use super::frame::{Feature, FrameContext, Phase};
use super::gpu::{color_target, depth_test, PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind, SHADOW_FORMAT};
use super::FrameStats;

/// The canopy's uniforms (matches `CanopyParams` in canopy.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    layer_count: f32,
    gsd_m: f32,
    pad: [f32; 2],
}

/// One layer instance: the tree's foot and crown radius; the photographed centre, the layer's
/// height over the foot and its index (matches `LayerIn` in canopy.wgsl).
pub(crate) type LayerInstance = [f32; 8];

/// The layer instances of `crowns` with `layers` layers each, layer by layer (every crown's
/// layer 0 first, so the lowest layers are the first `crowns.len()` instances): layer i at a
/// height from the crown base (i = 0) to its top (i = layers − 1), evenly spaced.
pub(crate) fn layer_instances(crowns: &[CrownDraw], layers: u32) -> Vec<LayerInstance> {
    let mut out = Vec::with_capacity(crowns.len() * layers as usize);
    for i in 0..layers {
        for c in crowns {
            let f = if layers > 1 { i as f32 / (layers - 1) as f32 } else { 1.0 };
            let h = c.base_m + (c.top_m - c.base_m) * f;
            out.push([c.foot.x, c.foot.y, c.foot.z, c.radius_m, c.photo_centre.x, c.photo_centre.y, h, i as f32]);
        }
    }
    out
}

/// Whether a crown's layers, or the shadows they cast nearby, may be seen through `view_proj`:
/// its bounding sphere, grown by twice its height for the shadows, against the frustum's planes.
pub(crate) fn in_view(view_proj: &glam::Mat4, c: &CrownDraw) -> bool {
    let centre = c.foot + glam::Vec3::Y * (0.5 * (c.base_m + c.top_m));
    let r = 1.8 * c.radius_m + 0.5 * (c.top_m - c.base_m) + 2.0 * c.top_m;
    let m = view_proj.transpose();
    let (x, y, z, w) = (m.x_axis, m.y_axis, m.z_axis, m.w_axis);
    // Left, right, bottom, top, near (depth 0..1) and far planes of a wgpu projection.
    [w + x, w - x, w + y, w - y, z, w - z].iter().all(|p| {
        let n = p.truncate();
        let len = n.length().max(1e-12);
        (n.dot(centre) + p.w) / len >= -r
    })
}

/// The canopy's pipelines of one key.
enum Pipelines {
    /// The depth pre-pass and the shading at equal depth.
    Main(wgpu::RenderPipeline, wgpu::RenderPipeline),
    /// The sun's depth.
    Shadow(wgpu::RenderPipeline),
}

/// The canopy feature.
pub(crate) struct Canopy {
    /// The summer photograph's clipmap.
    pub summer: FedClipmap,
    /// The layer masks' clipmap.
    pub masks: FedClipmap,
    layer_count: u32,
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    shadow_layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<Pipelines>,
    bind_group: wgpu::BindGroup,
    mask_bind_group: wgpu::BindGroup,
    instances: Option<(wgpu::Buffer, u32)>,
    /// The crowns drawn this frame: the shadow pass draws only their lowest, widest layer, whose
    /// outline holds the upper layers' (their masks' k is larger), at a sixth of the cost.
    crowns_drawn: u32,
    /// The bounds of the layers drawn this frame, for the shadow map's fit.
    pub bounds: Option<(glam::Vec3, glam::Vec3)>,
    /// The trunks under the crowns drawn this frame.
    trunks: trunks::Trunks,
}

impl Canopy {
    /// The feature over the summer and layer-mask clipmaps with `layer_count` layers.
    pub fn new(shared: &Shared, summer: FedClipmap, masks: FedClipmap, layer_count: u32) -> Canopy {
        let gsd = summer.source.placement().gsd_m as f32;
        let params = Params { layer_count: layer_count as f32, gsd_m: gsd, pad: [0.0; 2] };
        let buffer = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("canopy parameters"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let [a, b, c] = GpuClipmap::layout_entries(0);
        let group = shared.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("canopy layout"),
            entries: &[a, b, c, super::gpu::uniform_entry(3)],
        });
        let mask_group = shared.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("canopy mask layout"), entries: &GpuClipmap::layout_entries(0) });
        let [s0, s1, s2] = summer.gpu.bind_entries(0);
        let bind_group = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("canopy bind group"),
            layout: &group,
            entries: &[s0, s1, s2, wgpu::BindGroupEntry { binding: 3, resource: buffer.as_entire_binding() }],
        });
        let mask_bind_group = shared.device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("canopy mask bind group"), layout: &mask_group, entries: &masks.gpu.bind_entries(0) });
        Canopy {
            module: shared.shader("canopy.wgsl", &format!("{CLIPMAP_WGSL}\n{}", include_str!("canopy.wgsl"))),
            layout: shared.layout("canopy layout", &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&group), Some(&mask_group)]),
            shadow_layout: shared.layout("canopy shadow layout", &[Some(&shared.view_layout), None, Some(&group), Some(&mask_group)]),
            pipelines: PipelineCache::new("canopy"),
            bind_group,
            mask_bind_group,
            summer,
            masks,
            layer_count,
            instances: None,
            crowns_drawn: 0,
            bounds: None,
            trunks: trunks::Trunks::new(shared),
        }
    }

    /// Whether this frame has layers to draw (and so shadows to cast).
    pub fn draws_any(&self, cx: &FrameContext<'_>) -> bool {
        !cx.data.crowns.is_empty()
    }
}

/// The canopy's pipelines of `key`: for the main view a depth pre-pass and the shading at equal
/// depth, for the sun's view depth.
fn build(shared: &Shared, c: &Canopy, key: PipelineKey) -> Result<Pipelines, String> {
    const ATTRS: [wgpu::VertexAttribute; 2] = wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4];
    let buffers = [Some(wgpu::VertexBufferLayout { array_stride: 32, step_mode: wgpu::VertexStepMode::Instance, attributes: &ATTRS })];
    let constants = key.lit_constants();
    let pipeline = |label, layout, fragment, depth, targets: &[Option<wgpu::ColorTargetState>]| {
        shared.pipeline(&PipelineSpec {
            label,
            layout,
            module: &c.module,
            vertex: "vs_main",
            fragment: Some(fragment),
            buffers: &buffers,
            topology: wgpu::PrimitiveTopology::TriangleList,
            cull: None,
            depth,
            targets,
            constants: &constants,
        })
    };
    Ok(match key.view {
        ViewKind::Main => Pipelines::Main(
            pipeline("canopy depth pre-pass", &c.layout, "fs_prepass", depth_test(true, wgpu::CompareFunction::Less), &color_target(key.format, wgpu::ColorWrites::empty())),
            pipeline("canopy pipeline", &c.layout, "fs_main", depth_test(false, wgpu::CompareFunction::Equal), &color_target(key.format, wgpu::ColorWrites::ALL)),
        ),
        ViewKind::Sun => {
            let depth = wgpu::DepthStencilState { format: SHADOW_FORMAT, bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 }, ..depth_test(true, wgpu::CompareFunction::Less) };
            Pipelines::Shadow(pipeline("canopy shadow pipeline", &c.shadow_layout, "fs_depth", depth, &[]))
        }
    })
}

impl Feature for Canopy {
    fn prepare(&mut self, cx: &FrameContext<'_>) -> Result<(), String> {
        let camera = clip_camera(cx.data, cx.size);
        self.summer.update(&cx.shared.queue, &camera)?;
        self.masks.update(&cx.shared.queue, &camera)?;
        let view_proj = super::view::camera_matrix(&cx.data.camera, cx.size.0.max(1) as f32 / cx.size.1.max(1) as f32);
        let visible: Vec<CrownDraw> = cx.data.crowns.iter().filter(|c| in_view(&view_proj, c)).copied().collect();
        let layers = layer_instances(&visible, self.layer_count);
        self.crowns_drawn = visible.len() as u32;
        self.bounds = visible.iter().fold(None, |b, c| {
            let r = glam::Vec3::new(c.radius_m * 1.25, 0.0, c.radius_m * 1.25);
            let lo = c.foot - r + glam::Vec3::Y * c.base_m;
            let hi = c.foot + r + glam::Vec3::Y * c.top_m;
            Some(b.map_or((lo, hi), |(a, z): (glam::Vec3, glam::Vec3)| (a.min(lo), z.max(hi))))
        });
        self.instances = (!layers.is_empty()).then(|| {
            let buffer = cx.shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("canopy layers"),
                contents: bytemuck::cast_slice(&layers),
                usage: wgpu::BufferUsages::VERTEX,
            });
            (buffer, layers.len() as u32)
        });
        let keys = if cx.key.shadows { vec![cx.key, cx.key.with_view(ViewKind::Sun)] } else { vec![cx.key] };
        self.trunks.prepare(cx.shared, &visible, &keys)?;
        for k in keys {
            if self.pipelines.get(k).is_err() {
                let built = build(cx.shared, self, k);
                self.pipelines.prepare(k, |_| built)?;
            }
        }
        Ok(())
    }

    fn draw_depth<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey) -> Result<(), String> {
        self.trunks.draw_depth(pass, key)?;
        let Some((buffer, n)) = &self.instances else { return Ok(()) };
        let Pipelines::Shadow(p) = self.pipelines.get(key)? else { return Err("canopy: the sun's key has no shadow pipeline".into()) };
        pass.set_pipeline(p);
        pass.set_bind_group(2, &self.bind_group, &[]);
        pass.set_bind_group(3, &self.mask_bind_group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..6, 0..self.crowns_drawn.min(*n));
        Ok(())
    }

    fn draw<'p>(&'p self, phase: Phase, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey, stats: &mut FrameStats) -> Result<(), String> {
        let (Phase::AlphaClipped, Some((buffer, n))) = (phase, &self.instances) else { return Ok(()) };
        let trunks = self.trunks.draw(pass, key)?;
        stats.draws += usize::from(trunks > 0);
        stats.triangles += trunks::TRIANGLES as usize * trunks as usize;
        let Pipelines::Main(prepass, shade) = self.pipelines.get(key)? else { return Err("canopy: the main key has no main pipeline".into()) };
        pass.set_bind_group(2, &self.bind_group, &[]);
        pass.set_bind_group(3, &self.mask_bind_group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        for p in [prepass, shade] {
            pass.set_pipeline(p);
            pass.draw(0..6, 0..*n);
        }
        stats.draws += 2;
        stats.triangles += 4 * *n as usize;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::*;

    #[test]
    fn crowns_behind_the_camera_or_far_to_the_side_are_culled() {
        use crate::render::view::{camera_matrix, Camera};
        // The camera at the origin looks north (−Z) with a 60° field of view.
        let m = camera_matrix(&Camera { position: Vec3::ZERO, rotation: glam::Quat::IDENTITY, fov_y: 60f32.to_radians() }, 1.0);
        let crown = |x: f32, z: f32| CrownDraw { foot: Vec3::new(x, 0.0, z), photo_centre: Vec2::ZERO, radius_m: 1.0, base_m: 2.0, top_m: 4.0 };
        // Ahead, 50 m away: seen. Its sphere: centre 3 m up, radius 1.8 + 1 + 8 = 10.8 m.
        assert!(in_view(&m, &crown(0.0, -50.0)));
        // 50 m behind: the near plane (z = 0 in view space) is 50 m from it, more than 10.8.
        assert!(!in_view(&m, &crown(0.0, 50.0)));
        // 50 m ahead and 60 m to the east: the right plane, 30° from the view axis, is
        // 60 cos 30° − 50 sin 30° ≈ 27 m from it.
        assert!(!in_view(&m, &crown(60.0, -50.0)));
        // Beyond the far plane (600 m).
        assert!(!in_view(&m, &crown(0.0, -700.0)));
    }

    #[test]
    fn layers_stand_evenly_from_base_to_top() {
        let c = CrownDraw { foot: Vec3::new(1.0, 2.0, 3.0), photo_centre: Vec2::new(5.0, 6.0), radius_m: 2.0, base_m: 3.0, top_m: 8.0 };
        let l = layer_instances(&[c], 6);
        assert_eq!(l.len(), 6);
        // Heights 3, 4, 5, 6, 7, 8 m over the foot.
        for (i, layer) in l.iter().enumerate() {
            assert_eq!(layer[..6], [1.0, 2.0, 3.0, 2.0, 5.0, 6.0]);
            assert!((layer[6] - (3.0 + i as f32)).abs() < 1e-6, "{layer:?}");
            assert_eq!(layer[7], i as f32);
        }
    }
}
