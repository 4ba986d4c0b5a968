//! Shared pieces of the interaction systems: pure maths (bounding-box handles, handle drags,
//! touchpad rates, the snap rule, the manual-mode spawn point) and small world helpers.
//!
//! Every function here takes its inputs as explicit arguments and touches no world, so the
//! interaction rules can be read, and unit-tested, in one place. The systems in
//! `crate::systems` (raycast, spawn, plant_remove, select, handles, touchpad, drag,
//! selection_box) call them.

use std::cell::RefCell;

use glam::{Quat, Vec3};
use hecs::{Entity, World};
use parry3d::query::{Ray, RayCast};
use parry3d::shape::Ball;

use crate::catalogue::Catalogue;
use crate::components::{Handle, Pose, Selection, Transform};
use crate::single::{self, Singles};
use crate::spatial::{RayHit, SpatialIndex, TreeBox, tree_box};

/// The entity with these id bits, if the bits are a valid id (it may still be despawned).
pub fn entity(bits: u64) -> Option<Entity> {
    Entity::from_bits(bits)
}

/// The world-space oriented box of the tree `e` from its components and the catalogue, or
/// `None` if `e` is not a tree (any more) or its model is unknown.
pub fn tree_box_of(world: &mut World, catalogue: &Catalogue, memo: &BoxMemo, e: Entity) -> Option<TreeBox> {
    // One prepared look-up of the entity for the three components.
    let (model, t, scale) = crate::lookup::tree_parts(world, e)?;
    let m = catalogue.get(model)?;
    Some(memo.tree_box(e, &t, scale, m.bounds_min, m.bounds_max))
}

/// The last tree box ([`tree_box`]) and handle points ([`handle_points`]) computed, each with
/// the bits of what it was computed from, given again for the same bits: the selected tree's
/// box is computed twice a tick (by the raycast and selection_box systems) and its handles on
/// every tick that the ray passes near them, from inputs that change only when the tree moves.
/// The same bits in give the same bits out, so a kept value is the value computed again. A
/// cache in `Resources`, not hashed.
#[derive(Clone, Debug, Default)]
pub struct BoxMemo {
    tree_box: RefCell<Option<([u32; 13], TreeBox)>>,
    handles: RefCell<Option<([u32; 7], [(Handle, Vec3); 12])>>,
}

impl BoxMemo {
    /// [`tree_box`], kept for the same inputs.
    pub fn tree_box(&self, entity: Entity, transform: &Transform, scale: f32, min: Vec3, max: Vec3) -> TreeBox {
        let (p, a, b) = (transform.translation, min, max);
        let id = entity.to_bits().get();
        let f = [p.x, p.y, p.z, transform.yaw, scale, a.x, a.y, a.z, b.x, b.y, b.z].map(f32::to_bits);
        let key = [id as u32, (id >> 32) as u32, f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8], f[9], f[10]];
        if let Some((k, b)) = &*self.tree_box.borrow()
            && *k == key
        {
            return *b;
        }
        let b = tree_box(entity, transform, scale, min, max);
        *self.tree_box.borrow_mut() = Some((key, b));
        b
    }

    /// [`handle_points`], kept for the same inputs.
    pub fn handle_points(&self, center: Vec3, half: Vec3, yaw: f32) -> [(Handle, Vec3); 12] {
        let key = [center.x, center.y, center.z, half.x, half.y, half.z, yaw].map(f32::to_bits);
        if let Some((k, points)) = &*self.handles.borrow()
            && *k == key
        {
            return *points;
        }
        let points = handle_points(center, half, yaw);
        *self.handles.borrow_mut() = Some((key, points));
        points
    }
}

/// The id bits of the selected tree, if any (from the first `Selection` entity).
pub fn selected_tree(world: &mut World, singles: &Singles) -> Option<u64> {
    single::get::<Selection>(world, singles).and_then(|s| s.tree)
}

/// Sets the selected tree (or clears it with `None`) on every `Selection` entity. The box itself
/// is filled in by the selection_box system at the end of the tick.
pub fn set_selected(world: &mut World, singles: &Singles, tree: Option<u64>) {
    single::for_each_mut::<Selection>(world, singles, |s| s.tree = tree);
}

