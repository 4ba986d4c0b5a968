//! Every session verified as it streams: each open session's file is replayed by a worker as its
//! lines are acknowledged ([`LiveReplay`]: the world stepped to each line's tick, each checkpoint
//! compared as it comes), never by the request that acknowledges them. A request only notes how
//! far the file is acknowledged and, when the session is not queued already, queues it: the
//! queue holds each session at most once, so it is never longer than the sessions watched. The
//! workers (one per core less one, at least one; at a lower priority than the requests on Linux)
//! take a session, replay what it gained (at most [`super::live_replay::TURN_BYTES`] a turn) and
//! publish its verification; a worker that emptied the queue waits [`PASS`] before the next, so
//! that it takes each session a few ticks at a time. `grove serve --live off` watches nothing (a
//! session is then verified at its end, its file re-simulated whole): for comparisons.
//!
//! When a session ends, its verification is the live one once the worker has replayed its last
//! line ([`Live::finish`]): the file is not simulated a second time. Its view (the world's
//! figures, the trees and the ray's hits) is kept and the world let go. An ended session the
//! server did not watch (it ended before a restart) is replayed once when its view is first
//! asked for ([`Live::review`]).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::time::Duration;

use grove_systems::bank::Banks;

use crate::serve::sessions::live_replay::{LiveReplay, LiveView};
use crate::serve::sessions::verify::Verification;

/// How long a worker that found the queue empty waits before it takes the next session.
const PASS: Duration = Duration::from_millis(20);
/// How much lower than the requests' the workers' priority is (a nice value, on Linux).
#[cfg(target_os = "linux")]
const NICE: libc::c_int = 5;

/// A session's replay, or its last view once it ended.
enum Kept {
    Replaying(Box<LiveReplay>),
    Ended(Box<LiveView>),
}

/// One watched session.
struct Slot {
    /// Bytes of its file acknowledged: what the worker may read.
    acked: AtomicU64,
    /// Set once the session ended: the worker keeps the view and lets the world go after the
    /// last acknowledged byte.
    ending: AtomicBool,
    /// Whether the slot is in the queue.
    queued: AtomicBool,
    kept: Mutex<Kept>,
    /// The verification published after each turn.
    verification: Mutex<Verification>,
    /// Woken after each turn (a request waiting for the end's verification).
    turned: tokio::sync::Notify,
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Slot {
    /// Whether the worker has replayed every acknowledged byte of an ended session (or stopped).
    fn finished(&self) -> bool {
        matches!(*lock(&self.kept), Kept::Ended(_))
    }

    /// One turn of the worker: what the file gained, replayed; the verification published; at
    /// the end of an ended session, the view kept and the world let go. Returns whether more
    /// acknowledged bytes wait.
    fn turn(&self, banks: &Banks) -> bool {
        let mut kept = lock(&self.kept);
        let Kept::Replaying(replay) = &mut *kept else { return false };
        // The end is read before the bytes: an end seen here comes with its last byte count
        // (`finish` stores the count before the end).
        let ending = self.ending.load(Ordering::Acquire);
        let acked = self.acked.load(Ordering::Acquire);
        replay.read(acked, banks);
        *lock(&self.verification) = replay.verification();
        let more = replay.offset() < acked && !replay.stopped();
        if !more && ending {
            *kept = Kept::Ended(Box::new(replay.view()));
        }
        drop(kept);
        self.turned.notify_waiters();
        more
    }
}

/// The sessions' live replays and the workers that run them.
pub struct Live {
    slots: Mutex<HashMap<String, Arc<Slot>>>,
    queue: mpsc::Sender<Arc<Slot>>,
    /// False when sessions are not watched (`grove serve --live off`): each is verified at its
    /// end only.
    enabled: bool,
}

impl Live {
    /// Starts the workers, with the model banks a header may name; with `enabled` false, none:
    /// nothing is watched.
    pub fn start(bank_dirs: &[PathBuf], enabled: bool) -> Live {
        let (queue, rx) = mpsc::channel::<Arc<Slot>>();
        if !enabled {
            return Live { slots: Mutex::new(HashMap::new()), queue, enabled };
        }
        let rx = Arc::new(Mutex::new(rx));
        let banks = Arc::new(Banks::open(bank_dirs).unwrap_or_default());
        let workers = std::thread::available_parallelism().map_or(1, |n| n.get().saturating_sub(1).max(1));
        for i in 0..workers {
            let (rx, banks, again) = (rx.clone(), banks.clone(), queue.clone());
            let spawned = std::thread::Builder::new().name(format!("grove-live-{i}")).spawn(move || work(&rx, &banks, &again));
            if let Err(e) = spawned {
                crate::serve::log::log(&format!("cannot start a live verification worker: {e}"));
            }
        }
        Live { slots: Mutex::new(HashMap::new()), queue, enabled }
    }

