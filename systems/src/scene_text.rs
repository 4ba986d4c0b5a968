//! A scene handed over as text by another program or machine: a headset's room sent to `grove
//! serve` with a session's open request, or any scene given to the WebAssembly module as
//! `scene_text`. One rule for both, so that the server takes exactly the scenes the module
//! takes: the text is within [`MAX_SCENE_TEXT_BYTES`] and holds no control character but tabs
//! and line breaks (so that, as a JSON string, it is at most twice as long and fits the open
//! request that carries it), parses and checks as a scene, and is self-contained: it names no
//! file (no model banks, no aerial photographs), since the files of the machine that wrote it
//! are not beside a recording, and the module has no file system.

use crate::limits::MAX_SCENE_TEXT_BYTES;
use crate::scene::Scene;

/// Why a scene's text was refused; its `Display` is one line without the scene's name (the
/// caller names it).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SceneTextError {
    /// The text is longer than a scene handed over may be.
    #[error("larger than the limit of {MAX_SCENE_TEXT_BYTES} bytes per scene handed over as text")]
    TooLarge,
    /// The text holds a control character other than a tab or a line break.
    #[error("it holds the control character U+{0:04X}; a scene's text has none but tabs and line breaks")]
    Control(u32),
    /// The text is not a scene (RON syntax, a missing field, a number out of its range).
    #[error("{0}")]
    Invalid(String),
    /// It names model-bank folders.
    #[error("it names model banks, which are files of the machine that wrote it; send a scene that names no file")]
    Banks,
    /// It has an aerial section, which names photographs (and maybe a crowns file).
    #[error("it names aerial photographs, which are files of the machine that wrote it; send a scene that names no file")]
    Aerial,
}

/// The scene `text` describes, if it keeps the rule of the module's documentation.
pub fn self_contained(text: &str) -> Result<Scene, SceneTextError> {
    if text.len() as u64 > MAX_SCENE_TEXT_BYTES {
        return Err(SceneTextError::TooLarge);
    }
    if let Some(c) = text.chars().find(|c| c.is_control() && !matches!(c, '\t' | '\n' | '\r')) {
        return Err(SceneTextError::Control(c as u32));
    }
    let scene = Scene::parse(text, "").map_err(|e| SceneTextError::Invalid(e.message))?;
    if !scene.banks.is_empty() {
        return Err(SceneTextError::Banks);
    }
    if scene.aerial.is_some() {
        return Err(SceneTextError::Aerial);
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study() -> String {
        crate::scene::BUILTIN_SCENES[0].1.to_string()
    }

    #[test]
    fn the_study_scene_is_self_contained_and_a_scene_naming_files_is_not() {
        assert_eq!(self_contained(&study()).unwrap().name, "study");
        let banked = study().replacen("name: \"study\",", "name: \"study\", banks: [\"bank\"],", 1);
        assert_eq!(self_contained(&banked).unwrap_err(), SceneTextError::Banks);
        let aerial = "aerial: Some((summer: \"s.png\", winter: \"w.png\", gsd_m: 0.5, origin: (0.0, 0.0))),";
        let photographed = study().replacen("name: \"study\",", &format!("name: \"study\", {aerial}"), 1);
        assert_eq!(self_contained(&photographed).unwrap_err(), SceneTextError::Aerial, "photographs without a crowns file are files too");
        assert!(matches!(self_contained("Scene(name: \"x\"").unwrap_err(), SceneTextError::Invalid(m) if m.starts_with("line 1")));
        assert_eq!(self_contained(&" ".repeat(MAX_SCENE_TEXT_BYTES as usize + 1)).unwrap_err(), SceneTextError::TooLarge);
        let bell = study().replacen("name: \"study\"", "name: \"st\u{7}udy\"", 1);
        assert_eq!(self_contained(&bell).unwrap_err(), SceneTextError::Control(7));
        assert!(self_contained(&study().replace('\n', "\r\n\t")).is_ok(), "tabs and line breaks are text");
    }
}
