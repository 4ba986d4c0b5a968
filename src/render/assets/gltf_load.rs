//! Loading glTF 2.0 models (`.gltf` + resources, or `.glb`) through the `gltf` crate into plain
//! CPU data the renderer uploads.
//!
//! Any glTF 2.0 file works, not only grove's own: the node hierarchy of the default scene is
//! flattened (each primitive's vertices are transformed to model space), missing normals are
//! computed from the triangles, missing tangents from the texture coordinates, missing texture
//! coordinates are zero, and missing textures are replaced by neutral 1×1 textures. Only
//! triangle primitives are drawn; points and lines are skipped. Errors are one line naming the
//! file (and the texture, where one is at fault); nothing here panics on bad input.

use std::path::{Path, PathBuf};

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::Semantic;

use super::accessor::read_floats;

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
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
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
}

impl ModelData {
    /// Number of triangles.
    pub fn triangles(&self) -> usize {
        self.primitives.iter().map(|p| p.indices.len() / 3).sum()
    }
}

/// Loads a glTF 2.0 model. The error is one line naming the file.
pub fn load_model(path: &Path) -> Result<ModelData, String> {
    let file = path.display().to_string();
    let err = |m: String| format!("{file}: {m}");
    if path.is_dir() {
        return Err(err("is a directory, not a glTF file".into()));
    }
    if !path.exists() {
        return Err(err("no such file".into()));
    }
    if !path.is_file() {
        return Err(err("not a regular file".into()));
    }
    let bytes = std::fs::read(path).map_err(|e| err(grove_systems::scene::io_message(&e)))?;
    let gltf = super::gltf_open::parse(&bytes).map_err(|e| err(format!("not a valid glTF 2.0 file ({})", one_line(&e.to_string()))))?;
    let base = path.parent().unwrap_or(Path::new("."));
    let doc = gltf.document;
    let buffers = gltf::import_buffers(&doc, Some(base), gltf.blob).map_err(|e| err(format!("cannot read a buffer ({})", one_line(&e.to_string()))))?;
    // Check image files first, so that a missing texture is named.
    for img in doc.images() {
        if let gltf::image::Source::Uri { uri, .. } = img.source() {
            if !uri.starts_with("data:") {
                let decoded = uri.replace("%20", " ");
                let p = base.join(&decoded);
                if !p.is_file() {
                    return Err(err(format!("texture '{uri}': no such file")));
                }
            }
        }
    }
    let mut images = Vec::new();
    for (i, img) in doc.images().enumerate() {
        let name = match img.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => format!("texture '{uri}'"),
            _ => format!("image {i}"),
        };
        let data = load_image(&img, base, &buffers).map_err(|m| err(format!("{name}: {m}")))?;
        images.push(data);
    }
    let mut materials: Vec<MaterialData> = doc.materials().map(|m| material(&m)).collect();
    let default_material = materials.len();
    materials.push(MaterialData::default());

    let mut primitives = Vec::new();
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut stack: Vec<(gltf::Node, Mat4)> = match &scene {
        Some(s) => s.nodes().map(|n| (n, Mat4::IDENTITY)).collect(),
        None => doc.nodes().map(|n| (n, Mat4::IDENTITY)).collect(),
    };
    let mut depth_guard = 0usize;
    while let Some((node, parent)) = stack.pop() {
        depth_guard += 1;
        if depth_guard > 1_000_000 {
            return Err(err("the node hierarchy is too large or cyclic".into()));
        }
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    continue;
                }
                let mat = prim.material().index().unwrap_or(default_material);
                if let Some(p) = primitive(&prim, &buffers, m, mat).map_err(&err)? {
                    primitives.push(p);
                }
            }
        }
        for c in node.children() {
            stack.push((c, m));
        }
    }
    if primitives.is_empty() {
        return Err(err("has no triangles to draw".into()));
    }
    let mut bounds = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in &primitives {
        for v in &p.vertices {
            let q = Vec3::from(v.position);
            bounds = (bounds.0.min(q), bounds.1.max(q));
        }
    }
    if !(bounds.0.is_finite() && bounds.1.is_finite()) {
        return Err(err("has non-finite vertex positions".into()));
    }
    let own_wind = primitives.iter().all(|p| p.vertices.iter().all(|v| v.wind[3] >= 0.0));
    if !own_wind {
        let clipped: Vec<bool> = primitives.iter().map(|p| materials.get(p.material).is_some_and(|m| m.alpha_cutoff.is_some())).collect();
        super::wind_channels::compute_with(&mut primitives, bounds.0.y, &clipped);
    }
    Ok(ModelData { path: path.to_path_buf(), primitives, materials, images, bounds, own_wind })
}

