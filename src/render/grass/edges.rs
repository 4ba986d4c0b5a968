//! How far each corner of a shell lawn, or each blade of a blade lawn, lies inside its patch:
//! the lawn's edge (where the patch's polygon cuts it, a plane's outline, a hole's rim) fades
//! into the ground around it over the last [`EDGE_FADE`] metres. A shell lawn's strands grow
//! shorter and its layers more transparent there (`shells.wgsl`); a blade lawn's blades grow
//! shorter and fewer ([`fade_blades`]). Plain data in and out; units: metres, distances in (x, z).

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use grove_systems::grass::Blade;

use crate::render::mix::mix;

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

/// The edges of a patch (the edges of its triangles that belong to exactly one of them),
/// bucketed in cells of [`EDGE_FADE`] so that a point's distance to them looks at nine cells.
struct Edges {
    grid: HashMap<glam::IVec2, Vec<(Vec2, Vec2)>>,
}

fn cell(q: Vec2) -> glam::IVec2 {
    (q / EDGE_FADE).floor().as_ivec2()
}

impl Edges {
    fn new(triangles: &[[Vec3; 3]]) -> Edges {
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
        let mut grid: HashMap<glam::IVec2, Vec<(Vec2, Vec2)>> = HashMap::new();
        let mut edges: Vec<(Vec2, Vec2)> = count.values().filter(|e| e.0 == 1).map(|e| (e.1, e.2)).collect();
        // A fixed order, so the buckets (and the result) never depend on the map's.
        edges.sort_by(|p, q| {
            p.0.x
                .total_cmp(&q.0.x)
                .then(p.0.y.total_cmp(&q.0.y))
                .then(p.1.x.total_cmp(&q.1.x))
                .then(p.1.y.total_cmp(&q.1.y))
        });
        for (a, b) in edges {
            let (lo, hi) = (cell(a.min(b)), cell(a.max(b)));
            for x in lo.x..=hi.x {
                for z in lo.y..=hi.y {
                    grid.entry(glam::IVec2::new(x, z)).or_default().push((a, b));
                }
            }
        }
        Edges { grid }
    }

    /// The point's distance (in x, z) to the nearest edge over [`EDGE_FADE`], at most 1.
    fn share(&self, p: Vec3) -> f32 {
        let q = Vec2::new(p.x, p.z);
        let c = cell(q);
        let mut d = EDGE_FADE;
        for x in c.x - 1..=c.x + 1 {
            for z in c.y - 1..=c.y + 1 {
                for &(a, b) in self.grid.get(&glam::IVec2::new(x, z)).map_or(&[][..], |v| v.as_slice()) {
                    d = d.min(segment_distance(q, a, b));
                }
            }
        }
        d / EDGE_FADE
    }
}

/// For each corner of each triangle, its distance to the patch's edge (the edges that belong to
/// exactly one of `triangles`) over [`EDGE_FADE`], at most 1.
pub fn edge_shares(triangles: &[[Vec3; 3]]) -> Vec<[f32; 3]> {
    let edges = Edges::new(triangles);
    triangles.iter().map(|t| t.map(|p| edges.share(p))).collect()
}

