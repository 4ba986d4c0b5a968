//! The ground as a landscape around the planes (drawn only; not collidable and not in the world
//! hash): the sides of every plane (earth banks under its outline and pits under its holes,
//! down to a floor: [`super::banks`]), the dark soil floor under the planes that shows through
//! the holes, and terrain from the planes' edge out to the far plane, which the shader fades
//! into the sky.
//!
//! A vertex is 8 floats: position (metres), normal, its kind ([`KIND_PLANE`] …), which the
//! ground shader shades differently, and a shade (a factor of the albedo: 1, less at the bottom
//! of a pit's walls); the ground adds each vertex's [`Tint`] when it uploads the mesh. Units: metres; +Y up.

use glam::{Vec2, Vec3};
use noise::{NoiseFn, Perlin};

/// A vertex of a plane.
pub const KIND_PLANE: f32 = 0.0;
/// A vertex of a plane's soil side: the cut under its outer edge, a pit's wall.
pub const KIND_SIDE: f32 = 1.0;
/// A vertex of the terrain around the planes.
pub const KIND_TERRAIN: f32 = 2.0;
/// A vertex of the soil floor under the planes, seen through holes.
pub const KIND_FLOOR: f32 = 3.0;
/// A vertex of a bank's grassed slope, under a plane's soil edge.
pub const KIND_BANK: f32 = 4.0;

/// How far the floor lies below the lowest plane, metres.
pub const FLOOR_DEPTH: f32 = 0.6;
/// How far the terrain reaches beyond the planes' rectangle, metres (the camera's far plane is
/// 600 m away).
pub const TERRAIN_REACH: f32 = 650.0;

/// A mesh being built: vertices of 8 floats and triangle indices.
#[derive(Default)]
pub struct LandMesh {
    /// Position, normal, kind, shade (a factor of the albedo, 1 but at the bottom of a pit).
    pub vertices: Vec<[f32; 8]>,
    /// Triangles, counter-clockwise seen from the side the normal points to.
    pub indices: Vec<u32>,
}

impl LandMesh {
    /// Adds a quad `a b c d` (in order around it) with one normal for all four corners, wound so
    /// that its front faces the normal.
    pub fn quad(&mut self, corners: [Vec3; 4], normal: Vec3, kind: f32) {
        self.quad_shaded(corners, normal, kind, [1.0; 4]);
    }

    /// [`LandMesh::quad`] with a shade for each corner.
    pub fn quad_shaded(&mut self, corners: [Vec3; 4], normal: Vec3, kind: f32, shade: [f32; 4]) {
        let base = self.vertices.len() as u32;
        for (p, s) in corners.into_iter().zip(shade) {
            self.vertices.push([p.x, p.y, p.z, normal.x, normal.y, normal.z, kind, s]);
        }
        let [a, b, c, _] = corners;
        let front = (b - a).cross(c - a).dot(normal) >= 0.0;
        let order: [u32; 6] = if front { [0, 1, 2, 0, 2, 3] } else { [0, 2, 1, 0, 3, 2] };
        self.indices.extend(order.iter().map(|i| base + i));
    }
}

/// The ground's variation at scales larger than its texture's repeat (2.5 m), computed per
/// vertex so that the fragment shader takes one texture sample: a brightness that varies over
/// about 12 m (the detail, only where the terrain is cut finely enough to carry it; on planes
/// of coarse triangles over three of their edges, [`Tint::for_mesh`]) and over about 70 m, and a
/// hue between greener and browner over about 150 m.
pub struct Tint {
    /// The detail's wavelength, metres.
    detail_scale: f32,
    detail: Perlin,
    broad: Perlin,
    hue: Perlin,
}

/// The wavelengths of the tint's three variations, metres: detail, broad brightness, hue.
pub const TINT_SCALES: [f32; 3] = [12.0, 70.0, 150.0];

impl Default for Tint {
    fn default() -> Self {
        Tint { detail_scale: TINT_SCALES[0], detail: Perlin::new(11), broad: Perlin::new(12), hue: Perlin::new(13) }
    }
}

impl Tint {
    /// The tint for planes whose coarsest mesh has triangle edges of `mean_edge` metres on
    /// average: the detail's wavelength at least three edges, so linear interpolation between
    /// vertices carries it (the forest's 10 m cells: 30 m).
    pub fn for_mesh(mean_edge: f32) -> Tint {
        Tint { detail_scale: TINT_SCALES[0].max(3.0 * mean_edge), ..Tint::default() }
    }

