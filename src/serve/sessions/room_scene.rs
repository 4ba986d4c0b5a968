//! A scene a client built (a headset's page builds one from the floor its room has, `docs/headset.md`)
//! and sends with the open request as `scene_text`: checked as a scene, written beside the
//! recordings as `room-<hash>.ron` (its content's 64-bit xxh3, so one text is one file and no file
//! is ever replaced by another), and named by the session's header, so that `grove replay`,
//! `grove study` and the server's own verification find the same ground.
//!
//! The scene must keep the rule the WebAssembly module keeps for the scenes it is handed
//! (`grove_systems::scene_text`): within the size limit, a valid scene, naming no file (model
//! banks, aerial photographs), since the client's files are not beside a recording. So a room the
//! module built is never refused here.

use std::path::Path;

use grove_systems::scene_text::{self_contained, SceneTextError};

use crate::serve::http::refusal::Refusal;

/// The file name a scene text is kept under.
pub fn file_name(text: &str) -> String {
    format!("room-{:016x}.ron", xxhash_rust::xxh3::xxh3_64(text.as_bytes()))
}

/// Checks `text` as a scene for a session and writes it into `dir` (unless the same text is
/// there already); returns its file name, which the header names.
pub fn keep(text: &str, dir: &Path) -> Result<String, Refusal> {
    self_contained(text).map_err(|e| match e {
        SceneTextError::TooLarge => Refusal::too_large(format!("scene_text: {e}")),
        _ => Refusal::bad(format!("scene_text: {e}")),
    })?;
    let name = file_name(text);
    let path = dir.join(&name);
    match grove_systems::files::read(&path, grove_systems::files::Kind::Scene) {
        Ok(existing) if existing == text.as_bytes() => return Ok(name),
        Ok(_) => return Err(Refusal::internal(format!("{name} exists with other content; move it away"))),
        Err(_) if path.exists() => return Err(Refusal::internal(format!("{name} exists and cannot be read"))),
        Err(_) => {}
    }
    crate::atomic_write::write_bytes(&path, text.as_bytes()).map_err(|e| Refusal::internal(e.to_string()))?;
    Ok(name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use grove_systems::limits::MAX_SCENE_BYTES;
    use grove_systems::scene::Scene;

    fn floor_scene(elevation: f32) -> String {
        let study = Scene::builtin("study").unwrap();
        let mut s = study.clone();
        s.name = "room".into();
        s.planes.truncate(1);
        if let grove_systems::scene::PlaneShape::Grid { elevation: e, holes, unevenness, .. } = &mut s.planes[0].shape {
            *e = elevation;
            holes.clear();
            *unevenness = 0.0;
        }
        s.trees.clear();
        ron::ser::to_string_pretty(&s, ron::ser::PrettyConfig::default()).unwrap()
    }

    #[test]
    fn a_scene_is_kept_once_under_its_hash_and_bad_ones_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let text = floor_scene(-0.02);
        let name = keep(&text, dir.path()).unwrap();
        assert!(name.starts_with("room-") && name.ends_with(".ron") && name.len() == "room-.ron".len() + 16, "{name}");
        assert_eq!(std::fs::read_to_string(dir.path().join(&name)).unwrap(), text);
        assert_eq!(keep(&text, dir.path()).unwrap(), name, "the same text is the same file");
        let other = keep(&floor_scene(0.0), dir.path()).unwrap();
        assert_ne!(other, name);
        let files: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(files.len(), 2, "{files:?}: no temporary file left");

        let e = keep("Scene(name: \"x\"", dir.path()).unwrap_err();
        assert_eq!(e.status, 400);
        assert!(e.reason.starts_with("scene_text: line 1"), "{}", e.reason);
        let banked = text.replacen("name: \"room\",", "name: \"room\", banks: [\"../elsewhere\"],", 1);
        assert!(keep(&banked, dir.path()).unwrap_err().reason.contains("model banks"));
        let huge = " ".repeat(MAX_SCENE_BYTES as usize + 1);
        assert_eq!(keep(&huge, dir.path()).unwrap_err().status, 413);
        std::fs::write(dir.path().join(file_name("x")), "y").unwrap();
        assert_eq!(keep("x", dir.path()).unwrap_err().status, 400, "not a scene: refused before the file is looked at");
    }
}
