//! The background tile loader: one thread that reads tiles from a [`TileReader`] on request.
//!
//! Requests go through a bounded queue that the frame fills with `try_send`, so the frame never
//! waits: when the queue is full the rest are asked for on a later frame. The frame also keeps
//! the set of tiles it still wants in a shared set; the thread skips (and reports as cancelled)
//! any queued request that has left it, so a fast camera does not leave a backlog of tiles
//! nobody needs. Results come back on an unbounded channel, which holds at most one result per
//! request in flight.

use std::collections::HashSet;
use std::sync::mpsc::{Receiver, SyncSender, TryRecvError, TrySendError, channel, sync_channel};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;

use crate::aerial::tiles::TileReader;
use crate::render::error::ClipmapError;

/// A tile of the pyramid: mip and tile column and row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileKey {
    /// The mip.
    pub mip: u32,
    /// Tile column.
    pub tx: u32,
    /// Tile row.
    pub ty: u32,
}

/// What became of a request.
#[derive(Clone, Debug)]
pub enum TileResult {
    /// The tile's `tile²` RGBA8 texels.
    Loaded(Arc<Vec<u8>>),
    /// Reading it failed: one line.
    Failed(String),
    /// It was no longer wanted when its turn came, and was not read.
    Cancelled,
}

/// Why a request was not queued.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestRefused {
    /// The queue is full; ask again on a later frame.
    Full,
    /// The loader thread has ended (a reader panicked).
    Gone,
}

/// The frame's side of the loader thread.
pub struct Loader {
    requests: Option<SyncSender<TileKey>>,
    results: Receiver<(TileKey, TileResult)>,
    wanted: Arc<Mutex<HashSet<TileKey>>>,
    thread: Option<JoinHandle<()>>,
}

fn lock(m: &Mutex<HashSet<TileKey>>) -> MutexGuard<'_, HashSet<TileKey>> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl Loader {
    /// Starts the thread, reading from `reader`, with a queue of `queue` requests.
    pub fn spawn(reader: Arc<dyn TileReader>, queue: usize) -> Result<Loader, ClipmapError> {
        let (req_tx, req_rx) = sync_channel::<TileKey>(queue.max(1));
        let (res_tx, res_rx) = channel();
        let wanted = Arc::new(Mutex::new(HashSet::new()));
        let shared = Arc::clone(&wanted);
        let thread = std::thread::Builder::new()
            .name("clipmap-loader".into())
            .spawn(move || {
                for key in req_rx {
                    let still = lock(&shared).contains(&key);
                    let result = if still {
                        match reader.read_tile(key.mip, key.tx, key.ty) {
                            Ok(rgba) => TileResult::Loaded(Arc::new(rgba)),
                            Err(e) => TileResult::Failed(e.to_string()),
                        }
                    } else {
                        TileResult::Cancelled
                    };
                    if res_tx.send((key, result)).is_err() {
                        break;
                    }
                }
            })
            .map_err(ClipmapError::LoaderThread)?;
        Ok(Loader { requests: Some(req_tx), results: res_rx, wanted, thread: Some(thread) })
    }

    /// Queues a request without waiting.
    pub fn request(&self, key: TileKey) -> Result<(), RequestRefused> {
        let Some(tx) = &self.requests else { return Err(RequestRefused::Gone) };
        match tx.try_send(key) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(_)) => Err(RequestRefused::Full),
            Err(TrySendError::Disconnected(_)) => Err(RequestRefused::Gone),
        }
    }

    /// Replaces the set of tiles still wanted; queued requests outside it are cancelled.
    pub fn set_wanted(&self, wanted: &HashSet<TileKey>) {
        let mut w = lock(&self.wanted);
        if *w != *wanted {
            w.clone_from(wanted);
        }
    }

    /// The results that have arrived, without waiting.
    pub fn drain(&self) -> Vec<(TileKey, TileResult)> {
        let mut out = Vec::new();
        loop {
            match self.results.try_recv() {
                Ok(r) => out.push(r),
                Err(TryRecvError::Empty | TryRecvError::Disconnected) => return out,
            }
        }
    }

    /// Whether the thread has ended (only after a reader panicked).
    pub fn is_gone(&self) -> bool {
        self.thread.as_ref().is_none_or(JoinHandle::is_finished)
    }
}

impl Drop for Loader {
    /// Closes the queue so the thread ends after its current tile; it is not waited for, so
    /// dropping a clipmap never waits on disk either.
    fn drop(&mut self) {
        lock(&self.wanted).clear();
        self.requests = None;
        self.thread = None;
    }
}
