//! The pick shape of a tree model ([`PickShape`]): a stack of vertical cylinders, each as wide as
//! the model's vertices in its height band, so that every vertex lies inside.

use glam::{Vec2, Vec3};
use grove_systems::catalogue::{PICK_BANDS, PickShape};

/// Computes the pick shape of a model from its triangles (model space; `meshes` are pairs of
/// positions and triangle indices). The bands span the vertices' heights. A band's radius is the
/// largest horizontal distance from the Y axis of the surface inside it: the distance is convex,
/// so over a triangle cut to a band it is largest at a corner of the cut, which is a vertex in
/// the band or a point where an edge crosses the band's bottom or top. A small relative margin
/// covers rounding.
pub fn pick_shape(meshes: &[(&[Vec3], &[u32])]) -> PickShape {
    let all = || meshes.iter().flat_map(|(p, _)| p.iter());
    let bottom = all().map(|p| p.y).fold(f32::INFINITY, f32::min);
    let top = all().map(|p| p.y).fold(f32::NEG_INFINITY, f32::max);
    let (bottom, top) = if bottom < top { (bottom, top) } else { (0.0, 1.0) };
    let mut shape = PickShape { bottom, top, radii: [0.0; PICK_BANDS] };
    let h = shape.band_height();
    let mut grow = |band: usize, p: Vec3| shape.radii[band] = shape.radii[band].max(Vec2::new(p.x, p.z).length());
    for (positions, indices) in meshes {
        for p in positions.iter() {
            let i = (((p.y - bottom) / h) as usize).min(PICK_BANDS - 1);
            grow(i, *p);
        }
        for tri in indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b) = (positions[tri[k] as usize], positions[tri[(k + 1) % 3] as usize]);
                let (lo, hi) = if a.y <= b.y { (a, b) } else { (b, a) };
                // Every band boundary strictly between the edge's ends: the crossing point
                // belongs to the bands on both sides.
                for j in 1..PICK_BANDS {
                    let y = bottom + h * j as f32;
                    if lo.y < y && y < hi.y {
                        let p = lo.lerp(hi, (y - lo.y) / (hi.y - lo.y));
                        grow(j - 1, p);
                        grow(j, p);
                    }
                }
            }
        }
    }
    for r in &mut shape.radii {
        *r *= 1.0001;
    }
    shape
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trunk_under_a_cone_gives_thin_low_bands_and_narrowing_high_ones() {
        // A trunk of radius 0.2 from 0 to 3 m, and a cone from 3 m (radius 2) to 12 m (a point).
        let mut v = Vec::new();
        for i in 0..16 {
            let a = i as f32 * std::f32::consts::TAU / 16.0;
            for k in 0..=6 {
                v.push(Vec3::new(0.2 * a.cos(), k as f32 * 0.5, 0.2 * a.sin()));
            }
            for k in 0..=18 {
                let y = 3.0 + k as f32 * 0.5;
                let r = 2.0 * (12.0 - y) / 9.0;
                v.push(Vec3::new(r * a.cos(), y, r * a.sin()));
            }
        }
        // As triangles: each vertical pair of neighbours with the next ring's pair.
        let mut idx = Vec::new();
        let per_ring = 7 + 19;
        for i in 0..16u32 {
            let j = (i + 1) % 16;
            for k in 0..per_ring as u32 - 1 {
                let (a, b, c, d) = (
                    i * per_ring as u32 + k,
                    i * per_ring as u32 + k + 1,
                    j * per_ring as u32 + k,
                    j * per_ring as u32 + k + 1,
                );
                idx.extend([a, b, c, b, d, c]);
            }
        }
        let s = pick_shape(&[(&v, &idx)]);
        assert_eq!((s.bottom, s.top), (0.0, 12.0));
        // Bands of 1 m: the first three are the trunk.
        for i in 0..3 {
            assert!((s.radii[i] - 0.2).abs() < 1e-3, "band {i}: {:?}", s.radii);
        }
        // Band 3 (3 to 4 m) holds the cone's base; then each band is as wide as its bottom.
        for i in 3..12 {
            let want = 2.0 * (12.0 - i as f32) / 9.0;
            assert!((s.radii[i] - want).abs() < 1e-3, "band {i}: {} vs {want}", s.radii[i]);
        }
        let none = [0.0; PICK_BANDS];
        assert!(v.iter().all(|p| s.contains(*p, &none)));
        assert!(!s.contains(Vec3::new(1.0, 0.5, 0.0), &none), "beside the trunk");
        assert!(!s.contains(Vec3::new(1.5, 10.0, 0.0), &none), "beside the cone's top");
        assert!(s.contains(Vec3::new(1.05, 0.5, 0.0), &[1.0; PICK_BANDS]), "the pad grows the bands");
    }
}
