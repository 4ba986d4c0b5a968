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
use crate::scene::{read_scene_text, Scene};

/// Resolves and loads the scene a header names. `base_dir` is the recording's folder (`None`
/// or an empty path for the working directory).
pub fn resolve_scene(name: &str, base_dir: Option<&Path>) -> Result<Scene, String> {
    if let Some(s) = Scene::builtin(name) {
        return Ok(s);
    }
    let shown = format!("{:?}", name);
    if name.is_empty() || name.len() > 4096 || name.contains('\0') {
        return Err(format!("scene {shown} is neither a built-in scene name nor a usable file name"));
    }
    let rel = Path::new(name);
    if rel.extension().and_then(|e| e.to_str()) != Some("ron") {
        return Err(format!("scene {shown} is not a built-in scene name (\"study\") and does not end in .ron; a recording may only name a scene file ending in .ron"));
    }
    let cwd = std::env::current_dir().map_err(|e| format!("scene {shown}: the working directory is unreadable ({e})"))?;
    let base = match base_dir {
        Some(b) if !b.as_os_str().is_empty() => b.to_path_buf(),
        _ => cwd.clone(),
    };
    let mut refused = None;
    for folder in [base, cwd] {
        match inside(&folder, rel) {
            Ok(Some(path)) => return load(&path, &shown),
            Ok(None) => {}
            Err(e) => refused = refused.or(Some(e)),
        }
    }
    Err(match refused {
        Some(why) => format!("scene {shown} {why}"),
        None => format!("scene {shown}: no such file in the recording's folder or the working directory"),
    })
}

/// The canonical path of `rel` under `folder` when it exists and stays inside `folder` after
/// symbolic links and `..` are resolved; `Ok(None)` when there is no such file; an error (the
/// end of a sentence) when it exists but leads outside.
fn inside(folder: &Path, rel: &Path) -> Result<Option<PathBuf>, String> {
    let Ok(root) = folder.canonicalize() else { return Ok(None) };
    let Ok(path) = folder.join(rel).canonicalize() else { return Ok(None) };
    if !path.starts_with(&root) {
        return Err("leads outside the recording's folder and the working directory; a recording may only name a scene file inside them".into());
    }
    Ok(Some(path))
}

/// Loads a resolved scene file: only a regular file within the size limit; its content is never
/// quoted in an error.
fn load(path: &Path, shown: &str) -> Result<Scene, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("scene {shown}: {}", crate::scene::io_message(&e)))?;
    if !meta.is_file() {
        return Err(format!("scene {shown} is not a regular file (a folder, device, pipe or socket); a recording may only name a regular .ron file"));
    }
    if meta.len() > MAX_SCENE_BYTES {
        return Err(format!("scene {shown} is larger than the limit of {MAX_SCENE_BYTES} bytes per scene file ({})", crate::limits::RAISE));
    }
    let text = read_scene_text(path).map_err(|e| format!("scene {shown}: {}", e.message))?;
    let generic = |at: String| format!("scene {shown} is not a valid grove scene{at}; run `grove scene check` on it for details");
    // Only the position of a parse error: its message may quote the file's content.
    let mut scene: Scene = ron::from_str(&text).map_err(|e| generic(format!(" (line {}, column {})", e.span.start.line, e.span.start.col)))?;
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
        Err(m) if m.0.contains("limit") => Err(format!("scene {shown}: {m}")),
        _ => Err(generic(String::new())),
    }
}