/// The plane under a tree whose origin is at `origin`: the first plane a vertical ray meets
/// going down from `lift` metres above the tree's lowest point (`lowest × scale` above the
/// origin), on the tree's axis. Lifting the ray start lets a tree that sank a little into a
/// plane still find it. `None` over a hole or off every plane's edge.
pub fn ground_under(spatial: &SpatialIndex, origin: Vec3, lowest: f32, scale: f32, lift: f32) -> Option<RayHit> {
    let low = Vec3::new(origin.x, lowest_point_y(origin.y, lowest, scale), origin.z);
    spatial.ground_below(low, lift)
}

/// The 12 handles of an oriented box with centre `center`, half extents `half` and rotation
/// `yaw` about +Y: first the 8 corners (`Handle::Corner(i)`, bit 0 of `i` is +X, bit 1 is +Y,
/// bit 2 is +Z, in the box's own axes), then the midpoints of the 4 vertical edges
/// (`Handle::Edge(i)`, bit 0 is +X, bit 1 is +Z), at the height of the centre.
pub fn handle_points(center: Vec3, half: Vec3, yaw: f32) -> [(Handle, Vec3); 12] {
    let rot = Quat::from_rotation_y(yaw);
    let sign = |bit: bool| if bit { 1.0 } else { -1.0 };
    std::array::from_fn(|k| {
        if k < 8 {
            let i = k as u8;
            let local = Vec3::new(sign(i & 1 != 0), sign(i & 2 != 0), sign(i & 4 != 0)) * half;
            (Handle::Corner(i), center + rot * local)
        } else {
            let i = (k - 8) as u8;
            let local = Vec3::new(sign(i & 1 != 0) * half.x, 0.0, sign(i & 2 != 0) * half.z);
            (Handle::Edge(i), center + rot * local)
        }
    })
}

/// Distance along the ray (`dir` unit length) to a sphere, within `max`; 0 if the origin is
/// inside it.
pub fn ray_sphere(origin: Vec3, dir: Vec3, center: Vec3, radius: f32, max: f32) -> Option<f32> {
    Ball::new(radius).cast_local_ray(&Ray::new(origin - center, dir), max, true)
}

/// The nearest handle sphere (radius `radius`) of a box that the ray hits within `max`, with its
/// distance. Ties go to the handle listed first by [`handle_points`].
pub fn nearest_handle(
    origin: Vec3,
    dir: Vec3,
    b: &TreeBox,
    radius: f32,
    max: f32,
    memo: &BoxMemo,
) -> Option<(Handle, Vec3, f32)> {
    // Every handle lies within |half extents| of the centre, so a ray that misses the sphere
    // around them all (with a margin for rounding) hits none: most ticks stop here.
    let around = b.half_extents.length() + radius;
    ray_sphere(origin, dir, b.center, around * 1.001 + 1.0e-3, max)?;
    nearest_of_all_handles(origin, dir, b, radius, max, memo)
}

/// [`nearest_handle`] without the test against the sphere around all the handles.
fn nearest_of_all_handles(
    origin: Vec3,
    dir: Vec3,
    b: &TreeBox,
    radius: f32,
    max: f32,
    memo: &BoxMemo,
) -> Option<(Handle, Vec3, f32)> {
    let mut best: Option<(Handle, Vec3, f32)> = None;
    for (h, p) in memo.handle_points(b.center, b.half_extents, b.yaw) {
        let limit = best.map_or(max, |b| b.2);
        if let Some(d) = ray_sphere(origin, dir, p, radius, limit)
            && best.is_none_or(|b| d < b.2)
        {
            best = Some((h, p, d));
        }
    }
    best
}

/// Horizontal distance from `point` to the vertical axis through `axis`.
pub fn horizontal_radius(point: Vec3, axis: Vec3) -> f32 {
    let d = point - axis;
    (d.x * d.x + d.z * d.z).sqrt()
}

/// The angle of `point` around the vertical axis through `axis`, radians, counter-clockwise seen
/// from above, zero along +X: the same convention as `Transform::yaw`, so turning a tree by
/// `a` turns every point of it by `a` in this angle.
pub fn angle_around(point: Vec3, axis: Vec3) -> f32 {
    let d = point - axis;
    libm::atan2f(-d.z, d.x)
}

/// `a` wrapped into (−π, π].
pub fn wrap_angle(a: f32) -> f32 {
    use std::f32::consts::{PI, TAU};
    let mut r = a % TAU;
    if r <= -PI {
        r += TAU;
    } else if r > PI {
        r -= TAU;
    }
    r
}

