//! The canopy (issue #22, after Ropinski et al. 2007): each photographed crown tree drawn as
//! stacked horizontal layers between its crown base and top, textured from the summer
//! photograph's clipmap where that layer's bit of the layer masks (`grove aerial layers`) says
//! treetop. Alpha-tested, lit by the sun, casting shadows (a depth pass with the same test).
//!
//! The layers stand at each crown tree's current position (it can be moved), and read the
//! photograph around the crown's photographed centre ([`grove_systems::aerial::AerialCrown`]).
//! One instance per (crown, layer), built each frame from the extracted crowns: nearest crowns
//! first and each crown's top layer first, so that what lies behind or below fails the depth
//! test before its fragment shader runs; each layer's quad only as wide as its mask bits reach
//! ([`extents`]), none for an empty layer, and far crowns with fewer layers. One alpha-tested
//! pass: the depth pre-pass it replaced drew every quad twice (measured together with the smaller
//! quads, not alone).
//! Under each crown stands a trunk ([`trunks`]), drawn and casting shadows with the layers.

pub mod extents;
mod extract;
pub(crate) mod trunks;

use crate::render::error::{PipelineError, RenderError};
use wgpu::util::DeviceExt;

pub(crate) use self::extract::CrownDraw;
use self::extract::Crowns;
use super::clipmap::{FedClipmap, GpuClipmap, clip_camera};
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, PipelineSpec, SHADOW_FORMAT, Shared, ViewKind, color_target, depth_test};

/// The canopy's uniforms (matches `CanopyParams` in canopy.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    layer_count: f32,
    gsd_m: f32,
    /// The angle one pixel of the main view spans, radians.
    pixel_angle: f32,
    pad: f32,
}

/// One layer instance: the tree's foot and crown radius; the photographed centre, the layer's
/// height over the foot and its index; the half-side of its quad, metres, and padding (matches
/// `LayerIn` in canopy.wgsl).
pub(crate) type LayerInstance = [f32; 12];

/// Below this crown radius on screen, pixels, every other layer is drawn (and the top one).
pub(crate) const HALF_LAYERS_BELOW_PX: f32 = 8.0;
/// Below this crown radius on screen, pixels, only the lowest and the top layers are drawn.
pub(crate) const TWO_LAYERS_BELOW_PX: f32 = 3.0;

/// Whether layer `i` of `layers` is drawn for a crown whose radius spans `radius_px` pixels on
/// screen: all near by; far away every other one, then only the lowest and the top one (the
/// lowest always: it casts the shadow and holds the outline, the top one rounds the crown off).
pub(crate) fn layer_drawn(i: u32, layers: u32, radius_px: f32) -> bool {
    let top = layers.saturating_sub(1);
    if radius_px >= HALF_LAYERS_BELOW_PX || i == 0 || i == top {
        return true;
    }
    radius_px >= TWO_LAYERS_BELOW_PX && i.is_multiple_of(2)
}

/// The layer instances of `crowns` with `layers` layers each, seen from `eye` with pixels of
/// `pixel_angle` radians, and how many of them the main view draws. The main view's come
/// first: crowns nearest the eye first, each crown's layers from the top down (so that lower
/// and farther layers fail the depth test under nearer ones), only the layers
/// [`layer_drawn`] keeps at the crown's size on screen and whose extent (from `extents`, the
/// half-side of each layer's quad in metres) is not 0. After them come the crowns' lowest
/// layers again, in the order of `crowns`: the shadow pass draws those. Layer i stands at a
/// height from the crown base (i = 0) to its top (i = layers − 1), evenly spaced.
pub(crate) fn layer_instances(
    crowns: &[CrownDraw],
    layers: u32,
    eye: glam::Vec3,
    pixel_angle: f32,
    mut extents: impl FnMut(&CrownDraw) -> [f32; 8],
) -> (Vec<LayerInstance>, usize) {
    let centre = |c: &CrownDraw| c.foot + glam::Vec3::Y * (0.5 * (c.base_m + c.top_m));
    let mut order: Vec<(f32, usize)> = crowns.iter().enumerate().map(|(k, c)| (centre(c).distance(eye), k)).collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let ext: Vec<[f32; 8]> = crowns.iter().map(&mut extents).collect();
    let layer = |c: &CrownDraw, i: u32, e: f32| {
        let f = if layers > 1 { i as f32 / (layers - 1) as f32 } else { 1.0 };
        let h = c.base_m + (c.top_m - c.base_m) * f;
        [c.foot.x, c.foot.y, c.foot.z, c.radius_m, c.photo_centre.x, c.photo_centre.y, h, i as f32, e, 0.0, 0.0, 0.0]
    };
    let mut out = Vec::with_capacity(crowns.len() * (layers as usize + 1));
    for (dist, k) in order {
        let (c, e) = (&crowns[k], &ext[k]);
        let radius_px = c.radius_m / (dist * pixel_angle).max(1e-6);
        for i in (0..layers.min(8)).rev() {
            if layer_drawn(i, layers, radius_px) && e[i as usize] > 0.0 {
                out.push(layer(c, i, e[i as usize]));
            }
        }
    }
    let main = out.len();
    for (c, e) in crowns.iter().zip(&ext) {
        if e[0] > 0.0 {
            out.push(layer(c, 0, e[0]));
        }
    }
    (out, main)
}

