//! Tests of [`Clipmap`] with a slow stand-in tile reader and with a pyramid on disk: updates
//! return at once, texels arrive on later calls, and the level textures end up holding exactly
//! the pyramid's texels where toroidal addressing puts them.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use glam::{DVec2, DVec3};

use super::stream::Clipmap;
use super::*;
use crate::aerial::tiles::{PyramidMeta, TileReader};

/// A reader that sleeps before each tile and makes texels from their coordinates.
struct SlowReader {
    meta: PyramidMeta,
    delay: Duration,
    reads: Mutex<Vec<(u32, u32, u32)>>,
    calls: AtomicUsize,
}

/// The texel (u, v) of mip `mip` in [`SlowReader`]'s pyramid.
fn pattern(mip: u32, u: u32, v: u32) -> [u8; 4] {
    [(u % 251) as u8, (v % 241) as u8, (mip * 40) as u8, 255]
}

impl TileReader for SlowReader {
    fn meta(&self) -> &PyramidMeta {
        &self.meta
    }
    fn read_tile(&self, mip: u32, tx: u32, ty: u32) -> Result<Vec<u8>, crate::aerial::AerialError> {
        std::thread::sleep(self.delay);
        self.calls.fetch_add(1, Ordering::SeqCst);
        self.reads.lock().unwrap().push((mip, tx, ty));
        let t = self.meta.tile;
        let (w, h) = self.meta.mip_size(mip);
        let mut out = vec![0u8; (t * t * 4) as usize];
        for j in 0..t {
            for i in 0..t {
                let (u, v) = (tx * t + i, ty * t + j);
                if u < w && v < h {
                    out[((j * t + i) * 4) as usize..][..4].copy_from_slice(&pattern(mip, u, v));
                }
            }
        }
        Ok(out)
    }
}

fn reader(width: u32, height: u32, tile: u32, delay_ms: u64) -> Arc<SlowReader> {
    Arc::new(SlowReader {
        meta: PyramidMeta::new(width, height, 3, tile, "0".repeat(16)),
        delay: Duration::from_millis(delay_ms),
        reads: Mutex::new(Vec::new()),
        calls: AtomicUsize::new(0),
    })
}

/// The level textures as the GPU would hold them after the uploads.
struct Textures {
    n: u32,
    levels: Vec<Vec<u8>>,
}

impl Textures {
    fn new(cfg: ClipmapConfig) -> Textures {
        Textures { n: cfg.size, levels: vec![vec![0u8; (cfg.size * cfg.size * 4) as usize]; cfg.levels as usize] }
    }

    fn apply(&mut self, frame: &ClipmapFrame) {
        for u in &frame.uploads {
            assert!(u.x + u.w <= self.n && u.y + u.h <= self.n, "uploads are plain rectangles of the texture");
            assert_eq!(u.rgba.len(), (u.w * u.h * 4) as usize);
            let tex = &mut self.levels[u.level as usize];
            for j in 0..u.h {
                let d = (((u.y + j) * self.n + u.x) * 4) as usize;
                let s = (j * u.w * 4) as usize;
                tex[d..d + (u.w * 4) as usize].copy_from_slice(&u.rgba[s..s + (u.w * 4) as usize]);
            }
        }
    }

    /// Whether every level holds its window's texels: the pattern inside the photograph, alpha
    /// 0 outside it.
    fn complete(&self, meta: &PyramidMeta, placements: &[LevelPlacement]) -> bool {
        let n = self.n as i32;
        placements.iter().enumerate().all(|(l, p)| {
            let (w, h) = meta.mip_size(p.mip);
            (p.origin.y..p.origin.y + n).all(|v| {
                (p.origin.x..p.origin.x + n).all(|u| {
                    let k = ((v.rem_euclid(n) * n + u.rem_euclid(n)) * 4) as usize;
                    let want = if u >= 0 && v >= 0 && (u as u32) < w && (v as u32) < h {
                        pattern(p.mip, u as u32, v as u32)
                    } else {
                        [0; 4]
                    };
                    self.levels[l][k..k + 4] == want
                })
            })
        })
    }
}

