//! What every request of the server sees.

use std::time::Duration;

use crate::serve::sessions::registry::Registry;
use crate::serve::http::static_files::StaticRoots;

/// What every request sees.
pub struct State {
    /// The sessions.
    pub registry: Registry,
    /// The token every request must carry, if any.
    pub token: Option<String>,
    /// The folders served as they are.
    pub statics: StaticRoots,
    /// See [`crate::serve::ServeConfig::read_timeout`].
    pub read_timeout: Duration,
    /// See [`crate::serve::ServeConfig::writer_lease`].
    pub writer_lease: Duration,
    /// Whether connections are TLS (the token's cookie is then `Secure`).
    pub tls: bool,
    /// Re-simulations running at once: at most one per core less one (at least one), so that
    /// many sessions ending together do not take the cores from those still streaming.
    pub verifying: tokio::sync::Semaphore,
    /// The protocol's participants, when the server runs one.
    pub participants: Option<std::sync::Arc<crate::serve::protocol::participants::Participants>>,
    /// The dashboard's live views of the sessions.
    pub live: crate::serve::protocol::live::LiveCache,
}

