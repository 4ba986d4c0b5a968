//! The water's two extra cameras as matrices: the reflection camera (the head's camera mirrored
//! in the water plane, its near plane the water plane, so nothing below the surface is drawn)
//! and the refraction camera (the head's camera with its near plane the water plane the other
//! way round, so only what lies below the surface is drawn).
//!
//! Clipping at the plane uses an oblique near plane (Lengyel, "Oblique View Frustum Depth
//! Projection and Clipping", 2005), adapted to wgpu's clip depth 0..1: the projection's depth row
//! is replaced by the clip plane, scaled so that the far plane still passes through the far
//! corner of the frustum. The shaders of the other features need no clip distances.
//!
//! A mirror turns triangles' winding around; the reflection camera also flips clip-space X,
//! which turns it back, so the features draw with their usual culling, and the image is the
//! mirror image left to right. The water shader projects through the same matrix, so the flip
//! is undone by the lookup itself.
//!
//! Units: metres; right-handed, +Y up; wgpu clip depth 0..1.

use glam::{Mat4, Vec3, Vec4};

use crate::render::view::Camera;

/// Near and far planes of the water's cameras, metres, the same as the main camera's
/// (`view::camera_matrix`).
const NEAR: f32 = 0.05;
const FAR: f32 = 600.0;

/// The mirror in the horizontal plane at height `h`: (x, y, z) → (x, 2h − y, z).
pub fn mirror(h: f32) -> Mat4 {
    Mat4::from_cols(Vec4::X, Vec4::NEG_Y, Vec4::Z, Vec4::new(0.0, 2.0 * h, 0.0, 1.0))
}

/// The camera's world-to-view matrix.
fn view_matrix(camera: &Camera) -> Mat4 {
    Mat4::from_rotation_translation(camera.rotation, camera.position).inverse()
}

/// The camera's projection (the same as `view::camera_matrix` uses).
fn projection(camera: &Camera, aspect: f32) -> Mat4 {
    let fov = camera.fov_y.clamp(0.01, 3.1);
    glam::camera::rh::proj::directx::perspective(fov, aspect.max(1e-3), NEAR, FAR)
}

/// `proj` with its near plane replaced by `plane` (view space, (n, d) with n·p + d ≥ 0 the kept
/// side), wgpu clip depth 0..1. The depth row becomes `a · plane`, with `a` chosen so that the
/// far plane passes through the frustum corner opposite the plane.
pub fn oblique(proj: Mat4, plane: Vec4) -> Mat4 {
    // The plane in clip space decides which far corner is opposite it.
    let clip_plane = proj.inverse().transpose() * plane;
    let corner = proj.inverse() * Vec4::new(clip_plane.x.signum(), clip_plane.y.signum(), 1.0, 1.0);
    let w_row = proj.row(3);
    let denom = plane.dot(corner);
    if denom.abs() < 1e-12 {
        return proj;
    }
    let a = w_row.dot(corner) / denom;
    let row = plane * a;
    let mut m = proj;
    // Column-major: element [col][2] is row 2 (clip z).
    m.x_axis.z = row.x;
    m.y_axis.z = row.y;
    m.z_axis.z = row.z;
    m.w_axis.z = row.w;
    m
}

/// A world-space plane `(n, d)` (n·p + d ≥ 0 kept) in the view space of `world_to_view`.
fn plane_in_view(world_to_view: Mat4, plane: Vec4) -> Vec4 {
    world_to_view.inverse().transpose() * plane
}

/// The matrices of one of the water's cameras.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaterCamera {
    /// World to clip space, clipped at the water plane (what the pass draws with).
    pub view_proj: Mat4,
    /// The inverse of the same camera without the oblique near plane (the sky's view rays).
    pub inv_view_proj: Mat4,
    /// The eye, world metres (mirrored for the reflection).
    pub eye: Vec3,
}

/// The reflection camera for water at height `h`: the head's camera mirrored in the plane,
/// clip-space X flipped, keeping only what lies above the plane (less `bias` metres).
pub fn reflection(camera: &Camera, aspect: f32, h: f32, bias: f32) -> WaterCamera {
    let flip = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let world_to_view = view_matrix(camera) * mirror(h);
    let proj = projection(camera, aspect);
    let plane = plane_in_view(world_to_view, Vec4::new(0.0, 1.0, 0.0, -(h - bias)));
    WaterCamera {
        view_proj: flip * oblique(proj, plane) * world_to_view,
        inv_view_proj: (flip * proj * world_to_view).inverse(),
        eye: mirror(h).transform_point3(camera.position),
    }
}