    /// Watches session `id`, whose file at `path` has `acked` bytes acknowledged so far (its
    /// header at least): they are replayed at once.
    pub fn watch(&self, id: &str, path: &Path, acked: u64) {
        self.add(id, path, acked, false);
    }

    fn add(&self, id: &str, path: &Path, acked: u64, ending: bool) {
        if !self.enabled {
            return;
        }
        let slot = Arc::new(Slot {
            acked: AtomicU64::new(acked),
            ending: AtomicBool::new(ending),
            queued: AtomicBool::new(false),
            kept: Mutex::new(Kept::Replaying(Box::new(LiveReplay::new(path)))),
            verification: Mutex::new(Verification::found(false, 0, None, 0, 0)),
            turned: tokio::sync::Notify::new(),
        });
        lock(&self.slots).insert(id.to_string(), slot.clone());
        self.enqueue(&slot);
    }

    /// Session `id`'s file has `acked` bytes acknowledged now. Costs the request a map look-up
    /// and, at most, a message on the queue.
    pub fn grown(&self, id: &str, acked: u64) {
        let slot = lock(&self.slots).get(id).cloned();
        if let Some(slot) = slot {
            slot.acked.fetch_max(acked, Ordering::AcqRel);
            self.enqueue(&slot);
        }
    }

    fn enqueue(&self, slot: &Arc<Slot>) {
        if !slot.queued.swap(true, Ordering::AcqRel) {
            let _ = self.queue.send(slot.clone());
        }
    }

    /// Session `id` has ended with `acked` bytes: waits (at most `patience`) until its last line
    /// is replayed and returns its verification; `None` when it was not watched, or the worker
    /// did not finish in time.
    pub async fn finish(&self, id: &str, acked: u64, patience: Duration) -> Option<Verification> {
        let slot = lock(&self.slots).get(id).cloned()?;
        slot.acked.fetch_max(acked, Ordering::AcqRel);
        slot.ending.store(true, Ordering::Release);
        self.enqueue(&slot);
        let waiting = async {
            loop {
                let turned = slot.turned.notified();
                tokio::pin!(turned);
                turned.as_mut().enable();
                if slot.finished() {
                    return;
                }
                turned.await;
            }
        };
        tokio::time::timeout(patience, waiting).await.ok()?;
        Some(lock(&slot.verification).clone())
    }

    /// Replays an ended session's file (at `path`, `bytes` long) once, when it was not watched
    /// (it ended before the server started): its view is made in the background.
    pub fn review(&self, id: &str, path: &Path, bytes: u64) {
        if !lock(&self.slots).contains_key(id) {
            self.add(id, path, bytes, true);
        }
    }

    /// Whether session `id` is watched (or was, and its view is kept).
    pub fn has(&self, id: &str) -> bool {
        lock(&self.slots).contains_key(id)
    }

    /// The verification of session `id`'s lines so far, if it is watched.
    pub fn verification(&self, id: &str) -> Option<Verification> {
        let slot = lock(&self.slots).get(id).cloned()?;
        let v = lock(&slot.verification).clone();
        Some(v)
    }

    /// The view of session `id` now (waiting for a turn in progress), if it is watched. Call it
    /// off the requests' threads (it may wait for a worker's turn).
    pub fn view(&self, id: &str) -> Option<LiveView> {
        let slot = lock(&self.slots).get(id).cloned()?;
        let kept = lock(&slot.kept);
        Some(match &*kept {
            Kept::Replaying(r) => r.view(),
            Kept::Ended(v) => (**v).clone(),
        })
    }
}

/// A worker: takes a queued session, replays what it gained, queues it again when more waits.
/// When the queue is empty it waits [`PASS`] before it waits for the next session, so that a
/// session streaming at 60 Hz is taken a few ticks at a time rather than at every request.
fn work(rx: &Mutex<mpsc::Receiver<Arc<Slot>>>, banks: &Banks, again: &mpsc::Sender<Arc<Slot>>) {
    lower_priority();
    loop {
        let next = lock(rx).try_recv();
        let next = match next {
            Err(mpsc::TryRecvError::Empty) => {
                std::thread::sleep(PASS);
                lock(rx).recv().map_err(|_| mpsc::TryRecvError::Disconnected)
            }
            other => other,
        };
        let Ok(slot) = next else { return };
        slot.queued.store(false, Ordering::Release);
        if slot.turn(banks) && !slot.queued.swap(true, Ordering::AcqRel) {
            let _ = again.send(slot);
        }
    }
}

/// On Linux, the calling thread's nice value raised by [`NICE`]: the workers yield to the
/// requests.
fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: gettid and setpriority have no preconditions; PRIO_PROCESS with a thread id sets
    // that thread's nice value on Linux.
    unsafe {
        let tid = libc::gettid();
        libc::setpriority(libc::PRIO_PROCESS, tid as libc::id_t, NICE);
    }
}
