//! The session routes (`docs/serve.md` lists them):
//!
//! - `POST /api/sessions` opens a session, from a header line (`{"header": "…"}`) or from the
//!   fields a client may set (`{"participant": …, "task": …, "scene": …, "seed": …,
//!   "technique": …, "block": …, "scene_text": …, "device": …}`); the answer has the session id and the header line written.
//!   With `"continue": true` beside a header line, the session that the same line opened before
//!   is answered instead (200, `"continued": true`): how `grove serve push` run again goes on.
//! - `POST /api/sessions/ID/lines?from=N` appends lines (the body, each ending in `\n`) starting
//!   at line N of the file; each line is checked, written, and the answer's `acked` is the number
//!   of lines now in the file. A refused line ends the request with its reason and the `acked`
//!   count: nothing past the last good line is written.
//! - `GET /api/sessions` lists the sessions (without their ids).
//! - `GET /api/sessions/ID` says how many lines the file has (where a reconnecting client goes
//!   on from), at once, even while another request on the session is in progress; `POST /api/sessions/ID/end` ends the session and answers with its verification.
//! - `GET /api/sessions/ID/lines` is the open session's file as acknowledged (a reloaded page
//!   re-simulates it to go on where it stopped); `GET /api/sessions/ID/scene` the text of the
//!   scene file its header names (a room a page built, [`crate::serve::sessions::room_scene`]).
//!
//! Every session request names its client in the header `Grove-Writer`: while one client writes
//! a session, another is refused until the first has made no request for the writer lease.

use std::sync::Arc;
use std::time::Instant;

use grove_systems::limits::MAX_LINE_BYTES;
use grove_systems::replay::{encode_line, Line};
use hyper::body::Incoming;
use hyper::header::HeaderMap;
use hyper::{Method, Request, Response};
use serde_json::{json, Value};

use crate::serve::http::body::BodyReader;
use crate::serve::http::refusal::Refusal;
use crate::serve::http::respond::{json, refused, text, Body};
use crate::serve::http::router::{find, Route};
use crate::serve::line_split::{LineSplitter, SplitError};
use crate::serve::log::log;
use crate::serve::sessions::error::SessionError;
use crate::serve::sessions::registry::{Entry, OpenWith, Opened};
use crate::serve::sessions::service::Sessions;
use crate::serve::sessions::session::{header_from_fields, OpenFields};
use crate::serve::sessions::states::SessionState;

/// The largest body of a request other than lines (an open request carries a header line).
const MAX_JSON_BODY: usize = 2 * MAX_LINE_BYTES + 4096;

#[derive(Clone, Copy)]
enum To {
    List,
    Open,
    Status,
    Append,
    Lines,
    Scene,
    End,
}

/// The routes under `/api/sessions`.
fn routes() -> [Route<To>; 7] {
    [
        Route { method: Method::GET, path: "/api/sessions", to: To::List },
        Route { method: Method::POST, path: "/api/sessions", to: To::Open },
        Route { method: Method::GET, path: "/api/sessions/{id}", to: To::Status },
        Route { method: Method::POST, path: "/api/sessions/{id}/lines", to: To::Append },
        Route { method: Method::GET, path: "/api/sessions/{id}/lines", to: To::Lines },
        Route { method: Method::GET, path: "/api/sessions/{id}/scene", to: To::Scene },
        Route { method: Method::POST, path: "/api/sessions/{id}/end", to: To::End },
    ]
}

/// Whether `path` is under `/api/sessions`.
pub fn serves(path: &str) -> bool {
    path == "/api/sessions" || path.starts_with("/api/sessions/")
}

/// Routes a request under `/api/sessions`.
pub async fn route(sessions: &Arc<Sessions>, req: Request<Incoming>) -> Response<Body> {
    let path = req.uri().path().to_string();
    let (to, ids) = match find(&routes(), req.method(), &path) {
        Ok(found) => found,
        Err(miss) => return refused(&miss),
    };
    let id = ids.first().copied().unwrap_or_default();
    let answer = match to {
        To::List => Ok(json(200, &json!({ "sessions": sessions.registry.entries().iter().map(|e| public(sessions, e)).collect::<Vec<_>>() }))),
        To::Open => open(sessions, req).await,
        To::Status => status(sessions, id).await,
        To::Append => append(sessions, id, req).await,
        To::Lines => read_back(sessions, id, false).await,
        To::Scene => read_back(sessions, id, true).await,
        To::End => end(sessions, id, req).await,
    };
    answer.unwrap_or_else(|e| refused(&Refusal::from(e)))
}

