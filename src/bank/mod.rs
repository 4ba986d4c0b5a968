//! Model banks on disk: adding a glTF model to a bank, listing and checking banks, and loading
//! a session's bank models for the renderer (docs/model-bank.md).
//!
//! The catalogue format and the content hash are plain data in `grove_systems::bank`; this module
//! adds what needs the glTF loader ([`crate::models`], which also measures a model's mesh): the
//! extensions grove refuses ([`extensions`]), thumbnails ([`thumbnail`]) and `grove models add`
//! ([`import`]).

pub mod error;
pub mod extensions;
pub mod import;
pub mod thumbnail;
pub mod validate;

use std::path::{Path, PathBuf};

use grove_systems::bank::{BANK_ENV, Banks, bank_dirs};
use grove_systems::catalogue::ModelId;

pub use error::BankError;
pub use validate::validate_gltf;

/// The bank folders of a session: the `--bank` folders in order, then those of `GROVE_BANK`.
pub fn session_dirs(args: &[PathBuf]) -> Vec<PathBuf> {
    let env = std::env::var(BANK_ENV).ok();
    bank_dirs(args, env.as_deref())
}

/// Opens the banks of a session (see [`session_dirs`]).
pub fn open_session(args: &[PathBuf]) -> Result<Banks, BankError> {
    Ok(Banks::open(&session_dirs(args))?)
}

/// Opens the banks of a session on a scene: the scene's own banks first, then [`session_dirs`].
pub fn open_for_scene(scene: &grove_systems::scene::Scene, args: &[PathBuf]) -> Result<Banks, BankError> {
    let mut dirs = scene.bank_dirs();
    for d in session_dirs(args) {
        if !dirs.contains(&d) {
            dirs.push(d);
        }
    }
    Ok(Banks::open(&dirs)?)
}

/// A bank model for the renderer: its id in the session's catalogue, its glTF file, and the id
/// of its far model ([`grove_systems::bank::BankModel::far`]) where that is in the catalogue too.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFile {
    /// The model's id.
    pub id: ModelId,
    /// Its glTF file.
    pub path: PathBuf,
    /// The id of the coarser model drawn in its place where the tree is small on screen.
    pub far: Option<ModelId>,
}

/// The glTF file of every bank model of a session catalogue, with its model id (ids from 8 on,
/// in the order of [`Banks::session_catalogue`]), for the renderer to load.
pub fn model_files(banks: &Banks) -> Result<Vec<ModelFile>, BankError> {
    let (catalogue, _) = banks.session_catalogue()?;
    Ok(files_for(banks, &catalogue))
}

/// The glTF files of the models a catalogue holds beyond the shipped ones, looked up by name in
/// the banks (for a replay, whose catalogue comes from its header).
pub fn files_for(banks: &Banks, catalogue: &grove_systems::catalogue::Catalogue) -> Vec<ModelFile> {
    let id_of = |name: &str| catalogue.models.iter().find(|m| m.name == name).map(|m| m.id);
    catalogue
        .models
        .iter()
        .skip(grove_systems::catalogue::SHIPPED_MODELS)
        .filter_map(|m| {
            banks.find(&m.name).map(|(b, bm)| ModelFile {
                id: m.id,
                path: b.file_of(bm),
                far: bm.far.as_deref().and_then(id_of),
            })
        })
        .collect()
}

/// Loads bank models into a renderer (see [`model_files`], [`files_for`]) and ties each to its
/// far model; the error names the file.
pub fn load_into(renderer: &mut crate::render::Renderer, files: &[ModelFile]) -> Result<(), BankError> {
    for f in files {
        let data = validate_gltf(&f.path)?;
        renderer.features.trees.set_model(f.id, &data);
    }
    for f in files {
        renderer.features.trees.set_far(f.id, f.far);
    }
    Ok(())
}

/// Loads into a renderer the models of `catalogue` beyond the shipped ones (a scene's or a
/// replay's), found in the scene's own banks and then the session's (`args`, `GROVE_BANK`).
pub fn load_for_scene(
    renderer: &mut crate::render::Renderer,
    scene: &grove_systems::scene::Scene,
    args: &[PathBuf],
    catalogue: &grove_systems::catalogue::Catalogue,
) -> Result<(), BankError> {
    let banks = open_for_scene(scene, args)?;
    load_into(renderer, &files_for(&banks, catalogue))
}

/// The folder of the shipped models (`assets/trees` of the source tree).
pub fn shipped_dir() -> PathBuf {
    crate::render::default_assets_dir().join("trees")
}

/// Whether `path` lies inside `dir` once both are made absolute (no symbolic links followed).
pub fn lies_inside(path: &Path, dir: &Path) -> bool {
    match (std::path::absolute(path), std::path::absolute(dir)) {
        (Ok(p), Ok(d)) => p.starts_with(d),
        _ => false,
    }
}
