//! How far each corner of a shell lawn lies inside its patch: the lawn's edge (where the patch's
//! polygon cuts it, a plane's outline, a hole's rim) fades into the ground around it, its
//! strands shorter and its layers more transparent over the last [`EDGE_FADE`] metres
//! (`shells.wgsl`). Plain data in and out; units: metres, distances in (x, z).

use std::collections::HashMap;

use glam::{Vec2, Vec3};

/// The width of the band along a lawn's edge over which it fades, metres.
pub const EDGE_FADE: f32 = 1.2;

/// A point's key: its position in tenths of a millimetre, so that the corners two triangles
/// share compare equal.
fn key(p: Vec3) -> [i64; 3] {
    p.to_array().map(|c| (c as f64 * 1e4).round() as i64)
}

fn segment_distance(q: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let t = ((q - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
    q.distance(a + ab * t)
}

/// For each corner of each triangle, its distance to the patch's edge (the edges that belong to
/// exactly one of `triangles`) over [`EDGE_FADE`], at most 1.
pub fn edge_shares(triangles: &[[Vec3; 3]]) -> Vec<[f32; 3]> {
    let mut count: HashMap<([i64; 3], [i64; 3]), (u32, Vec2, Vec2)> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (ka, kb) = (key(a), key(b));
            let id = if ka <= kb { (ka, kb) } else { (kb, ka) };
            count.entry(id).or_insert((0, Vec2::new(a.x, a.z), Vec2::new(b.x, b.z))).0 += 1;
        }
    }
    // The edge's segments in cells of EDGE_FADE, each in every cell its box touches.
    let cell = |q: Vec2| (q / EDGE_FADE).floor().as_ivec2();
    let mut grid: HashMap<glam::IVec2, Vec<(Vec2, Vec2)>> = HashMap::new();
    let mut edges: Vec<(Vec2, Vec2)> = count.values().filter(|e| e.0 == 1).map(|e| (e.1, e.2)).collect();
    // A fixed order, so the buckets (and the result) never depend on the map's.
    edges.sort_by(|p, q| p.0.x.total_cmp(&q.0.x).then(p.0.y.total_cmp(&q.0.y)).then(p.1.x.total_cmp(&q.1.x)).then(p.1.y.total_cmp(&q.1.y)));
    for (a, b) in edges {
        let (lo, hi) = (cell(a.min(b)), cell(a.max(b)));
        for x in lo.x..=hi.x {
            for z in lo.y..=hi.y {
                grid.entry(glam::IVec2::new(x, z)).or_default().push((a, b));
            }
        }
    }
    let share = |p: Vec3| {
        let q = Vec2::new(p.x, p.z);
        let c = cell(q);
        let mut d = EDGE_FADE;
        for x in c.x - 1..=c.x + 1 {
            for z in c.y - 1..=c.y + 1 {
                for &(a, b) in grid.get(&glam::IVec2::new(x, z)).map_or(&[][..], |v| v.as_slice()) {
                    d = d.min(segment_distance(q, a, b));
                }
            }
        }
        d / EDGE_FADE
    };
    triangles.iter().map(|t| t.map(share)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_fade_towards_the_patch_edge_only() {
        // A 10 × 10 m square of 1 m cells, two triangles each, with a 1 m square hole at its
        // middle (cell (5, 5) left out).
        let mut tris = Vec::new();
        for j in 0..10 {
            for i in 0..10 {
                if (i, j) == (5, 5) {
                    continue;
                }
                let p = |x: i32, z: i32| Vec3::new(x as f32, 0.0, z as f32);
                tris.push([p(i, j), p(i, j + 1), p(i + 1, j)]);
                tris.push([p(i + 1, j), p(i, j + 1), p(i + 1, j + 1)]);
            }
        }
        let shares = edge_shares(&tris);
        let at = |x: f32, z: f32| {
            tris.iter().zip(&shares).flat_map(|(t, s)| t.iter().zip(s)).find(|(p, _)| p.x == x && p.z == z).map(|(_, s)| *s).unwrap()
        };
        assert_eq!(at(0.0, 3.0), 0.0, "on the outline");
        assert!((at(1.0, 3.0) - 1.0 / EDGE_FADE).abs() < 1e-6, "a metre in");
        assert_eq!(at(3.0, 3.0), 1.0, "beyond the band");
        assert_eq!(at(5.0, 5.0), 0.0, "on the hole's rim");
        assert!((at(5.0, 4.0) - 1.0 / EDGE_FADE).abs() < 1e-6, "a metre from the hole");
        // Inner edges (shared by two triangles) are no edge: the middle of the lawn is whole.
        assert!(shares.iter().flatten().all(|s| (0.0..=1.0).contains(s)));
    }
}
