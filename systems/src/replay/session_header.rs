//! The header of a new session's recording, built in one place for every recorder of a person's
//! session: `grove play --record`, `grove serve` opening a session by its fields, and the
//! WebAssembly module making its own recording (`web/sim`). [`SessionFields`] are what the
//! recorder knows beyond the scene and the seed; [`session_start_at`] formats its start.
//!
//! The rules: this build's format and version; a built-in technique is not written (the
//! session's `switch_mode` events say it), a registered plug-in is written with its version, an
//! unknown one is refused.

use super::{Header, HeaderTechnique};
use crate::resources::Overrides;

/// What a session's header says beyond its scene, seed and fixed step.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SessionFields {
    /// The participant's id.
    pub participant: Option<String>,
    /// The built-in task the session runs.
    pub task: Option<String>,
    /// The 1-based block of the participant's session.
    pub block: Option<u32>,
    /// When the session started (RFC 3339 UTC, [`session_start_at`]).
    pub session_start: Option<String>,
    /// The technique the session starts with, by name.
    pub technique: Option<String>,
    /// Whether the session is generated rather than a person's.
    pub synthetic: bool,
    /// Configuration overrides in effect.
    pub config: Overrides,
}

/// Why a session's header could not be made.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SessionHeaderError {
    /// The technique named is not registered (the message lists the registered ones).
    #[error("technique: {0}")]
    UnknownTechnique(String),
}

impl SessionFields {
    /// The header of a new recording on the scene named `scene` (as the header names it) with
    /// `seed` and the scene's fixed step `dt`.
    pub fn header(&self, scene: &str, seed: u64, dt: f32) -> Result<Header, SessionHeaderError> {
        let mut header = Header::new(scene, seed, dt);
        header.participant = self.participant.clone();
        header.task = self.task.clone();
        header.block = self.block;
        header.session_start = self.session_start.clone();
        header.synthetic = self.synthetic;
        header.config = self.config.clone();
        if let Some(name) = &self.technique {
            let techniques = crate::technique::installed();
            let t = techniques.get(name).ok_or_else(|| SessionHeaderError::UnknownTechnique(techniques.unknown(name)))?;
            if !t.is_builtin() {
                header.technique = Some(HeaderTechnique { name: t.name.to_string(), version: t.version });
            }
        }
        Ok(header)
    }
}

/// A session's `session_start`: `unix_seconds` after the Unix epoch as RFC 3339 UTC to the
/// second (`2019-06-03T09:00:00Z`), the form the replay format's header rule reads.
pub fn session_start_at(unix_seconds: i64) -> String {
    chrono::DateTime::from_timestamp(unix_seconds, 0).map_or_else(|| "1970-01-01T00:00:00Z".to_string(), |t| t.to_rfc3339_opts(chrono::SecondsFormat::Secs, true))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fields_fill_the_header_and_a_built_in_technique_is_not_written() {
        let fields = SessionFields { participant: Some("P09".into()), task: Some("manual-7".into()), block: Some(2), session_start: Some(session_start_at(1_559_552_400)), technique: Some("manual".into()), ..Default::default() };
        let h = fields.header("study", 4, 0.5).unwrap();
        assert_eq!((h.scene.as_str(), h.seed, h.dt), ("study", 4, 0.5));
        assert_eq!((h.participant.as_deref(), h.task.as_deref(), h.block), (Some("P09"), Some("manual-7"), Some(2)));
        assert_eq!(h.session_start.as_deref(), Some("2019-06-03T09:00:00Z"));
        assert_eq!(h.technique, None);
        assert!(!h.synthetic);
        crate::replay::names::check_header(&h).unwrap();
    }

    #[test]
    fn an_unknown_technique_is_refused_naming_the_registered_ones() {
        let e = SessionFields { technique: Some("telekinesis".into()), ..Default::default() }.header("study", 0, 0.5).unwrap_err();
        assert!(e.to_string().starts_with("technique: ") && e.to_string().contains("ray-casting, manual"), "{e}");
    }
}
