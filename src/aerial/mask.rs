//! The treetop rule: green flags and k × k neighbourhood counts.
//!
//! A texel is green when G > R and G > B, strictly, after the optional equalisation. Over the
//! k × k window centred on a texel (k odd, clipped at the border, n texels inside), the texel
//! is a treetop when `green_summer > s · n` and `not_green_winter > w · n`.
//!
//! The counts come from running sums: the image is cut into bands of [`BAND`] rows, processed in
//! parallel; each band keeps one running column sum per column (the flags of the k rows around
//! the current row, updated by adding the row entering the window and subtracting the row
//! leaving it) and takes each row's window count from a prefix sum over those column sums. The
//! work per texel is the same for every k, and every result is an integer computed the same way
//! on any thread count, so the mask is identical on one thread or many.
//!
//! [`Segmenter`] computes the flags once and then gives the mask for any (k, s, w), which the
//! canopy layers of the aerial renderer use with k growing with height.

use rayon::prelude::*;

use super::AerialError;
use super::equalize::{IDENTITY, Luts, equalize_luts};
use super::raster::RgbImage;

/// Rows per band of parallel work.
pub const BAND: usize = 64;

/// The largest window side accepted.
pub const MAX_K: u32 = 255;

/// The parameters of the treetop rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaskParams {
    /// The window side in texels, odd, 1..=[`MAX_K`].
    pub k: u32,
    /// A treetop needs more than `s · n` green summer texels in its window, 0 ≤ s < 1.
    pub s: f64,
    /// A treetop needs more than `w · n` not-green winter texels in its window, 0 ≤ w < 1.
    pub w: f64,
}

impl Default for MaskParams {
    fn default() -> Self {
        MaskParams { k: 3, s: 0.5, w: 0.5 }
    }
}

impl MaskParams {
    /// Checks the parameters; a one-line message for the first problem.
    pub fn validate(&self) -> Result<(), AerialError> {
        if self.k == 0 || self.k % 2 == 0 || self.k > MAX_K {
            return Err(AerialError::K(self.k));
        }
        for (name, v) in [("s", self.s), ("w", self.w)] {
            if !(v.is_finite() && (0.0..1.0).contains(&v)) {
                return Err(AerialError::Fraction { name, value: v });
            }
        }
        Ok(())
    }
}

/// The green flags of an image through lookup tables: 1 where G > R and G > B, else 0.
pub fn green_flags(img: &RgbImage, luts: &Luts) -> Vec<u8> {
    flags_where(img, luts, 0)
}

/// Green flags XOR `invert` (0: 1 where green; 1: 1 where not green), in one pass.
fn flags_where(img: &RgbImage, luts: &Luts, invert: u8) -> Vec<u8> {
    let mut flags = vec![0u8; img.texels()];
    flags.par_chunks_mut(1 << 16).enumerate().for_each(|(i, out)| {
        let start = i * (1 << 16) * 3;
        let texels = &img.data[start..start + out.len() * 3];
        for (f, t) in out.iter_mut().zip(texels.chunks_exact(3)) {
            let g = luts[1][t[1] as usize];
            *f = ((g > luts[0][t[0] as usize]) & (g > luts[2][t[2] as usize])) as u8 ^ invert;
        }
    });
    flags
}

/// A registered summer and winter pair, reduced to its flags, ready to give masks.
#[derive(Clone, Debug)]
pub struct Segmenter {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// 1 where the summer texel is green.
    pub summer_green: Vec<u8>,
    /// 1 where the winter texel is not green.
    pub winter_not_green: Vec<u8>,
}

impl Segmenter {
    /// Computes the flags of a pair, equalising each image first when `equalize` is set. The two
    /// images must be of the same size.
    pub fn new(summer: &RgbImage, winter: &RgbImage, equalize: bool) -> Result<Segmenter, AerialError> {
        if (summer.width, summer.height) != (winter.width, winter.height) {
            return Err(AerialError::PairSize {
                summer: (summer.width, summer.height),
                winter: (winter.width, winter.height),
            });
        }
        let (ls, lw) = if equalize {
            rayon::join(|| equalize_luts(summer), || equalize_luts(winter))
        } else {
            (IDENTITY, IDENTITY)
        };
        let (summer_green, winter_not_green) =
            rayon::join(|| flags_where(summer, &ls, 0), || flags_where(winter, &lw, 1));
        Ok(Segmenter { width: summer.width, height: summer.height, summer_green, winter_not_green })
    }

    /// The treetop mask for `p` (assumed valid): 255 treetop, 0 not, one byte per texel.
    pub fn mask(&self, p: &MaskParams) -> Vec<u8> {
        window_rule(&self.summer_green, &self.winter_not_green, self.width as usize, self.height as usize, p)
    }
}

