//! `grove models add`: validate a glTF model, measure it, copy it with its buffers and textures
//! into a bank folder, and add its entry to the bank's catalogue.
//!
//! The model goes to `BANK/<name>/` under its own file names; the catalogue is rewritten through
//! a temporary file and a rename. A name the bank already holds is refused unless the files are
//! identical (then nothing changes), so a different model is never overwritten.

use std::path::{Path, PathBuf};

use grove_systems::bank::{Bank, BankModel, CATALOGUE_FILE, MAX_MODELS, WindSource, hash_files, valid_name};
use grove_systems::catalogue::{Catalogue, ModelKind};

use grove_systems::files::{self, Kind};

use super::BankError;
use crate::models::{ModelData, gltf_files};

/// What to add, and under which name.
#[derive(Clone, Debug)]
pub struct AddRequest {
    /// The glTF (`.gltf` or `.glb`) file.
    pub file: PathBuf,
    /// The bank folder (created when missing).
    pub bank: PathBuf,
    /// The model's name (default: the file's stem).
    pub name: Option<String>,
    /// The species (default: the name).
    pub species: Option<String>,
    /// The kind (default: measured from the materials).
    pub kind: Option<ModelKind>,
    /// A coarser model of the same tree, already in the bank, that the renderer draws in this
    /// one's place where the tree is small on screen ([`BankModel::far`]).
    pub far: Option<String>,
}

/// What `add` did.
#[derive(Clone, Debug)]
pub enum Added {
    /// The model was copied in and catalogued.
    New(BankModel),
    /// The bank already held this model with identical files; nothing changed.
    Unchanged(BankModel),
}

/// The files a glTF file names beside itself (buffers and images that are not `data:` URIs),
/// relative to its folder, in document order without repeats. One that lies outside the folder
/// (`..`, an absolute path, a URL, or a symbolic link to a file or through a folder outside it)
/// is refused with one line naming the URI, before anything it names is read.
pub fn resources_of(file: &Path) -> Result<Vec<String>, BankError> {
    let bytes = files::read(file, Kind::Gltf).map_err(BankError::File)?;
    let gltf = crate::models::gltf_open::parse(&bytes)
        .map_err(|error| BankError::NotGltf { file: file.to_path_buf(), error })?;
    let mut uris: Vec<String> = Vec::new();
    for b in gltf.document.buffers() {
        if let gltf::buffer::Source::Uri(u) = b.source() {
            uris.push(u.to_string());
        }
    }
    for i in gltf.document.images() {
        if let gltf::image::Source::Uri { uri, .. } = i.source() {
            uris.push(uri.to_string());
        }
    }
    let base = source_dir(file);
    let mut out: Vec<String> = Vec::new();
    for u in uris {
        let named = |problem| BankError::Uri { file: file.to_path_buf(), uri: u.clone(), problem };
        let Some(rel) = gltf_files::relative_path(&u).map_err(named)? else { continue };
        gltf_files::resolve(&base, &u).map_err(named)?;
        if !out.contains(&rel) {
            out.push(rel);
        }
    }
    Ok(out)
}

/// The folder of a model file (`.` for a bare file name).
fn source_dir(file: &Path) -> PathBuf {
    file.parent().filter(|p| !p.as_os_str().is_empty()).map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."))
}

/// Loads a file the way `add` does, with every check of [`super::validate_gltf`].
pub fn load_checked(file: &Path) -> Result<ModelData, BankError> {
    super::validate_gltf(file)
}

/// Adds a model to a bank (see the module docs).
pub fn add(req: &AddRequest) -> Result<Added, BankError> {
    add_noted(req).map(|(added, _)| added)
}

/// [`add`], also returning the loaded model's `notes` (what a still shows in one state: the
/// rest pose of its animations, the bind pose of a skin) and `warnings` (what grove does not
/// draw), for the command's output.
pub fn add_noted(req: &AddRequest) -> Result<(Added, ModelData), BankError> {
    let file = &req.file;
    if !file.is_file() {
        return Err(BankError::NotAFile { file: file.clone(), exists: file.exists() });
    }
    let data = load_checked(file)?;
    let added = add_loaded(req, &data)?;
    Ok((added, data))
}

