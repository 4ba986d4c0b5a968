//! Ground: the planes' meshes, textured in world space at several scales, lit and shadowed (a
//! shadow receiver only; it casts none), as a landscape ([`landscape`]): the planes' sides as
//! earth banks and pits ([`banks`]), a soil floor seen through the holes, and terrain out to
//! the far plane fading into the sky. The mesh is rebuilt only when the planes change
//! ([`GroundKey`]).

pub mod banks;
mod extract;
pub mod landscape;
pub mod texture;

use std::path::Path;

use crate::render::error::{PipelineError, RenderError};
use wgpu::util::DeviceExt;

use self::extract::{GroundKey, PlaneMesh, Planes};
use super::assets::textures;
use super::feature::{ExtractContext, Feature, FrameContext, FrameStats, Phase};
use super::gpu::{PipelineCache, PipelineKey, PipelineSpec, Shared, ViewKind, color_target, depth_test};
use crate::models::gltf_load;

/// The ground's uniforms (matches `GroundParams` in ground.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct GroundParams {
    /// Metres per repeat of the ground texture.
    metres_per_repeat: f32,
    /// Padding to 16 bytes.
    pad: [f32; 3],
}

/// The planes' mesh on the GPU: the near ground (planes, sides, floor and the terrain next to
/// them) in `0..near_count` of the indices, the far terrain in `near_count..index_count`.
struct Mesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    near_count: u32,
    index_count: u32,
}

/// The ground feature.
pub(crate) struct Ground {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<wgpu::RenderPipeline>,
    /// The far terrain's pipelines: one texture scale, no shadow lookups (`fs_far`).
    far_pipelines: PipelineCache<wgpu::RenderPipeline>,
    bind_group: wgpu::BindGroup,
    /// The key of the planes `mesh` was built from.
    key: GroundKey,
    mesh: Option<Mesh>,
}

impl Ground {
    /// The feature with the ground texture `assets/env/ground.png` (2.5 m a repeat), widened
    /// ([`texture::widen`]).
    pub fn new(shared: &Shared, assets: &Path) -> Result<Ground, RenderError> {
        let path = assets.join("env").join("ground.png");
        let img = textures::read_image(&path)?.to_rgba8();
        let img = texture::widen(&img);
        // Encoded bytes in a linear format, decoded in the shader after filtering (`ENCODED_FORMAT`).
        let texture = textures::upload_2d_encoded(
            &shared.device,
            &shared.queue,
            "ground albedo",
            img.width(),
            img.height(),
            img.as_raw(),
        );
        let params = shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ground parameters"),
            contents: bytemuck::bytes_of(&GroundParams {
                metres_per_repeat: 2.5 * texture::WIDEN as f32,
                pad: [0.0; 3],
            }),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        Ok(Ground {
            module: shared.shader("ground.wgsl", include_str!("ground.wgsl")),
            layout: shared.layout(
                "ground layout",
                &[Some(&shared.view_layout), Some(&shared.lighting_layout), Some(&shared.material_layout)],
            ),
            pipelines: PipelineCache::new("ground"),
            far_pipelines: PipelineCache::new("far ground"),
            bind_group: bind_group(shared, &params, &texture),
            key: Vec::new(),
            mesh: None,
        })
    }

    /// Rebuilds the mesh from the planes (positions, smooth normals, the kind and the tint, 10
    /// floats a vertex), their sides, the floor under them and the terrain around them.
    fn rebuild(&mut self, shared: &Shared, key: &GroundKey, planes: &[PlaneMesh]) {
        let mut land = landscape::LandMesh::default();
        let mut far = landscape::LandMesh::default();
        let (mut lo, mut hi) = (glam::Vec3::splat(f32::MAX), glam::Vec3::splat(f32::MIN));
        // The longest mean edge of any plane's triangles, metres: how fine the coarsest plane's
        // mesh is, which decides the wavelength of the tint's detail.
        let mut coarsest = 0.0f32;
        for p in planes {
            coarsest = coarsest.max(landscape::mean_edge(&p.vertices, &p.triangles));
            let base = land.vertices.len() as u32;
            let tris: Vec<u32> =
                p.triangles.iter().flatten().copied().filter(|&i| (i as usize) < p.vertices.len()).collect();
            let normals = gltf_load::compute_normals(&p.vertices, &tris);
            for (v, n) in p.vertices.iter().zip(&normals) {
                land.vertices.push([v.x, v.y, v.z, n.x, n.y, n.z, landscape::KIND_PLANE, 1.0]);
                lo = lo.min(*v);
                hi = hi.max(*v);
            }
            land.indices.extend(tris.iter().map(|i| i + base));
        }
        if !land.indices.is_empty() {
            let floor_y = lo.y - landscape::FLOOR_DEPTH;
            landscape::surroundings(
                &mut land,
                &mut far,
                glam::Vec2::new(lo.x, lo.z),
                glam::Vec2::new(hi.x, hi.z),
                lo.y,
                floor_y,
            );
            // The sides after the terrain: most of a bank lies under the ground next to it,
            // which, drawn first, lets the early depth test skip that part.
            for p in planes {
                banks::sides(&mut land, &p.vertices, &p.triangles, floor_y);
            }
        }
        // The far terrain after the near ground, in one buffer.
        let near_count = land.indices.len() as u32;
        let base = land.vertices.len() as u32;
        land.vertices.extend_from_slice(&far.vertices);
        land.indices.extend(far.indices.iter().map(|i| i + base));
        // Each vertex's tint: the ground's variation at scales above the texture's.
        let tint = landscape::Tint::for_mesh(coarsest);
        let (rect_lo, rect_hi) = (glam::Vec2::new(lo.x, lo.z), glam::Vec2::new(hi.x, hi.z));
        let verts: Vec<[f32; 10]> = land
            .vertices
            .iter()
            .map(|v| {
                let p = glam::Vec2::new(v[0], v[2]);
                // Soil takes no tint, only its shade.
                let soil = v[6] == landscape::KIND_SIDE || v[6] == landscape::KIND_FLOOR;
                let [r, g, b] = if soil { [1.0; 3] } else { tint.at(p, landscape::detail_weight(p, rect_lo, rect_hi)) };
                [v[0], v[1], v[2], v[3], v[4], v[5], v[6], r * v[7], g * v[7], b * v[7]]
            })
            .collect();
        let idx = land.indices;
        self.key = key.clone();
        if idx.is_empty() {
            self.mesh = None;
            return;
        }
        let buffer = |label, contents: &[u8], usage| {
            shared.device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents, usage })
        };
        self.mesh = Some(Mesh {
            vertices: buffer("ground vertices", bytemuck::cast_slice(&verts), wgpu::BufferUsages::VERTEX),
            indices: buffer("ground indices", bytemuck::cast_slice(&idx), wgpu::BufferUsages::INDEX),
            near_count,
            index_count: idx.len() as u32,
        });
    }
}

