//! The part of space a pass can draw into: its view-projection's clip volume, narrowed to a
//! scissor rectangle where the pass has one. Features test bounding boxes against it to skip
//! what a pass cannot show (the trees of the main view and of the water's views); a box that
//! passes may still lie outside, a box that fails lies wholly outside, so culling with it
//! changes no pixel.
//!
//! The clip volume is `x0·w ≤ x ≤ x1·w`, `y0·w ≤ y ≤ y1·w` and `0 ≤ z ≤ w` in clip space (wgpu's
//! depth 0..1), with `x0..x1`, `y0..y1` the rectangle in normalised device coordinates. Each of
//! the six bounds is linear in clip coordinates, so it is one plane in world space (`Mᵀ c` for
//! the clip-space plane `c`), and a point behind the eye needs no division.
//!
//! Units: metres in world space; texels for the rectangle.

use glam::{Mat4, Vec3, Vec4};

/// Six world-space half-spaces `n·p + d ≥ 0` (as `(n, d)`) whose intersection holds everything
/// a pass can draw.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipRegion {
    planes: [Vec4; 6],
}

impl ClipRegion {
    /// The whole clip volume of `view_proj`.
    pub fn new(view_proj: Mat4) -> ClipRegion {
        ClipRegion::from_ndc(view_proj, [-1.0, 1.0], [-1.0, 1.0])
    }

    /// The clip volume of `view_proj` within `rect` (x, y, width, height in texels, y down) of a
    /// target of `size` texels; `None` is the whole target.
    pub fn scissored(view_proj: Mat4, rect: Option<[u32; 4]>, size: (u32, u32)) -> ClipRegion {
        let Some([x, y, w, h]) = rect else {
            return ClipRegion::new(view_proj);
        };
        let (sw, sh) = (size.0.max(1) as f32, size.1.max(1) as f32);
        let ndc_x = |t: u32| t as f32 / sw * 2.0 - 1.0;
        let ndc_y = |t: u32| 1.0 - t as f32 / sh * 2.0;
        ClipRegion::from_ndc(view_proj, [ndc_x(x), ndc_x(x + w)], [ndc_y(y + h), ndc_y(y)])
    }

    fn from_ndc(view_proj: Mat4, [x0, x1]: [f32; 2], [y0, y1]: [f32; 2]) -> ClipRegion {
        let clip = [
            Vec4::new(1.0, 0.0, 0.0, -x0),
            Vec4::new(-1.0, 0.0, 0.0, x1),
            Vec4::new(0.0, 1.0, 0.0, -y0),
            Vec4::new(0.0, -1.0, 0.0, y1),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
            Vec4::new(0.0, 0.0, -1.0, 1.0),
        ];
        let t = view_proj.transpose();
        ClipRegion { planes: clip.map(|c| t * c) }
    }

