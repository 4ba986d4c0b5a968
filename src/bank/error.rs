//! [`BankError`]: why a model was refused, a bank could not be opened or written, or a thumbnail
//! could not be made. Its `Display` is one line, worded as the CLI prints it; the errors it wraps
//! are shown in that line rather than as a `source()`, since the CLI prints an error's whole
//! chain.

use std::path::PathBuf;

use grove_systems::files::FileError;

use crate::models::{GltfError, GltfProblem};

/// Why a model was refused, the session's banks could not be opened, a model could not be added
/// to a bank, or a thumbnail could not be made.
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
    /// A file that `grove_systems::files` refused to read or to find inside its folder (the
    /// message names the path).
    #[error("{0}")]
    File(FileError),
    /// A model file that is not a regular file, or does not exist.
    #[error("{}: {}", file.display(), if *exists { "not a regular file" } else { "no such file" })]
    NotAFile {
        /// The file.
        file: PathBuf,
        /// Whether something is there.
        exists: bool,
    },
    /// A file the `gltf` crate cannot parse.
    #[error("{}: not a valid glTF 2.0 file ({})", file.display(), error.to_string().replace('\n', " "))]
    NotGltf {
        /// The file.
        file: PathBuf,
        /// The parser's error.
        error: gltf::Error,
    },
    /// A buffer or image URI that leads outside the model's folder, or cannot be a file.
    #[error("{}: names the file '{uri}', which {problem}", file.display())]
    Uri {
        /// The model file.
        file: PathBuf,
        /// The URI.
        uri: String,
        /// What is wrong with it.
        problem: GltfProblem,
    },
    /// A file the model names that lies outside its folder, found when it is copied.
    #[error("{}: names the file '{rel}', which {}", file.display(), error.reason())]
    Outside {
        /// The model file.
        file: PathBuf,
        /// The file it names, relative to its folder.
        rel: String,
        /// Why `grove_systems::files` refused it.
        error: FileError,
    },
    /// A file the model names that does not exist.
    #[error("{}: the file '{rel}' it names is missing", file.display())]
    Missing {
        /// The model file.
        file: PathBuf,
        /// The file it names, relative to its folder.
        rel: String,
    },
    /// A model path without a file name.
    #[error("{}: not a file name", .0.display())]
    NoFileName(PathBuf),
    /// A model name that is not a valid name.
    #[error("model name '{0}' must be 1 to 64 letters, digits, '-', '_' or '.'; choose one with --name")]
    Name(String),
    /// The name of a shipped model.
    #[error("'{0}' is the name of a shipped model; choose another with --name")]
    ShippedName(String),
    /// A species that is empty, too long or has control characters.
    #[error("--species must be 1 to 64 printable characters")]
    Species,
    /// A far model that is the model itself or has a far model of its own (the bank, the name).
    #[error("{}: --far '{far}' must be another model without a far model of its own", bank.display())]
    FarNotPlain {
        /// The bank.
        bank: PathBuf,
        /// The far model asked for.
        far: String,
    },
    /// A far model that is not in the bank.
    #[error("{}: --far '{far}' is not in this bank; add it first", bank.display())]
    FarMissing {
        /// The bank.
        bank: PathBuf,
        /// The far model asked for.
        far: String,
    },
    /// A name the bank holds for a different model.
    #[error("{}: the bank already has a different model named '{name}'; choose another --name", bank.display())]
    NameTaken {
        /// The bank.
        bank: PathBuf,
        /// The name.
        name: String,
    },
    /// A bank with the most models a catalogue may hold.
    #[error("{}: the bank is full ({models} models)", bank.display())]
    Full {
        /// The bank.
        bank: PathBuf,
        /// Its models.
        models: usize,
    },
    /// A model's folder that exists but is not catalogued.
    #[error("{}: exists but is not in the bank's catalogue; remove it or choose another --name", .0.display())]
    Uncatalogued(PathBuf),
    /// The bank folder could not be created.
    #[error("{}: cannot create the bank folder: {error}", path.display())]
    CreateBank {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A folder of the copy could not be created.
    #[error("{}: cannot create: {error}", path.display())]
    Create {
        /// The folder.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A file of the model could not be copied.
    #[error("{}: cannot copy: {error}", path.display())]
    Copy {
        /// The source file.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// The thumbnail could not be written (the folder it goes to).
    #[error("{}: cannot write the thumbnail: {error}", path.display())]
    WriteThumbnail {
        /// The model's temporary folder.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// The copied model could not be renamed into place.
    #[error("{}: cannot move the model into place: {error}", path.display())]
    MoveIntoPlace {
        /// The model's folder.
        path: PathBuf,
        /// The I/O error.
        error: std::io::Error,
    },
    /// A model file that changed while it was copied.
    #[error("{}: changed while it was being copied; try again", .0.display())]
    Changed(PathBuf),
    /// The bank's catalogue could not be written (through `atomic_write`, whose error it is,
    /// shown with its causes on one line).
    #[error("{0:#}")]
    Catalogue(anyhow::Error),
}
