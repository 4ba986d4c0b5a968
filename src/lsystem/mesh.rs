//! Tree models from turtle segments: tapered tubes for the wood and alpha-clipped leaf cards at
//! the branch tips, with the `_WIND` channels of `docs/assets.md`, written as glTF 2.0 with the
//! species' bark and card materials (the writer of `assetgen`).
//!
//! Model space: metres, +Y up, origin at the base of the trunk. The turtle's units are scaled so
//! that the model is `height` metres tall.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Vec3, Vec4};

use super::derive::mix32;
use super::error::LsystemError;
use super::grammar::Grammar;
use super::turtle::Segment;
use crate::assetgen::geometry::{Limb, MeshData, card, tube};
use crate::assetgen::gltf_out::{self, MaterialTextures};
use crate::assetgen::species::Species;
use crate::assetgen::textures;

/// Options of a model.
#[derive(Clone, Copy, Debug)]
pub struct ModelOptions {
    /// The model's height, metres (the turtle's drawing is scaled to it).
    pub height: f32,
    /// The most segments a model may have.
    pub max_segments: usize,
}

impl Default for ModelOptions {
    fn default() -> ModelOptions {
        ModelOptions { height: 6.0, max_segments: 150_000 }
    }
}

/// The wood and leaves of a model, and facts about it.
pub struct Model {
    /// Branches.
    pub wood: MeshData,
    /// Leaf cards.
    pub leaves: MeshData,
    /// Number of leaf cards (one per branch tip).
    pub tips: usize,
    /// Axis-aligned bounds (min, max), metres.
    pub bounds: (Vec3, Vec3),
}

fn species(name: &str) -> Species {
    match name {
        "conifer" => Species::Conifer,
        "birch" => Species::Birch,
        "shrub" => Species::Shrub,
        _ => Species::Broadleaf,
    }
}

