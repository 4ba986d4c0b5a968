//! `grove assets`: the deterministic procedural generator of the tree models, their textures,
//! the model catalogue, the ground texture and the sky cubemap.
//!
//! Output layout under the output folder (default `assets/`):
//! - `trees/<name>.gltf` + `trees/<name>.bin` for the 8 models of the catalogue;
//! - `trees/textures/<species>-{bark,leaf,card}[-normal|-specular].png`;
//! - `trees/catalogue.ron`, with bounds, crown radius and triangle count computed from the same
//!   geometry that goes into the glTF files;
//! - `env/{px,nx,py,ny,pz,nz}.png` (the sky cubemap) and `env/ground.png`.
//!
//! Every random choice comes from seeded generators, so every run writes the same bytes. The
//! format is described in `docs/assets.md`.

pub mod geometry;
pub mod gltf_out;
pub mod species;
pub mod textures;

use std::path::Path;

use anyhow::Context;
use glam::Vec3;
use grove_systems::catalogue::{Catalogue, ModelId, ModelInfo, ModelKind};
use image::{RgbImage, RgbaImage};

use geometry::MeshData;
use gltf_out::MaterialTextures;
use species::Species;

/// Size of a cube face, texels.
pub const CUBE_SIZE: u32 = 128;

/// What the generator wrote.
pub struct Summary {
    /// The catalogue it wrote.
    pub catalogue: Catalogue,
    /// Number of files written.
    pub files: usize,
}

enum Img {
    Rgb(RgbImage),
    Rgba(RgbaImage),
}

fn write_png(path: &Path, img: Img) -> anyhow::Result<()> {
    crate::atomic_write::write_via_temp(path, |tmp| {
        let result = match img {
            Img::Rgb(i) => i.save(tmp),
            Img::Rgba(i) => i.save(tmp),
        };
        result.with_context(|| format!("{}: cannot write", path.display()))
    })
}

fn write(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    crate::atomic_write::write_atomic(path, bytes)
}

/// Formats a catalogue as RON in the layout of `assets/trees/catalogue.ron`.
pub fn catalogue_ron(cat: &Catalogue) -> String {
    let v = |v: Vec3| format!("({:?}, {:?}, {:?})", v.x, v.y, v.z);
    let mut s = String::from(
        "// The model catalogue: written by `grove assets` from the generated glTF geometry.\n\
         // Model space: metres, +Y up, origin at the base of the trunk.\n(\n    models: [\n",
    );
    for m in &cat.models {
        s.push_str(&format!(
            "        (id: {}, name: {:?}, species: {:?}, kind: {:?}, bounds_min: {}, bounds_max: {}, crown_radius: {:?}, triangles: {}{}),\n",
            m.id.0,
            m.name,
            m.species,
            m.kind,
            v(m.bounds_min),
            v(m.bounds_max),
            m.crown_radius,
            m.triangles,
            m.pick.map_or(String::new(), |p| format!(
                ",\n            pick: Some((bottom: {:?}, top: {:?}, radii: ({})))",
                p.bottom,
                p.top,
                p.radii.iter().map(|r| format!("{r:?}")).collect::<Vec<_>>().join(", ")
            ))
        ));
    }
    s.push_str("    ],\n)\n");
    s
}

