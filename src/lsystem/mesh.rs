//! Tree models from turtle segments: tapered tubes for the wood and alpha-clipped leaf cards at
//! the branch tips, with the `_WIND` channels of `docs/assets.md`, written as glTF 2.0 with the
//! species' bark and card materials (the writer of `assetgen`).
//!
//! Model space: metres, +Y up, origin at the base of the trunk. The turtle's units are scaled so
//! that the model is `height` metres tall.

use std::collections::HashMap;
use std::path::Path;

use anyhow::{bail, Context};
use glam::{Vec3, Vec4};

use super::derive::mix32;
use super::grammar::Grammar;
use super::turtle::Segment;
use crate::assetgen::geometry::{card, tube, Limb, MeshData};
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
pub fn build(g: &Grammar, segs: &[Segment], opts: &ModelOptions) -> anyhow::Result<Model> {
    if segs.is_empty() {
        bail!("'{}' draws nothing (no F in the derived string)", g.name);
    }
    if segs.len() > opts.max_segments {
        bail!("'{}' has {} segments, more than a model's limit of {}; use a smaller --n", g.name, segs.len(), opts.max_segments);
    }
    if !(opts.height.is_finite() && opts.height > 0.0) {
        bail!("the height must be a positive number of metres");
    }
    if segs.iter().any(|s| !(s.start.is_finite() && s.end.is_finite() && s.width.is_finite())) {
        bail!("'{}' draws a segment at a position or width that is not a finite number; check its parameters", g.name);
    }
    if segs.iter().all(|s| s.start == s.end) {
        bail!("'{}' draws nothing: every segment has zero length (check the parameters of F)", g.name);
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
        let sides = if r0 > 0.05 { 8 } else if r0 > 0.015 { 5 } else { 3 };
        tube(&mut wood, &Limb { start: a, end: b, r0, r1, phase, trunk: s.depth == 0 }, sides, 1, 0.0, 1.0);
        if next.is_none() {
            tips.push((i, a, b, phase));
        }
    }
    if wood.positions.is_empty() {
        bail!("'{}' draws nothing: its segments are too short to draw (check the parameters of F)", g.name);
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
    pub gltf: std::path::PathBuf,
    /// Triangles of the model.
    pub triangles: usize,
}

fn save(img: Result<(), image::ImageError>, path: &Path) -> anyhow::Result<()> {
    img.with_context(|| format!("{}: cannot write", path.display()))
}

/// Writes `model` as `dir/name.gltf` + `dir/name.bin`, with its textures in `dir/textures/`.
/// Refuses to replace an existing model file.
pub fn write(dir: &Path, name: &str, g: &Grammar, model: &Model) -> anyhow::Result<Written> {
    let gltf = dir.join(format!("{name}.gltf"));
    if gltf.exists() {
        bail!("{}: already exists; choose another --out folder or remove it", gltf.display());
    }
    // Everything is written into a staging folder beside `dir` first and checked there; only a
    // complete, valid model is moved into `dir` (the glTF file last), so a failure leaves no file.
    let parent = dir.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).with_context(|| format!("{}: cannot create folder", parent.display()))?;
    let stage = crate::atomic_write::temp_path(&parent.join(format!("{name}-model")));
    let result = write_staged(&stage, dir, name, g, model);
    let _ = std::fs::remove_dir_all(&stage);
    result
}

fn write_staged(stage: &Path, dir: &Path, name: &str, g: &Grammar, model: &Model) -> anyhow::Result<Written> {
    let tex = stage.join("textures");
    std::fs::create_dir_all(&tex).with_context(|| format!("{}: cannot create folder", tex.display()))?;
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
    std::fs::write(&staged_bin, &bytes).with_context(|| format!("{}: cannot write", staged_bin.display()))?;
    let staged_gltf = stage.join(format!("{name}.gltf"));
    std::fs::write(&staged_gltf, json.as_bytes()).with_context(|| format!("{}: cannot write", staged_gltf.display()))?;
    // The same check a model gets when it is added to a bank.
    crate::bank::validate_gltf(&staged_gltf).with_context(|| format!("the model written for '{}' is not valid", g.name))?;
    place(stage, dir, name, &bin)?;
    Ok(Written { gltf: dir.join(format!("{name}.gltf")), triangles: model.wood.triangles() + model.leaves.triangles() })
}

/// Moves a staged model into `dir`: textures that are already there with the same bytes are
/// kept, different ones are refused before anything moves; the glTF file moves last.
fn place(stage: &Path, dir: &Path, name: &str, bin: &str) -> anyhow::Result<()> {
    let mut moves: Vec<(std::path::PathBuf, std::path::PathBuf)> = Vec::new();
    let staged_tex = stage.join("textures");
    for entry in std::fs::read_dir(&staged_tex).with_context(|| format!("{}: cannot list", staged_tex.display()))? {
        let from = entry?.path();
        let to = dir.join("textures").join(from.file_name().unwrap_or_default());
        if to.exists() {
            let same = grove_systems::files::read(&to, grove_systems::files::Kind::Image).ok() == grove_systems::files::read(&from, grove_systems::files::Kind::Image).ok();
            if !same {
                bail!("{}: already exists with other content; choose another --out folder", to.display());
            }
            continue;
        }
        moves.push((from, to));
    }
    let to_bin = dir.join(bin);
    if to_bin.exists() {
        bail!("{}: already exists; choose another --out folder or remove it", to_bin.display());
    }
    moves.push((stage.join(bin), to_bin));
    moves.push((stage.join(format!("{name}.gltf")), dir.join(format!("{name}.gltf"))));
    std::fs::create_dir_all(dir.join("textures")).with_context(|| format!("{}: cannot create folder", dir.join("textures").display()))?;
    for (from, to) in &moves {
        std::fs::rename(from, to).with_context(|| format!("{}: cannot write", to.display()))?;
    }
    Ok(())
}

/// The `_WIND` channel layout check used by tests: every vertex's x is its height above the root.
pub fn wind_height_ok(mesh: &MeshData) -> bool {
    mesh.positions.iter().zip(&mesh.wind).all(|(p, w): (&Vec3, &Vec4)| (w.x - p.y.max(0.0)).abs() < 1e-6)
}
