//! Responses: a body type for whole buffers and streamed files, JSON, text and HTML answers, and
//! a refusal as its JSON answer.

use bytes::Bytes;
use http_body_util::{combinators::BoxBody, BodyExt, Full};
use hyper::header::{HeaderValue, ALLOW, CACHE_CONTROL, CONTENT_TYPE};
use hyper::{Response, StatusCode};

use crate::serve::http::refusal::Refusal;

/// A response body: a whole buffer or a file streamed.
pub type Body = BoxBody<Bytes, std::io::Error>;

/// A whole response body.
pub fn full(bytes: impl Into<Bytes>) -> Body {
    Full::new(bytes.into()).map_err(|never| match never {}).boxed()
}

/// A whole answer with this content type, not cached.
fn uncached(status: u16, body: impl Into<Bytes>, content_type: &'static str) -> Response<Body> {
    let mut r = Response::new(full(body));
    *r.status_mut() = StatusCode::from_u16(status).unwrap_or(StatusCode::INTERNAL_SERVER_ERROR);
    r.headers_mut().insert(CONTENT_TYPE, HeaderValue::from_static(content_type));
    r.headers_mut().insert(CACHE_CONTROL, HeaderValue::from_static("no-store"));
    r
}

/// A JSON response.
pub fn json(status: u16, value: &serde_json::Value) -> Response<Body> {
    let mut text = serde_json::to_string(value).unwrap_or_default();
    text.push('\n');
    uncached(status, text, "application/json")
}

/// A plain-text answer (200), not cached: a recording's lines, a scene's text.
pub fn text(body: String) -> Response<Body> {
    uncached(200, body, "text/plain; charset=utf-8")
}

/// An HTML page (200), not cached.
pub fn html(page: impl Into<Bytes>) -> Response<Body> {
    uncached(200, page, "text/html; charset=utf-8")
}

/// A refusal as a JSON response `{"error": reason, …}` with its more fields, and for 405 the
/// `Allow` header.
pub fn refused(r: &Refusal) -> Response<Body> {
    let mut v = serde_json::Map::new();
    v.insert("error".into(), r.reason.clone().into());
    v.extend(r.more.clone());
    let mut response = json(r.status, &serde_json::Value::Object(v));
    if let Some(allow) = r.allow.as_deref().and_then(|a| HeaderValue::from_str(a).ok()) {
        response.headers_mut().insert(ALLOW, allow);
    }
    response
}
