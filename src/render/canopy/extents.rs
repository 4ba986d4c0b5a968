//! How far each canopy layer of a crown reaches: the half-side of the square around the crown's
//! (shifted) photographed centre that holds every texel of the layer's mask bit, found once per
//! crown in the layer masks held in memory. The canopy draws each layer's quad only that wide,
//! and not at all where the layer has no treetop texel, so the upper layers (their k is larger,
//! their cores small) cost far fewer fragments than a square of the crown's full width. The
//! look is unchanged: the mask still decides the outline inside the quad.

use std::collections::HashMap;

use glam::Vec2;

use super::extract::CrownDraw;

/// How far beyond the crown's radius the canopy reads its mask, in radii (matches the `inside`
/// test of canopy.wgsl: texels further out belong to neighbouring crowns).
pub const READ_RADII: f32 = 1.2;

/// The widest quad, in radii (matches `SPREAD` in canopy.wgsl).
pub const SPREAD: f32 = 1.25;

/// The texture shift of layer 1 in texels along X and Z (matches canopy.wgsl): layer i reads the
/// photograph `i` times this far from the crown's centre.
pub const SHIFT_TEXELS: Vec2 = Vec2::new(0.35, 0.2);

/// The layer masks' bits, one byte per texel (bit i: layer i is treetop), rows from the top,
/// and where they lie: texel `(0, 0)` has its top-left corner at `origin_m` (world X, Z) and
/// texels are `gsd_m` metres wide.
pub struct LayerBits {
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `width × height` bytes.
    pub bits: Vec<u8>,
    /// World (X, Z) of the top-left corner, metres.
    pub origin_m: Vec2,
    /// Metres per texel.
    pub gsd_m: f32,
}

impl LayerBits {
    /// The half-side of each of `layers` layers' squares of the crown centred at `centre`
    /// (world X, Z) with radius `radius_m`, metres: for layer i, the largest Chebyshev
    /// distance from `centre + i · SHIFT_TEXELS · gsd` of the far edge of a texel whose centre
    /// lies within `READ_RADII` radii of it and whose bit i is set; 0 where there is none. At
    /// most `SPREAD` radii.
    pub fn extents(&self, centre: Vec2, radius_m: f32, layers: u32) -> [f32; 8] {
        let mut out = [0.0f32; 8];
        let reach = READ_RADII * radius_m;
        for (i, e) in out.iter_mut().enumerate().take(layers.min(8) as usize) {
            let c = centre + SHIFT_TEXELS * self.gsd_m * i as f32;
            // The texels whose centres may lie within reach, clamped to the image.
            let lo = ((c - Vec2::splat(reach) - self.origin_m) / self.gsd_m - Vec2::splat(0.5)).floor();
            let hi = ((c + Vec2::splat(reach) - self.origin_m) / self.gsd_m - Vec2::splat(0.5)).ceil();
            let (x0, y0) = (lo.x.max(0.0) as u32, lo.y.max(0.0) as u32);
            let (x1, y1) = (hi.x.min(self.width as f32 - 1.0), hi.y.min(self.height as f32 - 1.0));
            if x1 < 0.0 || y1 < 0.0 {
                continue;
            }
            let (x1, y1) = (x1 as u32, y1 as u32);
            for y in y0..=y1 {
                let row = &self.bits[(y as usize * self.width as usize)..][..self.width as usize];
                for x in x0..=x1 {
                    if (row[x as usize] >> i) & 1 == 0 {
                        continue;
                    }
                    let t = self.origin_m + (Vec2::new(x as f32, y as f32) + Vec2::splat(0.5)) * self.gsd_m;
                    let d = (t - c).abs().max_element();
                    if d <= reach {
                        *e = e.max(d + 0.5 * self.gsd_m);
                    }
                }
            }
            *e = e.min(SPREAD * radius_m);
        }
        out
    }
}

/// The layers' extents of the crowns seen so far, by photographed centre and radius (a moved
/// crown keeps both, so its extents stay found).
pub(crate) struct ExtentCache {
    bits: Option<LayerBits>,
    layers: u32,
    found: HashMap<(u32, u32, u32), [f32; 8]>,
}

impl ExtentCache {
    /// A cache over `bits` for `layers` layers; without bits every layer is `SPREAD` radii wide.
    pub fn new(bits: Option<LayerBits>, layers: u32) -> ExtentCache {
        ExtentCache { bits, layers, found: HashMap::new() }
    }

    /// The extents of crown `c`'s layers, metres.
    pub fn get(&mut self, c: &CrownDraw) -> [f32; 8] {
        let Some(bits) = &self.bits else { return [SPREAD * c.radius_m; 8] };
        let key = (c.photo_centre.x.to_bits(), c.photo_centre.y.to_bits(), c.radius_m.to_bits());
        *self.found.entry(key).or_insert_with(|| bits.extents(c.photo_centre, c.radius_m, self.layers))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extents_hold_each_layers_bits_around_the_crown() {
        // 20 × 20 texels of 1 m from the origin. Layer 0 is set on texels x, y in 6..=13 (a
        // square whose edges are 4 m from the centre (10, 10)); layer 1 on the texel (11, 10)
        // alone; layer 2 nowhere near; a far texel (0, 0) has every bit (another crown's).
        let mut bits = vec![0u8; 400];
        for y in 6..=13 {
            for x in 6..=13 {
                bits[y * 20 + x] |= 1;
            }
        }
        bits[10 * 20 + 11] |= 2;
        bits[0] = 0xff;
        let b = LayerBits { width: 20, height: 20, bits, origin_m: Vec2::ZERO, gsd_m: 1.0 };
        let e = b.extents(Vec2::new(10.0, 10.0), 5.0, 3);
        // Layer 0: texel centres 6.5..13.5, so 3.5 m from 10 plus half a texel: 4 m.
        assert!((e[0] - 4.0).abs() < 1e-5, "{e:?}");
        // Layer 1 reads around (10.35, 10.2): the texel centred at (11.5, 10.5) is 1.15 m away
        // along X; its far edge 1.65 m.
        assert!((e[1] - 1.65).abs() < 1e-5, "{e:?}");
        // Layer 2: nothing within 6 m (the texel at (0.5, 0.5) is 9.5 m away).
        assert_eq!(e[2], 0.0);
        assert_eq!(e[3..], [0.0; 5]);
        // A small radius caps the extent at 1.25 radii: layer 0 within 1.2 · 3 = 3.6 m holds
        // texels up to 3.5 m away (edge 4 m), capped at 3.75 m.
        let e = b.extents(Vec2::new(10.0, 10.0), 3.0, 1);
        assert!((e[0] - 3.75).abs() < 1e-5, "{e:?}");
        // A crown off the image's corner reads only the texels inside it.
        let e = b.extents(Vec2::new(-3.0, -3.0), 5.0, 8);
        assert!((e[0] - 4.0).abs() < 1e-5, "{e:?}");
    }
}
