//! The session routes (`docs/serve.md` lists them):
//!
//! - `POST /api/sessions` opens a session, from a header line (`{"header": "…"}`) or from the
//!   fields a client may set (`{"participant": …, "task": …, "scene": …, "seed": …,
//!   "technique": …, "block": …, "scene_text": …, "device": …}`); the answer has the session id and the header line written.
//! - `POST /api/sessions/ID/lines?from=N` appends lines (the body, each ending in `\n`) starting
//!   at line N of the file; each line is checked, written, and the answer's `acked` is the number
//!   of lines now in the file. A refused line ends the request with its reason and the `acked`
//!   count: nothing past the last good line is written.
//! - `GET /api/status` names the server; `GET /api/index` lists the files it serves; `GET
//!   /api/sessions` lists the sessions (without their ids).
//! - `GET /api/sessions/ID` says how many lines the file has (where a reconnecting client goes
//!   on from); `POST /api/sessions/ID/end` ends the session and answers with its verification.
//! - `GET /api/sessions/ID/lines` is the open session's file as acknowledged (a reloaded page
//!   re-simulates it to go on where it stopped); `GET /api/sessions/ID/scene` the text of the
//!   scene file its header names (a room a page built, [`super::room_scene`]).
//!
//! Every session request names its client in the header `Grove-Writer`: while one client writes
//! a session, another is refused until the first has made no request for the writer lease.

use std::sync::Arc;
use std::time::{Duration, Instant};

use grove_systems::limits::MAX_LINE_BYTES;
use grove_systems::replay::{encode_line, Line};
use http_body_util::BodyExt;
use hyper::body::Incoming;
use hyper::{Method, Request, Response};
use serde_json::json;

use super::respond::{json, log, refused, text, Body};
use super::state::State;
use super::line_split::{LineSplitter, SplitError};
use super::registry::{Entry, Registry, Shared};
use super::session::{header_from_fields, OpenFields, Session};
use super::verify::{verify, Verification};
use super::{ids, Refusal};

/// The largest body of a request other than lines (an open request carries a header line).
const MAX_JSON_BODY: usize = 2 * MAX_LINE_BYTES + 4096;

/// Routes `/api/…`.
pub async fn route(state: &Arc<State>, req: Request<Incoming>) -> Response<Body> {
    let path = req.uri().path().to_string();
    let parts: Vec<&str> = path.trim_start_matches('/').split('/').collect();
    let method = req.method().clone();
    let result = match (&method, parts.as_slice()) {
        (&Method::GET, ["api", "status"]) => Ok(status(state)),
        (&Method::GET, ["api", "index"]) => Ok(json(200, &state.statics.index())),
        (&Method::GET, ["api", "sessions"]) => Ok(json(200, &json!({ "sessions": state.registry.entries().iter().map(public).collect::<Vec<_>>() }))),
        (&Method::POST, ["api", "sessions"]) => open(state, req).await,
        (&Method::GET, ["api", "sessions", id]) => session_status(state, id).await,
        (&Method::POST, ["api", "sessions", id, "lines"]) => append(state, id, req).await,
        (&Method::GET, ["api", "sessions", id, "lines"]) => read_back(state, id, false).await,
        (&Method::GET, ["api", "sessions", id, "scene"]) => read_back(state, id, true).await,
        (&Method::POST, ["api", "sessions", id, "end"]) => end(state, id, req).await,
        (_, ["api", "status"] | ["api", "index"] | ["api", "sessions"] | ["api", "sessions", _] | ["api", "sessions", _, "lines" | "end" | "scene"]) => {
            Err((Refusal::method(format!("{method} is not served at {path}")), json!({})))
        }
        _ => Err((Refusal::not_found(format!("no API route {path}")), json!({}))),
    };
    match result {
        Ok(r) => r,
        Err((r, more)) => refused(&r, more),
    }
}

type Answer = Result<Response<Body>, (Refusal, serde_json::Value)>;

fn no_more(r: Refusal) -> (Refusal, serde_json::Value) {
    (r, json!({}))
}

/// An entry without its id (a secret), as listed to any client with the token.
fn public(e: &Entry) -> serde_json::Value {
    json!({ "file": e.file, "participant": e.participant, "task": e.task, "opened": e.opened, "state": e.state, "lines": e.lines, "closed": e.closed, "verification": e.verification, "note": e.note })
}

