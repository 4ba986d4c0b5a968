//! [`Clipmap`]: the CPU half of a clipmap, a [`ClipmapSource`] fed from a tile pyramid by the
//! background [`Loader`].
//!
//! Each [`update`](ClipmapSource::update):
//!
//! 1. takes the tiles that arrived since the last call (never waiting) into a cache;
//! 2. places the levels for the camera ([`place_levels`]);
//! 3. writes each level's newly exposed texels ([`exposed`], split at the wrap by [`wrap`]) from
//!    the cache, alpha 0 where a tile has not arrived (the GPU falls back to the coarser level);
//! 4. writes the texels of tiles that arrived and that lay in a level's window already, so
//!    texels left transparent are filled once their tile is there;
//! 5. asks the loader for the tiles the windows need and does not have (coarsest level first,
//!    each level's centre first) and cancels the ones that left every window.
//!
//! A tile that cannot be read (missing, truncated, foreign) is reported once in
//! [`ClipmapStats::last_error`] and left transparent: the coarser level shows there.

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::sync::Arc;

use super::loader::{Loader, RequestRefused, TileKey, TileResult};
use super::place::{ImageExtent, place_levels};
use super::toroid::{TexelRect, exposed, window, wrap};
use super::{AerialPlacement, ClipCamera, ClipmapConfig, ClipmapFrame, ClipmapSource, LevelPlacement, Upload};
use crate::aerial::tiles::{Pyramid, PyramidMeta, TileReader};
use crate::render::error::ClipmapError;

/// Requests the loader's queue holds.
const QUEUE: usize = 64;

/// Counters of a clipmap, for benchmarks, tests and status lines.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ClipmapStats {
    /// Tiles held in the cache now.
    pub cached: usize,
    /// Tiles asked for and not answered yet.
    pub in_flight: usize,
    /// Tiles the current windows need that are neither cached nor failed (asked for or not).
    pub missing: usize,
    /// Tiles read since the start.
    pub loaded: u64,
    /// Tiles that could not be read since the start.
    pub failed: u64,
    /// Requests the loader skipped because they were no longer wanted.
    pub cancelled: u64,
    /// Texels written into the level textures since the start.
    pub texels_uploaded: u64,
    /// The last tile error, one line.
    pub last_error: Option<String>,
}

/// A clipmap over a tile pyramid (see the module docs).
pub struct Clipmap {
    config: ClipmapConfig,
    aerial: AerialPlacement,
    meta: PyramidMeta,
    extent: ImageExtent,
    loader: Loader,
    levels: Vec<Option<LevelPlacement>>,
    cache: HashMap<TileKey, (Arc<Vec<u8>>, u64)>,
    capacity: usize,
    in_flight: HashSet<TileKey>,
    failed: HashSet<TileKey>,
    frame: u64,
    stats: ClipmapStats,
}

/// Checks a clipmap configuration against the contract's ranges.
pub fn check_config(config: &ClipmapConfig) -> Result<(), ClipmapError> {
    if !(1..=16).contains(&config.levels) {
        return Err(ClipmapError::Levels(config.levels));
    }
    if !config.size.is_power_of_two() || !(16..=4096).contains(&config.size) {
        return Err(ClipmapError::LevelSize(config.size));
    }
    Ok(())
}

fn check_placement(p: &AerialPlacement) -> Result<(), ClipmapError> {
    if !(p.gsd_m.is_finite() && p.gsd_m > 0.0) || !p.origin_m.is_finite() {
        return Err(ClipmapError::Placement { origin: p.origin_m, gsd: p.gsd_m });
    }
    Ok(())
}

impl Clipmap {
    /// Opens the pyramid at `dir` and starts the loader thread.
    pub fn open(dir: &Path, config: ClipmapConfig, placement: AerialPlacement) -> Result<Clipmap, ClipmapError> {
        let pyramid = Pyramid::open(dir)?;
        Clipmap::with_reader(Arc::new(pyramid), config, placement)
    }

