//! The one reader of a request's body: everything it reads arrives before the read timeout
//! (`--read-timeout`, counted from when reading starts), whole within a size limit or chunk by
//! chunk. What it refuses: 408 (too slow), 413 (too large), 400 (unreadable, not a JSON object).
//!
//! A body its request left unread (refused part of the way: a line over the limit, a body too
//! large) is read on to its end and thrown away, within the same read time and at most
//! [`MAX_DRAIN`] bytes, while the refusal is sent: a client still sending then receives the
//! refusal, where closing the connection under it would reset it and lose the answer.

use std::time::Duration;

use bytes::Bytes;
use http_body_util::BodyExt;
use hyper::body::{Body as _, Incoming};
use serde_json::{Map, Value};

use crate::serve::http::refusal::Refusal;

/// The most bytes of an unread body read on and thrown away after its request was refused.
pub const MAX_DRAIN: usize = 64 << 20;

/// A request's body being read.
pub struct BodyReader {
    /// The body, until its end has been read.
    body: Option<Incoming>,
    timeout: Duration,
    deadline: tokio::time::Instant,
}

impl BodyReader {
    /// Starts reading `body`: all of it must arrive within `timeout` from now.
    pub fn new(body: Incoming, timeout: Duration) -> BodyReader {
        BodyReader { body: Some(body), timeout, deadline: tokio::time::Instant::now() + timeout }
    }

    fn late(&self) -> Refusal {
        Refusal::timeout(format!("the request body did not arrive within {:.1} s", self.timeout.as_secs_f64()))
    }

    /// The next chunk of the body's data (trailers are skipped), or `None` at its end.
    pub async fn chunk(&mut self) -> Result<Option<Bytes>, Refusal> {
        loop {
            let Some(body) = self.body.as_mut() else { return Ok(None) };
            match tokio::time::timeout_at(self.deadline, body.frame()).await {
                Err(_) => return Err(self.late()),
                Ok(None) => {
                    self.body = None;
                    return Ok(None);
                }
                Ok(Some(Err(e))) => return Err(Refusal::bad(format!("the request body could not be read: {e}"))),
                Ok(Some(Ok(frame))) => {
                    if let Ok(data) = frame.into_data() {
                        return Ok(Some(data));
                    }
                }
            }
        }
    }

    /// The whole body, at most `limit` bytes.
    pub async fn whole(mut self, limit: usize) -> Result<Bytes, Refusal> {
        let mut whole = bytes::BytesMut::new();
        while let Some(data) = self.chunk().await? {
            if whole.len() + data.len() > limit {
                return Err(Refusal::too_large(format!("the request body is larger than {limit} bytes")));
            }
            whole.extend_from_slice(&data);
        }
        Ok(whole.freeze())
    }

    /// The whole body as a JSON object, at most `limit` bytes; an empty body (or one of white
    /// space only) is the empty object.
    pub async fn json_object(self, limit: usize) -> Result<Map<String, Value>, Refusal> {
        let bytes = self.whole(limit).await?;
        if bytes.iter().all(u8::is_ascii_whitespace) {
            return Ok(Map::new());
        }
        match serde_json::from_slice(&bytes).map_err(|e| Refusal::bad(format!("the body is not JSON: {e}")))? {
            Value::Object(o) => Ok(o),
            _ => Err(Refusal::bad("the body must be a JSON object")),
        }
    }
}

impl Drop for BodyReader {
    /// Reads an unfinished body on to its end and throws it away (see the module's
    /// documentation), on the runtime, within the read time.
    fn drop(&mut self) {
        let Some(mut body) = self.body.take() else { return };
        let Ok(runtime) = tokio::runtime::Handle::try_current() else { return };
        if body.is_end_stream() {
            return;
        }
        let deadline = self.deadline;
        runtime.spawn(async move {
            let mut left = MAX_DRAIN;
            while let Ok(Some(Ok(frame))) = tokio::time::timeout_at(deadline, body.frame()).await {
                let n = frame.data_ref().map_or(0, Bytes::len);
                if n > left {
                    break;
                }
                left -= n;
            }
        });
    }
}