fn status(state: &Arc<State>) -> Response<Body> {
    // `protocol`: the name of the protocol the server runs (the headset page then follows it), or null.
    let protocol = state.participants.as_ref().map(|p| p.loaded.protocol.name.clone());
    json(200, &json!({ "server": "grove serve", "version": env!("CARGO_PKG_VERSION"), "open_sessions": state.registry.open_sessions().len(), "tls": state.tls, "protocol": protocol }))
}

/// Reads a whole small body within the read timeout.
async fn small_body(state: &Arc<State>, req: Request<Incoming>) -> Result<Vec<u8>, Refusal> {
    let limited = http_body_util::Limited::new(req.into_body(), MAX_JSON_BODY);
    match tokio::time::timeout(state.read_timeout, limited.collect()).await {
        Err(_) => Err(Refusal::timeout(format!("the request body did not arrive within {:.1} s", state.read_timeout.as_secs_f64()))),
        Ok(Err(e)) if e.is::<http_body_util::LengthLimitError>() => Err(Refusal::too_large(format!("the request body is larger than {MAX_JSON_BODY} bytes"))),
        Ok(Err(e)) => Err(Refusal::bad(format!("the request body could not be read: {e}"))),
        Ok(Ok(c)) => Ok(c.to_bytes().to_vec()),
    }
}

/// The client a request names (`Grove-Writer`: 1 to 64 letters, digits, `-` or `_`).
fn writer_of(req: &Request<Incoming>) -> Result<Option<String>, Refusal> {
    match req.headers().get("grove-writer") {
        None => Ok(None),
        Some(v) => {
            let w = v.to_str().unwrap_or("");
            if w.is_empty() || w.len() > 64 || !w.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_') {
                return Err(Refusal::bad("the Grove-Writer header must be 1 to 64 letters, digits, '-' or '_'"));
            }
            Ok(Some(w.to_string()))
        }
    }
}

async fn open(state: &Arc<State>, req: Request<Incoming>) -> Answer {
    let writer = writer_of(&req).map_err(no_more)?;
    let body = small_body(state, req).await.map_err(no_more)?;
    let value: serde_json::Value = serde_json::from_slice(&body).map_err(|e| no_more(Refusal::bad(format!("the body is not JSON: {e}"))))?;
    let header_text = match value.as_object() {
        Some(o) if o.contains_key("header") => {
            if o.len() != 1 {
                return Err(no_more(Refusal::bad("an open request with a header line has no other field")));
            }
            o["header"].as_str().ok_or_else(|| no_more(Refusal::bad("'header' must be the header line, a string")))?.to_string()
        }
        _ => {
            let fields: OpenFields = serde_json::from_value(value).map_err(|e| no_more(Refusal::bad(format!("open request: {e}"))))?;
            let header = header_from_fields(&fields, &state.registry.dir).map_err(no_more)?;
            encode_line(&Line::Header(header))
        }
    };
    let st = state.clone();
    let text = header_text.clone();
    let opened = tokio::task::spawn_blocking(move || st.registry.open(&text)).await.map_err(|e| no_more(Refusal::internal(e.to_string())))?;
    let (entry, shared) = match opened {
        Ok(o) => o,
        Err(r) => {
            log(&format!("refused a session: {}", r.reason));
            return Err(no_more(r));
        }
    };
    shared.lock().await.writer = writer;
    log(&format!("opened {} (participant {}, task {})", entry.file, entry.participant, entry.task.as_deref().unwrap_or("none")));
    Ok(json(201, &json!({ "session": entry.id, "file": entry.file, "header": header_text, "acked": 1 })))
}

/// The open session `id`, or why there is none.
fn find(state: &Arc<State>, id: &str) -> Result<Shared, (Refusal, serde_json::Value)> {
    if !ids::is_session_id(id) {
        return Err(no_more(Refusal::not_found("no such session")));
    }
    match state.registry.get(id) {
        Some(s) => Ok(s),
        None => match state.registry.entry(id) {
            Some(e) => Err((Refusal::gone(format!("session {} is {}", e.file, e.state)), json!({ "acked": e.lines, "state": e.state, "verification": e.verification }))),
            None => Err(no_more(Refusal::not_found("no such session"))),
        },
    }
}

