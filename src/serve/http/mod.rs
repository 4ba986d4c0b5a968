//! HTTP: connections, TLS, the token, responses and the files served as they are.

pub mod banner;
pub mod listen;
pub mod respond;
pub mod static_files;
pub mod tls;
