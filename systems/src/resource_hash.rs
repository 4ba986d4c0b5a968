//! The hashed resources, defined once: which fields of [`Resources`] the world hash covers, in
//! which order, and how each is written. Their postcard bytes, field after field (as postcard
//! writes a struct), are what the world hash's `resources` entry hashes
//! ([`crate::hash::world_hash`]); the end of each field in those bytes is noted too, so that a
//! replay that diverges in the resources can say which field differs ([`differing_fields`]).

use serde::Serialize;

use crate::resources::Resources;

/// Appends a value's postcard bytes.
fn put<T: Serialize + ?Sized>(value: &T, buf: &mut Vec<u8>) {
    // Serializing plain data into a Vec cannot fail.
    *buf = postcard::to_extend(value, std::mem::take(buf)).unwrap_or_default();
}

/// Declares the fields from one list of `name: |resources, buffer| writing`: [`FIELDS`] and
/// [`write`].
macro_rules! hashed_resources {
    ($($name:ident: |$r:ident, $buf:ident| $write:expr,)*) => {
        /// The hashed resources' fields, in hashing order.
        pub const FIELDS: &[&str] = &[$(stringify!($name)),*];

        /// How many fields [`FIELDS`] lists.
        pub const COUNT: usize = FIELDS.len();

        /// Writes the hashed resources' bytes into `buf` (cleared first) and returns where each
        /// field's bytes end.
        pub fn write(res: &Resources, buf: &mut Vec<u8>) -> [usize; COUNT] {
            buf.clear();
            let mut ends = [0; COUNT];
            let mut i = 0;
            $({
                let ($r, $buf) = (res, &mut *buf);
                $write;
                ends[i] = buf.len();
                i += 1;
            })*
            debug_assert_eq!(i, COUNT);
            ends
        }
    };
}

hashed_resources! {
    tick: |r, buf| put(&r.tick, buf),
    dt: |r, buf| put(&r.dt, buf),
    seed: |r, buf| put(&r.seed, buf),
    rng: |r, buf| put(&r.rng.get_word_pos(), buf),
    config: |r, buf| put(&r.config, buf),
    mode: |r, buf| put(&r.mode, buf),
    menu: |r, buf| put(&r.menu, buf),
    interaction: |r, buf| put(&r.interaction, buf),
    // The log as postcard writes a sequence: its length, then its entries, each serialized once
    // ([`Resources::log_bytes`]: the log only grows).
    log: |r, buf| {
        put(&r.log.entries.len(), buf);
        r.log_bytes.extend(&r.log, buf);
    },
    task: |r, buf| put(&r.task, buf),
}

/// The hashed resources' bytes and where each field ends in them.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ResourceBytes {
    /// The bytes, field after field.
    pub bytes: Vec<u8>,
    /// Where each field of [`FIELDS`] ends in `bytes`.
    pub ends: [usize; COUNT],
}

impl ResourceBytes {
    /// The resources' bytes, written into this value's buffer.
    pub fn of(res: &Resources) -> ResourceBytes {
        let mut bytes = Vec::new();
        let ends = write(res, &mut bytes);
        ResourceBytes { bytes, ends }
    }

    /// The bytes of field `i` of [`FIELDS`].
    pub fn field(&self, i: usize) -> &[u8] {
        let start = if i == 0 { 0 } else { self.ends[i - 1] };
        &self.bytes[start..self.ends[i]]
    }

    /// The hash of the whole, as the world hash's `resources` entry has it.
    pub fn hash(&self) -> u64 {
        xxhash_rust::xxh3::xxh3_64(&self.bytes)
    }
}