async fn session_status(state: &Arc<State>, id: &str) -> Answer {
    let shared = match find(state, id) {
        Ok(s) => s,
        // An ended session's status is its entry, not a refusal.
        Err((r, more)) if r.status == 410 => return Ok(json(200, &more)),
        Err(e) => return Err(e),
    };
    let s = match tokio::time::timeout(state.read_timeout + Duration::from_secs(1), shared.lock()).await {
        Ok(s) => s,
        Err(_) => return Err((Refusal::conflict("the session is busy with another request; ask again"), json!({ "code": "busy" }))),
    };
    Ok(json(200, &json!({ "acked": s.acked(), "state": if s.ended { "ended" } else { "open" }, "file": s.file_name })))
}

/// An open session's file as acknowledged (its first `acked` lines), or, with `scene`, the text
/// of the scene file its header names. Reading takes no writer lease: whoever has the id may
/// read what it may write.
async fn read_back(state: &Arc<State>, id: &str, scene: bool) -> Answer {
    let shared = find(state, id)?;
    let (path, acked, scene_name) = match tokio::time::timeout(state.read_timeout + Duration::from_secs(1), shared.lock()).await {
        Ok(s) => (s.path.clone(), s.acked(), s.header.scene.clone()),
        Err(_) => return Err((Refusal::conflict("the session is busy with another request; ask again"), json!({ "code": "busy" }))),
    };
    let dir = state.registry.dir.clone();
    let read = tokio::task::spawn_blocking(move || -> Result<String, Refusal> {
        use grove_systems::files::{read_text, Kind};
        if scene {
            if grove_systems::scene::Scene::builtin(&scene_name).is_some() {
                return Err(Refusal::not_found(format!("the session's scene is the built-in scene {scene_name:?}, not a file")));
            }
            // Where the replay looks: the recordings' folder, then the working directory.
            let cwd = std::env::current_dir().unwrap_or_default();
            let path = [&dir, &cwd].into_iter().find_map(|base| grove_systems::files::within(&base.join(&scene_name), base).ok());
            let path = path.ok_or_else(|| Refusal::not_found(format!("the session's scene file {scene_name:?} is not in the sessions' folder or the working directory")))?;
            return read_text(&path, Kind::Scene).map_err(|e| Refusal::internal(e.reason()));
        }
        let all = read_text(&path, Kind::Recording).map_err(|e| Refusal::internal(e.reason()))?;
        // Lines are only appended, so the first `acked` ones are as acknowledged even while a
        // later request writes more.
        let end = all.match_indices('\n').nth(acked.saturating_sub(1) as usize).map_or(all.len(), |(i, _)| i + 1);
        Ok(all[..end].to_string())
    });
    let body = read.await.map_err(|e| no_more(Refusal::internal(e.to_string())))?.map_err(no_more)?;
    Ok(text(body))
}

/// Takes the session for one request of `writer`: refused while another request on it is in
/// progress, or while another writer holds it.
fn take_session(state: &Arc<State>, shared: Shared, writer: &str) -> Result<tokio::sync::OwnedMutexGuard<Session>, (Refusal, serde_json::Value)> {
    let mut s = shared.try_lock_owned().map_err(|_| (Refusal::conflict("another request on this session is in progress; try again when it is answered"), json!({ "code": "busy" })))?;
    if s.ended {
        return Err(no_more(Refusal::gone("the session has ended")));
    }
    if let Some(why) = &s.broken {
        return Err((Refusal::internal(why.clone()), json!({ "acked": s.acked() })));
    }
    let idle = s.last_seen.elapsed();
    if let Some(w) = &s.writer
        && w != writer
        && idle < state.writer_lease
    {
        return Err((
            Refusal::conflict(format!(
                "session {} is being written by another client (its last request {:.1} s ago); another client may take it over after {:.0} s without requests",
                s.file_name,
                idle.as_secs_f64(),
                state.writer_lease.as_secs_f64()
            )),
            json!({ "acked": s.acked(), "code": "writer" }),
        ));
    }
    s.writer = Some(writer.to_string());
    s.last_seen = Instant::now();
    Ok(s)
}

