//! Impostors: far trees drawn as one textured quad each.
//!
//! - **Bake** ([`bake`]): when a model is loaded, it is drawn from [`GRID`]×[`GRID`] directions
//!   over the upper hemisphere (a hemi-octahedral layout: [`hemi_oct_encode`]) into two atlases:
//!   albedo with coverage alpha (sRGB), and the model-space normal with the depth across the
//!   model's bounding sphere in alpha. Each view is orthographic, fitted to that sphere.
//! - **Level of detail** ([`fade`]): a tree whose bounding sphere covers fewer than
//!   `impostor_pixels` pixels on screen is an impostor; between that and [`BAND`] times as many
//!   it is both, with a screen-door cross-fade: the mesh keeps the pixels whose dither
//!   (`impostor_dither` in `octa.wgsl`) is at least the tree's fade, the impostor the others. So
//!   a tree crossing the band trades pixels one by one instead of popping.
//! - **Draw** ([`draw`]): each impostor is a quad facing the camera (or the sun in the shadow
//!   map) showing the three atlas views around that direction blended by barycentric weights
//!   (so views change without a jump), alpha-tested, lit with the baked normals at the baked
//!   depth (the shadow map gets the quad's own depth), and leaned by the tree's wind state
//!   (`WindState::bend`) as its trunk would be.
//!
//! - **Cache** ([`cache`]): the atlases are kept on disk, keyed by the model's content and the
//!   bake, so each model is baked once.
//!
//! Directions are model space (+Y up, metres); the quad turns with the tree's yaw.

pub mod bake;
pub mod cache;
pub(crate) mod draw;

use glam::{UVec2, Vec2, Vec3, Vec4};

/// The views along each side of the atlas (`IMPOSTOR_GRID` in `octa.wgsl`).
pub const GRID: u32 = 8;

/// The edge of one view in the atlas, texels.
pub const CELL: u32 = 160;

/// A model's impostor atlases and its bounding sphere.
pub struct Atlas {
    /// Albedo and coverage, [`bake::ALBEDO_FORMAT`], `GRID * CELL` texels square.
    pub albedo: wgpu::Texture,
    /// Normal and depth, [`bake::NORMAL_FORMAT`].
    pub normal: wgpu::Texture,
    /// The bounding sphere's centre, model-space metres.
    pub centre: Vec3,
    /// Its radius, metres.
    pub radius: f32,
    /// The model's extent in each view ([`view_rects`]), row-major.
    pub rects: Vec<glam::Vec4>,
    /// The impostor shader's group 2 (set by [`draw::ImpostorGpu::bind`]).
    pub(crate) bind_group: Option<wgpu::BindGroup>,
}

/// Mip levels of the atlases: each is baked by drawing the model again at its size (views of
/// 160, 80, 40, 20 and 10 texels), so far impostors sample a small, cache-friendly level.
pub const MIP_LEVELS: u32 = 5;

/// The width of the cross-fade band: a tree is fully a mesh above `BAND` times the impostor
/// threshold (pixels on screen) and fully an impostor below the threshold.
pub const BAND: f32 = 1.25;

/// A direction with `y >= 0` to the square `[-1, 1]²` (the CPU twin of `hemi_oct_encode`).
pub fn hemi_oct_encode(d: Vec3) -> Vec2 {
    let a = d / (d.x.abs() + d.y.abs() + d.z.abs()).max(1e-6);
    Vec2::new(a.x + a.z, a.z - a.x)
}

/// A point of `[-1, 1]²` to a unit direction with `y >= 0` (the twin of `hemi_oct_decode`).
pub fn hemi_oct_decode(e: Vec2) -> Vec3 {
    let x = (e.x - e.y) * 0.5;
    let z = (e.x + e.y) * 0.5;
    Vec3::new(x, (1.0 - x.abs() - z.abs()).max(0.0), z).normalize()
}

/// The atlas cell (column, row) whose view is nearest to the direction `d` (model space).
pub fn cell(d: Vec3) -> UVec2 {
    let e = hemi_oct_encode(Vec3::new(d.x, d.y.max(0.0), d.z));
    let c = ((e * 0.5 + 0.5) * GRID as f32).floor().clamp(Vec2::ZERO, Vec2::splat(GRID as f32 - 1.0));
    c.as_uvec2()
}

