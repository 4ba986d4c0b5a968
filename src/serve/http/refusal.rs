//! A request refused: the HTTP status, the reason (one line) and any more fields of its JSON
//! answer. The session and protocol errors become refusals in one place, `serve/refusals.rs`;
//! what this folder refuses by itself (a body too slow or too large, a route that does not
//! exist, a file that is not served) it makes here.

use serde_json::{Map, Value};

/// A request refused: `{"error": reason, …more}` with the status.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct Refusal {
    /// The HTTP status.
    pub status: u16,
    /// Why, one line.
    pub reason: String,
    /// More fields of the answer (`acked`, `code`, `state`, …).
    pub more: Map<String, Value>,
    /// For 405: the methods the path takes, sent as the `Allow` header.
    pub allow: Option<String>,
}

impl Refusal {
    /// A refusal with this status and reason (its line breaks made spaces).
    pub fn new(status: u16, reason: impl Into<String>) -> Refusal {
        Refusal { status, reason: reason.into().replace(['\n', '\r'], " "), more: Map::new(), allow: None }
    }
    /// The same refusal with one more field in its answer.
    pub fn with(mut self, key: &str, value: impl Into<Value>) -> Refusal {
        self.more.insert(key.to_string(), value.into());
        self
    }
    /// 400: the request is malformed or names something that does not exist.
    pub fn bad(reason: impl Into<String>) -> Refusal {
        Refusal::new(400, reason)
    }
    /// 404: nothing there.
    pub fn not_found(reason: impl Into<String>) -> Refusal {
        Refusal::new(404, reason)
    }
    /// 405: the method is not served there.
    pub fn method(reason: impl Into<String>) -> Refusal {
        Refusal::new(405, reason)
    }
    /// 408: the request came too slowly.
    pub fn timeout(reason: impl Into<String>) -> Refusal {
        Refusal::new(408, reason)
    }
    /// 413: over a size limit.
    pub fn too_large(reason: impl Into<String>) -> Refusal {
        Refusal::new(413, reason)
    }
    /// 500: the server failed (a file could not be written).
    pub fn internal(reason: impl Into<String>) -> Refusal {
        Refusal::new(500, reason)
    }
}