fn query_from(req: &Request<Incoming>) -> Option<u64> {
    req.uri().query()?.split('&').find_map(|p| p.strip_prefix("from=")).and_then(|v| v.parse().ok())
}

async fn append(state: &Arc<State>, id: &str, req: Request<Incoming>) -> Answer {
    let writer = writer_of(&req).map_err(no_more)?.ok_or_else(|| no_more(Refusal::bad("a lines request needs the Grove-Writer header naming its client")))?;
    let from = query_from(&req).ok_or_else(|| no_more(Refusal::bad("a lines request needs ?from=N, the number of its first line in the file")))?;
    let shared = find(state, id)?;
    let mut s = take_session(state, shared, &writer)?;
    if from != s.acked() + 1 {
        let acked = s.acked();
        return Err((Refusal::conflict(format!("the file has {acked} lines; send from line {}", acked + 1)), json!({ "acked": acked, "code": "gap" })));
    }
    let first = s.acked();
    let deadline = tokio::time::Instant::now() + state.read_timeout;
    let mut body = req.into_body();
    let mut splitter = LineSplitter::new(MAX_LINE_BYTES);
    let mut refusal: Option<Refusal> = None;
    while refusal.is_none() {
        let frame = match tokio::time::timeout_at(deadline, body.frame()).await {
            Err(_) => {
                refusal = Some(Refusal::timeout(format!("the request body did not arrive within {:.1} s", state.read_timeout.as_secs_f64())));
                break;
            }
            Ok(None) => break,
            Ok(Some(Err(e))) => {
                refusal = Some(Refusal::bad(format!("the request body could not be read: {e}")));
                break;
            }
            Ok(Some(Ok(f))) => f,
        };
        let Ok(data) = frame.into_data() else { continue };
        let mut bad_line = None;
        let split = splitter.push(&data, &mut |text| match s.take(text) {
            Ok(()) => true,
            Err(why) => {
                bad_line = Some(why);
                false
            }
        });
        if let Some(why) = bad_line {
            refusal = Some(Refusal::bad_line(why));
        } else if let Err(e) = split {
            refusal = Some(match e {
                SplitError::TooLong { number, limit } => Refusal::too_large(format!("line {} is longer than the limit of {limit} bytes", first + number)),
                SplitError::NotUtf8 { number } => Refusal::bad_line(format!("line {}: not valid UTF-8 text", first + number)),
            });
        }
        if let Err(why) = s.write_out() {
            refusal = Some(Refusal::internal(why));
        }
    }
    if refusal.is_none() && !splitter.rest().is_empty() {
        refusal = Some(Refusal::bad(format!("line {} has no newline at the end of the request; every line ends in \\n", s.acked() + 1)));
    }
    if let Err(why) = s.write_out() {
        refusal = Some(Refusal::internal(why));
    }
    s.last_seen = Instant::now();
    let acked = s.acked();
    state.registry.note_lines(&s.id, acked);
    match refusal {
        Some(r) => {
            log(&format!("refused a line of {}: {}", s.file_name, r.reason));
            Err((r, json!({ "acked": acked })))
        }
        None => Ok(json(200, &json!({ "acked": acked }))),
    }
}

async fn end(state: &Arc<State>, id: &str, req: Request<Incoming>) -> Answer {
    let writer = writer_of(&req).map_err(no_more)?.ok_or_else(|| no_more(Refusal::bad("an end request needs the Grove-Writer header naming its client")))?;
    let shared = find(state, id)?;
    let s = take_session(state, shared, &writer)?;
    let v = close_and_verify(state, s, "ended").await.map_err(no_more)?;
    Ok(json(200, &v))
}