    /// The albedo factor (linear RGB, about 0.6 to 1.4) at `p` (x, z in metres), with the
    /// detail scale weighted by `detail` (0 to 1).
    pub fn at(&self, p: Vec2, detail: f32) -> [f32; 3] {
        let n = |f: &Perlin, scale: f32, offset: f64| {
            f.get([f64::from(p.x / scale) + offset, f64::from(p.y / scale) - offset]) as f32
        };
        let b =
            1.0 + 0.35 * detail * n(&self.detail, self.detail_scale, 0.31) + 0.3 * n(&self.broad, TINT_SCALES[1], 0.57);
        let h = n(&self.hue, TINT_SCALES[2], 0.13);
        [b * (1.0 + 0.25 * h), b, b * (1.0 - 0.3 * h)]
    }
}

/// How much of the tint's detail scale a vertex at `p` carries: all of it on and near the
/// rectangle `lo..hi` (x, z), where the mesh is dense, fading to none at the outer edge of the
/// near band, beyond which the terrain's cells are too large for it.
pub fn detail_weight(p: Vec2, lo: Vec2, hi: Vec2) -> f32 {
    let outside = (lo - p).max(p - hi).max(Vec2::ZERO).length();
    1.0 - smoothstep(NEAR_BAND / 3.0, NEAR_BAND, outside)
}

