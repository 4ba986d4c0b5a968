//! Writes a species' model: three glTF 2.0 files (`NAME.gltf` every triangle, `NAME-lod1.gltf`
//! about 25 % of them, `NAME-lod2.gltf` about 5 %, each with its `.bin`) and the six PNG textures
//! they share beside them (`NAME-bark.png`, `-bark-normal`, `-bark-specular`, `NAME-leaf.png`,
//! `-leaf-normal`, `-leaf-specular`). Everything is written into a staging folder beside the
//! output and checked by grove's own loader there; only then does it move into place (the glTF
//! files last), so a failure leaves no partial output and nothing existing is replaced.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use super::atlas::{self, Atlas};
use super::mesh::{self, Lod};
use super::preset::{self, Preset};
use super::stems::{self, Tree};
use super::{SpeciesError, images};
use crate::assetgen::gltf_out::{self, MaterialTextures};

/// The leaf material's specular factor (`KHR_materials_specular`): with the leaf's specular
/// map (about 0.5) the sun's highlight is at most 0.25 × 0.5 × this of its light, and the sky's
/// reflection is skipped (the renderer's `glossy` stays under 0.02).
pub const LEAF_SPECULAR: f32 = 0.06;
/// The leaf material's roughness: a broad highlight.
pub const LEAF_ROUGHNESS: f32 = 0.8;

/// A generated model, before it is written.
pub struct Model {
    /// The species' name.
    pub name: String,
    /// The stems and leaves.
    pub tree: Tree,
    /// Full, about 25 % and about 5 % of the triangles.
    pub lods: [Lod; 3],
    /// The leaf texture and its cells.
    pub atlas: Atlas,
}

impl Model {
    /// Axis-aligned bounds (min, max) of the full mesh, metres.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let (a, b) = self.lods[0].wood.bounds();
        if self.lods[0].leaves.positions.is_empty() {
            return (a, b);
        }
        let (c, d) = self.lods[0].leaves.bounds();
        (a.min(c), b.max(d))
    }

    /// The largest horizontal distance of the full mesh from the trunk's axis, metres.
    pub fn crown_radius(&self) -> f32 {
        let l = &self.lods[0];
        l.wood.positions.iter().chain(&l.leaves.positions).map(|p| Vec2::new(p.x, p.z).length()).fold(0.0, f32::max)
    }
}

/// Generates the model of preset `p` named `name` with `seed`.
pub fn model(name: &str, p: &Preset, seed: u64) -> Result<Model, SpeciesError> {
    let tree = stems::generate(p, seed);
    let atlas = atlas::atlas(p);
    let lods = mesh::build(&tree, p, &atlas);
    if lods[0].wood.positions.is_empty() {
        return Err(SpeciesError::Empty(name.to_string()));
    }
    Ok(Model { name: name.to_string(), tree, lods, atlas })
}

/// What [`write`] wrote.
pub struct Written {
    /// The full model's glTF file.
    pub gltf: PathBuf,
    /// The model.
    pub model: Model,
}

/// The files a species' model consists of, in the order they are moved into place.
pub fn file_names(name: &str) -> Vec<String> {
    let mut v: Vec<String> = ["bark", "bark-normal", "bark-specular", "leaf", "leaf-normal", "leaf-specular"]
        .iter()
        .map(|t| format!("{name}-{t}.png"))
        .collect();
    for lod in lod_names(name) {
        v.push(format!("{lod}.bin"));
    }
    for lod in lod_names(name) {
        v.push(format!("{lod}.gltf"));
    }
    v
}

fn lod_names(name: &str) -> [String; 3] {
    [lod_name(name, 0), lod_name(name, 1), lod_name(name, 2)]
}

/// The file stem of level of detail `lod` (0, 1 or 2) of species `name`: `NAME`, `NAME-lod1`, `NAME-lod2`.
pub fn lod_name(name: &str, lod: usize) -> String {
    if lod == 0 { name.to_string() } else { format!("{name}-lod{lod}") }
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> SpeciesError + '_ {
    move |source| SpeciesError::Write { path: path.display().to_string(), source }
}