/// A number in 0..1 fixed by a blade's root: which blades a thinning band keeps.
fn root_hash(p: Vec3) -> f32 {
    let h = mix((u64::from(p.x.to_bits()) << 32 | u64::from(p.z.to_bits())) ^ u64::from(p.y.to_bits()).rotate_left(17));
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// Fades a blade lawn into the ground along its edge (the edges of `triangles`, the patch's
/// ground): at `share` of [`EDGE_FADE`] from it, a blade is kept with probability
/// `smoothstep(0, 1, share)` (by a hash of its root; a blade left out gets height 0, so the
/// blades' count and order stay) and grows `sqrt(share)` of its height, as the shell lawn's
/// strands do. Blades beyond the band are unchanged.
pub fn fade_blades(triangles: &[[Vec3; 3]], blades: &mut [Blade]) {
    let edges = Edges::new(triangles);
    for b in blades {
        let s = edges.share(b.position);
        if s >= 1.0 {
            continue;
        }
        let keep = s * s * (3.0 - 2.0 * s);
        b.height = if root_hash(b.position) < keep { b.height * s.sqrt() } else { 0.0 };
    }
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
            tris.iter()
                .zip(&shares)
                .flat_map(|(t, s)| t.iter().zip(s))
                .find(|(p, _)| p.x == x && p.z == z)
                .map(|(_, s)| *s)
                .unwrap()
        };
        assert_eq!(at(0.0, 3.0), 0.0, "on the outline");
        assert!((at(1.0, 3.0) - 1.0 / EDGE_FADE).abs() < 1e-6, "a metre in");
        assert_eq!(at(3.0, 3.0), 1.0, "beyond the band");
        assert_eq!(at(5.0, 5.0), 0.0, "on the hole's rim");
        assert!((at(5.0, 4.0) - 1.0 / EDGE_FADE).abs() < 1e-6, "a metre from the hole");
        // Inner edges (shared by two triangles) are no edge: the middle of the lawn is whole.
        assert!(shares.iter().flatten().all(|s| (0.0..=1.0).contains(s)));
    }

    #[test]
    fn blades_grow_shorter_and_fewer_towards_the_edge_only() {
        // An 8 × 8 m square of 1 m cells with blades every 5 cm, all 0.3 m tall.
        let mut tris = Vec::new();
        for j in 0..8 {
            for i in 0..8 {
                let p = |x: i32, z: i32| Vec3::new(x as f32, 0.0, z as f32);
                tris.push([p(i, j), p(i, j + 1), p(i + 1, j)]);
                tris.push([p(i + 1, j), p(i, j + 1), p(i + 1, j + 1)]);
            }
        }
        let mut blades: Vec<Blade> = (0..160 * 160)
            .map(|k| Blade {
                position: Vec3::new((k % 160) as f32 * 0.05 + 0.025, 0.0, (k / 160) as f32 * 0.05 + 0.025),
                height: 0.3,
                yaw: 0.0,
                bend: 0.0,
                width: 0.01,
                variation: 0.5,
            })
            .collect();
        let before = blades.clone();
        fade_blades(&tris, &mut blades);
        assert_eq!(blades.len(), before.len());
        // The distance of a blade from the square's outline.
        let inset = |b: &Blade| b.position.x.min(b.position.z).min(8.0 - b.position.x).min(8.0 - b.position.z);
        let band = |lo: f32, hi: f32| blades.iter().filter(move |b| (lo..hi).contains(&inset(b)));
        let kept =
            |lo: f32, hi: f32| band(lo, hi).filter(|b| b.height > 0.0).count() as f32 / band(lo, hi).count() as f32;
        let mean = |lo: f32, hi: f32| band(lo, hi).map(|b| b.height).sum::<f32>() / band(lo, hi).count() as f32;
        // Beyond the band every blade is as it was.
        for (b, o) in blades.iter().zip(&before) {
            if inset(o) >= EDGE_FADE {
                assert_eq!(b, o);
            } else {
                assert!(b.height < o.height, "a blade {:.2} m from the edge keeps its height", inset(o));
            }
        }
        // Fewer and shorter towards the edge: kept share and mean height fall band by band.
        let (k0, k1, k2) = (kept(0.0, 0.2), kept(0.5, 0.7), kept(1.0, 1.2));
        assert!(k0 < 0.05 && k1 > 0.3 && k1 < 0.7 && k2 > 0.9, "kept {k0:.2}, {k1:.2}, {k2:.2}");
        let (m0, m1, m2) = (mean(0.0, 0.2), mean(0.5, 0.7), mean(1.0, 1.2));
        assert!(m0 < 0.01 && m0 < m1 && m1 < m2 && m2 < 0.3, "mean heights {m0:.3}, {m1:.3}, {m2:.3}");
        // The same blades give the same lawn.
        let mut again = before.clone();
        fade_blades(&tris, &mut again);
        assert_eq!(again, blades);
    }
}
