//! Trees: instanced, textured (albedo, normal, specular), alpha-clipped leaves, swayed per
//! vertex by the wind (`wind.wgsl`, the twin of `grove_systems::wind_model`), casting shadows.
//! Far trees draw a share of their leaves, grown to keep the crown's area ([`lod`]). Each pass
//! draws only the trees that may reach into its view, and the shadow map those whose shadows may
//! ([`Trees::cull`], [`views`]).
//!
//! Phases: [`Phase::Opaque`] draws the opaque materials, [`Phase::AlphaClipped`] the depth
//! pre-pass and then the shading of the alpha-clipped ones (see [`pipelines`]); the shadow map
//! gets both from [`Feature::draw_depth`].

mod extract;
pub mod impostor;
pub mod instances;
pub mod lod;
pub mod model;
mod models;
pub(crate) mod pipelines;
pub mod sweep;
pub(crate) mod views;

use glam::Vec3;

use self::extract::TreeDraw;
use self::impostor::draw::ImpostorGpu;
use self::instances::{BucketRanges, Detail, Gathered, Instance, gather};
use self::model::{GpuMaterial, GpuModel};
use self::pipelines::TreePipelines;
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, Shared, ViewKind};
use crate::render::clip::ClipRegion;
use crate::render::error::{PipelineError, RenderError};

/// Which trees a pass draws (see [`views`] and [`Trees::cull`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TreeView {
    /// The trees whose shadows may fall into a view: the sun's shadow map.
    Casters,
    /// The trees that may reach into the main view.
    Main,
    /// The trees that may reach into the extra view of this index ([`Trees::cull`]).
    Extra(usize),
}

impl TreeView {
    fn index(self) -> usize {
        match self {
            TreeView::Casters => 0,
            TreeView::Main => 1,
            TreeView::Extra(i) => 2 + i,
        }
    }
}

/// The trees feature: the models, this frame's instances and the pipelines by key. Its own
/// methods load models and read back what was loaded ([`models`]).
pub struct Trees {
    shared: Shared,
    module: wgpu::ShaderModule,
    lit_layout: wgpu::PipelineLayout,
    shadow_layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<TreePipelines>,
    /// The models, by catalogue index.
    pub models: Vec<Option<GpuModel>>,
    /// Each model's far model, by catalogue index ([`Trees::set_far`]).
    pub(crate) far: Vec<Option<usize>>,
    instances: wgpu::Buffer,
    capacity: usize,
    /// This frame's instance count in the main view (meshes and impostors).
    pub instance_count: usize,
    /// The tree instances the shadow map draws this frame (set by [`Trees::cull`]).
    pub shadow_instance_count: usize,
    /// This frame's trees as gathered, before culling (`None` before the first frame).
    every: Option<Gathered>,
    /// Each view's instance range of each (model, keep bucket), in the uploaded buffer.
    ranges: Vec<Vec<BucketRanges>>,
    /// The impostors' bake, shader and pipelines.
    pub(crate) impostors: ImpostorGpu,
    impostor_instances: wgpu::Buffer,
    /// The folder of the impostor atlas cache (`None`: every model is baked).
    pub(crate) impostor_cache: Option<std::path::PathBuf>,
    /// How many atlases were baked rather than read from the cache.
    pub(crate) impostor_bakes: usize,
    impostor_capacity: usize,
    /// Each view's impostor instance range of each model, in the uploaded buffer.
    impostor_ranges: Vec<Vec<std::ops::Range<u32>>>,
    /// The wind of this frame (for the trees' boxes; `None` before the first frame).
    wind: Option<grove_systems::wind_model::WindParams>,
}

/// Which tree materials a loop over the trees draws.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Materials {
    Opaque,
    Masked,
}