fn down(x: f64, z: f64) -> ClipCamera {
    ClipCamera { eye: DVec3::new(x, 50.0, z), forward: DVec3::NEG_Y, fov_y: 1.0, aspect: 1.0 }
}

const CFG: ClipmapConfig = ClipmapConfig { levels: 3, size: 32 };
const UNIT: AerialPlacement = AerialPlacement { origin_m: DVec2::ZERO, gsd_m: 1.0 };

/// Calls `update` until the textures are complete, checking that no call waits for the slow
/// reader; returns the number of calls.
fn run_until_complete(map: &mut Clipmap, tex: &mut Textures, cam: &ClipCamera, delay: Duration) -> usize {
    let start = Instant::now();
    for calls in 1.. {
        let t = Instant::now();
        let frame = map.update(cam);
        // An update that waited for the reader would take at least one tile's delay.
        assert!(t.elapsed() < delay, "update waited {:?} (a tile takes {delay:?})", t.elapsed());
        tex.apply(&frame);
        if tex.complete(map.meta(), &frame.placements) {
            return calls;
        }
        assert!(start.elapsed() < Duration::from_secs(30), "the tiles never all arrived: {:?}", map.stats());
        std::thread::sleep(Duration::from_millis(5));
    }
    unreachable!()
}

#[test]
fn update_returns_at_once_and_the_tiles_arrive_on_later_calls() {
    let delay = Duration::from_millis(100);
    let r = reader(200, 150, 16, 100);
    let mut map = Clipmap::with_reader(r.clone(), CFG, UNIT).unwrap();
    let mut tex = Textures::new(CFG);
    let cam = down(100.0, 75.0);
    let t = Instant::now();
    let first = map.update(&cam);
    assert!(t.elapsed() < delay, "the first update waited {:?}", t.elapsed());
    assert_eq!(r.calls.load(Ordering::SeqCst), 0, "no tile was read before the first update returned");
    // The first call writes every level's whole window, all transparent: nothing is loaded yet.
    let texels: u32 = first.uploads.iter().map(|u| u.w * u.h).sum();
    assert_eq!(texels, 3 * 32 * 32);
    assert!(first.uploads.iter().all(|u| u.rgba.chunks(4).all(|t| t[3] == 0)));
    tex.apply(&first);
    let calls = run_until_complete(&mut map, &mut tex, &cam, delay);
    assert!(calls > 2, "tiles arrive over several calls, not at once ({calls})");
    let stats = map.stats();
    assert_eq!((stats.failed, stats.missing, stats.in_flight), (0, 0, 0), "{stats:?}");
    // Worked by hand (1 m texels, windows of 32, nearest even start): mip 0: 100 − 16 = 84,
    // 75 − 16 = 59 → 60; mip 1: 50 − 16 = 34, 37.5 − 16 = 21.5 → 22; mip 2: 25 − 16 = 9 → 10,
    // 18.75 − 16 = 2.75 → 2.
    let windows: Vec<_> = first.placements.iter().map(|p| (p.mip, p.origin.x, p.origin.y)).collect();
    assert_eq!(windows, [(0, 84, 60), (1, 34, 22), (2, 10, 2)]);
    // Each tile was read once.
    let reads = r.reads.lock().unwrap().clone();
    let mut unique = reads.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), reads.len(), "no tile is read twice");

    // Moving by 6 texels east: the next update writes 6 · 32 new texels per mip-0 level and
    // they arrive later; the textures end up complete again.
    let cam2 = down(106.0, 75.0);
    let frame = map.update(&cam2);
    let level0: u32 = frame.uploads.iter().filter(|u| u.level == 0).map(|u| u.w * u.h).sum();
    assert_eq!(level0, 6 * 32);
    tex.apply(&frame);
    run_until_complete(&mut map, &mut tex, &cam2, delay);
}

