//! `grove serve`: a session server for a lab. Headsets (or any client) stream recordings to it
//! as they are made, in grove's own format, and it serves them the page, the wasm module, the
//! scenes, tasks and tree models. `docs/serve.md` is the user's guide.
//!
//! - [`session`]: a session's file, each line checked by the replay crate's rules before it is
//!   written; [`registry`]: the open sessions and `DIR/sessions.json`; [`verify`]: the
//!   re-simulation of a session that ended; [`room_scene`]: a scene a client built (a headset's
//!   room), kept beside the recordings.
//! - [`http`]: connections (plain or TLS, bounded in number and time), the token, the routes;
//!   [`api`]: the session routes; [`static_files`]: files served as they are, never outside
//!   their folders.
//! - [`client`], [`push`]: an HTTP client that streams a recording as a live client would
//!   (`grove serve push`); [`bench`]: many sessions at once (`grove serve bench`).

pub mod app;
pub mod client;
pub mod http;
pub mod ids;
pub mod line_split;
pub mod protocol;
pub mod sessions;

use std::net::IpAddr;
use std::path::PathBuf;
use std::time::Duration;

/// Why the server could not start or go on: one line.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// A file or folder could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// What went wrong, one line.
        message: String,
    },
    /// The operating system gave no random bytes.
    #[error("cannot draw random bytes from the operating system: {0}")]
    Random(String),
    /// The address could not be listened on.
    #[error("cannot listen on {addr}: {message}")]
    Bind {
        /// The address.
        addr: String,
        /// Why.
        message: String,
    },
    /// The certificate or key could not be made or read.
    #[error("TLS: {0}")]
    Tls(String),
    /// A model bank could not be opened.
    #[error("model banks: {0}")]
    Banks(String),
    /// A client-side problem (`push`, `bench`): the server, the URL or the network.
    #[error("{0}")]
    Client(String),
}

/// A request refused: the HTTP status and the reason, one line, sent to the client.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct Refusal {
    /// The HTTP status.
    pub status: u16,
    /// Why, one line.
    pub reason: String,
}

impl Refusal {
    fn with(status: u16, reason: impl Into<String>) -> Refusal {
        Refusal { status, reason: reason.into().replace(['\n', '\r'], " ") }
    }
    /// 400: the request is malformed or names something that does not exist.
    pub fn bad(reason: impl Into<String>) -> Refusal {
        Refusal::with(400, reason)
    }
    /// 401: no valid token.
    pub fn unauthorized(reason: impl Into<String>) -> Refusal {
        Refusal::with(401, reason)
    }
    /// 404: nothing there.
    pub fn not_found(reason: impl Into<String>) -> Refusal {
        Refusal::with(404, reason)
    }
    /// 405: the method is not served there.
    pub fn method(reason: impl Into<String>) -> Refusal {
        Refusal::with(405, reason)
    }
    /// 408: the request came too slowly.
    pub fn timeout(reason: impl Into<String>) -> Refusal {
        Refusal::with(408, reason)
    }
    /// 409: the session is in another state than the request assumes (another writer, a
    /// request in progress, another next line).
    pub fn conflict(reason: impl Into<String>) -> Refusal {
        Refusal::with(409, reason)
    }
    /// 410: the session has ended.
    pub fn gone(reason: impl Into<String>) -> Refusal {
        Refusal::with(410, reason)
    }
    /// 413: over a size limit.
    pub fn too_large(reason: impl Into<String>) -> Refusal {
        Refusal::with(413, reason)
    }
    /// 422: a line breaks the format's rules.
    pub fn bad_line(reason: impl Into<String>) -> Refusal {
        Refusal::with(422, reason)
    }
    /// 503: the server takes no more sessions now.
    pub fn busy(reason: impl Into<String>) -> Refusal {
        Refusal::with(503, reason)
    }
    /// 500: the server failed (a file could not be written).
    pub fn internal(reason: impl Into<String>) -> Refusal {
        Refusal::with(500, reason)
    }
}

/// How the server speaks TLS.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TlsChoice {
    /// Plain HTTP.
    Off,
    /// A self-signed certificate, made once and kept in `DIR/tls/` (`cert.pem`, `key.pem`).
    Auto,
    /// A certificate chain and its private key, PEM files.
    Files {
        /// The certificate chain.
        cert: PathBuf,
        /// The private key.
        key: PathBuf,
    },
}

/// What `grove serve` is started with.
#[derive(Clone, Debug)]
pub struct ServeConfig {
    /// The folder sessions are written to.
    pub out: PathBuf,
    /// The address to listen on.
    pub host: IpAddr,
    /// The port (0: any free one, printed).
    pub port: u16,
    /// TLS.
    pub tls: TlsChoice,
    /// Model-bank folders whose models headers may name and which are served.
    pub banks: Vec<PathBuf>,
    /// The web folder (`dist/` the page, `client/` the client library, `sim/` the module's loader).
    pub web: PathBuf,
    /// The folder of the built module (`grove_sim.wasm`, as `web/build.sh` makes it).
    pub wasm: PathBuf,
    /// The assets folder (`scenes/`, `tasks/`, `trees/`, `banks/`).
    pub assets: PathBuf,
    /// The longest a request's head or body may take to arrive.
    pub read_timeout: Duration,
    /// How long a session stays its last writer's after that writer's last request.
    pub writer_lease: Duration,
    /// A session without a request for this long is ended and verified.
    pub abandon_after: Duration,
    /// The most sessions open at once.
    pub max_sessions: usize,
    /// The most connections served at once (more wait to be accepted).
    pub max_connections: usize,
    /// Ask for the token on a loopback address too.
    pub require_token: bool,
    /// The study protocol run for the participants (`docs/protocol.md`), if any.
    pub protocol: Option<crate::protocol::Loaded>,
}

/// Runs the server until Ctrl-C (or SIGTERM); see [`http::listen::serve`].
pub fn run(config: ServeConfig) -> Result<(), ServeError> {
    let runtime = tokio::runtime::Builder::new_multi_thread().enable_all().build().map_err(|e| ServeError::Io { path: "tokio runtime".into(), message: e.to_string() })?;
    runtime.block_on(http::listen::serve(config))
}