impl Trees {
    /// The feature with no models yet.
    pub(crate) fn new(shared: &Shared) -> Trees {
        let capacity = 1024;
        Trees {
            module: shared.shader_with("trees.wgsl", include_str!("trees.wgsl"), &[model::MATERIAL_PIECE]),
            lit_layout: shared.layout(
                "tree lit layout",
                &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&shared.material_layout)],
            ),
            shadow_layout: shared
                .layout("tree shadow layout", &[Some(&shared.view_layout), None, Some(&shared.material_layout)]),
            pipelines: PipelineCache::new("trees"),
            models: Vec::new(),
            far: Vec::new(),
            instances: instance_buffer(&shared.device, capacity),
            capacity,
            instance_count: 0,
            shadow_instance_count: 0,
            every: None,
            ranges: Vec::new(),
            impostors: ImpostorGpu::new(shared),
            impostor_instances: instance_buffer(&shared.device, capacity),
            impostor_cache: impostor::cache::default_dir(),
            impostor_bakes: 0,
            impostor_capacity: capacity,
            impostor_ranges: Vec::new(),
            wind: None,
            shared: shared.clone(),
        }
    }

    /// Bakes and binds the impostor atlases of `model` (see [`impostor`]), or reads them from
    /// the cache folder `impostor_cache` where a file for this model and bake is there. A file
    /// that cannot be read is reported in one line on stderr and replaced by a new bake; a cache
    /// that cannot be written is reported and otherwise ignored.
    fn bake_impostor(&mut self, model: &mut GpuModel, data: &crate::models::ModelData) {
        let shared = &self.shared;
        let positions: Vec<Vec3> =
            data.primitives.iter().flat_map(|p| p.vertices.iter().map(|v| Vec3::from(v.position))).collect();
        let key = impostor::cache::model_key(data, &impostor::bake::bake_wgsl());
        let path = self.impostor_cache.as_deref().map(|d| impostor::cache::file_path(d, &model.name, key));
        let mut atlas = None;
        if let Some(p) = path.as_deref().filter(|p| p.exists()) {
            match grove_systems::files::read(p, grove_systems::files::Kind::Cache)
                .map_err(impostor::cache::AtlasError::Read)
                .and_then(|b| impostor::cache::decode(&b, key))
            {
                Ok(levels) => atlas = self.impostors.baker.from_levels(shared, model, &positions, &levels),
                Err(e) => eprintln!("warning: impostor cache {}: {e}; baking it again", p.display()),
            }
        }
        if atlas.is_none() {
            atlas = self.impostors.baker.bake(shared, model, &positions);
            self.impostor_bakes += usize::from(atlas.is_some());
            if let (Some(a), Some(p)) = (&atlas, &path) {
                if let Err(e) = impostor::cache::store(&shared.device, &shared.queue, [&a.albedo, &a.normal], p, key) {
                    eprintln!("warning: impostor cache: {e}");
                }
            }
        }
        model.impostor = atlas.map(|mut atlas| {
            self.impostors.bind(shared, &mut atlas);
            atlas
        });
    }

    /// Culls this frame's trees for every pass: the main view's (`main`), each extra view's
    /// (`extra`, [`TreeView::Extra`] in order) and the shadow map's, which keeps the trees that
    /// may reach into the sun's view (`light`, the shadow map's clip volume: a tree wholly
    /// outside it draws nothing there) and whose shadow, cast away from the sun (`sun`: the unit
    /// vector towards it and the lowest height a shadow can fall on), may reach into one of those
    /// views (any shadow when `sun` is `None`). The shadow map draws its trees with no more
    /// leaves than it can show at `shadow_texels_per_metre` ([`views::shadow_detail`]). Uploads
    /// every view's instances. Call after [`Feature::prepare`]. Without `enabled`, every view
    /// draws every tree.
    pub(crate) fn cull(
        &mut self,
        main: &ClipRegion,
        extra: &[ClipRegion],
        sun: Option<(Vec3, f32)>,
        light: &ClipRegion,
        shadow_texels_per_metre: f32,
        enabled: bool,
    ) {
        let (Some(every), Some(wind)) = (&self.every, &self.wind) else { return };
        let models = &self.models;
        let leaf_area = |m: usize| models.get(m).and_then(Option::as_ref).map(|model| model.leaf_area);
        if !enabled {
            self.instance_count = every.instances.len() + every.impostors.len();
            self.shadow_instance_count = self.instance_count;
            let mut all = vec![every.clone(); 2 + extra.len()];
            all[TreeView::Casters.index()] = views::shadow_detail(every, leaf_area, shadow_texels_per_metre);
            self.upload(&all);
            return;
        }
        let inside = |r: &ClipRegion| views::cull(every, models, wind, |lo, hi| r.may_hold(lo, hi));
        let receivers: Vec<&ClipRegion> = std::iter::once(main).chain(extra).collect();
        let casters = views::cull(every, models, wind, |lo, hi| {
            let shadow = sun.and_then(|(dir, floor)| views::shadow_box(lo, hi, dir, floor));
            light.may_hold(lo, hi) && shadow.is_none_or(|(lo, hi)| receivers.iter().any(|r| r.may_hold(lo, hi)))
        });
        let casters = views::shadow_detail(&casters, leaf_area, shadow_texels_per_metre);
        self.shadow_instance_count = casters.instances.len() + casters.impostors.len();
        let main = inside(main);
        self.instance_count = main.instances.len() + main.impostors.len();
        let views: Vec<Gathered> = [casters, main].into_iter().chain(extra.iter().map(inside)).collect();
        self.upload(&views);
    }

    /// Writes the instances of `views` (by [`TreeView::index`]) one after the other into the
    /// instance buffers (grown as needed) and keeps each view's ranges, moved to its place there.
    fn upload(&mut self, views: &[Gathered]) {
        let shift = |r: &std::ops::Range<u32>, by: u32| r.start + by..r.end + by;
        let (mut meshes, mut impostors) = (Vec::new(), Vec::new());
        self.ranges.clear();
        self.impostor_ranges.clear();
        for v in views {
            let (a, b) = (meshes.len() as u32, impostors.len() as u32);
            self.ranges.push(v.ranges.iter().map(|buckets| buckets.each_ref().map(|r| shift(r, a))).collect());
            self.impostor_ranges.push(v.impostor_ranges.iter().map(|r| shift(r, b)).collect());
            meshes.extend_from_slice(&v.instances);
            impostors.extend_from_slice(&v.impostors);
        }
        let device = &self.shared.device;
        if meshes.len() > self.capacity {
            self.capacity = meshes.len().next_power_of_two();
            self.instances = instance_buffer(device, self.capacity);
        }
        if !meshes.is_empty() {
            self.shared.queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&meshes));
        }
        if impostors.len() > self.impostor_capacity {
            self.impostor_capacity = impostors.len().next_power_of_two();
            self.impostor_instances = instance_buffer(device, self.impostor_capacity);
        }
        if !impostors.is_empty() {
            self.shared.queue.write_buffer(&self.impostor_instances, 0, bytemuck::cast_slice(&impostors));
        }
    }

    /// Draws each model's impostors of `view` over its range of the impostor instances
    /// (pipeline set).
    fn draw_impostors<'p>(
        &'p self,
        pass: &mut wgpu::RenderPass<'p>,
        view: TreeView,
        mut count: impl FnMut(&std::ops::Range<u32>),
    ) {
        let Some(ranges) = self.impostor_ranges.get(view.index()) else { return };
        pass.set_vertex_buffer(0, self.impostor_instances.slice(..));
        for (m, range) in self.models.iter().zip(ranges) {
            let Some(Some(group)) = m.as_ref().map(|m| m.impostor.as_ref().and_then(|a| a.bind_group.as_ref())) else {
                continue;
            };
            if range.is_empty() {
                continue;
            }
            pass.set_bind_group(2, group, &[]);
            count(range);
            pass.draw(0..6, range.clone());
        }
    }

    /// Draws every tree primitive of `view` whose material is of the kind `which`, instanced
    /// over its model's range of the instance buffer, with its material bound. `before_draw` runs just
    /// before each draw, to pick the pipeline or count what is drawn; the shadow pass sets its
    /// pipeline beforehand.
    fn draw_trees<'p>(
        &'p self,
        pass: &mut wgpu::RenderPass<'p>,
        view: TreeView,
        which: Materials,
        mut before_draw: impl FnMut(&mut wgpu::RenderPass<'p>, &'p GpuMaterial, u32, &std::ops::Range<u32>),
    ) {
        let Some(ranges) = self.ranges.get(view.index()) else { return };
        pass.set_vertex_buffer(1, self.instances.slice(..));
        for (m, buckets) in self.models.iter().zip(ranges) {
            let Some(m) = m else { continue };
            for p in &m.primitives {
                let Some(mat) = m.materials.get(p.material) else {
                    continue;
                };
                if mat.masked != (which == Materials::Masked) {
                    continue;
                }
                pass.set_bind_group(2, &mat.bind_group, &[]);
                pass.set_vertex_buffer(0, p.vertices.slice(..));
                pass.set_vertex_buffer(2, p.leaves.slice(..));
                pass.set_index_buffer(p.indices.slice(..), wgpu::IndexFormat::Uint32);
                for (range, &count) in buckets.iter().zip(&p.index_counts) {
                    if range.is_empty() {
                        continue;
                    }
                    before_draw(pass, mat, count, range);
                    pass.draw_indexed(0..count, 0, range.clone());
                }
            }
        }
    }
}

