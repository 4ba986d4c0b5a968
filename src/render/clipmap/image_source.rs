//! [`ImageSource`]: a [`ClipmapSource`] over a whole small photograph held in memory, for
//! photographs up to [`MAX_SIDE`] texels a side (test pairs, small sites), and for the GPU half's
//! tests. Large photographs go through the tiled pyramid and its loader thread instead.
//!
//! The mip pyramid is built in memory by 2 × 2 box filtering. The levels are placed by the
//! concentric rule: level i shows mip i, centred on the ground point below the eye, its origin
//! snapped to multiples of an eighth of the level so small moves upload nothing. A level that
//! moves is written whole (one upload of `size` × `size` texels, toroidally arranged), which for
//! the small sizes served here costs less than tracking strips. Texels outside the photograph
//! are transparent (alpha 0).

use glam::IVec2;

use super::{AerialPlacement, ClipCamera, ClipmapConfig, ClipmapFrame, ClipmapSource, LevelPlacement, Upload};
use crate::render::error::ClipmapError;

/// The largest side of a photograph held whole in memory, texels.
pub const MAX_SIDE: u32 = 8192;

/// One mip of the pyramid: width, height and RGBA8 texels.
#[derive(Clone, Debug)]
struct Mip {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

/// A clipmap source over a small RGBA photograph in memory.
#[derive(Clone, Debug)]
pub struct ImageSource {
    config: ClipmapConfig,
    placement: AerialPlacement,
    mips: Vec<Mip>,
    /// Each level's placement as last uploaded.
    shown: Vec<Option<IVec2>>,
}

/// How a mip is made from the one below.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Downsample {
    /// The mean of 2 × 2 texels: photographs.
    Average,
    /// The top-left texel of each 2 × 2: data whose bytes must not be blended (the canopy's
    /// layer masks, one bit per layer).
    Nearest,
}

impl ImageSource {
    /// A source over `rgba` (`width` × `height` texels, RGBA8, rows top to bottom). Fails with
    /// one line for a size past [`MAX_SIDE`] or data of the wrong length.
    pub fn new(
        width: u32,
        height: u32,
        rgba: Vec<u8>,
        config: ClipmapConfig,
        placement: AerialPlacement,
    ) -> Result<ImageSource, ClipmapError> {
        ImageSource::with_downsample(width, height, rgba, config, placement, Downsample::Average)
    }

