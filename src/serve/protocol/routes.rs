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

use std::sync::Arc;

use http_body_util::BodyExt;
use hyper::body::Incoming;
use hyper::{Method, Request, Response};
use serde_json::{json, Value};

use crate::serve::protocol::participants::{Participants, TaskSessions};
use crate::serve::sessions::registry::Registry;
use crate::serve::http::respond::{full, json, refused, Body};
use crate::serve::app::State;
use crate::serve::Refusal;

/// The largest body of a protocol request (answers included).
const MAX_BODY: usize = 256 * 1024;

struct Ended<'a>(&'a Registry);

impl TaskSessions for Ended<'_> {
    fn ended(&self, participant: &str, task: &str) -> bool {
        self.0.entries().iter().any(|e| e.participant == participant && e.task.as_deref() == Some(task) && (e.state == "ended" || e.state == "abandoned"))
    }
}

/// Whether `path` is one of the protocol's routes.
pub fn is_protocol_path(path: &str) -> bool {
    path == "/protocol" || path == "/dashboard" || path.starts_with("/protocol/") || path == "/api/protocol" || path.starts_with("/api/protocol/") || path == "/api/dashboard"
}

/// Routes a protocol request.
pub async fn route(state: &Arc<State>, req: Request<Incoming>) -> Response<Body> {
    let Some(parts) = state.participants.clone() else {
        return refused(&Refusal::not_found("this server runs no protocol (start it with grove serve --protocol FILE)"), json!({}));
    };
    let path = req.uri().path().to_string();
    let segs: Vec<String> = path.trim_start_matches('/').split('/').map(str::to_string).collect();
    let segs: Vec<&str> = segs.iter().map(|s| s.as_str()).collect();
    let method = req.method().clone();
    let answer: Result<Response<Body>, Refusal> = match (&method, segs.as_slice()) {
        (&Method::GET, ["protocol"]) => Ok(html(crate::serve::protocol::pages::PROTOCOL)),
        (&Method::GET, ["dashboard"]) => Ok(html(crate::serve::protocol::pages::DASHBOARD)),
        (&Method::GET, ["protocol", "media", block, what]) => media(&parts, block, what),
        (&Method::GET, ["api", "protocol"]) => {
            let p = &parts.loaded.protocol;
            Ok(json(200, &json!({"name": p.name, "participants": p.participants, "conditions": p.conditions, "scene": p.scene, "joined": parts.all().len()})))
        }
        (&Method::POST, ["api", "protocol", "participants"]) => match body(state, req).await {
            Ok(v) => {
                let id = v.get("participant").and_then(Value::as_str).map(str::to_string);
                parts.join(id.as_deref()).map(|(v, new)| json(if new { 201 } else { 200 }, &v))
            }
            Err(r) => Err(r),
        },
        (&Method::GET, ["api", "protocol", "participants", id]) => parts.get(id).map(|v| json(200, &v)),
        (&Method::POST, ["api", "protocol", "participants", id, "answers"]) => {
            let id = id.to_string();
            match body(state, req).await {
                Ok(v) => {
                    let step = v.get("step").and_then(Value::as_u64).unwrap_or(0) as usize;
                    match v.get("answers").and_then(Value::as_object) {
                        Some(a) => parts.answer(&id, step, a).map(|v| json(200, &v)),
                        None => Err(Refusal::bad("send {\"step\": N, \"answers\": {ITEM: ANSWER, …}}")),
                    }
                }
                Err(r) => Err(r),
            }
        }
        (&Method::POST, ["api", "protocol", "participants", id, "next"]) => {
            let id = id.to_string();
            match body(state, req).await {
                Ok(v) => match v.get("from").and_then(Value::as_u64) {
                    Some(from) => parts.next(&id, from as usize, &Ended(&state.registry)).map(|v| json(200, &v)),
                    None => Err(Refusal::bad("send {\"from\": N}, the step the participant leaves")),
                },
                Err(r) => Err(r),
            }
        }
        (&Method::GET, ["api", "dashboard"]) => Ok(json(200, &dashboard(state, &parts).await)),
        (_, ["api", "protocol", ..] | ["api", "dashboard"] | ["protocol", ..] | ["dashboard"]) => Err(Refusal::not_found(format!("{method} {path} is not served"))),
        _ => Err(Refusal::not_found(format!("no route {path}"))),
    };
    match answer {
        Ok(r) => r,
        Err(r) => {
            // A page waiting for a task to end asks every two seconds: those answers are not logged.
            let waiting = r.status == 409 && path.ends_with("/next");
            if r.status != 404 && !waiting {
                crate::serve::http::respond::log(&format!("refused {method} {path}: {}", r.reason));
            }
            let more = match (&method, segs.as_slice()) {
                (_, ["api", "protocol", "participants", id, ..]) => parts.get(id).map(|s| json!({"state": s})).unwrap_or(json!({})),
                _ => json!({}),
            };
            refused(&r, more)
        }
    }
}

