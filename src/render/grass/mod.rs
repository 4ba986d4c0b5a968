//! Grass: shell lawns and compute-generated blades (issue #18), a shadow receiver (it casts
//! none). Drawn right after the ground in the opaque phase.
//!
//! - **Shells** (`shells.wgsl`): per patch, its ground triangles drawn once, where the bottom
//!   layer lies; each fragment walks the layers along its view ray, from the highest the
//!   triangle keeps at its distance down, and blends them itself (front to back, stopping when
//!   nothing more shows through). A strand texture decides which texels of a layer are grass.
//!   A large patch is split into tiles (`tiles.rs`, at most 256): a tile outside the view is
//!   skipped.
//! - **Blades**: every blade of every blade patch is uploaded once, when the patches change
//!   ([`GrassKey`]). Each frame the **compute** stage (`cull.wgsl`) culls them against the view
//!   frustum and a far distance, evaluates each visible blade's wind, pushes and bend once into
//!   its shape (a Bézier curve), and by level of detail either lists it for one of two indirect
//!   draws (7 segments a blade near the camera, 3 further away; a second stage joins the
//!   blocks' lists in a fixed order, so that a frame does not depend on the order the
//!   invocations ran in, see `readback.rs`), or, far away
//!   where a blade is narrower than a pixel, rasterises its curve itself into an image of the
//!   nearest far blade's depth and colour per pixel (`raster`); the levels' distances follow
//!   the pixels a metre covers. The main pass draws the near and middle blades indirectly,
//!   then lays the far blades' image over the scene with a rectangle around them that lights
//!   each covered pixel and tests and writes its depth (`blades.wgsl`). The draws are not
//!   instanced (a software rasteriser pays per instance), and a far blade costs no primitive
//!   at all (a software rasteriser pays a fixed price per primitive). No per-blade data
//!   crosses from the CPU per frame: only the uniforms, the counters' reset, the image's
//!   clearing and the list of blocks in view (`blocks.rs`: the blades are uploaded in runs of
//!   1,024 that cover compact pieces of lawn; blocks out of view are skipped and blocks of far
//!   blades culled by a pipeline without the near and middle code).
//!
//! Wind is the world's `Wind` (its direction, strength and current gust, as the trees get it),
//! read from a world-space noise texture. Units: metres, radians, seconds.

pub(crate) mod blocks;
mod readback;
pub use blocks::BLOCK_BLADES;
pub use data::LOD_CAPS;
pub use readback::{BladeCounts, BladeLists};
pub(crate) mod data;
pub(crate) mod edges;
mod extract;
pub(crate) mod tiles;
mod setup;

use crate::render::error::{PipelineError, RenderError};
use wgpu::util::DeviceExt;

use self::extract::{GrassKey, Patches};
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, Shared};
use setup::{build_blades, build_shells, buffer_entries};
use data::{BladeParams, CullParams, GpuBlade, GrassPatch, ShellParams, MAX_PATCHES};

/// No blade is drawn beyond this distance, metres.
pub const FAR_DISTANCE: f32 = 60.0;
/// The radius within which blades bend away from the eye, metres.
pub const EYE_RADIUS: f32 = 0.9;
/// The radius within which blades bend away from the controller's hit point, metres.
pub const HIT_RADIUS: f32 = 0.5;
/// The wind noise: metres per tile of the texture and its scroll speed per unit of strength.
const WIND_SCALE: f32 = 1.0 / 12.0;
const WIND_SPEED: f32 = 3.0;
/// The bend of a blade tip, radians per unit of wind strength times gust.
const WIND_BEND: f32 = 0.9;

/// One shell patch on the GPU.
struct ShellPatch {
    vertices: wgpu::Buffer,
    /// The patch's tiles (runs of its vertex buffer) and whether each is in view this frame.
    tiles: Vec<tiles::Tile>,
    tile_visible: Vec<bool>,
    params: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    template: ShellParams,
}

/// Every blade of the scene on the GPU, with the cull pass's outputs.
struct BladeSet {
    count: u32,
    /// The index buffers of the near and middle draws.
    indices: [wgpu::Buffer; 2],
    blades: wgpu::Buffer,
    shapes: wgpu::Buffer,
    lists: wgpu::Buffer,
    cull_params: wgpu::Buffer,
    draw_params: wgpu::Buffer,
    /// The indirect draws and the far blades' count, then the far blades' image (one word a
    /// pixel), made again with the bind groups that refer to it when the frame's size
    /// (`raster_size`, pixels) changes.
    args: wgpu::Buffer,
    raster_size: (u32, u32),
    cull_group: wgpu::BindGroup,
    draw_group: wgpu::BindGroup,
    colours: [[f32; 4]; 2 * MAX_PATCHES],
    /// The bounds of each block of blades, and this frame's workgroups of the general and the
    /// far cull pipelines (their blocks' list follows the near and middle lists in `lists`).
    blocks: Vec<blocks::Block>,
    dispatch: [u32; 2],
}

