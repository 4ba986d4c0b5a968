//! The server's sessions: those open (their files being written) and every session of the
//! folder in `DIR/sessions.json`, written through a temporary file and a rename whenever a
//! session opens, ends or is verified, and when the server stops. A server started on a folder
//! reads it back and continues every session still open (after a crash as after Ctrl-C).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use grove_systems::bank::Banks;
use serde::{Deserialize, Serialize};

use crate::serve::ids;
use crate::serve::sessions::error::SessionError;
use crate::serve::sessions::session::Session;
use crate::serve::sessions::states::SessionState;
use crate::serve::sessions::verify::Verification;

/// The file that lists a folder's sessions.
pub const SESSIONS_FILE: &str = "sessions.json";

/// One session as `sessions.json` lists it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Entry {
    /// The session's id: whoever has it (and the token) may write the session.
    pub id: String,
    /// Its file's name in the folder.
    pub file: String,
    /// The participant id.
    pub participant: String,
    /// The task id, if any.
    pub task: Option<String>,
    /// When it opened (UTC, RFC 3339).
    pub opened: String,
    /// Open (may be continued), ended (its client ended it), abandoned (no request for the set
    /// time) or unresumable (its file no longer keeps the rules; `note` says why).
    pub state: SessionState,
    /// Lines in its file when last written here.
    pub lines: u64,
    /// When it ended or was abandoned.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub closed: Option<String>,
    /// Its re-simulation, once ended.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verification: Option<Verification>,
    /// Why a session could not be continued.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
    /// For a session opened with a recording's whole header line (`grove serve push`): the
    /// recording's identity, [`identity`] of that line, by which a push of the same file
    /// continues this session instead of making a second file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub identity: Option<String>,
}

/// A recording's identity: the XXH3-128 of its header line (its participant, task, seed, start
/// time and checksum), 32 hex digits.
pub fn identity(header_line: &str) -> String {
    format!("{:032x}", xxhash_rust::xxh3::xxh3_128(header_line.as_bytes()))
}

/// How a session is opened: from the fields a client may set (the server writes the header), with
/// a recording's whole header line (its identity recorded), or with that line continuing the
/// session it opened before if there is one (`"continue": true`, as `grove serve push` asks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpenWith {
    /// From fields.
    Fields,
    /// With a header line.
    Line,
    /// With a header line, continuing.
    LineContinuing,
}

/// What opening found: a new session and its file, or the session of the same recording opened
/// earlier (its entry, and the session while it is open).
pub enum Opened {
    /// A new session.
    New(Entry, Shared),
    /// The same recording's session.
    Found(Entry, Option<Shared>),
}

#[derive(Serialize, Deserialize)]
struct SessionsFile {
    format: String,
    version: u32,
    sessions: Vec<Entry>,
}

/// A session being written, shared by the requests that reach it (one at a time).
pub type Shared = Arc<tokio::sync::Mutex<Session>>;

/// The sessions of one folder.
pub struct Registry {
    /// The folder.
    pub dir: PathBuf,
    /// The model-bank folders headers may name models of.
    pub bank_dirs: Vec<PathBuf>,
    banks: Banks,
    entries: Mutex<Vec<Entry>>,
    open: Mutex<HashMap<String, Shared>>,
    /// Held while a session is looked up by its recording's identity and made if there is none,
    /// so that two pushes of one recording at once do not make two files.
    opening: Mutex<()>,
    /// The most sessions open at once.
    pub max_open: usize,
}

/// The time now, UTC, to the millisecond (a protocol's task step compares it to when the step
/// began).
fn now() -> String {
    chrono::DateTime::<chrono::Utc>::from(std::time::SystemTime::now()).format("%Y-%m-%dT%H:%M:%S%.3fZ").to_string()
}

impl Registry {
    /// Opens a folder (made if missing), reads its `sessions.json` and continues the sessions
    /// still open. Returns the registry and a line per session continued or not.
    pub fn load(dir: &Path, bank_dirs: Vec<PathBuf>, max_open: usize) -> Result<(Registry, Vec<String>), SessionError> {
        std::fs::create_dir_all(dir).map_err(|e| SessionError::Io { path: dir.display().to_string(), message: e.to_string() })?;
        let banks = Banks::open(&bank_dirs).map_err(|e| SessionError::Banks(e.to_string()))?;
        let list = dir.join(SESSIONS_FILE);
        let mut entries = Vec::new();
        if list.exists() {
            let text = grove_systems::files::read_text(&list, grove_systems::files::Kind::Index).map_err(|e| SessionError::Io { path: list.display().to_string(), message: e.reason() })?;
            let file: SessionsFile = serde_json::from_str(&text).map_err(|e| SessionError::Io { path: list.display().to_string(), message: format!("not a sessions list ({e})") })?;
            if file.format != "grove-sessions" || file.version != 1 {
                return Err(SessionError::Io { path: list.display().to_string(), message: "not a grove sessions list of version 1".into() });
            }
            entries = file.sessions;
        }
        let mut open = HashMap::new();
        let mut notes = Vec::new();
        for e in entries.iter_mut() {
            if e.state == SessionState::Open {
                match Session::resume(dir, e.id.clone(), &e.file, &banks) {
                    Ok(s) => {
                        e.lines = s.acked();
                        notes.push(format!("continuing {} ({} lines)", e.file, e.lines));
                        open.insert(e.id.clone(), Arc::new(tokio::sync::Mutex::new(s)));
                    }
                    Err(why) => {
                        notes.push(format!("cannot continue {}: {why}", e.file));
                        e.state = SessionState::Unresumable;
                        e.note = Some(why.to_string());
                    }
                }
            }
        }
        let registry = Registry { dir: dir.to_path_buf(), bank_dirs, banks, entries: Mutex::new(entries), open: Mutex::new(open), opening: Mutex::new(()), max_open };
        registry.save()?;
        Ok((registry, notes))
    }