/// The ground's bind group: the material layout with the ground's own sampler, which filters
/// within one mip level (bilinear) and picks the nearest level rather than blending two. On a
/// software rasteriser that halves the texels a ground pixel reads; the ground texture is noise
/// at every level, so the change of level does not show.
fn bind_group(shared: &Shared, params: &wgpu::Buffer, texture: &wgpu::TextureView) -> wgpu::BindGroup {
    let sampler = shared.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("ground sampler"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        ..Default::default()
    });
    shared.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("ground bind group"),
        layout: &shared.material_layout,
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(texture) },
            wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&shared.flat_normal) },
            wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&shared.white) },
            wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::Sampler(&sampler) },
        ],
    })
}

/// The ground's pipeline of `key`: main view only. With `far`, the far terrain's: the fragment
/// entry `fs_far`, built without shadow lookups whatever the key says (the shadow map does not
/// reach that far).
fn build(
    shared: &Shared,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    key: PipelineKey,
    far: bool,
) -> Result<wgpu::RenderPipeline, PipelineError> {
    if key.view != ViewKind::Main {
        return Err(PipelineError::MainViewOnly("the ground"));
    }
    const GV: [wgpu::VertexAttribute; 4] =
        wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32, 3 => Float32x3];
    let label = match (far, key.shadows) {
        (true, _) => "far ground pipeline",
        (false, true) => "ground pipeline (shadows)",
        (false, false) => "ground pipeline (no shadows)",
    };
    let constants = if far { [("SHADOWS", 0.0)] } else { key.lit_constants() };
    Ok(shared.pipeline(&PipelineSpec {
        label,
        layout,
        module,
        vertex: "vs_main",
        fragment: Some(if far { "fs_far" } else { "fs_main" }),
        buffers: &[Some(wgpu::VertexBufferLayout {
            array_stride: 40,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &GV,
        })],
        topology: wgpu::PrimitiveTopology::TriangleList,
        cull: None,
        depth: depth_test(true, wgpu::CompareFunction::Less),
        targets: &color_target(key.format, wgpu::ColorWrites::ALL),
        constants: &constants,
    }))
}

impl Feature for Ground {
    type Extracted = Planes;

    fn extract(&self, sim: &grove_systems::Sim, _cx: &ExtractContext<'_>) -> Planes {
        extract::planes(sim, &self.key)
    }

    fn shadow_bounds(&self, planes: &Planes) -> Option<(glam::Vec3, glam::Vec3)> {
        planes.bounds
    }

    fn prepare(&mut self, cx: &FrameContext<'_>, planes: Planes) -> Result<(), RenderError> {
        if let Some(meshes) = &planes.meshes {
            self.rebuild(cx.shared, &planes.key, meshes);
        }
        let (module, layout) = (&self.module, &self.layout);
        self.pipelines.prepare(cx.key, |k| build(cx.shared, module, layout, k, false))?;
        Ok(self.far_pipelines.prepare(cx.key, |k| build(cx.shared, module, layout, k, true))?)
    }

    fn draw<'p>(
        &'p self,
        phase: Phase,
        pass: &mut wgpu::RenderPass<'p>,
        key: PipelineKey,
        stats: &mut FrameStats,
    ) -> Result<(), RenderError> {
        let (Phase::Opaque, Some(g)) = (phase, &self.mesh) else {
            return Ok(());
        };
        // The near ground first: it is in front of the far terrain, whose hidden fragments the
        // early depth test then skips.
        pass.set_pipeline(self.pipelines.get(key)?);
        pass.set_bind_group(2, &self.bind_group, &[]);
        pass.set_vertex_buffer(0, g.vertices.slice(..));
        pass.set_index_buffer(g.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..g.near_count, 0, 0..1);
        stats.draws += 1;
        if g.index_count > g.near_count {
            pass.set_pipeline(self.far_pipelines.get(key)?);
            pass.draw_indexed(g.near_count..g.index_count, 0, 0..1);
            stats.draws += 1;
        }
        stats.triangles += g.index_count as usize / 3;
        Ok(())
    }
}
