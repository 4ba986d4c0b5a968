//! The connections served at once, and which one gives way when there are too many: at most
//! `--max-connections` in all and `--max-connections-per-address` from one address. A new
//! connection over either limit closes the connection that has been idle longest (no request in
//! progress and no answer being sent: one that never sent a request, or a keep-alive connection
//! between requests), of that address for the address's limit; so idle connections, however
//! many are opened, never keep a client that is sending from being served. Only when every
//! connection is busy does a new one wait (over the total) or get closed at once (over its
//! address's limit).

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use tokio::sync::Notify;

/// One connection as the pool sees it, shared with its [`Ticket`].
struct Slot {
    peer: IpAddr,
    /// Requests in progress (answers being sent included).
    busy: AtomicU32,
    /// Since when it has had no request in progress.
    idle_since: Mutex<Instant>,
    /// Told when the pool closes it.
    close: Notify,
}

/// The connections served at once.
pub struct Pool {
    slots: Mutex<HashMap<u64, Arc<Slot>>>,
    next: std::sync::atomic::AtomicU64,
    /// Told when a connection leaves.
    freed: Notify,
    max: usize,
    per_address: usize,
}

/// A connection's place in the pool, given back when dropped.
pub struct Ticket {
    pool: Arc<Pool>,
    id: u64,
    slot: Arc<Slot>,
}

/// A request in progress on a connection (held until its answer has been sent).
pub struct Busy {
    slot: Arc<Slot>,
}

impl Pool {
    /// A pool of at most `max` connections, `per_address` from one address.
    pub fn new(max: usize, per_address: usize) -> Arc<Pool> {
        Arc::new(Pool { slots: Mutex::new(HashMap::new()), next: 0.into(), freed: Notify::new(), max: max.max(1), per_address: per_address.max(1) })
    }

    /// Connections held now.
    pub fn len(&self) -> usize {
        self.slots.lock().unwrap_or_else(|p| p.into_inner()).len()
    }

    /// Whether no connection is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Takes a new connection from `peer`, closing the longest idle one where a limit is reached;
    /// waits while every connection is busy and the total is reached. `None`: the address has as
    /// many connections as it may and every one is busy: close the new one.
    pub async fn admit(self: &Arc<Self>, peer: IpAddr) -> Option<Ticket> {
        loop {
            let freed = self.freed.notified();
            tokio::pin!(freed);
            freed.as_mut().enable();
            {
                let mut slots = self.slots.lock().unwrap_or_else(|p| p.into_inner());
                let from_peer = slots.values().filter(|s| s.peer == peer).count();
                if from_peer >= self.per_address && !close_idlest(&mut slots, Some(peer)) {
                    return None;
                }
                if slots.len() < self.max || close_idlest(&mut slots, None) {
                    let id = self.next.fetch_add(1, Ordering::Relaxed);
                    let slot = Arc::new(Slot { peer, busy: AtomicU32::new(0), idle_since: Mutex::new(Instant::now()), close: Notify::new() });
                    slots.insert(id, slot.clone());
                    return Some(Ticket { pool: self.clone(), id, slot });
                }
            }
            freed.await;
        }
    }
}

/// Closes the connection idle longest (of `peer`, if given); false when every one is busy.
fn close_idlest(slots: &mut HashMap<u64, Arc<Slot>>, peer: Option<IpAddr>) -> bool {
    let idlest = slots
        .iter()
        .filter(|(_, s)| peer.is_none_or(|p| s.peer == p) && s.busy.load(Ordering::SeqCst) == 0)
        .min_by_key(|(_, s)| *s.idle_since.lock().unwrap_or_else(|p| p.into_inner()))
        .map(|(id, _)| *id);
    match idlest.and_then(|id| slots.remove(&id)) {
        Some(s) => {
            s.close.notify_one();
            true
        }
        None => false,
    }
}

impl Ticket {
    /// Marks a request in progress until the returned guard is dropped.
    pub fn busy(&self) -> Busy {
        self.slot.busy.fetch_add(1, Ordering::SeqCst);
        Busy { slot: self.slot.clone() }
    }

    /// Whether a request is in progress.
    pub fn is_busy(&self) -> bool {
        self.slot.busy.load(Ordering::SeqCst) > 0
    }

    /// Resolves when the pool has closed this connection to make room for another.
    pub async fn closed(&self) {
        self.slot.close.notified().await
    }
}

impl Drop for Ticket {
    fn drop(&mut self) {
        self.pool.slots.lock().unwrap_or_else(|p| p.into_inner()).remove(&self.id);
        self.pool.freed.notify_one();
    }
}

impl Drop for Busy {
    fn drop(&mut self) {
        *self.slot.idle_since.lock().unwrap_or_else(|p| p.into_inner()) = Instant::now();
        self.slot.busy.fetch_sub(1, Ordering::SeqCst);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(last: u8) -> IpAddr {
        IpAddr::from([127, 0, 0, last])
    }

    #[tokio::test]
    async fn the_longest_idle_connection_gives_way_and_busy_ones_never_do() {
        let pool = Pool::new(3, 2);
        let a = pool.admit(ip(1)).await.unwrap();
        tokio::time::sleep(std::time::Duration::from_millis(5)).await;
        let b = pool.admit(ip(1)).await.unwrap();
        // Over the address's limit: its longest idle connection (a) is closed.
        let c = pool.admit(ip(1)).await.unwrap();
        assert!(tokio::time::timeout(std::time::Duration::from_millis(50), a.closed()).await.is_ok(), "a was closed");
        assert_eq!(pool.len(), 2);
        // Both of that address's connections busy: a third is refused; another address is served.
        let (_b_busy, _c_busy) = (b.busy(), c.busy());
        assert!(pool.admit(ip(1)).await.is_none());
        let d = pool.admit(ip(2)).await.unwrap();
        // At the total with d the only idle one: d gives way to e.
        let e = pool.admit(ip(3)).await.unwrap();
        assert!(tokio::time::timeout(std::time::Duration::from_millis(50), d.closed()).await.is_ok(), "d was closed");
        let _e_busy = e.busy();
        // Every connection busy at the total: the next waits until one leaves.
        let pool2 = pool.clone();
        let waiting = tokio::spawn(async move { pool2.admit(ip(4)).await.is_some() });
        tokio::time::sleep(std::time::Duration::from_millis(30)).await;
        assert!(!waiting.is_finished(), "waits while every connection is busy");
        drop(_e_busy);
        drop(e);
        assert!(waiting.await.unwrap(), "admitted once a connection left");
        drop(a);
        drop(d);
    }
}
