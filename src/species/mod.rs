//! Parametric trees after Weber and Penn (1995), "Creation and rendering of realistic trees":
//! species presets as data (`preset`, `assets/species/*.ron`, `docs/species.md`), the recursive
//! stems with their curves, splits, pruning and leaves (`stems`), their meshes at three levels of
//! detail with wind channels and vertex colours (`mesh`), the bark texture (`images`), the leaf
//! atlas of single leaves, sprays and litter (`atlas`),
//! and the glTF files written through `assetgen`'s writer (`output`). `grove trees generate`
//! calls [`output::write`].

pub mod atlas;
pub mod images;
pub mod mesh;
pub mod output;
pub mod preset;
pub mod stems;

pub use preset::Preset;

/// What can go wrong making a species' model.
#[derive(Debug, thiserror::Error)]
pub enum SpeciesError {
    /// A preset that does not parse, has an unknown field or a value out of its range: the file
    /// and the words (the field and its allowed range).
    #[error("{file}: {message}")]
    Preset {
        /// The preset's path.
        file: String,
        /// What is wrong, one line.
        message: String,
    },
    /// A name that is neither a shipped preset nor a `.ron` path.
    #[error("unknown species '{name}'; the presets are {known}, or give the path of a .ron file")]
    Unknown {
        /// The name given.
        name: String,
        /// The shipped presets.
        known: String,
    },
    /// A preset file whose name cannot name a model.
    #[error("species name '{0}' must be 1 to 64 letters, digits, '-' and '_'")]
    BadName(String),
    /// A file that cannot be read.
    #[error(transparent)]
    File(#[from] grove_systems::files::FileError),
    /// A file or folder that cannot be written.
    #[error("{path}: cannot write ({source})")]
    Write {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// An output file that is there already.
    #[error("{0}: already exists; choose another --out folder or remove it")]
    Exists(String),
    /// A preset that makes no wood.
    #[error("'{0}' makes no stems; check its levels")]
    Empty(String),
    /// A written model that grove's own loader refuses (a bug).
    #[error("the model written for '{name}' is not valid: {source}")]
    Invalid {
        /// The species.
        name: String,
        /// The loader's words.
        source: crate::bank::BankError,
    },
}
