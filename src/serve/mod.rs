//! `grove serve`: a session server for a lab. Headsets (or any client) stream recordings to it
//! as they are made, in grove's own format, and it serves them the page, the wasm module, the
//! scenes, tasks and tree models. `docs/serve.md` is the user's guide.
//!
//! Its rooms, each folder's `mod.rs` saying what it owns and what it does not know:
//!
//! - [`http`]: connections (plain or TLS, bounded in number and time), the token, the one body
//!   reader, the one router behaviour, responses, the files served as they are. It knows no
//!   session and no protocol.
//! - [`sessions`]: a session's file checked line by line, the folder's sessions and
//!   `sessions.json`, their typed states, their verification, their routes and background jobs.
//! - [`protocol`]: a study protocol's participants, answers, routes, pages and live dashboard;
//!   it reads the sessions.
//! - [`client`]: the one HTTP client (`grove serve push`, `grove serve bench`, the tests).
//!
//! And the hall that joins them: [`server`] start to stop, [`app`] where each request goes,
//! [`refusals`] every session and protocol error as its HTTP status, [`error`] why the server
//! could not start, [`config`] what it starts with; [`ids`] the names it makes, [`line_split`]
//! lines out of byte chunks, [`log`] its log line, [`index_page`] its own page at `/`.

pub mod app;
pub mod client;
pub mod config;
pub mod error;
pub mod http;
pub mod ids;
pub mod index_page;
pub mod line_split;
pub mod log;
pub mod protocol;
pub mod refusals;
pub mod server;
pub mod sessions;

pub use config::{ServeConfig, TlsChoice};
pub use error::ServeError;
pub use server::run;