fn html(page: &'static str) -> Response<Body> {
    let mut r = Response::new(full(page));
    r.headers_mut().insert(hyper::header::CONTENT_TYPE, hyper::header::HeaderValue::from_static("text/html; charset=utf-8"));
    r.headers_mut().insert(hyper::header::CACHE_CONTROL, hyper::header::HeaderValue::from_static("no-store"));
    r
}

fn media(parts: &Participants, block: &str, what: &str) -> Result<Response<Body>, Refusal> {
    let path = parts.media(block, what).ok_or_else(|| Refusal::not_found(format!("block {block} has no {what}")))?;
    let inside = grove_systems::files::within(&path, &parts.loaded.folder).map_err(|e| Refusal::not_found(e.reason()))?;
    let bytes = grove_systems::files::read(&inside, grove_systems::files::Kind::Served).map_err(|e| Refusal::not_found(e.reason()))?;
    let mut r = Response::new(full(bytes));
    if let Ok(v) = hyper::header::HeaderValue::from_str(crate::serve::http::static_files::content_type(&inside)) {
        r.headers_mut().insert(hyper::header::CONTENT_TYPE, v);
    }
    Ok(r)
}

async fn body(state: &Arc<State>, req: Request<Incoming>) -> Result<Value, Refusal> {
    let limited = http_body_util::Limited::new(req.into_body(), MAX_BODY);
    let bytes = match tokio::time::timeout(state.read_timeout, limited.collect()).await {
        Err(_) => return Err(Refusal::timeout("the request body did not arrive in time")),
        Ok(Err(e)) if e.is::<http_body_util::LengthLimitError>() => return Err(Refusal::too_large(format!("the request body is larger than {MAX_BODY} bytes"))),
        Ok(Err(e)) => return Err(Refusal::bad(format!("the request body could not be read: {e}"))),
        Ok(Ok(c)) => c.to_bytes(),
    };
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Ok(json!({}));
    }
    let v: Value = serde_json::from_slice(&bytes).map_err(|e| Refusal::bad(format!("the body is not JSON: {e}")))?;
    if !v.is_object() {
        return Err(Refusal::bad("the body must be a JSON object"));
    }
    Ok(v)
}

/// Every participant (their step), every session (open ones with their live view, ended ones
/// with their verification).
async fn dashboard(state: &Arc<State>, parts: &Participants) -> Value {
    let participants = parts.all();
    let mut sessions = Vec::new();
    for e in state.registry.entries() {
        let mut v = json!({"file": e.file, "participant": e.participant, "task": e.task, "state": e.state, "lines": e.lines, "opened": e.opened, "closed": e.closed, "verification": e.verification});
        let _one_at_a_time = state.live.making.lock().await;
        let live = match state.live.get(&e.file, e.lines) {
            Some(l) => Some(l),
            None if e.state == "open" || state.live.last(&e.file).is_none() => {
                let (path, scratch, banks) = (state.registry.dir.join(&e.file), std::env::temp_dir().join(format!("grove-live-{}", std::process::id())), state.registry.bank_dirs.clone());
                match tokio::task::spawn_blocking(move || crate::serve::protocol::live::view(&path, &scratch, &banks)).await {
                    Ok(Ok(l)) => {
                        state.live.put(&e.file, e.lines, l.clone());
                        Some(l)
                    }
                    Ok(Err(why)) => Some(json!({"error": why})),
                    Err(_) => None,
                }
            }
            None => state.live.last(&e.file),
        };
        v["live"] = live.unwrap_or(Value::Null);
        sessions.push(v);
    }
    json!({"protocol": parts.loaded.protocol.name, "participants": participants, "sessions": sessions})
}