/// The mean length of the edges of `triangles` over `vertices`, metres (0 without triangles;
/// indices out of range are skipped).
pub fn mean_edge(vertices: &[Vec3], triangles: &[[u32; 3]]) -> f32 {
    let (mut sum, mut n) = (0.0f64, 0u32);
    for t in triangles {
        let Some(p) = t.iter().map(|&i| vertices.get(i as usize).copied()).collect::<Option<Vec<Vec3>>>() else {
            continue;
        };
        for k in 0..3 {
            sum += f64::from(p[k].distance(p[(k + 1) % 3]));
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { (sum / f64::from(n)) as f32 }
}

/// Hermite interpolation from 0 at `a` to 1 at `b` (as WGSL's `smoothstep`).
fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The largest side of a terrain cell in the near band and alongside the planes, metres: small
/// enough for the tint's detail scale to vary smoothly across it.
pub const NEAR_CELL: f32 = 4.0;

/// The largest side of a terrain cell, metres: the shader computes the aerial perspective per
/// vertex, so the cells must be small enough for it to vary linearly across them.
pub const TERRAIN_CELL: f32 = 40.0;
/// The width of the ring of terrain next to the planes drawn with the planes' full shading
/// (shadows, every texture scale), metres; beyond it the terrain is drawn with the cheap
/// far-ground shading.
pub const NEAR_BAND: f32 = 30.0;

/// Grid lines from `a` to `b` (`a < b`) no more than `cell` apart, both ends included, evenly
/// spaced.
fn lines(a: f32, b: f32, cell: f32) -> Vec<f32> {
    let n = ((b - a) / cell).ceil().max(1.0) as usize;
    (0..=n).map(|i| if i == n { b } else { a + (b - a) * i as f32 / n as f32 }).collect()
}

/// The grid lines of one axis: from `lo - reach` to the near band, through the band and the
/// rectangle `lo..hi`, and out to `hi + reach`, no more than [`TERRAIN_CELL`] apart.
fn axis_lines(lo: f32, hi: f32) -> Vec<f32> {
    let band = NEAR_BAND.min(TERRAIN_REACH);
    let hi = hi.max(lo + 1e-3);
    let mut v = lines(lo - TERRAIN_REACH, lo - band, TERRAIN_CELL);
    for part in [
        lines(lo - band, lo, TERRAIN_CELL),
        lines(lo, hi, TERRAIN_CELL),
        lines(hi, hi + band, TERRAIN_CELL),
        lines(hi + band, hi + TERRAIN_REACH, TERRAIN_CELL),
    ] {
        v.extend_from_slice(&part[1..]);
    }
    v
}

/// The soil floor under the rectangle `lo..hi` (x, z) at `floor_y`, and the terrain around it
/// at `ground_y`, reaching [`TERRAIN_REACH`] beyond it in every direction, as cells no larger
/// than [`TERRAIN_CELL`]. The terrain within [`NEAR_BAND`] of the rectangle goes into `mesh`, cut
/// into cells no larger than [`NEAR_CELL`]; the rest into `far`, which the ground draws with its
/// cheap far-ground shading.
pub fn surroundings(mesh: &mut LandMesh, far: &mut LandMesh, lo: Vec2, hi: Vec2, ground_y: f32, floor_y: f32) {
    let at = |x: f32, z: f32, y: f32| Vec3::new(x, y, z);
    mesh.quad(
        [at(lo.x, lo.y, floor_y), at(hi.x, lo.y, floor_y), at(hi.x, hi.y, floor_y), at(lo.x, hi.y, floor_y)],
        Vec3::Y,
        KIND_FLOOR,
    );
    let (xs, zs) = (axis_lines(lo.x, hi.x), axis_lines(lo.y, hi.y));
    let g = ground_y;
    let band = NEAR_BAND.min(TERRAIN_REACH);
    for w in zs.windows(2) {
        for u in xs.windows(2) {
            let centre = Vec2::new((u[0] + u[1]) * 0.5, (w[0] + w[1]) * 0.5);
            let inside =
                |m: f32| centre.x > lo.x - m && centre.x < hi.x + m && centre.y > lo.y - m && centre.y < hi.y + m;
            if inside(0.0) {
                continue;
            }
            if !inside(band) {
                far.quad(
                    [at(u[0], w[0], g), at(u[1], w[0], g), at(u[1], w[1], g), at(u[0], w[1], g)],
                    Vec3::Y,
                    KIND_TERRAIN,
                );
                continue;
            }
            // A cell of the near band, cut into cells of at most NEAR_CELL. Their corners on the
            // cell's edge lie on the straight edges of the neighbouring cells, all at one height.
            let (xs, zs) = (lines(u[0], u[1], NEAR_CELL), lines(w[0], w[1], NEAR_CELL));
            for b in zs.windows(2) {
                for a in xs.windows(2) {
                    mesh.quad(
                        [at(a[0], b[0], g), at(a[1], b[0], g), at(a[1], b[1], g), at(a[0], b[1], g)],
                        Vec3::Y,
                        KIND_TERRAIN,
                    );
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_terrain_surrounds_the_rectangle_without_covering_it() {
        let (mut near, mut far) = (LandMesh::default(), LandMesh::default());
        surroundings(&mut near, &mut far, Vec2::new(-5.0, -5.0), Vec2::new(5.0, 5.0), 0.0, -0.6);
        // Terrain area: the big square less the rectangle.
        let mut area = 0.0;
        for (m, is_far) in [(&near, false), (&far, true)] {
            for (q, tri) in m.indices.chunks(3).enumerate() {
                let p: Vec<Vec3> = tri
                    .iter()
                    .map(|&i| {
                        Vec3::new(m.vertices[i as usize][0], m.vertices[i as usize][1], m.vertices[i as usize][2])
                    })
                    .collect();
                if m.vertices[tri[0] as usize][6] == KIND_TERRAIN {
                    area += 0.5 * f64::from((p[1] - p[0]).cross(p[2] - p[0]).length());
                    // No terrain triangle's centre lies inside the rectangle.
                    let c = (p[0] + p[1] + p[2]) / 3.0;
                    assert!(c.x.abs() >= 5.0 || c.z.abs() >= 5.0, "triangle {q} at {c}");
                    // The far part lies beyond the near band, the near part within it.
                    let out = c.x.abs().max(c.z.abs()) - 5.0;
                    assert_eq!(is_far, out > NEAR_BAND, "triangle {q} at {c}");
                    // No side of a cell is longer than a cell (the diagonal excepted): 40 m far
                    // away, 4 m in the near band.
                    let cell = if is_far { TERRAIN_CELL } else { NEAR_CELL };
                    for k in 0..3 {
                        let e = p[(k + 1) % 3] - p[k];
                        assert!(e.x.abs() <= cell + 1e-3 && e.z.abs() <= cell + 1e-3, "{e}");
                    }
                }
            }
        }
        let side = 10.0 + 2.0 * f64::from(TERRAIN_REACH);
        // Within the rounding of f32 corners over some two thousand cells.
        assert!((area - (side * side - 100.0)).abs() < 1e-4 * side * side, "{area}");
    }

    #[test]
    fn the_detail_weight_is_whole_on_the_planes_and_gone_at_the_band_edge() {
        let (lo, hi) = (Vec2::new(-5.0, -5.0), Vec2::new(5.0, 5.0));
        assert_eq!(detail_weight(Vec2::ZERO, lo, hi), 1.0);
        assert_eq!(detail_weight(Vec2::new(5.0, -5.0), lo, hi), 1.0);
        // Within a third of the band: still whole.
        assert_eq!(detail_weight(Vec2::new(5.0 + NEAR_BAND / 3.0, 0.0), lo, hi), 1.0);
        // At the band's edge (also diagonally off a corner) and beyond: none.
        assert_eq!(detail_weight(Vec2::new(0.0, -5.0 - NEAR_BAND), lo, hi), 0.0);
        let corner = Vec2::new(5.0, 5.0) + Vec2::splat(NEAR_BAND / 2f32.sqrt());
        assert!(detail_weight(corner, lo, hi) < 1e-6);
        assert_eq!(detail_weight(Vec2::new(300.0, 0.0), lo, hi), 0.0);
        // Falling steadily in between.
        let mut last = 1.0;
        for i in 0..=30 {
            let w = detail_weight(Vec2::new(5.0 + i as f32, 0.0), lo, hi);
            assert!(w <= last + 1e-6, "{w} after {last} at {i} m");
            last = w;
        }
    }

    #[test]
    fn the_tint_varies_around_one_and_its_detail_only_where_weighted() {
        let tint = Tint::default();
        let (mut sum, mut n, mut detail_change, mut lo, mut hi) = (0.0f64, 0, 0.0f64, f32::MAX, f32::MIN);
        // A 400 m square in 2 m steps (Perlin noise has no fixed period to alias with).
        for i in 0..200 {
            for j in 0..200 {
                let p = Vec2::new(i as f32 * 2.0 - 200.0 + 0.37, j as f32 * 2.0 - 200.0 + 0.61);
                let [r, g, b] = tint.at(p, 1.0);
                for c in [r, g, b] {
                    lo = lo.min(c);
                    hi = hi.max(c);
                }
                sum += f64::from(g);
                n += 1;
                detail_change += f64::from((g - tint.at(p, 0.0)[1]).abs());
            }
        }
        let mean = sum / f64::from(n);
        // Brightness about 1 on average, and really varying, but within what the amplitudes
        // allow for noise within ±1: brightness 1 ± (0.35 + 0.3), the hue's factor 1 ± 0.3.
        assert!((mean - 1.0).abs() < 0.1, "{mean}");
        assert!(lo > 0.35 * 0.7 && hi < 1.65 * 1.3, "{lo}..{hi}");
        assert!(hi - lo > 0.3, "{lo}..{hi}");
        // The detail scale changes the tint by a few per cent on average, and nothing at weight 0.
        let detail_change = detail_change / f64::from(n);
        assert!(detail_change > 0.02 && detail_change < 0.35, "{detail_change}");
        // The same tint from a second instance: fixed seeds, so every run builds the same mesh.
        let p = Vec2::new(12.3, -4.5);
        assert_eq!(tint.at(p, 1.0), Tint::default().at(p, 1.0));
        // Smooth: points 1 m apart differ less than points 6 m apart, so 4 m cells carry it.
        let near: f64 = (0..100)
            .map(|k| {
                let q = Vec2::new(k as f32 * 7.1, k as f32 * 3.3);
                f64::from((tint.at(q, 1.0)[1] - tint.at(q + Vec2::new(1.0, 0.0), 1.0)[1]).abs())
            })
            .sum();
        let far: f64 = (0..100)
            .map(|k| {
                let q = Vec2::new(k as f32 * 7.1, k as f32 * 3.3);
                f64::from((tint.at(q, 1.0)[1] - tint.at(q + Vec2::new(6.0, 0.0), 1.0)[1]).abs())
            })
            .sum();
        assert!(near < far, "1 m apart {near}, 6 m apart {far}");
    }

    #[test]
    fn the_detail_widens_on_coarse_meshes() {
        // A 2 m grid square: edges 2, 2 and the 2.83 m diagonal; the third triangle's index is
        // out of range and skipped.
        let v = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 2.0), Vec3::new(0.0, 0.0, 2.0)];
        let t = [[0, 3, 1], [1, 3, 2], [0, 1, 99]];
        let e = mean_edge(&v, &t);
        assert!((e - (4.0 + 8f32.sqrt()) / 3.0).abs() < 1e-5, "{e}");
        assert_eq!(mean_edge(&v, &[]), 0.0);
        // Fine meshes keep the 12 m detail; 10 m cells take 30 m.
        assert_eq!(Tint::for_mesh(e).detail_scale, 12.0);
        assert_eq!(Tint::for_mesh(10.0).detail_scale, 30.0);
        // So between vertices 10 m apart the coarse tint changes less than the fine one.
        let step = |tint: &Tint| -> f64 {
            (0..200)
                .map(|k| {
                    let q = Vec2::new(k as f32 * 10.0, 3.7);
                    f64::from((tint.at(q, 1.0)[1] - tint.at(q + Vec2::new(10.0, 0.0), 1.0)[1]).abs())
                })
                .sum()
        };
        assert!(step(&Tint::for_mesh(10.0)) < step(&Tint::default()));
    }
}
