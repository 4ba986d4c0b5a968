//! A study protocol run by `grove serve --protocol` (`docs/protocol.md`): `participants.rs`
//! each participant's id, condition order, step and answers (`DIR/<id>.answers.jsonl`);
//! `routes.rs` its routes; `dashboard.rs` the researcher's live view of every session (the
//! sessions' own live replays, `serve/sessions/live.rs`); `pages.rs` the participant's form page and the
//! researcher's dashboard (`protocol.html`, `dashboard.html`); `error.rs` why a protocol request
//! was refused, one enum.
//!
//! It reads the sessions (a task step is finished when its session has ended) and never writes
//! them; it knows HTTP only through `serve/http/`. It does not know the token, TLS, the served
//! files or how a session's lines are checked.

use std::sync::Arc;

use crate::serve::protocol::participants::{Participants, TaskSessions};
use crate::serve::sessions::service::Sessions;

pub mod dashboard;
pub mod error;
pub mod pages;
pub mod participants;
pub mod routes;

/// A protocol as its routes see it: the participants and the sessions (whose ends finish the
/// task steps, and whose live views the dashboard shows).
pub struct Protocol {
    /// The participants.
    pub participants: Participants,
    /// The sessions.
    pub sessions: Arc<Sessions>,
}

impl TaskSessions for Sessions {
    fn ended(&self, participant: &str, task: &str) -> bool {
        self.registry.entries().iter().any(|e| e.participant == participant && e.task.as_deref() == Some(task) && e.state.is_closed())
    }
}