fn one_line(s: &str) -> String {
    s.replace('\n', " ")
}

fn load_image(img: &gltf::Image, base: &Path, buffers: &[gltf::buffer::Data]) -> Result<ImageData, String> {
    let bytes: Vec<u8> = match img.source() {
        gltf::image::Source::Uri { uri, .. } => {
            if let Some(rest) = uri.strip_prefix("data:") {
                let (_, b64) = rest.split_once(";base64,").ok_or("unsupported data URI")?;
                base64_decode(b64)?
            } else {
                let p = base.join(uri.replace("%20", " "));
                std::fs::read(&p).map_err(|e| grove_systems::scene::io_message(&e))?
            }
        }
        gltf::image::Source::View { view, .. } => {
            let buf = buffers.get(view.buffer().index()).ok_or("buffer view out of range")?;
            let (s, e) = (view.offset(), view.offset() + view.length());
            buf.0.get(s..e).ok_or("buffer view out of range")?.to_vec()
        }
    };
    let decoded = image::load_from_memory(&bytes).map_err(|e| format!("cannot decode ({})", one_line(&e.to_string())))?;
    let rgba = decoded.to_rgba8();
    let (width, height) = rgba.dimensions();
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(format!("unsupported size {width}x{height}"));
    }
    Ok(ImageData { width, height, rgba: rgba.into_raw() })
}

/// A small standard base64 decoder for `data:` URIs.
fn base64_decode(s: &str) -> Result<Vec<u8>, String> {
    let val = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a' + 26) as u32,
            b'0'..=b'9' => (c - b'0' + 52) as u32,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        })
    };
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    let (mut acc, mut bits) = (0u32, 0u32);
    for c in s.bytes() {
        if c == b'=' || c.is_ascii_whitespace() {
            continue;
        }
        let v = val(c).ok_or("invalid base64 in data URI")?;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

fn material(m: &gltf::Material) -> MaterialData {
    let pbr = m.pbr_metallic_roughness();
    let spec = m.specular();
    MaterialData {
        name: m.name().unwrap_or("unnamed").to_string(),
        base_color: Vec4::from(pbr.base_color_factor()),
        albedo: pbr.base_color_texture().map(|t| t.texture().source().index()),
        normal: m.normal_texture().map(|t| t.texture().source().index()),
        normal_scale: m.normal_texture().map_or(1.0, |t| t.scale()),
        specular: spec.as_ref().and_then(|s| s.specular_texture()).map(|t| t.texture().source().index()),
        specular_factor: spec.as_ref().map_or(0.5, |s| s.specular_factor()),
        roughness: pbr.roughness_factor(),
        alpha_cutoff: match m.alpha_mode() {
            gltf::material::AlphaMode::Mask => Some(m.alpha_cutoff().unwrap_or(0.5)),
            _ => None,
        },
        double_sided: m.double_sided(),
    }
}

fn primitive(prim: &gltf::Primitive, buffers: &[gltf::buffer::Data], m: Mat4, material: usize) -> Result<Option<PrimitiveData>, String> {
    let get = |b: gltf::Buffer| buffers.get(b.index()).map(|d| d.0.as_slice());
    let reader = prim.reader(get);
    // Float attributes through `accessor::read_floats`, which also reads the integer types of
    // KHR_mesh_quantization (the node transform then carries the dequantisation).
    let Some(pos) = prim.get(&Semantic::Positions) else { return Ok(None) };
    let positions: Vec<Vec3> = read_floats::<3>(&pos, buffers)?.into_iter().map(Vec3::from).collect();
    let n = positions.len();
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..n as u32).collect(),
    };
    if indices.iter().any(|&i| i as usize >= n) {
        return Err("a primitive has an index past its vertices".into());
    }
    let indices: Vec<u32> = indices.chunks_exact(3).flatten().copied().collect();
    let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(0)) {
        Some(t) => read_floats::<2>(&t, buffers)?.into_iter().map(Vec2::from).collect(),
        None => vec![Vec2::ZERO; n],
    };
    let mut normals: Vec<Vec3> = match prim.get(&Semantic::Normals) {
        Some(nr) => read_floats::<3>(&nr, buffers)?.into_iter().map(Vec3::from).collect(),
        None => compute_normals(&positions, &indices),
    };
    let mut tangents: Vec<Vec4> = match prim.get(&Semantic::Tangents) {
        Some(t) => read_floats::<4>(&t, buffers)?.into_iter().map(Vec4::from).collect(),
        None => compute_tangents(&positions, &normals, &uvs, &indices),
    };
    let wind: Vec<Vec4> = match prim.get(&Semantic::Extras("WIND".into())) {
        Some(acc) if acc.dimensions() == gltf::accessor::Dimensions::Vec4 && acc.data_type() == gltf::accessor::DataType::F32 => {
            gltf::accessor::Iter::<[f32; 4]>::new(acc, get).map(|it| it.map(Vec4::from).collect()).unwrap_or_default()
        }
        _ => Vec::new(),
    };
    if uvs.len() != n || normals.len() != n || tangents.len() != n || (!wind.is_empty() && wind.len() != n) {
        return Err("a primitive's attributes have different lengths".into());
    }
    // Bake the node transform into the vertices.
    let nm = Mat3::from_mat4(m).inverse().transpose();
    let flip = Mat3::from_mat4(m).determinant() < 0.0;
    let lin = Mat3::from_mat4(m);
    for i in 0..n {
        normals[i] = (nm * normals[i]).normalize_or(Vec3::Y);
        let t = (lin * tangents[i].truncate()).normalize_or(normals[i].any_orthonormal_vector());
        tangents[i] = t.extend(if tangents[i].w < 0.0 { -1.0 } else { 1.0 });
    }
    let vertices = (0..n)
        .map(|i| Vertex {
            position: m.transform_point3(positions[i]).to_array(),
            normal: normals[i].to_array(),
            uv: uvs[i].to_array(),
            tangent: tangents[i].to_array(),
            // A negative phase marks "no wind data"; it is replaced after the bounds are known.
            wind: wind.get(i).map_or([0.0, 0.0, 0.0, -1.0], |w| w.to_array()),
        })
        .collect();
    let mut indices = indices;
    if flip {
        for t in indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    Ok(Some(PrimitiveData { vertices, indices, material }))
}