/// Which fields differ between the resources a recording hashed (`expected`, known only by its
/// hash) and the replay's (`now`), given the resources at the last checkpoint where the replay
/// and the recording agreed (`agreed`; they were the same then).
///
/// A recording keeps one hash of all the resources, so this is found by trying: of the fields
/// the replay changed since `agreed` (the tick excepted, which the checkpoint fixes), the
/// smallest set that, put back as it was at `agreed`, gives `expected`: the recording left
/// exactly those as they were. When no set does, some field changed in the recording otherwise
/// than in the replay, and which one a single hash cannot tell: then the fields the replay
/// changed since `agreed` are named (every field that can change, if it changed none).
pub fn differing_fields(agreed: &ResourceBytes, now: &ResourceBytes, expected: u64) -> Vec<&'static str> {
    let changed: Vec<usize> = (0..COUNT).filter(|&i| FIELDS[i] != "tick" && agreed.field(i) != now.field(i)).collect();
    if changed.is_empty() {
        return FIELDS.iter().copied().filter(|f| !matches!(*f, "tick" | "dt" | "seed" | "config")).collect();
    }
    // At most 2^(COUNT - 1) sets, tried once, at a divergence.
    let mut sets: Vec<u32> = (1..1u32 << changed.len()).collect();
    sets.sort_by_key(|s| (s.count_ones(), *s));
    let mut buf = Vec::with_capacity(now.bytes.len().max(agreed.bytes.len()));
    for set in sets {
        buf.clear();
        for i in 0..COUNT {
            let back = changed.iter().position(|&c| c == i).is_some_and(|k| set & (1 << k) != 0);
            buf.extend_from_slice(if back { agreed.field(i) } else { now.field(i) });
        }
        if xxhash_rust::xxh3::xxh3_64(&buf) == expected {
            return changed.iter().enumerate().filter(|(k, _)| set & (1 << k) != 0).map(|(_, &i)| FIELDS[i]).collect();
        }
    }
    changed.iter().map(|&i| FIELDS[i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::events::Happening;

    fn fresh() -> Resources {
        Resources::new(1.0 / 60.0, 3, crate::catalogue::Catalogue::builtin())
    }

    /// The hashed resources serialized at once, as one tuple (postcard writes a tuple as it
    /// writes a struct: field after field).
    fn whole(r: &Resources) -> Vec<u8> {
        postcard::to_allocvec(&(
            r.tick,
            r.dt,
            r.seed,
            r.rng.get_word_pos(),
            &r.config,
            r.mode,
            &r.menu,
            &r.interaction,
            &r.log,
            &r.task,
        ))
        .unwrap()
    }

    #[test]
    fn the_fields_put_together_are_their_serialization() {
        let mut res = fresh();
        let mut buf = Vec::new();
        for tick in 0..200 {
            res.tick = tick;
            if tick % 3 == 0 {
                res.log.push(tick, Happening::Moved { tree: tick, position: glam::Vec3::new(tick as f32, 0.5, -1.0) });
            }
            let ends = write(&res, &mut buf);
            assert_eq!(buf, whole(&res), "tick {tick}");
            assert_eq!(ends[COUNT - 1], buf.len());
            assert!(ends.windows(2).all(|w| w[0] <= w[1]));
        }
        // A log past 127 entries (a two-byte count), then a shorter one: the bytes follow it.
        assert!(res.log.entries.len() < 128);
        for tick in 0..100 {
            res.log.push(tick, Happening::MenuOpened);
        }
        write(&res, &mut buf);
        assert_eq!(buf, whole(&res));
        res.log.entries.truncate(2);
        write(&res, &mut buf);
        assert_eq!(buf, whole(&res));
        // Each field's bytes are its own serialization.
        let b = ResourceBytes::of(&res);
        let log = FIELDS.iter().position(|f| *f == "log").unwrap();
        assert_eq!(b.field(log), postcard::to_allocvec(&res.log).unwrap());
        assert_eq!(b.field(0), postcard::to_allocvec(&res.tick).unwrap());
    }

    #[test]
    fn the_differing_field_is_named() {
        let mut agreed = fresh();
        agreed.tick = 60;
        let before = ResourceBytes::of(&agreed);
        // The recording: 60 ticks on, the menu opened.
        let mut recorded = fresh();
        recorded.tick = 120;
        recorded.menu.open = true;
        let expected = ResourceBytes::of(&recorded).hash();

        // The replay opened the menu and also planted: the log is what differs, exactly.
        let mut replay = fresh();
        replay.tick = 120;
        replay.menu.open = true;
        replay.log.push(100, Happening::MenuOpened);
        assert_eq!(differing_fields(&before, &ResourceBytes::of(&replay), expected), ["log"]);

        // The replay left the menu closed: it changed nothing, so every field that can change is
        // named.
        let mut replay = fresh();
        replay.tick = 120;
        let named = differing_fields(&before, &ResourceBytes::of(&replay), expected);
        assert!(named.contains(&"menu") && !named.contains(&"tick") && !named.contains(&"config"), "{named:?}");

        // The replay chose another model and logged it, where the recording opened the menu:
        // the menu changed in both, otherwise; the fields the replay changed are named.
        let mut replay = fresh();
        replay.tick = 120;
        replay.menu.current_model = crate::catalogue::ModelId(2);
        replay.log.push(100, Happening::MenuOpened);
        assert_eq!(differing_fields(&before, &ResourceBytes::of(&replay), expected), ["menu", "log"]);
    }
}
