//! Model banks: folders of glTF models with a catalogue file, read as plain data.
//!
//! A bank is a folder with a `catalogue.ron` ([`BankCatalogue`]) and, for each model, a
//! sub-folder holding its glTF file and the buffers and textures it names. `grove models add`
//! computes every entry from the model's mesh (bounds, lowest point, pick shape, crown radius,
//! triangles) and a content hash over its files; this module only reads the catalogue and
//! hashes files, and knows nothing about glTF. `docs/model-bank.md` documents the format.
//!
//! The simulation's catalogue for a session ([`Banks::session_catalogue`]) is the shipped models
//! first (ids 0 to 7, so the study's world hashes do not change), then every bank model in the
//! order the banks were given and, within a bank, in catalogue order. A recording's header lists
//! those added models with their content hashes ([`HeaderModel`]); a replay rebuilds the same
//! catalogue from that list ([`Banks::catalogue_for`]), so the ids match, and refuses with one
//! line when a listed model is missing or its files have changed.

use std::path::{Component, Path, PathBuf};

use glam::Vec3;
use serde::{Deserialize, Serialize};
use xxhash_rust::xxh3::Xxh3;

use crate::catalogue::{Catalogue, ModelId, ModelInfo, ModelKind, PickShape};

crate::message_error::message_error! {
    /// Why a model bank, its catalogue, a model's files or the banks a session or a recording
    /// needs could not be used: one line, usually naming the folder or file.
    BankError
}

/// The catalogue file's name inside a bank folder.
pub const CATALOGUE_FILE: &str = "catalogue.ron";
/// The environment variable that names extra banks, separated by `:`.
pub const BANK_ENV: &str = "GROVE_BANK";
/// The most models a session's catalogue holds (model ids are one byte).
pub const MAX_MODELS: usize = 255;
/// The largest model file (glTF, buffer or texture) grove hashes, bytes.
pub const MAX_FILE_BYTES: u64 = crate::limits::MAX_MODEL_FILE_BYTES;
/// The largest catalogue file grove reads, bytes.
pub const MAX_CATALOGUE_BYTES: u64 = crate::limits::MAX_INDEX_BYTES;

/// Where a model's wind channels (`_WIND`) come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum WindSource {
    /// The file carries its own `_WIND` attribute.
    Own,
    /// grove computes the channels when it loads the model (docs/model-bank.md).
    Computed,
}

/// One model of a bank, as `catalogue.ron` lists it. Model space: metres, +Y up, origin at the
/// base of the trunk.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BankModel {
    /// The model's stable name, unique across all loaded banks and the shipped models.
    pub name: String,
    /// The species, e.g. "birch" (by default the name).
    pub species: String,
    /// Mesh or billboard foliage.
    pub kind: ModelKind,
    /// The glTF file, relative to the bank folder, e.g. "oak/oak.glb".
    pub file: String,
    /// Every file of the model (the glTF file, its buffers and textures), relative to the bank.
    pub files: Vec<String>,
    /// The content hash over `files` ([`content_hash`]), 16 hex digits.
    pub hash: String,
    /// Minimum corner of the axis-aligned bounds, metres; `bounds_min.y` is the lowest point.
    pub bounds_min: Vec3,
    /// Maximum corner of the axis-aligned bounds, metres.
    pub bounds_max: Vec3,
    /// Horizontal radius of the model around its Y axis, metres.
    pub crown_radius: f32,
    /// Triangle count.
    pub triangles: u32,
    /// The pick shape computed from the mesh.
    pub pick: PickShape,
    /// Where the wind channels come from.
    pub wind: WindSource,
    /// A PNG thumbnail, relative to the bank folder, if one was made.
    #[serde(default)]
    pub thumbnail: Option<String>,
    /// A coarser model of the same tree in the same bank (say its level of detail 2), which the
    /// renderer draws in this one's place where the tree is small on screen; the simulation
    /// never sees it (picking, snapping and the hash use this model).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub far: Option<String>,
}

