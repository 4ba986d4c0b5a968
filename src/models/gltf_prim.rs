//! One glTF primitive as a triangle list in model space: triangle strips and fans turned into
//! lists (points and lines refused by name), morph targets applied with the default weights,
//! vertex colours (`COLOR_0`), the texture-coordinate set the material's textures read with its
//! `KHR_texture_transform` baked in, and the node transform baked into the vertices.

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::{Mode, Semantic};

use super::accessor::read_floats;
use super::error::GltfProblem;
use super::mesh::{PrimitiveData, Vertex};

/// Which texture coordinates a material's textures read: the set and the texture transform
/// (`KHR_texture_transform`, a 2×3 affine map, identity without one), the same for all its
/// textures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvChoice {
    /// `TEXCOORD_n`.
    pub set: u32,
    /// Columns of the affine map: `uv' = m[0] * u + m[1] * v + m[2]`.
    pub transform: [Vec2; 3],
}

impl Default for UvChoice {
    fn default() -> Self {
        UvChoice { set: 0, transform: [Vec2::X, Vec2::Y, Vec2::ZERO] }
    }
}

/// The affine map of a `KHR_texture_transform` (offset, rotation, scale), as the extension's
/// GLSL defines it: translation × rotation × scale, the rotation's columns (cos, sin) and
/// (−sin, cos), so that (1, 0) turns towards +v.
pub fn transform_of(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> [Vec2; 3] {
    let (s, c) = rotation.sin_cos();
    [Vec2::new(c, s) * scale[0], Vec2::new(-s, c) * scale[1], Vec2::from(offset)]
}

fn transform_json(v: Option<&serde_json::Value>, tex_coord: u32) -> (u32, [Vec2; 3]) {
    let Some(v) = v else { return (tex_coord, UvChoice::default().transform) };
    let pair = |k: &str, d: f32| -> [f32; 2] {
        v.get(k)
            .and_then(|a| a.as_array())
            .filter(|a| a.len() == 2)
            .map_or([d, d], |a| [a[0].as_f64().unwrap_or(d as f64) as f32, a[1].as_f64().unwrap_or(d as f64) as f32])
    };
    let rot = v.get("rotation").and_then(|r| r.as_f64()).unwrap_or(0.0) as f32;
    let set = v.get("texCoord").and_then(|t| t.as_u64()).map_or(tex_coord, |t| t.min(u32::MAX as u64) as u32);
    (set, transform_of(pair("offset", 0.0), rot, pair("scale", 1.0)))
}

/// The texture coordinates a material's textures read (base colour, normal map, specular map).
/// Textures that read different sets or transforms are refused by name: grove draws a material
/// with one set of coordinates.
pub fn uv_choice(m: &gltf::Material) -> Result<UvChoice, GltfProblem> {
    let mut found: Vec<(&str, u32, [Vec2; 3])> = Vec::new();
    if let Some(t) = m.pbr_metallic_roughness().base_color_texture() {
        let tt = t.texture_transform();
        let (set, tr) = match tt {
            Some(x) => (x.tex_coord().unwrap_or(t.tex_coord()), transform_of(x.offset(), x.rotation(), x.scale())),
            None => (t.tex_coord(), UvChoice::default().transform),
        };
        found.push(("base colour", set, tr));
    }
    if let Some(t) = m.normal_texture() {
        let (set, tr) = transform_json(t.extension_value("KHR_texture_transform"), t.tex_coord());
        found.push(("normal", set, tr));
    }
    if let Some(t) = m.specular().and_then(|s| s.specular_texture()) {
        let tt = t.texture_transform();
        let (set, tr) = match tt {
            Some(x) => (x.tex_coord().unwrap_or(t.tex_coord()), transform_of(x.offset(), x.rotation(), x.scale())),
            None => (t.tex_coord(), UvChoice::default().transform),
        };
        found.push(("specular", set, tr));
    }
    let Some(&(_, set, transform)) = found.first() else { return Ok(UvChoice::default()) };
    if let Some((what, other, _)) = found.iter().find(|f| f.1 != set) {
        return Err(GltfProblem::TexCoordSets {
            material: m.name().unwrap_or("unnamed").to_string(),
            what,
            other: *other,
            first: found[0].0,
            set,
        });
    }
    if let Some((what, _, _)) = found.iter().find(|f| f.2 != transform) {
        return Err(GltfProblem::TextureTransforms {
            material: m.name().unwrap_or("unnamed").to_string(),
            what,
            first: found[0].0,
        });
    }
    Ok(UvChoice { set, transform })
}

/// A primitive's name in messages: its mesh (by name, else index) and its index in the mesh.
pub fn name_of(mesh: &gltf::Mesh, prim: &gltf::Primitive) -> String {
    match mesh.name() {
        Some(n) => format!("mesh '{n}' primitive {}", prim.index()),
        None => format!("mesh {} primitive {}", mesh.index(), prim.index()),
    }
}

/// The triangle list of a primitive's indices (or `0..n` without indices) by its mode; points
/// and lines are refused by name.
pub fn triangle_list(mode: Mode, idx: Vec<u32>) -> Result<Vec<u32>, GltfProblem> {
    let tris: Vec<u32> = match mode {
        Mode::Triangles => idx.chunks_exact(3).flatten().copied().collect(),
        // Every other triangle of a strip is flipped to keep the winding.
        Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
            .flat_map(|i| if i % 2 == 0 { [idx[i], idx[i + 1], idx[i + 2]] } else { [idx[i + 1], idx[i], idx[i + 2]] })
            .collect(),
        Mode::TriangleFan => (1..idx.len().saturating_sub(1)).flat_map(|i| [idx[i], idx[i + 1], idx[0]]).collect(),
        Mode::Points => return Err(GltfProblem::Points),
        Mode::Lines | Mode::LineLoop | Mode::LineStrip => return Err(GltfProblem::Lines(mode)),
    };
    Ok(tris)
}

/// Adds the morph targets' displacements of one attribute, weighted.
fn morph<const N: usize>(
    base: &mut [[f32; N]],
    targets: &[(Option<gltf::Accessor>, f32)],
    buffers: &[gltf::buffer::Data],
) -> Result<(), GltfProblem> {
    for (acc, w) in targets {
        let (Some(acc), true) = (acc, *w != 0.0) else { continue };
        let d = read_floats::<N>(acc, buffers)?;
        if d.len() != base.len() {
            return Err(GltfProblem::MorphLength { accessor: acc.index(), len: d.len(), vertices: base.len() });
        }
        for (b, d) in base.iter_mut().zip(&d) {
            for k in 0..N {
                b[k] += w * d[k];
            }
        }
    }
    Ok(())
}

/// Reads one primitive (see the module docs) with the node's matrix `m` (identity for a skinned
/// mesh, drawn in its bind pose), its morph `weights` and its material's [`UvChoice`].
pub fn primitive(
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    m: Mat4,
    weights: &[f32],
    (material, uv): (usize, UvChoice),
) -> Result<Option<PrimitiveData>, GltfProblem> {
    let get = |b: gltf::Buffer| buffers.get(b.index()).map(|d| d.0.as_slice());
    let reader = prim.reader(get);
    // Float attributes through `accessor::read_floats`, which also reads the integer types of
    // KHR_mesh_quantization (the node transform then carries the dequantisation).
    let Some(pos) = prim.get(&Semantic::Positions) else { return Ok(None) };
    let targets: Vec<gltf::mesh::MorphTarget> = prim.morph_targets().collect();
    if !targets.is_empty() && !weights.is_empty() && weights.len() != targets.len() {
        return Err(GltfProblem::MorphWeights { targets: targets.len(), weights: weights.len() });
    }
    let w = |i: usize| weights.get(i).copied().unwrap_or(0.0);
    let mut positions = read_floats::<3>(&pos, buffers)?;
    morph(
        &mut positions,
        &targets.iter().enumerate().map(|(i, t)| (t.positions(), w(i))).collect::<Vec<_>>(),
        buffers,
    )?;
    let positions: Vec<Vec3> = positions.into_iter().map(Vec3::from).collect();
    let n = positions.len();
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None if prim.indices().is_some() => return Err(GltfProblem::UnreadableIndices),
        None => (0..n as u32).collect(),
    };
    if indices.iter().any(|&i| i as usize >= n) {
        return Err(GltfProblem::IndexPastVertices);
    }
    let indices = triangle_list(prim.mode(), indices)?;
    let uvs: Vec<Vec2> = match prim.get(&Semantic::TexCoords(uv.set)) {
        Some(t) => read_floats::<2>(&t, buffers)?
            .into_iter()
            .map(|q| uv.transform[0] * q[0] + uv.transform[1] * q[1] + uv.transform[2])
            .collect(),
        None if uv.set != 0 => return Err(GltfProblem::NoTexCoord(uv.set)),
        None => vec![Vec2::ZERO; n],
    };
    let mut normals: Vec<Vec3> = match prim.get(&Semantic::Normals) {
        Some(nr) => {
            let mut v = read_floats::<3>(&nr, buffers)?;
            morph(&mut v, &targets.iter().enumerate().map(|(i, t)| (t.normals(), w(i))).collect::<Vec<_>>(), buffers)?;
            v.into_iter().map(Vec3::from).collect()
        }
        None => compute_normals(&positions, &indices),
    };
    // Checked before the tangents are computed from them.
    if uvs.len() != n || normals.len() != n {
        return Err(GltfProblem::AttributeLengths);
    }
    let mut tangents: Vec<Vec4> = match prim.get(&Semantic::Tangents) {
        Some(t) => {
            let mut v = read_floats::<4>(&t, buffers)?;
            let mut xyz: Vec<[f32; 3]> = v.iter().map(|q| [q[0], q[1], q[2]]).collect();
            morph(
                &mut xyz,
                &targets.iter().enumerate().map(|(i, t)| (t.tangents(), w(i))).collect::<Vec<_>>(),
                buffers,
            )?;
            for (q, d) in v.iter_mut().zip(&xyz) {
                q[..3].copy_from_slice(d);
            }
            v.into_iter().map(Vec4::from).collect()
        }
        None => compute_tangents(&positions, &normals, &uvs, &indices),
    };
    let colors: Vec<[u8; 4]> = match prim.get(&Semantic::Colors(0)) {
        Some(c) if c.dimensions() == gltf::accessor::Dimensions::Vec3 => {
            read_floats::<3>(&c, buffers)?.into_iter().map(|q| unorm([q[0], q[1], q[2], 1.0])).collect()
        }
        Some(c) => read_floats::<4>(&c, buffers)?.into_iter().map(unorm).collect(),
        None => vec![[255; 4]; n],
    };
    let wind: Vec<Vec4> = match prim.get(&Semantic::Extras("WIND".into())) {
        Some(acc)
            if acc.dimensions() == gltf::accessor::Dimensions::Vec4
                && acc.data_type() == gltf::accessor::DataType::F32 =>
        {
            gltf::accessor::Iter::<[f32; 4]>::new(acc, get).map(|it| it.map(Vec4::from).collect()).unwrap_or_default()
        }
        _ => Vec::new(),
    };
    if uvs.len() != n
        || normals.len() != n
        || tangents.len() != n
        || colors.len() != n
        || (!wind.is_empty() && wind.len() != n)
    {
        return Err(GltfProblem::AttributeLengths);
    }
    // Bake the node transform into the vertices.
    let lin = Mat3::from_mat4(m);
    let nm = lin.inverse().transpose();
    let flip = lin.determinant() < 0.0;
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
            color: colors[i],
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

/// A linear RGBA colour in [0, 1] as bytes (`Unorm8x4`).
fn unorm(c: [f32; 4]) -> [u8; 4] {
    c.map(|x| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
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
    fn tangents_follow_u() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = [Vec3::Z; 3];
        let uv = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)];
        let t = compute_tangents(&p, &n, &uv, &[0, 1, 2]);
        assert!((t[0].truncate() - Vec3::X).length() < 1e-5);
        // v grows downwards in glTF, so the bitangent (+v) points along −Y: handedness −1.
        assert_eq!(t[0].w, -1.0);
    }

    #[test]
    fn strips_and_fans_become_lists_with_one_winding() {
        // A strip of 5 vertices: triangles 012, 213 (flipped), 234.
        assert_eq!(triangle_list(Mode::TriangleStrip, (0..5).collect()).unwrap(), vec![0, 1, 2, 2, 1, 3, 2, 3, 4]);
        // A fan of 5 vertices around 0: 120, 230, 340.
        assert_eq!(triangle_list(Mode::TriangleFan, (0..5).collect()).unwrap(), vec![1, 2, 0, 2, 3, 0, 3, 4, 0]);
        assert!(triangle_list(Mode::TriangleStrip, vec![0, 1]).unwrap().is_empty());
        assert!(triangle_list(Mode::Points, vec![0]).unwrap_err().to_string().contains("points"));
        assert!(triangle_list(Mode::LineStrip, vec![0, 1]).unwrap_err().to_string().contains("lines"));
    }

    #[test]
    fn a_texture_transform_maps_as_the_extension_defines() {
        // Rotation by 90° then offset: (1, 0) → (cos, sin) = (0, 1), plus (0.5, 0.5); (0, 1) →
        // (−sin, cos) = (−1, 0).
        let t = transform_of([0.5, 0.5], std::f32::consts::FRAC_PI_2, [1.0, 1.0]);
        let uv = t[0] * 1.0 + t[1] * 0.0 + t[2];
        assert!((uv - Vec2::new(0.5, 1.5)).length() < 1e-6, "{uv}");
        let uv = t[0] * 0.0 + t[1] * 1.0 + t[2];
        assert!((uv - Vec2::new(-0.5, 0.5)).length() < 1e-6, "{uv}");
        let s = transform_of([0.0, 0.0], 0.0, [2.0, 3.0]);
        assert_eq!(s[0] * 1.0 + s[1] * 1.0 + s[2], Vec2::new(2.0, 3.0));
    }
}
