//! What happens to sessions besides their requests: a session ended (by its client or as
//! abandoned) gets its verification (the live one, [`crate::serve::sessions::live`]) recorded; a
//! loop ends the sessions that had no request for `--abandon-after`; at the start, sessions that
//! ended without their verification are verified; at the stop, every open file is handed to the
//! operating system.

use std::sync::Arc;
use std::time::Duration;

use serde_json::{json, Value};
use tokio::sync::OwnedMutexGuard;

use crate::serve::log::log;
use crate::serve::sessions::error::SessionError;
use crate::serve::sessions::registry::Entry;
use crate::serve::sessions::service::Sessions;
use crate::serve::sessions::session::Session;
use crate::serve::sessions::states::SessionState;
use crate::serve::sessions::verify::{verify, Verification};

/// The longest an end waits for the live verification to reach the session's last line.
const END_PATIENCE: Duration = Duration::from_secs(60);

impl Sessions {
    /// Ends a session (held by its caller) as `how` (ended or abandoned), waits for its
    /// verification (its live replay reaching the last line) and records it; returns the answer
    /// to its client.
    pub async fn close_and_verify(&self, mut s: OwnedMutexGuard<Session>, how: SessionState) -> Result<Value, SessionError> {
        s.write_out()?;
        self.registry.close(&mut s, how)?;
        let (id, file, path, acked, last_tick, last_checkpoint, bytes) = (s.id.clone(), s.file_name.clone(), s.path.clone(), s.acked(), s.last_tick(), s.last_checkpoint(), s.bytes());
        drop(s);
        // The live verification once it has replayed the last line; the whole file re-simulated
        // only when the session was not watched or its worker did not finish in time.
        let v = match self.live.finish(&id, bytes, END_PATIENCE).await {
            Some(v) => v,
            None => {
                let banks = self.registry.bank_dirs.clone();
                let permit = self.verifying.acquire().await.map_err(|e| SessionError::Task(e.to_string()))?;
                let v = tokio::task::spawn_blocking(move || verify(&path, &banks, last_tick, last_checkpoint)).await.map_err(|e| SessionError::Task(e.to_string()))?;
                drop(permit);
                v
            }
        };
        log(&format!("{how} {file}: {acked} lines, {}", v.summary()));
        self.registry.verified(&id, v.clone())?;
        Ok(json!({ "acked": acked, "file": file, "state": how, "verification": v }))
    }

    /// Hands every open session's lines to the operating system and notes its line count; returns
    /// how many sessions are open.
    pub async fn flush_all(&self) -> usize {
        let open = self.registry.open_sessions();
        for shared in &open {
            if let Ok(mut s) = tokio::time::timeout(Duration::from_secs(2), shared.lock()).await {
                let _ = s.write_out();
                self.registry.note_lines(&s.id, s.acked());
            }
        }
        open.len()
    }

    /// Verifies every session that ended while the server stopped before its verification was
    /// written.
    pub async fn verify_unverified(&self) {
        for e in self.registry.unverified_ended() {
            self.verify_again(&e).await;
        }
    }

    async fn verify_again(&self, e: &Entry) {
        let registry = &self.registry;
        let (dir, id, file, banks) = (registry.dir.clone(), e.id.clone(), e.file.clone(), registry.bank_dirs.clone());
        let v = tokio::task::spawn_blocking(move || -> Verification {
            let bank_set = grove_systems::bank::Banks::open(&banks).unwrap_or_default();
            match Session::resume(&dir, id, &file, &bank_set) {
                Ok(s) => verify(&s.path, &banks, s.last_tick(), s.last_checkpoint()),
                Err(why) => Verification::invalid(why.to_string(), 0),
            }
        })
        .await;
        if let Ok(v) = v {
            log(&format!("{} {}: {}", e.state, e.file, v.summary()));
            let _ = registry.verified(&e.id, v);
        }
    }
}

/// Ends every session that has had no request for `after`, as abandoned, and verifies it.
pub async fn abandon_loop(sessions: Arc<Sessions>, after: Duration) {
    let every = (after / 4).clamp(Duration::from_millis(100), Duration::from_secs(5));
    loop {
        tokio::time::sleep(every).await;
        for shared in sessions.registry.open_sessions() {
            let Ok(s) = shared.try_lock_owned() else { continue };
            if !s.ended && s.last_seen.elapsed() >= after {
                let _ = sessions.close_and_verify(s, SessionState::Abandoned).await;
            }
        }
    }
}