/// Area-weighted vertex normals of a triangle list.
pub fn compute_normals(p: &[Vec3], idx: &[u32]) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; p.len()];
    for t in idx.chunks_exact(3) {
        let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
        let f = (p[b] - p[a]).cross(p[c] - p[a]);
        n[a] += f;
        n[b] += f;
        n[c] += f;
    }
    n.into_iter().map(|v| v.normalize_or(Vec3::Y)).collect()
}

/// Per-vertex tangents from texture coordinates (accumulated per triangle, then
/// Gram–Schmidt-orthogonalised). This is not MikkTSpace, so normal maps baked against MikkTSpace
/// tangents may show small seams; grove's own models carry their tangents.
pub fn compute_tangents(p: &[Vec3], n: &[Vec3], uv: &[Vec2], idx: &[u32]) -> Vec<Vec4> {
    let mut t = vec![Vec3::ZERO; p.len()];
    let mut b = vec![Vec3::ZERO; p.len()];
    for tri in idx.chunks_exact(3) {
        let (i0, i1, i2) = (tri[0] as usize, tri[1] as usize, tri[2] as usize);
        let (e1, e2) = (p[i1] - p[i0], p[i2] - p[i0]);
        let (d1, d2) = (uv[i1] - uv[i0], uv[i2] - uv[i0]);
        let r = d1.x * d2.y - d2.x * d1.y;
        if r.abs() < 1e-12 {
            continue;
        }
        let sdir = (e1 * d2.y - e2 * d1.y) / r;
        let tdir = (e2 * d1.x - e1 * d2.x) / r;
        for i in [i0, i1, i2] {
            t[i] += sdir;
            b[i] += tdir;
        }
    }
    (0..p.len())
        .map(|i| {
            let nn = n[i];
            let tt = (t[i] - nn * nn.dot(t[i])).normalize_or(nn.any_orthonormal_vector());
            let w = if nn.cross(tt).dot(b[i]) < 0.0 { -1.0 } else { 1.0 };
            tt.extend(w)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_decodes_a_known_string() {
        assert_eq!(base64_decode("aGVsbG8gd29ybGQ=").unwrap(), b"hello world");
    }

    #[test]
    fn tangents_follow_u() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = [Vec3::Z; 3];
        let uv = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)];
        let t = compute_tangents(&p, &n, &uv, &[0, 1, 2]);
        assert!((t[0].truncate() - Vec3::X).length() < 1e-5);
        // v grows downwards in glTF, so the bitangent (+v) points along −Y: handedness −1.
        assert_eq!(t[0].w, -1.0);
    }
}
