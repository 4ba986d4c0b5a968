//! The part of a water pass's target that the surface can read: the water bodies' outlines
//! projected by the pass's camera, widened by the most the ripples shift a lookup. The passes
//! draw only there (a scissor rectangle), so a pond that covers a small part of the screen costs
//! a small part of a target's pixels; every texel the surface reads is drawn as before.
//!
//! The surface (`water.wgsl`) reads the reflection at the surface point projected by the
//! reflection camera, and the refraction and its depth at the point's place on the screen (the
//! refraction camera's projection: its oblique near plane changes depth only), each shifted by
//! at most [`RIPPLE_SHIFT`] in texture coordinates per axis, then clamped to the texture.
//!
//! Units: texels of the pass's target; texture coordinates 0..1 with v down.

use glam::{Mat4, Vec3, Vec4};

use super::extract::WaterDraw;

/// The largest shift of a lookup by the ripples, in texture coordinates per axis: `water.wgsl`'s
/// `shift = n.xz * 0.035 * shore`, with `n` of unit length and `shore` at most 1.
pub const RIPPLE_SHIFT: f32 = 0.035;

/// Texels added on every side beyond the ripples' shift: bilinear filtering reads the texel
/// next to a lookup, and rounding.
const EXTRA_TEXELS: f32 = 2.0;

/// A rectangle of a target, texels: x, y, width, height (at least 1 × 1).
pub type Rect = [u32; 4];