/// The uniform scale during a corner-handle drag: the scale at the grab times the ratio of the
/// grab point's horizontal distance to the tree axis now and at the grab, clamped to
/// `[min, max]`. A grab closer than 1 cm to the axis keeps the start scale.
pub fn corner_scale(start_scale: f32, start_radius: f32, radius: f32, min: f32, max: f32) -> f32 {
    if start_radius < 0.01 {
        return start_scale;
    }
    (start_scale * radius / start_radius).clamp(min, max)
}

/// The scale after one tick of the Scale pad at `value` (after the dead zone): `scale` times
/// 2^(value × `octaves_per_s` × `dt`), clamped to `[min, max]`.
pub fn pad_scale(scale: f32, value: f32, octaves_per_s: f32, dt: f32, min: f32, max: f32) -> f32 {
    (scale * libm::exp2f(value * octaves_per_s * dt)).clamp(min, max)
}

/// The yaw during an edge-handle drag: the yaw at the grab plus the change of the grab point's
/// angle around the tree axis (the shorter way round), wrapped into (−π, π].
pub fn edge_yaw(start_yaw: f32, start_angle: f32, angle: f32) -> f32 {
    wrap_angle(start_yaw + wrap_angle(angle - start_angle))
}

/// The new origin height of a tree whose scale changes from `old` to `new`, such that its lowest
/// point (at `lowest × scale` above the origin) stays where it is.
pub fn rescaled_origin_y(y: f32, lowest: f32, old: f32, new: f32) -> f32 {
    y + lowest * (old - new)
}

/// Height of a tree's lowest point: origin height plus the model's lowest point times the scale.
pub fn lowest_point_y(origin_y: f32, lowest: f32, scale: f32) -> f32 {
    origin_y + lowest * scale
}

/// The origin height that puts a tree's lowest point exactly at `plane_y`.
pub fn snapped_origin_y(plane_y: f32, lowest: f32, scale: f32) -> f32 {
    plane_y - lowest * scale
}

/// The snap rule: the anchor ball is white (armed, releasing snaps) exactly when the distance
/// from the tree's lowest point to the plane below is strictly less than the threshold in
/// absolute value, `|distance| < threshold`; at `|distance| == threshold` it is green.
pub fn is_armed(distance: f32, threshold: f32) -> bool {
    distance.abs() < threshold
}

/// One touchpad axis after the dead zone: the deflection itself when strictly beyond
/// `dead_zone` in absolute value, otherwise 0.
pub fn touchpad_axis(value: f32, dead_zone: f32) -> f32 {
    if value.abs() > dead_zone { value } else { 0.0 }
}

/// The change of yaw for one tick of touchpad x deflection `x` (after the dead zone): x < 0
/// turns counter-clockwise seen from above (yaw grows), x > 0 clockwise.
pub fn touchpad_turn(x: f32, rate_deg: f32, dt: f32) -> f32 {
    -x * rate_deg.to_radians() * dt
}

/// The horizontal forward direction of a pose (unit length); −Z if it looks straight up or down.
pub fn horizontal_forward(pose: &Pose) -> Vec3 {
    let f = pose.forward();
    Vec3::new(f.x, 0.0, f.z).normalize_or(Vec3::NEG_Z)
}

