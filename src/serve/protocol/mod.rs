//! A study protocol run by `grove serve --protocol` (`docs/protocol.md`): `participants.rs`
//! each participant's id, condition order, step and answers (`DIR/<id>.answers.jsonl`);
//! `folder.rs` the folder read back at start, its ids checked; `task_step.rs` which session
//! finishes a task step; `routes.rs` its routes; `dashboard.rs` the researcher's live view of
//! every session (the sessions' own live replays, `serve/sessions/live.rs`); `pages.rs` the
//! participant's form page and the researcher's dashboard; `error.rs` why a protocol request was
//! refused, one enum.
//!
//! It reads the sessions (a task step is finished when its own session has ended; their
//! participant ids share one namespace with the participants') and never writes them; it knows HTTP only through `serve/http/`. It does not know the token, TLS, the served
//! files or how a session's lines are checked.

use std::sync::Arc;

use crate::serve::protocol::participants::{Participants, TaskSessions};
use crate::serve::sessions::registry::Entry;
use crate::serve::sessions::service::Sessions;

pub mod dashboard;
pub mod error;
pub mod folder;
pub mod pages;
pub mod participants;
pub mod routes;
pub mod task_step;

/// A protocol as its routes see it: the participants and the sessions (whose ends finish the
/// task steps, and whose live views the dashboard shows).
pub struct Protocol {
    /// The participants.
    pub participants: Participants,
    /// The sessions.
    pub sessions: Arc<Sessions>,
}

impl TaskSessions for Sessions {
    fn finishing(&self, participant: &str, task: &str, began: &str) -> Result<String, Vec<(String, &'static str)>> {
        let theirs: Vec<Entry> = self.registry.entries().into_iter().filter(|e| e.participant == participant && e.task.as_deref() == Some(task)).collect();
        match theirs.iter().find(|e| task_step::finishes(e, began)) {
            Some(e) => Ok(e.file.clone()),
            None => Err(theirs.iter().filter_map(|e| task_step::not_this_steps(e, began).map(|why| (e.file.clone(), why))).collect()),
        }
    }

    fn ids_in_use(&self) -> Vec<(String, String)> {
        let mut ids: Vec<(String, String)> = Vec::new();
        for e in self.registry.entries() {
            if !ids.iter().any(|(i, _)| *i == e.participant) {
                ids.push((e.participant, e.file));
            }
        }
        ids
    }
}