impl BankModel {
    /// The simulation's view of this model, with the id it has in a session's catalogue.
    pub fn info(&self, id: ModelId) -> ModelInfo {
        ModelInfo {
            id,
            name: self.name.clone(),
            species: self.species.clone(),
            kind: self.kind,
            bounds_min: self.bounds_min,
            bounds_max: self.bounds_max,
            crown_radius: self.crown_radius,
            triangles: self.triangles,
            pick: Some(self.pick),
        }
    }
}

/// The contents of a bank's `catalogue.ron`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BankCatalogue {
    /// The models, in the order they were added.
    pub models: Vec<BankModel>,
}

/// A model a recording uses beyond the shipped ones: its name and content hash.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeaderModel {
    /// The model's name.
    pub name: String,
    /// Its content hash when the recording was made, 16 hex digits.
    pub hash: String,
}

/// One bank folder and its catalogue.
#[derive(Clone, Debug)]
pub struct Bank {
    /// The folder.
    pub dir: PathBuf,
    /// Its catalogue (empty for a folder without `catalogue.ron`).
    pub catalogue: BankCatalogue,
}

/// Whether a path from a catalogue stays inside its bank: relative, without `..` or a root.
pub fn is_inside(rel: &str) -> bool {
    let p = Path::new(rel);
    !rel.is_empty() && p.components().all(|c| matches!(c, Component::Normal(_)))
}

/// Whether a name is usable as a model name: 1 to 64 ASCII letters, digits, '-', '_' or '.',
/// not starting with '.'.
pub fn valid_name(name: &str) -> bool {
    (1..=64).contains(&name.len())
        && !name.starts_with('.')
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_' || b == b'.')
}

/// The content hash of a model's files: XXH3-64 over each file's relative path, length and
/// bytes, in the listed order, as 16 hex digits. The error is one line naming the file.
pub fn content_hash(dir: &Path, files: &[String]) -> Result<String, BankError> {
    content_hash_message(dir, files).map_err(BankError)
}

fn content_hash_message(dir: &Path, files: &[String]) -> Result<String, String> {
    if let Some(f) = files.iter().find(|f| !is_inside(f)) {
        return Err(format!("{}: file '{f}' is outside the bank", dir.display()));
    }
    Ok(hash_files(files.iter().map(|f| (f.as_str(), dir.join(f))))?)
}

/// The content hash of files given as (name in the bank, where the bytes are now) pairs: the
/// same value [`content_hash`] gives once they are in the bank under those names.
pub fn hash_files<'a>(files: impl IntoIterator<Item = (&'a str, PathBuf)>) -> Result<String, BankError> {
    hash_files_message(files).map_err(BankError)
}

fn hash_files_message<'a>(files: impl IntoIterator<Item = (&'a str, PathBuf)>) -> Result<String, String> {
    let mut h = Xxh3::new();
    for (name, path) in files {
        // A regular file of at most the model-file limit, opened without blocking on a pipe.
        let (f, len) = crate::files::open(&path, crate::files::Kind::ModelFile).map_err(|e| e.to_string())?;
        // Streamed in blocks, so that hashing takes little memory however large the file; never
        // more than one byte past its length, in case it grows meanwhile.
        use std::io::Read;
        let io = |e: std::io::Error| format!("{}: {}", path.display(), crate::scene::io_message(&e));
        let mut f = f.take(len + 1);
        h.update(name.as_bytes());
        h.update(&len.to_le_bytes());
        let mut buf = vec![0u8; 1 << 16];
        let mut seen = 0u64;
        loop {
            let n = f.read(&mut buf).map_err(io)?;
            if n == 0 {
                break;
            }
            seen += n as u64;
            h.update(&buf[..n]);
        }
        if seen != len {
            return Err(format!("{}: changed while it was being read", path.display()));
        }
    }
    Ok(crate::hash::hex(h.digest()))
}

impl Bank {
    /// Opens a bank folder. A folder without a catalogue is an empty bank; a missing folder, a
    /// catalogue that does not parse, or one with invalid entries is an error naming the file.
    pub fn open(dir: &Path) -> Result<Bank, BankError> {
        Self::open_message(dir).map_err(BankError)
    }