/// The grass feature.
pub struct Grass {
    shared: Shared,
    shell_module: wgpu::ShaderModule,
    blade_module: wgpu::ShaderModule,
    shell_group_layout: wgpu::BindGroupLayout,
    blade_group_layout: wgpu::BindGroupLayout,
    cull_group_layout: wgpu::BindGroupLayout,
    shell_layout: wgpu::PipelineLayout,
    blade_layout: wgpu::PipelineLayout,
    /// The cull pass's general pipeline and its pipeline for blocks of far blades.
    cull_pipelines: [wgpu::ComputePipeline; 2],
    /// The cull pass's second stage, which joins the general blocks' lists in order (`cs_order`).
    order_pipeline: wgpu::ComputePipeline,
    shell_pipelines: PipelineCache<wgpu::RenderPipeline>,
    blade_pipelines: PipelineCache<[wgpu::RenderPipeline; 3]>,
    strand_tex: wgpu::TextureView,
    wind_tex: wgpu::TextureView,
    nearest: wgpu::Sampler,
    linear: wgpu::Sampler,
    /// The sky's irradiance cube (the far blades' light).
    irradiance: wgpu::TextureView,
    /// The key of the patches the buffers were built from.
    key: GrassKey,
    shells: Vec<ShellPatch>,
    blades: Option<BladeSet>,
    /// Whether this frame draws grass (`RenderOptions::grass`).
    enabled: bool,
}