/// Ends a session (held by its caller), re-simulates its file and records the result; returns
/// the answer to its client.
async fn close_and_verify(state: &Arc<State>, mut s: tokio::sync::OwnedMutexGuard<Session>, how: &str) -> Result<serde_json::Value, Refusal> {
    s.write_out().map_err(Refusal::internal)?;
    state.registry.close(&mut s, how).map_err(|e| Refusal::internal(e.to_string()))?;
    let (id, file, path, acked, last_tick, last_checkpoint) = (s.id.clone(), s.file_name.clone(), s.path.clone(), s.acked(), s.last_tick(), s.last_checkpoint());
    drop(s);
    let banks = state.registry.bank_dirs.clone();
    let permit = state.verifying.acquire().await.map_err(|e| Refusal::internal(e.to_string()))?;
    let v = tokio::task::spawn_blocking(move || verify(&path, &banks, last_tick, last_checkpoint)).await.map_err(|e| Refusal::internal(e.to_string()))?;
    drop(permit);
    log(&format!("{how} {file}: {acked} lines, {}", v.summary()));
    state.registry.verified(&id, v.clone()).map_err(|e| Refusal::internal(e.to_string()))?;
    Ok(json!({ "acked": acked, "file": file, "state": how, "verification": v }))
}

/// Ends every session that has had no request for `after`, as abandoned, and verifies it.
pub async fn abandon_loop(state: Arc<State>, after: Duration) {
    let every = (after / 4).clamp(Duration::from_millis(100), Duration::from_secs(5));
    loop {
        tokio::time::sleep(every).await;
        for shared in state.registry.open_sessions() {
            let Ok(s) = shared.try_lock_owned() else { continue };
            if !s.ended && s.last_seen.elapsed() >= after {
                let _ = close_and_verify(&state, s, "abandoned").await;
            }
        }
    }
}

/// Hands every open session's lines to the operating system and notes its line count; returns
/// how many sessions are open.
pub async fn flush_all(state: &Arc<State>) -> usize {
    let open = state.registry.open_sessions();
    for shared in &open {
        if let Ok(mut s) = tokio::time::timeout(Duration::from_secs(2), shared.lock()).await {
            let _ = s.write_out();
            state.registry.note_lines(&s.id, s.acked());
        }
    }
    open.len()
}

/// Verifies a session that ended while the server stopped before its verification was written.
pub async fn verify_again(registry: &Registry, e: &Entry) {
    let (dir, id, file, banks) = (registry.dir.clone(), e.id.clone(), e.file.clone(), registry.bank_dirs.clone());
    let v = tokio::task::spawn_blocking(move || -> Verification {
        let bank_set = grove_systems::bank::Banks::open(&banks).unwrap_or_default();
        match Session::resume(&dir, id, &file, &bank_set) {
            Ok(s) => verify(&s.path, &banks, s.last_tick(), s.last_checkpoint()),
            Err(why) => Verification { status: "invalid".into(), complete: false, checkpoints_checked: 0, verified_to_tick: None, last_tick: 0, first_divergence: None, error: Some(why) },
        }
    })
    .await;
    if let Ok(v) = v {
        log(&format!("{} {}: {}", e.state, e.file, v.summary()));
        let _ = registry.verified(&e.id, v);
    }
}

/// The page at `/` when the web folder has no built page: the sessions and what is served.
pub fn index_page(state: &Arc<State>) -> Response<Body> {
    let entries = state.registry.entries();
    let index = state.statics.index();
    let page = maud::html! {
        (maud::DOCTYPE)
        html lang="en" {
            head { meta charset="utf-8"; title { "grove serve" } }
            body style="font-family: sans-serif; max-width: 60em; margin: 2em auto" {
                h1 { "grove serve " (env!("CARGO_PKG_VERSION")) }
                p { "A session server: clients stream recordings here (" code { "docs/serve.md" } "). No page is built in the web folder yet." }
                h2 { "Sessions" }
                @if entries.is_empty() { p { "None yet." } }
                @else {
                    table {
                        tr { th { "file" } th { "state" } th { "lines" } th { "verification" } }
                        @for e in &entries {
                            tr { td { (e.file) } td { (e.state) } td { (e.lines) } td { (e.verification.as_ref().map(|v| v.summary()).unwrap_or_default()) } }
                        }
                    }
                }
                h2 { "Served files" }
                @for (name, files) in index.as_object().into_iter().flatten() {
                    h3 { (name) }
                    ul { @for f in files.as_array().into_iter().flatten() { @if let Some(u) = f.as_str() { li { a href=(u) { (u) } } } } }
                }
            }
        }
    };
    let mut r = Response::new(super::respond::full(page.into_string()));
    r.headers_mut().insert(hyper::header::CONTENT_TYPE, hyper::header::HeaderValue::from_static("text/html; charset=utf-8"));
    r
}