    /// Whether the box `lo..hi` (world metres) may reach into the region: false only where the
    /// whole box lies outside one of the six planes.
    pub fn may_hold(&self, lo: Vec3, hi: Vec3) -> bool {
        self.planes.iter().all(|p| {
            // The corner farthest along the plane's normal.
            let n = p.truncate();
            let corner = Vec3::select(n.cmpge(Vec3::ZERO), hi, lo);
            n.dot(corner) + p.w >= 0.0
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A camera at the origin looking down -Z, 90° vertically, square, near 0.1, far 100.
    fn view_proj() -> Mat4 {
        glam::camera::rh::proj::directx::perspective(90f32.to_radians(), 1.0, 0.1, 100.0)
    }

    fn cube(at: Vec3, half: f32) -> (Vec3, Vec3) {
        (at - Vec3::splat(half), at + Vec3::splat(half))
    }

    #[test]
    fn boxes_in_front_are_held_and_boxes_behind_or_beside_are_not() {
        let r = ClipRegion::new(view_proj());
        let held = |(lo, hi): (Vec3, Vec3)| r.may_hold(lo, hi);
        assert!(held(cube(Vec3::new(0.0, 0.0, -10.0), 1.0)));
        // Behind the eye.
        assert!(!held(cube(Vec3::new(0.0, 0.0, 10.0), 1.0)));
        // Beyond the far plane.
        assert!(!held(cube(Vec3::new(0.0, 0.0, -200.0), 1.0)));
        // At 45° the frustum's side is x = -z. A cube at x = 14, z = -10 with half 1 (x from
        // 13, z down to -11) is out; with half 3 (x from 11, z down to -13) it reaches in.
        assert!(!held(cube(Vec3::new(14.0, 0.0, -10.0), 1.0)));
        assert!(held(cube(Vec3::new(14.0, 0.0, -10.0), 3.0)));
        // Around the eye.
        assert!(held(cube(Vec3::ZERO, 1.0)));
    }

    #[test]
    fn a_scissor_narrows_the_region_to_its_rectangle() {
        // The right half of a 100 × 100 target: x from 0 to w in clip space.
        let r = ClipRegion::scissored(view_proj(), Some([50, 0, 50, 100]), (100, 100));
        let held = |(lo, hi): (Vec3, Vec3)| r.may_hold(lo, hi);
        assert!(held(cube(Vec3::new(5.0, 0.0, -10.0), 1.0)));
        assert!(!held(cube(Vec3::new(-5.0, 0.0, -10.0), 1.0)));
        // The top quarter of the target (rows 0..25): y from w/2 to w.
        let top = ClipRegion::scissored(view_proj(), Some([0, 0, 100, 25]), (100, 100));
        assert!(top.may_hold(cube(Vec3::new(0.0, 7.5, -10.0), 1.0).0, cube(Vec3::new(0.0, 7.5, -10.0), 1.0).1));
        assert!(!top.may_hold(cube(Vec3::new(0.0, -5.0, -10.0), 1.0).0, cube(Vec3::new(0.0, -5.0, -10.0), 1.0).1));
        // No rectangle: the whole volume.
        assert_eq!(ClipRegion::scissored(view_proj(), None, (100, 100)), ClipRegion::new(view_proj()));
    }

    #[test]
    fn every_point_a_box_holds_that_projects_inside_is_kept() {
        // Random boxes: whenever a sampled point of the box projects inside the volume, the box
        // must be held (the test may keep more, never less).
        let m = view_proj() * Mat4::from_rotation_y(0.3) * Mat4::from_translation(Vec3::new(1.0, -2.0, 3.0));
        let r = ClipRegion::scissored(m, Some([10, 20, 30, 40]), (64, 96));
        let mut seed = 7u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f32 / (1u32 << 24) as f32
        };
        let (x0, x1) = (10.0 / 64.0 * 2.0 - 1.0, 40.0 / 64.0 * 2.0 - 1.0);
        let (y0, y1) = (1.0 - 60.0 / 96.0 * 2.0, 1.0 - 20.0 / 96.0 * 2.0);
        let mut inside = 0;
        for _ in 0..2000 {
            let c = Vec3::new(next() * 40.0 - 20.0, next() * 40.0 - 20.0, next() * 40.0 - 20.0);
            let h = Vec3::new(next(), next(), next()) * 3.0;
            let (lo, hi) = (c - h, c + h);
            let held = r.may_hold(lo, hi);
            for i in 0..27 {
                let f = Vec3::new((i % 3) as f32, ((i / 3) % 3) as f32, (i / 9) as f32) * 0.5;
                let p = m * (lo + (hi - lo) * f).extend(1.0);
                let shown = p.w > 0.0
                    && p.x >= x0 * p.w
                    && p.x <= x1 * p.w
                    && p.y >= y0 * p.w
                    && p.y <= y1 * p.w
                    && p.z >= 0.0
                    && p.z <= p.w;
                if shown {
                    inside += 1;
                    assert!(held, "a box with a point inside was culled: {lo} {hi}");
                }
            }
        }
        assert!(inside > 50, "too few samples inside the region to test anything: {inside}");
    }
}
