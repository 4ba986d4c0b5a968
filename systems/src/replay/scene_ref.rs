//! The scene a recording's header names, resolved without trusting the recording.
//!
//! A header may name a built-in scene (e.g. `"study"`) or a regular file ending in `.ron` inside
//! the recording's folder or the working directory, at most [`MAX_SCENE_BYTES`] long. Anything
//! else is refused before it is opened: an absolute path or `..` leading outside both folders
//! (also through a symbolic link), a folder, a device, a pipe or a socket, another extension, a
//! larger file. Errors name the path as the header gives it and never quote the file's content:
//! a file that is not a valid scene is reported by position only, with the hint to run
//! `grove scene check` on it.

use std::path::{Path, PathBuf};

use crate::limits::MAX_SCENE_BYTES;
use crate::scene::{Scene, read_scene_text};

/// Why the scene a header (or a scenario) names was refused. Its `Display` names the scene as
/// written, quoted, and never quotes the file's content.
#[derive(Debug, thiserror::Error)]
pub enum SceneRefError {
    /// An empty name, one longer than 4096 bytes or one with a NUL.
    #[error("scene {name:?} is neither a built-in scene name nor a usable file name")]
    Unusable {
        /// The name as written.
        name: String,
    },
    /// Not a built-in name and not a `.ron` file.
    #[error(
        "scene {name:?} is not a built-in scene name (\"study\") and does not end in .ron; a recording may only name a scene file ending in .ron"
    )]
    NotRon {
        /// The name as written.
        name: String,
    },
    /// The working directory cannot be read.
    #[error("scene {name:?}: the working directory is unreadable ({error})")]
    WorkingDir {
        /// The name as written.
        name: String,
        /// The I/O error (in the message, so not a `source()`: the CLI prints the chain).
        error: std::io::Error,
    },
    /// The file exists but leads outside both folders.
    #[error(
        "scene {name:?} leads outside the recording's folder and the working directory; a recording may only name a scene file inside them"
    )]
    Outside {
        /// The name as written.
        name: String,
    },
    /// No such file in either folder.
    #[error("scene {name:?}: no such file in the recording's folder or the working directory")]
    NotFound {
        /// The name as written.
        name: String,
    },
    /// The file's metadata cannot be read.
    #[error("scene {name:?}: {}", crate::scene::io_message(error))]
    Metadata {
        /// The name as written.
        name: String,
        /// The I/O error (in the message, so not a `source()`: the CLI prints the chain).
        error: std::io::Error,
    },
    /// A folder, device, pipe or socket.
    #[error(
        "scene {name:?} is not a regular file (a folder, device, pipe or socket); a recording may only name a regular .ron file"
    )]
    NotRegularFile {
        /// The name as written.
        name: String,
    },
    /// Larger than [`MAX_SCENE_BYTES`].
    #[error(
        "scene {name:?} is larger than the limit of {MAX_SCENE_BYTES} bytes per scene file ({})",
        crate::limits::RAISE
    )]
    TooLarge {
        /// The name as written.
        name: String,
    },
    /// The file's text cannot be read.
    #[error("scene {name:?}: {}", error.message)]
    Read {
        /// The name as written.
        name: String,
        /// The reader's error.
        error: crate::scene::SceneError,
    },
    /// Not a valid scene: where parsing stopped (line, column), if it did.
    #[error("scene {name:?} is not a valid grove scene{}; run `grove scene check` on it for details", at.map(|(l, c)| format!(" (line {l}, column {c})")).unwrap_or_default())]
    Invalid {
        /// The name as written.
        name: String,
        /// The line and column of a parse error.
        at: Option<(usize, usize)>,
    },
    /// The scene crosses a limit.
    #[error("scene {name:?}: {error}")]
    Limit {
        /// The name as written.
        name: String,
        /// The crossed limit, with the planes named by number.
        error: crate::limits::InvalidScene,
    },
}

/// Resolves and loads the scene a header names. `base_dir` is the recording's folder (`None`
/// or an empty path for the working directory).
pub fn resolve_scene(name: &str, base_dir: Option<&Path>) -> Result<Scene, SceneRefError> {
    if let Some(s) = Scene::builtin(name) {
        return Ok(s);
    }
    let named = || name.to_string();
    if name.is_empty() || name.len() > 4096 || name.contains('\0') {
        return Err(SceneRefError::Unusable { name: named() });
    }
    let rel = Path::new(name);
    if rel.extension().and_then(|e| e.to_str()) != Some("ron") {
        return Err(SceneRefError::NotRon { name: named() });
    }
    let cwd = std::env::current_dir().map_err(|error| SceneRefError::WorkingDir { name: named(), error })?;
    let base = match base_dir {
        Some(b) if !b.as_os_str().is_empty() => b.to_path_buf(),
        _ => cwd.clone(),
    };
    let mut refused = false;
    for folder in [base, cwd] {
        match inside(&folder, rel) {
            Ok(Some(path)) => return load(&path, name),
            Ok(None) => {}
            Err(Outside) => refused = true,
        }
    }
    Err(if refused { SceneRefError::Outside { name: named() } } else { SceneRefError::NotFound { name: named() } })
}

/// A path that exists but leads outside its folder.
struct Outside;

/// The canonical path of `rel` under `folder` when it exists and stays inside `folder` after
/// symbolic links and `..` are resolved; `Ok(None)` when there is no such file; [`Outside`]
/// when it exists but leads outside.
fn inside(folder: &Path, rel: &Path) -> Result<Option<PathBuf>, Outside> {
    let Ok(root) = folder.canonicalize() else { return Ok(None) };
    let Ok(path) = folder.join(rel).canonicalize() else { return Ok(None) };
    if !path.starts_with(&root) {
        return Err(Outside);
    }
    Ok(Some(path))
}

/// Loads a resolved scene file: only a regular file within the size limit; its content is never
/// quoted in an error.
fn load(path: &Path, name: &str) -> Result<Scene, SceneRefError> {
    let named = || name.to_string();
    let meta = std::fs::metadata(path).map_err(|error| SceneRefError::Metadata { name: named(), error })?;
    if !meta.is_file() {
        return Err(SceneRefError::NotRegularFile { name: named() });
    }
    if meta.len() > MAX_SCENE_BYTES {
        return Err(SceneRefError::TooLarge { name: named() });
    }
    let text = read_scene_text(path).map_err(|error| SceneRefError::Read { name: named(), error })?;
    // Only the position of a parse error: its message may quote the file's content.
    let mut scene: Scene = ron::from_str(&text)
        .map_err(|e| SceneRefError::Invalid { name: named(), at: Some((e.span.start.line, e.span.start.col)) })?;
    // Its banks are relative to its own folder.
    scene.dir = Some(path.parent().map(Path::to_path_buf).unwrap_or_default());
    if scene.validate().is_ok() {
        return Ok(scene);
    }
    // A crossed limit is named, with the planes called by number rather than by their names (a
    // copy renamed so, since grass patches name their planes, is checked only to word the error).
    let mut anonymous = scene.clone();
    for (i, p) in anonymous.planes.iter_mut().enumerate() {
        p.name = format!("#{}", i + 1);
    }
    match anonymous.validate() {
        Err(m) if m.0.contains("limit") => Err(SceneRefError::Limit { name: named(), error: m }),
        _ => Err(SceneRefError::Invalid { name: named(), at: None }),
    }
}