fn add_loaded(req: &AddRequest, data: &ModelData) -> Result<Added, BankError> {
    let file = &req.file;
    let stem = file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = req.name.clone().unwrap_or(stem);
    if !valid_name(&name) {
        return Err(BankError::Name(name));
    }
    if Catalogue::builtin().by_name(&name).is_some() {
        return Err(BankError::ShippedName(name));
    }
    let species = req.species.clone().unwrap_or_else(|| name.clone());
    if species.is_empty() || species.len() > 64 || species.chars().any(char::is_control) {
        return Err(BankError::Species);
    }
    let src_dir = source_dir(file);
    let main = file
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .ok_or_else(|| BankError::NoFileName(file.clone()))?;
    let mut rels = vec![main.clone()];
    for r in resources_of(file)? {
        if !rels.contains(&r) {
            rels.push(r);
        }
    }
    // Only regular files whose real path lies inside the model's folder are copied (checked
    // again here, after the model was loaded, and read through `files` below).
    for r in &rels[1..] {
        let p = src_dir.join(r);
        if !p.exists() {
            return Err(BankError::Missing { file: file.clone(), rel: r.clone() });
        }
        files::within(&p, &src_dir).map_err(|error| BankError::Outside {
            file: file.clone(),
            rel: r.clone(),
            error,
        })?;
    }
    let files: Vec<String> = rels.iter().map(|r| format!("{name}/{r}")).collect();
    let hash = hash_files(files.iter().zip(&rels).map(|(f, r)| (f.as_str(), src_dir.join(r))))?;

    std::fs::create_dir_all(&req.bank).map_err(|error| BankError::CreateBank { path: req.bank.clone(), error })?;
    let bank = Bank::open(&req.bank)?;
    if let Some(far) = &req.far {
        match bank.get(far) {
            Some(f) if f.far.is_none() && far != &name => {}
            Some(_) => return Err(BankError::FarNotPlain { bank: req.bank.clone(), far: far.clone() }),
            None => return Err(BankError::FarMissing { bank: req.bank.clone(), far: far.clone() }),
        }
    }
    if let Some(old) = bank.get(&name) {
        if old.hash == hash && old.far == req.far {
            return Ok(Added::Unchanged(old.clone()));
        }
        return Err(BankError::NameTaken { bank: req.bank.clone(), name });
    }
    if bank.catalogue.models.len() >= MAX_MODELS - Catalogue::builtin().len() {
        return Err(BankError::Full { bank: req.bank.clone(), models: bank.catalogue.models.len() });
    }
    let dest = req.bank.join(&name);
    if dest.exists() {
        return Err(BankError::Uncatalogued(dest));
    }

    let m = crate::models::measure(data);
    let model = BankModel {
        name: name.clone(),
        species,
        kind: req.kind.unwrap_or(m.kind),
        file: format!("{name}/{main}"),
        files,
        hash,
        bounds_min: m.bounds_min,
        bounds_max: m.bounds_max,
        crown_radius: m.crown_radius,
        triangles: m.triangles,
        pick: m.pick,
        wind: if m.own_wind { WindSource::Own } else { WindSource::Computed },
        thumbnail: Some(format!("{name}/thumbnail.png")),
        far: req.far.clone(),
    };
    // Copy into a hidden folder, then rename it into place: a failure leaves no half model.
    let tmp = req.bank.join(format!(".{name}.tmp-{}", std::process::id()));
    let copied = (|| -> Result<(), BankError> {
        for r in &rels {
            let to = tmp.join(r);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent)
                    .map_err(|error| BankError::Create { path: parent.to_path_buf(), error })?;
            }
            let from = files::within(&src_dir.join(r), &src_dir).map_err(BankError::File)?;
            let bytes = files::read(&from, Kind::ModelFile).map_err(BankError::File)?;
            std::fs::write(&to, bytes).map_err(|error| BankError::Copy { path: src_dir.join(r), error })?;
        }
        let png = super::thumbnail::png(data)?;
        std::fs::write(tmp.join("thumbnail.png"), png)
            .map_err(|error| BankError::WriteThumbnail { path: tmp.clone(), error })?;
        std::fs::rename(&tmp, &dest).map_err(|error| BankError::MoveIntoPlace { path: dest.clone(), error })?;
        Ok(())
    })();
    if let Err(e) = copied {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    // The copy must hash as the source did (a file changed while being copied otherwise).
    let check = grove_systems::bank::content_hash(&req.bank, &model.files).map_err(BankError::Banks);
    let mut cat = bank.catalogue.clone();
    cat.models.push(model.clone());
    let written = check.and_then(|h| {
        if h != model.hash {
            return Err(BankError::Changed(file.clone()));
        }
        crate::atomic_write::write_atomic(&req.bank.join(CATALOGUE_FILE), cat.to_ron().as_bytes())
            .map_err(BankError::Catalogue)
    });
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&dest);
        return Err(e);
    }
    Ok(Added::New(model))
}