/// An entry without its id (a secret), as listed to any client with the token; an open
/// session's with its verification so far (`live`).
fn public(sessions: &Sessions, e: &Entry) -> Value {
    let live = if e.state == SessionState::Open { sessions.live.verification(&e.id) } else { None };
    json!({ "file": e.file, "participant": e.participant, "task": e.task, "opened": e.opened, "state": e.state, "lines": e.lines, "closed": e.closed, "verification": e.verification, "live": live, "note": e.note })
}

/// The client a request names (`Grove-Writer`: 1 to 64 letters, digits, `-` or `_`).
fn writer_of(headers: &HeaderMap, request: &'static str) -> Result<String, SessionError> {
    let v = headers.get("grove-writer").ok_or(SessionError::NoWriter { request })?;
    let w = v.to_str().unwrap_or("");
    if w.is_empty() || w.len() > 64 || !w.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_') {
        return Err(SessionError::BadWriter);
    }
    Ok(w.to_string())
}

async fn open(sessions: &Arc<Sessions>, req: Request<Incoming>) -> Result<Response<Body>, SessionError> {
    let (head, body) = req.into_parts();
    let body = BodyReader::new(body, sessions.read_timeout);
    let writer = writer_of(&head.headers, "an open request")?;
    let mut body = body.json_object(MAX_JSON_BODY).await?;
    let continuing = match body.remove("continue") {
        None => None,
        Some(Value::Bool(b)) => Some(b),
        Some(_) => return Err(SessionError::ContinueNotBool),
    };
    let (header_text, with) = if body.contains_key("header") {
        if body.len() != 1 {
            return Err(SessionError::HeaderAndFields);
        }
        let with = if continuing == Some(true) { OpenWith::LineContinuing } else { OpenWith::Line };
        (body["header"].as_str().ok_or(SessionError::HeaderNotText)?.to_string(), with)
    } else {
        if continuing.is_some() {
            return Err(SessionError::ContinueWithFields);
        }
        let fields: OpenFields = serde_json::from_value(Value::Object(body)).map_err(|e| SessionError::Fields(e.to_string()))?;
        (encode_line(&Line::Header(header_from_fields(&fields, &sessions.registry.dir)?)), OpenWith::Fields)
    };
    let (all, text) = (sessions.clone(), header_text.clone());
    let opened = tokio::task::spawn_blocking(move || all.registry.open(&text, with)).await.map_err(|e| SessionError::Task(e.to_string()))?;
    match opened.inspect_err(|e| log(&format!("refused a session: {e}")))? {
        Opened::New(entry, shared) => {
            {
                let mut s = shared.lock().await;
                s.writer = Some(writer);
                sessions.live.watch(&s.id, &s.path, s.bytes());
            }
            log(&format!("opened {} (participant {}, task {})", entry.file, entry.participant, entry.task.as_deref().unwrap_or("none")));
            Ok(json(201, &json!({ "session": entry.id, "file": entry.file, "header": header_text, "acked": 1 })))
        }
        Opened::Found(entry, Some(shared)) => {
            let s = sessions.take(shared, &writer)?;
            let acked = s.acked();
            drop(s);
            log(&format!("continuing {} for the same recording pushed again ({acked} lines)", entry.file));
            Ok(json(200, &json!({ "session": entry.id, "file": entry.file, "header": header_text, "acked": acked, "state": SessionState::Open, "continued": true })))
        }
        Opened::Found(entry, None) => {
            let found = json!({ "session": entry.id, "file": entry.file, "header": header_text, "acked": entry.lines, "state": entry.state, "verification": entry.verification, "continued": true });
            Ok(json(200, &found))
        }
    }
}

async fn status(sessions: &Sessions, id: &str) -> Result<Response<Body>, SessionError> {
    let shared = match sessions.find(id) {
        Ok(s) => s,
        // An ended session's status is its entry, not a refusal.
        Err(gone @ SessionError::Gone { .. }) => return Ok(json(200, &Value::Object(Refusal::from(gone).more))),
        Err(e) => return Err(e),
    };
    // Never waiting for a request in progress on the session: its lines are counted in the
    // session's entry as they are written.
    let (acked, ended, file) = match shared.try_lock() {
        Ok(s) => (s.acked(), s.ended, s.file_name.clone()),
        Err(_) => match sessions.registry.entry(id) {
            Some(e) => (e.lines, e.state != SessionState::Open, e.file),
            None => return Err(SessionError::NoSuchSession),
        },
    };
    let state = if ended { SessionState::Ended } else { SessionState::Open };
    Ok(json(200, &json!({ "acked": acked, "state": state, "file": file })))
}