/// The canopy's pipelines of one key.
enum Pipelines {
    /// Alpha-tested, lit and shadowed.
    Main(wgpu::RenderPipeline),
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
    params: Params,
    params_buffer: wgpu::Buffer,
    /// This frame's layer instances and how many of them are in the main view's draw; the rest
    /// are the crowns' lowest, widest layers, whose outline holds the upper layers' (their
    /// masks' k is larger): the shadow pass draws only those, at a sixth of the cost.
    instances: Option<(wgpu::Buffer, u32, u32)>,
    /// The layers' extents by crown.
    extents: extents::ExtentCache,
    /// The trunks under the crowns drawn this frame.
    trunks: trunks::Trunks,
}

impl Canopy {
    /// The feature over the summer and layer-mask clipmaps with `layer_count` layers; with the
    /// masks' bits in memory, each layer's quad is only as wide as its bits reach.
    pub fn new(
        shared: &Shared,
        summer: FedClipmap,
        masks: FedClipmap,
        layer_count: u32,
        bits: Option<extents::LayerBits>,
    ) -> Canopy {
        let gsd = summer.source.placement().gsd_m as f32;
        let params = Params { layer_count: layer_count as f32, gsd_m: gsd, pixel_angle: 1e-3, pad: 0.0 };
        let buffer = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("canopy parameters"),
            contents: bytemuck::bytes_of(&params),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let [a, b, c] = GpuClipmap::layout_entries(0);
        let group = shared.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("canopy layout"),
            entries: &[a, b, c, super::gpu::uniform_entry(3)],
        });
        let mask_group = shared.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("canopy mask layout"),
            entries: &GpuClipmap::layout_entries(0),
        });
        let [s0, s1, s2] = summer.gpu.bind_entries(0);
        let bind_group = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("canopy bind group"),
            layout: &group,
            entries: &[s0, s1, s2, wgpu::BindGroupEntry { binding: 3, resource: buffer.as_entire_binding() }],
        });
        let mask_bind_group = shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("canopy mask bind group"),
            layout: &mask_group,
            entries: &masks.gpu.bind_entries(0),
        });
        Canopy {
            module: shared.shader("canopy.wgsl", include_str!("canopy.wgsl")),
            layout: shared.layout(
                "canopy layout",
                &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&group), Some(&mask_group)],
            ),
            shadow_layout: shared
                .layout("canopy shadow layout", &[Some(&shared.view_layout), None, Some(&group), Some(&mask_group)]),
            pipelines: PipelineCache::new("canopy"),
            bind_group,
            mask_bind_group,
            summer,
            masks,
            layer_count,
            params,
            params_buffer: buffer,
            instances: None,
            extents: extents::ExtentCache::new(bits, layer_count),
            trunks: trunks::Trunks::new(shared),
        }
    }
}

/// The canopy's pipelines of `key`: for the main view alpha-tested shading, for the sun's view
/// alpha-tested depth.
fn build(shared: &Shared, c: &Canopy, key: PipelineKey) -> Result<Pipelines, PipelineError> {
    const ATTRS: [wgpu::VertexAttribute; 3] = wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4];
    let buffers = [Some(wgpu::VertexBufferLayout {
        array_stride: 48,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRS,
    })];
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
        ViewKind::Main => Pipelines::Main(pipeline(
            "canopy pipeline",
            &c.layout,
            "fs_main",
            depth_test(true, wgpu::CompareFunction::Less),
            &color_target(key.format, wgpu::ColorWrites::ALL),
        )),
        ViewKind::Sun => {
            let depth = wgpu::DepthStencilState {
                format: SHADOW_FORMAT,
                bias: wgpu::DepthBiasState { constant: 2, slope_scale: 1.5, clamp: 0.0 },
                ..depth_test(true, wgpu::CompareFunction::Less)
            };
            Pipelines::Shadow(pipeline("canopy shadow pipeline", &c.shadow_layout, "fs_depth", depth, &[]))
        }
    })
}

