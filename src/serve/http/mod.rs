//! HTTP, the server's lowest room: connections (`listen.rs`: plain or TLS over `tls.rs`,
//! bounded in number and time; `pool.rs`: which connection gives way, the idle first), the token checked before any handler sees a request
//! (`token.rs`), how the server shows itself at start (`banner.rs`: its URL and QR code), the
//! one reader of request bodies (`body.rs`), the one router behaviour (`router.rs`: 404 for an
//! unknown path, 405 with `Allow` for a wrong method), refusals (`refusal.rs`) and responses
//! (`respond.rs`), and the files served as they are (`static_files.rs`).
//!
//! It does not know sessions, recordings, protocols or participants: the routes are handed to
//! it (a [`listen::Handler`]), and the session and protocol errors become refusals outside it
//! (`serve/refusals.rs`).

pub mod banner;
pub mod body;
pub mod error;
pub mod listen;
pub mod pool;
pub mod refusal;
pub mod respond;
pub mod router;
pub mod static_files;
pub mod tls;
pub mod token;