    fn open_message(dir: &Path) -> Result<Bank, String> {
        if !dir.is_dir() {
            return Err(format!("{}: not a folder (a model bank is a folder with a {CATALOGUE_FILE})", dir.display()));
        }
        let path = dir.join(CATALOGUE_FILE);
        if !path.exists() {
            return Ok(Bank { dir: dir.to_path_buf(), catalogue: BankCatalogue::default() });
        }
        let text = crate::files::read_text(&path, crate::files::Kind::Index).map_err(|e| e.to_string())?;
        let catalogue = BankCatalogue::from_ron(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Bank { dir: dir.to_path_buf(), catalogue })
    }

    /// The model with this name, if the bank has it.
    pub fn get(&self, name: &str) -> Option<&BankModel> {
        self.catalogue.models.iter().find(|m| m.name == name)
    }

    /// The absolute path of a model's glTF file.
    pub fn file_of(&self, m: &BankModel) -> PathBuf {
        self.dir.join(&m.file)
    }

    /// Recomputes a model's content hash from its files now.
    pub fn current_hash(&self, m: &BankModel) -> Result<String, BankError> {
        self.current_hash_message(m).map_err(BankError)
    }

    fn current_hash_message(&self, m: &BankModel) -> Result<String, String> {
        Ok(content_hash(&self.dir, &m.files)?)
    }
}

impl BankCatalogue {
    /// Parses and checks a bank catalogue: unique valid names, files inside the bank, finite
    /// bounds and a valid pick shape.
    pub fn from_ron(text: &str) -> Result<BankCatalogue, BankError> {
        Self::from_ron_message(text).map_err(BankError)
    }

    fn from_ron_message(text: &str) -> Result<BankCatalogue, String> {
        let cat: BankCatalogue = ron::from_str(text).map_err(|e| format!("catalogue: {e}"))?;
        if cat.models.len() > MAX_MODELS {
            return Err(format!("catalogue: more than {MAX_MODELS} models"));
        }
        for (i, m) in cat.models.iter().enumerate() {
            if !valid_name(&m.name) {
                return Err(format!("catalogue: model {i} has an invalid name '{}'", m.name));
            }
            if cat.models[..i].iter().any(|o| o.name == m.name) {
                return Err(format!("catalogue: model '{}' is listed twice", m.name));
            }
            if !is_inside(&m.file) || !m.files.contains(&m.file) || !m.files.iter().all(|f| is_inside(f)) {
                return Err(format!("catalogue: model '{}' names a file outside the bank or not in its files", m.name));
            }
            if m.thumbnail.as_deref().is_some_and(|t| !is_inside(t)) {
                return Err(format!("catalogue: model '{}' has a thumbnail outside the bank", m.name));
            }
            let finite = m.bounds_min.is_finite() && m.bounds_max.is_finite() && m.crown_radius.is_finite();
            if !finite
                || m.bounds_min.cmpgt(m.bounds_max).any()
                || m.bounds_min.abs().max_element().max(m.bounds_max.abs().max_element()) > crate::limits::MAX_COORD
            {
                return Err(format!("catalogue: model '{}' has invalid bounds", m.name));
            }
            if let Some(far) = &m.far {
                let ok = far != &m.name && cat.models.iter().any(|o| &o.name == far && o.far.is_none());
                if !ok {
                    return Err(format!(
                        "catalogue: model '{}' names far model '{far}', which is not another model of this bank without a far model of its own",
                        m.name
                    ));
                }
            }
            let p = &m.pick;
            if !(p.bottom.is_finite()
                && p.top.is_finite()
                && p.bottom < p.top
                && p.radii.iter().all(|r| r.is_finite() && *r >= 0.0))
            {
                return Err(format!("catalogue: model '{}' has an invalid pick shape", m.name));
            }
        }
        Ok(cat)
    }

    /// The catalogue as RON text, with a comment line on top.
    pub fn to_ron(&self) -> String {
        let body = ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default()).unwrap_or_default();
        format!(
            "// A grove model bank, written by `grove models add` (docs/model-bank.md).\n// Model space: metres, +Y up, origin at the base of the trunk.\n{body}\n"
        )
    }
}

