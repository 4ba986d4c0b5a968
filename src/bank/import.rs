//! `grove models add`: validate a glTF model, measure it, copy it with its buffers and textures
//! into a bank folder, and add its entry to the bank's catalogue.
//!
//! The model goes to `BANK/<name>/` under its own file names; the catalogue is rewritten through
//! a temporary file and a rename. A name the bank already holds is refused unless the files are
//! identical (then nothing changes), so a different model is never overwritten.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use grove_systems::bank::{hash_files, is_inside, valid_name, Bank, BankModel, WindSource, CATALOGUE_FILE, MAX_MODELS};
use grove_systems::catalogue::{Catalogue, ModelKind};

use crate::render::assets::gltf_load::{load_model, ModelData};

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
/// relative to its folder, in document order without repeats; one outside the folder is an
/// error.
pub fn resources_of(file: &Path) -> anyhow::Result<Vec<String>> {
    let bytes = std::fs::read(file).with_context(|| format!("{}: cannot read", file.display()))?;
    let gltf = crate::render::assets::gltf_open::parse(&bytes).map_err(|e| anyhow!("{}: not a valid glTF 2.0 file ({})", file.display(), e.to_string().replace('\n', " ")))?;
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
    let mut out: Vec<String> = Vec::new();
    for u in uris {
        if u.starts_with("data:") {
            continue;
        }
        let rel = u.replace("%20", " ");
        if !is_inside(&rel) {
            bail!("{}: names the file '{u}' outside its folder; grove copies only files beside the model or below it", file.display());
        }
        if !out.contains(&rel) {
            out.push(rel);
        }
    }
    Ok(out)
}

/// Loads and measures a file the way `add` does, refusing unsupported compression first.
pub fn load_checked(file: &Path) -> anyhow::Result<ModelData> {
    super::extensions::check_file(file).map_err(|e| anyhow!(e))?;
    load_model(file).map_err(|e| anyhow!(e))
}

/// Adds a model to a bank (see the module docs).
pub fn add(req: &AddRequest) -> anyhow::Result<Added> {
    let file = &req.file;
    if !file.is_file() {
        bail!("{}: {}", file.display(), if file.exists() { "not a regular file" } else { "no such file" });
    }
    let data = load_checked(file)?;
    let stem = file.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let name = req.name.clone().unwrap_or(stem);
    if !valid_name(&name) {
        bail!("model name '{name}' must be 1 to 64 letters, digits, '-', '_' or '.'; choose one with --name");
    }
    if Catalogue::builtin().by_name(&name).is_some() {
        bail!("'{name}' is the name of a shipped model; choose another with --name");
    }
    let species = req.species.clone().unwrap_or_else(|| name.clone());
    if species.is_empty() || species.len() > 64 || species.chars().any(char::is_control) {
        bail!("--species must be 1 to 64 printable characters");
    }
    let src_dir = file.parent().map(Path::to_path_buf).unwrap_or_else(|| PathBuf::from("."));
    let main = file.file_name().map(|s| s.to_string_lossy().into_owned()).ok_or_else(|| anyhow!("{}: not a file name", file.display()))?;
    let mut rels = vec![main.clone()];
    for r in resources_of(file)? {
        if !rels.contains(&r) {
            rels.push(r);
        }
    }
    for r in &rels[1..] {
        if !src_dir.join(r).is_file() {
            bail!("{}: the file '{r}' it names is missing", file.display());
        }
    }
    let files: Vec<String> = rels.iter().map(|r| format!("{name}/{r}")).collect();
    let hash = hash_files(files.iter().zip(&rels).map(|(f, r)| (f.as_str(), src_dir.join(r)))).map_err(|e| anyhow!(e))?;

    std::fs::create_dir_all(&req.bank).with_context(|| format!("{}: cannot create the bank folder", req.bank.display()))?;
    let bank = Bank::open(&req.bank).map_err(|e| anyhow!(e))?;
    if let Some(old) = bank.get(&name) {
        if old.hash == hash {
            return Ok(Added::Unchanged(old.clone()));
        }
        bail!("{}: the bank already has a different model named '{name}'; choose another --name", req.bank.display());
    }
    if bank.catalogue.models.len() >= MAX_MODELS - Catalogue::builtin().len() {
        bail!("{}: the bank is full ({} models)", req.bank.display(), bank.catalogue.models.len());
    }
    let dest = req.bank.join(&name);
    if dest.exists() {
        bail!("{}: exists but is not in the bank's catalogue; remove it or choose another --name", dest.display());
    }

    let m = super::measure(&data);
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
    };
    // Copy into a hidden folder, then rename it into place: a failure leaves no half model.
    let tmp = req.bank.join(format!(".{name}.tmp-{}", std::process::id()));
    let copied = (|| -> anyhow::Result<()> {
        for r in &rels {
            let to = tmp.join(r);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).with_context(|| format!("{}: cannot create", parent.display()))?;
            }
            std::fs::copy(src_dir.join(r), &to).with_context(|| format!("{}: cannot copy", src_dir.join(r).display()))?;
        }
        let png = super::thumbnail::png(&data).map_err(|e| anyhow!(e))?;
        std::fs::write(tmp.join("thumbnail.png"), png).with_context(|| format!("{}: cannot write the thumbnail", tmp.display()))?;
        std::fs::rename(&tmp, &dest).with_context(|| format!("{}: cannot move the model into place", dest.display()))?;
        Ok(())
    })();
    if let Err(e) = copied {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    // The copy must hash as the source did (a file changed while being copied otherwise).
    let check = grove_systems::bank::content_hash(&req.bank, &model.files).map_err(|e| anyhow!(e));
    let mut cat = bank.catalogue.clone();
    cat.models.push(model.clone());
    let written = check.and_then(|h| {
        if h != model.hash {
            bail!("{}: changed while it was being copied; try again", file.display());
        }
        crate::atomic_write::write_atomic(&req.bank.join(CATALOGUE_FILE), cat.to_ron().as_bytes())
    });
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&dest);
        return Err(e);
    }
    Ok(Added::New(model))
}