/// Where a tree chosen from the menu in manual mode appears: `distance` metres in front of the
/// head (horizontally) and `drop` metres below head height.
pub fn spawn_point(head: &Pose, distance: f32, drop: f32) -> Vec3 {
    let p = head.position + horizontal_forward(head) * distance;
    Vec3::new(p.x, head.position.y - drop, p.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{FRAC_PI_2, PI};

    #[test]
    fn the_sphere_around_the_handles_never_changes_which_handle_is_hit() {
        // Rays from around a box, aimed near it, some hitting handles and most not: the early
        // exit must give the answer of testing all twelve, bit for bit.
        let mut x: u32 = 7;
        let mut r = || {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (x >> 8) as f32 / (1u32 << 24) as f32
        };
        let (mut hits, mut misses) = (0, 0);
        let memo = BoxMemo::default();
        for _ in 0..20_000 {
            let half = Vec3::new(0.2 + 2.0 * r(), 0.5 + 4.0 * r(), 0.2 + 2.0 * r());
            let center = Vec3::new(10.0 * r() - 5.0, half.y, 10.0 * r() - 5.0);
            let b = tree_box(
                Entity::DANGLING,
                &Transform { translation: center - Vec3::Y * half.y, yaw: 7.0 * r() },
                1.0,
                -half,
                half,
            );
            let origin = center + Vec3::new(8.0 * r() - 4.0, 3.0 * r(), 8.0 + 4.0 * r());
            let aim = b.center + Vec3::new(r() - 0.5, r() - 0.5, r() - 0.5) * half * 3.0;
            let dir = (aim - origin).normalize();
            let (radius, max) = (0.05 + 0.3 * r(), 5.0 + 20.0 * r());
            let fast = nearest_handle(origin, dir, &b, radius, max, &memo);
            let all = nearest_of_all_handles(origin, dir, &b, radius, max, &BoxMemo::default());
            assert_eq!(
                fast.map(|(h, p, d)| (h, p.to_array().map(f32::to_bits), d.to_bits())),
                all.map(|(h, p, d)| (h, p.to_array().map(f32::to_bits), d.to_bits()))
            );
            if all.is_some() { hits += 1 } else { misses += 1 }
        }
        assert!(hits > 1_000 && misses > 1_000, "{hits} hits, {misses} misses");
    }

    #[test]
    fn a_kept_box_or_handle_is_what_computing_it_again_gives() {
        let memo = BoxMemo::default();
        let bits = |b: &TreeBox| {
            (b.entity, [b.center, b.half_extents].map(|v| v.to_array().map(f32::to_bits)), b.yaw.to_bits())
        };
        let pts = |p: [(Handle, Vec3); 12]| p.map(|(h, v)| (h, v.to_array().map(f32::to_bits)));
        let (min, max) = (Vec3::new(-1.0, 0.0, -1.5), Vec3::new(1.0, 6.0, 1.5));
        let e = |id: u32| Entity::from_bits(u64::from(id) | 1 << 32).unwrap();
        // Inputs repeated, changed in one value, and changed only in the sign of a zero (equal
        // as numbers, not as bits; a zero's sign can show in the box).
        let inputs = [
            (e(1), Vec3::new(1.0, 0.0, 2.0), 0.5, 1.2),
            (e(1), Vec3::new(1.0, 0.0, 2.0), 0.5, 1.2),
            (e(2), Vec3::new(1.0, 0.0, 2.0), 0.5, 1.2),
            (e(2), Vec3::new(1.0, 0.0, 2.0), 0.5, 1.25),
            (e(2), Vec3::new(1.0, 0.0, 2.0), 0.0, 1.25),
            (e(2), Vec3::new(1.0, 0.0, 2.0), -0.0, 1.25),
            (e(2), Vec3::new(-0.0, 0.0, 2.0), -0.0, 1.25),
            (e(2), Vec3::new(-0.0, 0.0, 2.0), -0.0, 1.25),
        ];
        for (entity, translation, yaw, scale) in inputs {
            let t = Transform { translation, yaw };
            let kept = memo.tree_box(entity, &t, scale, min, max);
            let fresh = tree_box(entity, &t, scale, min, max);
            assert_eq!(bits(&kept), bits(&fresh));
            assert_eq!(
                pts(memo.handle_points(kept.center, kept.half_extents, kept.yaw)),
                pts(handle_points(fresh.center, fresh.half_extents, fresh.yaw))
            );
        }
        // A box with a zero's sign flipped is another box, bit for bit.
        let t = |x: f32| Transform { translation: Vec3::new(x, 0.0, 0.0), yaw: 0.0 };
        let zero = Vec3::new(0.0, 0.0, 0.0);
        assert_eq!(
            bits(&memo.tree_box(e(3), &t(0.0), 1.0, zero, zero)),
            bits(&tree_box(e(3), &t(0.0), 1.0, zero, zero))
        );
        assert_eq!(
            bits(&memo.tree_box(e(3), &t(-0.0), 1.0, zero, zero)),
            bits(&tree_box(e(3), &t(-0.0), 1.0, zero, zero))
        );
        assert_eq!(pts(memo.handle_points(zero, Vec3::ONE, 0.0)), pts(handle_points(zero, Vec3::ONE, 0.0)));
        assert_eq!(pts(memo.handle_points(-zero, Vec3::ONE, 0.0)), pts(handle_points(-zero, Vec3::ONE, 0.0)));
    }

    #[test]
    fn handles_sit_on_the_box_corners_and_edge_midpoints() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let h = Vec3::new(0.5, 2.0, 0.25);
        let pts = handle_points(c, h, 0.0);
        assert_eq!(pts[0], (Handle::Corner(0), c - h));
        assert_eq!(pts[7], (Handle::Corner(7), c + h));
        assert_eq!(pts[8], (Handle::Edge(0), Vec3::new(0.5, 2.0, 2.75)));
        assert_eq!(pts[11], (Handle::Edge(3), Vec3::new(1.5, 2.0, 3.25)));
        // A quarter turn counter-clockwise takes +X to −Z.
        let r = handle_points(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), FRAC_PI_2);
        assert!((r[9].1 - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    }

    #[test]
    fn nearest_handle_is_the_front_one() {
        let b = TreeBox { entity: Entity::DANGLING, center: Vec3::ZERO, half_extents: Vec3::ONE, yaw: 0.0 };
        // Straight down the +X+Z vertical edge midpoint (1, 0, 1) from above: the top corner
        // (1, 1, 1) is hit first.
        let (h, _, d) =
            nearest_handle(Vec3::new(1.0, 5.0, 1.0), Vec3::NEG_Y, &b, 0.1, 100.0, &BoxMemo::default()).unwrap();
        assert_eq!(h, Handle::Corner(7));
        assert!((d - 3.9).abs() < 1e-5);
        // From the side at mid-height, the edge handle.
        let (h, _, _) =
            nearest_handle(Vec3::new(5.0, 0.0, 1.0), Vec3::NEG_X, &b, 0.1, 100.0, &BoxMemo::default()).unwrap();
        assert_eq!(h, Handle::Edge(3));
        assert!(nearest_handle(Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Y, &b, 0.1, 100.0, &BoxMemo::default()).is_none());
    }

    #[test]
    fn angles_follow_the_yaw_convention() {
        let axis = Vec3::new(2.0, 0.0, 2.0);
        let p = axis + Vec3::X;
        let turned = axis + Quat::from_rotation_y(0.7) * Vec3::X;
        assert!((angle_around(turned, axis) - angle_around(p, axis) - 0.7).abs() < 1e-6);
        assert!((edge_yaw(0.2, 3.0, -3.0) - wrap_angle(0.2 + 2.0 * PI - 6.0)).abs() < 1e-6);
        assert!((wrap_angle(2.5 * PI) - FRAC_PI_2).abs() < 1e-5);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-6);
    }

    #[test]
    fn corner_scale_is_the_radius_ratio_clamped() {
        assert!((corner_scale(1.0, 2.0, 3.0, 0.25, 4.0) - 1.5).abs() < 1e-6);
        assert_eq!(corner_scale(1.0, 1.0, 100.0, 0.25, 4.0), 4.0);
        assert_eq!(corner_scale(1.0, 1.0, 0.0, 0.25, 4.0), 0.25);
        assert_eq!(corner_scale(1.3, 0.0, 5.0, 0.25, 4.0), 1.3);
    }

    #[test]
    fn rescaling_keeps_the_lowest_point() {
        let (y, lowest) = (0.3, -0.05);
        let y2 = rescaled_origin_y(y, lowest, 1.0, 2.5);
        assert!((lowest_point_y(y, lowest, 1.0) - lowest_point_y(y2, lowest, 2.5)).abs() < 1e-6);
        assert!((lowest_point_y(snapped_origin_y(0.8, lowest, 1.7), lowest, 1.7) - 0.8).abs() < 1e-6);
    }

    #[test]
    fn armed_is_strictly_below_the_threshold() {
        assert!(is_armed(0.2999, 0.3));
        assert!(is_armed(-0.2999, 0.3));
        assert!(!is_armed(0.3, 0.3));
        assert!(!is_armed(0.3001, 0.3));
    }

    #[test]
    fn touchpad_dead_zone_and_turn_direction() {
        assert_eq!(touchpad_axis(0.15, 0.15), 0.0);
        assert_eq!(touchpad_axis(-0.5, 0.15), -0.5);
        assert!(touchpad_turn(-1.0, 90.0, 1.0) > 0.0, "left turns counter-clockwise");
        assert!((touchpad_turn(1.0, 90.0, 1.0) + FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn spawn_point_is_in_front_of_the_head_and_below_it() {
        let head = Pose::looking_at(Vec3::new(1.0, 1.7, 0.0), Vec3::new(1.0, 0.0, -5.0));
        let p = spawn_point(&head, 1.5, 0.5);
        assert!((p - Vec3::new(1.0, 1.2, -1.5)).length() < 1e-5);
    }
}
