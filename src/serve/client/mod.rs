//! The server's HTTP client and what uses it: `grove serve push` and `grove serve bench`.

pub mod bench;
pub mod conn;
pub mod push;
