//! Shell patches split into tiles, so that each frame draws a tile only where it can show: a
//! tile outside the view is skipped, rather than running the vertex shader for every triangle
//! of a large lawn and dropping most of them.
//!
//! Units: metres.

use glam::Vec3;

/// The most tiles a patch is split into.
pub const MAX_TILES: usize = 256;
/// The smallest tile edge, metres.
pub const MIN_TILE: f32 = 8.0;

/// A run of a patch's triangles, consecutive in its vertex buffer.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// The tile's first vertex in the patch's vertex buffer.
    pub first_vertex: u32,
    /// Its number of vertices (three a triangle).
    pub vertex_count: u32,
    /// The centre of a sphere around the tile's triangles, metres.
    pub centre: Vec3,
    /// That sphere's radius, metres.
    pub radius: f32,
}

/// Groups triangles into square tiles of at least [`MIN_TILE`] metres on the horizontal plane,
/// at most [`MAX_TILES`] of them: the triangles reordered tile by tile (indices into
/// `triangles`), and the tiles over that order.
pub fn tile_triangles(triangles: &[[Vec3; 3]]) -> (Vec<usize>, Vec<Tile>) {
    if triangles.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let centre = |t: &[Vec3; 3]| (t[0] + t[1] + t[2]) / 3.0;
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for t in triangles {
        let c = centre(t);
        lo = lo.min(c);
        hi = hi.max(c);
    }
    let side = (hi.x - lo.x).max(hi.z - lo.z);
    let per_axis = (MAX_TILES as f32).sqrt();
    let edge = (side / per_axis).max(MIN_TILE);
    let columns = ((hi.x - lo.x) / edge).floor() as usize + 1;
    let key = |t: &[Vec3; 3]| {
        let c = centre(t);
        let (i, j) = (((c.x - lo.x) / edge).floor() as usize, ((c.z - lo.z) / edge).floor() as usize);
        j * columns + i
    };
    let mut order: Vec<usize> = (0..triangles.len()).collect();
    order.sort_by_key(|&k| key(&triangles[k]));
    let mut tiles = Vec::new();
    let mut start = 0;
    while start < order.len() {
        let k = key(&triangles[order[start]]);
        let end = order[start..].iter().position(|&t| key(&triangles[t]) != k).map_or(order.len(), |n| start + n);
        let points = order[start..end].iter().flat_map(|&t| triangles[t]);
        let (mut a, mut b) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in points.clone() {
            a = a.min(p);
            b = b.max(p);
        }
        let c = (a + b) / 2.0;
        let radius = points.map(|p| p.distance(c)).fold(0.0, f32::max);
        tiles.push(Tile { first_vertex: 3 * start as u32, vertex_count: 3 * (end - start) as u32, centre: c, radius });
        start = end;
    }
    (order, tiles)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_cover_every_triangle_once_and_bound_it() {
        // A 100 × 100 m field of 2 × 2 m squares (two triangles each): 5,000 triangles.
        let mut tris = Vec::new();
        for i in 0..50 {
            for j in 0..50 {
                let (x, z) = (i as f32 * 2.0, j as f32 * 2.0);
                let (a, b, c, d) = (
                    Vec3::new(x, 0.0, z),
                    Vec3::new(x + 2.0, 0.0, z),
                    Vec3::new(x + 2.0, 0.5, z + 2.0),
                    Vec3::new(x, 0.0, z + 2.0),
                );
                tris.push([a, b, c]);
                tris.push([a, c, d]);
            }
        }
        let (order, tiles) = tile_triangles(&tris);
        let mut seen = order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..tris.len()).collect::<Vec<_>>());
        // 100 m over 16 tiles an axis is 6.25 m, below the 8 m minimum: 8 m tiles, 13 an axis.
        assert_eq!(tiles.len(), 13 * 13);
        assert!(tiles.len() <= MAX_TILES);
        let mut next = 0;
        for t in &tiles {
            assert_eq!(t.first_vertex, next, "tiles are consecutive");
            next += t.vertex_count;
            for &k in &order[(t.first_vertex / 3) as usize..((t.first_vertex + t.vertex_count) / 3) as usize] {
                for p in tris[k] {
                    assert!(p.distance(t.centre) <= t.radius + 1e-4, "{p} outside its tile's sphere");
                }
            }
            // The triangles' centres lie in an 8 m square and their corners within 2 m of their
            // centres: the box is at most 12 × 0.5 × 12 m, the sphere at most half its diagonal.
            assert!(t.radius <= 0.5 * (2.0 * 144.0f32 + 0.25).sqrt() + 1e-3, "{}", t.radius);
        }
        assert_eq!(next as usize, 3 * tris.len());
    }
}
