//! `grove serve push FILE --to URL`: streams an existing recording to a server as a live client
//! would, so that a lab can test its network before a participant arrives. It opens a session
//! with the file's header line, sends the lines in batches (at full speed, or at the pace of the
//! events' `ms` times, or a multiple of it), each batch starting at the line after the last one
//! acknowledged; when the connection fails it keeps what is not acknowledged, reconnects, asks
//! the server how many lines it has and goes on from there, until the server is back or
//! `give_up` has passed without one. Run again on the same file (after it was killed, or after the
//! server restarted), it continues the session it began: the server finds it by the file's
//! header line, its identity, and the push checks that what the server has is the file's start,
//! so that a recording never makes a second file.

use std::collections::VecDeque;
use std::path::Path;
use std::time::{Duration, Instant};

use bytes::Bytes;
use hyper::Method;
use serde::Serialize;
use serde_json::json;

use crate::serve::client::conn::{Answer, ClientError, Conn, Endpoint, Reply};
use crate::serve::client::source::{event_ms, Source};
use crate::serve::sessions::states::{Code, SessionState, VerifyStatus};

/// How fast lines are sent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rate {
    /// As fast as the server acknowledges them.
    Max,
    /// At the pace of the events' `ms` times, this many times faster (1: real time).
    Real(f64),
}

/// Options of a push.
#[derive(Clone, Debug)]
pub struct PushOptions {
    /// How fast.
    pub rate: Rate,
    /// The longest one request (or a connection) may take.
    pub timeout: Duration,
    /// Give up after this long without reaching the server.
    pub give_up: Duration,
    /// The most bytes in one request.
    pub max_batch_bytes: usize,
}

/// What a push did.
#[derive(Clone, Debug, Serialize)]
pub struct PushReport {
    /// The file pushed.
    pub file: String,
    /// The session's id on the server.
    pub session: String,
    /// The session's file on the server.
    pub server_file: String,
    /// Lines the server had of the recording when this push began: 1 (its header) for a new
    /// session, more when a push of the same file had begun it.
    pub continued_from: u64,
    /// Lines acknowledged in all (the header included).
    pub lines: u64,
    /// Requests that carried lines.
    pub requests: u64,
    /// Connections opened again after one failed.
    pub reconnects: u64,
    /// Seconds from the first request to the answer of the last.
    pub seconds: f64,
    /// The server's answer to the session's end: its state and verification.
    pub ended: serde_json::Value,
}

impl PushReport {
    /// The verification's status, as the server's answer says it.
    pub fn status(&self) -> Option<VerifyStatus> {
        field(&self.ended["verification"], "status")
    }
}

/// The connection, opened again as needed.
struct Link<'a> {
    endpoint: &'a Endpoint,
    conn: Option<Conn>,
    options: &'a PushOptions,
    reconnects: u64,
    offline_since: Option<Instant>,
    say: &'a dyn Fn(&str),
}

impl Link<'_> {
    /// One request on the connection (opened again if it was lost): the whole answer.
    async fn send(&mut self, method: Method, path: &str, body: Bytes) -> Result<Reply, ClientError> {
        if self.conn.is_none() {
            let c = self.endpoint.connect(self.options.timeout).await?;
            if self.offline_since.is_some() {
                self.reconnects += 1;
            }
            self.conn = Some(c);
        }
        let conn = self.conn.as_mut().ok_or_else(|| ClientError::Connection("no connection".into()))?;
        let writer = self.endpoint.writer.clone();
        match conn.send(method, path, &[("grove-writer", writer.as_str())], body, self.options.timeout).await {
            Ok(r) => {
                if let Some(since) = self.offline_since.take() {
                    (self.say)(&format!("reconnected after {:.1} s", since.elapsed().as_secs_f64()));
                }
                Ok(r)
            }
            Err(e) => {
                self.conn = None;
                Err(e)
            }
        }
    }

    async fn call(&mut self, method: Method, path: &str, body: Bytes) -> Result<Answer, ClientError> {
        self.send(method, path, body).await.map(|r| (r.status, r.json()))
    }

    /// A GET whose answer is text (a session read back), retried while the server cannot be
    /// reached.
    async fn text(&mut self, path: &str) -> Result<(u16, Bytes), ClientError> {
        let mut attempt = 0;
        loop {
            match self.send(Method::GET, path, Bytes::new()).await {
                Ok(r) => return Ok((r.status, r.body)),
                Err(e) => self.wait(&e, &mut attempt).await?,
            }
        }
    }

    /// After a failed call: waits a moment, or gives up once the server has been away too long.
    async fn wait(&mut self, why: &ClientError, attempt: &mut u32) -> Result<(), ClientError> {
        let since = *self.offline_since.get_or_insert_with(|| {
            (self.say)(&format!("connection lost ({why}); keeping the lines not yet acknowledged and retrying"));
            Instant::now()
        });
        if since.elapsed() > self.options.give_up {
            return Err(ClientError::GaveUp { seconds: since.elapsed().as_secs_f64(), why: why.to_string() });
        }
        *attempt += 1;
        tokio::time::sleep(Duration::from_millis((100u64 << (*attempt).min(4)).min(1000))).await;
        Ok(())
    }

    /// Calls until the server answers (retrying while it cannot be reached).
    async fn answer(&mut self, method: Method, path: &str, body: Bytes) -> Result<Answer, ClientError> {
        let mut attempt = 0;
        loop {
            match self.call(method.clone(), path, body.clone()).await {
                Ok(a) => return Ok(a),
                Err(e) => self.wait(&e, &mut attempt).await?,
            }
        }
    }
}

