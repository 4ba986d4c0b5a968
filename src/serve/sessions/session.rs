//! One session being recorded: its file, and every line checked before it is written.
//!
//! A session's file is `DIR/<participant>-<task>-<n>.jsonl` ([`crate::serve::ids`]). Its header is
//! checked field by field (the replay format's header rules, the scene, the models and
//! techniques it names, a participant id fit for a file name) before the file is made; then
//! each line that arrives is checked by the replay crate's own rules ([`LineRules`]: checksum
//! chain, tick order, checkpoint interval) and the names its event uses (a model of the
//! session's catalogue, a built-in task, a registered technique), and only a line that keeps
//! them all is written. A refused line leaves the file and the rules where they were, so the
//! client may go on from the last good line.
//!
//! "On disk" is what `grove play --record` means by it: the lines of a request are handed to the
//! operating system (one `write` per request, no buffer left in the process) before the request
//! is acknowledged, so a killed server loses no acknowledged line; a power cut may still lose
//! what the operating system had not yet stored.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use grove_systems::bank::Banks;
use grove_systems::files::{self, Kind};
use grove_systems::limits::{MAX_LINE_BYTES, MAX_RECORDING_BYTES};
use grove_systems::replay::{self, header_line, session_start_at, Header, Line, LineRules, SessionFields};
use grove_systems::sim::Sim;

use crate::serve::ids;
use crate::serve::line_split::LineSplitter;
use crate::serve::sessions::error::SessionError;

/// What a client may set when it opens a session by its fields; the server writes the header.
#[derive(Clone, Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenFields {
    /// The participant id (required): letters, digits, `_`, `-`.
    pub participant: String,
    /// A built-in task id, or none for a free session.
    #[serde(default)]
    pub task: Option<String>,
    /// A built-in scene name (default `study`) or a `.ron` scene inside the server's working
    /// directory.
    #[serde(default)]
    pub scene: Option<String>,
    /// The simulation's seed (default 0).
    #[serde(default)]
    pub seed: u64,
    /// The technique the session starts with: a built-in one (`ray-casting`, `manual`: not
    /// written in the header) or a registered plug-in (written with its version).
    #[serde(default)]
    pub technique: Option<String>,
    /// The 1-based block of the participant's session.
    #[serde(default)]
    pub block: Option<u32>,
    /// A scene the client built (a headset's room), in place of `scene`: checked, kept beside the
    /// recordings and named by the header ([`crate::serve::sessions::room_scene`]).
    #[serde(default)]
    pub scene_text: Option<String>,
    /// The input device the client uses, written into the header as it is (checked with the
    /// header's other names).
    #[serde(default)]
    pub device: Option<grove_systems::replay::HeaderDevice>,
}

/// The header a server writes for a session opened by its fields: this build's format, the
/// scene's fixed step, the server's clock as `session_start`, not synthetic.
pub fn header_from_fields(fields: &OpenFields, dir: &Path) -> Result<Header, SessionError> {
    let scene_name = match (&fields.scene, &fields.scene_text) {
        (Some(_), Some(_)) => return Err(SessionError::SceneTwice),
        (_, Some(text)) => {
            // The participant id is checked before a file is written for the session.
            ids::participant(&fields.participant)?;
            crate::serve::sessions::room_scene::keep(text, dir)?
        }
        (name, None) => name.clone().unwrap_or_else(|| "study".into()),
    };
    let scene = replay::scene_ref::resolve_scene(&scene_name, Some(dir)).map_err(|e| SessionError::Scene(e.to_string()))?;
    let now = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() as i64);
    let session = SessionFields {
        participant: Some(fields.participant.clone()),
        task: fields.task.clone(),
        block: fields.block,
        session_start: Some(session_start_at(now)),
        technique: fields.technique.clone(),
        ..Default::default()
    };
    let mut header = session.header(&scene_name, fields.seed, scene.dt).map_err(|e| SessionError::Technique(e.to_string()))?;
    header.device = fields.device.clone();
    Ok(header)
}

/// A session's file with the rules its next line must keep.
pub struct Session {
    /// The session's id (a secret: whoever has it may write the session).
    pub id: String,
    /// The file's name inside the folder.
    pub file_name: String,
    /// The file's path.
    pub path: PathBuf,
    /// Its header.
    pub header: Header,
    file: File,
    rules: LineRules,
    /// The simulation the header describes, for the names an event uses (never stepped).
    sim: Sim,
    /// Lines in the file (the header is line 1).
    lines: u64,
    bytes: u64,
    pending: Vec<u8>,
    pending_lines: u64,
    /// The last checkpoint's tick among the lines written (0 for none).
    last_checkpoint: u64,
    pending_checkpoint: u64,
    last_tick: u64,
    /// The client that wrote last, and when it last made a request.
    pub writer: Option<String>,
    /// When the session last had a request.
    pub last_seen: Instant,
    /// Set once the session has ended: nothing more is taken.
    pub ended: bool,
    /// Set when a write failed: the file may hold less than the rules think; nothing more is
    /// taken until the server is restarted (which reads the file again).
    pub broken: Option<String>,
}