/// Every bank of a session, in order.
#[derive(Clone, Debug, Default)]
pub struct Banks {
    /// The banks, in the order they are searched.
    pub banks: Vec<Bank>,
}

/// The bank folders a session uses: each `--bank` folder in order, then those of
/// [`BANK_ENV`] (`env` is its value, if set), with empty entries skipped and repeats removed.
pub fn bank_dirs(args: &[PathBuf], env: Option<&str>) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = Vec::new();
    let from_env = env.into_iter().flat_map(|v| v.split(':')).filter(|s| !s.is_empty()).map(PathBuf::from);
    for d in args.iter().cloned().chain(from_env) {
        if !out.contains(&d) {
            out.push(d);
        }
    }
    out
}

impl Banks {
    /// Opens every folder; the first error is returned.
    pub fn open(dirs: &[PathBuf]) -> Result<Banks, BankError> {
        Self::open_message(dirs).map_err(BankError)
    }

    fn open_message(dirs: &[PathBuf]) -> Result<Banks, String> {
        Ok(Banks { banks: dirs.iter().map(|d| Bank::open(d)).collect::<Result<_, _>>()? })
    }

    /// Every bank model with its bank, in session order; a name that is shipped, or in an earlier
    /// bank with different files, is an error.
    pub fn models(&self) -> Result<Vec<(&Bank, &BankModel)>, BankError> {
        self.models_message().map_err(BankError)
    }

    fn models_message(&self) -> Result<Vec<(&Bank, &BankModel)>, String> {
        let shipped = Catalogue::builtin();
        let mut out: Vec<(&Bank, &BankModel)> = Vec::new();
        for b in &self.banks {
            for m in &b.catalogue.models {
                if shipped.by_name(&m.name).is_some() {
                    return Err(format!("{}: model '{}' has the name of a shipped model", b.dir.display(), m.name));
                }
                match out.iter().find(|(_, o)| o.name == m.name) {
                    Some((ob, o)) if o.hash != m.hash => {
                        return Err(format!(
                            "model '{}' is in two banks with different files: {} and {}",
                            m.name,
                            ob.dir.display(),
                            b.dir.display()
                        ));
                    }
                    Some(_) => {}
                    None => out.push((b, m)),
                }
            }
        }
        if shipped.len() + out.len() > MAX_MODELS {
            return Err(format!("the banks hold more than {MAX_MODELS} models in all"));
        }
        Ok(out)
    }

    /// The model of this name and its bank, if any bank has it.
    pub fn find(&self, name: &str) -> Option<(&Bank, &BankModel)> {
        self.banks.iter().find_map(|b| b.get(name).map(|m| (b, m)))
    }

    /// The catalogue of a new session: the shipped models, then every bank model. Also returns
    /// the header list of the added models, for a recording.
    pub fn session_catalogue(&self) -> Result<(Catalogue, Vec<HeaderModel>), BankError> {
        self.session_catalogue_message().map_err(BankError)
    }

    fn session_catalogue_message(&self) -> Result<(Catalogue, Vec<HeaderModel>), String> {
        let mut cat = Catalogue::builtin();
        let mut listed = Vec::new();
        for (_, m) in self.models()? {
            cat.models.push(m.info(ModelId(cat.models.len() as u8)));
            listed.push(HeaderModel { name: m.name.clone(), hash: m.hash.clone() });
        }
        Ok((cat, listed))
    }

    /// The catalogue a recording was made with: the shipped models, then the header's models in
    /// its order, each found by name in the banks and checked against its content hash now.
    /// A missing or changed model is one line naming it.
    pub fn catalogue_for(&self, listed: &[HeaderModel]) -> Result<Catalogue, BankError> {
        self.catalogue_for_message(listed).map_err(BankError)
    }