/// An open session's file as acknowledged (its first `acked` lines), or, with `scene`, the text
/// of the scene file its header names. Reading takes no writer lease: whoever has the id may
/// read what it may write.
async fn read_back(sessions: &Sessions, id: &str, scene: bool) -> Result<Response<Body>, SessionError> {
    let shared = sessions.find(id)?;
    let (path, acked, scene_name) = {
        let s = sessions.read(&shared).await?;
        (s.path.clone(), s.acked(), s.header.scene.clone())
    };
    let dir = sessions.registry.dir.clone();
    let read = tokio::task::spawn_blocking(move || -> Result<String, SessionError> {
        use grove_systems::files::{read_text, Kind};
        let unreadable = |e: grove_systems::files::FileError| SessionError::Read(e.reason());
        if scene {
            if grove_systems::scene::Scene::builtin(&scene_name).is_some() {
                return Err(SessionError::BuiltinScene(scene_name));
            }
            // Where the replay looks: the recordings' folder, then the working directory.
            let cwd = std::env::current_dir().unwrap_or_default();
            let path = [&dir, &cwd].into_iter().find_map(|base| grove_systems::files::within(&base.join(&scene_name), base).ok());
            let path = path.ok_or(SessionError::NoSceneFile(scene_name))?;
            return read_text(&path, Kind::Scene).map_err(unreadable);
        }
        let all = read_text(&path, Kind::Recording).map_err(unreadable)?;
        // Lines are only appended, so the first `acked` ones are as acknowledged even while a
        // later request writes more.
        let end = all.match_indices('\n').nth(acked.saturating_sub(1) as usize).map_or(all.len(), |(i, _)| i + 1);
        Ok(all[..end].to_string())
    });
    Ok(text(read.await.map_err(|e| SessionError::Task(e.to_string()))??))
}

fn query_from(uri: &hyper::Uri) -> Option<u64> {
    uri.query()?.split('&').find_map(|p| p.strip_prefix("from=")).and_then(|v| v.parse().ok())
}

async fn append(sessions: &Sessions, id: &str, req: Request<Incoming>) -> Result<Response<Body>, SessionError> {
    let (head, body) = req.into_parts();
    let mut body = BodyReader::new(body, sessions.read_timeout);
    let writer = writer_of(&head.headers, "a lines request")?;
    let from = query_from(&head.uri).ok_or(SessionError::NoFrom)?;
    let shared = sessions.find(id)?;
    let mut s = sessions.take(shared, &writer)?;
    if from != s.acked() + 1 {
        return Err(SessionError::Gap { acked: s.acked() });
    }
    let first = s.acked();
    let mut splitter = LineSplitter::new(MAX_LINE_BYTES);
    let mut stop: Option<SessionError> = None;
    while stop.is_none() {
        let data = match body.chunk().await {
            Ok(Some(data)) => data,
            Ok(None) => break,
            Err(r) => {
                stop = Some(r.into());
                break;
            }
        };
        let mut bad_line = None;
        let split = splitter.push(&data, &mut |text| match s.take(text) {
            Ok(()) => true,
            Err(why) => {
                bad_line = Some(why);
                false
            }
        });
        stop = bad_line.or(match split {
            Err(SplitError::TooLong { number, limit }) => Some(SessionError::LineTooLong { number: first + number, limit }),
            Err(SplitError::NotUtf8 { number }) => Some(SessionError::NotUtf8 { number: first + number }),
            Ok(_) => None,
        });
        if let Err(e) = s.write_out() {
            stop = Some(e);
        }
        sessions.registry.note_lines(&s.id, s.acked());
    }
    if stop.is_none() && !splitter.rest().is_empty() {
        stop = Some(SessionError::NoNewline { number: s.acked() + 1 });
    }
    if let Err(e) = s.write_out() {
        stop = Some(e);
    }
    s.last_seen = Instant::now();
    let acked = s.acked();
    sessions.registry.note_lines(&s.id, acked);
    sessions.live.grown(&s.id, s.bytes());
    match stop {
        Some(cause) => {
            log(&format!("refused a line of {}: {cause}", s.file_name));
            Err(SessionError::Stopped { acked, cause: Box::new(cause) })
        }
        None => Ok(json(200, &json!({ "acked": acked }))),
    }
}

async fn end(sessions: &Sessions, id: &str, req: Request<Incoming>) -> Result<Response<Body>, SessionError> {
    let writer = writer_of(req.headers(), "an end request")?;
    let shared = sessions.find(id)?;
    let s = sessions.take(shared, &writer)?;
    Ok(json(200, &sessions.close_and_verify(s, SessionState::Ended).await?))
}
