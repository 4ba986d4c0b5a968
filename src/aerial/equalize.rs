//! Per-channel histogram equalisation, in integers.
//!
//! For each channel of an image, with 256 bins, `cdf(v)` the number of texels of value at most
//! `v`, `cdf_min` the smallest non-zero cumulative count and `N` the texel count, a value maps to
//! `v' = round(255 · (cdf(v) − cdf_min) / (N − cdf_min))`, halves rounded up, computed exactly as
//! `(510 · (cdf(v) − cdf_min) + (N − cdf_min)) / (2 · (N − cdf_min))`. A constant channel
//! (`N = cdf_min`) is left as it is. Values below the channel's minimum do not occur in the image
//! and map to 0.
//!
//! The histogram is counted in parallel over bands of rows and summed; integer sums do not
//! depend on the order, so the result is the same on any thread count.

use rayon::prelude::*;

use super::raster::RgbImage;

/// Three lookup tables (R, G, B) from a value to its equalised value.
pub type Luts = [[u8; 256]; 3];

/// The identity tables (no equalisation).
pub const IDENTITY: Luts = {
    let mut t = [[0u8; 256]; 3];
    let mut v = 0;
    while v < 256 {
        t[0][v] = v as u8;
        t[1][v] = v as u8;
        t[2][v] = v as u8;
        v += 1;
    }
    t
};

/// Counts each channel's values: `[channel][value]`.
pub fn histograms(img: &RgbImage) -> [[u64; 256]; 3] {
    // Bands of about 1 MiB; each band counts into its own table, the tables are summed.
    let band = 3 * (1 << 18);
    img.data
        .par_chunks(band)
        .map(|chunk| {
            let mut h = [[0u32; 256]; 3];
            for t in chunk.chunks_exact(3) {
                h[0][t[0] as usize] += 1;
                h[1][t[1] as usize] += 1;
                h[2][t[2] as usize] += 1;
            }
            h
        })
        .fold(
            || [[0u64; 256]; 3],
            |mut acc, h| {
                for c in 0..3 {
                    for v in 0..256 {
                        acc[c][v] += h[c][v] as u64;
                    }
                }
                acc
            },
        )
        .reduce(
            || [[0u64; 256]; 3],
            |mut a, b| {
                for c in 0..3 {
                    for v in 0..256 {
                        a[c][v] += b[c][v];
                    }
                }
                a
            },
        )
}

/// The equalisation table of one channel's histogram (see the module docs for the formula).
pub fn lut_from_histogram(hist: &[u64; 256]) -> [u8; 256] {
    let n: u64 = hist.iter().sum();
    let cdf_min = hist.iter().copied().find(|&c| c > 0).unwrap_or(0);
    let mut lut = [0u8; 256];
    if n == cdf_min {
        // A constant (or empty) channel is left as it is.
        for (v, out) in lut.iter_mut().enumerate() {
            *out = v as u8;
        }
        return lut;
    }
    let denom = n - cdf_min;
    let mut cdf = 0u64;
    for v in 0..256 {
        cdf += hist[v];
        lut[v] = if cdf < cdf_min {
            0
        } else {
            let num = 510u128 * (cdf - cdf_min) as u128 + denom as u128;
            (num / (2 * denom as u128)) as u8
        };
    }
    lut
}

/// The equalisation tables of an image's three channels.
pub fn equalize_luts(img: &RgbImage) -> Luts {
    let h = histograms(img);
    [lut_from_histogram(&h[0]), lut_from_histogram(&h[1]), lut_from_histogram(&h[2])]
}

/// Applies tables to every texel, giving the equalised image.
pub fn apply(img: &RgbImage, luts: &Luts) -> RgbImage {
    let mut data = img.data.clone();
    data.par_chunks_mut(3 * 4096).for_each(|chunk| {
        for t in chunk.chunks_exact_mut(3) {
            t[0] = luts[0][t[0] as usize];
            t[1] = luts[1][t[1] as usize];
            t[2] = luts[2][t[2] as usize];
        }
    });
    RgbImage { width: img.width, height: img.height, data }
}