impl Grass {
    /// Rebuilds the GPU buffers of every patch, the far blades' image for a frame of `size`
    /// pixels.
    fn rebuild(&mut self, shared: &Shared, key: &GrassKey, patches: &[GrassPatch], size: (u32, u32)) {
        let device = &shared.device;
        self.key = key.clone();
        self.shells.clear();
        self.blades = None;
        let init = |label: &str, contents: &[u8], usage| device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage });
        let mut blades: Vec<GpuBlade> = Vec::new();
        let mut colours = [[0.0f32; 4]; 2 * MAX_PATCHES];
        for (i, p) in patches.iter().enumerate() {
            if p.shells {
                // Per vertex: position, the face's normal, and the triangle's centre and radius,
                // the same for its three corners, so the shader thins a whole triangle's layers
                // with distance at once.
                let (order, tiles) = tiles::tile_triangles(&p.triangles);
                let edge = edges::edge_shares(&p.triangles);
                let mut verts: Vec<[f32; 11]> = Vec::with_capacity(p.triangles.len() * 3);
                for (t, e) in order.iter().map(|&k| (&p.triangles[k], &edge[k])) {
                    let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize_or(glam::Vec3::Y);
                    let n = if n.y < 0.0 { -n } else { n };
                    let c = (t[0] + t[1] + t[2]) / 3.0;
                    let r = t.iter().map(|v| v.distance(c)).fold(0.0, f32::max);
                    verts.extend(t.iter().zip(e).map(|(v, e)| [v.x, v.y, v.z, n.x, n.y, n.z, c.x, c.y, c.z, r, *e]));
                }
                if verts.is_empty() {
                    continue;
                }
                let template = ShellParams {
                    root: [p.root.x, p.root.y, p.root.z, p.layers as f32],
                    tip: [p.tip.x, p.tip.y, p.tip.z, p.height.1],
                    wind: [1.0, 0.0, 0.0, 0.0],
                    strands: [p.density.sqrt(), WIND_SCALE, 0.0, p.height.0 / p.height.1],
                };
                let params = init("grass shell parameters", bytemuck::bytes_of(&template), wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST);
                let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("grass shell bind group"),
                    layout: &self.shell_group_layout,
                    entries: &[
                        wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                        wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&self.strand_tex) },
                        wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&self.wind_tex) },
                        wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::Sampler(&self.nearest) },
                        wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&self.linear) },
                    ],
                });
                self.shells.push(ShellPatch {
                    vertices: init("grass shell vertices", bytemuck::cast_slice(&verts), wgpu::BufferUsages::VERTEX),
                    tile_visible: vec![false; tiles.len()],
                    tiles,
                    params,
                    bind_group,
                    template,
                });
            } else if i < MAX_PATCHES {
                colours[2 * i] = [p.root.x, p.root.y, p.root.z, 1.0];
                colours[2 * i + 1] = [p.tip.x, p.tip.y, p.tip.z, 1.0];
                blades.extend(p.blades.iter().map(|b| GpuBlade::new(b, i)));
            }
        }
        if blades.is_empty() {
            return;
        }
        blocks::spatial_order(&mut blades);
        let bounds = blocks::block_bounds(&blades);
        let count = blades.len() as u32;
        let storage_buffer = |label, size: u64| device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage: wgpu::BufferUsages::STORAGE, mapped_at_creation: false });
        // The near and middle lists (far blades are not listed), this frame's blocks, each
        // block's numbers of near and middle blades and its own lists (cull.wgsl, `lists`).
        let lists_bytes = 4 * (2 * u64::from(count) + 2 * bounds.len() as u64 + bounds.len() as u64 * u64::from(blocks::BLOCK_BLADES));
        let lists = device.create_buffer(&wgpu::BufferDescriptor { label: Some("grass blade lists"), size: lists_bytes, usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC, mapped_at_creation: false });
        let shapes = storage_buffer("grass blade shapes", data::SHAPE_BYTES * u64::from(count));
        let blade_buf = init("grass blades", bytemuck::cast_slice(&blades), wgpu::BufferUsages::STORAGE);
        let uniform = |label, size: usize| device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size: size as u64, usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST, mapped_at_creation: false });
        let cull_params = uniform("grass cull parameters", std::mem::size_of::<CullParams>());
        let draw_params = uniform("grass blade parameters", std::mem::size_of::<BladeParams>());
        let index_buffer = |k: usize| {
            let idx = data::blade_indices(data::LOD_SEGMENTS[k], count.min(data::LOD_CAPS[k]));
            init("grass blade indices", bytemuck::cast_slice(&idx), wgpu::BufferUsages::INDEX)
        };
        let indices = [index_buffer(0), index_buffer(1)];
        let args = args_buffer(device, size);
        let (cull_group, draw_group) = self.blade_groups(device, [&cull_params, &blade_buf, &shapes, &lists, &args, &draw_params]);
        self.blades = Some(BladeSet {
            count,
            indices,
            blades: blade_buf,
            shapes,
            lists,
            cull_params,
            draw_params,
            args,
            raster_size: size,
            cull_group,
            draw_group,
            colours,
            blocks: bounds,
            dispatch: [0, 0],
        });
    }

    /// The cull pass's and the blade draws' bind groups over `buffers`: the cull parameters,
    /// the blades, the shapes, the lists, the indirect draws (with the far blades' image) and
    /// the draw parameters.
    fn blade_groups(&self, device: &wgpu::Device, buffers: [&wgpu::Buffer; 6]) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let [cull_params, blades, shapes, lists, args, draw_params] = buffers;
        let mut entries = buffer_entries(&[cull_params, blades, shapes, lists, args]);
        entries.push(wgpu::BindGroupEntry { binding: 5, resource: wgpu::BindingResource::TextureView(&self.wind_tex) });
        entries.push(wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::Sampler(&self.linear) });
        entries.push(wgpu::BindGroupEntry { binding: 7, resource: draw_params.as_entire_binding() });
        entries.push(wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::TextureView(&self.irradiance) });
        let cull_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("grass cull bind group"), layout: &self.cull_group_layout, entries: &entries });
        let entries = buffer_entries(&[draw_params, shapes, lists, args]);
        let draw_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("grass blade bind group"), layout: &self.blade_group_layout, entries: &entries });
        (cull_group, draw_group)
    }

    /// Makes the indirect draws' buffer with the far blades' image again, with the bind groups
    /// that refer to it, when the frame's size (pixels) is no longer the image's.
    fn resize_raster(&mut self, device: &wgpu::Device, size: (u32, u32)) {
        let Some(b) = self.blades.as_ref().filter(|b| b.raster_size != size) else { return };
        let args = args_buffer(device, size);
        let (cull_group, draw_group) = self.blade_groups(device, [&b.cull_params, &b.blades, &b.shapes, &b.lists, &args, &b.draw_params]);
        if let Some(b) = self.blades.as_mut() {
            (b.args, b.raster_size, b.cull_group, b.draw_group) = (args, size, cull_group, draw_group);
        }
    }

    /// The compute stage: culls the blades into this frame's lists and draw counts. Records
    /// nothing when there are no blades or grass is off.
    pub(crate) fn compute(&self, encoder: &mut wgpu::CommandEncoder, timer: Option<&mut super::timing::Timer>) {
        let Some(b) = self.blades.as_ref().filter(|_| self.enabled) else { return };
        let writes = timer.and_then(|t| t.scope("grass compute"));
        let timestamp_writes = writes.map(|w| wgpu::ComputePassTimestampWrites {
            query_set: w.query_set,
            beginning_of_pass_write_index: w.beginning_of_pass_write_index,
            end_of_pass_write_index: w.end_of_pass_write_index,
        });
        // No far blade covers a pixel until the pass has rasterised them.
        encoder.clear_buffer(&b.args, 4 * data::RASTER_OFFSET, None);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("grass cull pass"), timestamp_writes });
        pass.set_bind_group(0, &b.cull_group, &[]);
        // A workgroup per block in view: the general pipeline's blocks, then the far ones.
        for (pipeline, &groups) in self.cull_pipelines.iter().zip(&b.dispatch).filter(|(_, g)| **g > 0) {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(groups.min(65_535), groups.div_ceil(65_535), 1);
        }
        // Then the general blocks' near and middle blades into the draws' lists, in order.
        let general = b.dispatch[0];
        if general > 0 {
            pass.set_pipeline(&self.order_pipeline);
            pass.dispatch_workgroups(general.min(65_535), general.div_ceil(65_535), 1);
        }
    }
}