#[test]
fn requests_for_tiles_no_longer_in_view_are_cancelled() {
    let delay = Duration::from_millis(40);
    let r = reader(4096, 4096, 16, 40);
    let cfg = ClipmapConfig { levels: 1, size: 64 };
    let mut map = Clipmap::with_reader(r.clone(), cfg, UNIT).unwrap();
    // The first window needs 5 × 5 tiles; the camera leaves for the far corner at once.
    map.update(&down(100.0, 100.0));
    std::thread::sleep(Duration::from_millis(5));
    let mut tex = Textures::new(cfg);
    run_until_complete(&mut map, &mut tex, &down(3900.0, 3900.0), delay);
    let first_place = r.reads.lock().unwrap().iter().filter(|k| k.1 < 20 && k.2 < 20).count();
    assert!(first_place <= 2, "{first_place} tiles of the first place were read after it left the view");
    assert!(map.stats().cancelled >= 20, "{:?}", map.stats());
}

#[test]
fn a_missing_tile_stays_transparent_and_is_reported_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let img = dir.path().join("a.png");
    let data: Vec<u8> = (0..64 * 64 * 3).map(|i| (i % 200) as u8 + 10).collect();
    crate::aerial::raster::write_png(&img, 64, 64, 3, &data).unwrap();
    let pyr = dir.path().join("pyr");
    crate::aerial::tiles::tile_image(
        &img,
        &pyr,
        crate::aerial::tiles::TileOptions { tile: 16, force: false },
        &|_, _| {},
    )
    .unwrap();
    std::fs::remove_file(crate::aerial::tiles::tile_path(&pyr, 0, 1, 1)).unwrap();
    let cfg = ClipmapConfig { levels: 2, size: 32 };
    let mut map = Clipmap::open(&pyr, cfg, UNIT).unwrap();
    let mut tex = Textures::new(cfg);
    let cam = down(20.0, 20.0);
    let start = Instant::now();
    let mut placements = Vec::new();
    while map.stats().loaded + map.stats().failed < 8 || map.stats().in_flight > 0 {
        let f = map.update(&cam);
        tex.apply(&f);
        placements = f.placements;
        assert!(start.elapsed() < Duration::from_secs(20), "{:?}", map.stats());
        std::thread::sleep(Duration::from_millis(2));
    }
    let s = map.stats();
    assert_eq!(s.failed, 1, "{s:?}");
    let e = s.last_error.unwrap();
    assert!(e.contains("tile (1, 1) of mip 0") && !e.contains('\n'), "{e}");
    // Level 0's window starts at (4, 4); texel (20, 20) is in the missing tile, (5, 5) is not.
    assert_eq!(placements[0].origin, glam::IVec2::new(4, 4));
    assert_eq!(tex.levels[0][((20 * 32 + 20) * 4 + 3) as usize], 0, "the missing tile is transparent");
    let k = ((5 * 32 + 5) * 4) as usize;
    let want = &data[((5 * 64 + 5) * 3) as usize..][..3];
    assert_eq!(&tex.levels[0][k..k + 4], &[want[0], want[1], want[2], 255]);
}

#[test]
fn a_bad_configuration_or_pyramid_is_refused_in_one_line() {
    let r = reader(64, 64, 16, 0);
    for (cfg, needle) in
        [(ClipmapConfig { levels: 0, size: 32 }, "levels"), (ClipmapConfig { levels: 2, size: 48 }, "power of two")]
    {
        let e = Clipmap::with_reader(r.clone(), cfg, UNIT).err().unwrap().to_string();
        assert!(e.contains(needle), "{e}");
    }
    let bad = AerialPlacement { origin_m: DVec2::ZERO, gsd_m: 0.0 };
    assert!(Clipmap::with_reader(r, CFG, bad).is_err());
    let dir = tempfile::tempdir().unwrap();
    let e = Clipmap::open(dir.path(), CFG, UNIT).err().unwrap().to_string();
    assert!(e.contains("pyramid.ron") && !e.contains('\n'), "{e}");
}
