//! A tree model on the GPU: its primitives (with the leaves ordered for the level of detail)
//! and its materials, uploaded from a loaded glTF ([`ModelData`]).

use glam::Vec3;
use wgpu::util::DeviceExt;

use super::lod;
use crate::models::ModelData;
use crate::render::assets::textures;
use crate::render::gpu::Shared;

grove_systems::wgsl_struct! {
    /// The per-material uniforms, declared once for Rust and WGSL: the shaders that read a
    /// material (trees.wgsl, the impostor bake's bake.wgsl) import [`MaterialUniform::WGSL`] as
    /// the piece `material`, the struct `Material`.
    #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
    pub(crate) struct MaterialUniform as Material {
        /// Linear RGBA factor of the albedo.
        base_color: [f32; 4] as "vec4<f32>",
        /// The alpha below which texels are clipped; negative for opaque materials.
        alpha_cutoff: f32 as "f32",
        /// The normal map's strength.
        normal_scale: f32 as "f32",
        /// The specular map's factor.
        specular_factor: f32 as "f32",
        /// Roughness, 0..1.
        roughness: f32 as "f32",
        /// 1 when both faces are drawn.
        double_sided: f32 as "f32",
        /// How much light passes through (leaves), 0..1.
        translucency: f32 as "f32",
        /// Padding to 48 bytes.
        pad: [f32; 2] as "vec2<f32>",
    }
}

/// The WGSL piece `material` (the struct `Material`), for the shaders that import it.
pub(crate) const MATERIAL_PIECE: (&str, &str) = ("material", MaterialUniform::WGSL);

pub(crate) struct GpuPrimitive {
    pub vertices: wgpu::Buffer,
    /// Per vertex, its leaf's centre and rank (vertex buffer slot 2; see [`lod`]).
    pub leaves: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    /// Indices drawn for trees in each keep bucket; all of them where the primitive is not
    /// simplified.
    pub index_counts: [u32; lod::BUCKETS],
    pub material: usize,
}

pub(crate) struct GpuMaterial {
    /// The material's uniforms and textures, for shading and for the depth-only passes (which
    /// read only the albedo's alpha).
    pub bind_group: wgpu::BindGroup,
    pub double_sided: bool,
    /// Alpha-clipped (`alphaMode: MASK`).
    pub masked: bool,
}

/// A model on the GPU.
pub struct GpuModel {
    pub(crate) name: String,
    pub(crate) primitives: Vec<GpuPrimitive>,
    pub(crate) materials: Vec<GpuMaterial>,
    /// Model-space bounds.
    pub bounds: (Vec3, Vec3),
    /// Triangle count.
    pub triangles: usize,
    /// Mean leaf area of the simplified primitives, square metres; 0 when none is simplified.
    pub leaf_area: f32,
    /// The impostor atlases, baked by the renderer after the upload ([`super::impostor`]).
    pub impostor: Option<super::impostor::Atlas>,
    /// Where the model's vertices can be in a wind, by height band ([`super::sweep`]).
    pub sweep: super::sweep::Sweep,
}