/// The rectangle of a `size` target that the surface can read when the pass draws with
/// `view_proj`, or `None` where it cannot be bounded (a corner of an outline at or behind the
/// camera's eye plane): then the whole target is drawn.
pub fn rect(view_proj: Mat4, bodies: &[WaterDraw], size: (u32, u32)) -> Option<Rect> {
    let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::splat(f32::NEG_INFINITY));
    for body in bodies {
        for p in &body.polygon {
            let c: Vec4 = view_proj * Vec3::new(p.x, body.height, p.y).extend(1.0);
            // A projected outline bounds its projected inside only when every corner lies in
            // front of the eye (then each edge projects to a segment).
            if !(c.w > 1e-4) {
                return None;
            }
            let uv = glam::Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5);
            lo = lo.min(uv);
            hi = hi.max(uv);
        }
    }
    if !(lo.x <= hi.x && lo.y <= hi.y) {
        return None;
    }
    let (w, h) = (size.0.max(1), size.1.max(1));
    let axis = |lo: f32, hi: f32, n: u32| -> (u32, u32) {
        let n_f = n as f32;
        let a = ((lo - RIPPLE_SHIFT) * n_f - EXTRA_TEXELS).floor().clamp(0.0, n_f - 1.0) as u32;
        let b = ((hi + RIPPLE_SHIFT) * n_f + EXTRA_TEXELS).ceil().clamp(a as f32 + 1.0, n_f) as u32;
        (a, b - a)
    };
    let (x, width) = axis(lo.x, hi.x, w);
    let (y, height) = axis(lo.y, hi.y, h);
    Some([x, y, width, height])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::view::Camera;
    use crate::render::water::mirror;
    use glam::{Quat, Vec2};

    /// Water at -0.15 m, as the park's and the pond scene's ponds lie.
    const HEIGHT: f32 = -0.15;

    fn pond(at: Vec2, radius: f32) -> WaterDraw {
        let polygon = (0..12)
            .map(|i| {
                let a = i as f32 / 12.0 * std::f32::consts::TAU;
                at + radius * Vec2::new(a.cos(), a.sin())
            })
            .collect();
        WaterDraw { polygon, height: HEIGHT, depth: 1.0, colour: [0.0; 3], ripples: 1.0, ripple_speed: 0.1 }
    }

    /// The reflection's and the refraction's view-projection matrices, as the frame makes them,
    /// seen from 1.7 m up looking north and 10° down.
    fn cameras() -> [Mat4; 2] {
        let camera = Camera {
            position: Vec3::new(0.0, 1.7, 4.0),
            rotation: Quat::from_rotation_x(-10f32.to_radians()),
            fov_y: 60f32.to_radians(),
        };
        [
            mirror::reflection(&camera, 16.0 / 9.0, HEIGHT, 0.02).view_proj,
            mirror::refraction(&camera, 16.0 / 9.0, HEIGHT, 0.02).view_proj,
        ]
    }

    /// Where in a `size` target the surface reads for the world point `p` with the lookup
    /// shifted by `shift` and clamped, as water.wgsl does, texels.
    fn read_at(view_proj: Mat4, p: Vec3, shift: Vec2, size: (u32, u32)) -> Vec2 {
        let c = view_proj * p.extend(1.0);
        let uv = Vec2::new(c.x / c.w * 0.5 + 0.5, 0.5 - c.y / c.w * 0.5) + shift;
        uv.clamp(Vec2::splat(0.001), Vec2::splat(0.999)) * Vec2::new(size.0 as f32, size.1 as f32)
    }

    #[test]
    fn every_point_of_a_pond_read_with_the_largest_ripple_shift_lies_inside_with_its_filter_footprint() {
        let size = (640, 360);
        for vp in cameras() {
            for (body, small) in [(pond(Vec2::new(0.0, -6.0), 1.2), true), (pond(Vec2::new(-9.0, -20.0), 5.0), false)] {
                let r = rect(vp, std::slice::from_ref(&body), size).expect("a pond in front of the camera is bounded");
                assert!(r[2] >= 1 && r[3] >= 1 && r[0] + r[2] <= size.0 && r[1] + r[3] <= size.1, "{r:?}");
                if small {
                    assert!(
                        r[2] * r[3] < size.0 * size.1 / 4,
                        "a small pond's rectangle is a small part of the target: {r:?}"
                    );
                }
                let centre = body.polygon.iter().copied().sum::<Vec2>() / body.polygon.len() as f32;
                let outer = body.polygon[0].distance(centre) * 0.95;
                for i in 0..400 {
                    // A sunflower spiral over the disc inside the outline.
                    let a = i as f32 * 2.399;
                    let p = centre + outer * ((i as f32 + 0.5) / 400.0).sqrt() * Vec2::new(a.cos(), a.sin());
                    for shift in
                        [Vec2::new(1.0, 1.0), Vec2::new(-1.0, 1.0), Vec2::new(1.0, -1.0), Vec2::new(-1.0, -1.0)]
                    {
                        let t = read_at(vp, Vec3::new(p.x, HEIGHT, p.y), shift * RIPPLE_SHIFT, size);
                        // Bilinear filtering reads the texels about half a texel either side.
                        assert!(
                            t.x - 1.0 >= r[0] as f32 && t.x + 1.0 <= (r[0] + r[2]) as f32,
                            "x {} outside {r:?}",
                            t.x
                        );
                        assert!(
                            t.y - 1.0 >= r[1] as f32 && t.y + 1.0 <= (r[1] + r[3]) as f32,
                            "y {} outside {r:?}",
                            t.y
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn a_pond_behind_the_eye_is_not_bounded_and_one_beside_the_view_keeps_one_texel_at_the_edge() {
        let [reflection, refraction] = cameras();
        for vp in [reflection, refraction] {
            assert_eq!(rect(vp, &[pond(Vec2::new(0.0, 10.0), 2.0)], (640, 360)), None);
            assert_eq!(rect(vp, &[], (640, 360)), None);
        }
        // Far to the right of the view (to the left in the reflection, whose X is flipped): the
        // lookups clamp to that edge, which is kept.
        let far_right = [pond(Vec2::new(400.0, -10.0), 1.0)];
        let r = rect(refraction, &far_right, (640, 360)).unwrap();
        assert_eq!((r[0] + r[2], r[2]), (640, 1), "{r:?}");
        let r = rect(reflection, &far_right, (640, 360)).unwrap();
        assert_eq!((r[0], r[2]), (0, 1), "{r:?}");
    }
}