/// The direction towards the viewer of the view in cell `c`.
pub fn cell_dir(c: UVec2) -> Vec3 {
    hemi_oct_decode((c.as_vec2() + 0.5) / GRID as f32 * 2.0 - 1.0)
}

/// The right and up axes of the view looking along `-d` (`d` points to the viewer), as the
/// bake and the impostor shader build them.
pub fn view_basis(d: Vec3) -> (Vec3, Vec3) {
    let up_ref = if d.y.abs() > 0.999 { Vec3::NEG_Z } else { Vec3::Y };
    let right = up_ref.cross(d).normalize();
    (right, d.cross(right))
}

/// The extent of the model in each atlas view, as `(min x, min y, max x, max y)` in units of
/// the bounding sphere's radius (within `-1..=1`), grown by a texel: the impostor quad is cut
/// to it, so no fragment is spent on the empty corners of the view. Cells in row-major order.
pub fn view_rects(positions: &[Vec3], centre: Vec3, radius: f32) -> Vec<Vec4> {
    let texel = 2.0 / CELL as f32;
    (0..GRID * GRID)
        .map(|k| {
            let d = cell_dir(UVec2::new(k % GRID, k / GRID));
            let (right, up) = view_basis(d);
            let (mut lo, mut hi) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
            for p in positions {
                let rel = *p - centre;
                let q = Vec2::new(rel.dot(right), rel.dot(up)) / radius;
                lo = lo.min(q);
                hi = hi.max(q);
            }
            if lo.x > hi.x {
                return Vec4::new(-1.0, -1.0, 1.0, 1.0);
            }
            let lo = (lo - texel).max(Vec2::splat(-1.0));
            let hi = (hi + texel).min(Vec2::splat(1.0));
            Vec4::new(lo.x, lo.y, hi.x, hi.y)
        })
        .collect()
}

/// A tree's share drawn as an impostor, 0 (all mesh) to 1 (all impostor): `diameter` is its
/// bounding sphere's diameter in metres (scaled with the tree), `distance` the camera's distance
/// in metres, `pixels_per_radian` as in [`super::lod::keep_fraction`]. A threshold of 0 turns
/// impostors off.
pub fn fade(diameter: f32, distance: f32, pixels_per_radian: f32, impostor_pixels: f32) -> f32 {
    fade_in_band(diameter, distance, pixels_per_radian, impostor_pixels, BAND)
}

/// The share handed from one level of detail to the next, coarser one, 0 to 1, as [`fade`] with
/// a band of `band` times the threshold `pixels_below` (the same rule serves the cross-fade from
/// a model to its far model, `super::instances`). A band of 1 or less is a hard switch: 1 below
/// the threshold, 0 at or above it.
pub fn fade_in_band(diameter: f32, distance: f32, pixels_per_radian: f32, pixels_below: f32, band: f32) -> f32 {
    if pixels_below <= 0.0 || !(diameter > 0.0) {
        return 0.0;
    }
    let pixels = diameter * pixels_per_radian / distance.max(0.01);
    if band <= 1.0 {
        return if pixels < pixels_below { 1.0 } else { 0.0 };
    }
    let hi = pixels_below * band;
    ((hi - pixels) / (hi - pixels_below)).clamp(0.0, 1.0)
}

