//! The routes of a protocol run by `grove serve --protocol` (`docs/protocol.md`):
//!
//! - `GET /api/protocol`: the protocol's name, conditions and participants so far;
//! - `POST /api/protocol/participants`: a new participant (`{}`), or back to one (`{"participant": ID}`);
//! - `GET /api/protocol/participants/ID`: where they are, every step described;
//! - `POST /api/protocol/participants/ID/answers`: `{"step": N, "answers": {ITEM: ANSWER, …}}`,
//!   every answer checked against its item before any is written (422 with the reason);
//! - `POST /api/protocol/participants/ID/next`: `{"from": N}`, on to the next step once this one
//!   is finished (409 with the reason otherwise);
//! - `GET /api/dashboard`: every participant and session, with the live view of open sessions;
//! - `GET /protocol`, `GET /dashboard`: the participant's form page and the researcher's page;
//!   `GET /protocol/media/BLOCK/image|video`: an instruction block's file.

use hyper::body::Incoming;
use hyper::{Method, Request, Response};
use serde_json::{json, Value};

use crate::serve::http::body::BodyReader;
use crate::serve::http::refusal::Refusal;
use crate::serve::http::respond::{full, html, json, refused, Body};
use crate::serve::http::router::{find, Route};
use crate::serve::log::log;
use crate::serve::protocol::dashboard::dashboard;
use crate::serve::protocol::error::ParticipantError;
use crate::serve::protocol::pages::{DASHBOARD, PROTOCOL};
use crate::serve::protocol::participants::Participants;
use crate::serve::protocol::Protocol;

/// The largest body of a protocol request (answers included).
const MAX_BODY: usize = 256 * 1024;

#[derive(Clone, Copy, PartialEq)]
enum To {
    FormPage,
    DashboardPage,
    Media,
    Info,
    Join,
    Participant,
    Answers,
    Next,
    Dashboard,
}

fn routes() -> [Route<To>; 9] {
    [
        Route { method: Method::GET, path: "/protocol", to: To::FormPage },
        Route { method: Method::GET, path: "/dashboard", to: To::DashboardPage },
        Route { method: Method::GET, path: "/protocol/media/{block}/{what}", to: To::Media },
        Route { method: Method::GET, path: "/api/protocol", to: To::Info },
        Route { method: Method::POST, path: "/api/protocol/participants", to: To::Join },
        Route { method: Method::GET, path: "/api/protocol/participants/{id}", to: To::Participant },
        Route { method: Method::POST, path: "/api/protocol/participants/{id}/answers", to: To::Answers },
        Route { method: Method::POST, path: "/api/protocol/participants/{id}/next", to: To::Next },
        Route { method: Method::GET, path: "/api/dashboard", to: To::Dashboard },
    ]
}

/// Whether `path` is one of the protocol's.
pub fn serves(path: &str) -> bool {
    path == "/protocol" || path == "/dashboard" || path.starts_with("/protocol/") || path == "/api/protocol" || path.starts_with("/api/protocol/") || path == "/api/dashboard"
}