fn key(p: Vec3) -> [u32; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// A number in [0, 1) from a hash of `x`.
fn unit(x: u32) -> f32 {
    (mix32(x) >> 8) as f32 / (1u32 << 24) as f32
}

/// Builds the meshes of the segments.
pub fn build(g: &Grammar, segs: &[Segment], opts: &ModelOptions) -> Result<Model, LsystemError> {
    if segs.is_empty() {
        return Err(LsystemError::NoSegments(g.name.clone()));
    }
    if segs.len() > opts.max_segments {
        return Err(LsystemError::TooManySegments {
            name: g.name.clone(),
            segments: segs.len(),
            limit: opts.max_segments,
        });
    }
    if !(opts.height.is_finite() && opts.height > 0.0) {
        return Err(LsystemError::ModelHeight);
    }
    if segs.iter().any(|s| !(s.start.is_finite() && s.end.is_finite() && s.width.is_finite())) {
        return Err(LsystemError::NotFinite(g.name.clone()));
    }
    if segs.iter().all(|s| s.start == s.end) {
        return Err(LsystemError::ZeroLength(g.name.clone()));
    }
    let top = segs.iter().fold(0.0f32, |m, s| m.max(s.start.y).max(s.end.y));
    let extent = segs.iter().fold(0.0f32, |m, s| m.max(s.end.length()));
    let scale = opts.height / if top > 0.0 { top } else { extent.max(1e-6) };
    // The widest segment leaving each point: the taper's end radius.
    let mut from: HashMap<[u32; 3], f32> = HashMap::with_capacity(segs.len());
    for s in segs {
        let w = from.entry(key(s.start)).or_insert(0.0);
        *w = w.max(s.width);
    }
    let sp = species(&g.species);
    let leaf_size = match sp {
        Species::Broadleaf => 0.55,
        // A spray of needles: larger than a leaf, so that a twig's card reads as foliage.
        Species::Conifer => 0.8,
        Species::Birch => 0.4,
        Species::Shrub => 0.3,
    };
    let min_r = 0.004;
    let mut wood = MeshData::default();
    let mut tips = Vec::new();
    for (i, s) in segs.iter().enumerate() {
        let phase = if s.branch == 0 { 0.0 } else { unit(s.branch) };
        let (a, b) = (s.start * scale, s.end * scale);
        if a.distance(b) < 1e-6 {
            continue;
        }
        let r0 = (s.width * 0.5 * scale).max(min_r);
        let next = from.get(&key(s.end)).copied();
        let r1 = match next {
            Some(w) => (w * 0.5 * scale).clamp(min_r, r0),
            None => (r0 * 0.6).max(min_r),
        };
        let sides = if r0 > 0.05 {
            8
        } else if r0 > 0.015 {
            5
        } else {
            3
        };
        tube(&mut wood, &Limb { start: a, end: b, r0, r1, phase, trunk: s.depth == 0 }, sides, 1, 0.0, 1.0);
        if next.is_none() {
            tips.push((i, a, b, phase));
        }
    }
    if wood.positions.is_empty() {
        return Err(LsystemError::TooShort(g.name.clone()));
    }
    let crown = tips.iter().fold(Vec3::ZERO, |c, t| c + t.2) / tips.len().max(1) as f32;
    let mut leaves = MeshData::default();
    for &(i, a, b, phase) in &tips {
        let dir = (b - a).normalize_or(Vec3::Y);
        // A card hanging from the tip, turned by a hash of the segment so cards do not align.
        let turn = unit(i as u32 ^ 0x5eed) * std::f32::consts::TAU;
        let side = dir.any_orthonormal_vector();
        let normal = side * turn.cos() + dir.cross(side) * turn.sin();
        let centre = b + dir * (leaf_size * 0.35);
        card(&mut leaves, centre, normal, dir, leaf_size, crown, b, phase);
    }
    let (a, b) = wood.bounds();
    let (c, d) = if leaves.positions.is_empty() { (a, b) } else { leaves.bounds() };
    Ok(Model { wood, leaves, tips: tips.len(), bounds: (a.min(c), b.max(d)) })
}

/// What `write` wrote.
pub struct Written {
    /// The glTF file.
    pub gltf: PathBuf,
    /// Triangles of the model.
    pub triangles: usize,
}

fn save(img: Result<(), image::ImageError>, path: &Path) -> Result<(), LsystemError> {
    img.map_err(|error| LsystemError::WriteImage { path: path.to_path_buf(), error })
}

/// A folder created with its parents, or the error naming it.
fn create_folder(path: &Path) -> Result<(), LsystemError> {
    std::fs::create_dir_all(path).map_err(|error| LsystemError::CreateFolder { path: path.to_path_buf(), error })
}

/// Writes `model` as `dir/name.gltf` + `dir/name.bin`, with its textures in `dir/textures/`.
/// Refuses to replace an existing model file.
pub fn write(dir: &Path, name: &str, g: &Grammar, model: &Model) -> Result<Written, LsystemError> {
    let gltf = dir.join(format!("{name}.gltf"));
    if gltf.exists() {
        return Err(LsystemError::Exists(gltf));
    }
    // Everything is written into a staging folder beside `dir` first and checked there; only a
    // complete, valid model is moved into `dir` (the glTF file last), so a failure leaves no file.
    let parent = dir.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    create_folder(parent)?;
    let stage = crate::atomic_write::temp_path(&parent.join(format!("{name}-model")));
    let result = write_staged(&stage, dir, name, g, model);
    let _ = std::fs::remove_dir_all(&stage);
    result
}

fn write_staged(stage: &Path, dir: &Path, name: &str, g: &Grammar, model: &Model) -> Result<Written, LsystemError> {
    let tex = stage.join("textures");
    create_folder(&tex)?;
    let sp = species(&g.species);
    let n = sp.name();
    let (bark, bh) = textures::bark(sp, 128);
    let p = tex.join(format!("{n}-bark.png"));
    save(bark.save(&p), &p)?;
    let p = tex.join(format!("{n}-bark-normal.png"));
    save(textures::normal_from_height(&bh, 128, 4.0).save(&p), &p)?;
    let p = tex.join(format!("{n}-bark-specular.png"));
    save(textures::specular(&bh, 128, 0.25, 0.3).save(&p), &p)?;
    let (cardi, ch) = textures::card(sp, 256);
    let p = tex.join(format!("{n}-card.png"));
    save(cardi.save(&p), &p)?;
    let p = tex.join(format!("{n}-card-normal.png"));
    save(textures::normal_from_height(&ch, 256, 6.0).save(&p), &p)?;
    let p = tex.join(format!("{n}-card-specular.png"));
    save(textures::specular(&ch, 256, 0.4, 0.3).save(&p), &p)?;
    let bark_mat = MaterialTextures::bark(&n);
    let leaf_mat = MaterialTextures::with_maps(&format!("{n}-card"), "textures/", true);
    let mut parts: Vec<(&MeshData, &MaterialTextures)> = vec![(&model.wood, &bark_mat)];
    if !model.leaves.positions.is_empty() {
        parts.push((&model.leaves, &leaf_mat));
    }
    let bin = format!("{name}.bin");
    let (json, bytes) = gltf_out::build(name, &parts, &bin);
    let staged_bin = stage.join(&bin);
    std::fs::write(&staged_bin, &bytes).map_err(|error| LsystemError::Write { path: staged_bin.clone(), error })?;
    let staged_gltf = stage.join(format!("{name}.gltf"));
    std::fs::write(&staged_gltf, json.as_bytes())
        .map_err(|error| LsystemError::Write { path: staged_gltf.clone(), error })?;
    // The same check a model gets when it is added to a bank.
    crate::bank::validate_gltf(&staged_gltf).map_err(|error| LsystemError::Invalid { name: g.name.clone(), error })?;
    place(stage, dir, name, &bin)?;
    Ok(Written { gltf: dir.join(format!("{name}.gltf")), triangles: model.wood.triangles() + model.leaves.triangles() })
}

/// Moves a staged model into `dir`: textures that are already there with the same bytes are
/// kept, different ones are refused before anything moves; the glTF file moves last.
fn place(stage: &Path, dir: &Path, name: &str, bin: &str) -> Result<(), LsystemError> {
    let mut moves: Vec<(PathBuf, PathBuf)> = Vec::new();
    let staged_tex = stage.join("textures");
    for entry in
        std::fs::read_dir(&staged_tex).map_err(|error| LsystemError::List { path: staged_tex.clone(), error })?
    {
        let from = entry.map_err(LsystemError::Io)?.path();
        let to = dir.join("textures").join(from.file_name().unwrap_or_default());
        if to.exists() {
            let same = grove_systems::files::read(&to, grove_systems::files::Kind::Image).ok()
                == grove_systems::files::read(&from, grove_systems::files::Kind::Image).ok();
            if !same {
                return Err(LsystemError::OtherContent(to));
            }
            continue;
        }
        moves.push((from, to));
    }
    let to_bin = dir.join(bin);
    if to_bin.exists() {
        return Err(LsystemError::Exists(to_bin));
    }
    moves.push((stage.join(bin), to_bin));
    moves.push((stage.join(format!("{name}.gltf")), dir.join(format!("{name}.gltf"))));
    create_folder(&dir.join("textures"))?;
    for (from, to) in &moves {
        std::fs::rename(from, to).map_err(|error| LsystemError::Write { path: to.clone(), error })?;
    }
    Ok(())
}

/// The `_WIND` channel layout check used by tests: every vertex's x is its height above the root.
pub fn wind_height_ok(mesh: &MeshData) -> bool {
    mesh.positions.iter().zip(&mesh.wind).all(|(p, w): (&Vec3, &Vec4)| (w.x - p.y.max(0.0)).abs() < 1e-6)
}