/// The interleaved gradient noise of a pixel (the twin of `impostor_dither`).
pub fn dither(x: u32, y: u32) -> f32 {
    let v = (x as f32 * 0.067_110_56 + y as f32 * 0.005_837_15).fract();
    (52.982_918 * v).fract()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_and_decode_are_inverse_over_the_hemisphere() {
        for i in 0..=40 {
            for j in 0..=80 {
                let el = i as f32 / 40.0 * std::f32::consts::FRAC_PI_2;
                let az = j as f32 / 80.0 * std::f32::consts::TAU;
                let d = Vec3::new(el.cos() * az.cos(), el.sin(), el.cos() * az.sin());
                let e = hemi_oct_encode(d);
                assert!(e.x.abs() <= 1.0 + 1e-5 && e.y.abs() <= 1.0 + 1e-5, "{d:?} -> {e:?}");
                let back = hemi_oct_decode(e);
                assert!((back - d).length() < 1e-4, "{d:?} -> {e:?} -> {back:?}");
            }
        }
    }

    #[test]
    fn every_cell_direction_falls_in_its_own_cell() {
        let mut seen = std::collections::HashSet::new();
        for r in 0..GRID {
            for c in 0..GRID {
                let d = cell_dir(UVec2::new(c, r));
                assert!(d.y >= 0.0 && (d.length() - 1.0).abs() < 1e-5);
                assert_eq!(cell(d), UVec2::new(c, r));
                let (right, up) = view_basis(d);
                // An orthonormal, right-handed frame looking along -d.
                assert!(right.dot(up).abs() < 1e-5 && right.dot(d).abs() < 1e-5 && up.dot(d).abs() < 1e-5);
                assert!((right.cross(up) - d).length() < 1e-4);
                seen.insert((d * 1000.0).round().as_ivec3());
            }
        }
        assert_eq!(seen.len(), (GRID * GRID) as usize, "the views are distinct");
        // A horizontal view from +X lands on the square's edge, the zenith in its middle.
        let z = cell(Vec3::Y);
        assert!(z.x == GRID / 2 || z.x == GRID / 2 - 1);
        assert!(cell_dir(cell(Vec3::X)).x > 0.8);
    }

    #[test]
    fn view_rects_hold_the_model_and_little_else() {
        // A thin vertical pole 10 m tall: from the side its view is a narrow, tall strip; from
        // near the zenith a small square about the centre.
        let pts: Vec<Vec3> =
            (0..=10).flat_map(|h| [Vec3::new(-0.1, h as f32, 0.0), Vec3::new(0.1, h as f32, 0.0)]).collect();
        let centre = Vec3::new(0.0, 5.0, 0.0);
        let radius = (0.1f32 * 0.1 + 25.0).sqrt();
        let rects = view_rects(&pts, centre, radius);
        let side = rects[(4 * GRID + 7) as usize];
        assert!(side.z - side.x < 0.2 && side.w - side.y > 1.5, "{side:?}");
        for r in &rects {
            assert!(r.x >= -1.0 && r.y >= -1.0 && r.z <= 1.0 && r.w <= 1.0 && r.x < r.z && r.y < r.w);
        }
    }

    #[test]
    fn fade_crosses_the_band_linearly() {
        // A 10 m tree seen with 1000 px per radian covers 100 px at 100 m.
        let f = |d: f32| fade(10.0, d, 1000.0, 60.0);
        assert_eq!(f(100.0), 0.0, "100 px is above the band (60..75 px)");
        assert_eq!(f(10_000.0 / 60.0), 1.0);
        assert_eq!(f(1000.0), 1.0);
        // 67.5 px: halfway through the band.
        assert!((f(10_000.0 / 67.5) - 0.5).abs() < 1e-5);
        assert_eq!(fade(10.0, 1000.0, 1000.0, 0.0), 0.0, "0 turns impostors off");
        // Without a band the switch is hard, at the threshold.
        let hard = |d: f32| fade_in_band(10.0, d, 1000.0, 60.0, 1.0);
        assert_eq!((hard(10_000.0 / 61.0), hard(10_000.0 / 59.0)), (0.0, 1.0));
        // Monotone in the distance.
        let mut last = 0.0;
        for k in 0..400 {
            let v = f(100.0 + k as f32);
            assert!(v >= last);
            last = v;
        }
    }

    #[test]
    fn dither_thresholds_are_spread_evenly() {
        // Over a 64×64 block, each tenth of 0..1 holds about a tenth of the pixels, so a fade
        // of f hands close to the share f of a tree's pixels to the impostor.
        let mut bins = [0usize; 10];
        for y in 0..64 {
            for x in 0..64 {
                let d = dither(x, y);
                assert!((0.0..1.0).contains(&d));
                bins[(d * 10.0) as usize] += 1;
            }
        }
        for b in bins {
            assert!((b as f32 - 409.6).abs() < 60.0, "{bins:?}");
        }
    }
}