/// Routes a protocol request (`protocol`: the protocol the server runs, if any).
pub async fn route(protocol: Option<&Protocol>, req: Request<Incoming>) -> Response<Body> {
    let Some(protocol) = protocol else {
        return refused(&Refusal::from(ParticipantError::NoProtocol));
    };
    let (method, path) = (req.method().clone(), req.uri().path().to_string());
    let (to, captured) = match find(&routes(), &method, &path) {
        Ok(found) => found,
        Err(miss) => return refused(&miss),
    };
    let parts = &protocol.participants;
    // The pattern's `{…}` parts: the participant's id, or the block and what of it.
    let id = captured.first().copied().unwrap_or_default();
    let answer = match to {
        To::FormPage => Ok(html(PROTOCOL)),
        To::DashboardPage => Ok(html(DASHBOARD)),
        To::Media => media(parts, id, captured.get(1).copied().unwrap_or_default()),
        To::Info => {
            let p = &parts.loaded.protocol;
            Ok(json(200, &json!({"name": p.name, "participants": p.participants, "conditions": p.conditions, "scene": p.scene, "joined": parts.all().len()})))
        }
        To::Join => match body(protocol, req).await {
            Ok(v) => joining(&v).and_then(|named| parts.join(named, protocol.sessions.as_ref())).map(|(v, new)| json(if new { 201 } else { 200 }, &v)),
            Err(e) => Err(e),
        },
        To::Participant => parts.get(id).map(|v| json(200, &v)),
        To::Answers => match body(protocol, req).await {
            Ok(v) => step_of(&v, "step").and_then(|step| match v.get("answers").and_then(Value::as_object) {
                Some(a) => parts.answer(id, step, a).map(|v| json(200, &v)),
                None => Err(ParticipantError::AnswersShape),
            }),
            Err(e) => Err(e),
        },
        To::Next => match body(protocol, req).await {
            Ok(v) if !v.contains_key("from") => Err(ParticipantError::FromShape),
            Ok(v) => step_of(&v, "from").and_then(|from| parts.next(id, from, protocol.sessions.as_ref())).map(|v| json(200, &v)),
            Err(e) => Err(e),
        },
        To::Dashboard => Ok(json(200, &dashboard(protocol).await)),
    };
    match answer {
        Ok(r) => r,
        Err(e) => {
            let mut r = Refusal::from(e);
            // A page waiting for a task to end asks every two seconds: those answers are not logged.
            let waiting = r.status == 409 && to == To::Next;
            if r.status != 404 && !waiting {
                log(&format!("refused {method} {path}: {}", r.reason));
            }
            // A participant's request is answered with where they are.
            if matches!(to, To::Participant | To::Answers | To::Next)
                && let Ok(state) = parts.get(id)
            {
                r = r.with("state", state);
            }
            refused(&r)
        }
    }
}

fn media(parts: &Participants, block: &str, what: &str) -> Result<Response<Body>, ParticipantError> {
    let path = parts.media(block, what).ok_or_else(|| ParticipantError::NoMedia { block: block.to_string(), what: what.to_string() })?;
    let unserved = |e: grove_systems::files::FileError| ParticipantError::Media(format!("block {block}'s {what}: {}", e.public_reason()));
    let inside = grove_systems::files::within(&path, &parts.loaded.folder).map_err(unserved)?;
    let bytes = grove_systems::files::read(&inside, grove_systems::files::Kind::Served).map_err(unserved)?;
    let mut r = Response::new(full(bytes));
    if let Ok(v) = hyper::header::HeaderValue::from_str(crate::serve::http::static_files::content_type(&inside)) {
        r.headers_mut().insert(hyper::header::CONTENT_TYPE, v);
    }
    Ok(r)
}

/// The id a join request names: none (`{}`), or a string (`{"participant": "P07"}`); anything
/// else is refused.
fn joining(v: &serde_json::Map<String, Value>) -> Result<Option<&str>, ParticipantError> {
    if let Some(other) = v.keys().find(|k| *k != "participant") {
        return Err(ParticipantError::JoinShape(other.chars().take(40).collect()));
    }
    match v.get("participant") {
        None => Ok(None),
        Some(Value::String(id)) => Ok(Some(id)),
        Some(other) => Err(ParticipantError::IdNotText(sent(other))),
    }
}

/// A step a request names (`step`, `from`): a whole number from 1.
fn step_of(v: &serde_json::Map<String, Value>, field: &'static str) -> Result<usize, ParticipantError> {
    match v.get(field).and_then(Value::as_u64) {
        Some(n) if n >= 1 => Ok(n as usize),
        _ => Err(ParticipantError::StepNotNumber { field, sent: v.get(field).map_or_else(|| "nothing".into(), sent) }),
    }
}

/// A value as the request sent it, as JSON, cut short.
fn sent(v: &Value) -> String {
    let text = v.to_string();
    if text.chars().count() > 40 { format!("{}…", text.chars().take(40).collect::<String>()) } else { text }
}

/// The request's body, a JSON object (an empty body is `{}`).
async fn body(protocol: &Protocol, req: Request<Incoming>) -> Result<serde_json::Map<String, Value>, ParticipantError> {
    Ok(BodyReader::new(req.into_body(), protocol.sessions.read_timeout).json_object(MAX_BODY).await?)
}
