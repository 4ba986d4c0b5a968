//! The sessions as the routes and the background jobs share them: the folder's registry, how
//! long a request and a writer's lease last, how many re-simulations run at once; and the two
//! ways a request reaches one session: to read it (waiting for a request in progress) or to
//! write it (refused while another request or another writer holds it).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use tokio::sync::{MutexGuard, OwnedMutexGuard, Semaphore};

use crate::serve::ids;
use crate::serve::sessions::error::SessionError;
use crate::serve::sessions::live::Live;
use crate::serve::sessions::registry::{Registry, Shared};
use crate::serve::sessions::session::Session;

/// The sessions of one folder, as the requests see them.
pub struct Sessions {
    /// The folder's sessions.
    pub registry: Registry,
    /// The longest a request's body may take to arrive.
    pub read_timeout: Duration,
    /// How long a session stays its last writer's after that writer's last request.
    pub writer_lease: Duration,
    /// Re-simulations running at once: at most one per core less one (at least one), so that
    /// many sessions ending together do not take the cores from those still streaming.
    pub verifying: Semaphore,
    /// Every session's lines replayed and verified as they are acknowledged.
    pub live: Live,
}

impl Sessions {
    /// Opens a folder (made if missing) and continues the sessions still open in it, each
    /// verified as it streams unless `live` is false; returns a line per session continued or not.
    pub fn load(dir: &std::path::Path, banks: Vec<PathBuf>, max_open: usize, read_timeout: Duration, writer_lease: Duration, live: bool) -> Result<(Sessions, Vec<String>), SessionError> {
        let (registry, notes) = Registry::load(dir, banks, max_open)?;
        let verifying = Semaphore::new(std::thread::available_parallelism().map_or(1, |n| n.get().saturating_sub(1).max(1)));
        let live = Live::start(&registry.bank_dirs, live);
        for shared in registry.open_sessions() {
            // Nothing else holds a session yet.
            if let Ok(s) = shared.try_lock() {
                live.watch(&s.id, &s.path, s.bytes());
            }
        }
        Ok((Sessions { registry, read_timeout, writer_lease, verifying, live }, notes))
    }

    /// The open session `id`; for one that has ended, its entry as the refusal.
    pub fn find(&self, id: &str) -> Result<Shared, SessionError> {
        if !ids::is_session_id(id) {
            return Err(SessionError::NoSuchSession);
        }
        match self.registry.get(id) {
            Some(s) => Ok(s),
            None => match self.registry.entry(id) {
                Some(e) => Err(SessionError::Gone { file: e.file, state: e.state, acked: e.lines, verification: e.verification.map(Box::new) }),
                None => Err(SessionError::NoSuchSession),
            },
        }
    }

    /// Waits for a session to read it, at most as long as a request may take.
    pub async fn read<'a>(&self, shared: &'a Shared) -> Result<MutexGuard<'a, Session>, SessionError> {
        tokio::time::timeout(self.read_timeout + Duration::from_secs(1), shared.lock()).await.map_err(|_| SessionError::Busy)
    }

    /// Takes the session for one request of `writer`: refused while another request on it is in
    /// progress, or while another writer holds it.
    pub fn take(&self, shared: Shared, writer: &str) -> Result<OwnedMutexGuard<Session>, SessionError> {
        let mut s = shared.try_lock_owned().map_err(|_| SessionError::InProgress)?;
        if s.ended {
            return Err(SessionError::Ended);
        }
        if let Some(why) = &s.broken {
            return Err(SessionError::Broken { why: why.clone(), acked: s.acked() });
        }
        let idle = s.last_seen.elapsed();
        if let Some(w) = &s.writer
            && w != writer
            && idle < self.writer_lease
        {
            return Err(SessionError::Writer { file: s.file_name.clone(), idle_s: idle.as_secs_f64(), lease_s: self.writer_lease.as_secs_f64(), acked: s.acked() });
        }
        s.writer = Some(writer.to_string());
        s.last_seen = Instant::now();
        Ok(s)
    }
}