/// Checks a header for a session: the replay format's own checks (names, scene, models,
/// technique, fixed step, config), and a participant id and task fit for a file name. Returns the
/// simulation it describes and the file name parts.
fn check_header(header: &Header, dir: &Path, banks: &Banks) -> Result<(Sim, String, String), SessionError> {
    let participant = header.participant.as_deref().ok_or(SessionError::NoParticipant)?;
    let participant = ids::participant(participant)?.to_string();
    let task = ids::task_part(header.task.as_deref())?;
    let sim = replay::sim_for_header_in(header, Some(dir), &[], banks).map_err(|e| SessionError::Header(e.to_string()))?;
    Ok((sim, participant, task))
}

impl Session {
    /// Checks the header line and makes the session's file with it (written and handed to the
    /// operating system before this returns).
    pub fn create(dir: &Path, id: String, header_text: &str, banks: &Banks) -> Result<Session, SessionError> {
        if header_text.len() > MAX_LINE_BYTES {
            return Err(SessionError::HeaderTooLong { limit: MAX_LINE_BYTES });
        }
        if header_text.contains('\n') {
            return Err(SessionError::HeaderLines);
        }
        let header = header_line(header_text).map_err(|e| SessionError::Header(e.to_string()))?;
        let (sim, participant, task) = check_header(&header, dir, banks)?;
        let (mut file, path) = ids::create_session_file(dir, &participant, &task)?;
        let mut bytes = header_text.as_bytes().to_vec();
        bytes.push(b'\n');
        if let Err(e) = file.write_all(&bytes) {
            let _ = std::fs::remove_file(&path);
            return Err(SessionError::HeaderWrite { path: path.display().to_string(), message: e.to_string() });
        }
        let rules = LineRules::after(&header);
        Ok(Session {
            id,
            file_name: file_name(&path),
            path,
            header,
            file,
            rules,
            sim,
            lines: 1,
            bytes: bytes.len() as u64,
            pending: Vec::new(),
            pending_lines: 0,
            last_checkpoint: 0,
            pending_checkpoint: 0,
            last_tick: 0,
            writer: None,
            last_seen: Instant::now(),
            ended: false,
            broken: None,
        })
    }

    /// Opens an existing session's file again (after a restart): every line is checked again as
    /// it was when it arrived; a cut last line (bytes after the last newline, never
    /// acknowledged) is cut off the file; the session's last request counts from the file's last
    /// write, so that the abandon clock goes on across the restart. A line that breaks the rules is an error: the file was
    /// changed by someone else, and the session is not continued.
    pub fn resume(dir: &Path, id: String, name: &str, banks: &Banks) -> Result<Session, SessionError> {
        let path = dir.join(name);
        let shown = path.display().to_string();
        let io = |e: std::io::Error| SessionError::Io { path: shown.clone(), message: e.to_string() };
        let (mut input, _) = files::open(&path, Kind::Recording).map_err(|e| SessionError::Read(e.to_string()))?;
        let mut splitter = LineSplitter::new(MAX_LINE_BYTES);
        let mut state: Option<(Header, LineRules, Sim)> = None;
        let mut problem: Option<String> = None;
        let (mut good_bytes, mut last_checkpoint) = (0u64, 0u64);
        let mut chunk = vec![0u8; 64 * 1024];
        loop {
            let n = input.read(&mut chunk).map_err(io)?;
            if n == 0 {
                break;
            }
            let going = splitter.push(&chunk[..n], &mut |text| {
                let len = text.len() as u64 + 1;
                let result = match state.as_mut() {
                    None => header_line(&text)
                        .map_err(|e| e.to_string())
                        .and_then(|h| check_header(&h, dir, banks).map(|(sim, _, _)| (h, sim)).map_err(|r| r.to_string()))
                        .map(|(h, sim)| state = Some((h.clone(), LineRules::after(&h), sim))),
                    Some((_, rules, sim)) => take_line(rules, sim, text).map(|tick| {
                        if let Some(t) = tick {
                            last_checkpoint = t;
                        }
                    }),
                };
                match result {
                    Ok(()) => {
                        good_bytes += len;
                        true
                    }
                    Err(e) => {
                        problem = Some(e);
                        false
                    }
                }
            });
            match going {
                Ok(true) => {}
                Ok(false) => break,
                Err(e) => return Err(SessionError::Io { path: shown, message: e.to_string() }),
            }
        }
        if let Some(why) = problem {
            return Err(SessionError::FileLine { path: shown, line: splitter.lines(), why });
        }
        let Some((header, rules, sim)) = state else { return Err(SessionError::NoHeader { path: shown }) };
        let last_tick = rules.last_tick();
        // The abandon clock goes on from the file's last write, not from the restart.
        let written = std::fs::metadata(&path).and_then(|m| m.modified()).ok().and_then(|t| t.elapsed().ok());
        let last_seen = written.and_then(|ago| Instant::now().checked_sub(ago)).unwrap_or_else(Instant::now);
        let file = OpenOptions::new().write(true).open(&path).map_err(io)?;
        if !splitter.rest().is_empty() {
            file.set_len(good_bytes).map_err(|e| SessionError::Cut { path: shown.clone(), message: e.to_string() })?;
        }
        drop(file);
        let file = OpenOptions::new().append(true).open(&path).map_err(io)?;
        Ok(Session {
            id,
            file_name: name.to_string(),
            path,
            header,
            file,
            rules,
            sim,
            lines: splitter.lines(),
            bytes: good_bytes,
            pending: Vec::new(),
            pending_lines: 0,
            last_checkpoint,
            pending_checkpoint: last_checkpoint,
            last_tick,
            writer: None,
            last_seen,
            ended: false,
            broken: None,
        })
    }

