//! Trees: instanced, textured (albedo, normal, specular), alpha-clipped leaves, swayed per
//! vertex by the wind (`wind.wgsl`, the twin of `grove_systems::wind_model`), casting shadows.
//! Far trees draw a share of their leaves, grown to keep the crown's area ([`lod`]).
//!
//! Phases: [`Phase::Opaque`] draws the opaque materials, [`Phase::AlphaClipped`] the depth
//! pre-pass and then the shading of the alpha-clipped ones (see [`pipelines`]); the shadow map
//! gets both from [`Feature::draw_depth`].

mod extract;
mod models;
pub mod impostor;
pub mod instances;
pub mod lod;
pub mod model;
pub(crate) mod pipelines;

use glam::Vec3;

use self::impostor::draw::ImpostorGpu;
use self::instances::{gather, BucketRanges, Detail, Instance};
use self::model::{GpuMaterial, GpuModel};
use self::pipelines::TreePipelines;
use self::extract::TreeDraw;
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use crate::render::error::{PipelineError, RenderError};
use super::gpu::{PipelineCache, PipelineKey, Shared, ViewKind};


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
    /// This frame's instance count.
    pub instance_count: usize,
    /// This frame's instance range of each (model, keep bucket).
    ranges: Vec<BucketRanges>,
    /// The impostors' bake, shader and pipelines.
    pub(crate) impostors: ImpostorGpu,
    impostor_instances: wgpu::Buffer,
    /// The folder of the impostor atlas cache (`None`: every model is baked).
    pub(crate) impostor_cache: Option<std::path::PathBuf>,
    /// How many atlases were baked rather than read from the cache.
    pub(crate) impostor_bakes: usize,
    impostor_capacity: usize,
    /// This frame's impostor instance range of each model.
    impostor_ranges: Vec<std::ops::Range<u32>>,
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
            module: shared.shader("trees.wgsl", include_str!("trees.wgsl")),
            lit_layout: shared.layout("tree lit layout", &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&shared.material_layout)]),
            shadow_layout: shared.layout("tree shadow layout", &[Some(&shared.view_layout), None, Some(&shared.material_layout)]),
            pipelines: PipelineCache::new("trees"),
            models: Vec::new(),
            far: Vec::new(),
            instances: instance_buffer(&shared.device, capacity),
            capacity,
            instance_count: 0,
            ranges: Vec::new(),
            impostors: ImpostorGpu::new(shared),
            impostor_instances: instance_buffer(&shared.device, capacity),
            impostor_cache: impostor::cache::default_dir(),
            impostor_bakes: 0,
            impostor_capacity: capacity,
            impostor_ranges: Vec::new(),
            shared: shared.clone(),
        }
    }

    /// Bakes and binds the impostor atlases of `model` (see [`impostor`]), or reads them from
    /// the cache folder `impostor_cache` where a file for this model and bake is there. A file
    /// that cannot be read is reported in one line on stderr and replaced by a new bake; a cache
    /// that cannot be written is reported and otherwise ignored.
    fn bake_impostor(&mut self, model: &mut GpuModel, data: &super::assets::gltf_load::ModelData) {
        let shared = &self.shared;
        let positions: Vec<Vec3> = data.primitives.iter().flat_map(|p| p.vertices.iter().map(|v| Vec3::from(v.position))).collect();
        let key = impostor::cache::model_key(data, &impostor::bake::bake_wgsl());
        let path = self.impostor_cache.as_deref().map(|d| impostor::cache::file_path(d, &model.name, key));
        let mut atlas = None;
        if let Some(p) = path.as_deref().filter(|p| p.exists()) {
            match grove_systems::files::read(p, grove_systems::files::Kind::Cache).map_err(impostor::cache::AtlasError::Read).and_then(|b| impostor::cache::decode(&b, key)) {
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

    /// Draws each model's impostors over its range of the impostor instances (pipeline set).
    fn draw_impostors<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, mut count: impl FnMut(&std::ops::Range<u32>)) {
        pass.set_vertex_buffer(0, self.impostor_instances.slice(..));
        for (m, range) in self.models.iter().zip(&self.impostor_ranges) {
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

    /// Draws every tree primitive whose material is of the kind `which`, instanced over its
    /// model's range of the instance buffer, with its material bound. `before_draw` runs just
    /// before each draw, to pick the pipeline or count what is drawn; the shadow pass sets its
    /// pipeline beforehand.
    fn draw_trees<'p>(
        &'p self,
        pass: &mut wgpu::RenderPass<'p>,
        which: Materials,
        mut before_draw: impl FnMut(&mut wgpu::RenderPass<'p>, &'p GpuMaterial, u32, &std::ops::Range<u32>),
    ) {
        pass.set_vertex_buffer(1, self.instances.slice(..));
        for (m, buckets) in self.models.iter().zip(&self.ranges) {
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
        let detail = Detail { leaf_pixels: cx.options.leaf_pixels, impostor_pixels: cx.options.impostor_pixels, far_pixels: cx.options.far_pixels };
        let g = gather(&trees, &self.models, &self.far, &cx.common.camera, cx.size.1, detail);
        let instances = g.instances;
        if instances.len() > self.capacity {
            self.capacity = instances.len().next_power_of_two();
            self.instances = instance_buffer(&cx.shared.device, self.capacity);
        }
        if !instances.is_empty() {
            cx.shared.queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&instances));
        }
        if g.impostors.len() > self.impostor_capacity {
            self.impostor_capacity = g.impostors.len().next_power_of_two();
            self.impostor_instances = instance_buffer(&cx.shared.device, self.impostor_capacity);
        }
        if !g.impostors.is_empty() {
            cx.shared.queue.write_buffer(&self.impostor_instances, 0, bytemuck::cast_slice(&g.impostors));
        }
        self.instance_count = instances.len() + g.impostors.len();
        self.ranges = g.ranges;
        self.impostor_ranges = g.impostor_ranges;
        self.impostors.prepare(cx.shared, cx.key)?;
        if cx.key.shadows {
            self.impostors.prepare(cx.shared, cx.key.with_view(ViewKind::Sun))?;
        }
        let (module, lit, shadow) = (&self.module, &self.lit_layout, &self.shadow_layout);
        self.pipelines.prepare(cx.key, |k| pipelines::build(cx.shared, module, lit, shadow, k))?;
        if cx.key.shadows {
            self.pipelines.prepare(cx.key.with_view(ViewKind::Sun), |k| pipelines::build(cx.shared, module, lit, shadow, k))?;
        }
        Ok(())
    }

    fn draw_depth<'p>(&'p self, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey) -> Result<(), RenderError> {
        let TreePipelines::Shadow(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NotShadowKey { feature: "trees", key }.into());
        };
        pass.set_pipeline(&p.opaque);
        self.draw_trees(pass, Materials::Opaque, |_, _, _, _| {});
        pass.set_pipeline(&p.masked);
        self.draw_trees(pass, Materials::Masked, |_, _, _, _| {});
        pass.set_pipeline(&self.impostors.pipelines.get(key)?.depth);
        self.draw_impostors(pass, |_| {});
        Ok(())
    }

    fn draw<'p>(&'p self, phase: Phase, pass: &mut wgpu::RenderPass<'p>, key: PipelineKey, stats: &mut FrameStats) -> Result<(), RenderError> {
        let TreePipelines::Main(p) = self.pipelines.get(key)? else {
            return Err(PipelineError::NotMainKey { feature: "trees", key }.into());
        };
        let mut count = |count: u32, range: &std::ops::Range<u32>| {
            stats.draws += 1;
            stats.triangles += count as usize / 3 * range.len();
        };
        match phase {
            Phase::Opaque => self.draw_trees(pass, Materials::Opaque, |pass, mat, n, range| {
                pass.set_pipeline(&p.opaque[mat.double_sided as usize]);
                count(n, range);
            }),
            Phase::AlphaClipped => {
                self.draw_trees(pass, Materials::Masked, |pass, mat, _, _| pass.set_pipeline(&p.masked_depth[mat.double_sided as usize]));
                self.draw_trees(pass, Materials::Masked, |pass, mat, n, range| {
                    pass.set_pipeline(&p.masked_shade[mat.double_sided as usize]);
                    count(n, range);
                });
                // Impostors: their depth pre-pass, then their shading at equal depth.
                let imp = self.impostors.pipelines.get(key)?;
                pass.set_pipeline(&imp.depth);
                self.draw_impostors(pass, |_| {});
                if let Some(shade) = &imp.shade {
                    pass.set_pipeline(shade);
                    self.draw_impostors(pass, |range| count(6, range));
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
