//! The one check every model passes before grove accepts it, whoever made it: a model added to
//! a bank, a file given to `grove render --model`, a bank or scene model loaded into a renderer,
//! and a model grove generates itself (before its rename into place).

use std::path::Path;

use super::BankError;
use crate::models::{ModelData, load_model};

/// Reads and checks a glTF 2.0 file (`.gltf` or `.glb`) exactly as grove loads it: the file and
/// every file it names read through `grove_systems::files` with the URIs' places checked first,
/// `asset.version` 2.x, extensions read or refused by name, buffer views and accessors inside
/// their data, points and lines refused, morph targets, strips and fans, vertex colours, texture
/// sets and transforms applied, and a model of non-zero height. Returns the loaded model (its
/// `notes` say what a still shows in one state, its `warnings` what it does not draw).
pub fn validate_gltf(path: &Path) -> Result<ModelData, BankError> {
    load_model(path).map_err(BankError::Refused)
}