    fn catalogue_for_message(&self, listed: &[HeaderModel]) -> Result<Catalogue, String> {
        let mut cat = Catalogue::builtin();
        if cat.len() + listed.len() > MAX_MODELS {
            return Err(format!("header lists more than {} models", MAX_MODELS - cat.len()));
        }
        for h in listed {
            if cat.by_name(&h.name).is_some() {
                return Err(format!("header lists model '{}' twice or under a shipped name", h.name));
            }
            let Some((bank, m)) = self.find(&h.name) else {
                let dirs: Vec<String> = self.banks.iter().map(|b| b.dir.display().to_string()).collect();
                let searched = if dirs.is_empty() {
                    "no bank was given".to_string()
                } else {
                    format!("searched {}", dirs.join(", "))
                };
                return Err(format!(
                    "the recording uses model '{}', which is in no bank ({searched}); pass --bank DIR or set {BANK_ENV}",
                    h.name
                ));
            };
            let now = bank.current_hash(m)?;
            if now != h.hash || m.hash != h.hash {
                return Err(format!(
                    "model '{}' has changed since the recording (its files in {} hash to {now}, the recording has {})",
                    h.name,
                    bank.dir.display(),
                    h.hash
                ));
            }
            cat.models.push(m.info(ModelId(cat.models.len() as u8)));
        }
        Ok(cat)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_must_stay_inside_and_names_are_plain() {
        assert!(is_inside("oak/oak.glb"));
        assert!(!is_inside("../oak.glb"));
        assert!(!is_inside("/etc/passwd"));
        assert!(!is_inside(""));
        assert!(valid_name("oak-1.2_b"));
        assert!(!valid_name(".hidden") && !valid_name("a b") && !valid_name("") && !valid_name(&"x".repeat(65)));
    }

    #[test]
    fn a_far_model_is_another_model_of_the_bank_without_one_of_its_own() {
        let entry = |name: &str, far: Option<&str>| {
            let far = far.map_or(String::new(), |f| format!("far: Some(\"{f}\"),"));
            format!(
                "(name: \"{name}\", species: \"s\", kind: Mesh, file: \"{name}/m.glb\", files: [\"{name}/m.glb\"], hash: \"0123456789abcdef\", bounds_min: (-1.0, 0.0, -1.0), bounds_max: (1.0, 2.0, 1.0), crown_radius: 1.0, triangles: 10, pick: (bottom: 0.0, top: 2.0, radii: (1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)), wind: Own, {far})"
            )
        };
        let cat = |entries: &[String]| BankCatalogue::from_ron(&format!("(models: [{}])", entries.join(",")));
        let ok = cat(&[entry("far", None), entry("near", Some("far"))]).unwrap();
        assert_eq!(ok.models[1].far.as_deref(), Some("far"));
        // A catalogue without far models is written as before: no `far` field.
        assert!(!cat(&[entry("a", None)]).unwrap().to_ron().contains("far"));
        for bad in [
            vec![entry("near", Some("gone"))],
            vec![entry("near", Some("near"))],
            vec![entry("a", Some("b")), entry("b", Some("c")), entry("c", None)],
        ] {
            let e = cat(&bad).unwrap_err().to_string();
            assert!(e.contains("names far model"), "{e}");
        }
    }

    #[test]
    fn bank_dirs_keep_argument_order_then_the_environment_without_repeats() {
        let got = bank_dirs(&[PathBuf::from("a"), PathBuf::from("b")], Some("c::a:d"));
        assert_eq!(got, ["a", "b", "c", "d"].map(PathBuf::from).to_vec());
    }

    #[test]
    fn the_content_hash_covers_names_and_bytes() {
        let dir = std::env::temp_dir().join(format!("grove-bank-hash-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("a"), b"xy").unwrap();
        std::fs::write(dir.join("b"), b"z").unwrap();
        let h1 = content_hash(&dir, &["a".into(), "b".into()]).unwrap();
        // Moving a byte from one file to the other changes the hash, though the bytes in order
        // are the same.
        std::fs::write(dir.join("a"), b"x").unwrap();
        std::fs::write(dir.join("b"), b"yz").unwrap();
        let h2 = content_hash(&dir, &["a".into(), "b".into()]).unwrap();
        assert_ne!(h1, h2);
        assert_eq!(h1.len(), 16);
        assert!(content_hash(&dir, &["../a".into()]).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