    /// Writes `sessions.json` (through a temporary file and a rename).
    pub fn save(&self) -> Result<(), SessionError> {
        let entries = self.entries.lock().unwrap_or_else(|p| p.into_inner());
        let file = SessionsFile { format: "grove-sessions".into(), version: 1, sessions: entries.clone() };
        let text = serde_json::to_string_pretty(&file).unwrap_or_default() + "\n";
        let path = self.dir.join(SESSIONS_FILE);
        crate::atomic_write::write_atomic(&path, text.as_bytes()).map_err(|e| SessionError::Io { path: path.display().to_string(), message: format!("{e:#}") })
    }

    /// Opens a session with this header line: checked, its file made, listed. Continuing (a
    /// recording pushed whole), the session that a header line of the same [`identity`] opened
    /// before is found instead, if there is one.
    pub fn open(&self, header_text: &str, with: OpenWith) -> Result<Opened, SessionError> {
        let _one_at_a_time = (with == OpenWith::LineContinuing).then(|| self.opening.lock().unwrap_or_else(|p| p.into_inner()));
        let key = (with != OpenWith::Fields).then(|| identity(header_text));
        if let (Some(key), OpenWith::LineContinuing) = (&key, with) {
            let earlier = self.entries.lock().unwrap_or_else(|p| p.into_inner()).iter().rev().find(|e| e.identity.as_ref() == Some(key)).cloned();
            if let Some(e) = earlier {
                let shared = self.get(&e.id);
                return Ok(Opened::Found(e, shared));
            }
        }
        let open = self.open.lock().unwrap_or_else(|p| p.into_inner()).len();
        if open >= self.max_open {
            return Err(SessionError::Full { open });
        }
        let id = ids::random_hex(16)?;
        let session = Session::create(&self.dir, id.clone(), header_text, &self.banks)?;
        let (participant, task) = (session.header.participant.clone().unwrap_or_default(), session.header.task.clone());
        let entry = Entry { id: id.clone(), file: session.file_name.clone(), participant, task, opened: now(), state: SessionState::Open, lines: session.acked(), closed: None, verification: None, note: None, identity: key };
        let shared = Arc::new(tokio::sync::Mutex::new(session));
        self.entries.lock().unwrap_or_else(|p| p.into_inner()).push(entry.clone());
        self.open.lock().unwrap_or_else(|p| p.into_inner()).insert(id, shared.clone());
        self.save()?;
        Ok(Opened::New(entry, shared))
    }

    /// An open session by id.
    pub fn get(&self, id: &str) -> Option<Shared> {
        self.open.lock().unwrap_or_else(|p| p.into_inner()).get(id).cloned()
    }

    /// A session's entry by id.
    pub fn entry(&self, id: &str) -> Option<Entry> {
        self.entries.lock().unwrap_or_else(|p| p.into_inner()).iter().find(|e| e.id == id).cloned()
    }

    /// Every entry, in the order the sessions opened.
    pub fn entries(&self) -> Vec<Entry> {
        self.entries.lock().unwrap_or_else(|p| p.into_inner()).clone()
    }

    /// Every open session.
    pub fn open_sessions(&self) -> Vec<Shared> {
        self.open.lock().unwrap_or_else(|p| p.into_inner()).values().cloned().collect()
    }

    /// Ends an open session (its caller holds it): nothing more is taken, it leaves the open
    /// sessions, and its entry gets `state` (ended or abandoned).
    pub fn close(&self, session: &mut Session, state: SessionState) -> Result<(), SessionError> {
        session.ended = true;
        self.open.lock().unwrap_or_else(|p| p.into_inner()).remove(&session.id);
        self.update(&session.id, |e| {
            e.state = state;
            e.lines = session.acked();
            e.closed = Some(now());
        })
    }

    /// Records a session's verification.
    pub fn verified(&self, id: &str, v: Verification) -> Result<(), SessionError> {
        self.update(id, |e| e.verification = Some(v))
    }

    /// Updates the line count of an open session's entry (without writing the list).
    pub fn note_lines(&self, id: &str, lines: u64) {
        if let Some(e) = self.entries.lock().unwrap_or_else(|p| p.into_inner()).iter_mut().find(|e| e.id == id) {
            e.lines = lines;
        }
    }

    fn update(&self, id: &str, f: impl FnOnce(&mut Entry)) -> Result<(), SessionError> {
        if let Some(e) = self.entries.lock().unwrap_or_else(|p| p.into_inner()).iter_mut().find(|e| e.id == id) {
            f(e);
        }
        self.save()
    }

    /// Entries that ended without a verification (the server stopped before it finished).
    pub fn unverified_ended(&self) -> Vec<Entry> {
        self.entries().into_iter().filter(|e| e.state.is_closed() && e.verification.is_none()).collect()
    }
}

#[cfg(test)]
#[path = "registry_tests.rs"]
mod tests;