fn refused(what: &str, (status, v): &Answer) -> ClientError {
    ClientError::Refused { what: what.to_string(), status: *status, reason: v.get("error").and_then(|e| e.as_str()).unwrap_or("no reason given").to_string() }
}

/// A field of the server's answer as its type (a state, a code), if it has it.
fn field<T: serde::de::DeserializeOwned>(v: &serde_json::Value, key: &str) -> Option<T> {
    serde_json::from_value(v.get(key)?.clone()).ok()
}

/// The server's answer lacks the line count.
fn no_acked() -> ClientError {
    ClientError::Answer("the server's answer has no 'acked' count".into())
}

/// How many lines the server has of an open session, asked until it answers (a request of the
/// lost connection may still hold the session until the server's read time is up).
async fn server_lines(link: &mut Link<'_>, session: &str) -> Result<u64, ClientError> {
    loop {
        let status = link.answer(Method::GET, &format!("/api/sessions/{session}"), Bytes::new()).await?;
        match status {
            (200, ref v) if field(v, "state") == Some(SessionState::Open) => return v["acked"].as_u64().ok_or_else(no_acked),
            (409, ref v) if field(v, "code") == Some(Code::Busy) => tokio::time::sleep(Duration::from_millis(200)).await,
            other => return Err(refused("continuing the session", &other)),
        }
    }
}

/// Where a push begins: a new session, or the one an earlier push of the same recording opened.
struct Begun {
    session: String,
    server_file: String,
    /// Lines the server had of it when this push began (1: a new session, its header).
    acked: u64,
    /// The server's entry, when the session has ended already (nothing is sent then).
    ended: Option<serde_json::Value>,
}

/// Opens the session of a recording, or finds the one an earlier push of it opened (`"continue":
/// true`: the server looks it up by the header line, the recording's identity), waiting while a
/// request of that earlier push still holds it.
async fn begin(link: &mut Link<'_>, header: &str, say: &dyn Fn(&str)) -> Result<Begun, ClientError> {
    let body = Bytes::from(json!({ "header": header, "continue": true }).to_string());
    let (status, v) = loop {
        match link.answer(Method::POST, "/api/sessions", body.clone()).await? {
            (409, v) if field(&v, "code") == Some(Code::Busy) => tokio::time::sleep(Duration::from_millis(200)).await,
            answer => break answer,
        }
    };
    if status != 201 && status != 200 {
        return Err(refused("opening the session", &(status, v)));
    }
    let session = v["session"].as_str().unwrap_or("").to_string();
    let server_file = v["file"].as_str().unwrap_or("").to_string();
    let acked = v["acked"].as_u64().ok_or_else(no_acked)?;
    let state: Option<SessionState> = field(&v, "state");
    match (status, state) {
        (201, _) => say(&format!("session {session} opened: {server_file}")),
        (_, Some(SessionState::Open)) => say(&format!("session {session} continued: {server_file} has {acked} lines of this recording; sending from line {}", acked + 1)),
        (_, Some(SessionState::Ended)) => {
            say(&format!("session {session} ({server_file}) of this recording has ended already: nothing sent"));
            return Ok(Begun { session, server_file, acked, ended: Some(v) });
        }
        (_, Some(state)) => {
            return Err(ClientError::Answer(format!(
                "session {session} ({server_file}) of this recording is {state} with {acked} lines and cannot be continued; push the file to a server on a new --out folder"
            )))
        }
        (_, None) => return Err(ClientError::Answer("the server's answer has no session state".into())),
    }
    Ok(Begun { session, server_file, acked, ended: None })
}

/// Checks that the server's first `acked` lines of a continued session are the recording's
/// (the header already read), reading them past in `source`.
async fn same_start(link: &mut Link<'_>, begun: &Begun, source: &mut Source) -> Result<(), ClientError> {
    let (status, text) = link.text(&format!("/api/sessions/{}/lines", begun.session)).await?;
    if status != 200 {
        return Err(ClientError::Refused { what: "reading the session back".into(), status, reason: String::from_utf8_lossy(&text).trim().to_string() });
    }
    let text = String::from_utf8_lossy(&text);
    for (i, theirs) in text.lines().enumerate().skip(1).take(begun.acked.saturating_sub(1) as usize) {
        let ours = source.next()?;
        if ours.as_deref() != Some(theirs) {
            return Err(ClientError::Answer(format!(
                "line {} of {} on the server differs from {}'s: the session holds another recording with the same header line",
                i + 1,
                begun.server_file,
                source.name
            )));
        }
    }
    Ok(())
}