    /// A clipmap over any tile reader (a pyramid, or a stand-in in tests).
    pub fn with_reader(
        reader: Arc<dyn TileReader>,
        config: ClipmapConfig,
        placement: AerialPlacement,
    ) -> Result<Clipmap, ClipmapError> {
        check_config(&config)?;
        check_placement(&placement)?;
        let meta = reader.meta().clone();
        let extent = ImageExtent { width: meta.width, height: meta.height, mips: meta.levels };
        let per_level = (config.size / meta.tile + 2).pow(2) as usize;
        let loader = Loader::spawn(reader, QUEUE)?;
        Ok(Clipmap {
            config,
            aerial: placement,
            meta,
            extent,
            loader,
            levels: vec![None; config.levels as usize],
            cache: HashMap::new(),
            capacity: (2 * per_level * config.levels as usize).max(64),
            in_flight: HashSet::new(),
            failed: HashSet::new(),
            frame: 0,
            stats: ClipmapStats::default(),
        })
    }

    /// The pyramid's metadata.
    pub fn meta(&self) -> &PyramidMeta {
        &self.meta
    }

    /// The counters.
    pub fn stats(&self) -> ClipmapStats {
        ClipmapStats { cached: self.cache.len(), in_flight: self.in_flight.len(), ..self.stats.clone() }
    }

    /// The tiles that hold the texels of `rect` in mip `mip`, clipped to the mip.
    fn tiles_of(&self, mip: u32, rect: &TexelRect) -> Vec<TileKey> {
        let (w, h) = self.meta.mip_size(mip);
        let Some(r) = rect.intersect(&TexelRect { x: 0, y: 0, w, h }) else { return Vec::new() };
        let t = self.meta.tile as i32;
        let (x0, y0) = (r.x / t, r.y / t);
        let (x1, y1) = ((r.x + r.w as i32 - 1) / t, (r.y + r.h as i32 - 1) / t);
        let mut out = Vec::with_capacity(((x1 - x0 + 1) * (y1 - y0 + 1)) as usize);
        for ty in y0..=y1 {
            for tx in x0..=x1 {
                out.push(TileKey { mip, tx: tx as u32, ty: ty as u32 });
            }
        }
        out
    }

    /// The upload of mip texels `src` into level `level`'s texture at `tex`, from the cache;
    /// alpha 0 outside the photograph and where a tile is not cached.
    fn fill(&self, level: u32, mip: u32, tex: glam::IVec2, src: &TexelRect) -> Upload {
        let (mw, mh) = self.meta.mip_size(mip);
        let t = self.meta.tile as i64;
        let mut rgba = vec![0u8; src.area() as usize * 4];
        let row_bytes = src.w as usize * 4;
        for j in 0..src.h as i64 {
            let v = src.y as i64 + j;
            if v < 0 || v >= mh as i64 {
                continue;
            }
            let (ty, row_in_tile) = ((v / t) as u32, (v % t) as usize);
            // Only the columns inside the photograph, tile by tile.
            let mut u = (src.x as i64).max(0);
            let end = (src.x as i64 + src.w as i64).min(mw as i64);
            while u < end {
                let tx = u / t;
                let seg_end = ((tx + 1) * t).min(end);
                if let Some((tile, _)) = self.cache.get(&TileKey { mip, tx: tx as u32, ty }) {
                    let s = (row_in_tile * t as usize + (u - tx * t) as usize) * 4;
                    let d = j as usize * row_bytes + (u - src.x as i64) as usize * 4;
                    let len = (seg_end - u) as usize * 4;
                    rgba[d..d + len].copy_from_slice(&tile[s..s + len]);
                }
                u = seg_end;
            }
        }
        Upload { level, x: tex.x as u32, y: tex.y as u32, w: src.w, h: src.h, rgba }
    }

    /// The uploads that write `rect` (at most a window) of level `level`.
    fn write_rect(&self, level: u32, mip: u32, rect: &TexelRect, out: &mut Vec<Upload>) {
        for piece in wrap(rect, self.config.size) {
            out.push(self.fill(level, mip, piece.tex, &piece.src));
        }
    }

    /// Takes the loader's answers into the cache; returns the tiles that arrived.
    fn take_arrivals(&mut self) -> Vec<TileKey> {
        let mut arrived = Vec::new();
        for (key, result) in self.loader.drain() {
            self.in_flight.remove(&key);
            match result {
                TileResult::Loaded(rgba) => {
                    let n = self.meta.tile as usize;
                    if rgba.len() == n * n * 4 {
                        self.cache.insert(key, (rgba, self.frame));
                        self.stats.loaded += 1;
                        arrived.push(key);
                    } else {
                        self.fail(
                            key,
                            format!(
                                "tile ({}, {}) of mip {} came back with {} bytes, expected {}",
                                key.tx,
                                key.ty,
                                key.mip,
                                rgba.len(),
                                n * n * 4
                            ),
                        );
                    }
                }
                TileResult::Failed(e) => self.fail(key, e),
                TileResult::Cancelled => self.stats.cancelled += 1,
            }
        }
        arrived
    }

