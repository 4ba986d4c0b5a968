//! The pick shape of a tree model ([`PickShape`]): a trunk cylinder and a crown ellipsoid cut by
//! the crown's box, computed from the model's vertices so that every vertex lies inside.

use glam::{Vec2, Vec3};
use grove_systems::catalogue::PickShape;

/// Computes the pick shape of a model from its wood and foliage vertices (model space).
///
/// The crown starts at the lowest foliage vertex. Wood below it is the trunk: the cylinder's
/// radius is the largest horizontal distance of those vertices from the Y axis. Everything at
/// or above it is the crown: its box is their bounds, and the ellipsoid inscribed in that box
/// is grown until it holds every one of them (so for a cone-shaped crown the box clips the
/// grown ellipsoid's top and bottom).
pub fn pick_shape(wood: &[Vec3], foliage: &[Vec3]) -> PickShape {
    let all = || wood.iter().chain(foliage.iter());
    let crown_bottom = if foliage.is_empty() { all().map(|p| p.y).fold(f32::INFINITY, f32::min) } else { foliage.iter().map(|p| p.y).fold(f32::INFINITY, f32::min) };
    let trunk_radius = wood.iter().filter(|p| p.y < crown_bottom).map(|p| Vec2::new(p.x, p.z).length()).fold(0.0, f32::max);
    let crown: Vec<Vec3> = all().copied().filter(|p| p.y >= crown_bottom).collect();
    let (lo, hi) = crown.iter().fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(a, b), p| (a.min(*p), b.max(*p)));
    let center = (lo + hi) * 0.5;
    let half = ((hi - lo) * 0.5).max(Vec3::splat(1e-3));
    let grow = crown.iter().map(|p| ((*p - center) / half).length()).fold(0.0, f32::max).max(1.0);
    PickShape {
        trunk_radius: trunk_radius * 1.0001,
        trunk_top: crown_bottom,
        crown_min: lo,
        crown_max: hi,
        crown_center: center,
        // A relative margin covers the rounding of the containment test.
        crown_radii: half * grow * 1.0001,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trunk_and_a_ball_crown_give_a_thin_cylinder_and_a_tight_ellipsoid() {
        // A trunk of radius 0.2 up to 2 m, and a crown: points on a sphere of radius 1.5
        // around (0, 3.5, 0).
        let mut wood = Vec::new();
        for i in 0..16 {
            let a = i as f32 * std::f32::consts::TAU / 16.0;
            for y in [0.0, 1.0, 1.99] {
                wood.push(Vec3::new(0.2 * a.cos(), y, 0.2 * a.sin()));
            }
        }
        let mut foliage = Vec::new();
        for i in 0..12 {
            for j in 0..=6 {
                let (a, b) = (i as f32 * std::f32::consts::TAU / 12.0, j as f32 * std::f32::consts::PI / 6.0);
                foliage.push(Vec3::new(0.0, 3.5, 0.0) + 1.5 * Vec3::new(b.sin() * a.cos(), b.cos(), b.sin() * a.sin()));
            }
        }
        let s = pick_shape(&wood, &foliage);
        assert!((s.trunk_radius - 0.2).abs() < 1e-3, "{s:?}");
        assert!((s.trunk_top - 2.0).abs() < 1e-3, "{s:?}");
        assert!((s.crown_center - Vec3::new(0.0, 3.5, 0.0)).length() < 1e-3, "{s:?}");
        assert!((s.crown_radii - Vec3::splat(1.5)).abs().max_element() < 0.01, "a sphere's points need no growth: {s:?}");
        for p in wood.iter().chain(foliage.iter()) {
            assert!(s.contains(*p, 0.0, 0.0, 0.0), "{p} is outside");
        }
        // The ground under the crown's rim, beside the trunk, is outside.
        assert!(!s.contains(Vec3::new(1.2, 0.5, 0.0), 0.0, 0.0, 0.0));
        assert!(!s.contains(Vec3::new(1.2, 2.3, 1.2), 0.0, 0.0, 0.0), "a corner of the crown's box is outside");
    }
}
