//! The ground texture, widened: the 256² tile of `assets/env/ground.png` (2.5 m a repeat) blended
//! once, at load time, with a mirrored copy of itself at twice the size, the blend weight
//! varying smoothly across the result, into a texture [`WIDEN`] times the tile's size (10 m a
//! repeat). What the ground shader used to do per pixel with two more texture samples is then
//! one sample of this texture, and its repeat is four times longer. The weight is a sum of
//! sines with whole numbers of periods across the result, so the widened texture still tiles
//! without a seam. Units: texels; the texture is sRGB-encoded and blended as stored.

use image::RgbaImage;

/// How many tiles the widened texture spans on each side.
pub const WIDEN: u32 = 4;

/// The tile widened to `WIDEN` × its size, tiling seamlessly (see the module's documentation).
pub fn widen(tile: &RgbaImage) -> RgbaImage {
    let (w, h) = tile.dimensions();
    RgbaImage::from_fn(w * WIDEN, h * WIDEN, |x, y| widened_texel(tile, x, y))
}

/// The widened texture's texel `(x, y)`; beyond its size the texture repeats.
fn widened_texel(tile: &RgbaImage, x: u32, y: u32) -> image::Rgba<u8> {
    let (w, h) = tile.dimensions();
    let (big_w, big_h) = (w * WIDEN, h * WIDEN);
    let tau = std::f32::consts::TAU;
    // The mirrored copy at twice the size, sampled bilinearly: half a tile along and across,
    // so its pattern does not line up with the tile's.
    let copy = |x: f32, y: f32| -> [f32; 4] {
        let (fx, fy) = (x * 0.5 + w as f32 * 0.5 - 0.5, y * 0.5 + h as f32 * 0.25 - 0.5);
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let texel = |i: f32, j: f32| {
            // Mirrored: the tile read backwards on both axes, wrapping.
            let (i, j) = ((i as i64).rem_euclid(i64::from(w)) as u32, (j as i64).rem_euclid(i64::from(h)) as u32);
            tile.get_pixel(w - 1 - i, h - 1 - j).0.map(f32::from)
        };
        let (a, b, c, d) = (texel(x0, y0), texel(x0 + 1.0, y0), texel(x0, y0 + 1.0), texel(x0 + 1.0, y0 + 1.0));
        std::array::from_fn(|k| (a[k] * (1.0 - tx) + b[k] * tx) * (1.0 - ty) + (c[k] * (1.0 - tx) + d[k] * tx) * ty)
    };
    // Position across the widened texture, 0..1 on each axis (repeating beyond).
    let (u, v) = ((x % big_w) as f32 / big_w as f32, (y % big_h) as f32 / big_h as f32);
    let s1 = (tau * (u + 2.0 * v) + 0.3).sin();
    let s2 = (tau * (3.0 * u - v) + 1.1).sin();
    let s3 = (tau * (2.0 * u + 3.0 * v) + 2.0).sin();
    let weight = (0.45 + 0.3 * s1 * s2 + 0.2 * s3).clamp(0.0, 0.85);
    let a = tile.get_pixel(x % w, y % h).0;
    let b = copy(x as f32, y as f32);
    image::Rgba(std::array::from_fn(|k| {
        (f32::from(a[k]) * (1.0 - weight) + b[k] * weight).round().clamp(0.0, 255.0) as u8
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tile with a pattern that shows any seam or shift: a diagonal ramp in red, a checker in
    /// green, noise-like values in blue.
    fn tile() -> RgbaImage {
        RgbaImage::from_fn(16, 16, |x, y| {
            image::Rgba([
                ((x + y) * 8) as u8,
                if (x / 2 + y / 2) % 2 == 0 { 40 } else { 200 },
                ((x * 37 + y * 91) % 256) as u8,
                255,
            ])
        })
    }

    /// The largest difference of any channel between two pixels.
    fn diff(a: &image::Rgba<u8>, b: &image::Rgba<u8>) -> i32 {
        (0..4).map(|k| (i32::from(a.0[k]) - i32::from(b.0[k])).abs()).max().unwrap_or(0)
    }

    #[test]
    fn the_widened_texture_is_four_tiles_wide_and_keeps_the_tile_brightness() {
        let t = tile();
        let big = widen(&t);
        assert_eq!(big.dimensions(), (16 * WIDEN, 16 * WIDEN));
        // The mirrored copy holds the same texels, so the mean of each channel stays within a
        // few levels of the tile's (bilinear filtering and the blend move it a little).
        for k in 0..3 {
            let mean = |img: &RgbaImage| {
                img.pixels().map(|p| f64::from(p.0[k])).sum::<f64>() / f64::from(img.width() * img.height())
            };
            assert!((mean(&big) - mean(&t)).abs() < 12.0, "channel {k}: {} vs {}", mean(&big), mean(&t));
        }
        // Alpha stays opaque.
        assert!(big.pixels().all(|p| p.0[3] == 255));
    }

    #[test]
    fn the_widened_texture_tiles_without_a_seam() {
        let t = tile();
        let (w, h) = (16 * WIDEN, 16 * WIDEN);
        // The texel one period on, along either axis, is the same texel: the blend weight's
        // sines and the mirrored copy both have whole periods across the texture.
        for (x, y) in [(0, 0), (1, 7), (w - 1, 3), (5, h - 1), (w - 1, h - 1), (33, 21)] {
            let p = widened_texel(&t, x, y);
            assert!(diff(&p, &widened_texel(&t, x + w, y)) <= 1, "({x}, {y}) along x");
            assert!(diff(&p, &widened_texel(&t, x, y + h)) <= 1, "({x}, {y}) along y");
        }
        // Not periodic over one tile: the blend moved some texels by more than a few levels
        // from the tile's, so the tile's repeat is broken.
        let big = widen(&t);
        let moved = big.enumerate_pixels().map(|(x, y, p)| diff(p, t.get_pixel(x % 16, y % 16))).max().unwrap_or(0);
        assert!(moved > 20, "{moved}");
        // And one tile differs from the next.
        let shifted = (0..h)
            .flat_map(|y| (0..16).map(move |x| (x, y)))
            .filter(|&(x, y)| diff(big.get_pixel(x, y), big.get_pixel(x + 16, y)) > 10)
            .count();
        assert!(shifted > 100, "{shifted}");
    }
}
