//! What `grove serve` is started with (`cli/serve/` fills it from the command line).

use std::net::IpAddr;
use std::path::PathBuf;
use std::time::Duration;

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
    /// The most connections served at once (the longest idle one closes for a new one).
    pub max_connections: usize,
    /// The most connections from one address (the longest idle one of it closes for a new one).
    pub max_per_address: usize,
    /// Ask for the token on a loopback address too.
    pub require_token: bool,
    /// Draw a new token instead of the one kept in the folder (`DIR/token`).
    pub new_token: bool,
    /// The study protocol run for the participants (`docs/protocol.md`), if any.
    pub protocol: Option<crate::protocol::Loaded>,
    /// Whether every session is verified as it streams (else only at its end, its file
    /// re-simulated whole: for comparisons).
    pub live: bool,
}