impl GpuModel {
    /// Uploads a loaded model: each albedo image as sRGB-encoded texels, each material's normal
    /// and specular maps packed into one linear texture, one bind group per material, and per
    /// primitive its vertices, leaf order and indices.
    pub(crate) fn upload(shared: &Shared, data: &ModelData) -> GpuModel {
        let name = data.path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let device = &shared.device;
        // The albedo images: sRGB-encoded bytes with mips averaged in linear light, which the
        // shaders decode after filtering (see `textures::ENCODED_FORMAT`; the depth-only passes
        // read their alpha, which `textures::mip_chain` averages as stored). Only images that a
        // material uses as albedo are uploaded this way.
        let albedo_images: Vec<Option<wgpu::TextureView>> = data
            .images
            .iter()
            .enumerate()
            .map(|(i, img)| {
                data.materials.iter().any(|m| m.albedo == Some(i)).then(|| {
                    textures::upload_2d_encoded(
                        device,
                        &shared.queue,
                        &format!("{name} image {i} (sRGB-encoded albedo)"),
                        img.width,
                        img.height,
                        &img.rgba,
                    )
                })
            })
            .collect();
        let image = |k: Option<usize>| {
            k.and_then(|k| data.images.get(k)).map(|img| (img.width, img.height, img.rgba.as_slice()))
        };
        let materials = data
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let uniform = MaterialUniform {
                    base_color: m.base_color.to_array(),
                    alpha_cutoff: m.alpha_cutoff.unwrap_or(-1.0),
                    normal_scale: m.normal_scale,
                    specular_factor: m.specular_factor,
                    roughness: m.roughness,
                    double_sided: if m.double_sided { 1.0 } else { 0.0 },
                    translucency: if m.alpha_cutoff.is_some() { 0.35 } else { 0.0 },
                    pad: [0.0; 2],
                };
                let buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{name} material {i} ({})", m.name)),
                    contents: bytemuck::cast_slice(&[uniform]),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
                let albedo = m.albedo.and_then(|k| albedo_images.get(k)?.as_ref()).unwrap_or(&shared.white);
                // The normal map in RGB and the specular map in A: trees.wgsl reads both with one
                // sample. The specular slot of the shared layout holds the same view, so a shader
                // that reads the specular map there (its alpha) reads the same values.
                let normal_spec = textures::upload_normal_specular(
                    device,
                    &shared.queue,
                    &format!("{name} material {i} normal and specular ({})", m.name),
                    image(m.normal),
                    image(m.specular),
                );
                GpuMaterial {
                    bind_group: shared.material_bind_group(
                        &format!("{name} material {i} bind group"),
                        &buf,
                        [albedo, &normal_spec, &normal_spec],
                    ),
                    double_sided: m.double_sided,
                    masked: m.alpha_cutoff.is_some(),
                }
            })
            .collect();
        // Alpha-clipped primitives of many pieces are simplified with distance (see `lod`),
        // with a shuffle seeded by the model's name, so every run draws the same leaves.
        let seed =
            name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3));
        let (mut leaf_area, mut simplified) = (0.0f32, 0usize);
        let mut leaf_orders = Vec::new();
        let primitives = data
            .primitives
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let masked = data.materials.get(p.material).is_some_and(|m| m.alpha_cutoff.is_some());
                let order = masked.then(|| lod::order_leaves(&p.vertices, &p.indices, seed ^ i as u64)).flatten();
                let full = p.indices.len() as u32;
                let (indices, leaves, index_counts) = match &order {
                    Some(o) => {
                        leaf_area += o.mean_leaf_area;
                        simplified += 1;
                        (&o.indices, o.leaf.clone(), std::array::from_fn(|b| o.index_count(b)))
                    }
                    None => (&p.indices, lod::unsimplified(p.vertices.len()), [full; lod::BUCKETS]),
                };
                leaf_orders.push(leaves.clone());
                let buffer = |what: &str, contents: &[u8], usage| {
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some(&format!("{name} primitive {i} {what}")),
                        contents,
                        usage,
                    })
                };
                GpuPrimitive {
                    vertices: buffer("vertices", bytemuck::cast_slice(&p.vertices), wgpu::BufferUsages::VERTEX),
                    leaves: buffer("leaves", bytemuck::cast_slice(&leaves), wgpu::BufferUsages::VERTEX),
                    indices: buffer("indices", bytemuck::cast_slice(indices), wgpu::BufferUsages::INDEX),
                    index_counts,
                    material: p.material,
                }
            })
            .collect();
        let leaf_area = if simplified > 0 { leaf_area / simplified as f32 } else { 0.0 };
        let sweep =
            super::sweep::Sweep::new(data.primitives.iter().zip(&leaf_orders).map(|(p, l)| (&p.vertices[..], &l[..])));
        GpuModel {
            name,
            primitives,
            materials,
            bounds: data.bounds,
            triangles: data.triangles(),
            leaf_area,
            impostor: None,
            sweep,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_material_is_written_once_from_rust() {
        // The trees and the impostor bake read one declaration of `Material`, the Rust one, at
        // the Rust struct's offsets.
        for src in [include_str!("trees.wgsl"), include_str!("impostor/bake.wgsl")] {
            let wgsl = crate::render::shader::compose(src, &[MATERIAL_PIECE]);
            assert_eq!(wgsl.matches("struct Material {").count(), 1, "{wgsl}");
            assert!(wgsl.contains(MaterialUniform::WGSL));
            let (members, size) = crate::render::shader::struct_layout(&wgsl, "Material")
                .expect("the composed shader parses and declares Material");
            let rust: Vec<(String, usize)> = MaterialUniform::FIELDS.iter().map(|(n, o)| (n.to_string(), *o)).collect();
            assert_eq!(members, rust);
            assert_eq!(size, std::mem::size_of::<MaterialUniform>());
        }
    }
}
