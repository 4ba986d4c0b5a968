//! What `/api/dashboard` answers: every participant (their step) and every session (each with its
//! live view: the world's figures and the verification of its lines so far, made by the sessions'
//! workers as the lines came, [`crate::serve::sessions::live`]; ended ones with their
//! verification; a session of a task that is not its participant's task step with why:
//! `not_this_steps`), polled every second by the researcher's page.

use std::sync::Arc;

use serde_json::{json, Value};

use crate::serve::protocol::{task_step, Protocol};
use crate::serve::sessions::service::Sessions;

/// Every participant and every session, each with its live view.
pub async fn dashboard(protocol: &Protocol) -> Value {
    let participants = protocol.participants.all();
    let steps = protocol.participants.task_steps();
    let sessions = protocol.sessions.clone();
    // A view waits for a worker's turn in progress: read off the requests' threads.
    let listed = tokio::task::spawn_blocking(move || sessions_now(&sessions, &steps)).await.unwrap_or_default();
    json!({"protocol": protocol.participants.loaded.protocol.name, "participants": participants, "sessions": listed})
}

fn sessions_now(sessions: &Arc<Sessions>, steps: &[(String, String, Option<String>)]) -> Vec<Value> {
    let (registry, live) = (&sessions.registry, &sessions.live);
    let mut out = Vec::new();
    for e in registry.entries() {
        if !live.has(&e.id) {
            // Ended before this server started: its view is made once, in the background.
            let path = registry.dir.join(&e.file);
            let bytes = std::fs::metadata(&path).map_or(0, |m| m.len());
            live.review(&e.id, &path, bytes);
        }
        let view = live.view(&e.id);
        out.push(json!({"file": e.file, "participant": e.participant, "task": e.task, "state": e.state, "lines": e.lines, "opened": e.opened, "closed": e.closed, "verification": e.verification, "not_this_steps": task_step::listed(&e, steps), "live": view}));
    }
    out
}