/// The refraction camera for water at height `h`: the head's camera, keeping only what lies
/// below the plane (plus `bias` metres).
pub fn refraction(camera: &Camera, aspect: f32, h: f32, bias: f32) -> WaterCamera {
    let world_to_view = view_matrix(camera);
    let proj = projection(camera, aspect);
    let plane = plane_in_view(world_to_view, Vec4::new(0.0, -1.0, 0.0, h + bias));
    WaterCamera {
        view_proj: oblique(proj, plane) * world_to_view,
        inv_view_proj: (proj * world_to_view).inverse(),
        eye: camera.position,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Quat;

    fn camera() -> Camera {
        // 1.7 m up, looking north and 10° down.
        Camera {
            position: Vec3::new(0.0, 1.7, 4.0),
            rotation: Quat::from_rotation_x(-10f32.to_radians()),
            fov_y: 60f32.to_radians(),
        }
    }

    /// Whether a world point is drawn by a camera: inside the clip volume (x, y in ±w, depth in 0..w).
    fn drawn(m: Mat4, p: Vec3) -> bool {
        let c = m * p.extend(1.0);
        c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && c.z >= 0.0 && c.z <= c.w
    }

    #[test]
    fn the_mirror_maps_a_point_to_the_other_side_of_the_plane() {
        let m = mirror(-0.5);
        assert!((m.transform_point3(Vec3::new(1.0, 2.0, 3.0)) - Vec3::new(1.0, -3.0, 3.0)).length() < 1e-6);
        assert!((m * m - Mat4::IDENTITY).abs_diff_eq(Mat4::ZERO, 1e-6));
    }

    #[test]
    fn a_point_on_the_plane_projects_where_the_main_camera_sees_it_mirrored_left_to_right() {
        let cam = camera();
        let main = crate::render::view::camera_matrix(&cam, 16.0 / 9.0);
        let r = reflection(&cam, 16.0 / 9.0, -0.15, 0.0);
        for p in [Vec3::new(0.0, -0.15, -6.0), Vec3::new(2.0, -0.15, -3.0), Vec3::new(-1.5, -0.15, -9.0)] {
            let a = main.project_point3(p);
            let b = r.view_proj.project_point3(p);
            assert!((a.x + b.x).abs() < 1e-4 && (a.y - b.y).abs() < 1e-4, "{p}: {a} vs {b}");
        }
        // The mirrored eye is as far below the plane as the eye is above it.
        assert!((r.eye.y - (-0.15 - 1.85)).abs() < 1e-5);
    }

    #[test]
    fn the_reflection_keeps_what_is_above_the_plane_and_clips_what_is_below() {
        let cam = camera();
        let r = reflection(&cam, 16.0 / 9.0, -0.15, 0.0);
        // A tree top 6 m up on the far shore is seen in the water; a point 0.5 m under the
        // surface of the pond, in the same direction, is not.
        assert!(drawn(r.view_proj, Vec3::new(0.0, 6.0, -14.0)));
        assert!(drawn(r.view_proj, Vec3::new(0.5, 0.1, -8.0)));
        assert!(!drawn(r.view_proj, Vec3::new(0.5, -0.65, -8.0)));
        assert!(!drawn(r.view_proj, Vec3::new(0.0, -1.2, -6.0)));
    }

    #[test]
    fn the_refraction_keeps_what_is_below_the_plane_only() {
        let cam = camera();
        let r = refraction(&cam, 16.0 / 9.0, -0.15, 0.0);
        assert!(drawn(r.view_proj, Vec3::new(0.0, -1.2, -6.0)));
        assert!(!drawn(r.view_proj, Vec3::new(0.0, 0.3, -6.0)));
        // Depth still grows with distance along a line of sight below the surface.
        let near = r.view_proj.project_point3(Vec3::new(0.0, -0.5, -3.0)).z;
        let far = r.view_proj.project_point3(Vec3::new(0.0, -1.0, -8.0)).z;
        assert!(near < far && (0.0..=1.0).contains(&near) && (0.0..=1.0).contains(&far), "{near} {far}");
    }
}
