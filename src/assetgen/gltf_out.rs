//! Writes a tree model as glTF 2.0: a `.gltf` JSON file and a `.bin` buffer beside it, with
//! textures referenced by relative URI.

use glam::{Vec2, Vec3, Vec4};
use serde_json::{Value, json};

use super::geometry::MeshData;

/// The textures of one material, as URIs relative to the `.gltf` file.
pub struct MaterialTextures {
    /// Material name.
    pub name: String,
    /// Albedo (baseColorTexture).
    pub albedo: String,
    /// Tangent-space normal map.
    pub normal: String,
    /// Specular map (`KHR_materials_specular` specularTexture, strength in A).
    pub specular: String,
    /// Leaves: alpha mask and two-sided.
    pub leaves: bool,
    /// Specular factor.
    pub specular_factor: f32,
    /// Roughness factor.
    pub roughness: f32,
}

impl MaterialTextures {
    /// The material `name` (`oak-bark`, `birch-card`) with its albedo, normal and specular maps
    /// `{dir}{name}.png`, `{dir}{name}-normal.png` and `{dir}{name}-specular.png` (`dir` is empty
    /// or ends in `/`). Bark is opaque and matte; leaves are alpha-masked, two-sided and shinier.
    pub fn with_maps(name: &str, dir: &str, leaves: bool) -> MaterialTextures {
        let (specular_factor, roughness) = if leaves { (1.0, 0.6) } else { (0.5, 0.9) };
        MaterialTextures {
            name: name.to_string(),
            albedo: format!("{dir}{name}.png"),
            normal: format!("{dir}{name}-normal.png"),
            specular: format!("{dir}{name}-specular.png"),
            leaves,
            specular_factor,
            roughness,
        }
    }

    /// The bark material of species `n`: its bark texture with normal and specular maps under
    /// `textures/`, opaque, matte.
    pub fn bark(n: &str) -> MaterialTextures {
        MaterialTextures::with_maps(&format!("{n}-bark"), "textures/", false)
    }
}

struct Buf {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Buf {
    fn view(&mut self, data: &[u8], target: u32) -> usize {
        while self.bytes.len() % 4 != 0 {
            self.bytes.push(0);
        }
        let offset = self.bytes.len();
        self.bytes.extend_from_slice(data);
        self.views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target}));
        self.views.len() - 1
    }

    fn floats(&mut self, data: &[f32], count: usize, ty: &str, minmax: Option<(Vec<f32>, Vec<f32>)>) -> usize {
        let view = self.view(bytemuck::cast_slice(data), 34962);
        let mut acc = json!({"bufferView": view, "componentType": 5126, "count": count, "type": ty});
        if let Some((min, max)) = minmax {
            acc["min"] = json!(min);
            acc["max"] = json!(max);
        }
        self.accessors.push(acc);
        self.accessors.len() - 1
    }

    fn indices(&mut self, data: &[u32]) -> usize {
        let view = self.view(bytemuck::cast_slice(data), 34963);
        self.accessors.push(json!({"bufferView": view, "componentType": 5125, "count": data.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }
}

fn flat3(v: &[Vec3]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}
fn flat2(v: &[Vec2]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}
fn flat4(v: &[Vec4]) -> Vec<f32> {
    v.iter().flat_map(|p| p.to_array()).collect()
}

/// Builds the glTF JSON and the binary buffer for a model made of `(mesh, material)` parts.
/// `bin_uri` is the buffer's file name.
pub fn build(name: &str, parts: &[(&MeshData, &MaterialTextures)], bin_uri: &str) -> (String, Vec<u8>) {
    let mut buf = Buf { bytes: Vec::new(), views: Vec::new(), accessors: Vec::new() };
    let mut images: Vec<String> = Vec::new();
    let mut image_index = |uri: &str| -> usize {
        if let Some(i) = images.iter().position(|u| u == uri) {
            i
        } else {
            images.push(uri.to_string());
            images.len() - 1
        }
    };
    let mut materials = Vec::new();
    let mut primitives = Vec::new();
    for (i, (mesh, mat)) in parts.iter().enumerate() {
        let (min, max) = mesh.bounds();
        let pos = buf.floats(
            &flat3(&mesh.positions),
            mesh.positions.len(),
            "VEC3",
            Some((min.to_array().to_vec(), max.to_array().to_vec())),
        );
        let nrm = buf.floats(&flat3(&mesh.normals), mesh.normals.len(), "VEC3", None);
        let tan = buf.floats(&flat4(&mesh.tangents), mesh.tangents.len(), "VEC4", None);
        let uv = buf.floats(&flat2(&mesh.uvs), mesh.uvs.len(), "VEC2", None);
        let wind = buf.floats(&flat4(&mesh.wind), mesh.wind.len(), "VEC4", None);
        let mut attributes = json!({"POSITION": pos, "NORMAL": nrm, "TANGENT": tan, "TEXCOORD_0": uv, "_WIND": wind});
        if !mesh.colors.is_empty() {
            attributes["COLOR_0"] = json!(buf.floats(&flat4(&mesh.colors), mesh.colors.len(), "VEC4", None));
        }
        let idx = buf.indices(&mesh.indices);
        primitives.push(json!({
            "attributes": attributes,
            "indices": idx,
            "material": i,
            "mode": 4
        }));
        let (a, n, s) = (image_index(&mat.albedo), image_index(&mat.normal), image_index(&mat.specular));
        let mut m = json!({
            "name": mat.name,
            "pbrMetallicRoughness": {
                "baseColorTexture": {"index": a},
                "metallicFactor": 0.0,
                "roughnessFactor": mat.roughness
            },
            "normalTexture": {"index": n, "scale": 1.0},
            "extensions": {"KHR_materials_specular": {"specularFactor": mat.specular_factor, "specularTexture": {"index": s}}}
        });
        if mat.leaves {
            m["alphaMode"] = json!("MASK");
            m["alphaCutoff"] = json!(0.5);
            m["doubleSided"] = json!(true);
        }
        materials.push(m);
    }
    // One texture per image, all with the same sampler.
    let textures: Vec<Value> = (0..images.len()).map(|i| json!({"sampler": 0, "source": i})).collect();
    let images: Vec<Value> = images.iter().map(|u| json!({"uri": u, "mimeType": "image/png"})).collect();
    let doc = json!({
        "asset": {"version": "2.0", "generator": "grove assets (procedural, seeded)"},
        "extensionsUsed": ["KHR_materials_specular"],
        "scene": 0,
        "scenes": [{"name": name, "nodes": [0]}],
        "nodes": [{"name": name, "mesh": 0}],
        "meshes": [{"name": name, "primitives": primitives}],
        "materials": materials,
        "textures": textures,
        "images": images,
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"uri": bin_uri, "byteLength": buf.bytes.len()}]
    });
    let mut text = serde_json::to_string_pretty(&doc).expect("JSON values always serialise");
    text.push('\n');
    (text, buf.bytes)
}