/// Generates every asset under `out`.
pub fn generate(out: &Path) -> anyhow::Result<Summary> {
    let trees = out.join("trees");
    let tex = trees.join("textures");
    let env = out.join("env");
    for d in [&trees, &tex, &env] {
        std::fs::create_dir_all(d).with_context(|| format!("{}: cannot create folder", d.display()))?;
    }
    let mut files = 0;

    // Textures, per species.
    for sp in Species::ALL {
        let n = sp.name();
        let (bark, bh) = textures::bark(sp, 128);
        write_png(&tex.join(format!("{n}-bark.png")), Img::Rgb(bark))?;
        write_png(&tex.join(format!("{n}-bark-normal.png")), Img::Rgb(textures::normal_from_height(&bh, 128, 4.0)))?;
        write_png(&tex.join(format!("{n}-bark-specular.png")), Img::Rgba(textures::specular(&bh, 128, 0.25, 0.3)))?;
        let (leaf, lh) = textures::leaf(sp, 64);
        write_png(&tex.join(format!("{n}-leaf.png")), Img::Rgba(leaf))?;
        write_png(&tex.join(format!("{n}-leaf-normal.png")), Img::Rgb(textures::normal_from_height(&lh, 64, 3.0)))?;
        write_png(&tex.join(format!("{n}-leaf-specular.png")), Img::Rgba(textures::specular(&lh, 64, 0.5, 0.4)))?;
        let (card, ch) = textures::card(sp, 256);
        write_png(&tex.join(format!("{n}-card.png")), Img::Rgba(card))?;
        write_png(&tex.join(format!("{n}-card-normal.png")), Img::Rgb(textures::normal_from_height(&ch, 256, 6.0)))?;
        write_png(&tex.join(format!("{n}-card-specular.png")), Img::Rgba(textures::specular(&ch, 256, 0.4, 0.3)))?;
        files += 9;
    }

    // Models: the four mesh trees, then the four billboard trees (catalogue order).
    let mut models = Vec::new();
    for (kind_index, kind) in [ModelKind::Mesh, ModelKind::Billboard].into_iter().enumerate() {
        for (si, sp) in Species::ALL.into_iter().enumerate() {
            let id = (kind_index * 4 + si) as u8;
            let suffix = if kind == ModelKind::Mesh { "mesh" } else { "billboard" };
            let name = format!("{}-{suffix}", sp.name());
            let skel = species::skeleton(sp, kind == ModelKind::Billboard);
            let wood = species::wood(&skel);
            let foliage: MeshData = match kind {
                ModelKind::Mesh => species::mesh_foliage(sp, &skel),
                ModelKind::Billboard => species::card_foliage(sp, &skel),
            };
            let n = sp.name();
            let bark_mat = MaterialTextures::bark(n);
            let leaf_tex = if kind == ModelKind::Mesh { "leaf" } else { "card" };
            let leaf_mat = MaterialTextures::with_maps(&format!("{n}-{leaf_tex}"), "textures/", true);
            let bin = format!("{name}.bin");
            let (json, bytes) = gltf_out::build(&name, &[(&wood, &bark_mat), (&foliage, &leaf_mat)], &bin);
            write(&trees.join(format!("{name}.gltf")), json.as_bytes())?;
            write(&trees.join(&bin), &bytes)?;
            files += 2;
            let (a, b) = wood.bounds();
            let (c, d) = foliage.bounds();
            models.push(ModelInfo {
                id: ModelId(id),
                name,
                species: n.to_string(),
                kind,
                bounds_min: a.min(c),
                bounds_max: b.max(d),
                crown_radius: crate::models::measure::crown_radius([
                    wood.positions.as_slice(),
                    foliage.positions.as_slice(),
                ]),
                triangles: (wood.triangles() + foliage.triangles()) as u32,
                pick: Some(crate::models::pick::pick_shape(&[
                    (&wood.positions, &wood.indices),
                    (&foliage.positions, &foliage.indices),
                ])),
            });
        }
    }
    let catalogue = Catalogue { models };
    write(&trees.join("catalogue.ron"), catalogue_ron(&catalogue).as_bytes())?;
    files += 1;

    // The environment: the sky cubemap and the ground texture.
    for (face, name) in crate::cubemap::FACES.iter().enumerate() {
        write_png(&env.join(format!("{name}.png")), Img::Rgb(textures::sky_face(face, CUBE_SIZE)))?;
    }
    write_png(&env.join("ground.png"), Img::Rgb(textures::ground(256)))?;
    files += 7;
    Ok(Summary { catalogue, files })
}