impl Feature for Trees {
    type Extracted = Vec<TreeDraw>;

    fn extract(&self, sim: &grove_systems::Sim, cx: &ExtractContext<'_>) -> Vec<TreeDraw> {
        extract::trees(sim, cx)
    }

    /// Whether any tree of the frame has a loaded model.
    fn casts_shadows(&self, trees: &Vec<TreeDraw>) -> bool {
        trees.iter().any(|t| matches!(self.models.get(t.model), Some(Some(_))))
    }

    fn shadow_bounds(&self, trees: &Vec<TreeDraw>) -> Option<(Vec3, Vec3)> {
        instances::bounds(trees, &self.models)
    }

    fn prepare(&mut self, cx: &FrameContext<'_>, trees: Vec<TreeDraw>) -> Result<(), RenderError> {
        let detail = Detail {
            leaf_pixels: cx.options.leaf_pixels,
            impostor_pixels: cx.options.impostor_pixels,
            far_pixels: cx.options.far_pixels,
            cross_fade: cx.options.lod_cross_fade,
        };
        let g = gather(&trees, &self.models, &self.far, &cx.common.camera, cx.size.1, detail);
        self.wind = Some(cx.common.wind);
        self.every = Some(g);
        self.ranges.clear();
        self.impostor_ranges.clear();
        self.instance_count = 0;
        self.shadow_instance_count = 0;
        self.impostors.prepare(cx.shared, cx.key)?;
        if cx.key.shadows {
            self.impostors.prepare(cx.shared, cx.key.with_view(ViewKind::Sun))?;
        }
        let (module, lit, shadow) = (&self.module, &self.lit_layout, &self.shadow_layout);
        self.pipelines.prepare(cx.key, |k| pipelines::build(cx.shared, module, lit, shadow, k))?;
        if cx.key.shadows {
            self.pipelines
                .prepare(cx.key.with_view(ViewKind::Sun), |k| pipelines::build(cx.shared, module, lit, shadow, k))?;
        }
        Ok(())
    }