    /// Lines in the file and handed to the operating system (the header is line 1): the
    /// number a client may forget.
    pub fn acked(&self) -> u64 {
        self.lines
    }

    /// Bytes in the file and handed to the operating system: the acknowledged lines, each
    /// ending in its newline.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// The number the next line will have.
    pub fn next_number(&self) -> u64 {
        self.lines + self.pending_lines + 1
    }

    /// The tick of the last checkpoint written (0 before any).
    pub fn last_checkpoint(&self) -> u64 {
        self.last_checkpoint
    }

    /// The tick of the last line written (0 before any).
    pub fn last_tick(&self) -> u64 {
        self.last_tick
    }

    /// Whether the footer has been taken.
    pub fn has_footer(&self) -> bool {
        self.rules.footer_seen()
    }

    /// Checks the next line (its text without the newline) and keeps it for [`Session::write_out`];
    /// a line that breaks a rule is refused with the reason, and nothing changes.
    pub fn take(&mut self, text: String) -> Result<(), SessionError> {
        let number = self.next_number();
        let grown = self.bytes + self.pending.len() as u64 + text.len() as u64 + 1;
        if grown > MAX_RECORDING_BYTES {
            return Err(SessionError::RecordingFull { number, limit: MAX_RECORDING_BYTES });
        }
        let bytes = text.as_bytes().to_vec();
        let checkpoint = take_line(&mut self.rules, &self.sim, text).map_err(|why| SessionError::Line { number, why })?;
        if let Some(t) = checkpoint {
            self.pending_checkpoint = t;
        }
        self.pending.extend_from_slice(&bytes);
        self.pending.push(b'\n');
        self.pending_lines += 1;
        Ok(())
    }

    /// Hands the lines taken since the last call to the operating system in one write. A failed
    /// write breaks the session (see [`Session::broken`]).
    pub fn write_out(&mut self) -> Result<(), SessionError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        if let Err(e) = self.file.write_all(&self.pending) {
            let failed = SessionError::Write { path: self.path.display().to_string(), message: e.to_string() };
            self.broken = Some(failed.to_string());
            return Err(failed);
        }
        self.bytes += self.pending.len() as u64;
        self.lines += self.pending_lines;
        self.last_checkpoint = self.pending_checkpoint;
        self.last_tick = self.rules.last_tick();
        self.pending.clear();
        self.pending_lines = 0;
        Ok(())
    }
}

/// Checks one line after the header by the format's rules and the names its event uses, and
/// advances `rules` only if it keeps them all. Returns the tick of a checkpoint line.
fn take_line(rules: &mut LineRules, sim: &Sim, text: String) -> Result<Option<u64>, String> {
    let mut next = rules.clone();
    let ruled = next.check(text).map_err(|e| e.0)?;
    let checkpoint = match &ruled.line {
        Line::Event(e) => {
            replay::names::check_event(&e.event, sim).map_err(|e| e.to_string())?;
            None
        }
        Line::Checkpoint(c) => Some(c.tick),
        _ => None,
    };
    *rules = next;
    Ok(checkpoint)
}

fn file_name(path: &Path) -> String {
    path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default()
}
