//! Responses: a body type for whole buffers and streamed files, JSON answers and refusals, and
//! the server's log line.

use bytes::Bytes;
use http_body_util::{combinators::BoxBody, BodyExt, Full};
use hyper::{Response, StatusCode};

use crate::serve::Refusal;

/// A response body: a whole buffer or a file streamed.
pub type Body = BoxBody<Bytes, std::io::Error>;

/// A whole response body.
pub fn full(bytes: impl Into<Bytes>) -> Body {
    Full::new(bytes.into()).map_err(|never| match never {}).boxed()
}

/// A JSON response.
pub fn json(status: u16, value: &serde_json::Value) -> Response<Body> {
    let mut text = serde_json::to_string(value).unwrap_or_default();
    text.push('\n');
    let mut r = Response::new(full(text));
    *r.status_mut() = StatusCode::from_u16(status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    r.headers_mut().insert(hyper::header::CONTENT_TYPE, hyper::header::HeaderValue::from_static("application/json"));
    r.headers_mut().insert(hyper::header::CACHE_CONTROL, hyper::header::HeaderValue::from_static("no-store"));
    r
}

/// A plain-text answer (200), not cached: a recording's lines, a scene's text.
pub fn text(body: String) -> Response<Body> {
    let mut r = Response::new(full(body));
    r.headers_mut().insert(hyper::header::CONTENT_TYPE, hyper::header::HeaderValue::from_static("text/plain; charset=utf-8"));
    r.headers_mut().insert(hyper::header::CACHE_CONTROL, hyper::header::HeaderValue::from_static("no-store"));
    r
}

/// A refusal as a JSON response `{"error": reason}`, with more fields if given.
pub fn refused(r: &Refusal, more: serde_json::Value) -> Response<Body> {
    let mut v = serde_json::json!({ "error": r.reason });
    if let (Some(obj), serde_json::Value::Object(extra)) = (v.as_object_mut(), more) {
        obj.extend(extra);
    }
    json(r.status, &v)
}

/// Prints one line of the server's log (stdout), prefixed by the time.
pub fn log(line: &str) {
    println!("{} {line}", chrono::DateTime::<chrono::Utc>::from(std::time::SystemTime::now()).format("%H:%M:%S"));
}