/// Pushes a recording to the server at `endpoint`; `say` gets a line for the session (its id) and
/// for each connection lost and found again. Run again on the same file (after it was killed),
/// it continues the session it began, from the line after the last the server has.
pub async fn push(path: &Path, endpoint: &Endpoint, options: &PushOptions, say: &dyn Fn(&str)) -> Result<PushReport, ClientError> {
    let mut source = Source::open(path)?;
    let header = source.next()?.ok_or_else(|| ClientError::Local(format!("{}: empty file", path.display())))?;
    // One writer name per recording: a push run again is the same client to the server.
    let mut endpoint = endpoint.clone();
    endpoint.writer = format!("push-{:016x}", xxhash_rust::xxh3::xxh3_64(header.as_bytes()));
    let mut link = Link { endpoint: &endpoint, conn: None, options, reconnects: 0, offline_since: None, say };
    let begun = begin(&mut link, &header, say).await?;
    let report = |lines, requests, reconnects, seconds, ended| PushReport {
        file: path.display().to_string(),
        session: begun.session.clone(),
        server_file: begun.server_file.clone(),
        continued_from: begun.acked,
        lines,
        requests,
        reconnects,
        seconds,
        ended,
    };
    if let Some(ended) = &begun.ended {
        return Ok(report(begun.acked, 0, 0, 0.0, ended.clone()));
    }
    if begun.acked > 1 {
        same_start(&mut link, &begun, &mut source).await?;
    }
    let (session, server_file) = (begun.session.clone(), begun.server_file.clone());
    let start = Instant::now();
    let (mut acked, mut requests) = (begun.acked, 0u64);
    // Lines read and not yet acknowledged: (number, text, when it is due, seconds from start).
    let mut queue: VecDeque<(u64, String, f64)> = VecDeque::new();
    let (mut next_number, mut due) = (acked + 1, 0.0f64);
    let mut queued_bytes = 0usize;
    let lines_path = format!("/api/sessions/{session}/lines");
    loop {
        while queued_bytes < 4 * options.max_batch_bytes {
            let Some(line) = source.next()? else { break };
            if let Rate::Real(f) = options.rate
                && let Some(ms) = event_ms(&line)
            {
                due = due.max(ms as f64 / 1000.0 / f);
            }
            queued_bytes += line.len() + 1;
            queue.push_back((next_number, line, due));
            next_number += 1;
        }
        let Some(&(from, _, first_due)) = queue.front() else { break };
        let now = start.elapsed().as_secs_f64();
        if first_due > now {
            tokio::time::sleep(Duration::from_secs_f64(first_due - now)).await;
            continue;
        }
        let mut body = Vec::new();
        for (_, text, d) in queue.iter() {
            if *d > now || (!body.is_empty() && body.len() + text.len() + 1 > options.max_batch_bytes) {
                break;
            }
            body.extend_from_slice(text.as_bytes());
            body.push(b'\n');
        }
        requests += 1;
        let answer = link.call(Method::POST, &format!("{lines_path}?from={from}"), Bytes::from(body)).await;
        let new_acked = match answer {
            Ok((200, v)) => v["acked"].as_u64(),
            Ok((409, v)) if field(&v, "code") == Some(Code::Gap) => v["acked"].as_u64(),
            Ok((409, v)) if field(&v, "code") == Some(Code::Busy) => {
                tokio::time::sleep(Duration::from_millis(100)).await;
                Some(acked)
            }
            Ok(other) => return Err(refused("a batch of lines", &other)),
            Err(e) => {
                // The answer is lost, not perhaps the lines: ask the server what it has.
                let mut attempt = 0;
                link.wait(&e, &mut attempt).await?;
                Some(server_lines(&mut link, &session).await?)
            }
        };
        let new_acked = new_acked.ok_or_else(no_acked)?;
        if new_acked + 1 < from {
            return Err(ClientError::Answer(format!("the server has {new_acked} lines of {server_file}, fewer than it acknowledged ({})", from - 1)));
        }
        acked = new_acked;
        while queue.front().is_some_and(|(n, _, _)| *n <= acked) {
            if let Some((_, text, _)) = queue.pop_front() {
                queued_bytes -= text.len() + 1;
            }
        }
    }
    let ended = link.answer(Method::POST, &format!("/api/sessions/{session}/end"), Bytes::new()).await?;
    let ended = match ended {
        (200, v) => v,
        (410, _) => link.answer(Method::GET, &format!("/api/sessions/{session}"), Bytes::new()).await?.1,
        other => return Err(refused("ending the session", &other)),
    };
    Ok(report(acked, requests, link.reconnects, start.elapsed().as_secs_f64(), ended))
}
