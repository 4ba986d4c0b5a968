//! Why a session could not be opened, written, continued or read: one enum for the whole room,
//! each variant one line. `serve/refusals.rs` gives each its HTTP status; the server's start
//! reports them as they are.

use crate::serve::http::refusal::Refusal;
use crate::serve::ids::{BadId, IdError};
use crate::serve::sessions::states::SessionState;
use crate::serve::sessions::verify::Verification;

/// Why a session request or a session's file was refused.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    // Opening: the header and the fields.
    /// The header line is over the line limit.
    #[error("the header line is longer than the limit of {limit} bytes")]
    HeaderTooLong {
        /// The limit, bytes.
        limit: usize,
    },
    /// The header holds a line break.
    #[error("the header must be one line")]
    HeaderLines,
    /// The header breaks the replay format's rules.
    #[error("header: {0}")]
    Header(String),
    /// The header names no participant.
    #[error("the header has no participant id; a session needs one")]
    NoParticipant,
    /// A participant or task id unfit for a file name.
    #[error(transparent)]
    BadId(#[from] BadId),
    /// An open request with both a scene name and a scene's text.
    #[error("an open request names a scene or sends scene_text, not both")]
    SceneTwice,
    /// The scene cannot be resolved.
    #[error("{0}")]
    Scene(String),
    /// The technique is not registered.
    #[error("technique: {0}")]
    Technique(String),
    /// An open request with a header line and other fields.
    #[error("an open request with a header line has no other field")]
    HeaderAndFields,
    /// `continue` that is not true or false.
    #[error("'continue' must be true or false")]
    ContinueNotBool,
    /// `continue` beside fields: only a recording's header line names a recording to continue.
    #[error("'continue' goes with a recording's header line ({{\"header\": LINE, \"continue\": true}}), not with fields")]
    ContinueWithFields,
    /// The header line is not a string.
    #[error("'header' must be the header line, a string")]
    HeaderNotText,
    /// The open request's fields do not fit.
    #[error("open request: {0}")]
    Fields(String),
    /// As many sessions are open as the server takes.
    #[error("{open} sessions are open, the most this server takes (--max-sessions); end one first")]
    Full {
        /// Sessions open.
        open: usize,
    },
    /// No id or no file name could be made.
    #[error(transparent)]
    Name(#[from] IdError),
    /// Refused by the layer beneath (the body reader) or by the room scene's own check, as it is.
    #[error(transparent)]
    Refused(#[from] Refusal),

    // Lines.
    /// A line would take the recording past its limit.
    #[error("line {number}: the recording would pass the limit of {limit} bytes per recording")]
    RecordingFull {
        /// The line's number in the file.
        number: u64,
        /// The limit, bytes.
        limit: u64,
    },
    /// A line breaks the format's rules or names what the session does not have.
    #[error("line {number}: {why}")]
    Line {
        /// The line's number in the file.
        number: u64,
        /// Why.
        why: String,
    },
    /// A line over the line limit.
    #[error("line {number} is longer than the limit of {limit} bytes")]
    LineTooLong {
        /// The line's number in the file.
        number: u64,
        /// The limit, bytes.
        limit: usize,
    },
    /// A line that is not UTF-8.
    #[error("line {number}: not valid UTF-8 text")]
    NotUtf8 {
        /// The line's number in the file.
        number: u64,
    },
    /// The request's last line has no newline.
    #[error("line {number} has no newline at the end of the request; every line ends in \\n")]
    NoNewline {
        /// The line's number in the file.
        number: u64,
    },
    /// The header could not be written to the new file.
    #[error("{path}: cannot write ({message})")]
    HeaderWrite {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// Lines could not be written: the session takes nothing more until the server restarts.
    #[error("{path}: cannot write ({message}); restart the server to continue the session")]
    Write {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },

    // Files read back: a session continued, `sessions.json`, the model banks.
    /// A file or folder could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What went wrong, one line.
        message: String,
    },
    /// A line of a session's file no longer keeps the rules.
    #[error("{path}:{line}: {why}")]
    FileLine {
        /// The file.
        path: String,
        /// The line's number.
        line: u64,
        /// Why.
        why: String,
    },
    /// A session's file without a header line.
    #[error("{path}: no header line")]
    NoHeader {
        /// The file.
        path: String,
    },
    /// A cut last line could not be cut off.
    #[error("{path}: cannot cut its last, unfinished line ({message})")]
    Cut {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// A model bank could not be opened.
    #[error("model banks: {0}")]
    Banks(String),

    // Requests on one session.
    /// No session of that id (or not an id of the server's form).
    #[error("no such session")]
    NoSuchSession,
    /// The session has ended or could not be continued: its entry.
    #[error("session {file} is {state}")]
    Gone {
        /// Its file.
        file: String,
        /// Its state.
        state: SessionState,
        /// Lines in its file.
        acked: u64,
        /// Its verification, once made.
        verification: Option<Box<Verification>>,
    },
    /// Another request holds the session longer than a request may take.
    #[error("the session is busy with another request; ask again")]
    Busy,
    /// Another request on the session is in progress.
    #[error("another request on this session is in progress; try again when it is answered")]
    InProgress,
    /// The session ended while the request waited for it.
    #[error("the session has ended")]
    Ended,
    /// A write failed earlier: nothing more is taken.
    #[error("{why}")]
    Broken {
        /// Why, as the failed write said.
        why: String,
        /// Lines in the file.
        acked: u64,
    },
    /// Another client writes the session.
    #[error("session {file} is being written by another client (its last request {idle_s:.1} s ago); another client may take it over after {lease_s:.0} s without requests")]
    Writer {
        /// The session's file.
        file: String,
        /// Seconds since its writer's last request.
        idle_s: f64,
        /// The writer lease, seconds.
        lease_s: f64,
        /// Lines in the file.
        acked: u64,
    },
    /// A batch that does not start at the file's next line.
    #[error("the file has {acked} lines; send from line {}", .acked + 1)]
    Gap {
        /// Lines in the file.
        acked: u64,
    },
    /// A request that writes without naming its client.
    #[error("{request} needs the Grove-Writer header naming its client")]
    NoWriter {
        /// `a lines request`, `an end request`.
        request: &'static str,
    },
    /// A client name that is not a plain word.
    #[error("the Grove-Writer header must be 1 to 64 letters, digits, '-' or '_'")]
    BadWriter,
    /// A lines request without `?from=N`.
    #[error("a lines request needs ?from=N, the number of its first line in the file")]
    NoFrom,
    /// The session's scene is a built-in one.
    #[error("the session's scene is the built-in scene {0:?}, not a file")]
    BuiltinScene(String),
    /// The session's scene file is in neither place the replay looks.
    #[error("the session's scene file {0:?} is not in the sessions' folder or the working directory")]
    NoSceneFile(String),
    /// A file could not be read.
    #[error("{0}")]
    Read(String),
    /// A task of the server failed.
    #[error("{0}")]
    Task(String),
    /// A request stopped part of the way: its cause, with the lines now in the file.
    #[error("{cause}")]
    Stopped {
        /// Lines in the file.
        acked: u64,
        /// Why it stopped.
        cause: Box<SessionError>,
    },
}
