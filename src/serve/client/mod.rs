//! The server's one HTTP client and what uses it: `conn.rs` the client (a keep-alive
//! connection, plain or TLS, the token, every request bounded in time; the Rust tests' requests
//! go through it too), `push.rs` `grove serve push` (a recording streamed as a live client
//! would, reconnecting where the network fails; `source.rs` reads the file's lines), `bench.rs`
//! `grove serve bench` (many sessions at once against a server process of its own or one given by
//! `--to`), `bench_live.rs` how soon the server's live verification reached each checkpoint the
//! bench streamed.
//!
//! It knows the server only by its wire format: the routes, the JSON answers, the states and
//! codes of `sessions/states.rs`, and the TLS set-up of `http/tls.rs`. It does not know how the
//! server checks, stores or verifies a session.

pub mod bench;
pub mod bench_live;
pub mod conn;
pub mod push;
mod source;
