//! Loading glTF 2.0 models (`.gltf` + resources, or `.glb`) through the `gltf` crate into plain
//! CPU data the renderer uploads ([`ModelData`]).
//!
//! Any glTF 2.0 file works, not only grove's own, and every feature of a file is either drawn
//! or refused by name (docs/model-bank.md, "What grove reads in a glTF file"):
//!
//! - the file and every buffer and image it names are read through `grove_systems::files`
//!   (`gltf_files`): a URI that leads out of the model's folder is refused before anything is
//!   read; `asset.version` must be 2.x, every buffer view and accessor must lie inside its data,
//!   and every required extension must be one grove reads (`gltf_check`);
//! - the node hierarchy of the default scene is flattened (each primitive's vertices are
//!   transformed to model space); a skinned mesh is drawn in its bind pose, morph targets with
//!   the mesh's (or node's) default weights, animations not at all (the rest pose);
//! - triangle strips and fans become lists; points and lines are refused by name
//!   (`gltf_prim`); vertex colours multiply the base colour; each material's textures are read
//!   through their own `texCoord` set with their `KHR_texture_transform`;
//! - missing normals are computed from the triangles, missing tangents from the texture
//!   coordinates, missing texture coordinates are zero, and missing textures are replaced by
//!   neutral 1×1 textures;
//! - the model must have height: a model 0 m tall (an all-zero node matrix, say) is refused.
//!
//! Errors are one line naming the file (and the buffer, texture or primitive at fault); nothing
//! here panics on bad input.

use std::path::Path;

use glam::{Mat4, Vec3, Vec4};
use grove_systems::files::{self, Kind};

use super::error::{GltfError, GltfProblem};
use super::gltf_prim::{UvChoice, name_of, primitive, uv_choice};
pub use super::gltf_prim::{compute_normals, compute_tangents};
use super::mesh::{ImageData, MaterialData, ModelData};

/// The most nodes visited while flattening a hierarchy.
const MAX_NODE_VISITS: usize = 1_000_000;

/// Loads a glTF 2.0 model. The error is one line naming the file.
pub fn load_model(path: &Path) -> Result<ModelData, GltfError> {
    let file = path.display().to_string();
    let err = |problem: GltfProblem| GltfError::Model { path: path.to_path_buf(), problem };
    let bytes = files::read(path, Kind::Gltf).map_err(GltfError::File)?;
    let (required, used) = super::gltf_open::extensions_of(&bytes);
    let mut warnings = super::gltf_check::extensions(&file, &required, &used).map_err(&err)?;
    let gltf = super::gltf_open::parse(&bytes).map_err(|e| err(GltfProblem::Parse(one_line(&e.to_string()))))?;
    let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let doc = gltf.document;
    super::gltf_check::version(&doc).map_err(&err)?;
    // Every URI's place is checked before any file is read, so that the first fault named is
    // the one that matters (a texture outside the folder, not a buffer read first).
    for (what, uri) in doc
        .buffers()
        .filter_map(|b| match b.source() {
            gltf::buffer::Source::Uri(u) => Some(("buffer", u)),
            gltf::buffer::Source::Bin => None,
        })
        .chain(doc.images().filter_map(|i| match i.source() {
            gltf::image::Source::Uri { uri, .. } => Some(("texture", uri)),
            gltf::image::Source::View { .. } => None,
        }))
    {
        super::gltf_files::resolve(base, uri)
            .map_err(|m| err(GltfProblem::Uri { what, uri: uri.to_string(), problem: Box::new(m) }))?;
    }
    let buffers = super::gltf_files::load_buffers(&doc, base, gltf.blob).map_err(&err)?;
    super::gltf_check::bounds(&doc, &buffers).map_err(&err)?;
    let mut images = Vec::new();
    for (i, img) in doc.images().enumerate() {
        let name = match img.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => format!("texture '{uri}'"),
            _ => format!("image {i}"),
        };
        let data =
            load_image(&img, base, &buffers).map_err(|m| err(GltfProblem::Part { name, problem: Box::new(m) }))?;
        images.push(data);
    }
    let mut materials: Vec<MaterialData> = doc.materials().map(|m| material(&m)).collect();
    let uv_choices: Vec<Result<UvChoice, GltfProblem>> = doc.materials().map(|m| uv_choice(&m)).collect();
    for m in doc.materials() {
        warnings.extend(unread_material_parts(&m));
    }
    let default_material = materials.len();
    materials.push(MaterialData::default());

    let mut primitives = Vec::new();
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let mut stack: Vec<(gltf::Node, Mat4)> = match &scene {
        Some(s) => s.nodes().map(|n| (n, Mat4::IDENTITY)).collect(),
        None => doc.nodes().map(|n| (n, Mat4::IDENTITY)).collect(),
    };
    let (mut visits, mut skinned) = (0usize, false);
    while let Some((node, parent)) = stack.pop() {
        visits += 1;
        if visits > MAX_NODE_VISITS {
            return Err(err(GltfProblem::NodeHierarchy));
        }
        let m = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            // A skinned mesh ignores its node's transform; with its joints in the bind pose its
            // vertices are where the file stores them.
            let place = if node.skin().is_some() { Mat4::IDENTITY } else { m };
            skinned |= node.skin().is_some();
            let weights = node.weights().or(mesh.weights()).unwrap_or(&[]);
            for prim in mesh.primitives() {
                let name = name_of(&mesh, &prim);
                let (mat, uv) = match prim.material().index() {
                    Some(i) => (i, uv_choices.get(i).cloned().unwrap_or(Ok(UvChoice::default())).map_err(&err)?),
                    None => (default_material, UvChoice::default()),
                };
                if let Some(p) = primitive(&prim, &buffers, place, weights, (mat, uv))
                    .map_err(|m| err(GltfProblem::Primitive { name, problem: Box::new(m) }))?
                {
                    if !p.indices.is_empty() {
                        primitives.push(p);
                    }
                }
            }
        }
        for c in node.children() {
            stack.push((c, m));
        }
    }
    if primitives.is_empty() {
        return Err(err(GltfProblem::NoTriangles));
    }
    let mut bounds = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in &primitives {
        for v in &p.vertices {
            let q = Vec3::from(v.position);
            bounds = (bounds.0.min(q), bounds.1.max(q));
        }
    }
    if !(bounds.0.is_finite() && bounds.1.is_finite()) {
        return Err(err(GltfProblem::NonFinite));
    }
    let height = bounds.1.y - bounds.0.y;
    if !(height > 1e-6) {
        return Err(err(GltfProblem::Flat { height, min: bounds.0.to_array(), max: bounds.1.to_array() }));
    }
    let own_wind = primitives.iter().all(|p| p.vertices.iter().all(|v| v.wind[3] >= 0.0));
    if !own_wind {
        let clipped: Vec<bool> =
            primitives.iter().map(|p| materials.get(p.material).is_some_and(|m| m.alpha_cutoff.is_some())).collect();
        super::wind_channels::compute_with(&mut primitives, bounds.0.y, &clipped);
    }
    let mut notes = Vec::new();
    let animations = doc.animations().count();
    if animations > 0 {
        notes.push(format!("{animations} animation{} shown at the rest pose", if animations == 1 { "" } else { "s" }));
    }
    if skinned {
        notes.push("skinned mesh drawn in its bind pose".into());
    }
    let warnings = warnings.into_iter().map(|w| format!("{file}: {w}")).collect();
    Ok(ModelData { path: path.to_path_buf(), primitives, materials, images, bounds, own_wind, notes, warnings })
}