    /// [`ImageSource::new`] with the mips made by `down`.
    pub fn with_downsample(
        width: u32,
        height: u32,
        rgba: Vec<u8>,
        config: ClipmapConfig,
        placement: AerialPlacement,
        down: Downsample,
    ) -> Result<ImageSource, ClipmapError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(ClipmapError::MemorySide { width, height, max: MAX_SIDE });
        }
        if rgba.len() as u64 != u64::from(width) * u64::from(height) * 4 {
            return Err(ClipmapError::RgbaLength {
                width,
                height,
                expected: u64::from(width) * u64::from(height) * 4,
                found: rgba.len(),
            });
        }
        let mut mips = vec![Mip { width, height, rgba }];
        while mips.len() < config.levels as usize {
            let last = mips.last().expect("one mip");
            let next = if down == Downsample::Average { half(last) } else { nearest_half(last) };
            mips.push(next);
        }
        Ok(ImageSource { config, placement, mips, shown: vec![None; config.levels as usize] })
    }

    /// A source over an 8-bit RGB photograph, opaque.
    pub fn from_rgb(
        img: &crate::aerial::RgbImage,
        config: ClipmapConfig,
        placement: AerialPlacement,
    ) -> Result<ImageSource, ClipmapError> {
        let rgba = img.data.chunks_exact(3).flat_map(|t| [t[0], t[1], t[2], 255]).collect();
        ImageSource::new(img.width, img.height, rgba, config, placement)
    }

    /// The concentric placement of every level for `camera`: level i shows mip i with its
    /// window centred on the ground point below the eye, the origin snapped down to a multiple
    /// of `size / 8` texels.
    pub fn placements_for(&self, camera: &ClipCamera) -> Vec<LevelPlacement> {
        let n = self.config.size as i64;
        let snap = (n / 8).max(1);
        (0..self.config.levels)
            .map(|mip| {
                let texel = self.placement.gsd_m * f64::from(1u32 << mip);
                let centre = |c: f64, o: f64| ((c - o) / texel).floor() as i64;
                let cx = centre(camera.eye.x, self.placement.origin_m.x).clamp(-(1 << 40), 1 << 40);
                let cy = centre(camera.eye.z, self.placement.origin_m.y).clamp(-(1 << 40), 1 << 40);
                let o =
                    |c: i64| ((c - n / 2).div_euclid(snap) * snap).clamp(i32::MIN as i64, i32::MAX as i64 - n) as i32;
                LevelPlacement { mip, origin: IVec2::new(o(cx), o(cy)) }
            })
            .collect()
    }

    /// The whole window of `level` at `origin`, toroidally arranged: texture texel (tx, ty)
    /// holds the mip texel (u, v) of the window with u ≡ tx and v ≡ ty modulo the size.
    fn window(&self, level: u32, origin: IVec2) -> Upload {
        let n = self.config.size;
        let mip = &self.mips[level as usize];
        let mut rgba = vec![0u8; (n * n * 4) as usize];
        for ty in 0..n {
            let v = i64::from(origin.y) + (i64::from(ty) - i64::from(origin.y)).rem_euclid(i64::from(n));
            if v < 0 || v >= i64::from(mip.height) {
                continue;
            }
            for tx in 0..n {
                let u = i64::from(origin.x) + (i64::from(tx) - i64::from(origin.x)).rem_euclid(i64::from(n));
                if u < 0 || u >= i64::from(mip.width) {
                    continue;
                }
                let src = ((v as usize) * mip.width as usize + u as usize) * 4;
                let dst = ((ty * n + tx) * 4) as usize;
                rgba[dst..dst + 4].copy_from_slice(&mip.rgba[src..src + 4]);
            }
        }
        Upload { level, x: 0, y: 0, w: n, h: n, rgba }
    }
}

/// The next mip: the top-left texel of each 2 × 2.
fn nearest_half(m: &Mip) -> Mip {
    let (w, h) = (m.width.div_ceil(2).max(1), m.height.div_ceil(2).max(1));
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let s = (((2 * y) * m.width + 2 * x) * 4) as usize;
            rgba.extend_from_slice(&m.rgba[s..s + 4]);
        }
    }
    Mip { width: w, height: h, rgba }
}

/// The next mip: 2 × 2 box filtering (the last row or column repeated for odd sides).
fn half(m: &Mip) -> Mip {
    let (w, h) = (m.width.div_ceil(2).max(1), m.height.div_ceil(2).max(1));
    let mut rgba = vec![0u8; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            for c in 0..4 {
                let mut sum = 0u32;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let sx = (2 * x + dx).min(m.width - 1);
                    let sy = (2 * y + dy).min(m.height - 1);
                    sum += u32::from(m.rgba[((sy * m.width + sx) * 4 + c) as usize]);
                }
                rgba[((y * w + x) * 4 + c) as usize] = ((sum + 2) / 4) as u8;
            }
        }
    }
    Mip { width: w, height: h, rgba }
}

impl ClipmapSource for ImageSource {
    fn config(&self) -> ClipmapConfig {
        self.config
    }

    fn placement(&self) -> AerialPlacement {
        self.placement
    }

    fn update(&mut self, camera: &ClipCamera) -> ClipmapFrame {
        let placements = self.placements_for(camera);
        let mut uploads = Vec::new();
        for p in &placements {
            if self.shown[p.mip as usize] != Some(p.origin) {
                uploads.push(self.window(p.mip, p.origin));
                self.shown[p.mip as usize] = Some(p.origin);
            }
        }
        ClipmapFrame { placements, uploads }
    }
}

