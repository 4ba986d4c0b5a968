//! The one check every model passes before grove accepts it, whoever made it: a model added to
//! a bank, a file given to `grove render --model`, a bank or scene model loaded into a renderer,
//! and a model grove generates itself (before its rename into place).

use std::path::Path;

use crate::models::{load_model, GltfError, GltfProblem, ModelData};

/// Why a model was refused, the session's banks could not be opened, or a thumbnail could not
/// be made. Its `Display` is one line.
#[derive(Debug, thiserror::Error)]
pub enum BankError {
    /// The file is not a model grove draws as it says; the message is one line that names the
    /// file and the fault (an extension, a primitive, a URI, an accessor, the version, the
    /// bounds).
    #[error(transparent)]
    Refused(#[from] GltfError),
    /// The file uses or requires a glTF extension grove cannot read: the file and the loader's
    /// words (the extension, and a conversion that works).
    #[error("{file}: {problem}")]
    Extension {
        /// The file, as shown.
        file: String,
        /// What the loader refuses.
        problem: GltfProblem,
    },
    /// A bank folder, its catalogue or a model it lists could not be used.
    #[error(transparent)]
    Banks(#[from] grove_systems::bank::BankError),
    /// The thumbnail's pixels do not fill its size.
    #[error("thumbnail buffer has the wrong size")]
    ThumbnailSize,
    /// The thumbnail could not be encoded as PNG.
    #[error("cannot encode the thumbnail ({0})")]
    Thumbnail(image::ImageError),
}

/// Reads and checks a glTF 2.0 file (`.gltf` or `.glb`) exactly as grove loads it: the file and
/// every file it names read through `grove_systems::files` with the URIs' places checked first,
/// `asset.version` 2.x, extensions read or refused by name, buffer views and accessors inside
/// their data, points and lines refused, morph targets, strips and fans, vertex colours, texture
/// sets and transforms applied, and a model of non-zero height. Returns the loaded model (its
/// `notes` say what a still shows in one state, its `warnings` what it does not draw).
pub fn validate_gltf(path: &Path) -> Result<ModelData, BankError> {
    load_model(path).map_err(BankError::Refused)
}
