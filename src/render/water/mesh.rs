//! The water's geometry and its ripple texture: each body's outline triangulated (a constrained
//! Delaunay triangulation from `spade`, keeping the triangles inside the outline) at its surface
//! height, and a tileable normal map of small waves, made once on the CPU.
//!
//! Units: metres; the outline is (X, Z); +Y up.

use glam::{Vec2, Vec3};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::extract::WaterDraw;

/// One vertex of the water mesh (matches the vertex inputs of water.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct WaterVertex {
    /// Position on the surface, world metres.
    pub position: [f32; 3],
    /// The deep colour (linear RGB) and the body's depth, metres.
    pub colour_depth: [f32; 4],
    /// Ripple strength (0 = still) and drift speed, metres per second.
    pub ripple: [f32; 2],
}

/// The triangles that fill a simple polygon, as (X, Z) corner triples; empty for a polygon the
/// triangulation refuses.
pub fn triangulate(polygon: &[Vec2]) -> Vec<[Vec2; 3]> {
    let points: Vec<Point2<f64>> = polygon.iter().map(|p| Point2::new(f64::from(p.x), f64::from(p.y))).collect();
    let n = points.len();
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    // The scene loader checked that the outline is simple, so no constraint conflicts arise;
    // should one, it is skipped rather than panicking.
    let Ok(cdt) = ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(points, edges, |_| {}) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for face in cdt.inner_faces() {
        let p = face.positions().map(|q| Vec2::new(q.x as f32, q.y as f32));
        let centre = (p[0] + p[1] + p[2]) / 3.0;
        // The triangulation fills the convex hull; keep what lies inside the outline.
        if grove_systems::water::contains(polygon, centre) {
            out.push(p);
        }
    }
    out
}

/// The vertices (three per triangle) of every water body.
pub fn build(bodies: &[WaterDraw]) -> Vec<WaterVertex> {
    let mut v = Vec::new();
    for b in bodies {
        let colour_depth = [b.colour[0], b.colour[1], b.colour[2], b.depth];
        for tri in triangulate(&b.polygon) {
            for p in tri {
                v.push(WaterVertex {
                    position: [p.x, b.height, p.y],
                    colour_depth,
                    ripple: [b.ripples, b.ripple_speed],
                });
            }
        }
    }
    v
}

/// Edge of the ripple normal map, texels.
pub const NORMAL_MAP_SIZE: u32 = 128;

/// A tileable normal map of small waves, RGBA8 (tangent space: X right, Y along the texture's
/// v, Z up, each as 0.5 + 0.5 × component): the slopes of a sum of sine waves whose wave
/// vectors are whole numbers of periods over the tile, so it repeats without a seam.
pub fn normal_map() -> Vec<u8> {
    // (periods along u, periods along v, amplitude, phase): a few long waves and many short ones.
    const WAVES: [(f32, f32, f32, f32); 8] = [
        (1.0, 2.0, 0.30, 0.0),
        (-2.0, 1.0, 0.25, 1.3),
        (3.0, -1.0, 0.16, 2.1),
        (1.0, 4.0, 0.12, 0.7),
        (-4.0, -3.0, 0.08, 4.0),
        (5.0, 2.0, 0.07, 5.2),
        (-3.0, 6.0, 0.05, 3.3),
        (7.0, -5.0, 0.04, 0.4),
    ];
    let n = NORMAL_MAP_SIZE as usize;
    let mut out = Vec::with_capacity(n * n * 4);
    let tau = std::f32::consts::TAU;
    for j in 0..n {
        for i in 0..n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            // The height's gradient in height units per tile.
            let mut g = Vec2::ZERO;
            for (ku, kv, a, ph) in WAVES {
                let c = (tau * (ku * u + kv * v) + ph).cos();
                g += Vec2::new(ku, kv) * (a * tau * c);
            }
            // Scaled so that the steepest slopes lean the normal by about 45°.
            let nrm = Vec3::new(-g.x * 0.15, -g.y * 0.15, 1.0).normalize();
            for c in [nrm.x, nrm.y, nrm.z] {
                out.push(((c * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8);
            }
            out.push(255);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(t: &[Vec2; 3]) -> f32 {
        ((t[1] - t[0]).perp_dot(t[2] - t[0]) * 0.5).abs()
    }

    #[test]
    fn a_concave_outline_is_filled_exactly() {
        // An L of area 12 m²: the triangles cover it and nothing of its notch.
        let l = [
            Vec2::new(0.0, 0.0),
            Vec2::new(4.0, 0.0),
            Vec2::new(4.0, 2.0),
            Vec2::new(2.0, 2.0),
            Vec2::new(2.0, 4.0),
            Vec2::new(0.0, 4.0),
        ];
        let tris = triangulate(&l);
        let total: f32 = tris.iter().map(area).sum();
        assert!((total - 12.0).abs() < 1e-4, "area {total}");
        assert_eq!(tris.len(), 4, "a hexagon needs n − 2 triangles");
    }

    #[test]
    fn the_normal_map_tiles_and_leans_both_ways() {
        let m = normal_map();
        let n = NORMAL_MAP_SIZE as usize;
        assert_eq!(m.len(), n * n * 4);
        // Every normal points up; some lean left and some right.
        let texel = |i: usize, j: usize| &m[(j * n + i) * 4..(j * n + i) * 4 + 4];
        assert!((0..n).all(|i| texel(i, 3)[2] > 128));
        assert!((0..n).any(|i| texel(i, 5)[0] < 100) && (0..n).any(|i| texel(i, 5)[0] > 156));
        // The last column continues into the first: neighbours across the seam are close.
        let seam = (0..n).map(|j| (i32::from(texel(n - 1, j)[0]) - i32::from(texel(0, j)[0])).abs()).max().unwrap();
        let inside =
            (0..n).map(|j| (i32::from(texel(n / 2, j)[0]) - i32::from(texel(n / 2 + 1, j)[0])).abs()).max().unwrap();
        assert!(seam <= inside + 4, "seam step {seam}, inner step {inside}");
    }
}