#[cfg(test)]
mod tests {
    use glam::{DVec2, DVec3};

    use super::*;

    fn camera(x: f64, z: f64) -> ClipCamera {
        ClipCamera { eye: DVec3::new(x, 50.0, z), forward: DVec3::NEG_Y, fov_y: 1.0, aspect: 1.0 }
    }

    fn source(w: u32, h: u32) -> ImageSource {
        // Texel (x, y) of mip 0 holds (x, y, 7, 255).
        let rgba = (0..h).flat_map(|y| (0..w).flat_map(move |x| [x as u8, y as u8, 7, 255])).collect();
        let placement = AerialPlacement { origin_m: DVec2::new(-10.0, -20.0), gsd_m: 0.5 };
        ImageSource::new(w, h, rgba, ClipmapConfig { levels: 3, size: 16 }, placement).unwrap()
    }

    #[test]
    fn levels_are_concentric_below_the_eye() {
        let s = source(64, 64);
        // The eye above world (0, 0): 10 m east and 20 m south of the corner, so mip 0 texel
        // (20, 40), mip 1 (10, 20), mip 2 (5, 10). Windows of 16 centred there, snapped to 2.
        let p = s.placements_for(&camera(0.0, 0.0));
        assert_eq!(p[0], LevelPlacement { mip: 0, origin: IVec2::new(12, 32) });
        assert_eq!(p[1], LevelPlacement { mip: 1, origin: IVec2::new(2, 12) });
        assert_eq!(p[2], LevelPlacement { mip: 2, origin: IVec2::new(-4, 2) });
    }

    #[test]
    fn a_window_is_stored_toroidally_and_transparent_outside() {
        let mut s = source(64, 64);
        let frame = s.update(&camera(0.0, 0.0));
        assert_eq!(frame.uploads.len(), 3);
        let up = &frame.uploads[0];
        // Window origin (12, 32): texture texel (tx, ty) holds mip texel (u, v) with u in
        // 12..28 and u ≡ tx (mod 16): tx = 3 → u = 19; ty = 5 → v = 37.
        let at = |u: &Upload, tx: u32, ty: u32| u.rgba[((ty * 16 + tx) * 4) as usize..][..4].to_vec();
        assert_eq!(at(up, 3, 5), vec![19, 37, 7, 255]);
        // Level 2 starts at x = -4: texture column 13 holds u = -3, outside the photograph.
        assert_eq!(at(&frame.uploads[2], 13, 5)[3], 0);
        // Nothing moved: nothing uploaded.
        assert!(s.update(&camera(0.1, 0.1)).uploads.is_empty());
        // Moving 1 m east moves the centre of mip 0 to texel 22 (origin 14), of mip 1 to 11
        // (origin 3, snapped to 2: unchanged) and of mip 2 to 5 (origin -3, snapped to -4:
        // unchanged): one upload.
        let moved = s.update(&camera(1.0, 0.0));
        assert_eq!(moved.uploads.len(), 1);
        assert_eq!(moved.placements[0].origin, IVec2::new(14, 32));
    }

    #[test]
    fn mips_average_texels() {
        let m = Mip { width: 2, height: 2, rgba: vec![0, 0, 0, 255, 4, 0, 0, 255, 0, 8, 0, 255, 0, 0, 12, 255] };
        assert_eq!(half(&m).rgba, vec![1, 2, 3, 255]);
        assert_eq!(nearest_half(&m).rgba, vec![0, 0, 0, 255]);
    }

    #[test]
    fn bad_sizes_are_refused() {
        let config = ClipmapConfig { levels: 2, size: 16 };
        let placement = AerialPlacement { origin_m: DVec2::ZERO, gsd_m: 1.0 };
        assert!(ImageSource::new(4, 4, vec![0; 10], config, placement).is_err());
        assert!(ImageSource::new(0, 4, vec![], config, placement).is_err());
    }
}
