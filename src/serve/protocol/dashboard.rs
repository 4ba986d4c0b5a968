//! What `/api/dashboard` answers: every participant (their step) and every session (open ones
//! with their live view, ended ones with their verification, and a session of a task that is not
//! its participant's task step with why: `not_this_steps`), polled every second by the
//! researcher's page.

use serde_json::{json, Value};

use crate::serve::protocol::live::view;
use crate::serve::protocol::{task_step, Protocol};
use crate::serve::sessions::states::SessionState;

/// Every participant and every session, each with its live view.
pub async fn dashboard(protocol: &Protocol) -> Value {
    let (parts, live, registry) = (&protocol.participants, &protocol.live, &protocol.sessions.registry);
    let participants = parts.all();
    let steps = parts.task_steps();
    let mut sessions = Vec::new();
    for e in registry.entries() {
        let mut v = json!({"file": e.file, "participant": e.participant, "task": e.task, "state": e.state, "lines": e.lines, "opened": e.opened, "closed": e.closed, "verification": e.verification});
        v["not_this_steps"] = json!(task_step::listed(&e, &steps));
        let _one_at_a_time = live.making.lock().await;
        let seen = match live.get(&e.file, e.lines) {
            Some(l) => Some(l),
            None if e.state == SessionState::Open || live.last(&e.file).is_none() => {
                let (path, scratch, banks) = (registry.dir.join(&e.file), std::env::temp_dir().join(format!("grove-live-{}", std::process::id())), registry.bank_dirs.clone());
                match tokio::task::spawn_blocking(move || view(&path, &scratch, &banks)).await {
                    Ok(Ok(l)) => {
                        live.put(&e.file, e.lines, l.clone());
                        Some(l)
                    }
                    Ok(Err(why)) => Some(json!({"error": why.to_string()})),
                    Err(_) => None,
                }
            }
            None => live.last(&e.file),
        };
        v["live"] = seen.unwrap_or(Value::Null);
        sessions.push(v);
    }
    json!({"protocol": parts.loaded.protocol.name, "participants": participants, "sessions": sessions})
}
