//! The canopy's layer masks (issue #22): one treetop mask per canopy layer, the neighbourhood k
//! growing with height so that the upper layers keep only the crowns' cores and the crowns round
//! off towards the top, packed one bit per layer into a byte per texel (bit i: layer i, counted
//! from the crown base, is treetop there). Computed in memory from a [`Segmenter`].

use super::AerialError;
use super::mask::{MAX_K, MaskParams, Segmenter};

/// The most layers a byte holds.
pub const MAX_LAYERS: u32 = 8;

/// The window sides of `count` layers, odd, growing evenly from `k_base` (the lowest layer) to
/// `k_top` (the highest). Fails with one line for a count outside 1..=8 or a side that is not
/// odd and in 1..=255, or a top below the base.
pub fn layer_ks(count: u32, k_base: u32, k_top: u32) -> Result<Vec<u32>, AerialError> {
    if !(1..=MAX_LAYERS).contains(&count) {
        return Err(AerialError::LayerCount(count));
    }
    for k in [k_base, k_top] {
        if k == 0 || k % 2 == 0 || k > MAX_K {
            return Err(AerialError::WindowSide(k));
        }
    }
    if k_top < k_base {
        return Err(AerialError::KTop { top: k_top, base: k_base });
    }
    let steps = (k_top - k_base) / 2;
    Ok((0..count)
        .map(|i| {
            let f = if count > 1 { f64::from(i) / f64::from(count - 1) } else { 0.0 };
            k_base + 2 * (f64::from(steps) * f).round() as u32
        })
        .collect())
}

/// The packed layer masks: for each texel, bit i set where the treetop rule with window side
/// `ks[i]` (and the fractions `s`, `w`) holds.
pub fn layer_masks(seg: &Segmenter, ks: &[u32], s: f64, w: f64) -> Vec<u8> {
    let mut out = vec![0u8; seg.width as usize * seg.height as usize];
    for (i, &k) in ks.iter().enumerate().take(MAX_LAYERS as usize) {
        let mask = seg.mask(&MaskParams { k, s, w });
        for (o, m) in out.iter_mut().zip(&mask) {
            *o |= u8::from(*m != 0) << i;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aerial::RgbImage;

    #[test]
    fn window_sides_grow_evenly_and_stay_odd() {
        assert_eq!(layer_ks(6, 3, 13).unwrap(), vec![3, 5, 7, 9, 11, 13]);
        assert_eq!(layer_ks(3, 3, 31).unwrap(), vec![3, 17, 31]);
        assert_eq!(layer_ks(1, 5, 9).unwrap(), vec![5]);
        assert!(layer_ks(0, 3, 5).is_err() && layer_ks(9, 3, 5).is_err());
        assert!(layer_ks(4, 4, 9).is_err() && layer_ks(4, 9, 3).is_err());
    }

    #[test]
    fn a_green_square_shrinks_with_height() {
        // A 9 × 9 green square in summer, grey in winter, in a 21 × 21 grey field. A texel is
        // treetop when more than half its k × k window is green. k = 1: the whole square (81).
        // k = 5: a texel on the square's edge sees 3 green columns of 5, so it needs at least 5
        // green rows: the corners and their two edge neighbours drop (4 × 3), 69 remain. k = 9:
        // by rows and columns, a texel at distance a and b (0-based) from the nearest edges sees
        // (5 + a) × (5 + b) green texels, which must exceed 40.5: per corner the 8 texels with
        // (5 + a)(5 + b) <= 40, (a, b) in (0, 0..=3), (1, 0..=1), (2, 0), (3, 0), drop:
        // 81 − 4 × 8 = 49.
        let n = 21u32;
        let grey = [120u8, 120, 120];
        let summer: Vec<[u8; 3]> = (0..n * n)
            .map(|i| if (6..15).contains(&(i % n)) && (6..15).contains(&(i / n)) { [40, 160, 40] } else { grey })
            .collect();
        let winter = vec![grey; (n * n) as usize];
        let seg = Segmenter::new(
            &RgbImage::from_texels(n, n, &summer).unwrap(),
            &RgbImage::from_texels(n, n, &winter).unwrap(),
            false,
        )
        .unwrap();
        let packed = layer_masks(&seg, &[1, 5, 9], 0.5, 0.5);
        let count = |bit: u8| packed.iter().filter(|&&b| b & (1 << bit) != 0).count();
        assert_eq!((count(0), count(1), count(2)), (81, 69, 49));
        // No texel outside the square is set.
        assert!(
            packed
                .iter()
                .enumerate()
                .all(|(i, &b)| b == 0 || ((6..15).contains(&(i as u32 % n)) && (6..15).contains(&(i as u32 / n))))
        );
    }
}