    fn draw_depth<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey) -> Result<(), RenderError> {
        let TreePipelines::Shadow(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NotShadowKey { feature: "trees", key }.into());
        };
        pass.set_pipeline(&p.opaque);
        self.draw_trees(pass, TreeView::Casters, Materials::Opaque, |_, _, _, _| {});
        pass.set_pipeline(&p.masked);
        self.draw_trees(pass, TreeView::Casters, Materials::Masked, |_, _, _, _| {});
        pass.set_pipeline(&self.impostors.pipelines.get(key)?.depth);
        self.draw_impostors(pass, TreeView::Casters, |_| {});
        Ok(())
    }

    fn draw<'p>(
        &'p self,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        self.draw_view(TreeView::Main, phase, pass, key, stats)
    }
}

impl Trees {
    /// [`Feature::draw`] for the trees of `view`.
    pub(crate) fn draw_view<'p>(
        &'p self,
        view: TreeView,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        let TreePipelines::Main(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NotMainKey { feature: "trees", key }.into());
        };
        let mut count = |count: u32, range: &std::ops::Range<u32>| {
            stats.draws += 1;
            stats.triangles += count as usize / 3 * range.len();
        };
        match phase {
            Phase::Opaque => self.draw_trees(pass, view, Materials::Opaque, |pass, mat, n, range| {
                pass.set_pipeline(&p.opaque[mat.double_sided as usize]);
                count(n, range);
            }),
            Phase::AlphaClipped => {
                self.draw_trees(pass, view, Materials::Masked, |pass, mat, _, _| {
                    pass.set_pipeline(&p.masked_depth[mat.double_sided as usize])
                });
                self.draw_trees(pass, view, Materials::Masked, |pass, mat, n, range| {
                    pass.set_pipeline(&p.masked_shade[mat.double_sided as usize]);
                    count(n, range);
                });
                // Impostors: their depth pre-pass, then their shading at equal depth.
                let imp = self.impostors.pipelines.get(key)?;
                pass.set_pipeline(&imp.depth);
                self.draw_impostors(pass, view, |_| {});
                if let Some(shade) = &imp.shade {
                    pass.set_pipeline(shade);
                    self.draw_impostors(pass, view, |range| count(6, range));
                }
            }
            Phase::Sky | Phase::Blended | Phase::Overlay => {}
        }
        Ok(())
    }
}

fn instance_buffer(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tree instances"),
        size: (capacity * std::mem::size_of::<Instance>()) as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