/// The largest integer count that is *not* more than `frac · n`: a count c passes when
/// c > frac · n, which for an integer c is c > floor(frac · n).
fn threshold(frac: f64, n: usize) -> u32 {
    (frac * n as f64).floor() as u32
}

/// The rule over two flag planes (values 0 or 1) of `width × height`: 255 where the window
/// count of `a` exceeds `p.s · n` and that of `b` exceeds `p.w · n`.
pub fn window_rule(a: &[u8], b: &[u8], width: usize, height: usize, p: &MaskParams) -> Vec<u8> {
    assert_eq!(a.len(), width * height, "flag plane size");
    assert_eq!(b.len(), width * height, "flag plane size");
    let mut out = vec![0u8; width * height];
    if width == 0 || height == 0 {
        return out;
    }
    let r = (p.k / 2) as usize;
    out.par_chunks_mut(width * BAND).enumerate().for_each(|(band_index, band)| {
        let y0 = band_index * BAND;
        let rows = band.len() / width;
        fn row(plane: &[u8], width: usize, y: usize) -> &[u8] {
            &plane[y * width..(y + 1) * width]
        }
        // Column sums over the window's rows of the band's first row.
        let mut col_a = vec![0u16; width];
        let mut col_b = vec![0u16; width];
        for y in y0.saturating_sub(r)..=(y0 + r).min(height - 1) {
            add_row(&mut col_a, row(a, width, y));
            add_row(&mut col_b, row(b, width, y));
        }
        let mut pre_a = vec![0u32; width + 1];
        let mut pre_b = vec![0u32; width + 1];
        for dy in 0..rows {
            let y = y0 + dy;
            prefix(&mut pre_a, &col_a);
            prefix(&mut pre_b, &col_b);
            let nh = (y + r).min(height - 1) - y.saturating_sub(r) + 1;
            let out_row = &mut band[dy * width..(dy + 1) * width];
            // Texels whose window is clipped left or right.
            let edge = |x: usize| -> u8 {
                let (xl, xh) = (x.saturating_sub(r), (x + r).min(width - 1));
                let n = nh * (xh - xl + 1);
                let ca = pre_a[xh + 1] - pre_a[xl];
                let cb = pre_b[xh + 1] - pre_b[xl];
                if ca > threshold(p.s, n) && cb > threshold(p.w, n) { 255 } else { 0 }
            };
            if width > 2 * r {
                for x in (0..r).chain(width - r..width) {
                    out_row[x] = edge(x);
                }
                // The interior: every window holds nh · k texels.
                let n = nh * p.k as usize;
                let (ta, tb) = (threshold(p.s, n), threshold(p.w, n));
                let span = 2 * r + 1;
                let inner = &mut out_row[r..width - r];
                let hi_a = &pre_a[span..];
                let hi_b = &pre_b[span..];
                for (i, o) in inner.iter_mut().enumerate() {
                    let ca = hi_a[i] - pre_a[i];
                    let cb = hi_b[i] - pre_b[i];
                    *o = (((ca > ta) & (cb > tb)) as u8).wrapping_neg();
                }
            } else {
                for (x, o) in out_row.iter_mut().enumerate() {
                    *o = edge(x);
                }
            }
            // Slide the window down one row.
            if dy + 1 < rows {
                if y >= r {
                    sub_row(&mut col_a, row(a, width, y - r));
                    sub_row(&mut col_b, row(b, width, y - r));
                }
                if y + 1 + r < height {
                    add_row(&mut col_a, row(a, width, y + 1 + r));
                    add_row(&mut col_b, row(b, width, y + 1 + r));
                }
            }
        }
    });
    out
}

fn add_row(col: &mut [u16], flags: &[u8]) {
    for (c, &f) in col.iter_mut().zip(flags) {
        *c += f as u16;
    }
}

fn sub_row(col: &mut [u16], flags: &[u8]) {
    for (c, &f) in col.iter_mut().zip(flags) {
        *c -= f as u16;
    }
}

fn prefix(pre: &mut [u32], col: &[u16]) {
    let mut sum = 0u32;
    pre[0] = 0;
    for (p, &c) in pre[1..].iter_mut().zip(col) {
        sum += c as u32;
        *p = sum;
    }
}

/// Convenience: the treetop mask of a pair in one call.
pub fn treetop_mask(
    summer: &RgbImage,
    winter: &RgbImage,
    equalize: bool,
    p: &MaskParams,
) -> Result<Vec<u8>, AerialError> {
    p.validate()?;
    Ok(Segmenter::new(summer, winter, equalize)?.mask(p))
}