fn one_line(s: &str) -> String {
    s.replace('\n', " ")
}

/// What grove does not draw of a material, as warnings: emission, occlusion, the
/// metallic-roughness texture (grove shades with the roughness factor alone), the specular
/// colour, and alpha blending (drawn opaque).
fn unread_material_parts(m: &gltf::Material) -> Vec<String> {
    let mut parts = Vec::new();
    if m.alpha_mode() == gltf::material::AlphaMode::Blend {
        parts.push("its alpha blending (it is drawn opaque)");
    }
    if m.specular().is_some_and(|s| s.specular_color_texture().is_some() || s.specular_color_factor() != [1.0; 3]) {
        parts.push("its specular colour");
    }
    if m.emissive_texture().is_some() || m.emissive_factor().iter().any(|&c| c > 0.0) {
        parts.push("its emission");
    }
    if m.occlusion_texture().is_some() {
        parts.push("its occlusion texture");
    }
    if m.pbr_metallic_roughness().metallic_roughness_texture().is_some() {
        parts.push("its metallic-roughness texture");
    }
    if parts.is_empty() {
        return Vec::new();
    }
    vec![format!("material '{}': grove does not draw {}", m.name().unwrap_or("unnamed"), parts.join(" or "))]
}

fn load_image(img: &gltf::Image, base: &Path, buffers: &[gltf::buffer::Data]) -> Result<ImageData, GltfProblem> {
    let bytes: Vec<u8> = match img.source() {
        gltf::image::Source::Uri { uri, .. } => match super::gltf_files::read_uri(base, uri)? {
            Some(b) => b,
            None => super::gltf_files::data_uri(uri)?,
        },
        gltf::image::Source::View { view, .. } => {
            let buf = buffers.get(view.buffer().index()).ok_or(GltfProblem::ImageView)?;
            let (s, e) = (view.offset(), view.offset() + view.length());
            buf.0.get(s..e).ok_or(GltfProblem::ImageView)?.to_vec()
        }
    };
    let decoded = image::load_from_memory(&bytes).map_err(|e| GltfProblem::Decode(one_line(&e.to_string())))?;
    let rgba = decoded.to_rgba8();
    let (width, height) = rgba.dimensions();
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(GltfProblem::ImageSize { width, height });
    }
    Ok(ImageData { width, height, rgba: rgba.into_raw() })
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