    fn fail(&mut self, key: TileKey, e: String) {
        self.failed.insert(key);
        self.stats.failed += 1;
        self.stats.last_error = Some(e);
    }

    /// Asks for the tiles the windows need, coarsest level first, each level's centre first;
    /// returns the wanted set.
    fn request_missing(&mut self, placements: &[LevelPlacement]) {
        let mut wanted = HashSet::new();
        let mut order = Vec::new();
        let half = self.config.size as i64 / 2;
        for p in placements.iter().rev() {
            let win = window(p, self.config.size);
            let mut tiles = self.tiles_of(p.mip, &win);
            let t = self.meta.tile as i64;
            let (cx, cy) = (p.origin.x as i64 + half, p.origin.y as i64 + half);
            tiles.sort_by_key(|k| {
                let (mx, my) = (k.tx as i64 * t + t / 2, k.ty as i64 * t + t / 2);
                ((mx - cx).abs().max((my - cy).abs()), k.ty, k.tx)
            });
            for k in tiles {
                if wanted.insert(k) {
                    order.push(k);
                }
            }
        }
        self.loader.set_wanted(&wanted);
        let mut missing = 0;
        let mut queue_open = true;
        for k in order {
            if let Some(entry) = self.cache.get_mut(&k) {
                entry.1 = self.frame;
                continue;
            }
            if self.failed.contains(&k) {
                continue;
            }
            missing += 1;
            if !queue_open || self.in_flight.contains(&k) {
                continue;
            }
            match self.loader.request(k) {
                Ok(()) => {
                    self.in_flight.insert(k);
                }
                Err(RequestRefused::Full) => queue_open = false,
                Err(RequestRefused::Gone) => {
                    queue_open = false;
                    self.stats.last_error =
                        Some("the clipmap's loader thread has stopped; no more tiles will load".into());
                }
            }
        }
        self.stats.missing = missing;
        // Forget the oldest tiles no window needs once the cache is over its capacity.
        if self.cache.len() > self.capacity {
            let mut old: Vec<(u64, TileKey)> =
                self.cache.iter().filter(|(k, _)| !wanted.contains(*k)).map(|(k, v)| (v.1, *k)).collect();
            old.sort_unstable();
            for (_, k) in old.into_iter().take(self.cache.len() - self.capacity) {
                self.cache.remove(&k);
            }
        }
    }
}

impl ClipmapSource for Clipmap {
    fn config(&self) -> ClipmapConfig {
        self.config
    }

    fn placement(&self) -> AerialPlacement {
        self.aerial
    }

    fn missing_tiles(&self) -> usize {
        self.stats.missing
    }

    fn update(&mut self, camera: &ClipCamera) -> ClipmapFrame {
        self.frame += 1;
        let arrived = self.take_arrivals();
        let placements = place_levels(&self.config, &self.aerial, &self.extent, camera);
        let n = self.config.size;
        let mut uploads = Vec::new();
        for (i, new) in placements.iter().enumerate() {
            let old = self.levels[i];
            for rect in exposed(old.as_ref(), new, n) {
                self.write_rect(i as u32, new.mip, &rect, &mut uploads);
            }
            // Tiles that arrived now fill the texels the window held already (left transparent).
            let Some(old) = old.filter(|o| o.mip == new.mip) else { continue };
            let Some(kept) = window(&old, n).intersect(&window(new, n)) else { continue };
            let t = self.meta.tile;
            for key in arrived.iter().filter(|k| k.mip == new.mip) {
                let tile = TexelRect { x: (key.tx * t) as i32, y: (key.ty * t) as i32, w: t, h: t };
                if let Some(r) = tile.intersect(&kept) {
                    self.write_rect(i as u32, new.mip, &r, &mut uploads);
                }
            }
        }
        self.request_missing(&placements);
        for (slot, p) in self.levels.iter_mut().zip(&placements) {
            *slot = Some(*p);
        }
        self.stats.texels_uploaded += uploads.iter().map(|u| u.w as u64 * u.h as u64).sum::<u64>();
        ClipmapFrame { placements, uploads }
    }
}