impl Feature for Grass {
    /// The patches; `None` when the options turn grass off.
    type Extracted = Option<Patches>;

    fn extract(&self, sim: &grove_systems::Sim, cx: &ExtractContext<'_>) -> Option<Patches> {
        cx.options.grass.then(|| extract::patches(sim, &self.key, cx.options.blade_edge_fade))
    }

    fn prepare(&mut self, cx: &FrameContext<'_>, patches: Option<Patches>) -> Result<(), RenderError> {
        self.enabled = patches.is_some();
        let Some(patches) = patches else {
            return Ok(());
        };
        // The far blades' image must fit one storage binding (128 MiB by default: about
        // 5,800 × 5,800 pixels).
        let image_bytes = 4 * (data::RASTER_OFFSET + u64::from(cx.size.0) * u64::from(cx.size.1));
        let limit = cx.shared.device.limits().max_storage_buffer_binding_size as u64;
        if image_bytes > limit && (self.blades.is_some() || patches.patches.as_ref().is_some_and(|p| p.iter().any(|p| !p.shells))) {
            return Err(RenderError::GrassImage { width: cx.size.0, height: cx.size.1, bytes: image_bytes, limit });
        }
        if let Some(list) = &patches.patches {
            self.rebuild(cx.shared, &patches.key, list, cx.size);
        }
        self.resize_raster(&cx.shared.device, cx.size);
        let queue = &cx.shared.queue;
        let w = &cx.common.wind;
        let time = (cx.common.time % 3600.0) as f32;
        let bend = WIND_BEND * w.strength * w.gust;
        let speed = WIND_SPEED * w.strength.max(0.05);
        let view_proj = cx.views.camera_view_proj;
        let planes = data::frustum_planes(view_proj);
        let eye = cx.common.camera.position;
        for s in &mut self.shells {
            // Each tile in view or not: its sphere, raised by the grass and its sway.
            let reach = s.template.tip[3] * 1.5;
            for (tile, shown) in s.tiles.iter().zip(s.tile_visible.iter_mut()) {
                let (c, r) = (tile.centre + glam::Vec3::Y * (0.5 * reach), tile.radius + reach);
                *shown = planes.iter().all(|q| glam::Vec3::new(q[0], q[1], q[2]).dot(c) + q[3] >= -r);
            }
            let mut p = s.template;
            // The tip of a shell lawn sways by about a third of its height at full wind.
            p.wind = [w.direction[0], w.direction[1], 0.35 * p.tip[3] * w.strength * w.gust, time];
            p.strands[2] = speed;
            queue.write_buffer(&s.params, 0, bytemuck::bytes_of(&p));
        }
        if let Some(b) = &mut self.blades {
            let bend_near = cx.options.grass_bend;
            let hit = patches.hit.filter(|_| bend_near).map_or([0.0; 4], |h| [h.x, h.y, h.z, HIT_RADIUS]);
            let eye_radius = if bend_near { EYE_RADIUS } else { 0.0 };
            let (lod_near, lod_mid) = data::lod_distances(cx.size.1, cx.common.camera.fov_y);
            let (list, far_base) = blocks::block_lists(&b.blocks, &planes, eye, FAR_DISTANCE, lod_mid);
            b.dispatch = [far_base, list.len() as u32 - far_base];
            if !list.is_empty() {
                queue.write_buffer(&b.lists, 8 * u64::from(b.count), bytemuck::cast_slice(&list));
            }
            let cull = CullParams {
                planes,
                camera: [eye.x, eye.y, eye.z, FAR_DISTANCE],
                lod_near,
                lod_mid,
                count: b.count,
                far_base,
                wind: [w.direction[0], w.direction[1], bend, time],
                wind_noise: [speed, WIND_SCALE, 0.0, 0.0],
                eye: [eye.x, eye.y, eye.z, eye_radius],
                hit,
                view_proj: view_proj.to_cols_array_2d(),
            };
            queue.write_buffer(&b.cull_params, 0, bytemuck::bytes_of(&cull));
            let camera = glam::Mat4::from_rotation_translation(cx.common.camera.rotation, cx.common.camera.position);
            let (depth_a, depth_b) = data::depth_of_view_depth(view_proj, camera);
            // The sun as the frame's uniforms give it (src/render/frame.rs).
            let light = super::lighting::sun_light(cx.common.sun_elevation_deg);
            let params = BladeParams {
                colours: b.colours,
                viewport: [cx.size.0 as f32, cx.size.1 as f32, data::FAR_DEPTH_RANGE, 0.0],
                depth: [depth_a, depth_b, 0.0, 0.0],
                sun_dir: cx.common.sun_dir.extend(0.0).to_array(),
                sun_color: light.direct.extend(0.0).to_array(),
                ambient: light.ambient.extend(0.0).to_array(),
            };
            queue.write_buffer(&b.draw_params, 0, bytemuck::bytes_of(&params));
            // The two indexed indirect draws: nothing until the cull pass, one instance each,
            // the middle draw's base vertex at its list; no far blade yet.
            let mid_vertices = 2 * data::LOD_SEGMENTS[1] + 1;
            let args: [u32; data::ARGS_WORDS] = [0, 1, 0, 0, 0, 0, 1, 0, mid_vertices * b.count, 0, 0, u32::MAX, u32::MAX, 0, 0];
            queue.write_buffer(&b.args, 0, bytemuck::cast_slice(&args));
        }
        let (sm, sl, bm, bl) = (&self.shell_module, &self.shell_layout, &self.blade_module, &self.blade_layout);
        self.shell_pipelines.prepare(cx.key, |k| build_shells(cx.shared, sm, sl, k))?;
        Ok(self.blade_pipelines.prepare(cx.key, |k| build_blades(cx.shared, bm, bl, k))?)
    }