impl Feature for Canopy {
    type Extracted = Crowns;

    fn extract(&self, sim: &grove_systems::Sim, cx: &ExtractContext<'_>) -> Crowns {
        extract::crowns(sim, cx)
    }

    /// Whether the world has photographed crowns (they cast shadows even when out of view).
    fn casts_shadows(&self, crowns: &Crowns) -> bool {
        crowns.any
    }

    /// The bounds of the layers drawn this frame.
    fn shadow_bounds(&self, crowns: &Crowns) -> Option<(glam::Vec3, glam::Vec3)> {
        crowns.visible.iter().fold(None, |b, c| {
            let r = glam::Vec3::new(c.radius_m * 1.25, 0.0, c.radius_m * 1.25);
            let lo = c.foot - r + glam::Vec3::Y * c.base_m;
            let hi = c.foot + r + glam::Vec3::Y * c.top_m;
            Some(b.map_or((lo, hi), |(a, z): (glam::Vec3, glam::Vec3)| (a.min(lo), z.max(hi))))
        })
    }

    fn prepare(&mut self, cx: &FrameContext<'_>, crowns: Crowns) -> Result<(), RenderError> {
        let camera = clip_camera(&cx.common.camera, cx.size);
        self.summer.update(&cx.shared.queue, &camera)?;
        self.masks.update(&cx.shared.queue, &camera)?;
        let visible = crowns.visible;
        // The angle a pixel spans: the levels and the layers drawn depend on it.
        self.params.pixel_angle = 2.0 * (0.5 * cx.common.camera.fov_y).tan() / cx.size.1.max(1) as f32;
        cx.shared.queue.write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
        let cache = &mut self.extents;
        let (layers, main) =
            layer_instances(&visible, self.layer_count, cx.common.camera.position, self.params.pixel_angle, |c| {
                cache.get(c)
            });
        self.instances = (!layers.is_empty()).then(|| {
            let buffer = cx.shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("canopy layers"),
                contents: bytemuck::cast_slice(&layers),
                usage: wgpu::BufferUsages::VERTEX,
            });
            (buffer, layers.len() as u32, main as u32)
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

    fn draw_depth<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey) -> Result<(), RenderError> {
        self.trunks.draw_depth(pass, key)?;
        let Some((buffer, n, main)) = &self.instances else { return Ok(()) };
        let Pipelines::Shadow(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NoShadowPipeline("canopy").into());
        };
        pass.set_pipeline(p);
        pass.set_bind_group(2, &self.bind_group, &[]);
        pass.set_bind_group(3, &self.mask_bind_group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        // The lowest layers: the instances after the main view's.
        pass.draw(0..6, *main..*n);
        Ok(())
    }

    fn draw<'p>(
        &'p self,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        let (Phase::AlphaClipped, Some((buffer, _, main))) = (phase, &self.instances) else { return Ok(()) };
        let trunks = self.trunks.draw(pass, key)?;
        stats.draws += usize::from(trunks > 0);
        stats.triangles += trunks::TRIANGLES as usize * trunks as usize;
        let Pipelines::Main(shade) = self.pipelines.get(key)? else {
            return Err(PipelineError::NoMainPipeline("canopy").into());
        };
        pass.set_bind_group(2, &self.bind_group, &[]);
        pass.set_bind_group(3, &self.mask_bind_group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.set_pipeline(shade);
        pass.draw(0..6, 0..*main);
        stats.draws += 1;
        stats.triangles += 2 * *main as usize;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3};

    use super::extract::in_view;
    use super::*;

