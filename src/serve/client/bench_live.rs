//! How soon a server's live verification follows the bench's sessions: each checkpoint a
//! session's request carried is noted with the time its acknowledgement came; a watcher reads
//! `GET /api/sessions` four times a second, as a dashboard would, and takes the time from a
//! checkpoint's acknowledgement to the first listing whose `live.verified_to_tick` has reached it
//! (so the figures are at most a quarter of a second late). A live verification that diverged or
//! failed is counted as wrong: the bench's recordings verify.

use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use bytes::Bytes;
use hyper::Method;

use crate::serve::client::conn::Endpoint;
use crate::serve::sessions::states::VerifyStatus;

/// How often the watcher reads the listing.
const EVERY: Duration = Duration::from_millis(250);

#[derive(Default)]
struct Seen {
    /// By session file: the checkpoints acknowledged and not yet seen verified, with when.
    waiting: HashMap<String, VecDeque<(u64, Instant)>>,
    /// Milliseconds from an acknowledgement to the live verification of its checkpoint.
    ms: Vec<f64>,
    /// Sessions whose live verification diverged or failed.
    wrong: HashSet<String>,
}

/// The checkpoints the bench's sessions streamed, shared by them and the watcher.
#[derive(Clone, Default)]
pub struct Checkpoints(Arc<Mutex<Seen>>);

/// What the watcher found.
pub struct LiveFigures {
    /// Checkpoints seen verified.
    pub verified: usize,
    /// Milliseconds from a checkpoint's acknowledgement to its live verification: median, 99th
    /// percentile, most (none when no checkpoint was seen verified).
    pub p50: Option<f64>,
    /// See `p50`.
    pub p99: Option<f64>,
    /// See `p50`.
    pub max: Option<f64>,
    /// Sessions whose live verification diverged or failed.
    pub wrong: usize,
}

impl Checkpoints {
    fn seen(&self) -> std::sync::MutexGuard<'_, Seen> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Session `file`'s checkpoint of `tick` was acknowledged now.
    pub fn acked(&self, file: &str, tick: u64) {
        self.seen().waiting.entry(file.to_string()).or_default().push_back((tick, Instant::now()));
    }

    /// Session `file`'s live verification has reached `tick` (or is `status`).
    fn verified(&self, file: &str, tick: u64, status: VerifyStatus) {
        let now = Instant::now();
        let mut seen = self.seen();
        if status.is_wrong() {
            seen.wrong.insert(file.to_string());
        }
        let Some(waiting) = seen.waiting.get_mut(file) else { return };
        let mut done = Vec::new();
        while waiting.front().is_some_and(|(t, _)| *t <= tick) {
            if let Some((_, at)) = waiting.pop_front() {
                done.push(now.duration_since(at).as_secs_f64() * 1000.0);
            }
        }
        seen.ms.extend(done);
    }

    /// The figures so far.
    pub fn figures(&self) -> LiveFigures {
        let seen = self.seen();
        let mut ms = seen.ms.clone();
        ms.sort_by(f64::total_cmp);
        let q = |x: f64| (!ms.is_empty()).then(|| round(quantile(&ms, x), 1));
        LiveFigures { verified: ms.len(), p50: q(0.5), p99: q(0.99), max: q(1.0), wrong: seen.wrong.len() }
    }
}

/// Reads the server's listing four times a second until aborted, noting each open session's live
/// verification.
pub async fn watch_live(endpoint: Endpoint, checkpoints: Checkpoints) {
    let timeout = Duration::from_secs(10);
    let mut conn = None;
    let mut every = tokio::time::interval(EVERY);
    loop {
        every.tick().await;
        if conn.is_none() {
            conn = endpoint.connect(timeout).await.ok();
        }
        let Some(c) = conn.as_mut() else { continue };
        let Ok((200, listing)) = c.request(Method::GET, "/api/sessions", Bytes::new(), timeout).await else {
            conn = None;
            continue;
        };
        for s in listing["sessions"].as_array().into_iter().flatten() {
            let (Some(file), Some(live)) = (s["file"].as_str(), s.get("live").filter(|l| !l.is_null())) else { continue };
            let Ok(status) = serde_json::from_value::<VerifyStatus>(live["status"].clone()) else { continue };
            checkpoints.verified(file, live["verified_to_tick"].as_u64().unwrap_or(0), status);
        }
    }
}

/// The `q` quantile of sorted values (NaN for none).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// `x` rounded to `digits` decimals.
pub fn round(x: f64, digits: i32) -> f64 {
    let m = 10f64.powi(digits);
    (x * m).round() / m
}