    fn draw<'p>(&'p self, phase: Phase, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey, stats: &mut FrameStats) -> Result<(), RenderError> {
        if phase != Phase::Opaque || !self.enabled {
            return Ok(());
        }
        if let Some(b) = &self.blades {
            pass.set_bind_group(2, &b.draw_group, &[]);
            // Nearest first, so that near blades hide the ones behind them before they are shaded.
            let [near, mid, far] = self.blade_pipelines.get(key)?;
            for (k, pipeline) in [near, mid].into_iter().enumerate() {
                pass.set_pipeline(pipeline);
                pass.set_index_buffer(b.indices[k].slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed_indirect(&b.args, 20 * k as u64);
            }
            // The far blades' image over the scene: a rectangle around them.
            pass.set_pipeline(far);
            pass.draw(0..6, 0..1);
            stats.draws += 3;
        }
        if !self.shells.is_empty() {
            pass.set_pipeline(self.shell_pipelines.get(key)?);
            for s in &self.shells {
                pass.set_bind_group(2, &s.bind_group, &[]);
                pass.set_vertex_buffer(0, s.vertices.slice(..));
                // Each tile in view once: the fragments walk the layers.
                for (tile, _) in s.tiles.iter().zip(&s.tile_visible).filter(|(_, shown)| **shown) {
                    pass.draw(tile.first_vertex..tile.first_vertex + tile.vertex_count, 0..1);
                    stats.draws += 1;
                    stats.triangles += (tile.vertex_count / 3) as usize;
                }
            }
        }
        Ok(())
    }
}

/// The indirect draws' buffer for a frame of `size` pixels: the two indexed draws and the far
/// blades' count, then from word [`data::RASTER_OFFSET`] the far blades' image, one word a
/// pixel (`args` in cull.wgsl).
fn args_buffer(device: &wgpu::Device, size: (u32, u32)) -> wgpu::Buffer {
    let pixels = u64::from(size.0.max(1)) * u64::from(size.1.max(1));
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("grass indirect draws and far blades"),
        size: 4 * (data::RASTER_OFFSET + pixels),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}