    #[test]
    fn crowns_behind_the_camera_or_far_to_the_side_are_culled() {
        use crate::render::view::{Camera, camera_matrix};
        // The camera at the origin looks north (−Z) with a 60° field of view.
        let m = camera_matrix(
            &Camera { position: Vec3::ZERO, rotation: glam::Quat::IDENTITY, fov_y: 60f32.to_radians() },
            1.0,
        );
        let crown = |x: f32, z: f32| CrownDraw {
            foot: Vec3::new(x, 0.0, z),
            photo_centre: Vec2::ZERO,
            radius_m: 1.0,
            base_m: 2.0,
            top_m: 4.0,
        };
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
    fn near_crowns_come_first_far_ones_draw_fewer_layers_and_the_shadow_layers_come_last() {
        let crown = |z: f32| CrownDraw {
            foot: Vec3::new(0.0, 0.0, z),
            photo_centre: Vec2::new(0.0, z),
            radius_m: 2.0,
            base_m: 2.0,
            top_m: 6.0,
        };
        // From the crowns' centre height (4 m), with pixels of 1 mrad: 2 m at 100 m span 20
        // pixels (all 6 layers), at 400 m 5 pixels (layers 0, 2, 4 and the top 5), at 1000 m
        // 2 pixels (layers 0 and 5). The crowns are listed far to near.
        let crowns = [crown(-1000.0), crown(-400.0), crown(-100.0)];
        let (l, main) = layer_instances(&crowns, 6, Vec3::new(0.0, 4.0, 0.0), 1e-3, |_| [2.5; 8]);
        let drawn: Vec<(f32, u32)> = l[..main].iter().map(|x| (x[2], x[7] as u32)).collect();
        let want: Vec<(f32, u32)> =
            [(-100.0, vec![5, 4, 3, 2, 1, 0]), (-400.0, vec![5, 4, 2, 0]), (-1000.0, vec![5, 0])]
                .into_iter()
                .flat_map(|(z, ls)| ls.into_iter().map(move |i| (z, i)))
                .collect();
        assert_eq!(drawn, want);
        // Then the three crowns' lowest layers, in the given order, for the shadow pass.
        let shadow: Vec<(f32, f32)> = l[main..].iter().map(|x| (x[2], x[7])).collect();
        assert_eq!(shadow, vec![(-1000.0, 0.0), (-400.0, 0.0), (-100.0, 0.0)]);
        assert!(l.iter().all(|x| x[8] == 2.5));
    }

    #[test]
    fn empty_layers_are_not_drawn_and_quads_take_their_extents() {
        let c = CrownDraw { foot: Vec3::ZERO, photo_centre: Vec2::ZERO, radius_m: 2.0, base_m: 2.0, top_m: 6.0 };
        // Layers 3 to 5 empty, layer 0 2.4 m wide, the others 1 m.
        let (l, main) =
            layer_instances(&[c], 6, Vec3::new(0.0, 4.0, 10.0), 1e-3, |_| [2.4, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let drawn: Vec<(u32, f32)> = l[..main].iter().map(|x| (x[7] as u32, x[8])).collect();
        assert_eq!(drawn, vec![(2, 1.0), (1, 1.0), (0, 2.4)]);
        assert_eq!(l.len(), main + 1);
        // An empty lowest layer casts no shadow either.
        let (l, main) = layer_instances(&[c], 6, Vec3::new(0.0, 4.0, 10.0), 1e-3, |_| [0.0; 8]);
        assert_eq!((l.len(), main), (0, 0));
    }

    #[test]
    fn layers_stand_evenly_from_base_to_top() {
        let c = CrownDraw {
            foot: Vec3::new(1.0, 2.0, 3.0),
            photo_centre: Vec2::new(5.0, 6.0),
            radius_m: 2.0,
            base_m: 3.0,
            top_m: 8.0,
        };
        // Seen from 10 m with pixels of 1 mrad its radius spans 200 pixels: all six layers.
        let eye = Vec3::new(1.0, 2.0 + 5.5, 13.0);
        let (l, main) = layer_instances(&[c], 6, eye, 1e-3, |_| [2.5; 8]);
        assert_eq!((l.len(), main), (7, 6));
        // Top layer first: heights 8, 7, 6, 5, 4, 3 m over the foot.
        for (j, layer) in l[..6].iter().enumerate() {
            let i = 5 - j;
            assert_eq!(layer[..6], [1.0, 2.0, 3.0, 2.0, 5.0, 6.0]);
            assert!((layer[6] - (3.0 + i as f32)).abs() < 1e-6, "{layer:?}");
            assert_eq!(layer[7], i as f32);
        }
        assert_eq!(l[6][..8], l[5][..8]);
    }
}
