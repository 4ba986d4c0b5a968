//! The CPU form of a loaded model: vertices, triangle lists, materials and images, as the
//! renderer uploads them and the model bank measures them.

use std::path::PathBuf;

use glam::{Vec3, Vec4};

/// A decoded RGBA8 image.
#[derive(Clone, Debug)]
pub struct ImageData {
    /// Width, texels.
    pub width: u32,
    /// Height, texels.
    pub height: u32,
    /// RGBA8 texels, row by row.
    pub rgba: Vec<u8>,
}

/// A material, with indices into [`ModelData::images`].
#[derive(Clone, Debug)]
pub struct MaterialData {
    /// The material's name, if any.
    pub name: String,
    /// Base colour factor (linear RGBA).
    pub base_color: Vec4,
    /// Albedo image (sRGB).
    pub albedo: Option<usize>,
    /// Tangent-space normal map.
    pub normal: Option<usize>,
    /// Normal map scale.
    pub normal_scale: f32,
    /// Specular map (strength in A, `KHR_materials_specular`).
    pub specular: Option<usize>,
    /// Specular factor (`KHR_materials_specular`, default 1).
    pub specular_factor: f32,
    /// Roughness factor.
    pub roughness: f32,
    /// Alpha cutoff when the material is alpha-masked.
    pub alpha_cutoff: Option<f32>,
    /// Whether back faces are drawn (with the normal flipped along the face normal).
    pub double_sided: bool,
}

impl Default for MaterialData {
    fn default() -> Self {
        MaterialData {
            name: "default".into(),
            base_color: Vec4::ONE,
            albedo: None,
            normal: None,
            normal_scale: 1.0,
            specular: None,
            specular_factor: 1.0,
            roughness: 1.0,
            alpha_cutoff: None,
            double_sided: false,
        }
    }
}

/// One vertex as the tree shader reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Position, model space.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Texture coordinates.
    pub uv: [f32; 2],
    /// Tangent and bitangent sign.
    pub tangent: [f32; 4],
    /// Wind channels (`_WIND`); for models without them, x is the height above the lowest point.
    pub wind: [f32; 4],
    /// Vertex colour (`COLOR_0`, linear RGBA as `Unorm8x4`), multiplying the base colour; white
    /// where the file has none.
    pub color: [u8; 4],
}

impl Default for Vertex {
    fn default() -> Self {
        Vertex {
            position: [0.0; 3],
            normal: [0.0; 3],
            uv: [0.0; 2],
            tangent: [0.0; 4],
            wind: [0.0; 4],
            color: [255; 4],
        }
    }
}

/// A triangle list with one material.
#[derive(Clone, Debug)]
pub struct PrimitiveData {
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Triangle indices.
    pub indices: Vec<u32>,
    /// Index into [`ModelData::materials`].
    pub material: usize,
}

/// A whole model in model space.
#[derive(Clone, Debug)]
pub struct ModelData {
    /// Where it came from.
    pub path: PathBuf,
    /// Triangle primitives.
    pub primitives: Vec<PrimitiveData>,
    /// Materials.
    pub materials: Vec<MaterialData>,
    /// Decoded images.
    pub images: Vec<ImageData>,
    /// Axis-aligned bounds (min, max) of all drawn vertices.
    pub bounds: (Vec3, Vec3),
    /// Whether every vertex carried its own `_WIND` channels (otherwise grove computed them).
    pub own_wind: bool,
    /// What the file holds that a still shows in one fixed state (animations at the rest pose,
    /// skins in the bind pose), as short phrases for a command's output line.
    pub notes: Vec<String>,
    /// What the file uses that grove does not draw, one line each, for stderr.
    pub warnings: Vec<String>,
}

impl ModelData {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.primitives.iter().map(|p| p.indices.len() / 3).sum()
    }
}