fn png(img: impl FnOnce(&Path) -> image::ImageResult<()>, path: &Path) -> Result<(), SpeciesError> {
    img(path).map_err(|e| SpeciesError::Write {
        path: path.display().to_string(),
        source: std::io::Error::other(e.to_string()),
    })
}

/// Loads the species `name_or_path` (a preset name or a `.ron` path), generates it with `seed`
/// and writes it into `out` (created if missing; files already there are never replaced).
pub fn write(name_or_path: &str, seed: u64, out: &Path) -> Result<Written, SpeciesError> {
    let (name, p) = preset::load(name_or_path)?;
    let names = file_names(&name);
    if let Some(f) = names.iter().map(|f| out.join(f)).find(|f| f.exists()) {
        return Err(SpeciesError::Exists(f.display().to_string()));
    }
    if out.exists() && !out.is_dir() {
        return Err(SpeciesError::Exists(out.display().to_string()));
    }
    let model = model(&name, &p, seed)?;
    let parent = out.parent().filter(|q| !q.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::create_dir_all(parent).map_err(io(parent))?;
    let stage = crate::atomic_write::temp_path(&parent.join(format!("{name}-species")));
    let result = stage_files(&stage, &model, &p).and_then(|()| place(&stage, out, &names));
    let _ = std::fs::remove_dir_all(&stage);
    result?;
    Ok(Written { gltf: out.join(format!("{name}.gltf")), model })
}

fn stage_files(stage: &Path, model: &Model, p: &Preset) -> Result<(), SpeciesError> {
    std::fs::create_dir_all(stage).map_err(io(stage))?;
    let n = &model.name;
    let (bark, bh) = images::bark(p);
    let (bn, bs) = images::maps(&bh, images::BARK_SIZE, 4.0, 0.25);
    let (leaf, lh, size) = (&model.atlas.image, &model.atlas.height, model.atlas.size);
    let (ln, ls) = images::maps(lh, size, 3.0, 0.5);
    let f = |t: &str| stage.join(format!("{n}-{t}.png"));
    png(|q| bark.save(q), &f("bark"))?;
    png(|q| bn.save(q), &f("bark-normal"))?;
    png(|q| bs.save(q), &f("bark-specular"))?;
    png(|q| leaf.save(q), &f("leaf"))?;
    png(|q| ln.save(q), &f("leaf-normal"))?;
    png(|q| ls.save(q), &f("leaf-specular"))?;
    let bark_mat = MaterialTextures::with_maps(&format!("{n}-bark"), "", false);
    // Leaves are matt: a weak, broad highlight and no sky reflection, so that no leaf flares
    // brighter than the sunlit ground.
    let leaf_mat = MaterialTextures {
        specular_factor: LEAF_SPECULAR,
        roughness: LEAF_ROUGHNESS,
        ..MaterialTextures::with_maps(&format!("{n}-leaf"), "", true)
    };
    for (lod, file) in model.lods.iter().zip(lod_names(n)) {
        let mut parts = vec![(&lod.wood, &bark_mat)];
        if !lod.leaves.positions.is_empty() {
            parts.push((&lod.leaves, &leaf_mat));
        }
        let bin = format!("{file}.bin");
        let (json, bytes) = gltf_out::build(&file, &parts, &bin);
        std::fs::write(stage.join(&bin), &bytes).map_err(io(&stage.join(&bin)))?;
        let gltf = stage.join(format!("{file}.gltf"));
        std::fs::write(&gltf, json.as_bytes()).map_err(io(&gltf))?;
        crate::bank::validate_gltf(&gltf).map_err(|source| SpeciesError::Invalid { name: n.clone(), source })?;
    }
    Ok(())
}

/// Moves the staged files into `out`: the whole folder in one rename when `out` is new, else
/// file by file, the glTF files last.
fn place(stage: &Path, out: &Path, names: &[String]) -> Result<(), SpeciesError> {
    if !out.exists() && std::fs::rename(stage, out).is_ok() {
        return Ok(());
    }
    std::fs::create_dir_all(out).map_err(io(out))?;
    for f in names {
        let to = out.join(f);
        if to.exists() {
            return Err(SpeciesError::Exists(to.display().to_string()));
        }
        std::fs::rename(stage.join(f), &to).map_err(io(&to))?;
    }
    Ok(())
}
